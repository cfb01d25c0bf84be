"""The load capacity in the verdict (issue 29), both ways: a gear pair whose ISO 6336
safety factor falls below its minimum is a risk; the same pair at a load it carries is
not, and the numbers in the reasons are the rating's."""

from pathlib import Path

import pytest

from reducerlab import load_design
from reducerlab.analysis.capacity_reasons import capacity_reasons
from reducerlab.analysis.rating import load_capacity
from reducerlab.analysis.verdict import verdict

EXAMPLES = Path(__file__).parents[1] / "examples"


def _capacity(v):
    return [r for r in v.reasons if r["rule"] == "capacity"]


def test_rated_design_at_its_load_passes_capacity():
    design = load_design(EXAMPLES / "gear_pair.toml")
    v = verdict(design, run_response=False)
    rows = _capacity(v)
    assert len(rows) == 4  # S_H and S_F of pinion and gear
    assert all(r["status"] == "ok" for r in rows)
    s_h = load_capacity(design).pairs()["pair"]["S_H"]
    assert sorted(r["value"] for r in rows if r["factor"] == "S_H") == pytest.approx(sorted(s_h))


def test_overloaded_pair_is_a_risk():
    # 400/60 x the torque: ISO 6336-2 Eq. 7, S_H ~ 1/sqrt(T): 2.16/sqrt(6.67) = 0.84 <
    # S_Hmin = 1, while ISO 6336-3 Eq. 7, S_F ~ 1/T: 10.06/6.67 = 1.51 >= S_Fmin = 1.4
    design = load_design(EXAMPLES / "gear_pair.toml", ["operating.torque=400 N*m"])
    v = verdict(design, run_response=False)
    risks = [r for r in _capacity(v) if r["status"] == "risk"]
    assert risks and not v.ok
    assert {r["factor"] for r in risks} == {"S_H"}
    assert all(r["value"] < r["threshold"] for r in risks)
    assert "S_H = 0.8" in risks[0]["text"]


def test_unrateable_design_says_why_and_does_not_fail():
    rows = capacity_reasons(load_design(EXAMPLES / "nutation_double_sided.toml"))
    assert [r["status"] for r in rows] == ["note"]
    assert "involute" in rows[0]["text"]
    assert capacity_reasons(load_design(EXAMPLES / "cycloid_ball.toml")) == []


def test_capacity_can_be_left_out():
    design = load_design(EXAMPLES / "gear_pair.toml", ["operating.torque=600 N*m"])
    assert not _capacity(verdict(design, run_response=False, capacity=False))
