"""Figures of modal results: mode-shape bar charts, energy maps, sensitivity maps."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ReducerlabError

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from ..analysis.modal import ModalResult, SensitivityResult

__all__ = ["plot_energy", "plot_mode_shapes", "plot_sensitivity"]


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
