"""What a steady motion is: its period from the Poincaré points, its class (period-n,
quasi-periodic, chaotic, still unsettled), whether two runs hold the same attractor,
and the spectral peaks of a signal as multiples of the forcing frequency."""

from __future__ import annotations

import itertools
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError

__all__ = [
    "COEXIST_TOL",
    "SETTLE",
    "attractor_scale",
    "classify",
    "different_attractors",
    "period_of",
    "spectrum_peaks",
]


#: Two runs hold different attractors when their motion classes differ or their mean
#: Poincaré deflections differ by more than this share of the largest Poincaré spread
#: (:func:`different_attractors`).
COEXIST_TOL = 0.02


def attractor_scale(points: NDArray) -> float:
    """The size against which mean Poincaré deflections are compared: the largest spread
    of a Poincaré sequence (last axis) in ``points``, at least 1e-3 of the largest mean."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: diverged runs
        if not np.any(np.isfinite(points)):
            return 1e-300
        spread = float(np.nanmax(np.ptp(points, axis=-1)))
        mean = float(np.nanmax(np.abs(np.nanmean(points, axis=-1))))
    spread = spread if np.isfinite(spread) else 0.0
    return max(spread, 1e-3 * mean, 1e-300)


def different_attractors(
    a: NDArray, labels_a: Any, b: NDArray, labels_b: Any, size: float
) -> NDArray[np.bool_]:
    """Rows of Poincaré points ``a``, ``b`` (..., point) with their motion classes that
    belong to different attractors: different classes, or mean deflections apart by more
    than :data:`COEXIST_TOL` ``* size``."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: diverged runs
        apart = np.abs(np.nanmean(a, axis=-1) - np.nanmean(b, axis=-1)) > COEXIST_TOL * size
    return (np.asarray(labels_a, object) != np.asarray(labels_b, object)) | apart


def period_of(row: NDArray, tol: float, max_period: int) -> int:
    span = max(np.ptp(row), np.abs(row).max(), 1e-300)
    for n in range(1, max_period + 1):
        if np.all(np.abs(row[n:] - row[:-n]) <= tol * span):
            return n
    return 0


def classify(
    poincare: NDArray[np.float64],
    exponent: float,
    frequency: float,
    *,
    tol: float = 1e-3,
    max_period: int = 12,
    chaos: float = 0.01,
) -> str:
    """Label a steady motion from its Poincaré points and largest Lyapunov exponent.

    ``"chaotic"`` when the exponent exceeds ``chaos`` x the forcing frequency (1/s per
    Hz: a separation growing by e within ~100 periods), else ``"period-n"`` when the
    Poincaré sequence repeats every n <= ``max_period`` points (to ``tol`` of its
    range), else ``"unsettled"`` when the points still converge (their spread, or for
    some n <= ``max_period`` their n-step differences ``|x[k+n] - x[k]|``, shrink from
    quarter to quarter of the sequence, the last below :data:`SETTLE` times the first: a
    transient of a lightly damped mode towards a fixed point or a period-n orbit, not an
    attractor; run more periods), else ``"quasi-periodic"``.
    """
    if exponent > chaos * frequency:
        return "chaotic"
    pts = np.asarray(poincare, float)
    n = period_of(pts, tol, max_period)
    if n:
        return f"period-{n}"
    if pts.size >= 16 and _converging(pts, max_period):
        return "unsettled"
    return "quasi-periodic"


def _converging(pts: NDArray, max_period: int) -> bool:
    """Whether a Poincaré sequence still converges: the spread of its quarters (a
    transient towards a fixed point), or for some n <= ``max_period`` the largest n-step
    difference ``|x[k+n] - x[k]|`` in each quarter (towards a period-n orbit), shrinks
    from quarter to quarter, the last below :data:`SETTLE` times the first."""

    def shrinking(q: list[float]) -> bool:
        return q[3] < SETTLE * q[0] and all(a >= b for a, b in itertools.pairwise(q))

    if shrinking([float(np.ptp(part)) for part in np.array_split(pts, 4)]):
        return True
    for n in range(1, max_period + 1):
        diff = np.abs(pts[n:] - pts[:-n])
        if diff.size >= 8 and shrinking([float(part.max()) for part in np.array_split(diff, 4)]):
            return True
    return False


#: A Poincaré sequence whose spread shrinks from quarter to quarter, the last below this
#: fraction of the first, is still converging (``classify``: "unsettled"). A
#: quasi-periodic sequence fills its closed curve in every quarter (no steady shrinking);
#: a transient decaying by a factor 2 over the kept points ends at ~0.6.
SETTLE = 0.8


def spectrum_peaks(
    signal: NDArray[np.float64], dt: float, f_ref: float, count: int = 6
) -> list[tuple[float, float]]:
    """Largest spectral peaks of ``signal`` as ``(multiple of f_ref, amplitude)``, the
    labelling of paper 004 Fig. 8 ("0.48x, 0.57x, ...")."""
    if np.size(signal) < 4 or not (dt > 0 and f_ref > 0):
        raise ReducerlabError("spectrum_peaks: need >= 4 samples, dt > 0 and f_ref > 0")
    x = np.asarray(signal, float) - np.mean(signal)
    amp = 2 * np.abs(np.fft.rfft(x * np.hanning(x.size))) / np.sum(np.hanning(x.size))
    f = np.fft.rfftfreq(x.size, dt)
    peaks = [i for i in range(1, amp.size - 1) if amp[i] >= amp[i - 1] and amp[i] > amp[i + 1]]
    peaks.sort(key=lambda i: -amp[i])
    return [(float(f[i] / f_ref), float(amp[i])) for i in peaks[:count]]
