"""Figure of the transmission accuracy
(:class:`~reducerlab.analysis.transmission_accuracy.TransmissionAccuracyResult`): left,
the output angle error (arcsec) over one output revolution, each source dashed (under
load the loaded mesh's variation among them); middle, its amplitude spectrum in orders
of the output revolution, up to twice the highest order above 5 % of the largest line;
under load, right, three cycles of the loaded source (tooth-mesh cycles, or the
cycloid-ball track's ball-pattern periods). Plain
:class:`matplotlib.figure.Figure` (no pyplot, Agg-safe)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .axes import plain_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["NO_ERROR", "plot_transmission_accuracy"]

ARCSEC = np.pi / (180.0 * 3600.0)

#: What the figure says, without axes, when the result's error is zero throughout.
NO_ERROR = (
    "No manufacturing or assembly error given: the output angle error is zero "
    "(no curve, no spectrum to draw)."
)


def _meshes_zoom(fig: Figure, ax: Any, ds: Any, deg: Any) -> None:
    """Under load, a nutation drive (``mesh_count`` meshes,
    ``analysis.loaded_accuracy_nutation``): the title names the load and the meshes'
    summed mean wind-up; ``ax`` shows three cycles of the lowest tooth-mesh order, each
    mesh's loaded variation and the total."""
    a = ds.attrs
    fig.suptitle(f"under {a['load_N_m']:.4g} N m on the output: mean wind-up of the meshes "
                 f"{a['wind_up_arcsec']:.3g} arcsec (output behind; not in the trace)",
                 fontsize="medium")  # fmt: skip
    meshes = range(1, int(a["mesh_count"]) + 1)
    order = min(int(a[f"mesh{j}_order"]) for j in meshes)
    span = deg <= 3 * 360.0 / order
    for j in meshes:
        loaded = ds["contribution"].sel(source=f"mesh {j} under load").values
        ax.plot(deg[span], loaded[span] / ARCSEC, "--", lw=0.8, label=f"mesh {j} under load")
    ax.plot(deg[span], ds["error"].values[span] / ARCSEC, "k-", lw=1.2, label="total")
    ax.set_xlabel("output angle (deg)")
    ax.set_ylabel("output angle error (arcsec)")
    ax.set_title(f"three tooth-mesh cycles of mesh order {order}")
    ax.legend(fontsize="small")


def plot_transmission_accuracy(result: Any) -> Figure:
    """Error over the output revolution and its spectrum in orders."""
    from matplotlib.figure import Figure

    ds = result.data
    if not np.any(ds["error"].values):  # nothing to draw but a zero line: the message only
        fig = Figure(figsize=(8, 1.6))
        text = NO_ERROR.replace(": ", ":\n", 1)
        fig.text(0.5, 0.5, text, ha="center", va="center", fontsize=11, color="0.3")
        return fig
    loaded = "load_N_m" in ds.attrs  # a third panel: three tooth-mesh cycles
    fig = Figure(figsize=(15 if loaded else 11, 4.2), layout="constrained")
    ax, bx, *zx = fig.subplots(1, 3 if loaded else 2)
    deg = np.degrees(ds["output_angle"].values)
    for s in ds["source"].values:
        c = ds["contribution"].sel(source=s).values
        if np.any(c):
            ax.plot(deg, c / ARCSEC, "--", lw=0.8, label=str(s))
    ax.plot(deg, ds["error"].values / ARCSEC, "k-", lw=1.2, label="total")
    ax.set_xlabel("output angle (deg)")
    ax.set_ylabel("output angle error (arcsec)")
    ax.set_title(f"peak to peak {ds.attrs['peak_to_peak_arcsec']:.4g} arcsec")
    if loaded:
        (_meshes_zoom if "mesh_count" in ds.attrs else _loaded_zoom)(fig, zx[0], ds, deg)
    ax.legend(fontsize="small")
    order = ds["order"].values
    amp = ds["amplitude"].values
    top = int(order[np.nonzero(amp > 0.05 * max(amp.max(), 1e-300))[0]].max(initial=1))
    keep = order <= max(2 * top, 10)
    bx.vlines(order[keep][1:], 0, amp[keep][1:], color="k")
    bx.set_xlabel(
        f"order of the output revolution (input order = order / {abs(ds.attrs['ratio']):.4g})"
    )
    bx.set_ylabel("amplitude (arcsec)")
    bx.set_ylim(bottom=0.0)
    return plain_figure(fig)


def _loaded_zoom(fig: Figure, ax: Any, ds: Any, deg: Any) -> None:
    """Under load: the figure's title names the load and the mean wind-up (not in the
    trace), and ``ax`` shows the first three cycles of the loaded source (tooth-mesh
    cycles; ball-pattern periods of a cycloid-ball drive's ball track)."""
    a = ds.attrs
    gear = "mesh_order" in a
    what, source, cycle = (
        ("mesh", "mesh under load", "tooth-mesh cycles")
        if gear
        else ("ball track", "ball track under load", "ball-pattern periods")
    )
    order = a["mesh_order"] if gear else a["ball_pattern_order"]
    fig.suptitle(f"under {a['load_N_m']:.4g} N m on the output: mean wind-up of the {what} "
                 f"{a['wind_up_arcsec']:.3g} arcsec (output behind; not in the trace)",
                 fontsize="medium")  # fmt: skip
    span = deg <= 3 * 360.0 / order
    loaded = ds["contribution"].sel(source=source).values
    ax.plot(deg[span], loaded[span] / ARCSEC, "--", lw=0.8, label=source)
    ax.plot(deg[span], ds["error"].values[span] / ARCSEC, "k-", lw=1.2, label="total")
    ax.set_xlabel("output angle (deg)")
    ax.set_ylabel("output angle error (arcsec)")
    ax.set_title(f"three {cycle} (order {order})")
    ax.legend(fontsize="small")
