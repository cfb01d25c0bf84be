"""Figure of the torsion test's hysteresis loop
(:class:`~reducerlab.analysis.torsion_test.TorsionTestResult`).

Twist (arcmin) against output torque (N m), each branch in its colour, the K1/K2/K3
secants on both loading branches, and the lost-motion band (+/-3 % of rated) shaded.
A plain :class:`matplotlib.figure.Figure` (no pyplot, Agg-safe); SI in the dataset.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from .axes import plain_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["plot_torsion_loop"]

_ARCMIN = math.pi / (180.0 * 60.0)


def plot_torsion_loop(result: Any) -> Figure:
    """The loop with the K1/K2/K3 segments and the lost-motion band marked."""
    from matplotlib.figure import Figure

    from ..analysis.torsion_test import BRANCHES

    ds = result.data
    a = ds.attrs
    n = result.numbers
    T = ds["torque"].values
    th = ds["twist"].values / _ARCMIN
    br = ds["branch"].values
    fig = Figure(figsize=(7.5, 5.0), layout="constrained")
    ax = fig.subplots()
    rated = float(a["rated_torque"])
    ax.axvspan(-0.03 * rated, 0.03 * rated, color="0.85", label="+/-3 % rated (lost motion)")
    for j, name in enumerate(BRANCHES):
        sel = br == j
        ax.plot(T[sel], th[sel], "o-" if j % 2 == 0 else "x--", ms=3, lw=1, color=f"C{j}",
                label=name)  # fmt: skip
    # the jump across the backlash where the falling branch passes zero torque
    i = int(np.flatnonzero(br == 1)[-1])
    ax.plot(T[i : i + 2], th[i : i + 2], ":", color="C1", lw=1.2, label="backlash jump at 0")
    # K1/K2/K3: the piecewise-linear catalogue curve from each loading branch's zero
    for j, sign in ((0, 1.0), (2, -1.0)):
        sel = br == j
        zero = float(th[sel][np.argmin(np.abs(T[sel]))])
        knots_T = np.array([0.0, n.T1, n.T2, rated])
        seg = np.array([0.0, n.T1 / n.K1, (n.T2 - n.T1) / n.K2, (rated - n.T2) / n.K3])
        knots = zero + sign * np.cumsum(seg) / _ARCMIN
        ax.plot(sign * knots_T, knots, "-", color="k", lw=0.8, alpha=0.7,
                label="K1/K2/K3 secants" if j == 0 else None)  # fmt: skip
        ax.plot(sign * np.array([n.T1, n.T2]), knots[1:3], "ks", ms=4,
                label="T1, T2 (knees of the secants)" if j == 0 else None)  # fmt: skip
    lm = n.lost_motion_3 / _ARCMIN
    ax.set_xlabel("output torque (N m)")
    ax.set_ylabel("output twist (arcmin)")
    ax.set_title(
        f"Torsion test, input held: backlash {n.backlash / _ARCMIN:.3g} arcmin, lost motion "
        f"{lm:.3g} arcmin, K3 {n.K3 * _ARCMIN:.4g} N m/arcmin\n{_friction_note(result)}",
        fontsize=9,
    )
    ax.axhline(0.0, color="0.6", lw=0.5)
    ax.axvline(0.0, color="0.6", lw=0.5)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7, loc="upper left")
    plain_figure(fig)
    if float(a.get("friction_work", 0.0)) and float(a.get("mu", 0.0)):
        _loop_inset(ax, T, th, br)
    else:  # the branches coincide: say why there is no loop
        ax.text(0.97, 0.05, f"no hysteresis without friction (mu = {float(a.get('mu', 0.0)):g}):"
                "\nloading and unloading branches coincide", transform=ax.transAxes,
                ha="right", va="bottom", fontsize=8,
                bbox=dict(boxstyle="round", fc="lightyellow", ec="0.6"))  # fmt: skip
    return fig


def _loop_inset(ax: Any, T: np.ndarray, th: np.ndarray, br: np.ndarray) -> None:
    """The friction loop made visible: an inset, in the free lower right corner, of the
    unloading branch's twist less the loading branch's at the same torque (arcsec), on
    each side; the loop's width, too small to see on the whole loop's scale."""
    inset = ax.inset_axes((0.58, 0.07, 0.39, 0.33))
    for load, unload, side in ((0, 1, "+"), (2, 3, "-")):
        tl, hl = T[br == load], th[br == load]
        tu, hu = T[br == unload], th[br == unload]
        order = np.argsort(tl)
        gap = (hu - np.interp(tu, tl[order], hl[order])) * 60.0
        inset.plot(np.abs(tu), gap, "o-", ms=2, lw=0.8, label=f"torque {side}")
    inset.axhline(0.0, color="0.6", lw=0.5)
    inset.set_title("friction loop: unloading - loading twist", fontsize=7)
    inset.set_xlabel("|output torque| (N m)", fontsize=7)
    inset.set_ylabel("arcsec", fontsize=7)
    inset.tick_params(labelsize=6)
    inset.legend(fontsize=6, loc="best")
    inset.grid(True, lw=0.3)


def _friction_note(res: Any) -> str:
    """The title's friction line: the coefficient and the loop's area (the friction
    work per cycle), or why the loop is closed."""
    a = res.data.attrs
    mu = float(a.get("mu", 0.0))
    if not float(a.get("friction_work", 0.0)):
        return "no friction in the loop (" + str(a.get("friction", "none")).split("(", 1)[-1]
    return f"Coulomb mu = {mu:g}: loop area {res.numbers.loop_area:.3g} J (friction work per cycle)"
