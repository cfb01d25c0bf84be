"""Figures of Campbell diagrams: the undamped one (:func:`plot_campbell`), the damped,
whirl-split one (:func:`plot_complex_campbell`), the figure of a resonance verdict
(:func:`plot_resonance`: the diagram the verdict used, with the gear-body modes) and the
report's interactive Campbell diagram (:func:`plotly_campbell`).

Every figure draws the same things the same way: each tracked mode in its own colour
(:func:`mode_colours`, distinct for any number of modes; in the complex diagram the
colour is the mode's logarithmic decrement instead, with a colour bar, and the mode's
number is written at its end), each excitation line in its own colour and dash
(:func:`excitation_styles`) labelled with its name and order, the operating range as a
band or, for one operating speed, a line labelled with the speed, each crossing marked
once, and a frequency axis that reaches every excitation line's frequency over the
operating range up to :data:`CAP` times the highest natural frequency, naming the lines
it leaves off (:func:`frequency_axis`).

Figures take results, they compute nothing: matplotlib figures are plain
:class:`~matplotlib.figure.Figure` objects (no pyplot, Agg-safe); plotly is imported
only when its figure is built.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..units import RPM
from .campbell_style import (
    CROSSING_COLOUR,
    OUTSIDE_COLOUR,
    WHIRL,
    FrequencyAxis,
    damping_scale,
    excitation_label,
    excitation_styles,
    frequency_axis,
    mode_colours,
    modes_text,
    sig,
    spread,
    unique_crossings,
    whirl_marks,
)
from .components import draw_component_lines

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
        if fe[-1, k] <= top:
            ends.append((float(fe[-1, k]), str(names[k]), colour))
        else:
            tops.append((60.0 * top / float(orders[k]), str(names[k]), colour))  # rpm at top
    span = rpm[-1] - rpm[0]
    xs = spread([x for x, _, _ in tops], 0.03 * span)
    for x, (_, name, colour) in zip(xs, tops, strict=True):
        if x <= rpm[-1]:
            ax.text(x, 0.985 * top, name + " ", rotation=90, ha="right", va="top", fontsize=6,
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
    ys = spread([y for y, _, _ in ends], 0.035 * top)
    for y, (_, text, colour) in zip(ys, ends, strict=True):
        if y <= top:
            ax.text(x, y, " " + text, ha="left", va="center", fontsize=6, color=colour,
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
    """Body-mode lines (with ``components``), the clipped-lines note and the legend
    beside the axes."""
    handles, _ = ax.get_legend_handles_labels()
    if components:
        handles += draw_component_lines(ax, components, orders, (rpm[0], rpm[-1]), axis.top)
    note = axis.note(ds.attrs.get("operating_max_rad_s", 0.0) * RPM)
    if note:  # under the title: it never covers the diagram
        ax.set_title(ax.get_title() + "\n" + note, fontsize=8)
    ax.legend(handles=handles, fontsize=6.5, loc="upper left", bbox_to_anchor=(1.06, 1.0),
              ncol=2 if len(handles) > 26 else 1)  # fmt: skip
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
    for j, m in enumerate(ds["mode"].values):
        if not np.any(f[:, j] > 0):
            continue  # rigid throughout
        ax.plot(rpm, f[:, j], color=colours[j], lw=1.5, label=f"mode {int(m)}", gid="mode")
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
    for j, m in enumerate(ds["mode"].values):
        fj = f[:, j]
        if not np.any(np.nan_to_num(fj) > 0):
            continue
        pts = np.column_stack([rpm, fj])
        seg = np.stack([pts[:-1], pts[1:]], axis=1)
        d = 0.5 * (dec[:-1, j] + dec[1:, j])
        ok = np.all(np.isfinite(seg), axis=(1, 2))
        lc = LineCollection(seg[ok], array=d[ok], cmap=cmap, norm=norm, lw=2.2, gid="mode")
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
        Top of the frequency axis (Hz); default 1.05 x the highest body mode when the
        check has components, else :func:`frequency_axis`.
    """
    comps = result.components
    if fmax is None and comps:
        fmax = 1.05 * max(max(c.frequencies) for c in comps)
    if "whirl" in result.campbell.data:
        return plot_complex_campbell(result.campbell, comps, fmax=fmax)
    return plot_campbell(result.campbell, comps, fmax=fmax)


def plotly_campbell(
    result: CampbellResult | ComplexCampbellResult, check: Mapping[str, Any] | None = None
) -> Any:
    """Interactive Campbell diagram (plotly), drawn as :func:`plot_campbell` and
    :func:`plot_complex_campbell` draw it.

    Tracked modes in distinct colours (complex: their markers coloured by the log
    decrement, with a colour bar, and shaped by whirl, a legend entry explaining each
    whirl class shown; unstable points as red crosses); each excitation line in its own
    colour and dash, named with its order; the operating range as a band, or the
    operating speed as a line, labelled; the frequency axis of :func:`frequency_axis`
    with the lines it leaves off named; each crossing marked once.

    Parameters
    ----------
    result : CampbellResult or ComplexCampbellResult
        The diagram (a resonance verdict's :attr:`~reducerlab.analysis.resonance.
        ResonanceResult.campbell`).
    check : mapping, optional
        A resonance verdict: its crossings in the operating range are marked red when
        their excitation drives the mode, grey when not (``excited``), the diagram's
        other crossings dark; its gear-body modes drawn as dotted horizontal lines.

    Returns
    -------
    plotly.graph_objects.Figure
    """
    import plotly.graph_objects as go

    check = check if check is not None else {}
    ds = result.data
    rpm = ds["speed"].values * RPM
    x = sig(rpm)
    fig = go.Figure()
    axis = frequency_axis(ds)
    lo, hi = ds.attrs["operating_min_rad_s"] * RPM, ds.attrs["operating_max_rad_s"] * RPM
    if hi > lo:
        fig.add_vrect(x0=lo, x1=hi, fillcolor="rgba(60,120,200,0.13)", line_width=0,
                      annotation_text=f"operating range {lo:.4g}-{hi:.4g} rpm",
                      annotation_position="top left")  # fmt: skip
    elif hi > 0:
        fig.add_vline(x=lo, line=dict(color="rgba(60,120,200,0.55)", width=4),
                      annotation_text=f"operating speed {lo:.4g} rpm",
                      annotation_position="top right")  # fmt: skip
    complex_ = "whirl" in ds
    f_all = ds["frequency"].values
    colours = mode_colours(f_all.shape[1])
    dec, norm = damping_scale(ds) if complex_ else (None, None)
    shown: set[str] = set()
    for j, m in enumerate(ds["mode"].values):
        f = f_all[:, j]
        if not np.any(np.nan_to_num(f) > 0):
            continue
        name = f"mode {int(m)}"
        hover = "%{x:.4g} rpm, %{y:.4g} Hz"
        text = None
        if complex_:
            whirl = ds["whirl"].values[:, j]
            text = [f"{w}, log dec {d:.3g}" for w, d in zip(whirl, dec[:, j], strict=True)]
            hover += " %{text}"
        fig.add_trace(go.Scatter(
            x=x, y=sig(f), mode="lines", name=name, legendgroup=name, text=text,
            line=dict(color=colours[j], width=1.5 if complex_ else 2),
            hovertemplate=hover + f"<extra>{name}</extra>",
        ))  # fmt: skip
        if complex_:
            k = whirl_marks(whirl)
            k = k[np.isfinite(f[k])]
            symbols = [WHIRL.get(str(w), ("o", "circle", ""))[1] for w in whirl[k]]
            shown |= {str(w) for w in whirl[k]}
            fig.add_trace(go.Scatter(
                x=[x[i] for i in k], y=sig(f[k]), mode="markers", legendgroup=name,
                showlegend=False, name=f"{name} whirl", hoverinfo="skip",
                marker=dict(symbol=symbols, size=8, color=sig(dec[k, j], 3),
                            coloraxis="coloraxis", line=dict(color="black", width=0.6)),
            ))  # fmt: skip
            bad = ~ds["stable"].values[:, j] & np.isfinite(f)
            if bad.any():
                fig.add_trace(go.Scatter(
                    x=sig(rpm[bad]), y=sig(f[bad]), mode="markers", showlegend=False,
                    marker=dict(color="red", symbol="x", size=7), name=f"{name} unstable",
                ))  # fmt: skip
    for label in [k for k in WHIRL if k in shown]:
        fig.add_trace(go.Scatter(
            x=[None], y=[None], mode="markers", name=WHIRL[label][2],
            marker=dict(symbol=WHIRL[label][1], size=9, color="white",
                        line=dict(color="black", width=1)),
        ))  # fmt: skip
    names, orders = ds["excitation"].values, ds["order"].values
    fe = ds["excitation_frequency"].values
    for k, (colour, _, dash) in enumerate(excitation_styles(len(names))):
        label = excitation_label(str(names[k]), orders[k])
        fig.add_trace(go.Scatter(
            x=[x[0], x[-1]], y=sig([fe[0, k], fe[-1, k]]), mode="lines", name=label,
            line=dict(dash=dash, color=colour, width=1.5),
            hovertemplate=label + ": %{y:.4g} Hz<extra></extra>",
        ))  # fmt: skip
    for comp in check.get("components", ()):
        for fc in comp["frequencies"]:
            fig.add_hline(y=fc, line=dict(color="darkorange", width=1, dash="dot"))
        fig.add_trace(go.Scatter(x=[None], y=[None], mode="lines",
                                 name=f"{comp['label']} body modes",
                                 line=dict(color="darkorange", dash="dot")))  # fmt: skip
    _plotly_crossings(go, fig, result.crossings(), check.get("crossings"), lo, hi)
    note = axis.note(hi)
    if note:
        fig.add_annotation(
            text=note,
            xref="paper",
            yref="paper",
            x=0.01,
            y=0.99,
            xanchor="left",
            yanchor="top",
            showarrow=False,
            font=dict(size=11, color="#444"),
            bgcolor="rgba(255,255,255,0.8)",
        )
    layout: dict[str, Any] = dict(
        xaxis_title="input speed (rpm)",
        yaxis_title="damped natural frequency (Hz)" if complex_ else "frequency (Hz)",
        yaxis_range=[0, float(f"{axis.top:.4g}")], xaxis_range=[x[0], x[-1]],
        height=560, template="plotly_white", margin=dict(t=30, l=60, r=20, b=50),
    )  # fmt: skip
    if complex_:  # the legend below, the colour bar beside the axes
        layout["legend"] = dict(orientation="h", yanchor="top", y=-0.16, x=0, font_size=11)
        layout["margin"] = dict(t=30, l=60, r=20, b=150)
        layout["height"] = 640
        layout["coloraxis"] = dict(
            colorscale="Viridis", cmin=float(f"{norm.vmin:.3g}"), cmax=float(f"{norm.vmax:.3g}"),
            colorbar=dict(title="log dec"),
        )  # fmt: skip
    fig.update_layout(**layout)
    return fig


def _plotly_crossings(go: Any, fig: Any, rows: list[dict[str, Any]],
                      checked: Sequence[Mapping[str, Any]] | None, lo: float,
                      hi: float) -> None:  # fmt: skip
    """Each crossing of the diagram once: the verdict's rows in the range (driven: red;
    not driven: grey), the others dark."""
    if checked is None:
        checked = [r for r in rows if lo <= r["speed_rpm"] <= hi]
    inside = unique_crossings(checked)

    def key(g: list[Mapping[str, Any]]) -> tuple[str, float]:
        return str(g[0]["excitation"]), float(f"{g[0]['speed_rpm']:.6g}")

    seen = {key(g) for g in inside}
    outside = [g for g in unique_crossings(rows) if key(g) not in seen]
    kinds = (
        ([g for g in inside if any(r.get("excited", True) for r in g)], CROSSING_COLOUR, 11,
         "crossings in the operating range"),
        ([g for g in inside if not any(r.get("excited", True) for r in g)], "gray", 11,
         "crossings in range, not driven (mesh strain, whirl)"),
        (outside, OUTSIDE_COLOUR, 8, "crossings outside the operating range"),
    )  # fmt: skip
    for groups, colour, size, label in kinds:
        if not groups:
            continue
        fig.add_trace(go.Scatter(
            x=sig([g[0]["speed_rpm"] for g in groups]),
            y=sig([g[0]["frequency_hz"] for g in groups]),
            mode="markers", name=f"{label} ({len(groups)})",
            marker=dict(color=colour, size=size, symbol="circle-open", line=dict(width=2)),
            text=[f"{modes_text(g)} x {g[0]['excitation']}" + _share_text(g[0]) for g in groups],
            hovertemplate="%{text}<br>%{x:.5g} rpm, %{y:.5g} Hz<extra></extra>",
        ))  # fmt: skip


def _share_text(row: Mapping[str, Any]) -> str:
    """``", mesh strain 3.05 %"`` or ``", forward whirl 0 %"`` of a crossing row."""
    if row.get("mesh_share") is not None:
        return f", mesh strain {100 * row['mesh_share']:.3g} %"
    if row.get("forward_share") is not None:
        return f", forward whirl {100 * row['forward_share']:.3g} %"
    return ""
