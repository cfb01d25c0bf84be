"""Figures of modal results: mode-shape bar charts, energy maps, sensitivity maps, complex
modes, and the report's interactive (plotly) mode shapes and sensitivity map; plotly is
imported only when its figure is built."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ReducerlabError
from ..units import RPM

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from ..analysis.complex_modal import ComplexModalResult
    from ..analysis.modal import ModalResult, SensitivityResult

__all__ = [
    "plot_complex_modes",
    "plot_energy",
    "plot_mode_shapes",
    "plot_sensitivity",
    "plotly_mode_shapes",
    "plotly_sensitivity",
]


def _figure(**kw: object) -> Figure:
    from matplotlib.figure import Figure

    return Figure(**kw)  # no pyplot: no global state, works headless


def _mode_labels(ds: xr.Dataset) -> list[str]:
    """``"<mode>: <frequency> Hz"`` for every mode of a modal dataset."""
    modes, freqs = ds["mode"].values, ds["frequency"].values
    return [f"{int(m)}: {f:.4g} Hz" for m, f in zip(modes, freqs, strict=True)]


def plot_mode_shapes(
    result: ModalResult, modes: Sequence[int] | None = None, *, scale: str = "energy"
) -> Figure:
    """One panel per mode: a bar per DOF, coloured by body (the papers' mode-shape plots).

    Parameters
    ----------
    result : ModalResult
    modes : sequence of int, optional
        1-based mode numbers; all modes by default.
    scale : {"energy", "max"}
        ``"energy"`` (default) draws ``sign(phi_i) sqrt(kinetic share_i)``, which puts
        translations (m) and rotations (rad) on one comparable scale; ``"max"`` draws
        the max-normalised shape in each DOF's own unit, as the papers do.
    """
    if scale not in ("energy", "max"):
        raise ReducerlabError(f"scale must be 'energy' or 'max', got {scale!r}")
    ds = result.data
    all_modes = [int(m) for m in ds["mode"].values]
    modes = list(modes) if modes is not None else all_modes
    bad = [m for m in modes if m not in all_modes]
    if bad:
        raise ReducerlabError(f"modes {bad} do not exist; the result has modes 1..{len(all_modes)}")
    ncol = min(3, len(modes))
    nrow = math.ceil(len(modes) / ncol)
    fig = _figure(figsize=(4.2 * ncol, 2.6 * nrow + 0.4), layout="constrained")
    axes = np.atleast_1d(fig.subplots(nrow, ncol, sharey=True, squeeze=False)).ravel()
    bodies = [str(b) for b in ds["body"].values]
    unique = list(dict.fromkeys(bodies))
    import matplotlib as mpl

    cmap = mpl.colormaps["tab10"]
    colours = [cmap(unique.index(b) % 10) for b in bodies]
    labels = [f"{b}.{k}" for b, k in zip(bodies, ds["kind"].values, strict=True)]
    x = np.arange(len(labels))
    if scale == "energy":
        ke = np.clip(ds["kinetic_energy"].values.T, 0.0, None)  # (dof, mode)
        bars = np.sign(ds["shape"].values) * np.sqrt(ke)
        bars = bars / np.max(np.abs(bars), axis=0)
        ylabel = "signed sqrt(kinetic share), max 1"
    else:
        bars = ds["shape_max"].values
        ylabel = "shape (max 1)"
    for ax, m in zip(axes, modes, strict=False):
        j = all_modes.index(m)
        ax.bar(x, bars[:, j], color=colours)
        ax.axhline(0.0, color="0.3", lw=0.6)
        f = float(ds["frequency"].values[j])
        ax.set_title(f"mode {m}: {f:.5g} Hz\n{ds['classification'].values[j]}", fontsize=8)
        ax.set_xticks(x, labels, rotation=90, fontsize=7)
        ax.set_ylim(-1.1, 1.1)
        ax.grid(axis="y", alpha=0.3)
    for ax in axes[len(modes) :]:
        ax.set_visible(False)
    for ax in axes[::ncol]:
        ax.set_ylabel(ylabel, fontsize=7)
    handles = [mpl.patches.Patch(color=cmap(i % 10), label=b) for i, b in enumerate(unique)]
    fig.legend(handles=handles, loc="outside lower center", ncol=len(unique), fontsize=8)
    fig.suptitle(ds.attrs.get("title", ""), fontsize=10)
    return fig


def plot_energy(result: ModalResult) -> Figure:
    """Heat maps of kinetic-energy share per (body, DOF family) and strain-energy share
    per element, for every mode (percent annotated)."""
    ds = result.data
    bodies = [str(b) for b in ds["body"].values]
    fams = [str(f) for f in ds["family"].values]
    cells = list(dict.fromkeys(zip(bodies, fams, strict=True)))
    ke = ds["kinetic_energy"].values  # (mode, dof)
    grid = np.zeros((ke.shape[0], len(cells)))
    for i, cell in enumerate(zip(bodies, fams, strict=True)):
        grid[:, cells.index(cell)] += ke[:, i]
    ee = ds["element_energy"].values
    elements = [str(e) for e in ds["element"].values]
    fig = _figure(
        figsize=(2.0 + 0.7 * (len(cells) + len(elements)), 1.6 + 0.32 * ke.shape[0]),
        layout="constrained",
    )
    widths = [max(len(cells), 1), max(len(elements), 1)]
    ax1, ax2 = fig.subplots(1, 2, gridspec_kw={"width_ratios": widths})
    ylabels = _mode_labels(ds)
    for ax, data, xl, title in (
        (ax1, grid, [f"{b}\n{f}" for b, f in cells], "kinetic energy share"),
        (ax2, ee, elements, "strain energy share"),
    ):
        shown = np.nan_to_num(np.clip(data, 0, 1))
        im = ax.imshow(shown, vmin=0, vmax=1, cmap="viridis", aspect="auto")
        ax.set_xticks(np.arange(len(xl)), xl, rotation=90, fontsize=7)
        ax.set_yticks(np.arange(len(ylabels)), ylabels, fontsize=7)
        ax.set_title(title, fontsize=9)
        for (r, c), v in np.ndenumerate(data):
            if np.isfinite(v) and v >= 0.05:
                ax.text(
                    c,
                    r,
                    f"{100 * v:.0f}",
                    ha="center",
                    va="center",
                    fontsize=6,
                    color="w" if v < 0.6 else "k",
                )
    ax2.set_yticks([])
    fig.colorbar(im, ax=[ax1, ax2], shrink=0.8, label="share")
    fig.suptitle(ds.attrs.get("title", ""), fontsize=10)
    return fig


def plot_sensitivity(result: SensitivityResult) -> Figure:
    """Heat map of relative sensitivities ``(p/f) df/dp`` (mode x parameter)."""
    ds = result.data
    rel = ds["relative"].values
    params = [str(p) for p in ds["parameter"].values]
    fig = _figure(figsize=(2.5 + 0.9 * len(params), 1.6 + 0.3 * rel.shape[0]), layout="constrained")
    ax = fig.subplots()
    lim = float(np.nanmax(np.abs(rel))) if np.any(np.isfinite(rel)) else 1.0
    im = ax.imshow(np.nan_to_num(rel), cmap="RdBu_r", vmin=-lim, vmax=lim, aspect="auto")
    ax.set_xticks(np.arange(len(params)), params, rotation=90, fontsize=7)
    ylabels = _mode_labels(ds)
    ax.set_yticks(np.arange(len(ylabels)), ylabels, fontsize=7)
    for (r, c), v in np.ndenumerate(rel):
        if np.isfinite(v):
            ax.text(c, r, f"{v:.2f}", ha="center", va="center", fontsize=6)
    fig.colorbar(im, ax=ax, label="(p/f) df/dp")
    ax.set_title("relative frequency sensitivity", fontsize=9)
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
    marks = {"forward": ("^", "C0"), "backward": ("v", "C3"), "planar": ("o", "C2"),
             "rigid": ("s", "k")}  # fmt: skip
    for w in sorted(set(ds["whirl"].values.tolist())):
        sel = ds["whirl"].values == w
        mk, col = marks.get(w, ("d", "C7"))
        a1.plot(modes[sel], ds["frequency"].values[sel], mk, color=col, label=w)
        a2.plot(modes[sel], ds["damping_ratio"].values[sel], mk, color=col)
    bad = ~ds["stable"].values
    if bad.any():
        a1.plot(modes[bad], ds["frequency"].values[bad], "x", color="red", ms=10,
                label="unstable")  # fmt: skip
    a1.set_ylabel("damped frequency (Hz)")
    a2.set_ylabel("damping ratio")
    a2.set_xlabel("mode")
    a1.legend(fontsize=7)
    rpm = ds.attrs["speed_rad_s"] * RPM
    a1.set_title(f"complex modes: {ds.attrs.get('title', '')} at {rpm:.6g} rpm", fontsize=9)
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    return fig


def plotly_mode_shapes(result: ModalResult) -> Any:
    """Interactive bar chart (plotly) of the mass-weighted mode shapes, one mode per menu
    entry: each DOF's bar is ``sign(shape) sqrt(kinetic energy share)``, the largest 1.

    Parameters
    ----------
    result : ModalResult

    Returns
    -------
    plotly.graph_objects.Figure
    """
    import plotly.graph_objects as go

    ds = result.data
    dofs = [str(d) for d in ds["dof"].values]
    ke = ds["kinetic_energy"].values  # (mode, dof), sums to 1 per mode
    sign = np.sign(ds["shape"].values.T)
    amp = sign * np.sqrt(np.clip(ke, 0.0, None))
    fig = go.Figure()
    n = amp.shape[0]
    labels = []
    for j in range(n):
        f = float(ds["frequency"].values[j])
        cls = str(ds["classification"].values[j])
        labels.append(f"mode {j + 1}: {f:.5g} Hz ({cls})")
        a = amp[j] / max(float(np.max(np.abs(amp[j]))), 1e-300)
        fig.add_trace(
            go.Bar(
                x=dofs,
                y=a,
                name=f"mode {j + 1}",
                visible=j == min(1, n - 1),
                hovertemplate="%{x}: %{y:.3f}<extra></extra>",
            )
        )
    buttons = [
        dict(
            label=labels[j],
            method="update",
            args=[{"visible": [k == j for k in range(n)]}, {"title.text": labels[j]}],
        )
        for j in range(n)
    ]
    fig.update_layout(
        updatemenus=[
            dict(
                buttons=buttons, direction="down", x=0, xanchor="left", y=1.18, active=min(1, n - 1)
            )
        ],
        title=dict(text=labels[min(1, n - 1)], x=0.5, y=0.97, font=dict(size=13)),
        yaxis_title="mass-weighted amplitude (largest 1)",
        height=430,
        margin=dict(t=90, l=60, r=20, b=90),
        template="plotly_white",
        showlegend=False,
    )
    return fig


def plotly_sensitivity(result: SensitivityResult) -> Any:
    """Interactive heat map (plotly) of the relative sensitivities ``(p/f) df/dp``
    (mode x parameter), symmetric colour scale.

    Parameters
    ----------
    result : SensitivityResult

    Returns
    -------
    plotly.graph_objects.Figure
    """
    import plotly.graph_objects as go

    ds = result.data
    rel = ds["relative"].values
    lim = float(np.nanmax(np.abs(rel))) if np.any(np.isfinite(rel)) else 1.0
    modes = [
        f"{int(m)}: {f:.5g} Hz"
        for m, f in zip(ds["mode"].values, ds["frequency"].values, strict=True)
    ]
    fig = go.Figure(
        go.Heatmap(
            z=rel,
            x=[str(p) for p in ds["parameter"].values],
            y=modes,
            zmin=-lim,
            zmax=lim,
            colorscale="RdBu_r",
            colorbar=dict(title="(p/f) df/dp"),
            hovertemplate="mode %{y}<br>%{x}<br>(p/f) df/dp = %{z:.4f}<extra></extra>",
        )
    )
    fig.update_layout(
        height=max(320, 60 + 28 * len(modes)),
        template="plotly_white",
        margin=dict(t=20, l=120, r=20, b=160),
        yaxis_autorange="reversed",
    )
    return fig
