"""Figure of the mesh friction loss
(:class:`~reducerlab.analysis.efficiency.EfficiencyResult`): left, the drive and mesh
efficiencies against torque; right, the friction power over one mesh cycle at each
torque (pair 1 solid, further pairs dashed). Plain :class:`matplotlib.figure.Figure`
(no pyplot, Agg-safe)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .axes import plain_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_efficiency"]


def plot_efficiency(result: Any) -> Figure:
    """Efficiency against torque, and the loss per position over the mesh cycle."""
    from matplotlib.figure import Figure

    ds = result.data
    fig = Figure(figsize=(11, 4.2), layout="constrained")
    ax, bx = fig.subplots(1, 2)
    T = ds["torque"].values
    ax.plot(T, 100 * ds["efficiency"].values, "o-", color="k", label="drive")
    for k, p in enumerate(ds["pair"].values):
        ax.plot(T, 100 * ds["mesh_efficiency"].values[k], "s--", label=f"mesh {p} (own frame)")
    ax.set_xlabel("torque on gear A of pair 1 (N m)")
    ax.set_ylabel("efficiency (%)")
    ax.set_title(f"Coulomb friction, mu = {ds.attrs['mu']:.3g}")
    ax.legend()
    x = ds["position"].values / ds.sizes["position"]
    for k in range(ds.sizes["pair"]):
        for i, t in enumerate(T):
            bx.plot(x, ds["loss"].values[k, i], "-" if k == 0 else "--", color=f"C{i % 10}",
                    label=f"{t:.4g} N m" if k == 0 else None)  # fmt: skip
    bx.set_xlabel("mesh cycle")
    bx.set_ylabel("friction power (W)")
    bx.set_ylim(bottom=0.0)
    bx.legend(title="torque", loc="center left", bbox_to_anchor=(1.01, 0.5), frameon=False)
    return plain_figure(fig)
