"""The RK4 step of the compiled kernel (:mod:`.kernel`) and its located re-step at
backlash crossings.

A block of members advances in lock-step (:func:`rk4`, members innermost). After each
step :func:`event_times` finds every member's first backlash-boundary crossing inside
the step, and :func:`restep` steps the crossing members again, to the crossing and
from it: one at a time where few cross, the whole block in lock-step (the others with
zero-length steps) where many do. The law rows at their sub-step times are
interpolated from the step's table rows, not evaluated again (evaluating them, Fourier
sums and segment searches for every member of the block, was most of a crossing's
cost): quadratically through the step's start, middle and end. The laws are smooth
within a step (its ends are aligned with the stiffness-law jumps), so the error is
O(h^3) in the laws over one sub-step of length O(h) per crossing, O(h^4) in the
state, and the number of crossing steps per period does not grow as the step falls:
the located steps keep RK4's fourth order (docs/assumptions.md, "Located backlash
crossings").
"""

from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["event_times", "restep", "rk4", "workspace"]

_FM = {"contract", "reassoc", "nsz", "arcp"}


@nb.njit(cache=True, fastmath=_FM, inline="always")
def _elastic(k: float, f: float, p: float, r: float) -> float:
    """Elastic line force (N) under the deflection ``f`` (m) beyond the backlash: ``k f``
    for the load exponent ``p = 1``, else the power law ``k (r / p) sgn(f) (|f| / r)^p``
    whose slope is the law's ``k`` at the reference deflection ``r`` (m)
    (``model.system.power_force`` is the reference)."""
    if p == 1.0 or f == 0.0:
        return k * f
    a = k * r / p * (abs(f) / r) ** p
    return a if f > 0.0 else -a


@nb.njit(cache=True, fastmath=_FM)
def rhs(tab, row, y, out, MK, MC, pi, pj, MG, G, hb, cm, kl, d, dv, fm):
    """State derivative of every member of a block: ``out[2n, B]`` from ``y[2n, B]``
    (``kl`` (L, 3, B): each line's cubic stiffness, load exponent and reference
    deflection);
    ``(pi, pj)`` are the entries of ``M^-1 K`` and ``M^-1 C`` that are nonzero for some
    member (in modal coordinates after rigid-motion removal ``M^-1 K`` is diagonal)."""
    n = MK.shape[0]
    L = G.shape[0]
    B = y.shape[1]
    for i in range(n):
        for b in range(B):
            out[i, b] = y[n + i, b]
            out[n + i, b] = tab[row, 3 * L + i, b]
    for p in range(pi.shape[0]):
        i = pi[p]
        j = pj[p]
        for b in range(B):
            out[n + i, b] -= MK[i, j, b] * y[j, b] + MC[i, j, b] * y[n + j, b]
    for m in range(L):
        for b in range(B):
            d[b] = -tab[row, L + m, b]
            dv[b] = -tab[row, 2 * L + m, b]
        for i in range(n):
            for b in range(B):
                d[b] += G[m, i, b] * y[i, b]
                dv[b] += G[m, i, b] * y[n + i, b]
        for b in range(B):
            x = d[b]
            h = hb[m, b]
            f = x - min(max(x, -h), h)
            # the cubic term only where kl != 0: no 0 * inf when f^3 overflows
            c3 = kl[m, 0, b] * (f * f * f) if kl[m, 0, b] != 0.0 else 0.0
            el = _elastic(tab[row, m, b], f, kl[m, 1, b], kl[m, 2, b])
            fm[b] = el + c3 + cm[m, b] * dv[b]
        for i in range(n):
            for b in range(B):
                out[n + i, b] -= MG[i, m, b] * fm[b]


@nb.njit(cache=True, fastmath=_FM)
def rk4(tab, r0, y, dtv, k1, k2, k3s, k4, tmp, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb, d, dv, fm):
    """One RK4 step of every member of a block, in place: member ``b`` advances by
    ``dtv[b]`` (s; 0: unchanged) with the law rows ``r0`` (start), ``r0 + 1`` (middle)
    and ``r0 + 2`` (end) of ``tab``."""
    n2 = y.shape[0]
    nb_ = y.shape[1]
    rhs(tab, r0, y, k1, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb, d, dv, fm)
    for i in range(n2):
        for b in range(nb_):
            tmp[i, b] = y[i, b] + 0.5 * dtv[b] * k1[i, b]
    rhs(tab, r0 + 1, tmp, k2, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb, d, dv, fm)
    for i in range(n2):
        for b in range(nb_):
            tmp[i, b] = y[i, b] + 0.5 * dtv[b] * k2[i, b]
    rhs(tab, r0 + 1, tmp, k3s, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb, d, dv, fm)
    for i in range(n2):
        for b in range(nb_):
            tmp[i, b] = y[i, b] + dtv[b] * k3s[i, b]
    rhs(tab, r0 + 2, tmp, k4, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb, d, dv, fm)
    for i in range(n2):
        for b in range(nb_):
            y[i, b] += (dtv[b] / 6.0) * (k1[i, b] + 2.0 * k2[i, b] + 2.0 * k3s[i, b] + k4[i, b])


@nb.njit(cache=True, inline="always")
def _region(x: float, h: float) -> int:
    """Contact state of a deflection: 1 drive side, -1 back side, 0 apart."""
    if x > h:
        return 1
    if x < -h:
        return -1
    return 0


@nb.njit(cache=True, inline="always")
def _hermite_root(p0: float, p1: float, m0: float, m1: float) -> float:
    """Root in [0, 1] of the cubic Hermite polynomial with values ``p0, p1`` (of
    opposite signs, or ``p1 = 0``) and slopes ``m0, m1`` (per unit of the interval) at
    its ends: Newton's method from the secant point, kept inside the bracket that
    holds the sign change (a bisection where a Newton step leaves it), stopped when a
    step moves less than 1e-13 of the interval (Newton's last step then leaves an error
    far below that; 40 bisections gave 5e-13)."""
    lo, hi = 0.0, 1.0
    pos = p0 > 0.0
    th = p0 / (p0 - p1) if p0 != p1 else 0.5
    for _ in range(100):
        t2 = th * th
        t3 = t2 * th
        val = (
            (2 * t3 - 3 * t2 + 1) * p0
            + (t3 - 2 * t2 + th) * m0
            + (-2 * t3 + 3 * t2) * p1
            + (t3 - t2) * m1
        )
        if val == 0.0:
            return th
        if (val > 0.0) == pos:
            lo = th
        else:
            hi = th
        der = (6 * t2 - 6 * th) * (p0 - p1) + (3 * t2 - 4 * th + 1) * m0 + (3 * t2 - 2 * th) * m1
        nxt = th - val / der if der != 0.0 else -1.0
        if not (lo < nxt < hi):
            nxt = 0.5 * (lo + hi)
        if abs(nxt - th) <= 1e-13 or hi - lo <= 1e-13:
            return nxt
        th = nxt
    return th


@nb.njit(cache=True, fastmath=_FM)
def _changes(tab, r0, y0, y1, dtv, Gb, hbb, klb, dd, flag) -> bool:
    """Whether the contact state of some line of member ``b`` differs between the step's
    ends (``flag[b]`` 1, else 0; members with no time step: 0), in loops over the
    members that the compiler vectorises (``dd`` (2, B): scratch). Lines with backlash
    count, and lines with a power law (load exponent ``klb[m, 1] != 1``) without
    backlash too: their force's higher derivatives are singular where the deflection
    changes sign."""
    L = Gb.shape[0]
    n = Gb.shape[1]
    B = y0.shape[1]
    for b in range(B):
        flag[b] = 0.0
    for m in range(L):
        for b in range(B):
            dd[0, b] = -tab[r0, L + m, b]
            dd[1, b] = -tab[r0 + 2, L + m, b]
        for i in range(n):
            for b in range(B):
                dd[0, b] += Gb[m, i, b] * y0[i, b]
                dd[1, b] += Gb[m, i, b] * y1[i, b]
        for b in range(B):
            h = hbb[m, b]
            x0 = dd[0, b]
            x1 = dd[1, b]
            up = (x0 > h) != (x1 > h)
            down = (x0 < -h) != (x1 < -h)
            located = (h > 0.0) | (klb[m, 1, b] != 1.0)
            flag[b] = max(flag[b], 1.0 if (up | down) & located & (dtv[b] > 0.0) else 0.0)
    anyc = 0.0
    for b in range(B):
        anyc = max(anyc, flag[b])
    return anyc > 0.0


@nb.njit(cache=True)
def event_times(tab, r0, y0, y1, dtv, Gb, hbb, klb, tau, dd, flag) -> bool:
    """First backlash-boundary crossing of each member within its step (``tau[b]``, s
    from the step start; ``dtv[b]`` when none; a power-law line without backlash
    crosses where its deflection changes sign, ``klb`` (L, 3, B)): the members whose
    contact state differs between the step's ends are found first (:func:`_changes`;
    ``dd`` (2, B) and ``flag`` (B,) are its scratch); for those the deflection
    ``G q - e`` of every such line is interpolated by the cubic Hermite polynomial of
    its values and rates at both ends of the step (error O(h^4)) and the crossing found by
    :func:`_hermite_root`. Returns whether any member crosses."""
    L = Gb.shape[0]
    n = Gb.shape[1]
    nb_ = y0.shape[1]
    for b in range(nb_):
        tau[b] = dtv[b]
    if not _changes(tab, r0, y0, y1, dtv, Gb, hbb, klb, dd, flag):
        return False
    anyx = False
    for b in range(nb_):
        if flag[b] == 0.0:
            continue
        dt = dtv[b]
        best = 1.0
        for m in range(L):
            h = hbb[m, b]
            if h <= 0.0 and klb[m, 1, b] == 1.0:
                continue
            d0 = -tab[r0, L + m, b]
            d1 = -tab[r0 + 2, L + m, b]
            v0 = -tab[r0, 2 * L + m, b]
            v1 = -tab[r0 + 2, 2 * L + m, b]
            for i in range(n):
                g = Gb[m, i, b]
                d0 += g * y0[i, b]
                d1 += g * y1[i, b]
                v0 += g * y0[n + i, b]
                v1 += g * y1[n + i, b]
            a = _region(d0, h)
            c = _region(d1, h)
            if a == c:
                continue
            if a == 1:
                edge = h
            elif a == -1:
                edge = -h
            else:
                edge = h if c == 1 else -h
            th = _hermite_root(d0 - edge, d1 - edge, v0 * dt, v1 * dt)
            if th < best:
                best = th
        if 1e-9 < best < 1.0 - 1e-9:
            tau[b] = best * dt
            anyx = True
    return anyx


@nb.njit(cache=True)
def workspace(n: int, L: int, W: int, B: int):
    """Scratch arrays of :func:`restep` and :func:`event_times` for blocks of ``B``
    members of a model of ``n`` coordinates and ``L`` lines whose law table has ``W``
    columns."""
    return (
        np.zeros((6, W)),  # law rows at the sub-step sample times (one member)
        np.zeros((6, 2 * n)),  # state, stages k1 .. k4, stage state (one member)
        np.zeros((2, B)),  # deflections at the step's ends (event_times)
        np.zeros(B),  # contact change flags (event_times)
        np.zeros((6, W, B)),  # law rows at the sub-step sample times (block)
        np.zeros((2, B)),  # time steps to the crossing and from it (block)
    )


@nb.njit(cache=True, fastmath=_FM, inline="always")
def _rhs1(rows, s, y, out, b, MK, MC, pi, pj, MG, G, hb, cm, kl):
    """:func:`rhs` of block member ``b`` alone: ``out`` (2n) from ``y`` (2n) with the
    law row ``rows[s]``."""
    n = MK.shape[0]
    L = G.shape[0]
    for i in range(n):
        out[i] = y[n + i]
        out[n + i] = rows[s, 3 * L + i]
    for p in range(pi.shape[0]):
        i = pi[p]
        j = pj[p]
        out[n + i] -= MK[i, j, b] * y[j] + MC[i, j, b] * y[n + j]
    for m in range(L):
        x = -rows[s, L + m]
        dv = -rows[s, 2 * L + m]
        for i in range(n):
            x += G[m, i, b] * y[i]
            dv += G[m, i, b] * y[n + i]
        h = hb[m, b]
        f = x - min(max(x, -h), h)
        c3 = kl[m, 0, b] * (f * f * f) if kl[m, 0, b] != 0.0 else 0.0
        fm = _elastic(rows[s, m], f, kl[m, 1, b], kl[m, 2, b]) + c3 + cm[m, b] * dv
        for i in range(n):
            out[n + i] -= MG[i, m, b] * fm


@nb.njit(cache=True, fastmath=_FM, inline="always")
def _rk41(rows, s, st, dt, b, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb):
    """One RK4 step of length ``dt`` (s) of block member ``b`` alone, its state in
    ``st[0]`` (stages in ``st[1:5]``, stage state in ``st[5]``), with the law rows
    ``s, s + 1, s + 2`` of ``rows``."""
    y, k1, k2, k3s, k4, tmp = st[0], st[1], st[2], st[3], st[4], st[5]
    n2 = y.shape[0]
    _rhs1(rows, s, y, k1, b, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb)
    for i in range(n2):
        tmp[i] = y[i] + 0.5 * dt * k1[i]
    _rhs1(rows, s + 1, tmp, k2, b, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb)
    for i in range(n2):
        tmp[i] = y[i] + 0.5 * dt * k2[i]
    _rhs1(rows, s + 1, tmp, k3s, b, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb)
    for i in range(n2):
        tmp[i] = y[i] + dt * k3s[i]
    _rhs1(rows, s + 2, tmp, k4, b, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb)
    for i in range(n2):
        y[i] += (dt / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3s[i] + k4[i])


@nb.njit(cache=True, inline="always")
def _rows_at(tab, r0, b, x, s, c) -> float:
    """Column ``c`` of law row ``s`` (0 .. 5) of block member ``b``: the law rows at the sample
    times of the steps to the crossing at the fraction ``x`` of the step and from it,
    interpolated from the step's rows ``r0, r0 + 1, r0 + 2`` (quadratic Lagrange
    through 0, 1/2, 1: exact at the nodes)."""
    u = 0.5 * s * x if s < 3 else x + 0.5 * (s - 3) * (1.0 - x)
    w0 = 2.0 * (u - 0.5) * (u - 1.0)
    w1 = 4.0 * u * (1.0 - u)
    w2 = u * (2.0 * u - 1.0)
    return w0 * tab[r0, c, b] + w1 * tab[r0 + 1, c, b] + w2 * tab[r0 + 2, c, b]


@nb.njit(cache=True, fastmath=_FM)
def restep(tab, r0, y, yprev, dtv, tau, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb, ws, k1, k2,
           k3s, k4, tmp, d, dv, fm) -> None:  # fmt: skip
    """Step again, from ``yprev`` (the step's start), every member of the block that
    crosses a backlash boundary inside its step (``tau[b] < dtv[b]``, from
    :func:`event_times`): to the crossing and from it, two RK4 steps; the result
    replaces its state in ``y``, the other members keep their step. The law rows at the
    sub-step sample times are interpolated from the step's rows ``r0, r0 + 1, r0 + 2``
    (quadratic, :func:`_rows_at`). Few crossing members step one at a time (``ws``
    from :func:`workspace`); where more than ``B / 8 + 1`` of the block's ``B`` cross,
    the whole block steps in lock-step (the others with zero-length steps; ``k1 ..
    fm``: :func:`rk4`'s scratch)."""
    rows, st, sub, dts = ws[0], ws[1], ws[4], ws[5]
    n2 = y.shape[0]
    W = tab.shape[1]
    B = y.shape[1]
    count = 0
    for b in range(B):
        if tau[b] < dtv[b]:
            count += 1
    if count > B // 8 + 1:
        for b in range(B):
            cross = tau[b] < dtv[b]
            x = tau[b] / dtv[b] if cross else 1.0
            dts[0, b] = tau[b] if cross else 0.0
            dts[1, b] = dtv[b] - tau[b] if cross else 0.0
            for s in range(6):
                for c in range(W):
                    sub[s, c, b] = _rows_at(tab, r0, b, x, s, c)
            if cross:
                for i in range(n2):
                    y[i, b] = yprev[i, b]
        rk4(sub, 0, y, dts[0], k1, k2, k3s, k4, tmp, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb, d,
            dv, fm)  # fmt: skip
        rk4(sub, 3, y, dts[1], k1, k2, k3s, k4, tmp, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb, d,
            dv, fm)  # fmt: skip
        return
    for b in range(B):
        if not tau[b] < dtv[b]:
            continue
        full = dtv[b]
        x = tau[b] / full
        for s in range(6):
            for c in range(W):
                rows[s, c] = _rows_at(tab, r0, b, x, s, c)
        for i in range(n2):
            st[0, i] = yprev[i, b]
        _rk41(rows, 0, st, tau[b], b, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb)
        _rk41(rows, 3, st, full - tau[b], b, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb)
        for i in range(n2):
            y[i, b] = st[0, i]
