"""Largest Lyapunov exponents by two-trajectory renormalisation (Benettin's method)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..model import NonlinearSystem
from .accuracy import ACCURACY, PILOT_PERIODS, accurate_steps
from .guards import raise_diverged, state_bounds
from .prepare import prepare, with_steps

__all__ = ["LYAPUNOV_D0", "lyapunov"]

#: Initial (and renormalised) separation of the perturbed copies that measure Lyapunov
#: exponents, in state scales (:func:`lyapunov`, :func:`ensemble` with ``exponents``).
LYAPUNOV_D0 = 1e-9


def lyapunov(
    systems: Sequence[NonlinearSystem],
    *,
    periods: int = 600,
    transient: int = 200,
    steps_per_period: int | None = None,
    d0: float = LYAPUNOV_D0,
    y0: NDArray[np.float64] | None = None,
    period: float | None = None,
    accuracy: float = ACCURACY,
) -> NDArray[np.float64]:
    """Largest Lyapunov exponent (1/s) of each system, by two-trajectory renormalisation.

    A reference and a perturbed trajectory (initial separation ``d0`` in the first
    displacement) are integrated side by side in one call of the compiled kernel;
    after each period the separation is measured in a scaled state norm (displacements
    by their reference amplitude, velocities by amplitude x frequency), logged and reset
    to ``d0`` along the current separation direction (Benettin's method; it needs no
    linearisation, so it works with the non-smooth backlash). The first ``transient``
    periods are discarded. ``period`` (s) is the renormalisation period of systems
    without a periodic law (as in :func:`ensemble`).
    """
    from .kernel import block_width, rk4_ensemble

    if not (isinstance(periods, int) and isinstance(transient, int) and 0 <= transient < periods):
        raise ReducerlabError("lyapunov: need 0 <= transient < periods")
    pairs = [s for s in systems for _ in range(2)]
    labels = None if len(systems) == 1 else [f"member {i // 2}" for i in range(len(pairs))]
    prep = prepare(pairs, steps_per_period, period, labels)
    T = prep.period
    bw = block_width(len(pairs))
    E2, n = len(pairs), systems[0].n
    if y0 is None:
        Y = np.zeros((E2, 2 * n))
    else:
        y0 = np.asarray(y0, float)
        if y0.shape == (2 * n,):
            Y = np.tile(y0, (E2, 1))
        elif y0.shape == (len(systems), 2 * n):
            Y = np.repeat(y0, 2, axis=0)
        else:
            raise ReducerlabError(
                f"y0 must have shape ({2 * n},) or ({len(systems)}, {2 * n}), got {y0.shape}"
            )
    if not np.all(np.isfinite(Y)):
        raise ReducerlabError("y0: the initial state must be finite")
    bounds = state_bounds(pairs, Y, T)
    if steps_per_period is None:  # the same accuracy-driven step count as ensemble
        N = accurate_steps(prep, pairs, Y, bounds, accuracy, min(periods, PILOT_PERIODS))
        prep = with_steps(prep, pairs, N)
    # one compiled run: each pair separates at the end of the transient and is
    # renormalised after every later period inside the kernel
    _, _, status, logs = rk4_ensemble(
        *prep.arrays, Y, np.zeros(E2), T, prep.offs, prep.dts, prep.periodic, periods, 1,
        0, bounds, bw, transient, d0,
    )  # fmt: skip
    raise_diverged(pairs, status, bounds, labels, prep.steps)
    return logs[0::2] / ((periods - transient) * T[0::2])
