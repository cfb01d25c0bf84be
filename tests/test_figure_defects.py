"""The figure defects the report screenshots showed (issue 32): each test fails on the
figure as it was drawn before its fix."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from matplotlib.backends.backend_agg import FigureCanvasAgg

from reducerlab.drives import load_design


def drawn(fig):
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    return fig


def inside(box, outer) -> bool:
    return (
        box.x0 >= outer.x0 - 1
        and box.x1 <= outer.x1 + 1
        and box.y0 >= outer.y0 - 1
        and (box.y1 <= outer.y1 + 1)
    )


def overlaps(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


# --- torsion test: the hysteresis loop (defect 5) ---------------------------------------


@pytest.fixture(scope="module")
def gear_pair():
    return load_design("examples/gear_pair.toml")


def test_frictionless_loop_says_there_is_no_hysteresis_and_lists_t1_t2(gear_pair):
    from reducerlab.analysis.torsion_test import torsion_test

    fig = drawn(torsion_test(gear_pair, mu=0.0).figure())
    ax = fig.axes[0]
    assert any("no hysteresis without friction (mu = 0)" in t.get_text() for t in ax.texts)
    assert "T1, T2 (knees of the secants)" in [t.get_text() for t in ax.get_legend().texts]
    assert not ax.child_axes  # no loop to zoom on


def test_a_loop_with_friction_shows_its_width_in_an_inset(gear_pair):
    from reducerlab.analysis.torsion_test import torsion_test

    res = torsion_test(gear_pair, mu=0.08)
    fig = drawn(res.figure())
    (inset,) = fig.axes[0].child_axes
    gaps = np.concatenate([line.get_ydata() for line in inset.get_lines()[:2]])
    # the inset's scale shows the gap between the branches (arcsec), which the loop's
    # own scale (arcmin, over the whole twist) draws as one line
    assert np.ptp(gaps) > 0.05 * np.ptp(inset.get_ylim())
    assert np.abs(gaps).max() > 0


# --- modification layout (defect 6) ------------------------------------------------------


def synthetic_layout():
    from reducerlab.analysis.layout import LayoutResult

    c, r = np.meshgrid([0.0, 4e-6, 8e-6], [0.0, 4e-6, 8e-6])
    c, r = c.ravel(), r.ravel()
    pp = 2e-6 - 0.1 * c - 0.1 * r
    ok = c > 1e-6
    ds = xr.Dataset(
        {
            "crowning": ("candidate", c),
            "relief": ("candidate", r),
            "peak_to_peak": ("candidate", pp),
            "feasible": ("candidate", ok),
        },
        attrs=dict(
            best_crowning=8e-6,
            best_relief=8e-6,
            best_peak_to_peak=pp.min(),
            design_torque=60.0,
            pressure_limit=1.5e9,
            edge_limit=0.01,
        ),
    )
    return LayoutResult(ds)


def test_layout_markers_inside_the_axes_and_the_legend_off_the_star():
    from reducerlab.plot.te import plot_layout

    fig = drawn(plot_layout(synthetic_layout()))
    ax = fig.axes[0]
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x0 < 0.0 and x1 > 8.0 and y0 < 0.0 and y1 > 8.0  # corner markers whole
    star = ax.transData.transform((8.0, 8.0))
    legend = ax.get_legend().get_window_extent()
    assert not (legend.x0 <= star[0] <= legend.x1 and legend.y0 <= star[1] <= legend.y1)
    assert legend.y1 <= ax.get_window_extent().y0  # below the map


# --- the datasheet's transmission error with no error given (defect 3) ------------------


def test_a_zero_transmission_error_draws_no_axes(gear_pair):
    from reducerlab.analysis.transmission_accuracy import transmission_accuracy
    from reducerlab.plot.transmission_accuracy import NO_ERROR

    res = transmission_accuracy(gear_pair)
    assert not np.any(res.data["error"].values)
    fig = drawn(res.figure())
    assert fig.axes == []
    assert [t.get_text().replace("\n", " ") for t in fig.texts] == [NO_ERROR]


# --- KHV closed graph (defect 7) ---------------------------------------------------------


def test_closed_graph_draws_no_limit_along_the_unbuildable_region_and_says_so():
    from reducerlab.plot.khv import plot_closed_graph

    d = load_design("examples/khv.toml")
    pair = d.gears.pair()
    fig = drawn(plot_closed_graph(pair, d.gears.shift_line, n=61))
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().texts]
    # limits 2 and 4 have positive margins wherever a pair exists: listed, not drawn
    assert any(t.startswith("2: involute interference: not reached here") for t in labels)
    assert any(t.startswith("4: pointed planet teeth: not reached here") for t in labels)
    assert "no pair: no positive working pressure angle" in labels
    drawn_colours = {
        tuple(np.round(c.get_edgecolor()[0][:3], 3))
        for c in ax.collections
        if hasattr(c, "get_edgecolor")
        and len(c.get_edgecolor())
        and c.get_linewidth().size
        and c.get_facecolor().size == 0
    }
    from matplotlib.colors import to_rgb

    assert tuple(np.round(to_rgb("C3"), 3)) not in drawn_colours  # no red stair line
    # the design point is on limit 3 (paper 004's line M-N): stated with its margin
    assert any("on limit 3 (margin 0.0029)" in t for t in labels)
    # the legend sits below the axes, off the graph
    assert ax.get_legend().get_window_extent().y1 <= ax.get_window_extent().y0


# --- regime map and bifurcation (defects 11, 12) -----------------------------------------


def test_parameter_labels_are_words_not_paths():
    from reducerlab.plot.axes import parameter_label

    assert parameter_label("gears.x1") == "profile shift coefficient x1"
    assert parameter_label("input_speed") == "input speed"
    assert parameter_label("mesh.half_backlash") == "mesh half backlash"
    assert parameter_label("support:gear.x.stiffness") == "support gear x stiffness"


class _Map:
    """A regime map as the figures read it."""

    def __init__(self, labels):
        self._labels = np.asarray(labels)
        nb, ny, nx = self._labels.shape
        self.data = xr.Dataset(
            coords={
                "branch": ["up"] * nb,
                "p0": ("p0", np.linspace(0.5, 0.8, nx), {}),
                "p1": (
                    "p1",
                    np.linspace(1100, 1300, ny) * np.pi / 30,
                    {"display_unit": "rpm", "display_factor": 30 / np.pi},
                ),
            },
            attrs={
                "x": "gears.x1",
                "y": "input_speed",
                "title": "KHV drive",
                "design": json.dumps({"name": "KHV drive"}),
            },
        )

    def labels(self):
        return self._labels

    def impacts(self):
        return np.full(self._labels.shape, "no impact")

    def coexisting(self):
        return np.zeros(self._labels.shape[1:], bool)


def test_plotly_regime_map_has_a_discrete_colour_bar_and_named_axes():
    from reducerlab.plot.bifurcation import plotly_regime_map

    m = _Map([[["period-1", "period-1", "chaotic"], ["period-2", "unsettled", "chaotic"]]])
    fig = plotly_regime_map(m)
    (hm,) = fig.data
    classes = list(hm.colorbar.ticktext)
    assert sorted(classes) == sorted(["period-1", "period-2", "chaotic", "unsettled"])
    scale = [tuple(s) for s in hm.colorscale]
    # one colour a class: each colour holds over one class's band, steps between
    n = len(classes)
    assert len(scale) == 2 * n
    for k in range(n):
        (a, ca), (b, cb) = scale[2 * k], scale[2 * k + 1]
        assert ca == cb and a == pytest.approx(k / n) and b == pytest.approx((k + 1) / n)
    assert len({c for _, c in scale}) == n
    assert fig.layout.xaxis.title.text == "profile shift coefficient x1"
    assert fig.layout.yaxis.title.text == "input speed (rpm)"
    assert "KHV drive" in fig.layout.title.text and "regime map" in fig.layout.title.text


def test_matplotlib_regime_map_axes_are_named():
    m = _Map([[["period-1", "chaotic"], ["period-2", "chaotic"]]])
    from reducerlab.plot.bifurcation import plot_regime_map

    fig = drawn(plot_regime_map(m))
    assert fig.axes[-1].get_xlabel() == "profile shift coefficient x1"
    assert fig.axes[0].get_ylabel() == "input speed (rpm)"


class _Bif:
    def __init__(self):
        x = np.linspace(0.4, 0.8, 5)
        self.data = xr.Dataset(
            {
                "poincare": (
                    ("p0", "point"),
                    np.random.default_rng(0).normal(size=(5, 4)),
                    {"units": "um"},
                )
            },
            coords={"p0": x, "point": np.arange(4)},
            attrs={"parameter": "gears.x1", "title": "KHV drive (paper 004)"},
        )


def test_bifurcation_diagrams_have_a_title_and_a_named_axis():
    from reducerlab.plot.bifurcation import plot_bifurcation, plotly_bifurcation

    fig = plotly_bifurcation(_Bif())
    title = fig.layout.title.text
    assert "KHV drive (paper 004)" in title and "bifurcation diagram" in title
    assert "profile shift coefficient x1" in title
    assert fig.layout.xaxis.title.text == "profile shift coefficient x1"
    mfig = drawn(plot_bifurcation(_Bif()))
    assert mfig.axes[0].get_title().startswith("KHV drive (paper 004)\nbifurcation diagram")
    assert mfig.axes[-1].get_xlabel() == "profile shift coefficient x1"


# --- contact overview panel (d) (defect 9) -----------------------------------------------


def test_contact_panel_d_legend_handles_match_the_drawn_lines():
    from reducerlab.analysis.contact import contact_analysis
    from reducerlab.plot.contact import plot_contact

    res = contact_analysis(
        load_design("examples/nutation_surface.toml"), 1, torque=19.1, positions=3, order=1,
        rigid=True,
    )  # fmt: skip
    fig = drawn(plot_contact(res))
    (ax,) = [a for a in fig.axes if a.get_title().startswith("(d)")]
    legend = ax.get_legend()
    drawn_lines = {
        line.get_label(): line
        for a in [ax, *[t for t in fig.axes if t.bbox.bounds == ax.bbox.bounds and t is not ax]]
        for line in a.get_lines()
    }
    for handle, text in zip(legend.legend_handles, legend.texts, strict=True):
        line = drawn_lines[text.get_text()]
        assert handle.get_linestyle() == line.get_linestyle(), text.get_text()
        assert handle.get_marker() == line.get_marker(), text.get_text()
    pairs = drawn_lines["tooth pairs in contact"]
    # a dashed line whose legend handle shows its dashes: no marker over them
    assert pairs.get_linestyle() == "--" and pairs.get_marker() in ("None", "", None)


# --- the tooth sector render (defect 8) --------------------------------------------------


def test_tooth_sector_oblique_tight_and_readable():
    from matplotlib.text import Text

    from reducerlab.geometry.solid import build_gear_solid
    from reducerlab.plot.surface import ELEVATION, plot_tooth

    d = load_design("examples/nutation_double_sided.toml")
    crown, bevel = d.tooth_generation(1)  # the internal gear: seen from above before
    solid = build_gear_solid(crown, bevel, n_profile=9, n_face=9, n_land=3, n_space=5,
                             rim=d.surface.rim)  # fmt: skip
    fig = drawn(plot_tooth(solid))
    ax = fig.axes[0]
    assert ELEVATION[0] <= abs(ax.elev) <= ELEVATION[1]
    pts = solid.tooth_mesh().vertices * 1e3
    spans = np.ptp(pts, axis=0)
    limits = np.array([ax.get_xlim(), ax.get_ylim(), ax.get_zlim()])
    assert np.all(np.ptp(limits, axis=1) <= 1.2 * np.maximum(spans, 0.08 * spans.max()))
    r = fig.canvas.get_renderer()
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        boxes = [Text.get_window_extent(t, r) for t in axis.get_ticklabels() if t.get_text()]
        for i, a in enumerate(boxes):
            for b in boxes[i + 1 :]:
                assert not overlaps(a, b)


# --- safety factors (defect 4) -----------------------------------------------------------


class _Rating:
    """Safety factors as the figure reads them: the nutation pairs' S_H (0.92, 0.94)
    end just short of S_Hmin = 1."""

    data = xr.Dataset(attrs={"conditions": json.dumps({"S_Hmin": 1.0, "S_Fmin": 1.4})})

    def pairs(self):
        return {
            "pair 1": {"gears": ["gear 2", "gear 1"], "S_H": [0.94, 0.94], "S_F": [4.46, 4.88]},
            "pair 2": {"gears": ["gear 4", "gear 3"], "S_H": [0.92, 0.92], "S_F": [4.7, 1.45]},
        }


def test_safety_factor_labels_are_not_struck_through_by_the_minimum():
    from matplotlib.text import Text

    from reducerlab.plot.rating import plot_rating

    fig = drawn(plot_rating(_Rating()))
    r = fig.canvas.get_renderer()
    for ax in fig.axes:
        (floor,) = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
        x = ax.transData.transform((floor.get_xdata()[0], 0))[0]
        for t in ax.texts:
            box = Text.get_window_extent(t, r)
            assert not box.x0 < x < box.x1, t.get_text()
            assert box.x1 <= ax.get_window_extent(r).x1 + 1
        assert ax.get_legend() is None
