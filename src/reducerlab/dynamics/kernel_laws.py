"""The laws of time inside the compiled kernel: their evaluation from the flat layout
(:mod:`reducerlab.model.layout`; :func:`reducerlab.model.laws.evaluate_flat` is the
reference), their tables at the RK4 sample times, and the step grid aligned with their
discontinuities."""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from ..model.layout import (
    CONSTANT_VALUE,
    FOURIER_COUNT,
    FOURIER_HEAD,
    FOURIER_MEAN,
    FOURIER_OMEGA,
    LAW_CONSTANT,
    LAW_FOURIER,
    PIECE_COUNT,
    PIECE_HEAD,
    PIECE_PERIOD,
    PIECE_T0,
    PIECE_WIDTH,
)

__all__ = [
    "eval_law",
    "law_row",
    "law_values",
    "step_grid",
    "tabulate",
]


@nb.njit(cache=True, fastmath=False)
def eval_law(kind: int, p: np.ndarray, t: float) -> tuple[float, float]:
    """Value and derivative of a flat law at time ``t`` (mirrors ``evaluate_flat``)."""
    if kind == LAW_CONSTANT:
        return p[CONSTANT_VALUE], 0.0
    if kind == LAW_FOURIER:
        mean, omega, n = p[FOURIER_MEAN], p[FOURIER_OMEGA], int(p[FOURIER_COUNT])
        val, der = mean, 0.0
        for r in range(1, n + 1):
            arg = r * omega * t + p[FOURIER_HEAD + n + r - 1]
            val += p[FOURIER_HEAD + r - 1] * math.cos(arg)
            der -= p[FOURIER_HEAD + r - 1] * r * omega * math.sin(arg)
        return val, der
    period, t0 = p[PIECE_PERIOD], p[PIECE_T0]
    n, m = int(p[PIECE_COUNT]), int(p[PIECE_WIDTH])
    s = (t - t0) / period
    s = s - math.floor(s)
    i = 0
    while i + 1 < n and p[PIECE_HEAD + i + 1] <= s:
        i += 1
    base = PIECE_HEAD + n + i * m
    val, der = 0.0, 0.0
    for q in range(m - 1, -1, -1):
        if q < m - 1:
            der = der * s + val
        val = val * s + p[base + q]
    return val, der / period


@nb.njit(cache=True)
def step_grid(edges, counts, N):
    """Step starts and lengths (phases) of ``N`` steps per period for each member, whose
    period is cut at ``edges[e, :counts[e]]`` (increasing, starting at 0, ending at 1):
    each segment gets its share of ``N`` by largest remainder and at least one step."""
    E = edges.shape[0]
    offs = np.empty((E, N))
    dts = np.empty((E, N))
    for e in range(E):
        S = counts[e] - 1
        raw = np.empty(S)
        steps = np.empty(S, np.int64)
        total = 0
        for j in range(S):
            raw[j] = N * (edges[e, j + 1] - edges[e, j])
            steps[j] = max(1, math.floor(raw[j]))
            total += steps[j]
        while total < N:
            best, jb = -np.inf, 0
            for j in range(S):
                if raw[j] - steps[j] > best:
                    best, jb = raw[j] - steps[j], j
            steps[jb] += 1
            total += 1
        while total > N:
            best, jb = np.inf, -1
            for j in range(S):
                if steps[j] > 1 and raw[j] - steps[j] < best:
                    best, jb = raw[j] - steps[j], j
            steps[jb] -= 1
            total -= 1
        q = 0
        for j in range(S):
            a, b = edges[e, j], edges[e, j + 1]
            for i in range(steps[j]):
                offs[e, q] = a + (b - a) * i / steps[j]
                dts[e, q] = (b - a) / steps[j]
                q += 1
    return offs, dts


@nb.njit(cache=True, parallel=True)
def law_values(kinds, params, times):
    """Values and time derivatives, each ``(E, P, L)``, of the laws ``kinds`` (L,) with
    per-member ``params`` (E, L, width) at per-member ``times`` (E, P) (s); NaN where
    the time is NaN."""
    E, P = times.shape
    L = kinds.shape[0]
    val = np.empty((E, P, L))
    der = np.empty((E, P, L))
    for e in nb.prange(E):
        for p in range(P):
            t = times[e, p]
            for m in range(L):
                if math.isnan(t):
                    val[e, p, m] = np.nan
                    der[e, p, m] = np.nan
                else:
                    v, dv = eval_law(kinds[m], params[e, m], t)
                    val[e, p, m] = v
                    der[e, p, m] = dv
    return val, der


@nb.njit(cache=True, inline="always")
def law_row(tab, row, b, e, mb, ts, k_kind, k_par, e_kind, e_par, MB, f_kind, f_par, fv):
    """``tab[row, :, b]`` for member ``e`` at time ``ts``: ``k`` (L), ``e`` (L),
    ``de/dt`` (L), then the load acceleration ``M^-1 B f`` (n) from ``MB[mb]``."""
    L = k_kind.shape[0]
    n = MB.shape[1]
    nf = f_kind.shape[0]
    for m in range(L):
        k, _ = eval_law(k_kind[m], k_par[e, m], ts)
        v, dv = eval_law(e_kind[m], e_par[e, m], ts)
        tab[row, m, b] = k
        tab[row, L + m, b] = v
        tab[row, 2 * L + m, b] = dv
    for j in range(nf):
        fv[j], _ = eval_law(f_kind[j], f_par[e, j], ts)
    for i in range(n):
        acc = 0.0
        for j in range(nf):
            acc += MB[mb, i, j] * fv[j]
        tab[row, 3 * L + i, b] = acc


@nb.njit(cache=True, inline="always")
def _rows_equal(par, e, p) -> bool:
    """Whether the law rows ``par[e]`` and ``par[p]`` (L, width) are equal."""
    for m in range(par.shape[1]):
        for j in range(par.shape[2]):
            if par[e, m, j] != par[p, m, j]:
                return False
    return True


@nb.njit(cache=True)
def _same_laws(e, lo, t_base, offs, dts, k_par, e_par, MB, f_par) -> bool:
    """Whether member ``e``'s law table equals member ``e - 1``'s: the same period
    start, steps, law rows and load matrix ``M^-1 B`` (the table is a function of these
    alone; the trajectories of one member in :func:`.maps.affine_maps` share it)."""
    p = e - 1
    if t_base[e] != t_base[p]:
        return False
    for q in range(offs.shape[1]):
        if offs[e, q] != offs[p, q] or dts[e, q] != dts[p, q]:
            return False
    if not (_rows_equal(k_par, e, p) and _rows_equal(e_par, e, p) and _rows_equal(f_par, e, p)):
        return False
    for i in range(MB.shape[1]):
        for j in range(MB.shape[2]):
            if MB[e - lo, i, j] != MB[p - lo, i, j]:
                return False
    return True


@nb.njit(cache=True)
def tabulate(tab, lo, hi, t_base, offs, dts, k_kind, k_par, e_kind, e_par, MB, f_kind, f_par):
    """Fill ``tab[3 N, W, B]`` for members ``lo:hi``: rows ``3q, 3q+1, 3q+2`` are the
    RK4 sample times of step ``q`` (just inside its start, its middle, just inside its
    end, so that a jump at a step boundary is seen from the correct side); columns are
    ``k`` (L), ``e`` (L), ``de/dt`` (L), then the load acceleration ``M^-1 B f`` (n).
    Slots past ``hi - lo`` repeat the last member. A member whose laws, steps and period
    start equal the previous member's (:func:`_same_laws`) takes its column: the same
    numbers, without evaluating the laws again (copied in one pass over the rows, slots
    innermost)."""
    N = offs.shape[1]
    W = tab.shape[2]
    fv = np.empty(f_kind.shape[0])
    src = np.empty(W, np.int64)  # the slot whose column each slot takes
    for e in range(lo, hi):
        b = e - lo
        if e > lo and _same_laws(e, lo, t_base, offs, dts, k_par, e_par, MB, f_par):
            src[b] = src[b - 1]
            continue
        src[b] = b
        for q in range(N):
            dt = dts[e, q]
            t = t_base[e] + offs[e, q]
            # just inside the step: 1e-9 of it, and beyond the rounding of t (the law's
            # phase (t - t0) / period is computed from the absolute time)
            inside = max(1e-9 * dt, 16.0 * 2.220446049250313e-16 * (abs(t) + dt))
            for s in range(3):
                ts = t + inside if s == 0 else (t + 0.5 * dt if s == 1 else t + dt - inside)
                law_row(tab, 3 * q + s, b, e, b, ts, k_kind, k_par, e_kind, e_par, MB,
                         f_kind, f_par, fv)  # fmt: skip
    for b in range(hi - lo, W):
        src[b] = src[hi - lo - 1]
    copies = False
    for b in range(W):
        if src[b] != b:
            copies = True
    if copies:
        for r in range(tab.shape[0]):
            for c in range(tab.shape[1]):
                for b in range(W):
                    tab[r, c, b] = tab[r, c, src[b]]
