"""Gear-body (component) modes in the resonance check and its figures (paper 000 §4,
Tables 4-5): crossings with excitation lines in closed form, coincidences with system
modes, validation, figures and the JSON report."""

from __future__ import annotations

import io
import json
import math
from types import SimpleNamespace

import numpy as np
import pytest

from reducerlab.analysis.campbell import campbell
from reducerlab.analysis.components import ComponentModes
from reducerlab.analysis.excitation import excitation_orders
from reducerlab.analysis.resonance import format_check, resonance_check
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.plot.campbell import plot_campbell
from reducerlab.plot.components import plot_component_comparison

NUTATION = example_dir() / "nutation_double_sided.toml"
RPM = 60.0 / (2.0 * math.pi)
#: Input speeds (rad/s) where the example drive's own modes are clear of every
#: excitation line (highest line at the top: 89.1 x 130 / 2 pi = 1844 Hz, lowest
#: elastic mode 2239 Hz).
QUIET = (100.0, 130.0)
#: Paper 000 Table 4, gear 1 (the first five modes).
GEAR1 = ComponentModes(
    "gear 1",
    (4162.7, 4182.3, 5466.4, 5468.2, 6307.0),
    ("torsional", "torsional", "folding", "folding", "umbrella"),
    "paper 000 Table 4",
)


@pytest.fixture(scope="module")
def design():
    return load_design(NUTATION)


@pytest.fixture(scope="module")
def base(design):
    return resonance_check(design)


@pytest.fixture(scope="module")
def quiet(design):
    return resonance_check(design, speed_range=QUIET)


def elastic(report):
    return [f for f in report["system"]["frequencies_hz"] if f > 0]


def test_without_components_the_report_is_unchanged(design, base):
    assert set(base) == {"ok", "margin", "frequencies", "speed_range_rpm", "crossings", "near",
                         "stability", "title", "mesh_strain_share",
                         "forward_whirl_share"}  # fmt: skip
    assert resonance_check(design, components=()) == base
    assert "BODY" not in format_check(base) and "COINCIDE" not in format_check(base)


def test_body_mode_on_a_mesh_harmonic_crosses_at_the_closed_form_speed(design):
    orders = excitation_orders(design)
    name = "2x mesh 1 (gears 1-2)"
    w0 = 1500 / RPM  # inside the 1000-2000 rpm operating range
    f = orders[name] * w0 / (2 * math.pi)
    report = resonance_check(design, components=[ComponentModes("ring", [f], ["torsional"])])
    assert not report["ok"]
    lo, hi = (v / RPM for v in report["speed_range_rpm"])
    found = {c["excitation"]: c for c in report["component_crossings"]}
    c = found[name]
    assert (c["component"], c["mode"], c["type"]) == ("ring", 1, "torsional")
    assert c["speed_rad_s"] == pytest.approx(w0, rel=1e-9)
    assert c["speed_rad_s"] == pytest.approx(2 * math.pi * f / orders[name], rel=1e-12)
    assert c["speed_rpm"] == pytest.approx(1500.0, rel=1e-9)
    assert c["frequency_hz"] == f
    # every excitation line whose exact crossing speed lies in the range, and only those
    expect = {n for n, q in orders.items() if lo <= 2 * math.pi * f / q <= hi}
    assert set(found) == expect
    for n, row in found.items():
        assert row["speed_rad_s"] == pytest.approx(2 * math.pi * f / orders[n], rel=1e-12)
    near = next(r for r in report["component_near"] if r["excitation"] == name)
    assert near["distance"] == pytest.approx(0.0, abs=1e-12)
    assert report["components"][0]["closest"]["excitation"]["distance"] < 1e-12
    text = format_check(report)
    assert "CROSSING  ring mode 1 (torsional) with 2x mesh 1 (gears 1-2) at 1500 rpm" in text
    assert "RESONANCE RISK" in text


def test_body_mode_near_but_outside_the_range_is_near_at_the_range_end(design):
    orders = excitation_orders(design)
    name = "1x mesh 1 (gears 1-2)"
    # the line meets f at 2100 rpm, 5 % above the top of the range: closest at 2000 rpm
    f = orders[name] * 2100 / RPM / (2 * math.pi)
    report = resonance_check(design, components=[ComponentModes("ring", [f])])
    assert all(c["excitation"] != name for c in report["component_crossings"])
    near = next(r for r in report["component_near"] if r["excitation"] == name)
    fe = orders[name] * 2000 / RPM / (2 * math.pi)
    assert near["speed_rpm"] == pytest.approx(2000.0, rel=1e-12)
    assert near["excitation_hz"] == pytest.approx(fe, rel=1e-12)
    assert near["distance"] == pytest.approx(0.05, rel=1e-9)
    assert near["type"] == ""


def test_body_far_from_everything_keeps_ok(design, quiet):
    assert quiet["ok"]  # the drive itself is clear in this range
    top = max(excitation_orders(design).values()) * QUIET[1] / (2 * math.pi)
    system = elastic(resonance_check(design, speed_range=QUIET, components=[GEAR1]))
    f = 15000.0
    assert f >= 3 * top
    assert all(abs(f - fn) / fn >= 0.2 for fn in system)
    body = ComponentModes("gear 2", [f], ["torsional"], "synthetic")
    report = resonance_check(design, speed_range=QUIET, components=[body])
    assert report["ok"]
    assert not report["component_crossings"]
    assert not report["component_near"]
    assert not report["coincidences"]
    (summary,) = report["components"]
    assert summary["label"] == "gear 2" and summary["source"] == "synthetic"
    assert summary["frequencies"] == [f] and summary["types"] == ["torsional"]
    closest = summary["closest"]
    assert closest["excitation"]["distance"] == pytest.approx((f - top) / top, rel=1e-9)
    assert closest["system_mode"]["distance"] >= 0.2
    text = format_check(report)
    assert "no resonance risk" in text and "BODY      gear 2: 1 mode(s)" in text


def test_body_within_margin_of_a_system_mode_is_a_coincidence(design, quiet):
    system = resonance_check(design, speed_range=QUIET, components=[GEAR1])["system"]
    f6 = system["frequencies_hz"][5]  # system mode 6
    assert system["min_hz"][5] == pytest.approx(f6, rel=1e-12)  # speed independent here
    body = ComponentModes("gear 3", [1.05 * f6], ["circumferential"])
    report = resonance_check(design, speed_range=QUIET, components=[body])
    assert quiet["ok"] and not report["ok"]
    assert not report["component_crossings"] and not report["component_near"]
    row = next(r for r in report["coincidences"] if r["system_mode"] == 6)
    assert (row["component"], row["mode"], row["type"]) == ("gear 3", 1, "circumferential")
    assert row["distance"] == pytest.approx(0.05, rel=1e-9)  # relative to the system mode
    assert row["natural_hz"] == pytest.approx(1.05 * f6, rel=1e-15)
    assert row["system_hz"] == pytest.approx(f6, rel=1e-12)
    # every elastic system mode within 10 % is listed, none outside it
    expect = {j + 1 for j, fn in enumerate(system["frequencies_hz"])
              if fn > 0 and abs(1.05 * f6 - fn) / fn <= 0.10}  # fmt: skip
    assert {r["system_mode"] for r in report["coincidences"]} == expect
    assert report["components"][0]["closest"]["system_mode"]["system_mode"] == 6
    # a tighter margin drops it
    assert resonance_check(design, speed_range=QUIET, margin=0.04, components=[body])["ok"]
    text = format_check(report)
    assert "COINCIDE  gear 3 mode 1 (circumferential)" in text
    # percentages by the numformat rule (issue 32): 3 significant digits, no trailing zeros
    assert "within 5 % of system mode 6" in text


def test_rigid_system_modes_are_not_coincidences(design):
    report = resonance_check(design, speed_range=QUIET, components=[ComponentModes("g", [1e-3])])
    assert report["system"]["frequencies_hz"][0] == 0.0
    assert all(r["system_mode"] != 1 for r in report["coincidences"])


def test_report_serialises_to_json(design):
    report = resonance_check(design, components=[GEAR1, ComponentModes("gear 2", [11000.0])])
    back = json.loads(json.dumps(report, allow_nan=False))
    assert back == report
    assert [c["label"] for c in back["components"]] == ["gear 1", "gear 2"]


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (("", [1.0]), "label must be a non-empty string"),
        ((3, [1.0]), "label must be a non-empty string"),
        (("g", []), "frequencies must hold at least one frequency"),
        (("g", "100"), "frequencies must be a sequence of numbers"),
        (("g", 100.0), "frequencies must be a sequence of numbers"),
        (("g", [1.0, "2"]), r"frequencies\[1\] must be a number"),
        (("g", [1.0, True]), r"frequencies\[1\] must be a number"),
        (("g", np.ones((2, 2))), "frequencies must be one-dimensional"),
        (("g", [100.0, -5.0]), r"finite and > 0 Hz, frequencies\[1\] = -5.0"),
        (("g", [0.0]), "finite and > 0 Hz"),
        (("g", [math.nan]), "finite and > 0 Hz"),
        (("g", [math.inf]), "finite and > 0 Hz"),
        (("g", [200.0, 100.0]), r"frequencies must be ascending.*frequencies\[1\] = 100.0"),
        (("g", [1.0, 2.0], ["a"]), "types must have the same length as frequencies"),
        (("g", [1.0], [3]), "types must be strings"),
        (("g", [1.0], "torsional"), "types must be a sequence of strings"),
        (("g", [1.0], (), 5), "source must be a string"),
    ],
)
def test_bad_component_modes(args, match):
    with pytest.raises(ReducerlabError, match=match):
        ComponentModes(*args)


def test_component_modes_normalise():
    c = ComponentModes("gear 4", np.array([10.0, 10.0, 20]))  # repeated roots allowed
    assert c.frequencies == (10.0, 10.0, 20.0) and c.types == ("", "", "")
    assert all(type(f) is float for f in c.frequencies)
    with pytest.raises(AttributeError):
        c.label = "x"  # frozen
    fake = SimpleNamespace(
        frequencies=np.array([1.0, 2.0]),
        types=["torsional", "folding"],
        data=SimpleNamespace(attrs={"gear": 2, "boundary": "free"}),
    )
    b = ComponentModes.from_body_modal(fake)
    assert b.label == "gear 2" and b.types == ("torsional", "folding")
    assert b.source == "FE body modes (free)"


def test_bad_components_argument(design):
    with pytest.raises(ReducerlabError, match="sequence of ComponentModes"):
        resonance_check(design, components=[[1.0, 2.0]])
    with pytest.raises(ReducerlabError, match="sequence of ComponentModes"):
        resonance_check(design, components="gear 1")
    with pytest.raises(ReducerlabError, match="labels must be unique, 'gear 1'"):
        resonance_check(design, components=[GEAR1, GEAR1])
    # a single ComponentModes is taken as one component
    one = resonance_check(design, speed_range=QUIET, components=GEAR1)
    assert [c["label"] for c in one["components"]] == ["gear 1"]


def test_comparison_figure_from_report_and_from_frequencies(design):
    # issue 32: the system modes, the body modes and the excitation bands on one
    # frequency axis; no system mode is paired with a body mode by its index
    g2 = ComponentModes("gear 2", (10987.0, 10988.0, 11184.0), ("torsional",) * 2 + ("",))
    report = resonance_check(design, speed_range=QUIET, components=[GEAR1, g2])
    fig = plot_component_comparison(report)
    (ax,) = fig.axes
    body = [ln for ln in ax.lines if ln.get_gid() == "body-mode"]
    got = sorted((ln.get_xdata()[0], ln.get_ydata()[0]) for ln in body)
    want = sorted([(f, 1) for f in GEAR1.frequencies] + [(f, 0) for f in g2.frequencies])
    assert got == want  # the given values, drawn as given
    system = [ln.get_xdata()[0] for ln in ax.lines if ln.get_gid() == "system-mode"]
    elastic = [f for f in report["system"]["frequencies_hz"] if f > 0]
    assert system == pytest.approx(elastic)
    assert all(ln.get_ydata()[0] == 2 for ln in ax.lines if ln.get_gid() == "system-mode")
    assert [t.get_text() for t in ax.get_yticklabels()][::-1][1:] == ["gear 1", "gear 2"]
    # each excitation's frequencies over the range: a band from order lo to order hi
    lo, hi = report["speed_range_rpm"]
    ds = report.campbell.data
    bands = {p.get_label().split(":")[0]: p for p in ax.patches if p.get_gid() == "excitation"}
    for name, q in zip(ds["excitation"].values, ds["order"].values, strict=True):
        key = f"{name} (order {q:.4g})"
        assert key in bands
        x0, x1 = bands[key].get_x(), bands[key].get_x() + bands[key].get_width()
        assert (x0, x1) == pytest.approx((q * lo / 60, q * hi / 60))
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert {"torsional", "folding", "umbrella", "(type not given)"} <= set(legend)
    # (system frequencies, components): a log axis, no excitation without orders
    fig = plot_component_comparison(report["system"]["frequencies_hz"], [GEAR1, g2], log=True)
    (ax,) = fig.axes
    assert ax.get_xscale() == "log" and not [p for p in ax.patches if p.get_gid()]
    fig = plot_component_comparison(([0.0, 6600, 7870], [GEAR1]), orders={"1x": 1.0},
                                    speed_range_rpm=(60.0, 60.0))  # fmt: skip
    (ax,) = fig.axes
    lines = [ln for ln in ax.lines if ln.get_gid() == "excitation"]
    assert len(lines) == 1 and lines[0].get_xdata()[0] == pytest.approx(1.0)
    assert len([ln for ln in ax.lines if ln.get_gid() == "system-mode"]) == 2
    fig.savefig(io.BytesIO(), format="png")
    with pytest.raises(ReducerlabError, match="no component modes"):
        plot_component_comparison(resonance_check(design, speed_range=QUIET))
    with pytest.raises(ReducerlabError, match="give the components"):
        plot_component_comparison([1.0, 2.0])


def test_campbell_figure_with_body_lines(design):
    res = campbell(design, np.linspace(0, 3000 / RPM, 61))
    plain = plot_campbell(res)
    n_plain = len(plain.axes[0].lines)
    body = ComponentModes("gear 9", (2000.0, 4162.7, 50000.0), ("torsional", "", "radial"))
    fig = plot_campbell(res, [body])
    (ax,) = fig.axes
    modes = [ln for ln in ax.lines if ln.get_gid() == "component-mode"]
    # the frequency axis ends 10 % above the highest excitation in the operating
    # range: 4162.7 Hz and 50 kHz lie above it, named in the title
    assert [ln.get_label() for ln in modes] == ["gear 9 body: 2000 Hz (torsional)"]
    assert "gear 9 body modes above" in ax.get_title()
    assert ax.get_title().endswith(": 4163, 50000 Hz")
    assert all(ln.get_linestyle() == "-." for ln in modes)  # apart from the system modes
    assert len(ax.lines) == n_plain + 2  # one body line and one set of crossing marks
    (marks,) = [ln for ln in ax.lines if ln.get_gid() == "component-crossing"]
    orders = res.data["order"].values
    expect = sorted((60 * f / q, f) for f in (2000.0,) for q in orders if 60 * f / q <= 3000)
    got = sorted(zip(marks.get_xdata(), marks.get_ydata(), strict=True))
    np.testing.assert_allclose(np.array(got), np.array(expect), rtol=1e-12)
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "gear-body modes, FE (gear 9): named at the line" in legend
    assert any(t.get_text().strip() == "gear 9 body: 2000 Hz (torsional)" for t in ax.texts)
    # a higher frequency axis shows the third mode; CampbellResult.plot passes components
    fig = plot_campbell(res, [body], fmax=60000.0)
    assert sum(ln.get_gid() == "component-mode" for ln in fig.axes[0].lines) == 3
    fig = res.plot(components=[body])
    assert sum(ln.get_gid() == "component-mode" for ln in fig.axes[0].lines) == 1
    with pytest.raises(ReducerlabError, match="fmax"):
        plot_campbell(res, [body], fmax=-1.0)
