"""Figure of a Monte-Carlo over tolerances
(:class:`~reducerlab.analysis.tolerances.TolerancesResult`): for each quantity (lost
motion, backlash, transmission error peak to peak) a histogram of the samples over their
empirical CDF, the mean and the 95th percentile marked. A plain
:class:`matplotlib.figure.Figure` (no pyplot, Agg-safe); SI in the dataset, catalogue
units (arcmin, arcsec) on the axes."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .axes import plain_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_tolerances"]


def plot_tolerances(result: Any) -> Figure:
    """Histogram (top) and empirical CDF (bottom) of each quantity, mean and p95 marked."""
    from matplotlib.figure import Figure

    qs = result.quantities()
    a = result.data.attrs
    fig = Figure(figsize=(4.2 * len(qs), 6.0), layout="constrained")
    axes = np.asarray(fig.subplots(2, len(qs), squeeze=False))
    for j, (name, label, unit, per) in enumerate(qs):
        x = result.values(name) / per
        mean, p95 = a[f"{name}_mean"] / per, a[f"{name}_p95"] / per
        top, bottom = axes[0, j], axes[1, j]
        span = float(np.ptp(x))
        bins = min(50, max(5, int(np.sqrt(x.size)))) if span > 0 else 1
        top.hist(x, bins=bins, color="0.7", edgecolor="0.4")
        xs = np.sort(x)
        bottom.step(xs, np.arange(1, xs.size + 1) / xs.size, where="post", color="k")
        for ax in (top, bottom):
            ax.axvline(mean, color="C0", ls="-", label=f"mean {mean:.4g} {unit}")
            ax.axvline(p95, color="C3", ls="--", label=f"p95 {p95:.4g} {unit}")
        bottom.axhline(0.95, color="C3", lw=0.6, ls=":")
        top.set_title(label, fontsize="medium")
        top.set_ylabel("samples")
        bottom.set_xlim(top.get_xlim())  # one value axis per column
        bottom.legend(fontsize="small", loc="lower right")  # under the rising CDF: free
        if span == 0:  # every sample the same: no spread to draw
            top.text(0.5, 0.5, f"every sample {x[0]:.4g} {unit}:\nno toleranced field "
                     "changes it", transform=top.transAxes, ha="center", va="center",
                     fontsize="small", color="0.3",
                     bbox={"facecolor": "white", "edgecolor": "none"})  # fmt: skip
        bottom.set_xlabel(f"{label} ({unit})")
        bottom.set_ylabel("fraction of samples below")
        bottom.set_ylim(0, 1.02)
    fig.suptitle(f"Monte-Carlo over tolerances: {a['samples']} samples, seed {a['seed']}")
    return plain_figure(fig)
