"""Figures of the steady nonlinear response and of the frequency-response curves: the
matplotlib figures the results' ``plot()`` draw and the report's time history of the
transmission error; matplotlib is imported only when a figure is built."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .axes import fit_limits, parameter_axis, plain_axes, scaled_unit

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.frequency_response import FrequencyResponseResult
    from ..analysis.response import ResponseResult

__all__ = [
    "COINCIDE",
    "SMALL_ORBIT",
    "orbit_note",
    "plot_frequency_response",
    "plot_response",
    "plot_transmission_error",
]

#: Poincaré points that repeat every n points to within this share of the orbit's size
#: (the phase trajectory's peak-to-peak) are drawn as the n points they are: on axes
#: that show the orbit their spread is far below a pixel, and drawn on the spread's own
#: scale it would look like a cloud or a ring (a quasi-periodic motion) that is not there.
COINCIDE = 1e-4


#: Style of the note naming a backlash edge outside the phase plot's view.
EDGE_NOTE: dict = {"xycoords": "axes fraction", "fontsize": 7, "va": "top", "color": "0.3"}


def plot_response(result: ResponseResult) -> Figure:
    """Phase trajectory, Poincaré map and labelled spectrum (paper 004 Fig. 8).

    Parameters
    ----------
    result : ResponseResult
        The steady response to draw.

    Returns
    -------
    matplotlib.figure.Figure
        Three panels, their units chosen from the data's size (nm, um, mm/s, ...) and
        their tick labels plain numbers: the phase trajectory of the mesh deflection on
        limits from the orbit (the backlash edges drawn where they fall inside, named
        at the side where they do not); the Poincaré map (points that coincide to
        within 1e-4 of the orbit's size, a period-n orbit whose spread is round-off,
        drawn as its n points on the orbit's scale, the spread stated); and the
        Hann-windowed spectrum over multiples of the forcing frequency, its resolution
        stated, the harmonics marked and the largest peaks labelled.
    """
    from matplotlib.figure import Figure

    ds = result.data
    fig = Figure(figsize=(12, 4.0), layout="constrained")
    a1, a2, a3 = fig.subplots(1, 3)
    _phase(a1, ds)
    _poincare(a2, ds)
    _spectrum(a3, result)
    for ax in (a1, a2, a3):
        ax.grid(alpha=0.3)
    note = orbit_note(ds)
    title = str(ds.attrs.get("title", ""))
    fig.suptitle(f"{title}\n{note}" if note else title, fontsize=10)
    return fig


#: An orbit smaller than this share of its static deflection is a small vibration about
#: it: the figure states how small (a tangle drawn on its own scale looks large).
SMALL_ORBIT = 1e-2


def orbit_note(ds: Any) -> str:
    """What the figure says of an orbit that is small against its static deflection:
    its peak-to-peak against the mean deflection, and, where it is below what the
    integration resolves (``accuracy`` x the deflection), that it is; ``""`` otherwise
    (and for a motion nothing excites, which the figures draw as a still point)."""
    from ..analysis.response import NOISE_M

    d = ds["delta"].values
    ptp, mean = float(np.ptp(d)), float(np.abs(np.mean(d)))
    if ptp <= NOISE_M or mean <= 0.0 or ptp >= SMALL_ORBIT * mean:
        return ""
    fo, uo = scaled_unit([ptp], "m")
    fm, um = scaled_unit([mean], "m")
    text = (
        f"orbit {ptp * fo:.3g} {uo} peak to peak: {ptp / mean:.2g} × the static deflection "
        f"{mean * fm:.3g} {um}"
    )
    accuracy = float(ds.attrs.get("accuracy", float("nan")))
    if np.isfinite(accuracy) and ptp <= accuracy * mean:
        text += f", below the integration accuracy ({accuracy:g} × the deflection)"
    return text


def _scales(ds: Any) -> tuple[float, str, float, str, float, float]:
    """Display factors and units of the mesh deflection and its velocity, and the least
    sizes the figures show of each: :data:`reducerlab.analysis.response.NOISE_M` (1 pm,
    the round-off of a mesh deflection) and that times the forcing's angular frequency,
    so that a motion nothing excites is drawn as the still point it is, not as its
    round-off magnified."""
    from ..analysis.response import NOISE_M

    floor_d = NOISE_M
    floor_v = 2 * np.pi * float(ds.attrs["forcing_hz"]) * NOISE_M
    fd, ud = scaled_unit(np.append(ds["delta"].values, floor_d), "m")
    fv, uv = scaled_unit(np.append(ds["delta_velocity"].values, floor_v), "m/s")
    return fd, ud, fv, uv, floor_d, floor_v


def _phase(ax: Axes, ds: Any) -> None:
    """The phase trajectory on the orbit's limits, the backlash edges inside the view
    drawn, those outside named at the side they lie on."""
    fd, ud, fv, uv, floor_d, floor_v = _scales(ds)
    d, v = ds["delta"].values * fd, ds["delta_velocity"].values * fv
    xlim, ylim = fit_limits(d, floor=floor_d * fd), fit_limits(v, floor=floor_v * fv)
    ax.plot(d, v, lw=0.7, color="C0")
    if np.ptp(d) <= floor_d * fd:  # a still point: a line of no length shows nothing
        ax.plot(d[:1], v[:1], "o", color="C0", ms=5)
    b = float(ds.attrs.get("half_backlash_m", 0.0)) * fd
    if b > 0:  # the backlash: no elastic force while |deflection| < b
        lo, hi = max(-b, xlim[0]), min(b, xlim[1])
        if lo < hi:
            ax.axvspan(lo, hi, color="0.88", zorder=0, label="teeth apart")
            ax.legend(fontsize=7, loc="best")
        outside_left = [e for e in (-b, b) if e < xlim[0]]
        outside_right = [e for e in (-b, b) if e > xlim[1]]
        for e in (-b, b):
            if xlim[0] <= e <= xlim[1]:
                ax.axvline(e, color="0.4", lw=0.8, ls="--")
        # an edge outside the view: named at its side, with its distance from the orbit
        if outside_left:
            e = max(outside_left)
            text = f"← backlash edge at {e:.3g} {ud}\n({float(np.min(d)) - e:.3g} {ud}"
            ax.annotate(text + " from the orbit)", (0.02, 0.97), ha="left", **EDGE_NOTE)
        if outside_right:
            e = min(outside_right)
            text = f"backlash edge at {e:.3g} {ud} →\n({e - float(np.max(d)):.3g} {ud}"
            ax.annotate(text + " from the orbit)", (0.98, 0.97), ha="right", **EDGE_NOTE)
        if outside_left or outside_right:  # room above the orbit for the note
            ylim = (ylim[0], ylim[1] + 0.2 * (ylim[1] - ylim[0]))
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    plain_axes(ax, xbins=4)
    ax.set_xlabel(f"mesh deflection ({ud})")
    ax.set_ylabel(f"velocity ({uv})")
    cls = ds.attrs.get("impact_class")
    ax.set_title(
        f"phase trajectory: {cls}, apart {100 * ds.attrs['separation_fraction']:.0f} %"
        if cls
        else "phase trajectory",
        fontsize=9,
    )


def _poincare(ax: Axes, ds: Any) -> None:
    """The Poincaré map: coinciding points (a period-n orbit, spread by round-off) as
    their n points on the orbit's scale, over the faint trajectory; others on their own
    extent."""
    from ..analysis.motion import coinciding_period

    fd, ud, fv, uv, floor_d, floor_v = _scales(ds)
    d, v = ds["delta"].values, ds["delta_velocity"].values
    pts = np.column_stack([ds["poincare_delta"].values, ds["poincare_velocity"].values])
    # the orbit's size, at least the round-off floors (a motion nothing excites: its
    # points coincide as the fixed point they are)
    sizes = np.array([max(float(np.ptp(d)), floor_d), max(float(np.ptp(v)), floor_v)])
    n = coinciding_period(pts, sizes, tol=COINCIDE)
    spread_d = float(np.ptp(pts[:, 0]))
    if n:
        ax.plot(d * fd, v * fv, lw=0.6, color="0.8", zorder=1, label="trajectory")
        centres = np.array([pts[k::n].mean(axis=0) for k in range(n)])
        spread = max(float(np.ptp(pts[k::n, 0])) for k in range(n))
        ax.plot(centres[:, 0] * fd, centres[:, 1] * fv, "o", color="k", ms=6, zorder=3,
                label=f"{n} point{'s' if n > 1 else ''}")  # fmt: skip
        rel = spread / max(sizes[0], 1e-300)
        accuracy = float(ds.attrs.get("accuracy", float("nan")))
        if spread <= 1e-9 * max(float(np.abs(d).max()), 1e-300):
            cause = "round-off"
        elif rel <= (accuracy if np.isfinite(accuracy) else 1e-6):
            cause = "integration accuracy"
        else:
            cause = "below what this scale shows"
        note = (
            f"period {n}: {pts.shape[0]} points coincide,\nspread {spread:.1g} m "
            f"= {rel:.1g} × orbit ({cause})"
        )
        ax.set_xlim(*fit_limits(d * fd, floor=floor_d * fd))
        ax.set_ylim(*fit_limits(v * fv, floor=floor_v * fv))
        ax.legend(fontsize=7, loc="upper right")
    else:
        note = ""
        ax.plot(pts[:, 0] * fd, pts[:, 1] * fv, ".k", ms=3)
        ax.set_xlim(*fit_limits(pts[:, 0] * fd, floor=floor_d * fd))
        ax.set_ylim(*fit_limits(pts[:, 1] * fv, floor=floor_v * fv))
        rel = spread_d / max(sizes[0], 1e-300)
        if rel < 0.05:
            note = f"spread {spread_d:.2g} m = {rel:.2g} × orbit"
    plain_axes(ax, xbins=4)
    ax.set_xlabel(f"mesh deflection ({ud})")
    ax.set_ylabel(f"velocity ({uv})")
    # the note in the title, off the points (in a corner it can cover one)
    head = f"Poincaré map ({pts.shape[0]} periods)"
    ax.set_title(f"{head}\n{note}" if note else head, fontsize=9 if not note else 8)


def _spectrum(ax: Axes, result: ResponseResult) -> None:
    """The Hann-windowed spectrum against multiples of the forcing frequency, its
    resolution stated, harmonics marked, the largest peaks labelled."""
    from ..analysis.response import NOISE_M

    ds = result.data
    fh = float(ds.attrs["forcing_hz"])
    sp = result.spectrum()
    m = sp.frequency / fh
    peaks = result.peaks(5)
    top = max([4.0, *(p + 0.5 for p, _ in peaks)])
    top = min(float(np.ceil(top)), float(m[-1]))
    shown = m <= top
    fa, ua = scaled_unit(np.append(sp.amplitude[shown], NOISE_M), "m")
    amp = sp.amplitude * fa
    big = float(amp[shown].max()) if np.any(shown) else 0.0
    heights = [float(a) * fa for _, a in peaks]
    log = big > 0 and len(heights) > 1 and min(heights) < big / 30
    for k in range(1, int(top) + 1):
        ax.axvline(k, color="C1", lw=0.6, ls=":", zorder=0)
    ax.plot(m[shown], amp[shown], lw=0.9, color="C0")
    ax.set_xlim(0, top)
    if log:
        ax.set_yscale("log")
        ax.set_ylim(max(big * 1e-5, min(heights) / 3), big * 3)
    else:
        ax.set_ylim(0, max(big * 1.15, NOISE_M * fa))
    _peak_labels(ax, m, amp, peaks, sp.resolution / fh, top, log)
    if float(np.ptp(ds["delta"].values)) <= NOISE_M:
        ax.text(0.5, 0.5, f"not excited: the deflection varies by\nless than {NOISE_M:g} m "
                "(round-off)", transform=ax.transAxes, ha="center", va="center", fontsize=8,
                color="0.3")  # fmt: skip
    plain_axes(ax)
    ax.set_xlabel(f"frequency / forcing frequency (f = {fh:.4g} Hz)")
    ax.set_ylabel(f"amplitude ({ua})")
    dlf = ds.attrs["dynamic_load_factor"]
    head = f"spectrum (DLF {dlf:.3f})" if np.isfinite(dlf) else "spectrum (no mean load)"
    ax.set_title(
        f"{head}\n{sp.window} window, Δf = {sp.resolution:.3g} Hz "
        f"(record {sp.record * fh:.3g} periods)",
        fontsize=9,
    )


def _peak_labels(
    ax: Axes, m: Any, amp: Any, peaks: list, resolution: float, top: float, log: bool
) -> None:
    """Label each peak ``"2.05×"`` above it, on a white ground (a harmonic line behind
    it does not strike it through), right-aligned near the right edge (not clipped),
    and raised above a neighbour's label that it would overlap."""
    lo, hi = ax.get_ylim()
    width = 0.12 * top  # a label's width, in orders (five characters at 7 pt, a panel)
    tall = 0.07  # its height, in shares of the axes' height (10 pt a level)

    def frac(h: float) -> float:
        if log:
            return float(np.log10(max(h, lo) / lo) / np.log10(hi / lo))
        return (h - lo) / (hi - lo)

    placed: list[tuple[float, float, float]] = []  # (x0, x1, y0) of each label
    for p, _ in sorted(peaks, key=lambda pk: -pk[1]):  # the largest first, lowest
        near = np.abs(m - p) <= 0.5 * resolution
        h = float(amp[near].max()) if np.any(near) else 0.0
        right = p + width > top
        x0, x1 = (p - width, p) if right else (p, p + width)
        level = 0
        while any(
            x0 < b1 and b0 < x1 and abs(frac(h) + tall * level - y) < tall for b0, b1, y in placed
        ):
            level += 1
        placed.append((x0, x1, frac(h) + tall * level))
        ax.annotate(
            f"{p:.2f}×", (p, h), xytext=(-2 if right else 2, 2 + 10 * level),
            textcoords="offset points", fontsize=7, ha="right" if right else "left",
            bbox=dict(boxstyle="square,pad=0.1", fc="white", ec="none", alpha=0.85),
            arrowprops=dict(arrowstyle="-", color="0.5", lw=0.5) if level else None,
        )  # fmt: skip


def plot_transmission_error(result: ResponseResult) -> Figure:
    """Dynamic transmission error and mesh deflection over the last periods of a steady
    response (the design report's time history).

    Parameters
    ----------
    result : ResponseResult
        The steady response to draw.

    Returns
    -------
    matplotlib.figure.Figure
        One panel: the dynamic transmission error and the mesh deflection (one curve
        where they are equal: no static transmission error) against the time from the
        start of the kept history, the units chosen from the data's size.
    """
    from matplotlib.figure import Figure

    ds = result.data
    fig = Figure(figsize=(9, 3), layout="constrained")
    ax = fig.subplots()
    t = ds["time"].values
    ft, ut = scaled_unit(t - t[0], "s")
    dte, delta = ds["dte"].values, ds["delta"].values
    f, unit = scaled_unit(np.concatenate([dte, delta]), "m")
    same = np.allclose(dte, delta, rtol=0.0, atol=1e-9 * max(float(np.abs(delta).max()), 1e-300))
    if same:  # no static transmission error: the two curves are one
        ax.plot((t - t[0]) * ft, delta * f, lw=0.8, label="DTE = mesh deflection (e = 0)")
    else:
        ax.plot((t - t[0]) * ft, dte * f, lw=0.8, label="DTE")
        ax.plot((t - t[0]) * ft, delta * f, lw=0.8, label="mesh deflection")
    ax.set_xlim(0, float(t[-1] - t[0]) * ft)
    plain_axes(ax, xbins=8)
    ax.set_xlabel(f"time ({ut})")
    ax.set_ylabel(f"displacement along the line ({unit})", fontsize=9)
    ax.legend(fontsize=8, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=2, frameon=False)
    ax.grid(alpha=0.3)
    return fig


def plot_frequency_response(result: FrequencyResponseResult) -> Figure:
    """RMS DTE, dynamic load factor and separation share against the parameter, the
    ascending sweep solid, the descending one dashed.

    Parameters
    ----------
    result : FrequencyResponseResult
        The frequency-response curves to draw.

    Returns
    -------
    matplotlib.figure.Figure
        Three panels sharing the parameter axis, one line per sweep direction.
    """
    from matplotlib.figure import Figure

    ds = result.data
    fig = Figure(figsize=(7.5, 6.6), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    x, xlabel = parameter_axis(ds["p0"], ds.attrs["parameter"])
    f, unit = scaled_unit(ds["rms_dte"].values, "m")
    style = {"up": ("-o", "k", "ascending sweep"), "down": ("--x", "C3", "descending sweep")}
    for b in ds["branch"].values.tolist():
        fmt, colour, label = style[b]
        sel = ds.sel(branch=b)
        axes[0].plot(x, sel["rms_dte"].values * f, fmt, color=colour, ms=3, label=label)
        axes[1].plot(x, sel["dynamic_load_factor"].values, fmt, color=colour, ms=3)
        axes[2].plot(x, 100 * sel["separation_fraction"].values, fmt, color=colour, ms=3)
    axes[0].set_ylabel(f"RMS dynamic TE ({unit})")
    axes[1].set_ylabel("dynamic load factor")
    axes[2].set_ylabel("teeth apart (% of time)")
    axes[2].set_xlabel(xlabel)
    axes[0].legend(fontsize=7)
    axes[0].set_title(f"frequency response: {ds.attrs.get('title', '')}", fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3)
        plain_axes(ax, ybins=4)
    return fig
