"""Figures of parameter sweeps (natural frequencies over one or two parameters)."""

from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any

import numpy as np

from .axes import parameter_axis, plain_axes

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from numpy.typing import NDArray

    from ..analysis.sweep import SweepResult

__all__ = ["plot_sweep"]


def plot_sweep(result: SweepResult) -> Figure:
    """Natural frequencies over the swept parameters.

    Parameters
    ----------
    result : SweepResult
        The sweep to draw.

    Returns
    -------
    matplotlib.figure.Figure
        1-D: one line per tracked mode against the parameter, veerings (o) and crossings
        (x) marked; 2-D: maps of the first six natural frequencies over the grid. The
        parameter axes are labelled with their unit (N/m, kg, kg·m², rpm, ..., with an
        SI prefix where it shortens the numbers; % of design for a relative sweep), the
        tick labels plain numbers.
    """
    from matplotlib.figure import Figure

    ds = result.data
    paths = result.parameters
    relative = json.loads(ds.attrs.get("relative", "[]")) or [False] * len(paths)
    if len(paths) == 1:
        fig = Figure(figsize=(7.5, 4.5), layout="constrained")
        ax = fig.subplots()
        p = ds["p0"].values
        base = ds["p0"].attrs.get("design_value", 1.0)
        x, label = _axis(ds["p0"], paths[0], relative[0])
        nz = np.flatnonzero(p)
        shown = float(x[nz[0]] / p[nz[0]]) if nz.size else 1.0  # the display factor
        var = "tracked_frequency" if "tracked_frequency" in ds else "frequency"
        f = ds[var].values
        for j in range(f.shape[1]):
            ax.plot(x, f[:, j], lw=1.4, label=f"track {j + 1}" if var != "frequency" else None)
        for e in result.events():
            xe = 100 * e["param"] / base if relative[0] and base else e["param"] * shown
            i0, i1 = e["modes"][0] - 1, e["modes"][1] - 1
            k = int(np.argmin(np.abs(p - e["param"])))
            fe = 0.5 * (ds["frequency"].values[k, i0] + ds["frequency"].values[k, i1])
            ax.plot(xe, fe, "o" if e["kind"] == "veering" else "x", ms=9, mfc="none", mew=1.8,
                    color="k")  # fmt: skip
        if ds["p0"].attrs.get("scale") == "log":
            ax.set_xscale("log")
        plain_axes(ax)
        ax.set_xlabel(label)
        ax.set_ylabel("natural frequency (Hz)")
        ax.set_title(f"{ds.attrs.get('title', '')}\n(o veering, x crossing)", fontsize=9)
        ax.grid(alpha=0.3)
        if f.shape[1] <= 12 and var != "frequency":
            ax.legend(fontsize=7, ncol=2)
        return fig
    n = min(ds.sizes["mode"], 6)
    fig = Figure(figsize=(3.6 * min(n, 3), 3.0 * ((n + 2) // 3)), layout="constrained")
    axes = np.atleast_1d(fig.subplots((n + 2) // 3, min(n, 3), squeeze=False)).ravel()
    y, ylabel = _axis(ds["p0"], paths[0], relative[0])
    x, xlabel = _axis(ds["p1"], paths[1], relative[1])
    for j, ax in enumerate(axes[:n]):
        im = ax.pcolormesh(x, y, ds["frequency"].values[:, :, j])
        ax.set_title(f"mode {j + 1} (Hz)", fontsize=8)
        ax.set_xlabel(xlabel, fontsize=7)
        ax.set_ylabel(ylabel, fontsize=7)
        plain_axes(ax, xbins=4, ybins=4)
        fig.colorbar(im, ax=ax)
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig


def _axis(coord: Any, path: str, relative: bool) -> tuple[NDArray, str]:
    """A swept parameter's values and label: % of the design value for a relative sweep,
    else in its unit (:func:`reducerlab.plot.axes.parameter_axis`); a sweep saved before
    the coordinates carried their unit says SI."""
    p = np.asarray(coord.values, dtype=float)
    base = coord.attrs.get("design_value", 1.0)
    if relative and base:
        return 100 * p / base, f"{path} (% of design)"
    if "display_unit" not in coord.attrs:
        return p, f"{path} (SI)"
    return parameter_axis(coord, path)
