"""Issue 13, command line: one output convention (-o DIR, checked before any work,
atomic sets, reported replacements), verbatim error text, validated options with
bounds, --scheduler checks, response --period, stamped and reloadable result files."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from reducerlab import __version__
from reducerlab.cli import app, options
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.io import OutputSet, prepare_output_dir, prepare_output_file
from reducerlab.results import Result

runner = CliRunner()
GEAR = str(example_dir() / "gear_pair.toml")
KHV = str(example_dir() / "khv.toml")
NUTATION = str(example_dir() / "nutation_double.toml")
SURFACE = str(example_dir() / "nutation_surface.toml")
CYCLOID = str(example_dir() / "cycloid_ball.toml")
SHORT = ["--periods", "20", "--keep", "5"]

# every command that writes files, with arguments for a short run (design first)
WRITERS = {
    "modal": ["modal", GEAR],
    "sensitivity": ["sensitivity", GEAR, "-p", "mesh.stiffness"],
    "kinematics": ["kinematics", NUTATION],
    "campbell": ["campbell", GEAR, "--speeds", "lin:0:3000:11"],
    "sweep": ["sweep", GEAR, "-p", "mesh.stiffness", "-v", "150%,200%", "--workers", "1"],
    "bifurcation": ["bifurcation", KHV, "-p", "gears.x1", "-v", "0.5,0.6", *SHORT],
    "response": ["response", GEAR, *SHORT, "--history", "2"],
    "frequency-response": [
        "frequency-response",
        KHV,
        "-p",
        "input_speed",
        "-v",
        "1400 rpm,1500 rpm",
        "--periods",
        "20",
        "--history",
        "2",
    ],
    "khv closed-graph": ["khv", "closed-graph", KHV],
    "khv stiffness": ["khv", "stiffness", KHV, "--x1", "0.5"],
    "balls": ["balls", CYCLOID, "--points", "3", "--phases", "1"],
    "datasheet": ["datasheet", GEAR, "--steps", "3", "--rigid", "--positions", "3"],
    "efficiency": ["efficiency", GEAR, "--rigid", "--positions", "3", "--loads", "1"],
    "accuracy": ["accuracy", KHV, "--samples", "256"],
    "khv clearances": ["khv", "clearances", KHV, "--teeth=-1:1", "--positions", "2"],
    # coarse FE teeth (0.35 m) and 3 positions: about 15 s
    "khv sharing": [
        "khv",
        "sharing",
        KHV,
        "--positions",
        "3",
        "--torques",
        "0,50",
        "--tooth-size",
        "1.225 mm",
    ],
    "contact": [
        "contact",
        SURFACE,
        "--torque",
        "19.1 N*m",
        "--rigid",
        "--positions",
        "4",
        "--order",
        "1",
    ],
}


def _with_design(args: list[str], design: str) -> list[str]:
    """The command's arguments with its design file replaced."""
    return [design if a in (GEAR, KHV, NUTATION, SURFACE, CYCLOID) else a for a in args]


# ------------------------------------------------------------------ output convention
def test_khv_commands_write_into_an_output_directory(tmp_path):
    out = tmp_path / "a.b"  # a dot in the name used to crash (matplotlib format 'b')
    r = runner.invoke(app, ["khv", "closed-graph", KHV, "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert (out / "closed-graph.png").stat().st_size > 0
    assert f"wrote {out / 'closed-graph.png'}" in r.stderr
    r = runner.invoke(app, ["khv", "stiffness", KHV, "--x1", "0.5", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert (out / "mesh-stiffness.png").stat().st_size > 0
    assert f"wrote {out / 'mesh-stiffness.png'}" in r.stderr
    assert sorted(p.name for p in out.iterdir()) == ["closed-graph.png", "mesh-stiffness.png"]


@pytest.mark.parametrize("command", [*WRITERS, "demo"])
def test_an_output_that_is_a_file_is_refused_before_any_work(tmp_path, command):
    target = tmp_path / "taken"
    target.write_text("keep me")
    # a missing design: the -o check must come first (before the design is even read)
    args = _with_design(WRITERS.get(command, ["demo"]), str(tmp_path / "missing.toml"))
    r = runner.invoke(app, [*args, "-o", str(target)])
    assert r.exit_code == 2, r.output
    assert f"-o {target}: is an existing file; -o names an output directory" in r.output
    assert "Traceback" not in r.output and target.read_text() == "keep me"
    r = runner.invoke(app, [*args, "-o", str(target / "sub")])
    assert r.exit_code == 2 and f"{target} is a file, not a directory" in r.output


def test_output_set_is_all_or_nothing(tmp_path, monkeypatch):
    from reducerlab.analysis.modal import ModalResult

    out = tmp_path / "d"
    r = runner.invoke(app, ["modal", GEAR, "-o", str(out)])
    assert r.exit_code == 0, r.output
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert set(before) == {
        "modal.nc",
        "modal.json",
        "modal.txt",
        "mode_shapes.png",
        "energy.png",
        "drive_shapes.png",
    }

    def broken(self, *a, **k):
        raise OSError("disk full")

    monkeypatch.setattr(ModalResult, "plot_energy", broken)
    r = runner.invoke(app, ["modal", GEAR, "-o", str(out)])
    assert r.exit_code == 2 and "disk full" in r.output
    # nothing replaced, nothing partial, no staging folder left behind
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert [p.name for p in tmp_path.iterdir()] == ["d"]
    r = runner.invoke(app, ["modal", GEAR, "-o", str(tmp_path / "new")])
    assert r.exit_code == 2 and not (tmp_path / "new").exists()


def test_replaced_outputs_are_reported(tmp_path):
    out = tmp_path / "c"
    args = ["campbell", GEAR, "--speeds", "lin:0:3000:11", "-o", str(out)]
    r = runner.invoke(app, args)
    assert r.exit_code == 0 and f"wrote {out / 'campbell.nc'}" in r.stderr
    r = runner.invoke(app, args)
    assert r.exit_code == 0
    assert f"replaced {out / 'campbell.nc'}" in r.stderr
    assert f"replaced {out / 'campbell.png'}" in r.stderr


def test_io_helpers(tmp_path):
    with pytest.raises(ReducerlabError, match=re.escape("--cloud: unknown file type '.txt'")):
        prepare_output_file(tmp_path / "a.txt", "--cloud", (".ply",))
    (tmp_path / "d.ply").mkdir()
    with pytest.raises(ReducerlabError, match="is a directory; --cloud names one file"):
        prepare_output_file(tmp_path / "d.ply", "--cloud", (".ply",))
    assert prepare_output_dir(tmp_path / "x" / "y") == tmp_path / "x" / "y"
    files = OutputSet(tmp_path / "s", report=None)
    with pytest.raises(ReducerlabError, match=re.escape("b.txt were not written")), files:
        files.path("a.txt").write_text("a")
        files.path("b.txt")
    assert not (tmp_path / "s").exists()
    with OutputSet(tmp_path / "s") as files, pytest.raises(ValueError, match="plain file"):
        files.path("../escape.txt")


linux_proc = pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs Linux /proc")


@linux_proc
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["modal", GEAR, "-o", "/proc/nope"],
         "-o /proc/nope: cannot create it, /proc is not writable"),
        (["modal", GEAR, "-o", "/proc"], "-o /proc: the directory is not writable"),
        (["sweep", GEAR, "-p", "mesh.stiffness", "-v", "1e8,2e8", "-o", "/proc/nope"],
         "-o /proc/nope: cannot create it, /proc is not writable"),
        (["surface", str(example_dir() / "nutation_surface.toml"), "-e", "/proc/x.stl"],
         "--export /proc/x.stl: cannot create it, /proc is not writable"),
    ],
)  # fmt: skip
def test_an_unwritable_output_is_refused_before_any_work(args, message):
    # root passes a permission check everywhere: writability is tested for real
    r = runner.invoke(app, args)
    assert r.exit_code == 2, r.output
    assert message in r.output
    assert "partial" not in r.output and "Errno" not in r.output and not r.stdout


def test_a_failed_commit_names_the_output_not_the_staging_folder(tmp_path, monkeypatch):
    import reducerlab.io as io

    def full(src, dst):
        raise OSError(28, "No space left on device", str(src))

    monkeypatch.setattr(io.os, "replace", full)
    out = tmp_path / "d"
    with pytest.raises(ReducerlabError) as exc, OutputSet(out) as files:
        files.path("a.txt").write_text("a")
    assert str(exc.value) == (
        f"-o {out / 'a.txt'}: cannot write it (No space left on device); the previous "
        "outputs are unchanged"
    )
    with pytest.raises(ReducerlabError) as exc, io.atomic_path(tmp_path / "b.nc") as tmp:
        tmp.write_text("b")
    assert str(exc.value) == f"{tmp_path / 'b.nc'}: cannot write it (No space left on device)"
    assert [p.name for p in tmp_path.iterdir()] == []


@linux_proc
def test_an_atomic_write_that_cannot_start_names_the_file():
    from reducerlab.io import atomic_path

    with (
        pytest.raises(ReducerlabError, match=re.escape("/proc/x.nc: cannot write it")),
        atomic_path("/proc/x.nc"),
    ):
        pass  # pragma: no cover - never entered


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def test_written_files_get_the_mode_of_a_plain_open(tmp_path):
    from reducerlab.io import FILE_MODE, atomic_path

    assert 0o666 & ~_umask() == FILE_MODE
    with atomic_path(tmp_path / "a.txt") as tmp:
        tmp.write_text("a")
    with OutputSet(tmp_path / "set") as files:
        files.path("b.txt").write_text("b")
    plain = tmp_path / "plain.txt"
    plain.write_text("c")
    want = plain.stat().st_mode & 0o777
    assert (tmp_path / "a.txt").stat().st_mode & 0o777 == want
    assert (tmp_path / "set" / "b.txt").stat().st_mode & 0o777 == want


def test_a_design_path_that_is_a_directory_or_a_device_says_so(tmp_path):
    r = runner.invoke(app, ["modal", str(tmp_path)])
    assert r.exit_code == 2 and f"{tmp_path}: is a directory" in r.output
    r = runner.invoke(app, ["modal", "/dev/zero"])
    assert r.exit_code == 2 and "/dev/zero: is not a regular file" in r.output
    assert "no such design file" not in r.output


# ------------------------------------------------------------------ verbatim messages
def test_error_text_is_printed_verbatim(tmp_path):
    weird = tmp_path / "x[/b]:a:[bold]"
    weird.mkdir(parents=True)
    bad = weird / "bad.toml"
    bad.write_text(Path(GEAR).read_text().replace('"3.8e8 N/m"', '"5 kg"'))
    r = runner.invoke(app, ["modal", str(bad)])
    assert r.exit_code == 2 and "Traceback" not in r.output
    assert f"{bad}: mesh.stiffness = '5 kg'" in r.output
    assert "[[mass] / [time] ** 2]" in r.output and "is [[mass]]" in r.output
    r = runner.invoke(app, ["sweep", GEAR, "-p", "mesh.stiffness", "-v", "lin:a:b:c",
                            "-o", str(tmp_path / "s")])  # fmt: skip
    assert r.exit_code == 2 and "'lin:a:b:c'" in r.output and "\U0001f170" not in r.output
    r = runner.invoke(app, ["modal", GEAR, "-o", str(weird / "out")])
    assert r.exit_code == 0, r.output
    assert f"wrote {weird / 'out' / 'modal.nc'}" in r.stderr


# ------------------------------------------------------------------ options
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["bifurcation", KHV, "-p", "gears.x1", "-v", "5 kg"], "'gears.x1': value '5 kg'"),
        (["bifurcation", KHV, "-p", "gears.x1", "-v", "lin:0.4:0.8:1000000"], "at most 100000"),
        (["bifurcation", KHV, "-p", "gears.x1", "-v", "0.5", "--steps", "0"], "'--steps'"),
        (["bifurcation", KHV, "-p", "gears.x1", "-v", "0.5", "--steps", "3"], "'--steps'"),
        (["bifurcation", KHV, "-p", "gears.x1", "-v", "0.5", "--steps", "1000000000"],
         "'--steps'"),
        (["bifurcation", KHV, "-p", "gears.x1", "-v", "0.5", "--periods", "10000000"],
         "'--periods'"),
        (["bifurcation", KHV, "-p", "gears.x1", "-v", "0.5", "--periods", "0"], "'--periods'"),
        (["bifurcation", KHV, "-p", "gears.x1", "-v", "0.5", "--periods", "10", "--keep", "11"],
         "--keep 11: must be at most --periods (10)"),
        (["bifurcation", KHV, "-p", "gears.x1", "-v", "0.5", "--workers", "0"], "'--workers'"),
        (["response", GEAR, "--periods", "10", "--keep", "5", "--history", "11"],
         "--history 11: must be at most --periods (10)"),
        (["response", GEAR, "--keep", "0"], "'--keep'"),
        (["response", GEAR, "--history", "-1"], "'--history'"),
        (["response", GEAR, "--steps", "0"], "'--steps'"),
        (["response", GEAR, "--period", "2 kg"], "--period: wrong dimension"),
        (["response", GEAR, "--period", "nan"], "--period: must be a finite time > 0"),
        (["response", GEAR, "--period", "-1"], "--period: must be a finite time > 0"),
        (["response", GEAR, "--frequency", "inf"], "--frequency: must be a finite frequency"),
        (["response", GEAR, "--frequency", "3 rpm"], "--frequency:"),
        (["response", GEAR, "--period", "1 ms", "--frequency", "1 kHz"], "give one of them"),
        (["campbell", GEAR, "--speeds", "lin:0:3000:100000000"],
         "--speeds: 'lin:0:3000:100000000' asks for 100000000 values; at most 100000"),
        (["check", GEAR, "--speed-range", "lin:0:3000:100000000"], "--speed-range:"),
        (["campbell", GEAR, "--speeds", "lin:0:1e300:5"],
         "--speeds: 2.5e+299 rpm is outside the range of speeds"),
        (["campbell", GEAR, "--speeds", "-100,1000"],
         "--speeds: -100 rpm is outside the range of speeds"),
        (["check", GEAR, "--speed-range", "1000,1e9"],
         "--speed-range: 1e+09 rpm is outside the range of speeds"),
        (["check", GEAR, "--margin", "nan"], "margin must be a fraction"),
        (["check", GEAR, "--margin", "-0.1"], "margin must be a fraction"),
        (["modal", GEAR, "--rigid-tol", "nan"], "'--rigid-tol'"),
        (["modal", GEAR, "--rigid-tol", "-1"], "'--rigid-tol'"),
        (["modal", GEAR, "--rigid-tol", "inf"], "'--rigid-tol'"),
        (["sweep", GEAR, "-p", "mesh.stiffness", "-v", "1,2", "--chunk-size", "0"],
         "'--chunk-size'"),
        (["sweep", GEAR, "-p", "mesh.stiffness", "-v", "1,2", "--workers", "-1"], "'--workers'"),
        (["sweep", GEAR, "-p", "mesh.stiffness", "-v", "lin:1:2:2000", "--grid",
          "gear.mass=lin:1:2:2000"], "4000000 points; at most 1000000"),
        (["khv", "stiffness", KHV, "--x1", "nan"], "--x1: 'nan': the values must be finite"),
        (["khv", "stiffness", KHV, "--x1", "0.5,inf"], "the values must be finite"),
        (["surface", str(example_dir() / "nutation_surface.toml"), "--points", "-3"],
         "--points: must be an integer in [3, 401]"),
    ],
)  # fmt: skip
def test_bad_options_are_refused_before_any_work(tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    r = runner.invoke(app, args)
    assert r.exit_code == 2, r.output
    assert message in r.output
    assert "Traceback" not in r.output and not list(tmp_path.iterdir())


@pytest.mark.parametrize("command", ["sweep", "bifurcation"])
def test_scheduler_address_and_connection_errors(tmp_path, monkeypatch, command):
    base = WRITERS[command]
    r = runner.invoke(app, [*base, "--scheduler", "garbage", "-o", str(tmp_path / "a")])
    assert r.exit_code == 2
    assert "--scheduler: 'garbage' is not a scheduler address; write tcp://HOST:PORT" in r.output
    monkeypatch.setattr(options, "SCHEDULER_TIMEOUT_S", 0.5)
    r = runner.invoke(app, [*base, "--scheduler", "tcp://127.0.0.1:1", "-o", str(tmp_path / "b")])
    assert r.exit_code == 2 and "Traceback" not in r.output
    assert "--scheduler tcp://127.0.0.1:1: cannot connect to a Dask scheduler" in r.output


def test_response_takes_the_forcing_period(tmp_path):
    # a gear pair with a constant mesh stiffness has no periodic law of its own
    text = Path(GEAR).read_text()
    text = re.sub(r"^stiffness_(harmonics|phases) = .*$", "", text, flags=re.M)
    design = tmp_path / "constant.toml"
    design.write_text(text)
    args = ["response", str(design), *SHORT, "--history", "2", "-o", str(tmp_path / "r")]
    r = runner.invoke(app, args)
    assert r.exit_code == 2 and "--period" in r.output and "--frequency" in r.output
    r = runner.invoke(app, [*args, "--period", "2 ms"])
    assert r.exit_code == 0, r.output
    from reducerlab.analysis.response import ResponseResult

    back = ResponseResult.load(tmp_path / "r" / "response.nc")
    assert back.data.attrs["forcing_hz"] == pytest.approx(500.0)
    r = runner.invoke(app, [*args, "--frequency", "250 Hz"])
    assert r.exit_code == 0, r.output
    back = ResponseResult.load(tmp_path / "r" / "response.nc")
    assert back.data.attrs["forcing_hz"] == pytest.approx(250.0)
    r = runner.invoke(app, [*args, "--period", "0.004"])  # plain number: seconds
    assert r.exit_code == 0, r.output
    assert ResponseResult.load(tmp_path / "r" / "response.nc").data.attrs[
        "forcing_hz"
    ] == pytest.approx(250.0)


# ------------------------------------------------------------------ stamps and reload
def _result_classes() -> dict[str, type[Result]]:
    import reducerlab.analysis.ball_track
    import reducerlab.analysis.bifurcation
    import reducerlab.analysis.body_modal
    import reducerlab.analysis.campbell
    import reducerlab.analysis.complex_modal
    import reducerlab.analysis.contact
    import reducerlab.analysis.efficiency
    import reducerlab.analysis.frequency_response
    import reducerlab.analysis.khv_sharing
    import reducerlab.analysis.kinematics
    import reducerlab.analysis.layout
    import reducerlab.analysis.modal
    import reducerlab.analysis.rating
    import reducerlab.analysis.regime_map
    import reducerlab.analysis.response
    import reducerlab.analysis.sweep
    import reducerlab.analysis.te_sweep
    import reducerlab.analysis.tolerances
    import reducerlab.analysis.torsion_test
    import reducerlab.analysis.transmission_accuracy  # noqa: F401

    found, todo = {}, [Result]
    while todo:
        cls = todo.pop()
        found[cls.kind] = cls
        todo.extend(cls.__subclasses__())
    return found


def test_every_result_file_is_stamped_and_reloads(tmp_path):
    from reducerlab.drives import load_design

    classes = _result_classes()
    seen: set[str] = set()
    for name, args in WRITERS.items():
        out = tmp_path / name.replace(" ", "-")
        r = runner.invoke(app, [*args, "-o", str(out)])
        assert r.exit_code == 0, (name, r.output)
        design_path = next(a for a in args if a.endswith(".toml"))
        design = load_design(design_path)
        for nc in out.glob("*.nc"):
            with xr.open_dataset(nc) as ds:
                kind = ds.attrs["result_kind"]
            res = classes[kind].load(nc)
            assert type(Result.load(nc)) is classes[kind], nc  # the base class dispatches
            seen.add(kind)
            stamp = res.provenance
            assert stamp["reducerlab_version"] == __version__, nc
            assert re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\+00:00", stamp["created"]), nc
            assert stamp["design_hash"] == design.hash, nc
            assert stamp["design"] == json.loads(design.provenance["design"]), nc
        for f in out.rglob("*"):  # results are readable by others, as with a plain open()
            if f.is_file():
                assert f.stat().st_mode & 0o777 == 0o666 & ~_umask(), f
        for js in out.glob("*.json"):
            if js.name in ("sweep.json", "bifurcation.json"):  # resume manifests
                assert json.loads(js.read_text())["design_hash"] == design.hash, js
                continue
            d = json.loads(js.read_text())
            assert d["reducerlab_version"] == __version__, js
            assert d["design_hash"] == design.hash and d["created"], js
            assert d["design"] == json.loads(design.provenance["design"]), js
        pngs = list(out.glob("*.png"))
        assert pngs, name
        for png in pngs:  # figures carry the stamp as PNG text chunks
            from PIL import Image

            with Image.open(png) as im:
                text = dict(im.text)
            assert text["reducerlab_version"] == __version__, png
            assert text["created"] and text["design_hash"], png
            if name != "khv closed-graph":  # that one reads the gears table only
                assert text["design_hash"] == design.hash, png
    assert seen == {
        "modal", "sensitivity", "kinematics", "campbell", "sweep", "bifurcation", "response",
        "contact", "frequency-response", "ball-track", "khv-sharing", "torsion-test",
        "efficiency", "transmission-accuracy",
    }  # fmt: skip


def test_loading_a_garbage_result_file_names_the_file(tmp_path):
    from reducerlab.analysis.modal import ModalResult

    rng = np.random.default_rng(0)
    cases = {
        "random.nc": rng.bytes(4096),
        "empty.nc": b"",
        "truncated.nc": b"\x89HDF\r\n\x1a\n" + rng.bytes(100),
    }
    for name, content in cases.items():
        p = tmp_path / name
        p.write_bytes(content)
        with pytest.raises(ReducerlabError, match=rf"{name}: not a readable result file"):
            ModalResult.load(p)
    other = tmp_path / "other.nc"
    xr.Dataset({"x": ("t", np.arange(3.0))}).to_netcdf(other)
    with pytest.raises(ReducerlabError, match=r"other\.nc: a netCDF file but not a reducerlab"):
        ModalResult.load(other)


def test_result_load_dispatches_on_the_stored_kind(tmp_path):
    from reducerlab.analysis.campbell import CampbellResult
    from reducerlab.analysis.modal import ModalResult
    from reducerlab.results import _KNOWN_KINDS

    # every kind is known with its module, so Result.load finds it before an import
    classes = _result_classes()
    assert {k: c.__module__ for k, c in classes.items() if k != "result"} == _KNOWN_KINDS
    r = runner.invoke(app, ["campbell", GEAR, "--speeds", "0,1000", "-o", str(tmp_path)])
    assert r.exit_code == 0, r.output
    nc = tmp_path / "campbell.nc"
    assert isinstance(Result.load(nc), CampbellResult)
    with pytest.raises(ReducerlabError, match="holds a 'campbell' result, not a 'modal' result"):
        ModalResult.load(nc)
    with xr.open_dataset(nc) as ds:
        data = ds.load()
    data.attrs["result_kind"] = "future"
    data.to_netcdf(tmp_path / "future.nc")
    with pytest.raises(ReducerlabError, match="holds a result of unknown kind 'future'"):
        Result.load(tmp_path / "future.nc")
    # in a fresh interpreter, without importing the analysis module first
    code = (
        "import sys; from reducerlab.results import Result; "
        "print(type(Result.load(sys.argv[1])).__name__)"
    )
    out = subprocess.run(
        [sys.executable, "-c", code, str(nc)], capture_output=True, text=True, check=True
    )
    assert out.stdout.strip() == "CampbellResult"


def test_save_is_atomic(tmp_path, monkeypatch):
    from reducerlab.analysis.modal import modal
    from reducerlab.drives import build_model, load_design

    res = modal(build_model(load_design(GEAR)))
    p = res.save(tmp_path / "m.nc")
    old = p.read_bytes()

    def fail(self, path, **kwargs):
        Path(path).write_bytes(b"half")
        raise OSError("interrupted")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", fail)
    with pytest.raises(OSError, match="interrupted"):
        res.save(p)
    assert p.read_bytes() == old and [f.name for f in tmp_path.iterdir()] == ["m.nc"]


def test_a_set_that_fails_halfway_is_rolled_back(tmp_path, monkeypatch):
    """If moving the files of a set into place fails after some were moved (a full disk,
    a file system error), the ones already moved are put back: the previous set is
    untouched, not half old and half new."""
    import reducerlab.io as rio

    out = tmp_path / "o"
    out.mkdir()
    (out / "a.txt").write_text("old a")
    (out / "b.txt").write_text("old b")
    real = os.replace
    calls = {"n": 0}

    def flaky(src, dst):
        if Path(dst).parent == out:
            calls["n"] += 1
            if calls["n"] == 2:
                raise OSError(28, "No space left on device")
        return real(src, dst)

    monkeypatch.setattr(rio.os, "replace", flaky)
    with (
        pytest.raises(ReducerlabError, match=r"b\.txt: cannot write it .*previous outputs"),
        rio.OutputSet(out, "-o") as files,
    ):
        files.path("a.txt").write_text("new a")
        files.path("b.txt").write_text("new b")
        files.path("c.txt").write_text("new c")
    assert (out / "a.txt").read_text() == "old a"
    assert (out / "b.txt").read_text() == "old b"
    assert sorted(p.name for p in out.iterdir()) == ["a.txt", "b.txt"]
