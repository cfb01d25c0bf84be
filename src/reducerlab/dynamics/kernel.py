"""Compiled (numba) fixed-step RK4 integration of an ensemble of nonlinear systems.

The kernel works on the flat arrays of :class:`~reducerlab.model.NonlinearSystem`,
stacked over an ensemble (one member per parameter value). Its layout is *structure of
arrays*: every quantity carries the member index last, members are integrated in
lock-step in blocks of :data:`BLOCK` and every inner loop runs over the members of a
block, contiguous in memory, so that the compiler emits SIMD instructions; blocks run in
parallel threads.

All members take the same number of steps per forcing period, aligned with their own
stiffness-law discontinuities (so no step straddles a jump; the step lengths differ
between members). The time laws (stiffness, error and its rate, loads) are tabulated at
the three RK4 sample times of every step of one period; when every law repeats within
the period (the usual case) the table is built once and reused for all periods, so the
inner loop does no trigonometry and no segment search. Otherwise it is rebuilt each
period. :func:`reducerlab.model.laws.evaluate_flat` is the reference for the law
evaluation here.

numba's cache (``cache=True``) is checked against this file only: after a change to
:mod:`.kernel_laws`, :mod:`.kernel_step` or :mod:`reducerlab.model.layout`, run
``scripts/warm_kernels.py`` (``make`` does), which removes the old caches before
compiling.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

from .kernel_laws import tabulate
from .kernel_step import event_times, restep, rk4, workspace

__all__ = ["BLOCK", "block_width", "rk4_ensemble"]

#: Most members integrated in lock-step by one thread (a multiple of the SIMD width);
#: smaller ensembles use smaller blocks so that every thread gets work.
BLOCK = 64
_FM = {"contract", "reassoc", "nsz", "arcp"}


def block_width(members: int) -> int:
    """Members per lock-step block: a multiple of 8 (the SIMD width of AVX-512), at most
    :data:`BLOCK`, small enough that every thread gets a block."""
    threads = nb.get_num_threads()
    per_thread = -(-members // threads)
    return BLOCK if per_thread >= BLOCK else 8


@nb.njit(cache=True, fastmath=_FM, inline="always")
def _block(
    lo, hi, Minv, C, K, G, k_kind, k_par, cm, hb, kl, e_kind, e_par, B_, f_kind, f_par,
    y0, t_start, period, offs, dts, periodic, counts, limit, poincare, hist, status, d0,
    lyap, nb_,
):  # fmt: skip
    """Integrate members ``lo:hi`` (at most ``nb_``) in lock-step; with ``lyap_from >= 0``
    members come in pairs (reference, perturbed) whose separation is logged into
    ``lyap`` and renormalised after every period from ``lyap_from`` on. ``counts`` is
    ``(n_periods, n_keep, n_hist, lyap_from)`` (one argument: CPython passes calls of
    more than 30 arguments as ``*args``, which numba cannot inline)."""
    n_periods, n_keep, n_hist, lyap_from = counts[0], counts[1], counts[2], counts[3]
    E = y0.shape[0]
    n = Minv.shape[1]
    L = G.shape[1]
    n2 = 2 * n
    N = offs.shape[1]
    # members of the block in structure-of-arrays layout; slots past hi repeat the last
    # member so that every slot runs the same vectorised code
    MK = np.empty((n, n, nb_))
    MC = np.empty((n, n, nb_))
    MG = np.empty((n, L, nb_))
    Gb = np.empty((L, n, nb_))
    hbb = np.empty((L, nb_))
    cmb = np.empty((L, nb_))
    klb = np.empty((L, 3, nb_))
    y = np.empty((n2, nb_))
    dtb = np.empty((N, nb_))
    limb = np.empty((n2, nb_))
    invl = np.empty((n2, nb_))
    for b in range(nb_):
        e = min(lo + b, hi - 1)
        for i in range(n):
            for j in range(n):
                ak = 0.0
                ac = 0.0
                for r in range(n):
                    ak += Minv[e, i, r] * K[e, r, j]
                    ac += Minv[e, i, r] * C[e, r, j]
                MK[i, j, b] = ak
                MC[i, j, b] = ac
            for m in range(L):
                ag = 0.0
                for r in range(n):
                    ag += Minv[e, i, r] * G[e, m, r]
                MG[i, m, b] = ag
        for m in range(L):
            for i in range(n):
                Gb[m, i, b] = G[e, m, i]
            hbb[m, b] = hb[e, m]
            cmb[m, b] = cm[e, m]
            for c in range(3):
                klb[m, c, b] = kl[e, m, c]
        for i in range(n2):
            y[i, b] = y0[e, i]
            limb[i, b] = limit[e, i]
            invl[i, b] = 1.0 / limit[e, i] if limit[e, i] > 0.0 else math.inf
        for q in range(N):
            dtb[q, b] = dts[e, q]
    MB = np.empty((hi - lo, n, f_kind.shape[0]))
    for e in range(lo, hi):
        for i in range(n):
            for j in range(f_kind.shape[0]):
                acc = 0.0
                for r in range(n):
                    acc += Minv[e, i, r] * B_[e, r, j]
                MB[e - lo, i, j] = acc
    # entries of M^-1 K, M^-1 C nonzero for some member of the block
    pi = np.empty(n * n, np.int64)
    pj = np.empty(n * n, np.int64)
    npairs = 0
    for i in range(n):
        for j in range(n):
            for b in range(nb_):
                if MK[i, j, b] != 0.0 or MC[i, j, b] != 0.0:
                    pi[npairs] = i
                    pj[npairs] = j
                    npairs += 1
                    break
    pi = pi[:npairs]
    pj = pj[:npairs]
    tab = np.zeros((3 * N, 3 * L + n, nb_))
    k1 = np.empty((n2, nb_))
    k2 = np.empty((n2, nb_))
    k3s = np.empty((n2, nb_))
    k4 = np.empty((n2, nb_))
    tmp = np.empty((n2, nb_))
    d = np.empty(nb_)
    dv = np.empty(nb_)
    fm = np.empty(nb_)
    tot = np.empty(nb_)
    yprev = np.empty((n2, nb_))
    tau = np.empty(nb_)
    ws = workspace(n, L, 3 * L + n, nb_)
    events = False
    for m in range(L):
        for b in range(nb_):
            if hbb[m, b] > 0.0 or klb[m, 1, b] != 1.0:
                events = True
    failed = np.zeros(nb_, np.bool_)
    t_base = np.empty(E)
    width = hi - lo
    h_index = 0
    sc = np.ones((n2, nb_))  # state scales of the pairs (Lyapunov exponents)
    if lyap_from == 0:
        _perturb(y, sc, lo, width, n, period, d0)
    for p in range(n_periods):
        if p == 0 or not periodic:
            for e in range(lo, hi):
                t_base[e] = t_start[e] + p * period[e]
            # slots past width repeat the last member
            tabulate(
                tab, lo, hi, t_base, offs, dts, k_kind, k_par, e_kind, e_par, MB, f_kind, f_par
            )
        if p >= n_periods - n_keep:
            for b in range(width):
                if not failed[b]:
                    for i in range(n2):
                        poincare[lo + b, p - (n_periods - n_keep), i] = y[i, b]
        for q in range(N):
            r0 = 3 * q
            for i in range(n2):
                for b in range(nb_):
                    yprev[i, b] = y[i, b]
            rk4(tab, r0, y, dtb[q], k1, k2, k3s, k4, tmp, MK, MC, pi, pj, MG, Gb, hbb, cmb,
                klb, d, dv, fm)  # fmt: skip
            if events and event_times(tab, r0, yprev, y, dtb[q], Gb, hbb, klb, tau, ws[2],
                                      ws[3]):  # fmt: skip
                # a member crossed a backlash boundary inside the step, where the force
                # has a kink that RK4 steps over at first order: the crossing members
                # step again, to the crossing and from it (kernel_step.restep)
                restep(tab, r0, y, yprev, dtb[q], tau, MK, MC, pi, pj, MG, Gb, hbb, cmb, klb,
                       ws, k1, k2, k3s, k4, tmp, d, dv, fm)  # fmt: skip
            for b in range(nb_):
                tot[b] = 0.0
            for i in range(n2):
                for b in range(nb_):
                    tot[b] += abs(y[i, b]) * invl[i, b]
            # cheap test first: the sum of |y_i| / limit_i bounds every component's
            # ratio; NaN fails it too
            for b in range(width):
                if not (tot[b] <= 1.0) and not failed[b]:
                    for i in range(n2):
                        if not (abs(y[i, b]) <= limb[i, b]):
                            failed[b] = True
                            status[lo + b, 0] = 1.0
                            status[lo + b, 1] = (
                                t_start[lo + b]
                                + p * period[lo + b]
                                + (offs[lo + b, q] + dts[lo + b, q])
                            )
                            status[lo + b, 2] = i
                            for j in range(n2):
                                status[lo + b, 3 + j] = y[j, b]
                            for qq in range(N):
                                dtb[qq, b] = 0.0
                            break
            if p >= n_periods - n_hist:
                for b in range(width):
                    if not failed[b]:
                        for i in range(n2):
                            hist[lo + b, h_index, i] = y[i, b]
                h_index += 1
        if lyap_from >= 0:
            if p + 1 == lyap_from:
                _perturb(y, sc, lo, width, n, period, d0)
            elif p + 1 > lyap_from:
                _renormalise(y, sc, lo, width, failed, d0, lyap)
    for b in range(width):
        if not failed[b]:
            for i in range(n2):
                poincare[lo + b, n_keep, i] = y[i, b]


@nb.njit(cache=True)
def _perturb(y, sc, lo, width, n, period, d0):
    """Start each pair's separation: the state scales from the reference (displacements
    by their largest amplitude, velocities by that times the forcing frequency) and the
    perturbed member displaced by ``d0`` scales in its first coordinate."""
    n2 = y.shape[0]
    for b in range(0, width - 1, 2):
        amp = 1e-12
        for i in range(n):
            amp = max(amp, abs(y[i, b]))
        w = 2.0 * math.pi / period[lo + b]
        for i in range(n):
            sc[i, b] = amp
            sc[n + i, b] = amp * w
        for i in range(n2):
            y[i, b + 1] = y[i, b]
        y[0, b + 1] += d0 * sc[0, b]


@nb.njit(cache=True)
def _renormalise(y, sc, lo, width, failed, d0, lyap):
    """Benettin's step for each pair: log the scaled separation, reset it to ``d0``
    along its direction."""
    n2 = y.shape[0]
    for b in range(0, width - 1, 2):
        if failed[b] or failed[b + 1]:
            continue
        dist = 0.0
        for i in range(n2):
            r = (y[i, b + 1] - y[i, b]) / sc[i, b]
            dist += r * r
        dist = math.sqrt(dist)
        if not dist > 0.0:
            continue  # no separation (log 1 = 0)
        lyap[lo + b] += math.log(dist / d0)
        f = d0 / dist
        for i in range(n2):
            y[i, b + 1] = y[i, b] + (y[i, b + 1] - y[i, b]) * f


# the block width is a compile-time constant in each of these (numba inlines _block),
# so the compiler knows the trip count of the member loops
@nb.njit(cache=True, fastmath=_FM)
def _block_narrow(
    lo, hi, Minv, C, K, G, k_kind, k_par, cm, hb, kl, e_kind, e_par, B, f_kind, f_par, y0,
    t_start, period, offs, dts, periodic, counts, limit, poincare, hist, status, d0, lyap,
):  # fmt: skip
    _block(
        lo, hi, Minv, C, K, G, k_kind, k_par, cm, hb, kl, e_kind, e_par, B, f_kind, f_par, y0,
    t_start, period, offs, dts, periodic, counts, limit, poincare, hist, status, d0, lyap,
    8,
    )  # fmt: skip


@nb.njit(cache=True, fastmath=_FM)
def _block_wide(
    lo, hi, Minv, C, K, G, k_kind, k_par, cm, hb, kl, e_kind, e_par, B, f_kind, f_par, y0,
    t_start, period, offs, dts, periodic, counts, limit, poincare, hist, status, d0, lyap,
):  # fmt: skip
    _block(
        lo, hi, Minv, C, K, G, k_kind, k_par, cm, hb, kl, e_kind, e_par, B, f_kind, f_par, y0,
    t_start, period, offs, dts, periodic, counts, limit, poincare, hist, status, d0, lyap,
    BLOCK,
    )  # fmt: skip


@nb.njit(parallel=True, cache=True)
def rk4_ensemble(
    Minv, C, K, G, k_kind, k_par, cm, hb, kl, e_kind, e_par, B, f_kind, f_par,
    y0, t_start, period, offs, dts, periodic, n_periods, n_keep, n_hist, limit, width,
    lyap_from, d0,
):  # fmt: skip
    """Integrate every member for ``n_periods`` forcing periods.

    Per-member arrays carry the member first: ``Minv, C, K`` (E, n, n), ``G`` (E, L, n),
    law parameters (E, rows, width), ``cm, hb`` (E, L) line damping and half backlash,
    ``kl`` (E, L, 3) cubic stiffness, load exponent and reference deflection, ``B``
    (E, n, loads), ``y0`` (E, 2n). Member ``e`` starts at
    ``t_start[e]`` with period ``period[e]``; step ``q`` of every period starts at
    ``offs[e, q]`` (s, from the period's start) and lasts ``dts[e, q]``. ``periodic``
    says every law repeats within the period (the law table is then built once).

    Returns ``poincare`` (E, n_keep + 1, 2n): the state at the start of each of the last
    ``n_keep`` periods and at the end; ``hist`` (E, n_hist * N, 2n): every step of the
    last ``n_hist`` periods; ``status`` (E, 3 + 2n): (failed flag, time, state index,
    state) when a state component became non-finite or exceeded its bound ``limit``
    (E, 2n; inf for none). Rows after a failure stay NaN.
    Members run in blocks of ``width``: 8 or :data:`BLOCK` (see :func:`block_width`).

    With ``lyap_from >= 0`` the members come in pairs (even: reference, odd: its copy,
    same system and start): at the end of period ``lyap_from - 1`` the copy is displaced
    by ``d0`` state scales, and after every later period the scaled separation is
    logged and reset to ``d0`` along its direction (Benettin's method, no linearisation
    needed across the backlash kink). ``lyap`` (E,) returns the sum of the logs at each
    reference (divide by the time to get the largest Lyapunov exponent).
    """
    E, n2 = y0.shape
    lyap = np.zeros(E)
    counts = np.array([n_periods, n_keep, n_hist, lyap_from], np.int64)
    N = offs.shape[1]
    poincare = np.full((E, n_keep + 1, n2), np.nan)
    hist = np.full((E, max(n_hist, 0) * N, n2), np.nan)
    status = np.zeros((E, 3 + n2))
    n_blocks = (E + width - 1) // width
    for blk in nb.prange(n_blocks):
        lo = blk * width
        hi = min(E, lo + width)
        if width == BLOCK:
            _block_wide(
                lo, hi, Minv, C, K, G, k_kind, k_par, cm, hb, kl, e_kind, e_par, B, f_kind,
                f_par, y0, t_start, period, offs, dts, periodic, counts, limit, poincare, hist,
                status, d0, lyap,
            )  # fmt: skip
        else:
            _block_narrow(
                lo, hi, Minv, C, K, G, k_kind, k_par, cm, hb, kl, e_kind, e_par, B, f_kind,
                f_par, y0, t_start, period, offs, dts, periodic, counts, limit, poincare, hist,
                status, d0, lyap,
            )  # fmt: skip
    return poincare, hist, status, lyap
