"""The resonance verdict's result (issue 25): a JSON-ready dict that carries the Campbell
diagram the verdict used, so the report and ``check -o`` draw it without computing it
again; the damped, whirl-split branches when the model has gyroscopic terms."""

from __future__ import annotations

import json

import pytest

from reducerlab.analysis import campbell as campbell_module
from reducerlab.analysis import resonance
from reducerlab.analysis.campbell import CampbellResult
from reducerlab.analysis.complex_modal import ComplexCampbellResult
from reducerlab.analysis.components import ComponentModes
from reducerlab.analysis.resonance import ResonanceResult, format_check, resonance_check
from reducerlab.drives import load_design
from reducerlab.examples import example_dir
from reducerlab.reporting import report

GEAR = example_dir() / "gear_pair.toml"
DISC = example_dir() / "spinning_disc.toml"


@pytest.fixture(scope="module")
def gear():
    return resonance_check(load_design(GEAR), components=[ComponentModes("gear 1", [900.0])])


def test_the_result_is_the_verdict_and_carries_its_diagram(gear):
    assert isinstance(gear, ResonanceResult) and isinstance(gear, dict)
    assert gear.ok == gear["ok"] and gear.table() == format_check(gear)
    assert json.loads(json.dumps(gear)) == gear.to_dict() == dict(gear)
    assert type(gear.to_dict()) is dict
    assert isinstance(gear.campbell, CampbellResult)
    assert [c.label for c in gear.components] == ["gear 1"]
    # the verdict's crossings are the carried diagram's, inside the checked range
    lo, hi = gear["speed_range_rpm"]
    inside = [c for c in gear.campbell.crossings() if lo <= c["speed_rpm"] <= hi]
    assert [c["speed_rpm"] for c in inside] == pytest.approx(
        [c["speed_rpm"] for c in gear["crossings"]]
    )


def test_plot_draws_the_carried_diagram_with_the_body_lines(gear):
    fig = gear.plot()
    (ax,) = fig.axes
    # the frequency axis where excitations can meet modes (10 % above 3x mesh at
    # 1800 rpm), the body mode on it, drawn in its own style
    assert ax.get_ylim()[1] == pytest.approx(1.1 * 75 * 1800 / 60)
    assert any(line.get_gid() == "component-mode" for line in ax.lines)
    # the body modes on the system modes' frequency axis: one marker per body mode
    (comp,) = gear.plot_components().axes
    marks = [ln for ln in comp.lines if ln.get_gid() == "body-mode"]
    assert [ln.get_xdata()[0] for ln in marks] == [900.0]


def test_gyroscopic_models_carry_the_complex_branches():
    res = resonance_check(load_design(DISC))
    assert res["frequencies"] != "undamped"
    assert isinstance(res.campbell, ComplexCampbellResult)
    assert "whirl" in res.campbell.data
    ax, bar = res.plot().axes  # the diagram and its damping colour bar
    assert ax.get_ylabel() == "damped natural frequency (Hz)"
    assert bar.get_xlabel() == "logarithmic decrement (damping)"


def test_the_report_does_not_compute_the_diagram_again(monkeypatch):
    calls = []
    real = resonance.campbell

    def counted(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)

    monkeypatch.setattr(resonance, "campbell", counted)
    monkeypatch.setattr(campbell_module, "campbell", counted)
    r = report(GEAR, only=["campbell"])
    assert r.section("campbell").values["crossings"]
    assert len(calls) == 1
