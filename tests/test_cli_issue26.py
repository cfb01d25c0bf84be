"""Smaller command-line fixes of issue 26 (item 9), each with its regression test."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from reducerlab.cli import app
from reducerlab.examples import example_dir

runner = CliRunner()
GEAR = str(example_dir() / "gear_pair.toml")


# ------------------------------------------------- messages name their command
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["regime-map", GEAR, "-x", "nope=1,2", "-y", "mesh.stiffness=1e8,2e8"],
         "regime-map: unknown parameter path 'nope'"),
        (["regime-map", GEAR, "-x", "mesh.stiffness=lin:a:b:c", "-y", "mesh.stiffness=1,2"],
         "regime-map -x 'mesh.stiffness': 'lin:a:b:c': write lin:START:STOP:N"),
        (["regime-map", GEAR, "-x", "mesh.stiffness=1e8", "-y", "mesh.stiffness=rel:a"],
         "regime-map -y 'mesh.stiffness': relative value 'a' is not a number"),
        (["frequency-response", GEAR, "-p", "nope", "-v", "1,2"],
         "frequency-response: unknown parameter path 'nope'"),
        (["frequency-response", GEAR, "-p", "mesh.stiffness", "-v", "abc"],
         "frequency-response --values 'mesh.stiffness': value 'abc' is not a number"),
        (["bifurcation", GEAR, "-p", "nope", "-v", "1,2"],
         "bifurcation: unknown parameter path 'nope'"),
    ],
)  # fmt: skip
def test_parameter_errors_name_the_command_not_sweep(tmp_path, args, message):
    r = runner.invoke(app, [*args, "-o", str(tmp_path / "out")])
    assert r.exit_code == 2, r.output
    text = " ".join(r.output.split())
    assert message in text and "sweep" not in text, text


# ------------------------------------------------- --write-design checked before the work
@pytest.mark.parametrize(
    ("where", "message"),
    [
        ("folder", "is a directory"),
        ("under-a-file", "is a file, not a directory"),
        ("bad-suffix", "unknown file type '.txt'"),
    ],
)
def test_write_design_is_checked_before_the_analysis(tmp_path, monkeypatch, where, message):
    import reducerlab.analysis.contact as contact

    def never(*a, **k):
        raise AssertionError("the analysis ran before --write-design was checked")

    monkeypatch.setattr(contact, "contact_analysis", never)
    (tmp_path / "afile").write_text("x")
    (tmp_path / "adir.toml").mkdir()
    target = {
        "folder": tmp_path / "adir.toml",
        "under-a-file": tmp_path / "afile" / "d.toml",
        "bad-suffix": tmp_path / "d.txt",
    }[where]
    surface = str(example_dir() / "nutation_surface.toml")
    r = runner.invoke(app, ["contact", surface, "--torque", "19.1 N*m", "-o",
                            str(tmp_path / "out"), "--write-design", str(target)])  # fmt: skip
    assert r.exit_code == 2, r.output
    assert "--write-design" in r.output and message in r.output, r.output


# ------------------------------------------------- --format and display units
KHV = str(example_dir() / "khv.toml")


def test_bifurcation_and_frequency_response_print_a_table_in_rpm(tmp_path):
    import json

    args = ["-p", "input_speed", "-v", "1400 rpm,1600 rpm", "--periods", "30"]
    r = runner.invoke(app, ["bifurcation", KHV, *args, "--keep", "3", "-o",
                            str(tmp_path / "b")])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "value (rpm)" in r.stdout and "period" in r.stdout and "{" not in r.stdout
    rows = [line.split() for line in r.stdout.splitlines() if line.strip()[:1].isdigit()]
    assert [float(x[0]) for x in rows] == [1400.0, 1600.0]
    r = runner.invoke(app, ["bifurcation", KHV, *args, "--keep", "3", "-o",
                            str(tmp_path / "b"), "--format", "json"])  # fmt: skip
    d = json.loads(r.stdout)
    assert d["display_unit"] == "rpm" and d["display_values"] == [1400.0, 1600.0]
    assert d["values"][0] == pytest.approx(1400 * 3.141592653589793 / 30)  # SI kept
    fr = ["frequency-response", KHV, *args, "--history", "4", "-o", str(tmp_path / "f")]
    r = runner.invoke(app, fr)
    assert r.exit_code == 0, r.output
    assert "value (rpm)" in r.stdout and "RMS DTE (um)" in r.stdout
    assert sum(line.split()[:2] == ["1400", "up"] for line in r.stdout.splitlines()) == 1
    d = json.loads(runner.invoke(app, [*fr, "--format", "json"]).stdout)
    assert d["display_unit"] == "rpm" and d["display_values"] == [1400.0, 1600.0]


# ------------------------------------------------- report -o DIR
@pytest.mark.parametrize("form", ["existing", "slash", "no-suffix"])
def test_report_into_a_folder(tmp_path, form):
    folder = tmp_path / "rdir"
    if form == "existing":
        folder.mkdir()
    arg = str(folder) + ("/" if form == "slash" else "")
    r = runner.invoke(app, ["report", GEAR, "-o", arg, "-s", "modal"])
    assert r.exit_code == 0, r.output
    assert (folder / "report.html").stat().st_size > 0
    # a file name still names the file; an existing file without a suffix is refused
    (tmp_path / "plain").write_text("x")
    r = runner.invoke(app, ["report", GEAR, "-o", str(tmp_path / "plain"), "-s", "modal"])
    assert r.exit_code == 2 and "unknown file type" in r.output


# ------------------------------------------------- Ctrl-C says what was kept
def _interrupt(monkeypatch, capsys, argv):
    import signal
    import sys

    from reducerlab.cli import main

    monkeypatch.setattr(sys, "argv", ["reducerlab", *argv])
    old = signal.getsignal(signal.SIGTERM)
    try:
        with pytest.raises(SystemExit) as e:
            main()
    finally:
        signal.signal(signal.SIGTERM, old)
    return e.value.code, " ".join(capsys.readouterr().err.split())


def test_ctrl_c_says_what_was_kept(tmp_path, monkeypatch, capsys):
    import reducerlab.analysis.bifurcation as bif
    import reducerlab.analysis.response as resp

    def halfway(design, axis, *, output, **kw):
        (output / "chunks").mkdir(parents=True)
        (output / "chunks" / "chunk_00000.npz").write_bytes(b"")
        raise KeyboardInterrupt

    monkeypatch.setattr(bif, "bifurcation", halfway)
    out = tmp_path / "run"
    code, err = _interrupt(monkeypatch, capsys, ["bifurcation", KHV, "-p", "gears.x1", "-v",
                                                 "0.5,0.6", "-o", str(out)])  # fmt: skip
    assert code == 130
    assert f"interrupted: 1 finished chunk(s) kept in {out}; run the same command" in err

    def at_once(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(resp, "response", at_once)
    code, err = _interrupt(monkeypatch, capsys, ["response", GEAR, "-o", str(tmp_path / "r")])
    assert code == 130 and "interrupted: nothing written" in err, err
