"""The accuracy rule of the fixed-step integrators: the step count that meets a target
error of the Poincaré points on the attractor (Richardson estimate over one period)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..model import NonlinearSystem
from .guards import BOUND_FACTOR
from .limits import ACCURACY
from .prepare import Prepared, with_steps
from .steps import MAX_STEPS, Steps

__all__ = [
    "ACCURACY",
    "PERIOD_ERROR_GAIN",
    "PILOT_PERIODS",
    "accurate_steps",
    "pilot_run",
    "refine_steps",
]


#: Periods integrated before the step count is checked (the state then lies on or near
#: the attractor, where the error is measured).
PILOT_PERIODS = 40

#: Error of the Poincaré points over the one-period error estimate (measured 2-4 on
#: the rattle oscillators of tests/test_accuracy.py: a stable orbit accumulates the
#: per-period error over a few periods).
PERIOD_ERROR_GAIN = 5.0


def accurate_steps(
    prep: Prepared,
    systems: Sequence[NonlinearSystem],
    Y0: NDArray[np.float64],
    bounds: NDArray[np.float64],
    accuracy: float = ACCURACY,
    pilot: int = PILOT_PERIODS,
) -> int:
    """Steps per forcing period that meet ``accuracy`` on the attractor.

    The members are integrated for ``pilot`` periods with the stability-based step
    count of ``prep`` (``omega_max h <= 0.25``, at least 32); from there one period is
    integrated with ``N`` and ``2 N`` steps, and the difference (the error of the
    ``N``-step period, Richardson) relative to each member's displacement scale
    (``bounds / BOUND_FACTOR``, velocities by that times the highest frequency) must be
    below ``accuracy / PERIOD_ERROR_GAIN``; otherwise ``N`` grows by the fourth root of
    the excess (RK4 is fourth order, kinks of the backlash included, since the kernel
    steps to each boundary crossing) and the check repeats. The largest over the
    members is returned, at most :data:`MAX_STEPS`. Members that diverge or have no
    scale are left to the main run.
    """
    Steps.accuracy(accuracy)  # a number in (0, 1)
    T, N = prep.period, prep.steps
    end, ran = pilot_run(prep, Y0, bounds, pilot)
    Y = end.copy()
    ok = ran & np.all(np.isfinite(Y), axis=1)
    if not np.any(ok):
        return N
    Y[~ok] = Y0[~ok]
    return refine_steps(prep, systems, Y, pilot * T, ok, bounds, accuracy)


def pilot_run(
    prep: Prepared, Y0: NDArray[np.float64], bounds: NDArray[np.float64], pilot: int
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """The pilot of :func:`accurate_steps`: ``pilot`` periods of the RK4 kernel from
    ``Y0`` (E, 2n) with the steps of ``prep``.

    Returns
    -------
    end : (E, 2n)
        The state at the end (NaN for a member that left its ``bounds``).
    ran : (E,)
        Whether each member stayed within its bounds.
    """
    from .kernel import block_width, rk4_ensemble

    E = Y0.shape[0]
    P, _, status, _ = rk4_ensemble(
        *prep.arrays, Y0, np.zeros(E), prep.period, prep.offs, prep.dts, prep.periodic,
        pilot, 1, 0, bounds, block_width(E), -1, 0.0,
    )  # fmt: skip
    return P[:, 1], status[:, 0] == 0


def refine_steps(
    prep: Prepared,
    systems: Sequence[NonlinearSystem],
    Y: NDArray[np.float64],
    start: NDArray[np.float64],
    ok: NDArray[np.bool_],
    bounds: NDArray[np.float64],
    accuracy: float,
) -> int:
    """The check of :func:`accurate_steps` from states ``Y`` at times ``start`` (s) on
    or near the attractor (members ``ok``): one period with ``N`` and ``2N`` steps, ``N``
    grown until their difference meets ``accuracy / PERIOD_ERROR_GAIN``."""
    from .kernel import block_width, rk4_ensemble

    E = len(systems)
    T, N = prep.period, prep.steps
    scale = bounds / BOUND_FACTOR
    scale[~np.isfinite(scale) | (scale <= 0)] = np.inf
    bw = block_width(E)
    ok = ok.copy()
    target = accuracy / PERIOD_ERROR_GAIN
    for _ in range(6):
        ends = []
        for steps in (N, 2 * N):
            p = with_steps(prep, systems, steps)
            out, _, st, _ = rk4_ensemble(
                *p.arrays, Y, start, T, p.offs, p.dts, p.periodic, 1, 1, 0, bounds, bw, -1, 0.0,
            )  # fmt: skip
            ok &= st[:, 0] == 0
            ends.append(out[:, 1])
        err = np.abs(ends[0] - ends[1]) / scale
        est = float(np.nanmax(np.where(ok[:, None], err, 0.0)))
        if not est > target or N >= MAX_STEPS:
            return N
        grow = min(8.0, max(1.5, 1.2 * (est / target) ** 0.25))
        N = min(MAX_STEPS, math.ceil(N * grow))
    return N
