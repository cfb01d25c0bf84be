"""The report's interactive Campbell diagram (:func:`plotly_campbell`), drawn as the
static ones of :mod:`.campbell` are, for a page an engineer reads at a glance: the
diagram keeps the page's width (mode numbers and excitation names written at the
lines' ends, one legend entry for all the modes, the legend in rows below), repeated
frequencies drawn so that each shows, gear-body modes in their own grey dash-dot style,
and the frequency axis where the excitations can meet the modes
(:func:`~reducerlab.plot.campbell_style.frequency_axis`), the modes above it named.

plotly is imported only when the figure is built.
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
    coincident_dash,
    damping_scale,
    excitation_label,
    excitation_styles,
    frequency_axis,
    mode_colours,
    modes_text,
    short_name,
    sig,
    spread,
    unique_crossings,
    whirl_marks,
)
from .components import BODY_COLOUR, CLOSE, bodies_above, close_groups, group_label

if TYPE_CHECKING:
    from ..analysis.campbell import CampbellResult
    from ..analysis.complex_modal import ComplexCampbellResult

__all__ = ["plotly_campbell"]

#: plotly dashes of a mode sharing its line with 0, 1, 2 earlier modes.
SHARED_DASHES = ("solid", "dash", "dot")
#: Legend name of all the modes (one entry).
MODES_NAME = "natural frequencies (mode numbers at the right)"
#: Height of the end labels' gap, as a fraction of the frequency axis.
LABEL_GAP = 0.04


def plotly_campbell(
    result: CampbellResult | ComplexCampbellResult, check: Mapping[str, Any] | None = None
) -> Any:
    """Interactive Campbell diagram (plotly), drawn as :func:`~reducerlab.plot.
    campbell.plot_campbell` and :func:`~reducerlab.plot.campbell.plot_complex_campbell`
    draw it.

    Tracked modes in distinct colours, numbered at their right ends (modes of a repeated
    frequency share their number label, ``"3, 4"``, the later ones dashed), one legend
    entry for them all (complex: markers coloured by the log decrement, with a colour
    bar, and shaped by whirl, a legend entry explaining each whirl class shown;
    unstable points as red crosses); each excitation line in its own colour and dash,
    named with its order in the legend and by name at its end; the operating range as
    a band, or the operating speed as a line, labelled; the frequency axis of
    :func:`~reducerlab.plot.campbell_style.frequency_axis`, what it leaves off named in
    the title; each crossing marked once. The legend lies in rows below the diagram.

    Parameters
    ----------
    result : CampbellResult or ComplexCampbellResult
        The diagram (a resonance verdict's :attr:`~reducerlab.analysis.resonance.
        ResonanceResult.campbell`).
    check : mapping, optional
        A resonance verdict: its crossings in the operating range are marked red when
        their excitation drives the mode, grey when not (``excited``), the diagram's
        other crossings dark; its gear-body modes drawn as grey dash-dot horizontal
        lines named at the line (``"gear 2 body: 3746.3 Hz (bending)"``), those above
        the axis named in the title.

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
    top = axis.top
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
    ends: list[tuple[float, str, str]] = []
    _modes(go, fig, ds, x, rpm, ends)
    _excitations(go, fig, ds, x, top, ends)
    for comp in check.get("components", ()):
        _body(fig, comp, top)
    if any(f <= top for comp in check.get("components", ()) for f in comp["frequencies"]):
        fig.add_trace(go.Scatter(
            x=[None], y=[None], mode="lines", name="gear-body modes, FE (named at the line)",
            line=dict(color=BODY_COLOUR, dash="dashdot", width=1.5),
        ))  # fmt: skip
    _plotly_crossings(go, fig, result.crossings(), check.get("crossings"), lo, hi)
    _end_labels(fig, ends, top)
    note = "; ".join(t for t in (axis.note(hi), bodies_above(check.get("components", ()), top))
                     if t)  # fmt: skip
    layout: dict[str, Any] = dict(
        xaxis_title="input speed (rpm)",
        yaxis_title="damped natural frequency (Hz)" if complex_ else "frequency (Hz)",
        yaxis_range=[0, float(f"{top:.4g}")], xaxis_range=[x[0], x[-1]],
        height=620, template="plotly_white",
        margin=dict(t=40 if note else 24, l=60, r=110, b=60),
        legend=dict(orientation="h", yanchor="top", y=-0.13, x=0, font_size=11,
                    entrywidth=0, tracegroupgap=0),
        title=dict(text=note, font=dict(size=12, color="#444"), x=0.01, xanchor="left",
                   y=0.995, yanchor="top") if note else None,
    )  # fmt: skip
    if complex_:  # the colour bar beside the axes, left of the end labels' column
        _, norm = damping_scale(ds)
        layout["height"] = 660
        layout["coloraxis"] = dict(
            colorscale="Viridis", cmin=float(f"{norm.vmin:.3g}"), cmax=float(f"{norm.vmax:.3g}"),
            colorbar=dict(title="log dec", x=1.0, xpad=90, len=0.6, y=0.99, yanchor="top",
                          thickness=14),
        )  # fmt: skip
    fig.update_layout(**layout)
    return fig


def _modes(go: Any, fig: Any, ds: Any, x: list, rpm: np.ndarray,
           ends: list[tuple[float, str, str]]) -> None:  # fmt: skip
    """Each tracked mode a line of its colour (dashed where it repeats an earlier one),
    one legend entry for all; complex: whirl markers coloured by the log decrement."""
    complex_ = "whirl" in ds
    f_all = ds["frequency"].values
    colours = mode_colours(f_all.shape[1])
    dashes = coincident_dash(f_all)
    dec = damping_scale(ds)[0] if complex_ else None
    shown: set[str] = set()
    first = True
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
            x=x, y=sig(f), mode="lines", name=MODES_NAME if first else name,
            legendgroup="modes", showlegend=first, text=text,
            line=dict(color=colours[j], width=(1.8 if complex_ else 2.2) + 0.8 * (not dashes[j]),
                      dash=SHARED_DASHES[min(dashes[j], 2)]),
            hovertemplate=hover + f"<extra>{name}</extra>",
        ))  # fmt: skip
        first = False
        last = np.nonzero(np.isfinite(f))[0]
        if last.size:
            ends.append((float(f[last[-1]]), f"mode {int(m)}", colours[j]))
        if complex_:
            k = whirl_marks(whirl)
            k = k[np.isfinite(f[k])]
            symbols = [WHIRL.get(str(w), ("o", "circle", ""))[1] for w in whirl[k]]
            shown |= {str(w) for w in whirl[k]}
            fig.add_trace(go.Scatter(
                x=[x[i] for i in k], y=sig(f[k]), mode="markers", legendgroup="modes",
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


def _excitations(go: Any, fig: Any, ds: Any, x: list, top: float,
                 ends: list[tuple[float, str, str]]) -> None:  # fmt: skip
    """Each excitation line in its colour and dash, named with its order in the legend
    and by name where it leaves the axes: at the right edge (added to ``ends``) or at
    the top edge (written there, upright)."""
    names, orders = ds["excitation"].values, ds["order"].values
    fe = ds["excitation_frequency"].values
    tops = []
    for k, (colour, _, dash) in enumerate(excitation_styles(len(names))):
        label = excitation_label(str(names[k]), orders[k])
        fig.add_trace(go.Scatter(
            x=[x[0], x[-1]], y=sig([fe[0, k], fe[-1, k]]), mode="lines", name=label,
            line=dict(dash=dash, color=colour, width=1.5),
            hovertemplate=label + ": %{y:.4g} Hz<extra></extra>",
        ))  # fmt: skip
        short = short_name(str(names[k]))
        if fe[-1, k] <= top:
            ends.append((float(fe[-1, k]), short, colour))
        else:
            tops.append((60.0 * top / float(orders[k]), short, colour))
    span = x[-1] - x[0]
    xs = spread([t[0] for t in tops], 0.022 * span)
    for xt, (_, name, colour) in zip(xs, tops, strict=True):
        if xt <= x[-1]:
            fig.add_annotation(x=float(f"{xt:.5g}"), y=float(f"{top:.4g}"), text=name,
                               textangle=-90, xanchor="right", yanchor="top", showarrow=False,
                               font=dict(size=11, color=colour))  # fmt: skip


def _body(fig: Any, comp: Mapping[str, Any], top: float) -> None:
    """One gear body's modes below ``top``: grey dash-dot lines, each named at the line
    (close ones together)."""
    types = comp.get("types") or [""] * len(comp["frequencies"])
    rows = [(float(f), str(t)) for f, t in zip(comp["frequencies"], types, strict=True)
            if f <= top]  # fmt: skip
    for f, _ in rows:
        fig.add_hline(y=float(f"{f:.5g}"), line=dict(color=BODY_COLOUR, width=1.5, dash="dashdot"))
    for group in close_groups(rows, CLOSE * top):
        fig.add_annotation(
            x=0.005, xref="paper", y=float(f"{group[0][0]:.5g}"), xanchor="left", yanchor="bottom",
            text=group_label(f"{comp['label']} body", group), showarrow=False,
            font=dict(size=11, color=BODY_COLOUR), bgcolor="rgba(255,255,255,0.7)",
        )  # fmt: skip


def _end_labels(fig: Any, ends: list[tuple[float, str, str]], top: float) -> None:
    """Mode numbers and excitation names at the right edge, spread so that none
    overlaps; modes ending at one frequency (a repeated one) share a label
    (``"3, 4"``)."""
    ends = sorted((e for e in ends if np.isfinite(e[0]) and 0 <= e[0] <= top), key=lambda e: e[0])
    merged: list[tuple[float, str, str]] = []
    for e in ends:
        last = merged[-1] if merged else None
        if (last is not None and e[1].startswith("mode ") and last[1].startswith("mode")
                and e[0] - last[0] <= 0.004 * top):  # fmt: skip
            merged[-1] = (last[0], f"modes {last[1].split(' ', 1)[1]}, {e[1][5:]}", "#262626")
        else:
            merged.append(e)
    ys = spread([y for y, _, _ in merged], LABEL_GAP * top)
    for y, (_, text, colour) in zip(ys, merged, strict=True):
        if y <= 1.02 * top:
            fig.add_annotation(
                x=1.0, xref="paper", y=float(f"{y:.4g}"), xanchor="left", yanchor="middle",
                text=" " + text, showarrow=False,
                font=dict(size=11, color=colour), name="end-label",
            )  # fmt: skip


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
