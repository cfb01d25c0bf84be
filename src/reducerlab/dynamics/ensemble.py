"""Integration of an ensemble of systems of one structure with the compiled RK4 kernel
(:mod:`.kernel`), or the one-period maps (:mod:`.maps`) where the teeth stay in
contact: Poincaré points, histories, mesh deflections and Lyapunov exponents."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..model import NonlinearSystem
from .accuracy import ACCURACY, PILOT_PERIODS, accurate_steps
from .coordinates import static_states
from .guards import raise_diverged, state_bounds
from .lyapunov import LYAPUNOV_D0
from .prepare import linear_lines, prepare, subset, with_steps
from .runsize import run_estimate

__all__ = ["Ensemble", "ensemble"]


@dataclass(frozen=True)
class Ensemble:
    """Result of :func:`ensemble`: Poincaré states (member, point, state), the history of
    the last periods (member, step, state), the mesh deflections at the Poincaré points
    (member, point, line), the period and the step times of the history."""

    poincare: NDArray[np.float64]
    history: NDArray[np.float64]
    delta_poincare: NDArray[np.float64]
    delta_history: NDArray[np.float64]
    period: NDArray[np.float64]
    history_time: NDArray[np.float64]  # (member, step), s
    systems: list[NonlinearSystem]
    steps_per_period: int = 0  # RK4 steps per period used
    diverged: NDArray[np.bool_] | None = None  # (member,), with on_divergence="mark"
    exponent: NDArray[np.float64] | None = None  # (member,), 1/s, with exponents=True
    mapped: NDArray[np.bool_] | None = None  # (member,): fast-forwarded by one-period maps


def ensemble(
    systems: Sequence[NonlinearSystem],
    *,
    periods: int = 600,
    keep: int = 100,
    history: int = 0,
    steps_per_period: int | None = None,
    y0: NDArray[np.float64] | None = None,
    limit: float | None = None,
    labels: Sequence[str] | None = None,
    period: float | None = None,
    accuracy: float = ACCURACY,
    on_divergence: str = "raise",
    exponents: bool = False,
    method: str = "auto",
) -> Ensemble:
    """Integrate systems of identical structure with the compiled RK4 kernel.

    Parameters
    ----------
    systems : sequence of NonlinearSystem
        Same DOFs, lines and law kinds; parameter values may differ.
    periods : int
        Forcing periods to integrate (transient included).
    keep : int
        Poincaré points kept: the states at the start of the last ``keep`` periods.
    history : int
        Periods at the end whose every step is returned (phase plots, spectra).
    steps_per_period : int, optional
        Overrides :func:`~reducerlab.dynamics.steps.steps_for` (the largest over the
        members is used).
    y0 : array, optional
        Initial states (member, 2n) or (2n,); zeros by default.
    limit : float, optional
        |state component| above this counts as divergence (in the system's
        coordinates: after rigid-motion removal they are mass-weighted modal amplitudes,
        not metres); ``math.inf``: only a non-finite state (overflow, NaN) does. By
        default each member gets the bounds of :func:`state_bounds`: 1e6 times its
        displacement scale (static deflection under the peak loads, initial state,
        mesh clearances), and that times its highest frequency for velocities.
    labels : sequence of str
        Names of the members for error messages (parameter values).
    period : float, optional
        Sampling period (s) when the systems have no periodic law.
    accuracy : float
        Target error of the Poincaré points relative to each member's displacement
        scale (and that scale times its highest frequency for velocities), default
        1e-6: the step count is the smallest that meets it on the attractor
        (:func:`accurate_steps`); ignored when ``steps_per_period`` is given.
    on_divergence : {"raise", "mark"}
        A member that leaves its bounds during the run raises ``DivergenceError``
        (default), or with ``"mark"`` is flagged in :attr:`Ensemble.diverged` with NaN
        rows from the divergence on, and the other members' results are kept.
    exponents : bool
        Also the largest Lyapunov exponent of each member (1/s) over its last ``keep``
        periods, from the same trajectory as the points (:attr:`Ensemble.exponent`):
        every member runs beside a perturbed copy inside the compiled kernel
        (Benettin's renormalisation after every period, as :func:`lyapunov`), at twice
        the cost of the trajectory alone.
    method : {"auto", "rk4", "maps"}
        ``"rk4"`` integrates every period with the compiled RK4 kernel. ``"maps"``
        first tries the one-period map of the contact system (:mod:`.maps`): exact
        while every line with backlash stays in contact, which it checks in every
        period (members whose teeth would separate are integrated by RK4 from the
        start); the last ``history`` periods are always RK4's. ``"auto"`` (default)
        takes the map where it pays: every law repeats within the period, no cubic
        or power-law line, at least ``4 (2n + 1)`` periods, and not every member's teeth separating
        in the first period (one period of RK4 tells:
        :func:`~reducerlab.dynamics.maps.separate_at_once`).

    Raises
    ------
    DivergenceError
        Before integrating, when a member's linear part has a divergent mode
        (:func:`~reducerlab.dynamics.guards.check_stability`); during it, when a state
        component leaves its bound or becomes non-finite: the message names the member
        (``labels``), the time and the physical DOFs that dominate the motion.
    """
    from .kernel import block_width, rk4_ensemble
    from .kernel_laws import law_values
    from .maps import contact_sides, map_run, map_steps, maps_pay, separate_at_once

    if not systems:
        raise ReducerlabError("ensemble: no systems")
    s0 = systems[0]
    if not (isinstance(periods, int) and isinstance(keep, int) and 1 <= keep <= periods):
        raise ReducerlabError(f"need 1 <= keep <= periods, got keep={keep}, periods={periods}")
    if not (isinstance(history, int) and 0 <= history <= periods):
        raise ReducerlabError(f"history must be in [0, periods], got {history!r}")
    E, n = len(systems), s0.n
    if labels is not None and len(labels) != E:
        raise ReducerlabError(f"labels: {len(labels)} names for {E} members")
    if y0 is not None:
        y0 = np.asarray(y0, float)
        if y0.shape not in ((2 * n,), (E, 2 * n)):
            raise ReducerlabError(
                f"y0 must have shape ({2 * n},) or ({E}, {2 * n}), got {y0.shape}"
            )
    if limit is not None and not (isinstance(limit, int | float) and limit > 0):
        raise ReducerlabError(f"limit must be a number > 0, got {limit!r}")
    if on_divergence not in ("raise", "mark"):
        raise ReducerlabError(f"on_divergence must be 'raise' or 'mark', got {on_divergence!r}")
    L = s0.G.shape[0]
    prep = prepare(systems, steps_per_period, period, labels)
    T, N = prep.period, prep.steps
    size = (E, periods, N, n, L, keep, history, exponents)
    run_estimate("integration", *size, at_least=steps_per_period is None).check()
    Y0 = (
        np.zeros((E, 2 * n))
        if y0 is None
        else np.broadcast_to(np.asarray(y0, float), (E, 2 * n)).copy()
    )
    if not np.all(np.isfinite(Y0)):
        raise ReducerlabError("y0: the initial state must be finite")
    bounds = state_bounds(systems, Y0, T) if limit is None else np.full((E, 2 * n), float(limit))
    if method not in ("auto", "rk4", "maps"):
        raise ReducerlabError(f"method must be 'auto', 'rk4' or 'maps', got {method!r}")

    maps = None
    cache: dict = {}
    if prep.periodic and (method == "maps" or (method == "auto" and maps_pay(n, periods))):
        sides = contact_sides(prep.arrays, static_states(systems))
        if linear_lines(prep.arrays) and np.any(np.all(sides != 0, axis=1)):
            maps = sides
            # "auto": not where every member's teeth separate in the first period (the
            # maps would fail there after costing 2n + 1 periods each)
            if method == "auto" and np.all(separate_at_once(prep, Y0, bounds, sides)):
                maps = None
    if steps_per_period is None:
        if maps is not None:
            N = map_steps(prep, systems, Y0, bounds, accuracy, min(periods, PILOT_PERIODS),
                           maps, cache)  # fmt: skip
        else:
            N = accurate_steps(prep, systems, Y0, bounds, accuracy, min(periods, PILOT_PERIODS))
        prep = with_steps(prep, systems, N)
        N = prep.steps
        run_estimate("integration", E, periods, N, n, L, keep, history, exponents).check()

    def rk4_run(idx: NDArray[np.intp], Ys: NDArray[np.float64]) -> tuple:
        """Poincaré states, history, status and exponents of members ``idx``."""
        sub = subset(prep, idx)
        Tk, bk, Ek = T[idx], bounds[idx], idx.size
        if not exponents:
            P, H, st, _ = rk4_ensemble(
                *sub.arrays, Ys, np.zeros(Ek), Tk, sub.offs, sub.dts, sub.periodic,
                periods, keep, history, bk, block_width(Ek), -1, 0.0,
            )  # fmt: skip
            return P, H, st, None
        # each member beside its perturbed copy: pairs in one kernel call
        two = subset(prep, np.repeat(idx, 2))
        P, H, st, logs = rk4_ensemble(
            *two.arrays, np.repeat(Ys, 2, axis=0), np.zeros(2 * Ek), np.repeat(Tk, 2),
            two.offs, two.dts, two.periodic, periods, keep, history,
            np.repeat(bk, 2, axis=0), block_width(2 * Ek), periods - keep, LYAPUNOV_D0,
        )  # fmt: skip
        P, H, st = P[0::2], H[0::2], st[0::2]
        lam = logs[0::2] / (keep * Tk)
        lam[st[:, 0] != 0] = np.nan
        return P, H, st, lam

    if maps is None:
        poincare, hist, status, exponent = rk4_run(np.arange(E), Y0)
        mapped = np.zeros(E, bool)
    else:
        poincare, hist, status, exponent, mapped = map_run(
            prep, Y0, bounds, periods, keep, history, exponents, maps, rk4_run, cache
        )
    diverged = status[:, 0] != 0
    if on_divergence == "raise":
        raise_diverged(systems, status, bounds, labels, N)
    G = prep.arrays.G
    # mesh deflections G q - e(t) at the Poincare times and along the history
    tP = (periods - keep + np.arange(keep + 1))[None, :] * T[:, None]
    start = periods - history
    ends = prep.offs + prep.dts  # (E, N): end of each step from the period start
    tH = (
        ((start + np.arange(history))[None, :, None] * T[:, None, None] + ends[:, None, :])
        .reshape(E, history * N)
    )  # fmt: skip
    width = tH.shape[1]
    e_kind, e_par = prep.arrays.e_kind, prep.arrays.e_par
    eP = law_values(e_kind, e_par, np.ascontiguousarray(tP * np.ones((E, 1))))[0]
    dP = np.einsum("eln,epn->epl", G, poincare[:, :, :n]) - eP
    if history:
        hist = hist[:, :width]
        eH = law_values(e_kind, e_par, np.ascontiguousarray(tH))[0]
        dH = np.einsum("eln,epn->epl", G, hist[:, :, :n]) - eH
    else:
        dH = np.empty((E, 0, L))
    times = tH
    return Ensemble(poincare, hist, dP, dH, T, times, list(systems), N, diverged, exponent,
                    mapped)  # fmt: skip
