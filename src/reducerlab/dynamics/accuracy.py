"""The accuracy rule of the fixed-step integrators: the step count that meets a target
error of the Poincaré points on the attractor (Richardson estimate over every period of
a span that covers the orbit: its detected period, at least two periods)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..model import NonlinearSystem
from .guards import BOUND_FACTOR
from .limits import ACCURACY
from .prepare import Prepared, subset, with_steps
from .steps import MAX_STEPS, Steps

__all__ = [
    "ACCURACY",
    "MAX_SPAN",
    "PERIOD_ERROR_GAIN",
    "PILOT_PERIODS",
    "SPAN_TOL",
    "accurate_steps",
    "check_span",
    "pilot_keep",
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


#: Most periods the accuracy check covers (:func:`check_span`): a member whose pilot
#: points repeat every ``p <= MAX_SPAN`` periods is checked over ``max(p, 2)`` periods,
#: any other (unsettled, quasi-periodic, chaotic, or a longer period) over ``MAX_SPAN``.
MAX_SPAN = 8

#: Pilot points that repeat to this share of the member's displacement scale (velocities
#: by that times the highest frequency) count as periodic (:func:`check_span`). Only the
#: cost of the check depends on it: a period missed is checked over :data:`MAX_SPAN`.
SPAN_TOL = 1e-4


def accurate_steps(
    prep: Prepared,
    systems: Sequence[NonlinearSystem],
    Y0: NDArray[np.float64],
    bounds: NDArray[np.float64],
    accuracy: float = ACCURACY,
    pilot: int = PILOT_PERIODS,
) -> int:
    """Steps per forcing period that meet ``accuracy`` on the attractor.

    Parameters
    ----------
    prep : Prepared
        The ensemble, with the stability-based step count (``omega_max h <= 0.25``, at
        least 32) that the pilot uses and the check starts from.
    systems : sequence of NonlinearSystem
        The members of ``prep``.
    Y0 : (E, 2n) array
        Initial states.
    bounds : (E, 2n) array
        State bounds (:func:`~.guards.state_bounds`); ``bounds / BOUND_FACTOR`` is each
        member's displacement scale (velocities by that times its highest frequency).
    accuracy : float
        Target error of the Poincaré points relative to that scale.
    pilot : int
        Periods integrated before the check (the state then lies on or near the
        attractor).

    Returns
    -------
    int
        The largest step count over the members, at most :data:`MAX_STEPS`.

    Notes
    -----
    The span rule: the check covers the orbit, not one period. The period ``p`` of each
    member is read from the last pilot points (:func:`check_span`: they repeat every
    ``p <= MAX_SPAN`` periods to :data:`SPAN_TOL` of the scale); each of the last
    ``max(p, 2)`` pilot points (:data:`MAX_SPAN` of them where no period is found) starts
    one period integrated with ``N`` and ``2 N`` steps, and the largest difference (the
    error of the ``N``-step period, Richardson) must be below
    ``accuracy / PERIOD_ERROR_GAIN``; otherwise ``N`` grows by the fourth root of the
    excess (RK4 is fourth order, kinks of the backlash included, since the kernel steps
    to each boundary crossing) and the check repeats. So a period-2 rattle orbit that
    loses contact every other period is checked in its impact period whatever the
    pilot's parity; checking one period missed it (issue 26). The span multiplies the
    cost of the check only, never of the pilot or the main run. Members that diverge or
    have no scale are left to the main run.
    """
    Steps.accuracy(accuracy)  # a number in (0, 1)
    N = prep.steps
    P, ran = pilot_run(prep, Y0, bounds, pilot)
    ok = ran & np.all(np.isfinite(P), axis=(1, 2))
    if not np.any(ok):
        return N
    P[~ok] = Y0[~ok, None, :]
    return refine_steps(prep, systems, P, pilot * prep.period, ok, bounds, accuracy)


def pilot_run(
    prep: Prepared, Y0: NDArray[np.float64], bounds: NDArray[np.float64], pilot: int
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """The pilot of :func:`accurate_steps`: ``pilot`` periods of the RK4 kernel from
    ``Y0`` (E, 2n) with the steps of ``prep``.

    Returns
    -------
    points : (E, k + 1, 2n)
        The states at the start of the last ``k = min(pilot, 2 MAX_SPAN)`` periods and
        at the end (NaN for a member that left its ``bounds``).
    ran : (E,)
        Whether each member stayed within its bounds.
    """
    from .kernel import block_width, rk4_ensemble

    E = Y0.shape[0]
    P, _, status, _ = rk4_ensemble(
        *prep.arrays, Y0, np.zeros(E), prep.period, prep.offs, prep.dts, prep.periodic,
        pilot, pilot_keep(pilot), 0, bounds, block_width(E), -1, 0.0,
    )  # fmt: skip
    return P, status[:, 0] == 0


def pilot_keep(pilot: int) -> int:
    """Pilot points kept for :func:`check_span`: enough to see a period up to
    :data:`MAX_SPAN` twice."""
    return max(1, min(pilot, 2 * MAX_SPAN))


def check_span(points: NDArray[np.float64], scale: NDArray[np.float64]) -> NDArray[np.intp]:
    """Periods each member's accuracy check covers: ``max(p, 2)`` for the smallest
    ``p <= MAX_SPAN`` with which its pilot ``points`` (E, k + 1, 2n) repeat to
    :data:`SPAN_TOL` of ``scale`` (E, 2n), else ``MAX_SPAN``; at most the ``k + 1``
    points there are."""
    E, K1, _ = points.shape
    span = np.full(E, MAX_SPAN, np.intp)
    found = np.zeros(E, bool)
    with np.errstate(invalid="ignore"):
        for p in range(1, min(MAX_SPAN, K1 - 1) + 1):
            if K1 - p < p:  # fewer than p differences: the period is not seen twice
                break
            d = np.abs(points[:, p:] - points[:, :-p]) / scale[:, None, :]
            rep = np.all(d <= SPAN_TOL, axis=(1, 2)) & ~found
            span[rep] = max(p, 2)
            found |= rep
    return np.minimum(span, K1)


def refine_steps(
    prep: Prepared,
    systems: Sequence[NonlinearSystem],
    points: NDArray[np.float64],
    end: NDArray[np.float64],
    ok: NDArray[np.bool_],
    bounds: NDArray[np.float64],
    accuracy: float,
) -> int:
    """The check of :func:`accurate_steps` from the pilot ``points`` (E, k + 1, 2n; the
    last at times ``end`` (s), one period apart) on or near the attractor (members
    ``ok``): one period with ``N`` and ``2N`` steps from each of the last
    :func:`check_span` points, ``N`` grown until their largest difference meets
    ``accuracy / PERIOD_ERROR_GAIN``."""
    from .kernel import block_width, rk4_ensemble

    E = len(systems)
    T, N = prep.period, prep.steps
    scale = bounds / BOUND_FACTOR
    scale[~np.isfinite(scale) | (scale <= 0)] = np.inf
    K1 = points.shape[1]
    span = check_span(points, np.where(np.isfinite(scale), scale, 1.0))
    member = np.repeat(np.arange(E), span)  # one check run per (member, period)
    back = np.concatenate([np.arange(s - 1, -1, -1) for s in span])  # periods before end
    Y = points[member, K1 - 1 - back]
    start = end[member] - back * T[member]
    ok = ok[member].copy()
    M = member.size
    bw = block_width(M)
    target = accuracy / PERIOD_ERROR_GAIN
    for _ in range(6):
        ends = []
        for steps in (N, 2 * N):
            p = subset(with_steps(prep, systems, steps), member)
            out, _, st, _ = rk4_ensemble(
                *p.arrays, Y, start, p.period, p.offs, p.dts, p.periodic, 1, 1, 0,
                bounds[member], bw, -1, 0.0,
            )  # fmt: skip
            ok &= st[:, 0] == 0
            ends.append(out[:, 1])
        err = np.abs(ends[0] - ends[1]) / scale[member]
        est = float(np.nanmax(np.where(ok[:, None], err, 0.0)))
        if not est > target or N >= MAX_STEPS:
            return N
        grow = min(8.0, max(1.5, 1.2 * (est / target) ** 0.25))
        N = min(MAX_STEPS, math.ceil(N * grow))
    return N
