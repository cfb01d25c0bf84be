"""Figures of the ball-track contact (issue 30): stiffness and loaded balls against
torque, and the ball forces round the track."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from .axes import plain_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_ball_track"]


def plot_ball_track(result: Any) -> Figure:
    """Left: torsional stiffness about the centre disc's axis against torque (mean over
    the ball-set positions, their range shaded) and the loaded balls (right axis).
    Right: the balls on their circle at the rated torque (phase 0), each marked by the
    force of its loaded line (colour and size), line ``-`` hollow, undercut lines
    crossed, the pitch point and the line of centres drawn."""
    from matplotlib.figure import Figure

    ds = result.data
    a = ds.attrs
    t = ds["torque"].values
    kt = ds["torsional_stiffness"].values
    n = ds["loaded"].values
    fig = Figure(figsize=(11.5, 4.8), layout="constrained")
    ax, polar = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1.25, 1]})
    ax.fill_between(t, kt.min(axis=1) / 1e3, kt.max(axis=1) / 1e3, color="C0", alpha=0.25,
                    lw=0, label="range over one ball pitch")  # fmt: skip
    ax.plot(t, kt.mean(axis=1) / 1e3, "C0-o", ms=3, label="torsional stiffness (mean)")
    ax.axvline(a["rated_torque_N_m"], color="0.5", ls=":", lw=1, label="rated torque")
    ax.set_xlabel("torque on the centre disc (N m)")
    ax.set_ylabel("torsional stiffness (kN m/rad)")
    ax.grid(alpha=0.3)
    ax2 = ax.twinx()
    ax2.plot(t, n.mean(axis=1), "C3-s", ms=3, label="loaded balls (mean)")
    ax2.set_ylabel("loaded balls", color="C3")
    ax2.set_ylim(0, a["balls"] + 1)
    ax.set_ylim(0, 1.08 * max(float(kt.max()) / 1e3, 1e-300))  # both zeros on the baseline
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, loc="lower right", fontsize=8)
    ax.set_title(f"{a['balls']} balls, clearance {1e6 * a['clearance_m']:.3g} um, y {a['y']}")
    # the track at the rated torque
    i = int(np.argmin(np.abs(t - a["rated_torque_N_m"])))
    f = ds["force"].values[i, 0]  # (ball, line)
    psi = ds["psi"].values[0]
    K, R = a["short_width"], a["ball_circle_radius_m"]
    x, yv = R * np.sin(psi), -R * np.cos(psi)  # about M, the pitch point at (0, -K R)
    theta = np.linspace(0, 2 * math.pi, 200)
    polar.plot(R * np.cos(theta) * 1e3, R * np.sin(theta) * 1e3, color="0.8", lw=1)
    fmax = max(float(f.max()), 1e-12)
    size = 20 + 180 * f.max(axis=1) / fmax
    plus = f[:, 0] >= f[:, 1]
    sc = polar.scatter(x[plus] * 1e3, yv[plus] * 1e3, s=size[plus], c=f[plus, 0],
                       cmap="viridis", vmin=0, vmax=fmax, edgecolors="k", linewidths=0.5,
                       label="line +")  # fmt: skip
    polar.scatter(x[~plus] * 1e3, yv[~plus] * 1e3, s=size[~plus], facecolors="none",
                  edgecolors=[sc.cmap(sc.norm(v)) for v in f[~plus, 1]], linewidths=1.5,
                  label="line -")  # fmt: skip
    under = ds["undercut"].values[0].any(axis=1)
    polar.scatter(x[under] * 1e3, yv[under] * 1e3, marker="x", color="C3", s=25,
                  label="a line undercut")  # fmt: skip
    polar.plot([0], [-K * R * 1e3], "k*", ms=10, label="pitch point")
    polar.plot([0, 0], [-R * 1.1e3, R * 1.1e3], color="0.6", ls="--", lw=0.8)
    polar.set_aspect("equal")
    polar.set_xlabel("across the line of centres (mm)")
    polar.set_ylabel("along the line of centres (mm)")
    polar.set_title(f"ball forces at {t[i]:.3g} N m (max {fmax:.3g} N)")
    polar.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=4, fontsize=7)
    fig.colorbar(sc, ax=polar, label="force (N)", shrink=0.8)
    return plain_figure(fig)
