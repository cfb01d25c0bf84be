"""Figures of parameter sweeps (natural frequencies over one or two parameters)."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..analysis.sweep import SweepResult

__all__ = ["plot_sweep"]


def plot_sweep(result: SweepResult) -> Figure:
    """1-D: one line per tracked mode, veerings (o) and crossings (x) marked.
    2-D: maps of the first natural frequencies over the grid."""
    from matplotlib.figure import Figure

    ds = result.data
    paths = result.parameters
    relative = json.loads(ds.attrs.get("relative", "[]")) or [False] * len(paths)
    if len(paths) == 1:
        fig = Figure(figsize=(7.5, 4.5), layout="constrained")
        ax = fig.subplots()
        p = ds["p0"].values
        base = ds["p0"].attrs.get("design_value", 1.0)
        x = 100 * p / base if relative[0] and base else p
        var = "tracked_frequency" if "tracked_frequency" in ds else "frequency"
        f = ds[var].values
        for j in range(f.shape[1]):
            ax.plot(x, f[:, j], lw=1.4, label=f"track {j + 1}" if var != "frequency" else None)
        for e in result.events():
            xe = 100 * e["param"] / base if relative[0] and base else e["param"]
            i0, i1 = e["modes"][0] - 1, e["modes"][1] - 1
            k = int(np.argmin(np.abs(p - e["param"])))
            fe = 0.5 * (ds["frequency"].values[k, i0] + ds["frequency"].values[k, i1])
            ax.plot(xe, fe, "o" if e["kind"] == "veering" else "x", ms=9, mfc="none", mew=1.8,
                    color="k")  # fmt: skip
        if ds["p0"].attrs.get("scale") == "log":
            ax.set_xscale("log")
        ax.set_xlabel(f"{paths[0]} ({'% of design' if relative[0] else 'SI'})")
        ax.set_ylabel("natural frequency (Hz)")
        ax.set_title(f"{ds.attrs.get('title', '')}\n(o veering, x crossing)", fontsize=9)
        ax.grid(alpha=0.3)
        if f.shape[1] <= 12 and var != "frequency":
            ax.legend(fontsize=7, ncol=2)
        return fig
    n = min(ds.sizes["mode"], 6)
    fig = Figure(figsize=(3.6 * min(n, 3), 3.0 * ((n + 2) // 3)), layout="constrained")
    axes = np.atleast_1d(fig.subplots((n + 2) // 3, min(n, 3), squeeze=False)).ravel()
    for j, ax in enumerate(axes[:n]):
        im = ax.pcolormesh(ds["p1"].values, ds["p0"].values, ds["frequency"].values[:, :, j])
        ax.set_title(f"mode {j + 1} (Hz)", fontsize=8)
        ax.set_xlabel(paths[1], fontsize=7)
        ax.set_ylabel(paths[0], fontsize=7)
        fig.colorbar(im, ax=ax)
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig
