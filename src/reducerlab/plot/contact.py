"""Figures of a loaded tooth contact analysis (:class:`~reducerlab.analysis.contact.ContactResult`).

:func:`plot_contact` draws the overview of one mesh cycle (2 x 2): the contact pattern
and pressure on the external gear's flank, the mesh stiffness ``k(t)`` with the Fourier
series of paper 000's Eq. 8 (paper 000 Fig. 3), the loaded transmission error, and the
peak contact pressure and largest subsurface von Mises stress with the number of tooth
pairs in contact. :func:`plot_pressure_map` draws the pressure on each loaded tooth pair
at one position.

The flank maps use the external gear's *developed* flank
(:mod:`reducerlab.plot.contact_flank`, which also draws the bearing pattern). Every
panel over the cycle has one abscissa: gear A's rotation in the mesh (deg), the angle
the analysis steps, with the mesh period (one angular pitch of gear A) marked.

Figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot, Agg-safe);
quantities are SI in the dataset and drawn in mm, MPa, um and deg.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from .contact_flank import (
    angle_deg,
    contact_data,
    developed_flank,
    flank_pattern,
    frame_flank,
    gear_a_name,
    loaded_cells,
    peak_position,
    pressure_mpa,
)

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.contact import ContactResult

__all__ = ["cycle_label", "plot_contact", "plot_pressure_map", "stiffness_curves"]

Array = NDArray[np.float64]

#: colour map of the contact pressure
CMAP = "viridis"
#: colour of the contact pattern (envelope of the loaded cells over the cycle)
PATTERN = "0.82"
PRESSURE_LABEL = "contact pressure (MPa)"
#: the positions' patches are outlined (white) in the overview when less than this
#: fraction of the pattern's cells is loaded at more than one position
OUTLINES = 0.5


def _figure(**kw: object) -> Figure:
    from matplotlib.figure import Figure

    return Figure(**kw)  # no pyplot: no global state, works headless


# ------------------------------------------------------------------ panels


def _panel_pattern(ax: Axes, ds: xr.Dataset, fig: Figure) -> None:
    from .contact_pattern import draw_bearing_pattern

    ax.set_title(f"(a) bearing pattern on {gear_a_name(ds)}'s flank", fontsize=9)
    if not loaded_cells(ds).any():
        ax.text(0.5, 0.5, "no loaded cells", transform=ax.transAxes, ha="center")
        return
    draw_bearing_pattern(ax, ds, fig)


def _cycle(ds: xr.Dataset) -> tuple[float, float]:
    """Gear A's rotation at the cycle's start and its mesh period (deg): one angular
    pitch, ``360 / z_A`` (from the positions' spacing for results without ``z_A``)."""
    ang = angle_deg(ds)
    z = ds.attrs.get("teeth_external")
    if z:
        period = 360.0 / float(z)
    elif len(ang) > 1:
        period = len(ang) * float(ang[1] - ang[0])
    else:
        period = 1.0
    return float(ang[0]) if len(ang) else 0.0, period


def cycle_label(ds: xr.Dataset) -> str:
    """The abscissa of every panel over the mesh cycle: gear A's rotation (deg), relative
    to gear B where the pair's frame turns (the nutation pair's nutating gear, the KHV
    pair's carrier frame): the angle the analysis steps."""
    _, period = _cycle(ds)
    z = ds.attrs.get("teeth_external")
    per = f"360/{int(z)} = {period:.4g} deg" if z else f"{period:.4g} deg"
    b = str(ds.attrs.get("gear_b", ""))
    moving = ds.attrs.get("pair_kind", "spur") != "spur" and b  # a frame that turns
    rel = (
        f" relative to {b.replace('gear', 'gear ', 1) if b[4:5].isdigit() else b}" if moving else ""
    )
    return f"rotation of {gear_a_name(ds)}{rel} (deg); mesh period {per}"


def _cycle_axis(ax: Axes, ds: xr.Dataset) -> None:
    """The shared abscissa: one mesh period from the first position, its ends dotted."""
    start, period = _cycle(ds)
    ax.set_xlim(start - 0.02 * period, start + 1.02 * period)
    for x in (start, start + period):
        ax.axvline(x, color="0.3", lw=0.8, ls=":", zorder=0)
    ax.set_xlabel(cycle_label(ds), fontsize=8)


def stiffness_curves(ds: xr.Dataset, points: int = 400) -> dict[str, Array]:
    """The mesh stiffness over one mesh period as the panel draws it (N/m).

    Returns
    -------
    dict
        ``angle`` (deg, ``points`` from the first position over one period);
        ``between``: the LTCA samples joined by a periodic shape-preserving (PCHIP)
        interpolation, which never leaves the range of its two neighbouring samples;
        ``law`` (with ``k_mean`` in the attributes): paper 000's Eq. 8,
        ``k_m + sum_r k_r cos(r 2 pi (theta - theta_0) / period + phi_r)``, the
        stiffness law the dynamic model uses (the truncated series rings between the
        samples where ``k`` jumps).
    """
    from scipy.interpolate import PchipInterpolator

    start, period = _cycle(ds)
    ang = angle_deg(ds)
    k = np.asarray(ds["stiffness"].values, float)
    x = np.linspace(start, start + period, points)
    out = {"angle": x}
    if len(k) > 1:
        xs = np.r_[ang[-1] - period, ang, ang[0] + period]
        out["between"] = PchipInterpolator(xs, np.r_[k[-1], k, k[0]])(x)
    else:
        out["between"] = np.full(points, k[0] if len(k) else np.nan)
    if "k_mean" in ds.attrs and "amplitude" in ds and "phase" in ds:
        amp = np.asarray(ds["amplitude"].values, float)
        ph = np.asarray(ds["phase"].values, float)
        r = np.arange(1, len(amp) + 1)
        arg = np.multiply.outer(2 * math.pi * (x - start) / period, r) + ph
        out["law"] = float(ds.attrs["k_mean"]) + np.sum(amp * np.cos(arg), axis=-1)
    return out


def _panel_stiffness(ax: Axes, ds: xr.Dataset) -> None:
    n = ds.sizes["position"]
    k = 1e-8 * np.asarray(ds["stiffness"].values, float)
    start, period = _cycle(ds)
    ang = angle_deg(ds)
    curves = stiffness_curves(ds)
    x = curves["angle"]
    ax.plot(x, 1e-8 * curves["between"], "-", color="k", lw=0.9,
            label="LTCA between positions (shape-preserving)")  # fmt: skip
    ax.plot(ang, k, "o", color="k", ms=4, label=f"LTCA ({n} positions)", clip_on=False)
    if n:  # the cycle closes: position 0 again one period on
        ax.plot([start + period], [k[0]], "o", mfc="w", mec="k", ms=4, clip_on=False)
    a = ds.attrs
    if "law" in curves:
        law = 1e-8 * curves["law"]
        res = float(a.get("fit_residual", math.nan))
        label = (
            f"Eq. 8 in the dynamic model, order {a.get('order', 0)} (residual {100 * res:.2g} %)"
        )
        lo, hi = float(np.nanmin(k)), float(np.nanmax(k))
        out = max(lo - float(law.min()), float(law.max()) - hi, 0.0)
        if out > 1e-3 * max(hi - lo, 1e-30):  # the truncated series rings
            label += f",\nleaves the LTCA range by up to {100 * out / lo:.2g} % of k_min"
        ax.plot(x, law, "--", color="tab:red", lw=1.4, label=label)
    if "k_mean" in a:
        km = 1e-8 * float(a["k_mean"])
        ax.axhline(km, color="0.45", lw=0.9, ls=":", label=f"k_m = {km:.4g} x 10^8 N/m")
    _cycle_axis(ax, ds)
    ax.set_ylabel("mesh stiffness k (10^8 N/m)", fontsize=8)
    ax.set_title("(b) mesh stiffness over one mesh period", fontsize=9)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")


def _panel_te(ax: Axes, ds: xr.Dataset) -> None:
    ang = angle_deg(ds)
    te = 1e6 * np.asarray(ds["te"].values, float)
    ax.plot(ang, te, "o-", color="tab:blue", ms=4, lw=1.2)
    if np.isfinite(te).any():
        ptp = float(np.nanmax(te) - np.nanmin(te))
        ax.text(0.02, 0.95, f"peak to peak {ptp:.3g} um", transform=ax.transAxes, va="top",
                fontsize=7)  # fmt: skip
    _cycle_axis(ax, ds)
    ax.set_ylabel("loaded transmission error (um)", fontsize=8)
    ax.set_title("(c) loaded transmission error", fontsize=9)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)


def _panel_stress(ax: Axes, ds: xr.Dataset) -> Axes:
    ang = angle_deg(ds)
    pk = pressure_mpa(ds, "peak_pressure")
    vm = pressure_mpa(ds, "von_mises")
    if "von_mises_depth" in ds:  # 0 with no depth: no interior cell, not computed
        vm = np.where(np.isfinite(np.asarray(ds["von_mises_depth"].values, float)), vm, np.nan)
    ax.plot(ang, pk, "o-", color="tab:red", ms=4, lw=1.2, label="peak contact pressure")
    vm_label = "max subsurface von Mises"
    if not np.isfinite(vm).any():
        vm_label += " (not computed)"
    ax.plot(ang, vm, "s-", color="tab:purple", ms=4, lw=1.2, label=vm_label)
    top = np.nanmax(np.concatenate([pk, vm, [0.0]]))
    ax.set_ylim(0.0, 1.12 * top if top > 0 else 1.0)
    _cycle_axis(ax, ds)
    ax.set_ylabel("stress (MPa)", fontsize=8)
    ax.set_title("(d) contact pressure and subsurface stress", fontsize=9)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)
    tw = ax.twinx()
    pairs = np.asarray(ds["pairs"].values, float)
    # dashed steps, no marker: a marker in the legend's short handle hid its dashes, so
    # that it read as a solid line
    tw.plot(ang, pairs, drawstyle="steps-mid", color="0.35", ls="--", lw=1.0,
            label="tooth pairs in contact")  # fmt: skip
    hi = int(np.nanmax(pairs)) if np.isfinite(pairs).any() else 1
    tw.set_ylim(0, hi + 1)
    tw.set_yticks(range(hi + 2))
    tw.set_ylabel("tooth pairs in contact", fontsize=8)
    tw.tick_params(labelsize=7)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = tw.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="lower left", handlelength=3.0)
    return tw


def _title(ds: xr.Dataset) -> str:
    a = ds.attrs
    parts = [str(a.get("title", "Loaded tooth contact"))]
    extra = []
    if "profile" in a:
        extra.append(str(a["profile"]))
    if "torque_external" in a:
        extra.append(f"T on {gear_a_name(ds)} = {float(a['torque_external']):.4g} N m")
    if int(a.get("rigid", 0)):
        extra.append("rigid teeth")
    if extra:
        parts.append(", ".join(extra))
    return ": ".join(parts)


# ------------------------------------------------------------------ public


def plot_contact(result: ContactResult) -> Figure:
    """Overview of a loaded tooth contact analysis over one mesh cycle (2 x 2 panels).

    Parameters
    ----------
    result : ContactResult
        Or its dataset.

    Returns
    -------
    matplotlib.figure.Figure
        (a) the bearing pattern on the external gear's developed flank
        (:func:`~reducerlab.plot.contact_pattern.draw_bearing_pattern`: the highest
        pressure over the cycle inside the flank's outline, the highest cell starred);
        (b) the mesh stiffness at each position (10^8 N/m), joined by a
        shape-preserving interpolation, with the Fourier series of paper 000's Eq. 8
        that the dynamic model uses (dashed red; its excursion beyond the samples
        stated) and ``k_m``; (c) the loaded transmission error (um); (d) the peak
        contact pressure and the largest subsurface von Mises stress (MPa; gaps where it
        was not computed: NaN, or no cell away from the flank edges) with the tooth
        pairs in contact (twin axis). (b)-(d) share one abscissa, gear A's rotation
        (deg) over one mesh period (:func:`cycle_label`), its ends dotted.
    """
    ds = contact_data(result)
    fig = _figure(figsize=(12.0, 8.0), layout="constrained")
    (a, b), (c, d) = fig.subplots(2, 2)
    _panel_pattern(a, ds, fig)
    _panel_stiffness(b, ds)
    _panel_te(c, ds)
    _panel_stress(d, ds)
    fig.suptitle(_title(ds), fontsize=10)
    return fig


def plot_pressure_map(result: ContactResult, position: int | None = None) -> Figure:
    """Contact pressure at one position, one panel per loaded tooth pair.

    Parameters
    ----------
    result : ContactResult
        Or its dataset.
    position : int, optional
        Index of the position (``0 .. positions - 1``); default the one with the
        highest peak pressure.

    Returns
    -------
    matplotlib.figure.Figure
        Each tooth pair in contact side by side on the external gear's developed flank
        (mm): the cycle's contact pattern in light grey, the pair's loaded cells
        coloured by pressure (MPa, one scale for all panels), the highest cell starred.
        A position without loaded cells gives one panel that says so.
    """
    ds = contact_data(result)
    n = ds.sizes["position"]
    if position is None:
        position = peak_position(ds)
    elif (
        isinstance(position, bool)
        or not isinstance(position, (int, np.integer))
        or not (0 <= position < n)
    ):
        raise ReducerlabError(f"position: must be an integer in 0..{n - 1}; got {position!r}")
    j = int(position)
    fl = developed_flank(ds)
    loaded = loaded_cells(ds)
    pos = np.asarray(ds["cell_position"].values, np.int64)
    tooth = np.asarray(ds["cell_tooth"].values, np.int64)
    pressure = pressure_mpa(ds, "pressure")
    force = np.asarray(ds["cell_force"].values, float)
    here = loaded & (pos == j)
    teeth = [int(k) for k in np.unique(tooth[here])]
    ncol = max(1, len(teeth))
    width, height = float(np.ptp(fl.ev)), float(np.ptp(fl.eu))
    equal = fl.mm and width <= 4 * height
    panel_w = 4.6 if width >= height else 3.2
    ratio = height / width if equal and width > 0 else 0.5
    fig = _figure(figsize=(panel_w * ncol + 1.0, min(6.0, max(1.0, panel_w * ratio)) + 1.3),
                  layout="constrained")  # fmt: skip
    axes = np.atleast_1d(fig.subplots(1, ncol, sharex=True, sharey=True, squeeze=False)).ravel()
    env = flank_pattern(fl, loaded) if loaded.any() else None
    from matplotlib.colors import ListedColormap

    finite = here & np.isfinite(pressure)
    vmax = float(pressure[finite].max()) if finite.any() else 1.0
    im = None
    top = int(np.flatnonzero(finite)[np.argmax(pressure[finite])]) if finite.any() else -1
    for ax, k in zip(axes, teeth or [None], strict=True):
        frame_flank(ax, fl, equal=equal)
        if env is not None:
            ax.pcolormesh(fl.ev, fl.eu, np.ma.masked_invalid(env),
                          cmap=ListedColormap([PATTERN]), vmin=0, vmax=1)  # fmt: skip
        if k is None:
            ax.text(0.5, 0.5, f"no loaded cells at position {j}", transform=ax.transAxes,
                    ha="center", va="center", fontsize=8)  # fmt: skip
            continue
        m = here & (tooth == k)
        im = ax.pcolormesh(fl.ev, fl.eu, np.ma.masked_invalid(fl.grid(m, pressure)),
                           cmap=CMAP, vmin=0.0, vmax=vmax or 1.0)  # fmt: skip
        p_k = float(np.nanmax(pressure[m])) if np.isfinite(pressure[m]).any() else math.nan
        ax.set_title(f"tooth pair {k}: F = {np.nansum(force[m]):.4g} N, "
                     f"p_max = {p_k:.0f} MPa", fontsize=8)  # fmt: skip
        if top >= 0 and tooth[top] == k:
            ax.plot(fl.cv[fl.iv[top]], fl.cu[fl.iu[top]], marker="*", ms=11, mfc="w", mec="k",
                    clip_on=False)  # fmt: skip
    for ax in axes[1:]:
        ax.set_ylabel("")
    if im is not None:
        cb = fig.colorbar(im, ax=list(axes), shrink=0.95, pad=0.01, aspect=15)
        cb.set_label(PRESSURE_LABEL, fontsize=8)
        cb.ax.tick_params(labelsize=7)
    t = ""
    fig.suptitle(f"{_title(ds)}\nposition {j}: {gear_a_name(ds)} at "
                 f"{angle_deg(ds)[j]:.3f} deg{t}", fontsize=9)  # fmt: skip
    return fig
