"""Campbell diagrams that follow each mode and show what they draw (issue 32): modes
tracked across speed by shape, crossings named by the tracked mode, whirl decided per
branch, damping by colour, distinct mode and excitation styles, the operating speed at
any width, a frequency axis that reaches the excitation lines, each crossing once."""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.analysis.campbell import campbell
from reducerlab.analysis.complex_modal import complex_campbell, steady_whirl
from reducerlab.analysis.components import ComponentModes
from reducerlab.analysis.resonance import resonance_check
from reducerlab.drives import load_design
from reducerlab.examples import example_dir
from reducerlab.model import Centripetal, Coupling, Dof, Inertia, Model, Support
from reducerlab.plot.campbell import plot_campbell, plot_complex_campbell, plotly_campbell
from reducerlab.plot.campbell_style import (
    coincident_dash,
    excitation_styles,
    frequency_axis,
    mode_colours,
    unique_crossings,
)
from reducerlab.plot.components import BODY_COLOUR, plot_component_comparison
from reducerlab.reporting.sections.modes import crossing_rows

DISC = example_dir() / "spinning_disc.toml"
KHV_RATTLE = example_dir() / "khv_rattle.toml"
TWO_PI = 2 * math.pi


def crossing_pair() -> Model:
    """Two uncoupled oscillators: ``a`` at 10 rad/s whatever the speed, ``b`` softened
    by its frame's rotation, ``sqrt(400 - Omega^2)`` rad/s: they cross at Omega^2 = 300."""
    els = [Inertia("a.x", 1.0), Support("a.x", 100.0), Inertia("b.x", 1.0),
           Support("b.x", 400.0), Centripetal("b.x", 1.0)]  # fmt: skip
    return Model([Dof("a", "x"), Dof("b", "x")], els, speed=5.0)


@pytest.fixture(scope="module")
def disc():
    return complex_campbell(load_design(DISC))


def test_modes_are_tracked_through_a_crossing_and_crossings_name_them():
    w = np.linspace(0.0, 19.5, 40)
    res = campbell(crossing_pair(), w, orders={"half": 0.5})
    f = res.data["frequency"].values
    # numbered at the operating speed (5 rad/s): mode 1 is a, mode 2 is b, everywhere
    np.testing.assert_allclose(f[:, 0], 10 / TWO_PI, rtol=1e-9)
    np.testing.assert_allclose(f[:, 1], np.sqrt(400 - w**2) / TWO_PI, rtol=1e-9)
    sorted_mode = res.data["sorted_mode"].values
    assert sorted_mode[0].tolist() == [1, 2] and sorted_mode[-1].tolist() == [2, 1]
    # the half-order line meets b beyond the mode crossing (Omega^2 = 400 / 1.25):
    # tracked mode 2, the lower of the two there
    (c,) = res.crossings()
    assert c["speed_rad_s"] == pytest.approx(math.sqrt(320.0), rel=1e-9)
    assert (c["mode"], c["sorted_mode"]) == (2, 1)


def test_complex_modes_are_tracked_and_their_whirl_does_not_flicker(disc):
    ds = disc.data
    whirl = ds["whirl"].values
    # every branch keeps one whirl: the backward tilt passes the planar translation
    # pair (about 65 Hz) near 8000 rpm and stays backward, its frequency falling
    for j in range(whirl.shape[1]):
        assert len(set(whirl[:, j])) == 1
    back = int(np.nonzero(whirl[0] == "backward")[0][0])
    assert np.all(np.diff(ds["frequency"].values[:, back]) < 0)
    assert ds["sorted_mode"].values[-1, back] == 1 and ds["sorted_mode"].values[0, back] > 2
    # damping over speed, as the log decrement of the damping ratio
    z = ds["damping_ratio"].values
    np.testing.assert_allclose(ds["log_decrement"].values, TWO_PI * z / np.sqrt(1 - z**2))


def test_steady_whirl_keeps_real_changes_only():
    flicker = ["forward"] * 20 + ["planar"] + ["forward"] * 20
    assert set(steady_whirl(flicker)) == {"forward"}
    at_rest = ["ccw"] + ["backward"] * 10
    assert set(steady_whirl(at_rest)) == {"backward"}
    change = ["forward"] * 20 + ["backward"] * 20
    assert steady_whirl(change).tolist() == change
    noisy = ["planar", "forward"] * 30  # a repeated eigenvalue: no whirl of its own
    assert len(set(steady_whirl(noisy))) == 1


def test_colours_are_distinct_for_any_number_of_modes_and_excitations():
    for n in (3, 10, 11, 25, 60):
        assert len(set(mode_colours(n))) == n
    styles = excitation_styles(20)
    assert len({(c, str(d)) for c, d, _ in styles}) == 20
    assert len({c for c, _, _ in styles[:8]}) == 8
    # a chain of 14 inertias: 13 elastic modes, each line its own colour
    n = 14
    dofs = [Dof(f"b{i}", "x") for i in range(n)]
    els = [Inertia(f"b{i}.x", 1.0 + 0.1 * i) for i in range(n)]
    els += [Coupling({f"b{i}.x": 1.0, f"b{i + 1}.x": -1.0}, 1e4 * (1 + i)) for i in range(n - 1)]
    res = campbell(Model(dofs, els, speed=10.0), np.linspace(0, 20, 5), orders={"1x": 1.0})
    ax = plot_campbell(res).axes[0]
    lines = [ln for ln in ax.lines if ln.get_gid() == "mode"]
    assert len(lines) == n - 1 and len({ln.get_color() for ln in lines}) == n - 1


def test_excitation_lines_are_drawn_and_named_apart():
    d = load_design(example_dir() / "gear_pair.toml")
    res = campbell(d, np.linspace(0, 3000 / 60 * TWO_PI, 31))
    ax = plot_campbell(res).axes[0]
    exc = [ln for ln in ax.lines if ln.get_gid() == "excitation"]
    assert len(exc) == res.data.sizes["excitation"] == 4
    assert len({(ln.get_color(), ln.get_linestyle()) for ln in exc}) == 4
    assert [ln.get_label() for ln in exc] == [
        "1x input (order 1)", "1x mesh (order 25)", "2x mesh (order 50)", "3x mesh (order 75)"
    ]  # fmt: skip
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "1x mesh (order 25)" in legend and "mode 2" in legend
    fig = plotly_campbell(res)
    names = {t.name: t for t in fig.data}
    dashes = {(names[k].line.color, names[k].line.dash) for k in legend if k.endswith(")")
              and "order" in k}  # fmt: skip
    assert len(dashes) == 4


def test_one_operating_speed_is_drawn_and_the_mesh_line_is_on_the_chart():
    # examples/khv_rattle.toml runs at 1230 rpm only: its 1x mesh line (order 33,
    # 676.5 Hz there) lies above every natural frequency and must be on the chart
    res = campbell(load_design(KHV_RATTLE))
    ds = res.data
    axis = frequency_axis(ds)
    mesh = 33 * 1230 / 60
    assert axis.top > mesh
    clipped = dict(axis.clipped)
    assert set(clipped) == {"2x mesh", "3x mesh"}
    assert clipped["2x mesh"] == pytest.approx(2 * mesh, rel=1e-9)
    ax = plot_campbell(res).axes[0]
    assert ax.get_ylim()[1] == pytest.approx(axis.top)
    (op,) = [ln for ln in ax.lines if ln.get_gid() == "operating-speed"]
    assert op.get_xdata()[0] == pytest.approx(1230) and "1230 rpm" in op.get_label()
    assert "2x mesh" in ax.get_title() and "off the chart" in ax.get_title()
    fig = plotly_campbell(res)
    assert fig.layout.yaxis.range[1] > mesh
    (vline,) = [s for s in fig.layout.shapes if s.type == "line"]
    assert vline.x0 == pytest.approx(1230)
    texts = [a.text for a in fig.layout.annotations]
    assert any("operating speed 1230 rpm" in t for t in texts)
    title = fig.layout.title.text  # what the axis leaves off: above the diagram
    assert "off the chart" in title and "3x mesh" in title


def test_each_crossing_is_marked_and_listed_once(disc):
    # the translation pair is a repeated frequency: both its modes cross 1x input at
    # one point, marked once and listed in one row naming both modes
    cr = disc.crossings()
    groups = unique_crossings(cr)
    assert len(groups) == len(cr) - 1 and sorted(len(g) for g in groups)[-1] == 2
    ax = plot_complex_campbell(disc).axes[0]
    pts = [(x, y) for ln in ax.lines if ln.get_gid() == "crossing"
           for x, y in zip(ln.get_xdata(), ln.get_ydata(), strict=True)]  # fmt: skip
    assert len(pts) == len(groups) == len(set(pts))
    check = resonance_check(load_design(DISC))
    rows = crossing_rows(check, gyro=True)
    merged = [r for r in rows if r[0] == "1, 2"]
    assert len(merged) == 1 and merged[0][2] == "crossing in range" and merged[0][5] == 0
    assert merged[0][1] == "1x input (order 1)"
    fig = plotly_campbell(check.campbell, check)
    marks = [t for t in fig.data if t.name and t.name.startswith("crossings")]
    xs = [x for t in marks for x in t.x]
    assert len(xs) == len(groups) == len(set(xs))


def test_crossing_rows_give_the_margin_to_the_operating_range():
    d = load_design(example_dir() / "gear_pair.toml")
    check = resonance_check(d)
    lo, hi = check["speed_range_rpm"]
    rows = crossing_rows(check, gyro=False)
    outside = [r for r in rows if r[2] == "crossing outside range"]
    assert outside
    for r in outside:
        edge = lo if r[3] < lo else hi
        assert r[5] == pytest.approx(100 * (r[3] - edge) / edge)
    inside = [r for r in rows if r[2] == "crossing in range"]
    assert len(inside) == len(unique_crossings(check["crossings"]))
    assert all(r[7] in ("yes", "no") for r in inside)


def test_complex_figure_shows_whirl_and_damping(disc):
    fig = plot_complex_campbell(disc)
    ax, bar = fig.axes
    assert bar.get_xlabel() == "logarithmic decrement (damping)"
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    for key in ("forward whirl", "backward whirl", "planar"):
        assert any(t.startswith(key) for t in legend)
    gids = {c.get_gid() for c in ax.collections}
    assert {"whirl-forward", "whirl-backward", "whirl-planar", "mode"} <= gids
    # the colours are the log decrements: the tilt branches are more damped here
    sc = [c for c in ax.collections if c.get_gid() == "whirl-forward"]
    dec = disc.data["log_decrement"].values
    assert np.all(np.isin(np.round(sc[0].get_array(), 12), np.round(dec, 12)))
    # the numbers at the branch ends do not overlap
    # (the translation pair ends at one frequency: one label for both)
    # the axis ends 10 % above the 1x line at the top of the range (100 Hz): the
    # forward branch (mode 4, 138-322 Hz) is named above it, 1x input leaves at the top
    ends = [t for t in ax.texts if t.get_gid() == "end-label"]
    assert sorted(t.get_text().strip() for t in ends) == ["1, 2", "3"]
    assert [t.get_text().strip() for t in ax.texts if t.get_gid() == "excitation-label"] == [
        "1x input"
    ]
    assert "mode 4 above 110 Hz: 140-320 Hz" in ax.get_title()
    ys = sorted(t.get_position()[1] for t in ends)
    top = ax.get_ylim()[1]
    assert top == pytest.approx(110.0)
    assert np.all(np.diff(ys) >= 0.04 * top * (1 - 1e-9))
    p = plotly_campbell(disc)
    assert p.layout.coloraxis.colorbar.title.text == "log dec"
    symbols = {s for t in p.data if t.marker and isinstance(t.marker.symbol, tuple)
               for s in t.marker.symbol}  # fmt: skip
    assert {"triangle-up", "triangle-down", "circle"} <= symbols
    names = [t.name for t in p.data]
    assert any(n.startswith("backward whirl") for n in names)


def test_plotly_data_stay_compact(disc):
    fig = plotly_campbell(disc)
    ys = [y for t in fig.data if t.y is not None for y in t.y if y is not None]
    assert ys and all(len(f"{y:.12g}".replace(".", "").lstrip("0-")) <= 5 for y in ys)


NUT2 = example_dir() / "nutation_double_sided.toml"
SURFACE = example_dir() / "nutation_surface.toml"
GEAR2 = ComponentModes("gear 2", (1900.0, 1900.0, 2900.0, 8860.0),
                       ("bending", "bending", "umbrella", "torsional"))  # fmt: skip


@pytest.fixture(scope="module")
def nut2():
    return campbell(load_design(NUT2))


def _shown_in_legend(fig) -> list[str]:
    return [t.name for t in fig.data if t.name and t.showlegend is not False]


def test_plotly_legend_is_compact_and_below_with_modes_named_at_their_ends(nut2):
    # 12 modes and 7 excitations: one legend entry for all modes, the legend in rows
    # below the diagram (it keeps the page's width), mode numbers and excitation names
    # at the lines' right ends
    fig = plotly_campbell(nut2)
    legend = fig.layout.legend
    assert legend.orientation == "h" and legend.y < 0
    names = _shown_in_legend(fig)
    assert sum(n.startswith("natural frequencies") for n in names) == 1
    assert not any(n.startswith("mode ") for n in names)
    assert len(names) <= nut2.data.sizes["excitation"] + 4
    ends = [a.text.strip() for a in fig.layout.annotations if a.name == "end-label"]
    assert {"mode 2", "modes 3, 4", "1x mesh 1", "1x input"} <= set(ends)
    assert fig.layout.margin.r >= 100  # room for the end labels
    ys = sorted(a.y for a in fig.layout.annotations if a.name == "end-label")
    assert np.all(np.diff(ys) >= 0.04 * fig.layout.yaxis.range[1] * (1 - 1e-3))


def test_coincident_modes_are_drawn_so_that_both_show(nut2):
    # modes 3 and 4 of the double-sided drive differ by 0.008 %: mode 4 is dashed over
    # mode 3 (matplotlib and plotly), the two share one end label
    f = nut2.data["frequency"].values
    assert coincident_dash(f)[2:4] == [0, 1]
    ax = plot_campbell(nut2).axes[0]
    lines = {ln.get_label(): ln for ln in ax.lines if ln.get_gid() == "mode"}
    assert lines["mode 3"].get_linestyle() == "-" and lines["mode 4"].get_linestyle() == "--"
    assert lines["mode 3"].get_color() != lines["mode 4"].get_color()
    ends = [t.get_text().strip() for t in ax.texts if t.get_gid() == "end-label"]
    assert "3, 4" in ends and "3" not in ends and "4" not in ends
    fig = plotly_campbell(nut2)
    dash = {t.hovertemplate.split("<extra>")[1][:-8]: t.line.dash for t in fig.data
            if t.legendgroup == "modes" and t.mode == "lines"}  # fmt: skip
    assert dash["mode 3"] == "solid" and dash["mode 4"] == "dash"


def test_frequency_axis_ends_where_excitations_can_meet_modes(nut2):
    # nutation_surface at 1500 rpm: the excitations stay under 2 kHz, the lowest
    # elastic mode is at 5.08 kHz, the others up to 16 kHz: the axis ends 10 % above
    # mode 2 and names modes 3-8
    res = campbell(load_design(SURFACE))
    axis = frequency_axis(res.data)
    f = res.data["frequency"].values
    assert axis.top == pytest.approx(1.1 * f[0, 1])
    assert [m for m, _, _ in axis.above] == [3, 4, 5, 6, 7, 8]
    note = axis.note(1500.0)
    assert note == "modes 3-8 above 5.6 kHz: 8.2-16 kHz"
    ax = plot_campbell(res).axes[0]
    assert ax.get_ylim()[1] == pytest.approx(axis.top) and note in ax.get_title()
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "mode 2" in legend and "mode 3" not in legend
    fig = plotly_campbell(res)
    assert fig.layout.yaxis.range[1] == pytest.approx(axis.top, rel=1e-3)
    assert note in fig.layout.title.text
    # double-sided, 1000-2000 rpm: 10 % above 3x mesh 2 (order 89.14) at 2000 rpm
    axis = frequency_axis(nut2.data)
    assert axis.top == pytest.approx(1.1 * 2000 / 60 * 624 / 7)
    assert axis.note(2000.0).startswith("modes 5-12 above 3.3 kHz: 3.5-9.6 kHz")


def test_body_modes_are_drawn_apart_from_the_system_modes(nut2):
    # grey dash-dot, named at the line "gear 2 body: f Hz (type)", one legend entry;
    # a repeated body mode labelled once, those above the axis named in the title
    ax = plot_campbell(nut2, [GEAR2]).axes[0]
    body = [ln for ln in ax.lines if ln.get_gid() == "component-mode"]
    modes = {ln.get_color() for ln in ax.lines if ln.get_gid() == "mode"}
    assert len(body) == 3 and all(ln.get_color() == BODY_COLOUR for ln in body)
    assert all(ln.get_linestyle() == "-." for ln in body) and BODY_COLOUR not in modes
    labels = sorted(t.get_text().strip() for t in ax.texts if t.get_gid() == "component-label")
    assert labels == ["gear 2 body: 1900 Hz (bending) x 2", "gear 2 body: 2900 Hz (umbrella)"]
    legend = [t.get_text() for t in ax.get_legend().get_texts()]
    assert sum("gear-body modes" in t for t in legend) == 1
    assert "gear 2 body modes above 3.3 kHz: 8860 Hz" in ax.get_title()
    check = {"components": [{"label": "gear 2", "frequencies": list(GEAR2.frequencies),
                             "types": list(GEAR2.types)}]}  # fmt: skip
    fig = plotly_campbell(nut2, check)
    hlines = [s for s in fig.layout.shapes if s.type == "line" and s.line.dash == "dashdot"]
    assert len(hlines) == 3 and {s.line.color for s in hlines} == {BODY_COLOUR}
    assert sum("gear-body modes" in n for n in _shown_in_legend(fig)) == 1
    texts = [a.text for a in fig.layout.annotations]
    assert "gear 2 body: 2900 Hz (umbrella)" in texts
    assert "gear 2 body modes above 3.3 kHz: 8860 Hz" in fig.layout.title.text


def test_component_figure_groups_close_mode_numbers_in_readable_text():
    # system modes 3/4, 7/8, 9/10 repeated: one label each ("9, 10", never "910"),
    # labels that would touch staggered, every text at least 8 pt
    system = [0.0, 2239.0, 2565.8, 2566.0, 3450.9, 4068.2, 4696.7, 4696.7, 5611.1, 5611.1,
              7779.2, 9594.3]  # fmt: skip
    fig = plot_component_comparison(system, [GEAR2], orders={"1x mesh": 26.0},
                                    speed_range_rpm=(1000.0, 2000.0))  # fmt: skip
    ax = fig.axes[0]
    labels = [t for t in ax.texts if t.get_gid() == "system-label"]
    assert [t.get_text() for t in labels] == ["2", "3, 4", "5", "6", "7, 8", "9, 10", "11", "12"]
    fig.canvas.draw()
    boxes = [t.get_window_extent() for t in labels]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])
    texts = ax.texts + ax.get_legend().get_texts() + ax.get_yticklabels()
    assert min(t.get_fontsize() for t in texts) >= 8
