"""The response figures read right (issue 32): no axis offsets, a Poincaré map whose
coinciding points (a period-n orbit spread by round-off) are drawn as the n points on the
orbit's scale while a quasi-periodic ring stays a ring, the phase plot's limits set by
the orbit and not by the backlash band, a Hann-windowed spectrum with its resolution
1 / record length stated, and parameter axes labelled with their unit."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import xarray as xr
from matplotlib.backends.backend_agg import FigureCanvasAgg

from reducerlab.analysis.motion import coinciding_period, windowed_spectrum
from reducerlab.analysis.parameters import parameter_kind, parse_values
from reducerlab.analysis.response import ResponseResult
from reducerlab.drives import build_model, load_design
from reducerlab.plot.axes import fit_limits, parameter_axis, scaled_unit
from reducerlab.plot.response import plot_response, plot_transmission_error

F = 625.0  # forcing frequency (Hz)
STEPS, HISTORY = 200, 20


def synthetic(
    mean: float = 44.5e-6,
    amp: float = 0.6e-6,
    backlash: float = 40e-6,
    poincare: str = "period-1",
    spread: float = 1e-20,
    rng: int = 0,
) -> ResponseResult:
    """A steady response as ``response()`` returns it: a mesh deflection of two
    harmonics about ``mean`` (m), its Poincaré points (``"period-1"``: the orbit's point
    at the period, spread by ``spread`` (m; 1e-20: round-off); ``"period-2"``: two points;
    ``"ring"``: a closed curve of 0.3 x the orbit, quasi-periodic)."""
    w = 2 * math.pi * F
    t = np.arange(1, STEPS * HISTORY + 1) / (STEPS * F)
    delta = mean + amp * np.sin(w * t) + 0.2 * amp * np.sin(2 * w * t + 0.3)
    vel = amp * w * np.cos(w * t) + 0.4 * amp * w * np.cos(2 * w * t + 0.3)
    noise = np.random.default_rng(rng).standard_normal((2, 100))
    k = np.arange(100)
    if poincare == "period-1":
        pd = mean + 0.2 * amp * math.sin(0.3) + spread * noise[0]
        pv = amp * w * (1 + 0.4 * math.cos(0.3)) + 1e-15 * noise[1]
    elif poincare == "period-2":
        pd = mean + 0.5 * amp * (-1.0) ** k + 1e-20 * noise[0]
        pv = 0.5 * amp * w * (-1.0) ** k + 1e-15 * noise[1]
    else:
        phase = 2 * math.pi * (math.sqrt(5) - 1) / 2 * k
        pd = mean + 0.3 * amp * np.cos(phase)
        pv = 0.3 * amp * w * np.sin(phase)
    data = xr.Dataset(
        {
            "delta": ("time", delta, {"units": "m"}),
            "dte": ("time", delta, {"units": "m"}),
            "delta_velocity": ("time", vel, {"units": "m/s"}),
            "poincare_delta": ("point", pd, {"units": "m"}),
            "poincare_velocity": ("point", pv, {"units": "m/s"}),
        },
        coords={"time": ("time", t, {"units": "s"}), "point": k},
        attrs={
            "title": "synthetic",
            "forcing_hz": F,
            "dynamic_load_factor": 1.01,
            "half_backlash_m": backlash,
            "separation_fraction": float(np.mean(np.abs(delta) < backlash)),
            "impact_class": "no impact",
        },
    )
    return ResponseResult(data)


def drawn(fig):
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    return fig


CASES = {
    "period-1 far from the backlash": dict(poincare="period-1"),
    "period-2": dict(poincare="period-2"),
    "quasi-periodic ring": dict(poincare="ring"),
    "rattle across the backlash": dict(mean=-5e-6, amp=8e-6, backlash=2e-6, poincare="ring"),
    "not excited (round-off)": dict(amp=0.0),
}


@pytest.mark.parametrize("case", list(CASES))
def test_no_axis_carries_an_offset_or_a_multiplier(case):
    res = synthetic(**CASES[case])
    for fig in (drawn(plot_response(res)), drawn(plot_transmission_error(res))):
        for ax in fig.axes:
            for axis in (ax.xaxis, ax.yaxis):
                assert axis.get_offset_text().get_text() == "", (case, ax.get_title())
                assert axis.get_major_formatter().get_offset() == ""
                # the tick labels in view tell the ticks apart (no '43.8' repeated)
                lo, hi = sorted(axis.get_view_interval())
                labels = [
                    t.get_text()
                    for t, v in zip(axis.get_ticklabels(), axis.get_ticklocs(), strict=True)
                    if lo <= v <= hi and t.get_text()
                ]
                assert len(labels) == len(set(labels)) and len(labels) <= 9, labels


def shown_factor(label: str) -> float:
    """The factor from m (or m/s) to the unit an axis label names."""
    unit = re.search(r"\((\S+?)(?:/s)?\)", label).group(1)
    return {"m": 1.0, "mm": 1e3, "µm": 1e6, "nm": 1e9}[unit]


def test_coinciding_poincare_points_are_drawn_on_the_orbit_scale():
    res = synthetic(poincare="period-1")
    ds = res.data
    fig = drawn(plot_response(res))
    ax = fig.axes[1]
    fx, fy = shown_factor(ax.get_xlabel()), shown_factor(ax.get_ylabel())
    # the range shows the orbit's size, not the 1e-20 m spread of the round-off
    assert np.ptp(ax.get_xlim()) >= np.ptp(ds["delta"].values) * fx
    assert np.ptp(ax.get_ylim()) >= np.ptp(ds["delta_velocity"].values) * fy
    markers = [line for line in ax.get_lines() if line.get_marker() == "o"]
    assert len(markers) == 1 and len(markers[0].get_xdata()) == 1
    note = ax.get_title()  # the note in the title, off the points
    assert "period 1" in note and "round-off" in note
    # a spread above round-off but within the integrator's accuracy says so
    fuzzy = drawn(plot_response(synthetic(spread=1e-13))).axes[1]
    assert "(integration accuracy)" in fuzzy.get_title()
    two = drawn(plot_response(synthetic(poincare="period-2"))).axes[1]
    (marks,) = [line for line in two.get_lines() if line.get_marker() == "o"]
    assert len(marks.get_xdata()) == 2


def test_a_quasi_periodic_ring_is_drawn_as_its_points_on_its_own_extent():
    res = synthetic(poincare="ring")
    ax = drawn(plot_response(res)).axes[1]
    fx = shown_factor(ax.get_xlabel())
    (dots,) = ax.get_lines()
    assert len(dots.get_xdata()) == 100
    ring = np.ptp(res.data["poincare_delta"].values) * fx
    assert ring <= np.ptp(ax.get_xlim()) <= 1.5 * ring  # the ring fills the panel
    assert not any("period" in t.get_text() for t in ax.texts) and "coincide" not in ax.get_title()


def test_coinciding_period():
    k = np.arange(60)
    sizes = np.array([1.0, 1.0])
    three = np.column_stack([np.sin(2 * np.pi * k / 3), np.cos(2 * np.pi * k / 3)])
    assert coinciding_period(three + 1e-9, sizes) == 3
    assert coinciding_period(three + 1e-3 * k[:, None] / 60, sizes) == 0  # drifts
    assert coinciding_period(np.column_stack([np.cos(0.7 * k), np.sin(0.7 * k)]), sizes) == 0


def test_the_backlash_band_does_not_set_the_phase_limits():
    res = synthetic(poincare="period-1")  # orbit at 43.7-45.3 um, backlash edge at 40 um
    ax = drawn(plot_response(res)).axes[0]
    assert ax.get_xlabel() == "mesh deflection (µm)"
    d = res.data["delta"].values * 1e6
    lo, hi = ax.get_xlim()
    assert lo > 40.0 and lo < d.min() and hi > d.max()
    assert hi - lo <= 1.3 * np.ptp(d)  # the orbit fills the panel
    assert not ax.patches  # no band drawn outside the view
    assert any("backlash edge at 40" in t.get_text() for t in ax.texts)
    # a rattling orbit crosses the gap: both edges in view, drawn, limits still the orbit's
    rattle = synthetic(mean=-5e-6, amp=8e-6, backlash=2e-6, poincare="ring")
    ax = drawn(plot_response(rattle)).axes[0]
    d = rattle.data["delta"].values * 1e6
    edges = sorted(line.get_xdata()[0] for line in ax.get_lines() if line.get_linestyle() == "--")
    assert edges == pytest.approx([-2.0, 2.0])
    assert ax.patches and not ax.texts
    assert ax.get_xlim() == pytest.approx(fit_limits(d))


def test_spectrum_states_its_window_and_resolution():
    res = synthetic(poincare="period-1")
    sp = res.spectrum()
    n = res.data.sizes["time"]
    dt = res.uniform_deflection()[1]
    assert sp.resolution == pytest.approx(1 / (n * dt), rel=1e-9)
    assert sp.resolution == pytest.approx(F / HISTORY, rel=1e-3)  # 20 periods recorded
    assert sp.window == "Hann" and sp.frequency[1] == pytest.approx(sp.resolution / sp.pad)
    ax = drawn(plot_response(res)).axes[2]
    title = ax.get_title()
    assert "Hann window" in title
    stated = float(re.search(r"Δf = ([0-9.]+) Hz", title).group(1))
    assert stated == pytest.approx(sp.resolution, rel=5e-3)
    # the harmonics of the forcing frequency are marked; the 2x peak (a fifth of the
    # first) is labelled where the spectrum peaks
    marks = [line.get_xdata()[0] for line in ax.get_lines() if line.get_linestyle() == ":"]
    assert marks[:3] == [1, 2, 3]
    labels = {t.get_text(): t.xy for t in ax.texts}
    x, y = labels["2.00×"]
    assert x == pytest.approx(2.0) and y == pytest.approx(0.2 * 600, rel=1e-2)  # nm


def test_the_window_is_hann():
    n, dt = 4000, 1e-4
    t = dt * np.arange(n)
    for bins in (40.5, 40.25, 40.1):  # off the record's bins
        f = bins / (n * dt)
        x = 3.0 + np.sin(2 * np.pi * f * t + 0.3)
        sp = windowed_spectrum(x, dt)
        assert sp.amplitude.max() == pytest.approx(1.0, rel=1e-3)  # zero-padded: no scallop
        far = np.abs(sp.frequency - f) >= 8 * sp.resolution
        assert sp.amplitude[far].max() < 1e-3  # Hann sidelobes at 8 bins: below -60 dB
        rect = 2 * np.abs(np.fft.rfft(x - x.mean())) / n  # no window: -30 dB leakage
        fr = np.fft.rfftfreq(n, dt)
        assert rect[(np.abs(fr - f) >= 8 / (n * dt)) & (fr > 0)].max() > 1e-2


def test_scaled_units():
    assert scaled_unit([44.5e-6], "m") == (pytest.approx(1e6), "µm")
    assert scaled_unit([3e-3, -1e-3], "m/s") == (pytest.approx(1e3), "mm/s")
    assert scaled_unit([1e8, 3e8], "N/m") == (pytest.approx(1e-6), "MN/m")
    assert scaled_unit([0.02, 0.06], "kg*m^2") == (pytest.approx(1e3), "10⁻³ kg·m²")
    assert scaled_unit([0.5], "kg") == (pytest.approx(1e3), "g")
    assert scaled_unit([1500.0], "rpm") == (1.0, "rpm")


def test_parameter_kinds_of_design_fields_and_model_parameters():
    d = load_design("examples/gear_pair.toml")
    m = build_model(d)
    kinds = {
        "mesh.stiffness": "stiffness",
        "gear.moment_of_inertia": "moment of inertia",
        "gear.mass": "mass",
        "operating.speed": "angular velocity",
        "support:gear.x.stiffness": "stiffness",
        "inertia:gear.rz.value": "moment of inertia",
        "inertia:gear.x.value": "mass",
        "load_torque.value": "torque",
        "model:mesh.stiffness": "stiffness",
        "speed": "angular velocity",
        "pinion.teeth": None,
        "mesh.stiffness+gear.mass": "stiffness",
    }
    for path, kind in kinds.items():
        assert parameter_kind(d, m, path) == kind, path
    assert parameter_kind(None, m, "support:gear.x.stiffness") == "stiffness"
    assert parameter_kind(d, None, "support:gear.x.stiffness") is None


def test_sweep_axes_name_the_unit_not_si():
    from reducerlab.analysis.sweep import sweep

    d = load_design("examples/gear_pair.toml")
    expect = {
        "mesh.stiffness": (["1e8", "2e8", "3e8"], "mesh stiffness (MN/m)"),
        "support:gear.x.stiffness": (["2e8", "4e8"], "support gear x stiffness (MN/m)"),
        "gear.moment_of_inertia": (["0.02", "0.04"], "gear moment of inertia (10⁻³ kg·m²)"),
        "operating.speed": (["1000 rpm", "1500 rpm"], "speed (rpm)"),
    }
    for path, (values, label) in expect.items():
        res = sweep(d, parse_values(path, ",".join(values)), workers=1)
        ax = drawn(res.plot()).axes[0]
        assert ax.get_xlabel() == label
        assert ax.xaxis.get_offset_text().get_text() == ""
        x, _ = parameter_axis(res.data["p0"], path)
        assert ax.get_xlim()[0] <= x.min() and ax.get_xlim()[1] >= x.max()


def test_plain_figure_widens_a_round_off_span_and_keeps_placed_ticks():
    from matplotlib.figure import Figure

    from reducerlab.plot.axes import plain_figure

    fig = Figure()
    ax, bx = fig.subplots(1, 2)
    speed = 157.07963267948966 + 1e-13 * np.random.default_rng(1).standard_normal(50)
    ax.plot(np.arange(50), speed)  # a constant speed, varying in its 15th digit
    bx.barh([0, 1], [2.16, 2.33])
    bx.set_yticks([0, 1], ["pinion", "gear"])
    drawn(plain_figure(fig))
    lo, hi = ax.get_ylim()
    assert hi - lo >= 1e-2 * 157.0 and lo < speed.min() and hi > speed.max()
    for axis in (ax.xaxis, ax.yaxis, bx.xaxis, bx.yaxis):
        assert axis.get_offset_text().get_text() == ""
    assert [t.get_text() for t in bx.get_yticklabels()] == ["pinion", "gear"]
    labels = [t.get_text() for t in ax.get_yticklabels()]
    assert len(set(labels)) == len(labels)


def test_rating_figure_has_no_legend_over_its_bars():
    from reducerlab.analysis.rating import load_capacity
    from reducerlab.plot.rating import plot_rating

    fig = drawn(plot_rating(load_capacity(load_design("examples/gear_pair.toml"))))
    for ax in fig.axes:
        assert ax.get_legend() is None and "dashed: S_" in ax.get_xlabel()
        assert ax.xaxis.get_offset_text().get_text() == ""
    assert [t.get_text() for t in fig.axes[0].get_yticklabels()] == ["pinion", "gear"]


def test_time_history_draws_one_curve_where_dte_equals_the_deflection():
    (ax,) = drawn(plot_transmission_error(synthetic())).axes
    (line,) = ax.get_lines()
    assert line.get_label() == "DTE = mesh deflection (e = 0)"
    assert ax.get_ylabel().endswith("(µm)") and ax.get_xlabel() == "time (ms)"


def test_a_zero_transmission_error_says_why_its_figure_is_empty():
    from reducerlab.analysis.transmission_accuracy import transmission_accuracy

    res = transmission_accuracy(load_design("examples/gear_pair.toml"))  # no errors given
    assert not np.any(res.data["error"].values)
    fig = drawn(res.plot())  # no axes: a zero line and an empty spectrum say nothing
    assert not fig.axes
    assert any("No manufacturing or assembly error" in t.get_text() for t in fig.texts)


def test_tolerance_histograms_keep_their_legends_off_the_bars():
    from reducerlab.analysis.tolerances import tolerances

    d = load_design("examples/gear_pair.toml")
    res = tolerances(d, {"mesh.backlash": "60..100 um"}, samples=8, te_samples=256)
    axes = np.asarray(drawn(res.plot()).axes).reshape(2, -1)
    for j in range(axes.shape[1]):
        top, bottom = axes[:, j]
        assert top.get_legend() is None and bottom.get_legend() is not None
        assert bottom.get_xlim() == pytest.approx(top.get_xlim())
        for ax in (top, bottom):
            assert ax.xaxis.get_offset_text().get_text() == ""
    # the backlash alone leaves the unloaded transmission error at zero in every sample
    te = axes[0, -1]
    assert any("every sample" in t.get_text() for t in te.texts)
    assert not any(t.get_text() for t in axes[0, 0].texts)


def tones(orders: dict[float, float], mean: float = 20e-6) -> ResponseResult:
    """A response whose deflection holds the tones ``{order: amplitude}`` (multiples of
    the forcing frequency, m) about ``mean``; its Poincaré points one scattered cloud."""
    res = synthetic(mean=mean, poincare="ring")
    ds = res.data.copy()
    t = ds["time"].values
    w = 2 * math.pi * F
    d = mean + sum(a * np.sin(k * w * t + k) for k, a in orders.items())
    v = sum(a * k * w * np.cos(k * w * t + k) for k, a in orders.items())
    ds["delta"] = ("time", d, {"units": "m"})
    ds["dte"] = ("time", d, {"units": "m"})
    ds["delta_velocity"] = ("time", v, {"units": "m/s"})
    return ResponseResult(ds)


def test_a_small_orbit_states_its_size_against_the_static_deflection():
    # issue 32, cycloid ball: a sub-nanometre tangle about 1.9 um, drawn on its own
    # scale, looked like a large motion
    res = tones({1.0: 3e-10, 1.95: 2e-11, 9.9: 5e-11}, mean=1.88e-6)
    fig = drawn(plot_response(res))
    title = fig.get_suptitle()
    assert "orbit" in title and "static deflection 1.88 µm" in title
    assert re.search(r"orbit [\d.]+ pm peak to peak: 0\.000\d+ ×", title)
    # a large orbit says nothing of the kind
    assert "\n" not in drawn(plot_response(synthetic())).get_suptitle()


def test_spectrum_labels_stay_inside_and_apart():
    # issue 32: "9.90×" clipped at the right edge, "2.05×" on the 2× label
    res = tones({1.0: 1e-6, 2.0: 2e-7, 2.15: 1.9e-7, 9.9: 1e-7, 8.9: 0.9e-7})
    fig = drawn(plot_response(res))
    ax = fig.axes[2]
    r = fig.canvas.get_renderer()
    from matplotlib.text import Text

    # the labels' text (an annotation's extent takes in its leader line too)
    boxes = {t.get_text(): Text.get_window_extent(t, r) for t in ax.texts if "×" in t.get_text()}
    assert {"9.90×", "2.15×", "2.00×"} <= set(boxes), set(boxes)
    frame = ax.get_window_extent(r)
    names = list(boxes)
    for i, a in enumerate(names):
        assert boxes[a].x1 <= frame.x1 + 1, a  # not clipped at the right edge
        for b in names[i + 1 :]:
            bx, by = boxes[a], boxes[b]
            assert not (bx.x0 < by.x1 and by.x0 < bx.x1 and bx.y0 < by.y1 and by.y0 < bx.y1), (
                a,
                b,
            )


def test_the_poincare_note_is_off_the_points():
    # issue 32, nutation mesh 2: the spread note in the lower left covered a point
    fig = drawn(plot_response(synthetic(poincare="period-2")))
    ax = fig.axes[1]
    assert not [t for t in ax.texts if "spread" in t.get_text()]
    assert "spread" in ax.get_title() and "coincide" in ax.get_title()
