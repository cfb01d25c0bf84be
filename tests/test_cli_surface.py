"""``reducerlab surface``: generated tooth surfaces of a nutation design, exported."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.examples import example_dir

pytest.importorskip("trimesh")

runner = CliRunner()
EXAMPLE = example_dir() / "nutation_surface.toml"


def test_surface_writes_a_closed_stl_of_the_gear(tmp_path):
    from reducerlab.geometry.export import load_mesh
    from reducerlab.geometry.solid import build_gear_solid

    out = tmp_path / "gear2.stl"
    r = runner.invoke(
        app, ["surface", str(EXAMPLE), "--gear", "2", "--export", str(out), "--points", "7"]
    )
    assert r.exit_code == 0, r.output
    assert "external, z = 26" in r.output and "closed (watertight)" in r.output
    assert "meshing residual" in r.output
    mesh = load_mesh(out)
    assert mesh.to_trimesh().is_watertight
    # the same solid as the library builds from the design (STL: float32 in mm)
    crown, gear = load_design(EXAMPLE).tooth_generation(2)
    ref = build_gear_solid(crown, gear, 7, 7, 1, 3, rim=4e-3).gear_mesh()
    assert len(mesh.faces) == len(ref.faces)
    assert mesh.volume == pytest.approx(ref.volume, rel=1e-5)


def test_surface_double_arc_tooth_ply_cloud_and_png(tmp_path):
    args = ["surface", str(EXAMPLE), "--gear", "1", "--profile", "double-arc", "--points", "5"]
    files = {"--export": "tooth.ply", "--cloud": "flanks.ply", "--png": "tooth.png"}
    for opt, name in files.items():
        args += [opt, str(tmp_path / name)]
    r = runner.invoke(app, [*args, "--tooth"])
    assert r.exit_code == 0, r.output
    assert "internal, z = 28" in r.output and "double_arc profile" in r.output
    assert "tooth sector solid" in r.output
    for name in files.values():
        assert (tmp_path / name).stat().st_size > 1000


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--gear", "3"], "--gear: gear must be 1..2"),
        (["--points", "2"], "--points: must be an integer in [3, 401]"),
        (["--export", "gear.obj"], "--export: unknown file type '.obj'"),
        (["--png", "tooth.jpg"], "--png: unknown file type '.jpg' in tooth.jpg; use one of .png"),
        (["--cloud", "pts.xyz"], "--cloud: unknown file type '.xyz'"),
        (["--export", "."], "--export: unknown file type '(none)'"),
        (["--png", "missing_dir_is_a_file.png/t.png"], None),
    ],
)
def test_surface_rejects_bad_options(tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    if message is None:  # the folder of the file is an existing file
        (tmp_path / "missing_dir_is_a_file.png").write_text("")
        message = "--png missing_dir_is_a_file.png/t.png: missing_dir_is_a_file.png is a file"
    r = runner.invoke(app, ["surface", str(EXAMPLE), *args])
    assert r.exit_code == 2
    assert message in r.output
    assert "Traceback" not in r.output


def test_surface_needs_a_surface_table_and_a_nutation_design(no_surface_design):
    r = runner.invoke(app, ["surface", str(no_surface_design)])
    assert r.exit_code == 2 and "no 'surface' table" in r.output
    r = runner.invoke(app, ["surface", str(example_dir() / "gear_pair.toml")])
    assert r.exit_code == 2 and "need a nutation design" in r.output
    r = runner.invoke(app, ["surface", str(EXAMPLE), "--profile", "cycloid"])
    assert r.exit_code == 2


def test_surface_module_must_agree_with_the_mean_radii(tmp_path):
    text = EXAMPLE.read_text().replace('normal_module = "2 mm"', 'normal_module = "2.5 mm"')
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    r = runner.invoke(app, ["surface", str(bad)])
    assert r.exit_code == 2
    assert "surface.normal_module" in r.output
    assert "2.5 mm disagrees with the mean radius of gear1" in r.output


def test_both_gears_of_a_pair_come_from_one_crown_gear(tmp_path):
    # without normal_module, the module is taken from the pair's nutating gear for both
    # gears (their mean radii agree only to the design's rounding): one crown gear
    text = EXAMPLE.read_text().replace('normal_module = "2 mm"', "")
    path = tmp_path / "no_module.toml"
    path.write_text(text)
    design = load_design(path)
    (c1, _), (c2, _) = design.tooth_generation(1), design.tooth_generation(2)
    assert c1.profile.module == c2.profile.module
    assert c1.mean_cone_distance == pytest.approx(c2.mean_cone_distance, rel=1e-12)
    assert c1.teeth == pytest.approx(c2.teeth, rel=1e-12)
