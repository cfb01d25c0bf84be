"""Figures of sweeps and Campbell diagrams."""

from __future__ import annotations

import json
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ReducerlabError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..analysis.campbell import CampbellResult, ComponentModes
    from ..analysis.sweep import SweepResult

__all__ = ["plot_campbell", "plot_sweep"]


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


def plot_campbell(
    result: CampbellResult,
    components: Sequence[ComponentModes] = (),
    *,
    fmax: float | None = None,
) -> Figure:
    """Natural frequencies and excitation lines against speed; crossings marked.

    ``components`` (gear-body modes, :class:`~reducerlab.analysis.campbell.
    ComponentModes`): each mode inside the frequency range shown is drawn as a
    horizontal dashed line labelled ``"gear N: f Hz (type)"``, its crossings with the
    excitation lines marked (diamonds). ``fmax``: top of the frequency axis (Hz);
    default 1.1 x the highest natural frequency.
    """
    from matplotlib.figure import Figure

    ds = result.data
    rpm = ds["speed"].values * 60 / (2 * np.pi)
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
        ax.axvspan(lo * 60 / (2 * np.pi), hi * 60 / (2 * np.pi), color="0.9", zorder=0,
                   label="operating range")  # fmt: skip
    if fmax is None:
        fmax = np.nanmax(f) * 1.1 if np.isfinite(np.nanmax(f)) else 1.0
    elif not (isinstance(fmax, int | float) and 0 < fmax < np.inf):
        raise ReducerlabError(f"fmax must be a positive frequency (Hz), got {fmax!r}")
    ax.set_ylim(0, fmax)
    ax.set_xlim(rpm[0], rpm[-1])
    handles: list = []
    if components:
        from .components import draw_component_lines

        handles, _ = ax.get_legend_handles_labels()
        handles += draw_component_lines(
            ax, components, ds["order"].values, (rpm[0], rpm[-1]), float(fmax)
        )
    ax.set_xlabel("input speed (rpm)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(f"Campbell diagram: {ds.attrs.get('title', '')}", fontsize=9)
    if components:
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    else:
        ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    return fig
