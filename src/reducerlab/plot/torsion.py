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
        for t, k in zip((n.T1, n.T2), knots[1:3], strict=True):
            ax.plot(sign * t, k, "ks", ms=4)
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
    return plain_figure(fig)


def _friction_note(res: Any) -> str:
    """The title's friction line: the coefficient and the loop's area (the friction
    work per cycle), or why the loop is closed."""
    a = res.data.attrs
    mu = float(a.get("mu", 0.0))
    if not float(a.get("friction_work", 0.0)):
        return "no friction in the loop (" + str(a.get("friction", "none")).split("(", 1)[-1]
    return f"Coulomb mu = {mu:g}: loop area {res.numbers.loop_area:.3g} J (friction work per cycle)"
