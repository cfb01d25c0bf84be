"""Figures of Campbell diagrams: the undamped one (:func:`plot_campbell`), the damped,
whirl-split one (:func:`plot_complex_campbell`), the figure of a resonance verdict
(:func:`plot_resonance`: the diagram the verdict used, with the gear-body modes) and the
report's interactive Campbell diagram (:func:`plotly_campbell`).

Figures take results, they compute nothing: matplotlib figures are plain
:class:`~matplotlib.figure.Figure` objects (no pyplot, Agg-safe); plotly is imported
only when its figure is built.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ReducerlabError
from ..units import RPM
from .components import draw_component_lines

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.campbell import CampbellResult
    from ..analysis.complex_modal import ComplexCampbellResult
    from ..analysis.components import ComponentModes
    from ..analysis.resonance import ResonanceResult

__all__ = ["plot_campbell", "plot_complex_campbell", "plot_resonance", "plotly_campbell"]

#: Marker and colour of each whirl in the complex Campbell diagram.
WHIRL_MARKS = {"forward": ("^", "C0"), "backward": ("v", "C3"), "planar": (".", "C2"),
               "none": (".", "C7"), "ccw": (".", "C7"), "cw": (".", "C7")}  # fmt: skip


def _fmax(fmax: float | None, f: np.ndarray, scale: float) -> float:
    """The top of the frequency axis: ``fmax`` checked, else ``scale`` x the highest
    frequency drawn."""
    if fmax is None:
        top = np.nanmax(f) if np.any(np.isfinite(f)) else np.nan
        return float(top * scale) if np.isfinite(top) else 1.0
    if not (isinstance(fmax, int | float) and 0 < fmax < np.inf):
        raise ReducerlabError(f"fmax must be a positive frequency (Hz), got {fmax!r}")
    return float(fmax)


def _finish(ax: Axes, components: Sequence[Any], orders: Any, rpm: np.ndarray,
            fmax: float) -> None:  # fmt: skip
    """Body-mode lines (with ``components``) and the legend: beside the axes when the
    body lines are drawn, inside otherwise."""
    if components:
        handles, _ = ax.get_legend_handles_labels()
        handles += draw_component_lines(ax, components, orders, (rpm[0], rpm[-1]), fmax)
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    else:
        ax.legend(fontsize=7)
    ax.grid(alpha=0.3)


def plot_campbell(
    result: CampbellResult,
    components: Sequence[ComponentModes] | Sequence[Mapping[str, Any]] = (),
    *,
    fmax: float | None = None,
) -> Figure:
    """Natural frequencies and excitation lines against speed; crossings marked.

    ``components`` (gear-body modes, :class:`~reducerlab.analysis.components.
    ComponentModes`, or a resonance report's component entries): each mode inside the
    frequency range shown is drawn as a horizontal dashed line labelled
    ``"gear N: f Hz (type)"``, its crossings with the excitation lines marked (diamonds).
    ``fmax``: top of the frequency axis (Hz); default 1.1 x the highest natural frequency.
    """
    from matplotlib.figure import Figure

    ds = result.data
    rpm = ds["speed"].values * RPM
    fig = Figure(figsize=(9.5 if components else 7.5, 4.8), layout="constrained")
    ax = fig.subplots()
    f = ds["frequency"].values
    for j in range(f.shape[1]):
        ax.plot(rpm, f[:, j], color="C0", lw=1.3)
    for k, name in enumerate(ds["excitation"].values):
        ax.plot(rpm, ds["excitation_frequency"].values[:, k], "--", lw=1.0, label=str(name))
    for c in result.crossings():
        ax.plot(c["speed_rpm"], c["frequency_hz"], "o", mfc="none", color="r", ms=8, mew=1.5)
    lo, hi = ds.attrs.get("operating_min_rad_s"), ds.attrs.get("operating_max_rad_s")
    if lo is not None and hi is not None:
        ax.axvspan(lo * RPM, hi * RPM, color="0.9", zorder=0,
                   label="operating range")  # fmt: skip
    fmax = _fmax(fmax, f, 1.1)
    ax.set_ylim(0, fmax)
    ax.set_xlim(rpm[0], rpm[-1])
    ax.set_xlabel("input speed (rpm)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(f"Campbell diagram: {ds.attrs.get('title', '')}", fontsize=9)
    _finish(ax, components, ds["order"].values, rpm, fmax)
    return fig


def plot_complex_campbell(
    result: ComplexCampbellResult,
    components: Sequence[ComponentModes] | Sequence[Mapping[str, Any]] = (),
    *,
    fmax: float | None = None,
) -> Figure:
    """Damped natural frequencies against speed, split by whirl.

    Forward whirl as up-triangles, backward as down-triangles, unstable points as red
    crosses; excitation lines (dashed, labelled at the right end); crossings circled;
    the operating range shaded.

    Parameters
    ----------
    result : ComplexCampbellResult
    components : sequence of ComponentModes, optional
        Gear-body modes, drawn as horizontal lines with their crossings of the excitation
        lines (as in :func:`plot_campbell`).
    fmax : float, optional
        Top of the frequency axis (Hz); default 1.1 x the highest damped frequency.
    """
    from matplotlib.figure import Figure

    ds = result.data
    fig = Figure(figsize=(9.5 if components else 7.5, 5.0), layout="constrained")
    ax = fig.subplots()
    rpm = ds["speed"].values * RPM
    f = ds["frequency"].values
    w = ds["whirl"].values
    st = ds["stable"].values
    R = np.repeat(rpm[:, None], f.shape[1], axis=1)
    for label, (mk, col) in WHIRL_MARKS.items():
        sel = (w == label) & st
        if sel.any():
            ax.plot(R[sel], f[sel], mk, color=col, ms=3, label=label)
    if (~st).any():
        ax.plot(R[~st], f[~st], "x", color="red", ms=6, label="unstable")
    for k, name in enumerate(ds["excitation"].values):
        ax.plot(rpm, ds["excitation_frequency"].values[:, k], "--", lw=0.8, color="0.5")
        ax.annotate(str(name), (rpm[-1], ds["excitation_frequency"].values[-1, k]),
                    fontsize=6, color="0.4")  # fmt: skip
    if ds.sizes["crossing"]:
        ax.plot(ds["crossing_speed"].values * RPM, ds["crossing_frequency"].values,
                "o", mfc="none", color="k", ms=7, label="crossing")  # fmt: skip
    lo, hi = ds.attrs["operating_min_rad_s"], ds.attrs["operating_max_rad_s"]
    if hi > lo:
        ax.axvspan(lo * RPM, hi * RPM, color="0.9", zorder=0)
    fmax = _fmax(fmax, f, 1.1)
    ax.set_ylim(0, fmax)
    ax.set_xlabel("input speed (rpm)")
    ax.set_ylabel("damped natural frequency (Hz)")
    ax.set_title(f"complex Campbell diagram: {ds.attrs.get('title', '')}", fontsize=9)
    _finish(ax, components, ds["order"].values, rpm, fmax)
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
        check has components, else 1.1 x the highest natural frequency.
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
    """Interactive Campbell diagram (plotly): branches, excitation lines, crossings, range.

    Parameters
    ----------
    result : CampbellResult or ComplexCampbellResult
        The diagram (a resonance verdict's :attr:`~reducerlab.analysis.resonance.
        ResonanceResult.campbell`); the whirl of a complex diagram in the hover text, its
        unstable points as red crosses.
    check : mapping, optional
        A resonance verdict: its crossings in the operating range are circled (red when
        their excitation drives the mode, grey when not: ``excited``) and its gear-body
        modes drawn as dotted horizontal lines.

    Returns
    -------
    plotly.graph_objects.Figure
    """
    import plotly.graph_objects as go

    check = check if check is not None else {}
    ds = result.data
    rpm = ds["speed"].values * RPM
    fig = go.Figure()
    lo, hi = ds.attrs["operating_min_rad_s"] * RPM, ds.attrs["operating_max_rad_s"] * RPM
    if hi > 0:
        fig.add_vrect(
            x0=lo,
            x1=max(hi, lo + 1e-9),
            fillcolor="rgba(60,120,200,0.12)",
            line_width=0,
            annotation_text="operating range",
        )
    whirl = ds["whirl"].values if "whirl" in ds else None
    stable = ds["stable"].values if "stable" in ds else None
    for j, m in enumerate(ds["mode"].values):
        f = ds["frequency"].values[:, j]
        if np.all(np.nan_to_num(f) == 0):
            continue
        text = None if whirl is None else [str(w) for w in whirl[:, j]]
        name = f"mode {int(m)}"
        if text:  # whirl at the top speed (hover: at each speed; branches may swap)
            name += f" ({text[-1]} at top speed)"
        fig.add_trace(
            go.Scatter(
                x=rpm,
                y=f,
                mode="lines",
                name=name,
                text=text,
                hovertemplate="%{x:.0f} rpm, %{y:.5g} Hz"
                + (" %{text}" if text else "")
                + "<extra>mode "
                + str(int(m))
                + "</extra>",
            )
        )
        if stable is not None and not stable[:, j].all():
            bad = ~stable[:, j]
            fig.add_trace(
                go.Scatter(
                    x=rpm[bad],
                    y=f[bad],
                    mode="markers",
                    showlegend=False,
                    marker=dict(color="red", symbol="x", size=7),
                    name=f"mode {int(m)} unstable",
                )
            )
    for k, e in enumerate(ds["excitation"].values):
        fig.add_trace(
            go.Scatter(
                x=rpm,
                y=ds["excitation_frequency"].values[:, k],
                mode="lines",
                line=dict(dash="dash", color="gray", width=1),
                name=str(e),
                hovertemplate=str(e) + ": %{y:.5g} Hz<extra></extra>",
            )
        )
    for comp in check.get("components", ()):
        for f in comp["frequencies"]:
            fig.add_hline(y=f, line=dict(color="darkorange", width=1, dash="dot"))
        fig.add_trace(
            go.Scatter(
                x=[rpm[0]],
                y=[comp["frequencies"][0]],
                mode="lines",
                line=dict(color="darkorange", dash="dot"),
                name=f"{comp['label']} body modes",
            )
        )
    crossings = check.get("crossings", [])
    kinds = ((True, "crimson", "crossings in range"),
             (False, "gray", "crossings not driven (mesh strain, whirl)"))  # fmt: skip
    for driven, color, label in kinds:
        cr = [c for c in crossings if c.get("excited", True) == driven]
        if not cr:
            continue
        fig.add_trace(
            go.Scatter(
                x=[c["speed_rpm"] for c in cr],
                y=[c["frequency_hz"] for c in cr],
                mode="markers",
                marker=dict(color=color, size=10, symbol="circle-open", line=dict(width=2)),
                name=label,
                text=[f"mode {c['mode']} x {c['excitation']}" + _share_text(c) for c in cr],
                hovertemplate="%{text}<br>%{x:.5g} rpm, %{y:.5g} Hz<extra></extra>",
            )
        )
    top = float(np.nanmax(ds["frequency"].values)) if ds["frequency"].size else 1.0
    fig.update_layout(
        xaxis_title="input speed (rpm)",
        yaxis_title="frequency (Hz)",
        yaxis_range=[0, 1.05 * top],
        height=520,
        template="plotly_white",
        margin=dict(t=30, l=60, r=20, b=50),
    )
    return fig


def _share_text(row: Mapping[str, Any]) -> str:
    """``", mesh strain 3.05 %"`` or ``", forward whirl 0 %"`` of a crossing row."""
    if row.get("mesh_share") is not None:
        return f", mesh strain {100 * row['mesh_share']:.3g} %"
    if row.get("forward_share") is not None:
        return f", forward whirl {100 * row['forward_share']:.3g} %"
    return ""
