"""Figures of modal results: mode-shape bar charts, energy maps, sensitivity maps, complex
modes, and the report's interactive (plotly) mode shapes and sensitivity map; plotly is
imported only when its figure is built."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ReducerlabError
from ..units import RPM
from .axes import plain_axis, scaled_unit

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from ..analysis.complex_modal import ComplexModalResult
    from ..analysis.modal import ModalResult, SensitivityResult

__all__ = [
    "SCALES",
    "energy_columns",
    "plot_complex_modes",
    "plot_energy",
    "plot_mode_shapes",
    "plot_sensitivity",
    "plotly_mode_shapes",
    "plotly_sensitivity",
    "shape_bars",
]


def _figure(**kw: object) -> Figure:
    from matplotlib.figure import Figure

    return Figure(**kw)  # no pyplot: no global state, works headless


def _mode_labels(ds: xr.Dataset) -> list[str]:
    """``"<mode>: <frequency> Hz"`` for every mode of a modal dataset."""
    modes, freqs = ds["mode"].values, ds["frequency"].values
    return [f"{int(m)}: {f:.4g} Hz" for m, f in zip(modes, freqs, strict=True)]


#: DOF kinds drawn on the translation axis (m) and on the rotation axis (rad).
TRANSLATIONS = ("x", "y", "z", "u")
ROTATIONS = ("rx", "ry", "rz")
#: What each bar scale draws, stated on the axes and in the title.
SCALES = {
    "mass": "mass-normalised shape, φᵀMφ = 1 (modal.nc 'shape')",
    "energy": "signed √(kinetic-energy share), largest 1",
    "max": "max-normalised shape, largest component 1",
}


def shape_bars(
    result: ModalResult, scale: str = "mass"
) -> tuple[np.ndarray, list[tuple[str, list[int], str]]]:
    """The bar heights of every mode and the DOF groups they are drawn in.

    Parameters
    ----------
    result : ModalResult
    scale : {"mass", "energy", "max"}
        ``"mass"`` (default): the mass-normalised shape (``φᵀMφ = 1``), each DOF in its
        unit (m: x, y, z and ``u = r θ``; rad: rx, ry, rz); ``"energy"``:
        ``sign(φ_i) √(kinetic share_i)``, the largest 1; ``"max"``: the max-normalised
        shape.

    Returns
    -------
    bars : ndarray, shape (dof, mode)
    groups : list of (name, DOF indices, axis label)
        The translations and the rotations, those the model has.
    """
    if scale not in SCALES:
        raise ReducerlabError(f"scale must be one of {', '.join(map(repr, SCALES))}, got {scale!r}")
    ds = result.data
    if scale == "energy":
        ke = np.clip(ds["kinetic_energy"].values.T, 0.0, None)  # (dof, mode)
        bars = np.sign(ds["shape"].values) * np.sqrt(ke)
        bars = bars / np.max(np.abs(bars), axis=0)
    elif scale == "max":
        bars = ds["shape_max"].values
    else:
        bars = ds["shape"].values
    # round-off (1e-16 of the mode's largest component) drawn as nothing, not magnified
    # to a full axis
    bars = np.where(np.abs(bars) <= 1e-9 * np.max(np.abs(bars), axis=0), 0.0, bars)
    kinds = [str(k) for k in ds["kind"].values]
    unit = {"mass": (" (m)", " (rad)"), "energy": ("", ""), "max": ("", "")}[scale]
    groups = [
        (
            "translation",
            [i for i, k in enumerate(kinds) if k in TRANSLATIONS],
            "x, y, z, u = rθ" + unit[0],
        ),
        ("rotation", [i for i, k in enumerate(kinds) if k in ROTATIONS], "rx, ry, rz" + unit[1]),
    ]
    return bars, [g for g in groups if g[1]]


def plot_mode_shapes(
    result: ModalResult, modes: Sequence[int] | None = None, *, scale: str = "mass"
) -> Figure:
    """One panel per mode: a bar per DOF, coloured by body, translations (m) and
    rotations (rad) on separate axes (see :func:`shape_bars` for ``scale``).

    Parameters
    ----------
    result : ModalResult
    modes : sequence of int, optional
        1-based mode numbers; all modes by default.
    scale : {"mass", "energy", "max"}
        What the bars show, stated in the title: the mass-normalised shape (default,
        as the report's interactive chart), the signed root of the kinetic-energy
        shares, or the max-normalised shape.
    """
    bars, groups = shape_bars(result, scale)
    ds = result.data
    all_modes = [int(m) for m in ds["mode"].values]
    modes = list(modes) if modes is not None else all_modes
    bad = [m for m in modes if m not in all_modes]
    if bad:
        raise ReducerlabError(f"modes {bad} do not exist; the result has modes 1..{len(all_modes)}")
    ncol = min(3, len(modes))
    nrow = math.ceil(len(modes) / ncol)
    fig = _figure(
        figsize=(4.2 * ncol, (1.5 + 1.3 * len(groups)) * nrow + 0.6), layout="constrained"
    )
    panels = np.atleast_1d(fig.subfigures(nrow, ncol, squeeze=False)).ravel()
    bodies = [str(b) for b in ds["body"].values]
    unique = list(dict.fromkeys(bodies))
    import matplotlib as mpl

    cmap = mpl.colormaps["tab10"]
    colours = [cmap(unique.index(b) % 10) for b in bodies]
    labels = [f"{b}.{k}" for b, k in zip(bodies, ds["kind"].values, strict=True)]
    for panel, m in zip(panels, modes, strict=False):
        j = all_modes.index(m)
        axes = np.atleast_1d(panel.subplots(len(groups), 1))
        for ax, (name, idx, ylabel) in zip(axes, groups, strict=True):
            h = bars[idx, j]
            if scale == "mass":  # shown with the prefix that keeps the numbers short
                factor, unit = scaled_unit(h, "m" if name == "translation" else "rad")
                h = factor * h
                ylabel = ylabel.rsplit(" (", 1)[0] + f" ({unit})"
            x = np.arange(len(idx))
            ax.bar(x, h, color=[colours[i] for i in idx])
            ax.axhline(0.0, color="0.3", lw=0.6)
            ax.set_xticks(x, [labels[i] for i in idx], rotation=90, fontsize=7)
            top = float(np.max(np.abs(h))) if np.any(h) else 1.0
            ax.set_ylim(-1.15 * top, 1.15 * top)
            ax.set_ylabel(ylabel, fontsize=7)
            ax.tick_params(axis="y", labelsize=7)
            plain_axis(ax.yaxis)
            ax.grid(axis="y", alpha=0.3)
        f = float(ds["frequency"].values[j])
        panel.suptitle(f"mode {m}: {f:.5g} Hz\n{ds['classification'].values[j]}", fontsize=8)
    for panel in panels[len(modes) :]:
        panel.set_visible(False)
    handles = [mpl.patches.Patch(color=cmap(i % 10), label=b) for i, b in enumerate(unique)]
    fig.legend(handles=handles, loc="outside lower center", ncol=len(unique), fontsize=8)
    fig.suptitle(f"{ds.attrs.get('title', '')}: {SCALES[scale]}", fontsize=10)
    return fig


#: Widest figure (in) that the report shows at its size (1132 px at 110 dpi): text of
#: ``TEXT`` pt stays that size in the report.
REPORT_WIDTH = 10.2
#: Smallest text (pt) of the heat maps.
TEXT = 9.0


def text_colour(rgba: Sequence[float]) -> str:
    """Black or white, whichever reads on a cell of colour ``rgba`` (its relative
    luminance, WCAG: white below 0.4)."""
    lin = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in rgba[:3]]
    lum = 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]
    return "white" if lum < 0.4 else "black"


def _annotate(
    ax: Any, im: Any, data: np.ndarray, label: Callable[[float], str | None], size: float
) -> None:
    """Write each cell's ``label(value)`` (None: nothing) in the colour that reads on it."""
    for (r, c), v in np.ndenumerate(data):
        text = label(v) if np.isfinite(v) else None
        if text is not None:
            colour = text_colour(im.cmap(im.norm(v)))
            ax.text(c, r, text, ha="center", va="center", fontsize=size, color=colour)


#: The narrowest heat-map column (in) whose cells still carry their number at TEXT pt,
#: and the narrowest that still takes a tick label.
CELL_TEXT_WIDTH = 0.3
TICK_WIDTH = 0.17
#: Left over beside the heat maps (in): mode labels, colour bar.
MAP_MARGIN = 2.4
#: The most columns a heat map draws at :data:`REPORT_WIDTH` with TEXT-pt tick labels.
MAX_COLUMNS = int((REPORT_WIDTH - MAP_MARGIN) / TICK_WIDTH)


def energy_columns(
    result: ModalResult,
) -> tuple[np.ndarray, list[str], np.ndarray, list[str], list[str]]:
    """The columns of the energy maps: kinetic-energy shares per (body, DOF family), per
    body where those are more than :data:`MAX_COLUMNS`; strain-energy shares per element
    that takes 0.5 % of some mode; in each, the smallest columns beyond
    :data:`MAX_COLUMNS` summed as "other DOFs" or "other elements".

    Returns
    -------
    kinetic : ndarray (mode, column), its labels; strain : ndarray (mode, column), its
    labels; the elements left out (under 0.5 % in every mode).
    """
    ds = result.data
    bodies = [str(b) for b in ds["body"].values]
    fams = [str(f) for f in ds["family"].values]
    keys = list(zip(bodies, fams, strict=True))
    if len(dict.fromkeys(keys)) > MAX_COLUMNS:
        keys = [(b, "") for b in bodies]
    cells = list(dict.fromkeys(keys))
    ke = ds["kinetic_energy"].values  # (mode, dof)
    kinetic = np.zeros((ke.shape[0], len(cells)))
    for i, key in enumerate(keys):
        kinetic[:, cells.index(key)] += ke[:, i]
    labels = [f"{b}\n{f}" if f else b for b, f in cells]
    kinetic, labels = _top_columns(kinetic, labels, "DOFs")
    ee = np.nan_to_num(ds["element_energy"].values)
    elements = [str(e) for e in ds["element"].values]
    peak = np.max(np.abs(ee), axis=0) if ee.size else np.zeros(len(elements))
    kept = [j for j in range(len(elements)) if peak[j] >= 0.005]
    dropped = [elements[j] for j in range(len(elements)) if peak[j] < 0.005]
    strain, names = _top_columns(ee[:, kept], [elements[j] for j in kept], "elements")
    return kinetic, labels, strain, names, dropped


def _top_columns(data: np.ndarray, labels: list[str], what: str) -> tuple[np.ndarray, list]:
    """At most :data:`MAX_COLUMNS` columns: the largest shares in their order, the
    rest summed in a last column "other WHAT (n)"."""
    if len(labels) <= MAX_COLUMNS:
        return data, labels
    order = np.argsort(-np.max(np.abs(data), axis=0), kind="stable")
    top = sorted(order[: MAX_COLUMNS - 1])
    rest = order[MAX_COLUMNS - 1 :]
    out = np.column_stack([data[:, top], data[:, rest].sum(axis=1)])
    return out, [labels[j] for j in top] + [f"other {what} ({len(rest)})"]


def plot_energy(result: ModalResult) -> Figure:
    """Heat maps of kinetic-energy share per (body, DOF family) (top) and strain-energy
    share per element (below), for every mode (columns: :func:`energy_columns`), shares
    of 5 % and more written in per cent where a column is :data:`CELL_TEXT_WIDTH` wide
    (else read on the colour bar); at most :data:`REPORT_WIDTH` wide, all text
    :data:`TEXT` pt or more."""
    import textwrap

    ds = result.data
    kinetic, kin_labels, strain, elements, dropped = energy_columns(result)
    ncol = max(kinetic.shape[1], len(elements), 1)
    rows = kinetic.shape[0]
    width = min(REPORT_WIDTH, max(6.0, MAP_MARGIN + 0.5 * ncol))
    cell_text = (width - MAP_MARGIN) / ncol >= CELL_TEXT_WIDTH
    foot = ""
    if dropped:
        foot = f"elements under 0.5 % strain energy in every mode: {', '.join(dropped)}"
    lines = textwrap.wrap(foot, int(width * 72 / (0.55 * TEXT)))
    height = 2.2 * 1.6 + 2 * 0.3 * rows + 0.2 * len(lines)
    fig = _figure(figsize=(width, height), layout="constrained")
    ax1, ax2 = fig.subplots(2, 1, gridspec_kw={"height_ratios": [1, 1]})
    ylabels = _mode_labels(ds)
    how = "" if cell_text else " (values on the colour bar)"
    for ax, data, xl, title in (
        (ax1, kinetic, kin_labels, "kinetic energy share (%)" + how),
        (ax2, strain, elements, "strain energy share (%)" + how),
    ):
        shown = np.nan_to_num(np.clip(data, 0, 1))
        im = ax.imshow(shown, vmin=0, vmax=1, cmap="viridis", aspect="auto")
        ax.set_xticks(np.arange(len(xl)), xl, rotation=90, fontsize=TEXT)
        ax.set_yticks(np.arange(len(ylabels)), ylabels, fontsize=TEXT)
        ax.set_title(title, fontsize=TEXT + 1)
        if cell_text:
            _annotate(ax, im, data, lambda v: f"{100 * v:.0f}" if v >= 0.05 else None, TEXT)
    fig.colorbar(im, ax=[ax1, ax2], shrink=0.6, label="share").ax.tick_params(labelsize=TEXT)
    fig.suptitle(ds.attrs.get("title", ""), fontsize=TEXT + 1)
    if lines:
        fig.supxlabel("\n".join(lines), fontsize=TEXT, ha="left", x=0.01)
    return fig


def _sensitivity_cells(result: SensitivityResult) -> tuple[np.ndarray, list[str], list[str], str]:
    """The relative sensitivities the maps draw (elastic modes x parameters that show),
    their row and column labels and the note naming what is left out."""
    ds = result.data
    cells = result.map_cells()
    rel = ds["relative"].values[np.ix_(cells.modes, cells.parameters)]
    params = [str(ds["parameter"].values[j]) for j in cells.parameters]
    modes = [
        f"{int(ds['mode'].values[i])}: {float(ds['frequency'].values[i]):.5g} Hz"
        for i in cells.modes
    ]
    return rel, modes, params, cells.note()


def plot_sensitivity(result: SensitivityResult) -> Figure:
    """Heat map of relative sensitivities ``(p/f) df/dp`` (elastic mode x parameter),
    each value of at least 0.005 written in black or white by its cell's luminance;
    rigid-body modes and parameters under 0.005 on every mode left out and named below
    the map (:meth:`SensitivityResult.map_cells`); text of :data:`TEXT` pt."""
    import textwrap

    rel, modes, params, left_out = _sensitivity_cells(result)
    width = min(REPORT_WIDTH, max(6.0, 3.2 + 0.75 * len(params)))
    lines = textwrap.wrap(left_out, int(width * 72 / (0.55 * TEXT)))
    longest = max((len(p) for p in params), default=4)
    height = 1.0 + 0.32 * max(len(modes), 1) + 0.075 * longest + 0.2 * len(lines)
    fig = _figure(figsize=(width, height), layout="constrained")
    ax = fig.subplots()
    if not modes or not params:
        ax.set_axis_off()
        ax.text(0.5, 0.5, "no elastic mode moves by 0.5 %", ha="center", transform=ax.transAxes)
    else:
        lim = float(np.max(np.abs(rel)))
        im = ax.imshow(rel, cmap="RdBu_r", vmin=-lim, vmax=lim, aspect="auto")
        ax.set_xticks(np.arange(len(params)), params, rotation=90, fontsize=TEXT)
        ax.set_yticks(np.arange(len(modes)), modes, fontsize=TEXT)
        _annotate(ax, im, rel, lambda v: f"{v:.2f}" if abs(v) >= 0.005 else None, TEXT)
        bar = fig.colorbar(im, ax=ax, label="(p/f) df/dp")
        bar.ax.tick_params(labelsize=TEXT)
    ax.set_title("relative frequency sensitivity (p/f) df/dp", fontsize=TEXT + 1)
    if lines:
        fig.get_layout_engine().set(h_pad=0.1)
        fig.supxlabel("\n".join(lines), fontsize=TEXT, ha="left", x=0.01)
    return fig


def plot_complex_modes(result: ComplexModalResult) -> Figure:
    """Damped frequencies (marker by whirl) and damping ratios of every complex mode;
    unstable modes crossed in red.

    Parameters
    ----------
    result : ComplexModalResult
    """
    ds = result.data
    fig = _figure(figsize=(7.0, 4.2), layout="constrained")
    a1, a2 = fig.subplots(2, 1, sharex=True)
    modes = ds["mode"].values
    marks = {
        "forward": ("^", "C0"),
        "backward": ("v", "C3"),
        "planar": ("o", "C2"),
        "rigid": ("s", "k"),
    }
    for w in sorted(set(ds["whirl"].values.tolist())):
        sel = ds["whirl"].values == w
        mk, col = marks.get(w, ("d", "C7"))
        a1.plot(modes[sel], ds["frequency"].values[sel], mk, color=col, label=w)
        a2.plot(modes[sel], ds["damping_ratio"].values[sel], mk, color=col)
    bad = ~ds["stable"].values
    if bad.any():
        a1.plot(modes[bad], ds["frequency"].values[bad], "x", color="red", ms=10, label="unstable")
    a1.set_ylabel("damped frequency (Hz)")
    a2.set_ylabel("damping ratio")
    a2.set_xlabel("mode")
    a1.legend(fontsize=7)
    rpm = ds.attrs["speed_rad_s"] * RPM
    a1.set_title(f"complex modes: {ds.attrs.get('title', '')} at {rpm:.6g} rpm", fontsize=9)
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    return fig


def plotly_mode_shapes(result: ModalResult, scale: str = "mass") -> Any:
    """Interactive bar chart (plotly) of the mode shapes, one mode per menu entry,
    translations (m) and rotations (rad) on separate axes, scaled as
    :func:`plot_mode_shapes` (:func:`shape_bars`).

    Parameters
    ----------
    result : ModalResult
    scale : {"mass", "energy", "max"}

    Returns
    -------
    plotly.graph_objects.Figure
        One trace per (mode, DOF group), the first elastic mode's visible.
    """
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    bars, groups = shape_bars(result, scale)
    ds = result.data
    dofs = [str(d) for d in ds["dof"].values]
    fig = make_subplots(rows=len(groups), cols=1, vertical_spacing=0.22)
    bodies = [str(b) for b in ds["body"].values]
    unique = list(dict.fromkeys(bodies))
    tab10 = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
             "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf")  # fmt: skip
    colours = [tab10[unique.index(b) % 10] for b in bodies]
    n = bars.shape[1]
    first = next((j for j in range(n) if not ds["rigid"].values[j]), 0)
    labels = []
    for j in range(n):
        f = float(ds["frequency"].values[j])
        labels.append(f"mode {j + 1}: {f:.5g} Hz ({ds['classification'].values[j]})")
        for row, (name, idx, _) in enumerate(groups, start=1):
            values = [float(f"{v:.4g}") for v in bars[idx, j]]
            fig.add_trace(
                go.Bar(
                    x=[dofs[i] for i in idx],
                    y=values,
                    name=f"mode {j + 1} {name}",
                    marker_color=[colours[i] for i in idx],
                    visible=j == first,
                    hovertemplate="%{x}: %{y:.4g}<extra></extra>",
                ),
                row=row,
                col=1,
            )
    per = len(groups)
    buttons = [
        dict(
            label=labels[j],
            method="update",
            args=[{"visible": [k // per == j for k in range(n * per)]}, {"title.text": labels[j]}],
        )
        for j in range(n)
    ]
    for row, (_, _, ylabel) in enumerate(groups, start=1):
        fig.update_yaxes(title_text=ylabel, exponentformat="power", row=row, col=1)
    fig.update_layout(
        updatemenus=[
            dict(buttons=buttons, direction="down", x=0, xanchor="left", y=1.22, active=first)
        ],
        title=dict(text=labels[first], x=0.5, y=0.97, font=dict(size=13)),
        annotations=[
            dict(
                text=SCALES[scale],
                xref="paper",
                yref="paper",
                x=1,
                y=1.08,
                xanchor="right",
                showarrow=False,
                font=dict(size=11),
            )
        ],
        height=260 + 170 * len(groups),
        margin=dict(t=110, l=80, r=20, b=80),
        template="plotly_white",
        showlegend=False,
    )
    return fig


def plotly_sensitivity(result: SensitivityResult) -> Any:
    """Interactive heat map (plotly) of the relative sensitivities ``(p/f) df/dp``
    (elastic mode x parameter, as :func:`plot_sensitivity`: rigid-body modes and
    parameters under 0.005 on every mode left out, :meth:`SensitivityResult.map_cells`
    names them), symmetric colour scale, values of at least 0.005 written in the cells
    (in black or white by the cell's colour); the height follows the rows, the top
    margin holds the mode bar.

    Parameters
    ----------
    result : SensitivityResult

    Returns
    -------
    plotly.graph_objects.Figure
        ``layout.meta["left_out"]``: the note naming what the map leaves out.
    """
    import plotly.graph_objects as go

    rel, modes, params, left_out = _sensitivity_cells(result)
    lim = float(np.max(np.abs(rel))) if rel.size else 1.0
    fig = go.Figure(
        go.Heatmap(
            z=rel,
            x=params,
            y=modes,
            zmin=-lim,
            zmax=lim,
            colorscale="RdBu_r",
            colorbar=dict(title="(p/f) df/dp", len=1.0, lenmode="fraction"),
            # plotly writes cell text black or white by the cell's colour (auto colour)
            text=[[f"{v:.2f}" if abs(v) >= 0.005 else "" for v in row] for row in rel],
            texttemplate="%{text}",
            textfont=dict(size=12),
            hovertemplate="mode %{y}<br>%{x}<br>(p/f) df/dp = %{z:.4f}<extra></extra>",
        )
    )
    # tick labels at -45 degrees: about 7 px a character of 12 px type, times sin 45
    longest = max((len(p) for p in params), default=4)
    bottom = 30 + int(7 * 0.71 * longest)
    top = 40  # the mode bar sits here, over no cell
    fig.update_layout(
        # rows of 30 px, at least 180 px of them (room for the colour bar's ticks)
        height=top + bottom + max(180, 30 * len(modes)),
        template="plotly_white",
        font=dict(size=12),
        margin=dict(t=top, l=110, r=20, b=bottom),
        xaxis=dict(tickangle=-45, automargin=True),
        yaxis=dict(autorange="reversed", automargin=True),
        meta={"left_out": left_out},
    )
    return fig
