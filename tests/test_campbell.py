"""Campbell diagrams and the resonance check against closed forms, and their CLI."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.campbell import CampbellResult, campbell
from reducerlab.analysis.excitation import excitation_orders
from reducerlab.analysis.resonance import format_check, resonance_check
from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.model import Centripetal, Dof, Inertia, Model, Support

runner = CliRunner()
GEAR = example_dir() / "gear_pair.toml"


def oscillator(centripetal: bool) -> Model:
    els = [Inertia("b.x", 2.0), Support("b.x", 8.0e5)]
    if centripetal:
        els.append(Centripetal("b.x", 2.0))
    return Model([Dof("b", "x")], els, speed=100.0)


def test_constant_frequency_crossings_are_exact():
    # f_n = sqrt(k/m)/2pi is speed independent: line q Omega / 2pi crosses it at
    # Omega* = 2 pi f_n / q = sqrt(k/m) / q
    wn = math.sqrt(8.0e5 / 2.0)
    res = campbell(oscillator(False), np.linspace(0, 1000, 51), orders={"1x": 1.0, "3x": 3.0})
    cr = {c["excitation"]: c["speed_rad_s"] for c in res.crossings()}
    assert cr["1x"] == pytest.approx(wn, rel=1e-10)
    assert cr["3x"] == pytest.approx(wn / 3, rel=1e-10)


def test_speed_dependent_crossing_closed_form():
    # f(Omega) = sqrt(k/m - Omega^2)/2pi meets q Omega/2pi at Omega* = sqrt(k/m/(1+q^2));
    # the grid is coarse, the root finder on the exact relation is not
    q, kpm = 2.0, 8.0e5 / 2.0
    res = campbell(oscillator(True), np.linspace(0, 600, 13), orders={"2x": q})
    (c,) = res.crossings()
    assert c["speed_rad_s"] == pytest.approx(math.sqrt(kpm / (1 + q * q)), rel=1e-9)
    f = res.data["frequency"].values[:, 0]
    w = res.data["speed"].values
    np.testing.assert_allclose(f[w**2 < kpm], np.sqrt(kpm - w[w**2 < kpm] ** 2) / (2 * math.pi))


def test_excitation_orders_from_kinematics_and_from_laws():
    assert excitation_orders(load_design(GEAR)) == pytest.approx(
        {"1x input": 1.0, "1x mesh": 25.0, "2x mesh": 50.0, "3x mesh": 75.0}
    )
    chain = load_design(example_dir() / "torsional_chain.toml")  # no kinematics: mesh law
    assert excitation_orders(chain) == pytest.approx(
        {"1x input": 1.0, "1x mesh": 16.0, "2x mesh": 32.0, "3x mesh": 48.0}
    )


def test_resonance_check_of_the_example():
    design = load_design(GEAR)
    report = resonance_check(design)
    assert not report["ok"]
    # 2x mesh = 50 Omega/2pi meets mode 2 (1382.35 Hz) at Omega = 2 pi 1382.35 / 50
    c = next(c for c in report["crossings"] if c["mode"] == 2 and c["excitation"] == "2x mesh")
    assert c["speed_rpm"] == pytest.approx(1382.3498 / 50 * 60, rel=1e-6)
    assert "RESONANCE RISK" in format_check(report)
    quiet = resonance_check(design, speed_range=(10.0, 20.0))
    assert quiet["ok"] and "no resonance risk" in format_check(quiet)
    with pytest.raises(ReducerlabError, match="margin"):
        resonance_check(design, margin=2.0)
    with pytest.raises(ReducerlabError, match="speed range"):
        resonance_check(design, speed_range=(20.0, 10.0))


def test_campbell_bad_input():
    with pytest.raises(ReducerlabError, match="at least two speeds"):
        campbell(oscillator(False), [1.0])
    with pytest.raises(ReducerlabError, match="strictly increasing"):
        campbell(oscillator(False), [0.0, 2.0, 1.0])
    with pytest.raises(ReducerlabError, match="orders must be positive"):
        campbell(oscillator(False), [0.0, 1.0], orders={"x": -1.0})
    from reducerlab.errors import DesignError

    with pytest.raises(DesignError, match="kinematics only"):
        campbell(load_design(example_dir() / "khv_kinematics.toml"))


def test_cli_check_exit_codes():
    r = runner.invoke(app, ["check", str(GEAR)])
    assert r.exit_code == 1 and "RESONANCE RISK" in r.output
    r = runner.invoke(app, ["check", str(GEAR), "--speed-range", "100,200"])
    assert r.exit_code == 0 and "no resonance risk" in r.output
    r = runner.invoke(app, ["check", str(GEAR), "--format", "json", "--margin", "0.01"])
    d = json.loads(r.stdout)
    assert d["margin"] == 0.01 and not d["ok"]
    r = runner.invoke(app, ["check", str(GEAR), "--margin", "5"])
    assert r.exit_code == 2 and "margin must be a fraction" in r.output


def test_cli_campbell(tmp_path):
    r = runner.invoke(
        app, ["campbell", str(GEAR), "--speeds", "lin:0:3000:61", "-o", str(tmp_path)]
    )
    assert r.exit_code == 0, r.output
    assert (tmp_path / "campbell.png").stat().st_size > 0
    back = CampbellResult.load(tmp_path / "campbell.nc")
    assert back.data["speed"].size == 61
    r = runner.invoke(app, ["campbell", str(GEAR), "--format", "json"])
    assert json.loads(r.stdout)["crossings"]
    r = runner.invoke(app, ["campbell", str(GEAR), "--speeds", "rel:1,2"])
    assert r.exit_code == 2 and "plain numbers in rpm" in r.output


def test_cli_sweep(tmp_path):
    out = tmp_path / "s"
    r = runner.invoke(
        app,
        ["sweep", str(GEAR), "-p", "mesh.stiffness", "-v", "150%,200%,250%", "-o", str(out),
         "--format", "json", "--workers", "1"],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["values"][0] == pytest.approx([5.7e8, 7.6e8, 9.5e8])
    assert len(d["frequencies_hz"]) == 3 and d["vectorised"]
    assert (out / "sweep.png").exists() and (out / "sweep.nc").exists()
    r = runner.invoke(
        app,
        ["sweep", str(GEAR), "-p", "mesh.stiffness", "-v", "lin:1e8:1e9:3",
         "--grid", "gear.mass=5,6", "-o", str(tmp_path / "g"), "--workers", "1"],
    )  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "grid 3 x 2" in r.output
    r = runner.invoke(app, ["sweep", str(GEAR), "-p", "mesh.stiffness", "-v", "1,2",
                            "--grid", "gear.mass", "-o", str(tmp_path / "h")])  # fmt: skip
    assert r.exit_code == 2 and "--grid must be 'PATH=VALUES'" in r.output
    r = runner.invoke(app, ["sweep", str(GEAR), "-p", "nope.x", "-v", "1,2", "-o",
                            str(tmp_path / "i")])  # fmt: skip
    assert r.exit_code == 2 and "unknown parameter path 'nope.x'" in r.output
