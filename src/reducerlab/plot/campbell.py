"""Figures of Campbell diagrams: the undamped one (:func:`plot_campbell`), the damped,
whirl-split one (:func:`plot_complex_campbell`), the figure of a resonance verdict
(:func:`plot_resonance`: the diagram the verdict used, with the gear-body modes) and the
report's interactive Campbell diagram (:func:`plotly_campbell`, from
:mod:`.campbell_plotly`).

Every figure draws the same things the same way: each tracked mode in its own colour
(:func:`mode_colours`, distinct for any number of modes; in the complex diagram the
colour is the mode's logarithmic decrement instead, with a colour bar, and the mode's
number is written at its end), each excitation line in its own colour and dash
(:func:`excitation_styles`) labelled with its name and order, the operating range as a
band or, for one operating speed, a line labelled with the speed, each crossing marked
once, the modes of a repeated frequency drawn so that each shows (the later ones dashed)
and numbered together (``"3, 4"``), gear-body modes as grey dash-dot lines named at the
line, and a frequency axis where the excitations can meet the modes (a margin above the
highest excitation frequency over the operating range, at least above the lowest
elastic mode), naming the modes above it (:func:`frequency_axis`).

Figures take results, they compute nothing: matplotlib figures are plain
:class:`~matplotlib.figure.Figure` objects (no pyplot, Agg-safe); plotly is imported
only when its figure is built.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..units import RPM
from .campbell_plotly import plotly_campbell
from .campbell_style import (
    CROSSING_COLOUR,
    OUTSIDE_COLOUR,
    WHIRL,
    FrequencyAxis,
    coincident_dash,
    damping_scale,
    excitation_label,
    excitation_styles,
    frequency_axis,
    mode_colours,
    short_name,
    spread,
    unique_crossings,
    whirl_marks,
)
from .components import bodies_above, draw_component_lines

#: Line styles of a mode that shares its line with 0, 1, 2 earlier modes (a repeated
#: frequency): solid, then dashed and dotted so that the earlier colour shows through.
SHARED_DASHES = ("-", (0, (5, 4)), (0, (1.5, 3)))

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.campbell import CampbellResult
    from ..analysis.complex_modal import ComplexCampbellResult
    from ..analysis.components import ComponentModes
    from ..analysis.resonance import ResonanceResult

__all__ = ["plot_campbell", "plot_complex_campbell", "plot_resonance", "plotly_campbell"]


def _operating(ax: Axes, ds: xr.Dataset) -> None:
    """The operating range as a band, or one operating speed as a line (matplotlib)."""
    lo, hi = ds.attrs.get("operating_min_rad_s"), ds.attrs.get("operating_max_rad_s")
    if lo is None or hi is None or hi <= 0:
        return
    lo, hi = lo * RPM, hi * RPM
    if hi > lo:
        ax.axvspan(lo, hi, color="#dbe8f6", zorder=0,
                   label=f"operating range {lo:.4g}-{hi:.4g} rpm")  # fmt: skip
    else:
        ax.axvline(lo, color="#4a7ebb", lw=3, alpha=0.45, zorder=0.5, gid="operating-speed",
                   label=f"operating speed {lo:.4g} rpm")  # fmt: skip


def _excitations(ax: Axes, ds: xr.Dataset, rpm: np.ndarray, top: float,
                 ends: list[tuple[float, str, str]]) -> None:  # fmt: skip
    """Excitation lines, each in its own colour and dash with its name and order in the
    legend; each is named where it leaves the axes (the top edge here, the right edge
    added to ``ends`` for :func:`_right_labels`)."""
    fe = ds["excitation_frequency"].values
    names, orders = ds["excitation"].values, ds["order"].values
    tops = []
    for k, (colour, dash, _) in enumerate(excitation_styles(len(names))):
        ax.plot(rpm, fe[:, k], linestyle=dash, color=colour, lw=1.1, gid="excitation",
                label=excitation_label(str(names[k]), orders[k]))  # fmt: skip
        short = short_name(str(names[k]))
        if fe[-1, k] <= top:
            ends.append((float(fe[-1, k]), short, colour))
        else:
            tops.append((60.0 * top / float(orders[k]), short, colour))  # rpm at top
    span = rpm[-1] - rpm[0]
    xs = spread([x for x, _, _ in tops], 0.03 * span)
    for x, (_, name, colour) in zip(xs, tops, strict=True):
        if x <= rpm[-1]:
            ax.text(x, 0.985 * top, name + " ", rotation=90, ha="right", va="top", fontsize=7.5,
                    color=colour, gid="excitation-label")  # fmt: skip


def _right_labels(ax: Axes, ends: list[tuple[float, str, str]], x: float, top: float) -> None:
    """Labels at the right edge (excitation names, mode numbers), spread so that none
    overlaps."""
    ends = sorted((e for e in ends if np.isfinite(e[0]) and 0 <= e[0] <= top), key=lambda e: e[0])
    merged: list[tuple[float, str, str]] = []
    for e in ends:  # modes ending at one frequency (a repeated one) share one label
        last = merged[-1] if merged else None
        if (last is not None and e[1].isdigit() and last[1].replace(", ", "").isdigit()
                and e[0] - last[0] <= 0.004 * top):  # fmt: skip
            merged[-1] = (last[0], f"{last[1]}, {e[1]}", "0.15")
        else:
            merged.append(e)
    ends = merged
    ys = spread([y for y, _, _ in ends], 0.04 * top)
    for y, (_, text, colour) in zip(ys, ends, strict=True):
        if y <= top:
            ax.text(x, y, " " + text, ha="left", va="center", fontsize=7.5, color=colour,
                    clip_on=False, gid="end-label")  # fmt: skip


def _crossings(ax: Axes, ds: xr.Dataset, rows: list[dict[str, Any]]) -> None:
    """Each crossing once: in the operating range (red), outside it (dark)."""
    lo = ds.attrs.get("operating_min_rad_s", 0.0) * RPM
    hi = ds.attrs.get("operating_max_rad_s", 0.0) * RPM
    groups = unique_crossings(rows)
    inside = [g[0] for g in groups if lo <= g[0]["speed_rpm"] <= hi]
    outside = [g[0] for g in groups if not lo <= g[0]["speed_rpm"] <= hi]
    kinds = ((inside, CROSSING_COLOUR, "crossing in the operating range"),
             (outside, OUTSIDE_COLOUR, "crossing outside the operating range"))  # fmt: skip
    for sel, colour, label in kinds:
        if sel:
            ax.plot([c["speed_rpm"] for c in sel], [c["frequency_hz"] for c in sel], "o",
                    mfc="none", color=colour, ms=8 if colour == CROSSING_COLOUR else 6,
                    mew=1.5, ls="none", gid="crossing", label=f"{label} ({len(sel)})")  # fmt: skip


def _finish(ax: Axes, components: Sequence[Any], orders: Any, rpm: np.ndarray,
            axis: FrequencyAxis, ds: xr.Dataset) -> None:  # fmt: skip
    """Body-mode lines (with ``components``), the note of what the axis leaves off
    and the legend beside the axes, right of the end labels."""
    from matplotlib.transforms import ScaledTranslation

    handles, _ = ax.get_legend_handles_labels()
    note = axis.note(ds.attrs.get("operating_max_rad_s", 0.0) * RPM)
    if components:
        handles += draw_component_lines(ax, components, orders, (rpm[0], rpm[-1]), axis.top)
        note = "; ".join(t for t in (note, bodies_above(components, axis.top)) if t)
    if note:  # under the title: it never covers the diagram
        ax.set_title(ax.get_title() + "\n" + note, fontsize=8.5)
    width = max([len(t.get_text()) for t in ax.texts if t.get_gid() == "end-label"] + [2])
    shift = ScaledTranslation((4.5 * width + 8) / 72, 0, ax.figure.dpi_scale_trans)
    ax.legend(handles=handles, fontsize=7.5, loc="upper left", bbox_to_anchor=(1.0, 1.0),
              bbox_transform=ax.transAxes + shift, borderaxespad=0,  # clear of the labels
              ncol=2 if len(handles) > 22 else 1)  # fmt: skip
    ax.grid(alpha=0.3)
    ax.set_ylim(0, axis.top)
    ax.set_xlim(rpm[0], rpm[-1])
    ax.set_xlabel("input speed (rpm)")


def plot_campbell(
    result: CampbellResult,
    components: Sequence[ComponentModes] | Sequence[Mapping[str, Any]] = (),
    *,
    fmax: float | None = None,
) -> Figure:
    """Natural frequencies (one colour per tracked mode) and excitation lines (one
    colour and dash each, named with their order) against speed; crossings marked once;
    the operating range, or the operating speed, shown.

    ``components`` (gear-body modes, :class:`~reducerlab.analysis.components.
    ComponentModes`, or a resonance report's component entries): each mode inside the
    frequency range shown is drawn as a horizontal dashed line labelled
    ``"gear N: f Hz (type)"``, its crossings with the excitation lines marked (diamonds).
    ``fmax``: top of the frequency axis (Hz); default :func:`frequency_axis`.
    """
    from matplotlib.figure import Figure

    ds = result.data
    rpm = ds["speed"].values * RPM
    fig = Figure(figsize=(10.0, 5.0), layout="constrained")
    ax = fig.subplots()
    f = ds["frequency"].values
    axis = frequency_axis(ds, fmax)
    ends: list[tuple[float, str, str]] = []
    colours = mode_colours(f.shape[1])
    dashes = coincident_dash(f)
    above = {m for m, _, _ in axis.above}
    for j, m in enumerate(ds["mode"].values):
        if not np.any(f[:, j] > 0):
            continue  # rigid throughout
        label = f"mode {int(m)}" if int(m) not in above else "_above"  # named in the note
        ax.plot(rpm, f[:, j], color=colours[j], lw=1.6 if dashes[j] else 2.4, label=label,
                gid="mode", linestyle=SHARED_DASHES[min(dashes[j], 2)])  # fmt: skip
        ends.append((float(f[-1, j]), str(int(m)), colours[j]))
    _excitations(ax, ds, rpm, axis.top, ends)
    _crossings(ax, ds, result.crossings())
    _operating(ax, ds)
    _right_labels(ax, ends, rpm[-1], axis.top)
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(f"Campbell diagram: {ds.attrs.get('title', '')} (modes tracked by shape)",
                 fontsize=9)  # fmt: skip
    _finish(ax, components, ds["order"].values, rpm, axis, ds)
    return fig


def plot_complex_campbell(
    result: ComplexCampbellResult,
    components: Sequence[ComponentModes] | Sequence[Mapping[str, Any]] = (),
    *,
    fmax: float | None = None,
) -> Figure:
    """Damped natural frequencies against speed, coloured by damping, marked by whirl.

    Each tracked mode is a line coloured by its logarithmic decrement (colour bar) and
    numbered at its right end; its whirl is marked along it (up-triangles forward,
    down-triangles backward, circles planar, squares no lateral motion; the legend
    explains each class shown), unstable points as red crosses; excitation lines (a
    colour and dash each, named with their order); crossings marked once; the operating
    range shaded, or the operating speed drawn as a line.

    Parameters
    ----------
    result : ComplexCampbellResult
    components : sequence of ComponentModes, optional
        Gear-body modes, drawn as horizontal lines with their crossings of the excitation
        lines (as in :func:`plot_campbell`).
    fmax : float, optional
        Top of the frequency axis (Hz); default :func:`frequency_axis`.
    """
    from matplotlib.cm import ScalarMappable
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure

    ds = result.data
    fig = Figure(figsize=(10.5, 5.2), layout="constrained")
    ax = fig.subplots()
    rpm = ds["speed"].values * RPM
    f = ds["frequency"].values
    w = ds["whirl"].values
    st = ds["stable"].values
    axis = frequency_axis(ds, fmax)
    dec, norm = damping_scale(ds)
    cmap = "viridis"
    ends: list[tuple[float, str, str]] = []
    shown: set[str] = set()
    dashes = coincident_dash(f)
    for j, m in enumerate(ds["mode"].values):
        fj = f[:, j]
        if not np.any(np.nan_to_num(fj) > 0):
            continue
        pts = np.column_stack([rpm, fj])
        seg = np.stack([pts[:-1], pts[1:]], axis=1)
        d = 0.5 * (dec[:-1, j] + dec[1:, j])
        ok = np.all(np.isfinite(seg), axis=(1, 2))
        lc = LineCollection(seg[ok], array=d[ok], cmap=cmap, norm=norm, lw=2.2, gid="mode",
                            linestyles=[SHARED_DASHES[min(dashes[j], 2)]])  # fmt: skip
        ax.add_collection(lc)
        k = whirl_marks(w[:, j])
        k = k[np.isfinite(fj[k]) & st[k, j]]
        for label in dict.fromkeys(w[k, j]):
            sel = k[w[k, j] == label]
            mk = WHIRL.get(str(label), ("o", "circle", str(label)))[0]
            ax.scatter(rpm[sel], fj[sel], c=dec[sel, j], cmap=cmap, norm=norm, marker=mk, s=22,
                       edgecolors="k", linewidths=0.6, zorder=3, gid=f"whirl-{label}")  # fmt: skip
            shown.add(str(label))
        last = np.nonzero(np.isfinite(fj))[0]
        if last.size:
            ends.append((float(fj[last[-1]]), str(int(m)), "0.15"))
    bad = ~st & np.isfinite(f) & (f > 0)
    if bad.any():
        R = np.repeat(rpm[:, None], f.shape[1], axis=1)
        ax.plot(R[bad], f[bad], "x", color="red", ms=6, ls="none", label="unstable (grows)")
    _excitations(ax, ds, rpm, axis.top, ends)
    _crossings(ax, ds, result.crossings())
    _operating(ax, ds)
    _right_labels(ax, ends, rpm[-1], axis.top)
    for label in [k for k in WHIRL if k in shown] + sorted(shown - set(WHIRL)):
        mk, _, text = WHIRL.get(label, ("o", "circle", label))
        ax.plot([], [], mk, mfc="white", mec="k", ls="none", label=text)
    fig.colorbar(ScalarMappable(norm, cmap), ax=ax, location="bottom", shrink=0.45, aspect=35,
                 pad=0.02, label="logarithmic decrement (damping)")  # fmt: skip
    ax.set_ylabel("damped natural frequency (Hz)")
    ax.set_title(
        f"complex Campbell diagram: {ds.attrs.get('title', '')} (modes tracked by shape, "
        "numbered at the right)", fontsize=9,
    )  # fmt: skip
    _finish(ax, components, ds["order"].values, rpm, axis, ds)
    return fig


def plot_resonance(result: ResonanceResult, *, fmax: float | None = None) -> Figure:
    """The Campbell diagram a resonance verdict used, with its gear-body modes.

    The undamped diagram (:func:`plot_campbell`), or the damped, whirl-split one
    (:func:`plot_complex_campbell`) when the model has gyroscopic, Coriolis or
    circulatory terms; the gear bodies given to the check drawn as horizontal lines.

    Parameters
    ----------
    result : ResonanceResult
        From :func:`~reducerlab.analysis.resonance.resonance_check`.
    fmax : float, optional
        Top of the frequency axis (Hz); default :func:`frequency_axis` (body modes
        above it named in the figure).
    """
    comps = result.components
    if "whirl" in result.campbell.data:
        return plot_complex_campbell(result.campbell, comps, fmax=fmax)
    return plot_campbell(result.campbell, comps, fmax=fmax)
