"""Figures of the loaded transmission error against torque
(:class:`~reducerlab.analysis.te_sweep.TESweepResult`) and of the flank modification
layout (:class:`~reducerlab.analysis.layout.LayoutResult`).

:func:`plot_te_sweep`: left, TE over one mesh cycle at each torque overlaid (the
unloaded TE dashed); right, the peak-to-peak TE and the amplitudes of the first mesh
harmonics against torque. Plain :class:`matplotlib.figure.Figure` objects (no pyplot,
Agg-safe); SI in the dataset, drawn in um, deg and N m.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .axes import plain_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_layout", "plot_te_sweep"]


def _figure(**kw: object) -> Figure:
    from matplotlib.figure import Figure

    return Figure(**kw)


def plot_te_sweep(result: Any) -> Figure:
    """TE curves against the mesh position at each torque, and the peak-to-peak TE and
    the mesh harmonics against torque."""
    ds = result.data
    fig = _figure(figsize=(11, 4.2), layout="constrained")
    ax, bx = fig.subplots(1, 2)
    angle = np.degrees(ds["angle"].values - ds["angle"].values[0])
    T = ds["torque"].values
    te = 1e6 * ds["te"].values
    colours = [f"C{i % 10}" for i in range(len(T))]
    for t, row, c in zip(T, te, colours, strict=True):
        style = "--" if t == 0 else "-"
        label = "unloaded" if t == 0 else f"{t:.4g} N m"
        ax.plot(angle, row, style, color=c, marker=".", label=label)
    ax.set_xlabel(f"mesh position, {ds.attrs['gear_a']} rotation (deg)")
    ax.set_ylabel(f"transmission error at r = {1e3 * ds.attrs['te_radius_m']:.4g} mm (um)")
    ax.set_title("Loaded TE over one mesh cycle")
    ax.grid(alpha=0.3)
    ax.legend(  # beside the panel: the curves fill its width
        fontsize=8,
        title="torque on " + ds.attrs["gear_a"],
        title_fontsize=8,
        loc="center left",
        bbox_to_anchor=(1.0, 0.5),
        frameon=False,
    )
    bx.plot(T, 1e6 * ds["peak_to_peak"].values, "k-o", label="peak-to-peak")
    for r in ds["order"].values:
        amp = 1e6 * ds["harmonic_amplitude"].sel(order=r).values
        bx.plot(T, amp, "-s", markersize=4, label=f"mesh order {int(r)}")
    bx.axvline(ds.attrs["design_torque"], color="0.5", ls=":", label="design load")
    bx.set_xlabel(f"torque on {ds.attrs['gear_a']} (N m)")
    bx.set_ylabel("TE (um)")
    bx.set_title("Peak-to-peak TE and mesh harmonics")
    bx.grid(alpha=0.3)
    bx.legend(fontsize=8)
    return plain_figure(fig)


def plot_layout(result: Any) -> Figure:
    """TE peak-to-peak over lead crowning and tip relief (interpolated between the
    candidates), each candidate marked (red x: infeasible, pressure above the limit or
    edge contact), the infeasible region hatched, the best layout starred."""
    from matplotlib.tri import Triangulation

    ds = result.data
    a = ds.attrs
    c = 1e6 * ds["crowning"].values
    r = 1e6 * ds["relief"].values
    pp = 1e6 * ds["peak_to_peak"].values
    ok = ds["feasible"].values.astype(bool)
    fig = _figure(figsize=(6.4, 5.0), layout="constrained")
    ax = fig.subplots()
    try:
        tri = Triangulation(c, r)
        cs = ax.tricontourf(tri, pp, levels=14, cmap="viridis")
        fig.colorbar(cs, ax=ax, label="TE peak-to-peak (um)")
        if not ok.all():
            ax.tricontourf(tri, (~ok).astype(float), levels=[0.5, 1.5], colors="none",
                           hatches=["//"])  # fmt: skip
    except (ValueError, RuntimeError):  # collinear candidates: markers only
        sc = ax.scatter(c, r, c=pp, cmap="viridis")
        fig.colorbar(sc, ax=ax, label="TE peak-to-peak (um)")
    ax.scatter(c[ok], r[ok], marker="o", facecolors="w", edgecolors="k", label="feasible")
    ax.scatter(c[~ok], r[~ok], marker="x", color="r",
               label="infeasible (pressure or edge contact)")  # fmt: skip
    if np.isfinite(a["best_crowning"]):
        ax.scatter([1e6 * a["best_crowning"]], [1e6 * a["best_relief"]], marker="*", s=220,
                   color="gold", edgecolors="k", zorder=5,
                   label=f"best: {1e6 * a['best_peak_to_peak']:.3g} um")  # fmt: skip
    ax.set_xlabel("lead crowning C_beta of each flank (um)")
    ax.set_ylabel("tip relief C_a of each flank (um)")
    ax.set_title(
        f"TE p-p at {a['design_torque']:.4g} N m; p <= {a['pressure_limit'] * 1e-6:.4g} MPa, "
        f"edge < {100 * a['edge_limit']:.3g} %",
        fontsize=10,
    )
    # the candidates sit on the grid's corners and edges: a margin keeps their markers
    # whole; the legend goes below the axes, off the map and the best star
    for lim, v in ((ax.set_xlim, c), (ax.set_ylim, r)):
        lo, hi = float(np.min(v)), float(np.max(v))
        pad = 0.06 * (hi - lo) if hi > lo else max(0.5, 0.1 * abs(hi))
        lim(lo - pad, hi + pad)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3,
              frameon=False)  # fmt: skip
    return plain_figure(fig)
