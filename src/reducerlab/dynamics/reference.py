"""The reference integrator: scipy ``solve_ivp`` (DOP853) restarted at every
stiffness-law discontinuity and at every backlash boundary crossing (events on
``|delta| = b``), tolerances tight enough to serve as ground truth for the compiled
kernel."""

from __future__ import annotations

import math

import numpy as np
import scipy.integrate
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..model import NonlinearSystem
from ..model.laws import evaluate_flat
from .systems import forcing_period, law_breaks

__all__ = ["simulate_reference"]


def simulate_reference(
    system: NonlinearSystem,
    t_eval: NDArray[np.float64],
    y0: NDArray[np.float64] | None = None,
    *,
    rtol: float = 1e-11,
    atol: float = 1e-16,
) -> NDArray[np.float64]:
    """Reference solution at the (increasing, > 0) times ``t_eval``: DOP853 restarted at
    every stiffness-law discontinuity and at every crossing of a backlash boundary
    (``|delta| = b``, located by events), so that no step straddles a kink.

    Returns the states, shape (len(t_eval), 2n).
    """
    t_eval = np.asarray(t_eval, dtype=float)
    if t_eval.ndim != 1 or t_eval.size == 0 or np.any(np.diff(t_eval) <= 0) or t_eval[0] <= 0:
        raise ReducerlabError("t_eval must be increasing times > 0")
    n = system.n
    y = np.zeros(2 * n) if y0 is None else np.asarray(y0, float).copy()
    if y.shape != (2 * n,):
        raise ReducerlabError(f"y0 must have shape ({2 * n},), got {y.shape}")
    t_end = float(t_eval[-1])
    try:
        T = forcing_period(system)
        k = np.arange(0, math.ceil(t_end / T) + 1)
        jumps = (k[:, None] + law_breaks(system, T)).ravel() * T
    except ReducerlabError:
        T, jumps = t_end, np.empty(0)
    jumps = np.unique(np.append(jumps[(jumps > 0) & (jumps < t_end)], t_end))
    events = []
    for m in range(system.G.shape[0]):
        h = system.half_backlash[m]
        if h <= 0:
            continue
        for sgn in (1.0, -1.0):

            def ev(t: float, yy: NDArray, m: int = m, sgn: float = sgn, h: float = h) -> float:
                e = evaluate_flat(int(system.e_kind[m]), system.e_params[m], t)[0]
                return float(system.G[m] @ yy[:n] - e - sgn * h)

            ev.terminal = True  # type: ignore[attr-defined]
            events.append(ev)
    out = np.full((t_eval.size, 2 * n), np.nan)
    t0 = 0.0
    tiny = 1e-9 * T
    t_seg = 0.0
    for t1 in jumps:
        lo, hi = t_seg + 1e-12 * T, t1 - 1e-12 * T
        t_seg = t1

        def rhs(t: float, yy: NDArray, lo: float = lo, hi: float = hi) -> NDArray:
            # laws are read just inside the segment: a jump at its ends is seen from
            # the correct side
            return system.rhs(min(max(t, lo), hi), yy)

        while t0 < t1:
            sol = scipy.integrate.solve_ivp(
                rhs, (t0, t1), y, method="DOP853", rtol=rtol, atol=atol,
                events=events or None, dense_output=True,
            )  # fmt: skip
            if not sol.success:
                raise ReducerlabError(f"reference integration failed after t = {t0:.6g} s")
            t_stop = float(sol.t[-1])
            if sol.status == 1 and t_stop - t0 < tiny:
                # an event at the restart point itself: step over it without events
                sol = scipy.integrate.solve_ivp(
                    rhs, (t0, min(t0 + tiny, t1)), y, method="DOP853", rtol=rtol,
                    atol=atol, dense_output=True,
                )  # fmt: skip
                t_stop = float(sol.t[-1])
            mask = (t_eval > t0) & (t_eval <= t_stop)
            if mask.any():
                out[mask] = sol.sol(t_eval[mask]).T
            y = sol.y[:, -1].copy()
            t0 = t_stop
    return out
