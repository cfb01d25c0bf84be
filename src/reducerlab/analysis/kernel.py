"""Compiled (numba) fixed-step RK4 integration of an ensemble of nonlinear systems.

The kernel works on the flat arrays of :class:`~reducerlab.model.NonlinearSystem`,
stacked over an ensemble (one member per parameter value): mass inverse, damping and
stiffness matrices, mesh projection rows, stiffness/error/load laws as
``(kind, params)`` rows (:func:`reducerlab.model.laws.evaluate_flat` is the reference
for the law evaluation here). Members run in parallel threads; each period of the
forcing is split into segments at the stiffness law's discontinuities so that no RK4
step straddles a jump.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

__all__ = ["LAW_CONSTANT", "LAW_FOURIER", "LAW_PIECEWISE", "eval_law", "rk4_ensemble"]

from ..model.laws import LAW_CONSTANT, LAW_FOURIER, LAW_PIECEWISE


@nb.njit(cache=True, fastmath=False)
def eval_law(kind: int, p: np.ndarray, t: float) -> tuple[float, float]:
    """Value and derivative of a flat law at time ``t`` (mirrors ``evaluate_flat``)."""
    if kind == LAW_CONSTANT:
        return p[0], 0.0
    if kind == LAW_FOURIER:
        mean, omega, n = p[0], p[1], int(p[2])
        val, der = mean, 0.0
        for r in range(1, n + 1):
            arg = r * omega * t + p[2 + n + r]
            val += p[2 + r] * math.cos(arg)
            der -= p[2 + r] * r * omega * math.sin(arg)
        return val, der
    period, t0, n, m = p[0], p[1], int(p[2]), int(p[3])
    s = (t - t0) / period
    s = s - math.floor(s)
    i = 0
    while i + 1 < n and p[4 + i + 1] <= s:
        i += 1
    base = 4 + n + i * m
    val, der = 0.0, 0.0
    for q in range(m - 1, -1, -1):
        if q < m - 1:
            der = der * s + val
        val = val * s + p[base + q]
    return val, der / period


@nb.njit(cache=True, inline="always")
def _rhs(t, y, out, Minv, C, K, G, k_kind, k_par, cm, hb, e_kind, e_par, B, f_kind, f_par, F, Fm):
    n = Minv.shape[0]
    L = G.shape[0]
    for i in range(n):
        F[i] = 0.0
    for j in range(f_kind.shape[0]):
        v, _ = eval_law(f_kind[j], f_par[j], t)
        for i in range(n):
            F[i] += B[i, j] * v
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += C[i, j] * y[n + j] + K[i, j] * y[j]
        F[i] -= acc
    for m in range(L):
        k, _ = eval_law(k_kind[m], k_par[m], t)
        e, de = eval_law(e_kind[m], e_par[m], t)
        d, dv = -e, -de
        for i in range(n):
            d += G[m, i] * y[i]
            dv += G[m, i] * y[n + i]
        h = hb[m]
        if d > h:
            f = d - h
        elif d < -h:
            f = d + h
        else:
            f = 0.0
        Fm[m] = k * f + cm[m] * dv
        for i in range(n):
            F[i] -= G[m, i] * Fm[m]
    for i in range(n):
        out[i] = y[n + i]
        acc = 0.0
        for j in range(n):
            acc += Minv[i, j] * F[j]
        out[n + i] = acc


@nb.njit(parallel=True, cache=True)
def rk4_ensemble(
    Minv,
    C,
    K,
    G,
    k_kind,
    k_par,
    cm,
    hb,
    e_kind,
    e_par,
    B,
    f_kind,
    f_par,
    y0,
    t_start,
    period,
    seg_start,
    seg_steps,
    n_periods,
    n_keep,
    n_hist,
    limit,
):
    """Integrate every member for ``n_periods`` forcing periods.

    Member ``e`` starts at time ``t_start[e]``. Returns ``poincare`` (E, n_keep, 2n):
    the state at the start of each of the last
    ``n_keep`` periods and at the end; ``hist`` (E, n_hist * steps, 2n): every step of
    the last ``n_hist`` periods; ``status`` (E, 3): (failed flag, time, state index)
    when a state became non-finite or exceeded ``limit``.
    """
    E, n2 = y0.shape
    S = seg_steps.shape[1]
    steps_per_period = np.zeros(E, np.int64)
    for e in range(E):
        steps_per_period[e] = seg_steps[e].sum()
    max_steps = steps_per_period.max()
    poincare = np.full((E, n_keep + 1, n2), np.nan)
    hist = np.full((E, max(n_hist, 0) * max_steps + 1, n2), np.nan)
    status = np.zeros((E, 3))
    for e in nb.prange(E):
        y = y0[e].copy()
        k1 = np.empty(n2)
        k2 = np.empty(n2)
        k3 = np.empty(n2)
        k4 = np.empty(n2)
        tmp = np.empty(n2)
        F = np.empty(n2 // 2)
        Fm = np.empty(G.shape[1])
        T = period[e]
        Me, Ce, Ke, Ge = Minv[e], C[e], K[e], G[e]
        kpe, cme, hbe, epe, Be, fpe = k_par[e], cm[e], hb[e], e_par[e], B[e], f_par[e]
        h_index = 0
        failed = False
        for p in range(n_periods):
            if p >= n_periods - n_keep:
                poincare[e, p - (n_periods - n_keep)] = y
            t_base = t_start[e] + p * T
            for s in range(S):
                ns = seg_steps[e, s]
                if ns == 0:
                    continue
                ta = t_base + seg_start[e, s] * T
                tb = t_base + seg_start[e, s + 1] * T
                dt = (tb - ta) / ns
                # stages at the segment ends are evaluated just inside it, so that a law
                # with a jump at a segment boundary is seen from the correct side
                inside = 1e-9 * dt
                for q in range(ns):
                    t = ta + q * dt
                    _rhs(
                        t + inside,
                        y,
                        k1,
                        Me,
                        Ce,
                        Ke,
                        Ge,
                        k_kind,
                        kpe,
                        cme,
                        hbe,
                        e_kind,
                        epe,
                        Be,
                        f_kind,
                        fpe,
                        F,
                        Fm,
                    )
                    for i in range(n2):
                        tmp[i] = y[i] + 0.5 * dt * k1[i]
                    _rhs(
                        t + 0.5 * dt,
                        tmp,
                        k2,
                        Me,
                        Ce,
                        Ke,
                        Ge,
                        k_kind,
                        kpe,
                        cme,
                        hbe,
                        e_kind,
                        epe,
                        Be,
                        f_kind,
                        fpe,
                        F,
                        Fm,
                    )
                    for i in range(n2):
                        tmp[i] = y[i] + 0.5 * dt * k2[i]
                    _rhs(
                        t + 0.5 * dt,
                        tmp,
                        k3,
                        Me,
                        Ce,
                        Ke,
                        Ge,
                        k_kind,
                        kpe,
                        cme,
                        hbe,
                        e_kind,
                        epe,
                        Be,
                        f_kind,
                        fpe,
                        F,
                        Fm,
                    )
                    for i in range(n2):
                        tmp[i] = y[i] + dt * k3[i]
                    _rhs(
                        t + dt - inside,
                        tmp,
                        k4,
                        Me,
                        Ce,
                        Ke,
                        Ge,
                        k_kind,
                        kpe,
                        cme,
                        hbe,
                        e_kind,
                        epe,
                        Be,
                        f_kind,
                        fpe,
                        F,
                        Fm,
                    )
                    for i in range(n2):
                        y[i] += dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])
                        if not (abs(y[i]) <= limit):
                            if not failed:
                                status[e, 0] = 1.0
                                status[e, 1] = t + dt
                                status[e, 2] = i
                            failed = True
                    if failed:
                        break
                    if p >= n_periods - n_hist:
                        hist[e, h_index] = y
                        h_index += 1
                if failed:
                    break
            if failed:
                break
        if not failed:
            poincare[e, n_keep] = y
    return poincare, hist, status
