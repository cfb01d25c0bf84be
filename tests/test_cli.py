"""The command line on the bundled example, in a temporary folder."""

from __future__ import annotations

import json
import subprocess
import sys

from typer.testing import CliRunner

from reducerlab.cli import app
from reducerlab.examples import example_dir

runner = CliRunner()
EXAMPLE = example_dir() / "gear_pair.toml"


def test_help_lists_commands():
    r = runner.invoke(app, ["--help"])
    assert r.exit_code == 0
    for cmd in ("modal", "sensitivity", "demo"):
        assert cmd in r.output


def test_modal_table():
    r = runner.invoke(app, ["modal", str(EXAMPLE)])
    assert r.exit_code == 0, r.output
    assert "frequency (Hz)" in r.output and "rigid body" in r.output


def test_modal_json_and_outputs(tmp_path):
    r = runner.invoke(app, ["modal", str(EXAMPLE), "--format", "json", "-o", str(tmp_path)])
    assert r.exit_code == 0, r.output
    data = json.loads(r.stdout)
    f = data["frequencies_hz"]
    assert f == sorted(f) and len(f) == 6 and f[0] == 0.0
    assert all({"frequency_hz", "classification"} <= set(m) for m in data["modes"])
    for name in (
        "modal.nc",
        "modal.json",
        "modal.txt",
        "mode_shapes.png",
        "energy.png",
        "drive_shapes.png",
    ):
        assert (tmp_path / name).stat().st_size > 0


def test_bad_design_gives_message_and_exit_code_2(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(EXAMPLE.read_text().replace('mass = "1.25 kg"', 'mass = "-642 g"'))
    r = runner.invoke(app, ["modal", str(bad)])
    assert r.exit_code == 2
    assert "pinion.mass" in r.output and "-642 g" in r.output
    assert "Traceback" not in r.output
    r = runner.invoke(app, ["modal", str(tmp_path / "none.toml")])
    assert r.exit_code == 2 and "no such design file" in r.output


def test_bad_option_is_rejected():
    r = runner.invoke(app, ["modal", str(EXAMPLE), "--format", "xml"])
    assert r.exit_code == 2 and "xml" in r.output


def test_sensitivity_list_and_json(tmp_path):
    r = runner.invoke(app, ["sensitivity", str(EXAMPLE), "--list"])
    assert r.exit_code == 0 and "mesh.stiffness = 3.8e+08" in r.output
    r = runner.invoke(
        app,
        [
            "sensitivity",
            str(EXAMPLE),
            "-p",
            "mesh.stiffness",
            "--format",
            "json",
            "-o",
            str(tmp_path),
        ],
    )
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["parameters"] == ["mesh.stiffness"]
    assert d["relative"][0] == [None]  # rigid mode
    assert 0 < max(row[0] for row in d["relative"][1:]) <= 0.5
    assert (tmp_path / "sensitivity.png").exists()
    r = runner.invoke(app, ["sensitivity", str(EXAMPLE), "-p", "mesh.bogus"])
    assert r.exit_code == 2 and "has no parameter 'bogus'" in r.output


def test_console_script_version():
    r = subprocess.run(
        [sys.executable, "-m", "reducerlab", "--version"], capture_output=True, text=True
    )
    assert r.returncode == 0 and r.stdout.startswith("reducerlab ")


def test_kinematics_table_json_and_figure(tmp_path):
    design = example_dir() / "nutation_double.toml"
    r = runner.invoke(app, ["kinematics", str(design)])
    assert r.exit_code == 0, r.output
    assert "ratio i = omega_in / omega_out = 105" in r.output
    r = runner.invoke(app, ["kinematics", str(design), "--format", "json", "-o", str(tmp_path)])
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["ratio"] == 105.0
    assert d["mesh_frequencies_hz"]["mesh 1 (gears 1-2)"] == 650.0  # 26 x 25 rev/s
    assert set(d["cone_angles_deg"]) == {"gear 1", "gear 2", "gear 3", "gear 4"}
    assert (tmp_path / "angular_velocity.png").stat().st_size > 0
    from reducerlab.analysis.kinematics import KinematicsResult

    back = KinematicsResult.load(tmp_path / "kinematics.nc")
    assert back.ratio == 105.0 and back.data["omega"].shape == (2, 361, 3)


def test_kinematics_of_a_gear_pair_and_of_a_design_without_kinematics():
    r = runner.invoke(app, ["kinematics", str(EXAMPLE), "--format", "json"])
    assert r.exit_code == 0 and json.loads(r.stdout)["ratio"] == -2.4
    r = runner.invoke(app, ["kinematics", str(example_dir() / "torsional_chain.toml")])
    assert r.exit_code == 2 and "defines no drive kinematics" in r.output
    r = runner.invoke(app, ["modal", str(example_dir() / "khv_kinematics.toml")])
    assert r.exit_code == 2 and "kinematics only" in r.output
