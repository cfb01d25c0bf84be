"""Load capacity rating of the designs (issue 29): ``load_capacity`` and ``reducerlab
rating``.

Oracles: the structure of ISO 6336-2/-3:2019 itself. The contact stress grows with the
square root of the tangential load (Eq. 2 to 4) and the root stress in proportion to it
(Eq. 2 to 3), while the permissible stresses do not depend on the load; so doubling the
torque divides S_H by exactly sqrt(2) and S_F by exactly 2. The published worked example
is in ``tests/published/test_iso6336_example.py``.
"""

from __future__ import annotations

import json
import math

import pytest
from typer.testing import CliRunner

from reducerlab.analysis.rating import RatingResult, load_capacity
from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.rating.material import RatingConditions

runner = CliRunner()
GEAR_PAIR = example_dir() / "gear_pair.toml"
KHV = example_dir() / "khv.toml"


@pytest.fixture(scope="module")
def pair_design():
    return load_design(GEAR_PAIR)


def test_safety_factors_scale_with_the_load_as_the_standard_says(pair_design):
    a = load_capacity(pair_design, torque=60.0)
    b = load_capacity(pair_design, torque=120.0)
    for gear in ("1", "2"):
        assert a.value("S_H", gear) / b.value("S_H", gear) == pytest.approx(math.sqrt(2), rel=1e-12)
        assert a.value("S_F", gear) / b.value("S_F", gear) == pytest.approx(2.0, rel=1e-12)
    # the design's own load is its 60 N m pinion torque; power = torque x speed
    own = load_capacity(pair_design)
    w = pair_design.operating.speed
    by_power = load_capacity(pair_design, power=60.0 * w)
    assert own.pairs() == a.pairs()
    assert by_power.value("S_F", "1") == pytest.approx(a.value("S_F", "1"), rel=1e-12)


def test_every_factor_closes_the_chain(pair_design):
    r = load_capacity(pair_design, conditions=RatingConditions(K_v=1.2, S_Fmin=1.0))
    v = r.value
    for g in ("1", "2"):
        # sigma_H = Z_B|D sigma_H0 sqrt(K_A K_v K_Hbeta K_Halpha), S_H = sigma_HG / sigma_H
        zbd = v("Z_B", "1") if g == "1" else v("Z_D", "2")
        k = math.sqrt(v("K_A") * v("K_v") * v("K_Hbeta") * v("K_Halpha"))
        assert v("sigma_H", g) == pytest.approx(zbd * v("sigma_H0") * k, rel=1e-12)
        hg = v("sigma_Hlim", g) * v("Z_NT", g) * v("Z_L") * v("Z_v") * v("Z_R")
        assert v("S_H", g) == pytest.approx(hg / v("sigma_H", g), rel=1e-12)
        # sigma_F0 = F_t / (b m) Y_F Y_S; S_F = sigma_FG / sigma_F with S_Fmin = 1
        assert v("sigma_FP", g) / v("sigma_F", g) == pytest.approx(v("S_F", g), rel=1e-12)
    assert v("K_v") == 1.2


def test_khv_internal_pair(tmp_path):
    r = load_capacity(load_design(KHV))
    p = r.pairs()["mesh K-V"]
    assert p["gears"] == ["planet V", "ring K"]
    assert r.value("Z_D", "2") == 1.0  # ISO 6336-2: Z_D = 1 for an internal gear
    # the planet carries the output torque (50 N m) on its reference radius 52.5 mm
    assert r.value("F_t") == pytest.approx(50.0 / 0.0525, rel=1e-12)
    assert all(s > 0 for s in p["S_H"] + p["S_F"])
    back = RatingResult.load(r.save(tmp_path / "r.nc"))
    assert back.pairs() == r.pairs()
    assert back.value("Y_F", "2") == r.value("Y_F", "2")


def test_cli_writes_and_prints(tmp_path):
    out = tmp_path / "out"
    res = runner.invoke(app, ["rating", str(GEAR_PAIR), "-o", str(out), "--kv", "1.05"])
    assert res.exit_code == 0, res.output
    assert "S_H: pinion" in res.output and "Y_F" in res.output
    assert {p.name for p in out.iterdir()} == {
        "rating.nc",
        "rating.json",
        "rating.txt",
        "rating.png",
    }
    data = json.loads((out / "rating.json").read_text())
    assert data["pairs"]["pair"]["gears"] == ["pinion", "gear"]
    res = runner.invoke(app, ["rating", str(GEAR_PAIR), "--format", "json", "--torque", "90 N*m"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.output)["factors"]


@pytest.mark.parametrize(
    "args, named",
    [
        (["--kv", "0.9"], "--kv"),
        (["--torque", "1 N*m", "--power", "1 kW"], "--power/--torque"),
        (["--set", "mesh.face_width=null"], "mesh.face_width"),
        (["--set", "material.sigma_Hlim=-5 MPa"], "material.sigma_Hlim"),
    ],
)
def test_cli_refuses_bad_input_naming_it(args, named):
    res = runner.invoke(app, ["rating", str(GEAR_PAIR), *args])
    assert res.exit_code != 0
    assert named in res.output


def test_no_load_refused(pair_design):
    unloaded = pair_design.with_values({"operating.torque": None})
    with pytest.raises(ReducerlabError, match="torque/power"):
        load_capacity(unloaded)
