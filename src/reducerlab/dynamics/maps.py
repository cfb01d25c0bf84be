"""Fast-forward of drives whose teeth stay in contact: the one-period map (issue 16).

While every mesh line with backlash stays in contact on its loaded flank, a drive is a
*linear* time-periodic system: the state after one forcing period is an affine map of
the state before it, ``y_{p+1} = Phi y_p + p`` (Floquet's monodromy matrix ``Phi`` and
the response ``p`` to the forcing from rest). Both follow from one period of the RK4
kernel started from ``2n + 1`` states (rest and each unit state) of the contact system
(backlash removed, the transmission error shifted by the half backlash towards the
loaded flank), with the same steps as the full run: applying the map is then the RK4
run itself, up to round-off, for a fraction of its cost (the map costs ``2n + 1``
periods once, then ``(2n)^2`` multiply-adds per period instead of ``4 N`` evaluations of
the equations of motion).

The map is only valid while the teeth stay in contact. Every period is checked: the
deflection of every line with backlash must stay beyond its half backlash on the loaded
side at every step end and between step ends (the cubic Hermite interpolant of its
values and rates, as the kernel's event location reads it); the per-step deflections
and rates are affine in the period's start state, so the check costs ``2 L (2n)`` per
step. A member that fails it anywhere (its teeth would separate) is integrated by the
RK4 kernel from the start instead. The last periods whose every step is wanted (the
history of a run) are integrated by the RK4 kernel from the map's state, so histories,
impact statistics and phase plots come from the full nonlinear equations.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ..model import NonlinearSystem
from ..model.layout import constant_terms
from .accuracy import pilot_keep, pilot_run, refine_steps
from .kernel import BLOCK, block_width, rk4_ensemble
from .kernel_laws import eval_law, law_values
from .lyapunov import LYAPUNOV_D0
from .prepare import KernelArrays, Prepared, subset

__all__ = [
    "affine_maps",
    "contact_arrays",
    "contact_sides",
    "map_block",
    "map_members",
    "map_run",
    "map_steps",
    "maps_pay",
    "margin",
    "run_maps",
    "trajectory_width",
]


#: Fewest members whose maps are built at once (the per-step states of 2n + 1 runs of
#: each are held in memory: 8 members of a 12-DOF drive at 3000 steps take ~100 MB).
MAP_BLOCK = 8

#: Bytes of per-step states (and a copy of them) up to which more members than
#: :data:`MAP_BLOCK` are built at once (:func:`map_block`).
MAP_BYTES = 64 * 2**20

#: Most bytes of maps kept between the pilot and the main run of :func:`map_members`.
CACHE_BYTES = 256 * 2**20


def contact_sides(arrays: KernelArrays, y_static: NDArray[np.float64]) -> NDArray[np.float64]:
    """Loaded flank of every line (E, L): the sign of the static deflection under the
    mean loads (``y_static``: ``coordinates.static_states``, backlash offsets ignored);
    0 where a line with backlash carries no static load (below 1e-6 of its half
    backlash: its teeth float, no contact map); 1 for a line without backlash (always
    linear). Whether the teeth stay in contact is checked along the motion."""
    G, hb, e_kind, e_par = arrays.G, arrays.hb, arrays.e_kind, arrays.e_par
    E, L, n = G.shape
    out = np.ones((E, L))
    for e in range(E):
        for m in range(L):
            if hb[e, m] <= 0:
                continue
            d = float(G[e, m] @ y_static[e, :n]) - eval_law(int(e_kind[m]), e_par[e, m], 0.0)[0]
            out[e, m] = 0.0 if abs(d) <= 1e-6 * hb[e, m] else math.copysign(1.0, d)
    return out


def contact_arrays(arrays: KernelArrays, sides: NDArray[np.float64]) -> KernelArrays:
    """The contact system's kernel arrays: no backlash, the error shifted by
    ``side * b`` (in contact ``k (delta - side b) = k (G q - (e + side b))``): the
    constant, the mean of a Fourier series, the constant term of every piece of a
    piecewise polynomial (:func:`reducerlab.model.layout.constant_terms`)."""
    hb, e_kind, e_par = arrays.hb, arrays.e_kind, arrays.e_par.copy()
    for m in range(e_kind.shape[0]):
        shift = sides[:, m] * hb[:, m]
        kind = int(e_kind[m])
        for e in range(e_par.shape[0]):
            constant_terms(kind, e_par[e, m])[:] += shift[e]
    return arrays._replace(hb=np.zeros_like(hb), e_par=e_par)


def trajectory_width(count: int) -> int:
    """Block width for the ``count`` one-period trajectories of :func:`affine_maps`.

    A wide block (:data:`.kernel.BLOCK` members) costs about half a narrow one (8) per
    member-step on these linear runs (the per-step work outside the member loops is
    shared by 64 members instead of 8): the wide width is taken where its rounds of
    blocks over the threads take less than half the narrow width's, counted at that
    cost (120 trajectories, 8 members of a 7-DOF drive, on two threads: two wide blocks,
    not fifteen narrow ones; :func:`.kernel.block_width` keeps narrow blocks below 128).
    The results are the same (every member's arithmetic is its own)."""
    threads = nb.get_num_threads()
    wide = math.ceil(math.ceil(count / BLOCK) / threads)  # rounds of wide blocks
    narrow = math.ceil(math.ceil(count / 8) / threads)
    return BLOCK if wide * BLOCK < 2 * 8 * narrow else 8


def affine_maps(prep: Prepared, sides: NDArray[np.float64]) -> tuple[NDArray, ...]:
    """One-period maps of every member of ``prep`` (:class:`~.prepare.Prepared`).

    Returns
    -------
    Phi : (E, 2n, 2n)
        Monodromy matrices.
    p : (E, 2n)
        State after one period from rest.
    D, Dv : (E, N + 1, L, 2n)
        Deflection and its rate of each line at each step end (index 0: the period
        start), as linear functions of the start state.
    d, dv : (E, N + 1, L)
        Their constant parts (from the forcing from rest, minus the error and its rate).
    """
    arrays = contact_arrays(prep.arrays, sides)
    E = prep.period.size
    G = arrays.G
    n2 = 2 * G.shape[2]
    n = n2 // 2
    C = n2 + 1
    reps = tuple(a if a.ndim == 1 else np.repeat(a, C, axis=0) for a in arrays)  # kinds: 1-D
    Y0 = np.zeros((E, C, n2))
    Y0[:, 1:, :] = np.eye(n2)
    T = np.repeat(prep.period, C)
    limit = np.full((E * C, n2), np.inf)
    _, H, _, _ = rk4_ensemble(
        *reps, Y0.reshape(E * C, n2), np.zeros(E * C), T, np.repeat(prep.offs, C, axis=0),
        np.repeat(prep.dts, C, axis=0), prep.periodic, 1, 1, 1, limit, trajectory_width(E * C),
        -1, 0.0,
    )  # fmt: skip
    N = prep.offs.shape[1]
    H = H.reshape(E, C, N, n2)
    base = H[:, 0]  # (E, N, 2n): from rest
    # the linear part at each step end, projected on the lines at once (no (E, N, 2n, 2n)
    # array): D[e, k, l, s] = G[e, l] . (state at step k from unit state s, minus rest)
    Gq = (
        np.einsum("eln,eskn->ekls", G, H[:, 1:, :, :n])
        - np.einsum("eln,ekn->ekl", G, base[:, :, :n])[..., None]
    )
    Gv = (
        np.einsum("eln,eskn->ekls", G, H[:, 1:, :, n:])
        - np.einsum("eln,ekn->ekl", G, base[:, :, n:])[..., None]
    )
    Phi = np.transpose(H[:, 1:, -1, :] - base[:, None, -1, :], (0, 2, 1))  # (E, 2n, 2n)
    p = base[:, -1]
    start_q = np.concatenate([G, np.zeros_like(G)], axis=2)[:, None]  # k = 0: the start
    start_v = np.concatenate([np.zeros_like(G), G], axis=2)[:, None]
    D = np.concatenate([start_q, Gq], axis=1)  # (E, N + 1, L, 2n)
    Dv = np.concatenate([start_v, Gv], axis=1)
    bases = np.concatenate([np.zeros((E, 1, n2)), base], axis=1)  # (E, N + 1, 2n)
    times = np.concatenate([np.zeros((E, 1)), prep.offs + prep.dts], axis=1)
    ev, edot = law_values(prep.arrays.e_kind, prep.arrays.e_par, np.ascontiguousarray(times))
    d = np.einsum("eln,ekn->ekl", G, bases[:, :, :n]) - ev
    dv = np.einsum("eln,ekn->ekl", G, bases[:, :, n:]) - edot
    return Phi, p, D, Dv, d, dv


@nb.njit(cache=True)
def margin(D, Dv, d, dv, dts, y, sides, hb) -> float:
    """Smallest distance (m) beyond the half backlash on the loaded side, over every
    line with backlash and one period from state ``y``: at the step ends and at the
    interior minima of the cubic Hermite interpolant between them (negative: the teeth
    separate; inf: no line with backlash)."""
    K, L, n2 = D.shape
    low = math.inf
    for m in range(L):
        h = hb[m]
        if h <= 0.0:
            continue
        s = sides[m]
        prev_x = 0.0
        prev_v = 0.0
        for k in range(K):
            x = d[k, m]
            v = dv[k, m]
            for i in range(n2):
                x += D[k, m, i] * y[i]
                v += Dv[k, m, i] * y[i]
            x = s * x - h
            v = s * v
            low = min(low, x)
            if k > 0:
                dt = dts[k - 1]
                x0, m0, m1 = prev_x, prev_v * dt, v * dt
                a = 2 * x0 - 2 * x + m0 + m1
                b = -3 * x0 + 3 * x - 2 * m0 - m1
                # interior extrema of a t^3 + b t^2 + m0 t + x0 on (0, 1)
                qa, qb, qc = 3 * a, 2 * b, m0
                if qa != 0.0:
                    disc = qb * qb - 4 * qa * qc
                    if disc >= 0.0:
                        r = math.sqrt(disc)
                        for t in ((-qb - r) / (2 * qa), (-qb + r) / (2 * qa)):
                            if 0.0 < t < 1.0:
                                low = min(low, a * t**3 + b * t**2 + m0 * t + x0)
                elif qb != 0.0:
                    t = -qc / qb
                    if 0.0 < t < 1.0:
                        low = min(low, b * t**2 + m0 * t + x0)
            prev_x = x
            prev_v = v
    return low


@nb.njit(parallel=True, cache=True)
def run_maps(Phi, p, D, Dv, d, dv, dts, sides, hb, y0, n_periods, n_keep, limit, lyap_from,
             d0, period, ystar, safe, bound):  # fmt: skip
    """Iterate the one-period maps of every member for ``n_periods`` periods, checking
    contact in each.

    A period passes at once when the start state is close enough to the map's fixed
    point ``ystar``: its margin ``safe`` (:func:`margin` of the fixed point) exceeds
    ``bound * |y - ystar|`` (``bound``: the largest change of a deflection along the
    Hermite interpolant per unit change of the state); otherwise :func:`margin` is
    evaluated for the period.

    Returns the states at the start of the last ``n_keep`` periods and at the end
    (E, n_keep + 1, 2n; the last is the end state), the first period whose contact check
    failed or whose state left ``limit`` (-1: none) and the sum of Benettin's logs from
    period ``lyap_from`` on (E,) (as ``kernel.rk4_ensemble``: the perturbation applied at
    the end of period ``lyap_from - 1``, renormalised after each later period)."""
    E, n2 = y0.shape
    n = n2 // 2
    poincare = np.full((E, n_keep + 1, n2), np.nan)
    failed = np.full(E, -1, np.int64)
    logs = np.zeros(E)
    for e in nb.prange(E):
        y = y0[e].copy()
        w = np.zeros(n2)
        sc = np.ones(n2)
        nxt = np.empty(n2)
        for per in range(n_periods):
            if per == lyap_from:
                amp = 1e-12
                for i in range(n):
                    amp = max(amp, abs(y[i]))
                om = 2.0 * math.pi / period[e]
                for i in range(n):
                    sc[i] = amp
                    sc[n + i] = amp * om
                w[:] = 0.0
                w[0] = d0 * sc[0]
            if per >= n_periods - n_keep:
                poincare[e, per - (n_periods - n_keep)] = y
            dist = 0.0
            for i in range(n2):
                dist += (y[i] - ystar[e, i]) ** 2
            near = safe[e] - bound[e] * math.sqrt(dist) > 0.0  # NaN (no fixed point): not
            if not near and not margin(D[e], Dv[e], d[e], dv[e], dts[e], y, sides[e],
                                        hb[e]) > 0.0:  # fmt: skip
                failed[e] = per
                break
            for i in range(n2):
                acc = p[e, i]
                for j in range(n2):
                    acc += Phi[e, i, j] * y[j]
                nxt[i] = acc
            bad = False
            for i in range(n2):
                if not (abs(nxt[i]) <= limit[e, i]):
                    bad = True
            if bad:
                failed[e] = per
                break
            y[:] = nxt
            if lyap_from >= 0 and per >= lyap_from:
                for i in range(n2):
                    acc = 0.0
                    for j in range(n2):
                        acc += Phi[e, i, j] * w[j]
                    nxt[i] = acc
                dist = 0.0
                for i in range(n2):
                    dist += (nxt[i] / sc[i]) ** 2
                dist = math.sqrt(dist)
                if dist > 0.0:
                    logs[e] += math.log(dist / d0)
                    for i in range(n2):
                        w[i] = nxt[i] * (d0 / dist)
        if failed[e] < 0:
            poincare[e, n_keep] = y
    return poincare, failed, logs


def _fixed_point(Phi: NDArray, p: NDArray, D, Dv, d, dv, dts, sides, hb) -> tuple:
    """Per member: the map's fixed point (the periodic steady state; NaN when the map
    is not contracting), its contact margin and the bound of :func:`run_maps`."""
    E, n2 = p.shape
    ystar = np.full((E, n2), np.nan)
    safe = np.full(E, -np.inf)
    bound = np.full(E, np.inf)
    for e in range(E):
        if not np.max(np.abs(np.linalg.eigvals(Phi[e]))) < 1.0:
            continue
        ystar[e] = np.linalg.solve(np.eye(n2) - Phi[e], p[e])
        lines = hb[e] > 0
        if not np.any(lines):
            safe[e], bound[e] = np.inf, 0.0
            continue
        safe[e] = margin(D[e], Dv[e], d[e], dv[e], dts[e], ystar[e], sides[e], hb[e])
        cx = np.linalg.norm(D[e][:, lines], axis=-1).max()
        cv = np.linalg.norm(Dv[e][:, lines], axis=-1).max()
        bound[e] = cx + (8.0 / 27.0) * float(dts[e].max()) * cv
    return ystar, safe, bound


def map_block(prep: Prepared) -> int:
    """Members whose maps :func:`map_members` builds at once: :data:`MAP_BLOCK`, or more
    while their per-step states (``2n + 1`` runs of ``N`` steps, and a copy for the
    projections) take at most :data:`MAP_BYTES` (16 members of a 7-DOF drive at 624
    steps take 34 MB: one kernel call for all, not two)."""
    n2 = 2 * prep.arrays.G.shape[2]
    per_member = 2 * (n2 + 1) * prep.steps * n2 * 8
    return max(MAP_BLOCK, MAP_BYTES // per_member)


def map_members(
    prep: Prepared,
    sides: NDArray[np.float64],
    y0: NDArray[np.float64],
    limit: NDArray[np.float64],
    n_periods: int,
    n_keep: int,
    lyap_from: int,
    d0: float,
    cache: dict | None = None,
) -> tuple[NDArray, NDArray, NDArray]:
    """:func:`run_maps` for every member of ``prep``, the maps built and run in blocks
    of :func:`map_block` members (memory). With ``cache`` (a dict), the maps of a block
    are kept there for a later call with the same step count, while the cache holds
    less than :data:`CACHE_BYTES`."""
    E, n2 = y0.shape
    poincare = np.full((E, n_keep + 1, n2), np.nan)
    failed = np.zeros(E, np.int64)
    logs = np.zeros(E)
    hb = prep.arrays.hb
    size = map_block(prep)
    for lo in range(0, E, size):
        idx = np.arange(lo, min(E, lo + size))
        sub = subset(prep, idx)
        key = (lo, prep.steps)
        if cache is not None and key in cache:
            maps = cache[key]
        else:
            maps = affine_maps(sub, sides[idx])
            maps = (*maps, *_fixed_point(*maps, sub.dts, sides[idx], hb[idx]))
            size = sum(a.nbytes for a in maps)
            if cache is not None and cache.get("bytes", 0) + size <= CACHE_BYTES:
                cache[key] = maps
                cache["bytes"] = cache.get("bytes", 0) + size
        Phi, p, D, Dv, d, dv, ystar, safe, bound = maps
        out = run_maps(Phi, p, D, Dv, d, dv, sub.dts, sides[idx], hb[idx], y0[idx],
                       n_periods, n_keep, limit[idx], lyap_from, d0, sub.period, ystar, safe,
                       bound)  # fmt: skip
        poincare[idx], failed[idx], logs[idx] = out
    return poincare, failed, logs


def separate_at_once(
    prep: Prepared,
    Y0: NDArray[np.float64],
    bounds: NDArray[np.float64],
    sides: NDArray[np.float64],
) -> NDArray[np.bool_]:
    """Members (E,) whose teeth leave their loaded flank within the first period from
    ``Y0``: one period of the RK4 kernel with ``prep``'s steps, the deflection of every
    line with backlash at every step end (``side (G q - e) < b/2``; a line with side 0
    floats, a member that leaves its bounds counts too). The one-period map of such a
    member fails in its first period and hands it to RK4 after costing ``2n + 1``
    periods to build: ``ensemble(method="auto")`` does not try the maps when every
    member separates at once (a rattling KHV drive), and costs one period where the
    maps are tried."""
    E, n2 = Y0.shape
    n = n2 // 2
    a = prep.arrays
    _, H, status, _ = rk4_ensemble(
        *a, Y0, np.zeros(E), prep.period, prep.offs, prep.dts, prep.periodic,
        1, 1, 1, bounds, block_width(E), -1, 0.0,
    )  # fmt: skip
    e_val, _ = law_values(a.e_kind, a.e_par, prep.offs + prep.dts)  # (E, N, L)
    d = np.einsum("eln,ekn->ekl", a.G, H[:, :, :n]) - e_val
    hb = a.hb[:, None, :]
    out = ((sides[:, None, :] * d - hb < 0.0) & (hb > 0.0)).any(axis=(1, 2))
    return out | (status[:, 0] != 0) | ~np.isfinite(d).all(axis=(1, 2))


def maps_pay(n: int, periods: int) -> bool:
    """Whether the one-period map is worth trying: it costs ``2n + 1`` periods."""
    return periods >= 4 * (2 * n + 1)


def map_steps(
    prep: Prepared,
    systems: Sequence[NonlinearSystem],
    Y0: NDArray[np.float64],
    bounds: NDArray[np.float64],
    accuracy: float,
    pilot: int,
    sides: NDArray[np.float64],
    cache: dict,
) -> int:
    """:func:`.accuracy.accurate_steps` with the pilot periods run through the one-period maps
    (members whose teeth separate in the pilot run them with the RK4 kernel); the maps
    stay in ``cache`` for the main run."""
    keep = pilot_keep(pilot)
    P, failed, _ = map_members(prep, sides, Y0, bounds, pilot, keep, -1, 0.0, cache)
    ok = np.ones(len(systems), bool)
    bad = np.flatnonzero(failed >= 0)
    if bad.size:  # teeth that separate: their pilot by the RK4 kernel
        pts, ran = pilot_run(subset(prep, bad), Y0[bad], bounds[bad], pilot)
        P[bad] = np.where(np.isfinite(pts), pts, Y0[bad, None, :])
        ok[bad] = ran
    if not np.any(ok):
        return prep.steps
    return refine_steps(prep, systems, P, pilot * prep.period, ok, bounds, accuracy)


def map_run(
    prep: Prepared,
    Y0: NDArray[np.float64],
    bounds: NDArray[np.float64],
    periods: int,
    keep: int,
    history: int,
    exponents: bool,
    sides: NDArray[np.float64],
    rk4_run: Callable[[NDArray[np.intp], NDArray[np.float64]], tuple],
    cache: dict,
) -> tuple:
    """:func:`.ensemble.ensemble`'s outputs with the periods before the history taken by the
    one-period maps; members whose teeth separate (or that leave their bounds) in any
    period go to ``rk4_run`` from their start."""
    E, n2 = Y0.shape
    N = prep.steps
    n_keep = max(keep, history)
    P, failed, logs = map_members(prep, sides, Y0, bounds, periods, n_keep,
                                     periods - keep if exponents else -1, LYAPUNOV_D0,
                                     cache)  # fmt: skip
    poincare = np.ascontiguousarray(P[:, n_keep - keep :])
    hist = np.full((E, history * N, n2), np.nan)
    status = np.zeros((E, 3 + n2))
    exponent = logs / (keep * prep.period) if exponents else None
    good = np.flatnonzero(failed < 0)
    if history and good.size:  # the last periods, every step: the full equations
        sub = subset(prep, good)
        start = P[good, n_keep - history]
        _, H, st, _ = rk4_ensemble(
            *sub.arrays, start, (periods - history) * sub.period, sub.period, sub.offs,
            sub.dts, sub.periodic, history, 1, history, bounds[good], block_width(good.size),
            -1, 0.0,
        )  # fmt: skip
        hist[good] = H
        status[good] = st
    bad = np.flatnonzero(failed >= 0)
    if bad.size:
        Pb, Hb, sb, lb = rk4_run(bad, Y0[bad])
        poincare[bad], hist[bad], status[bad] = Pb, Hb, sb
        if exponents:
            exponent[bad] = lb
    return poincare, hist, status, exponent, failed < 0
