"""Mode tracking along a 1-D sweep, and detection of crossings and veerings.

Modes are followed by shape, not by sorted order: between neighbouring points the
mass-weighted MAC matrix is assigned one-to-one (Hungarian algorithm), so a track is one
physical mode. A **crossing** is two tracks exchanging their frequency order (the
frequencies coincide; the modes do not interact). A **veering** is two neighbouring
sorted frequencies approaching to a local minimum of their gap without crossing while
their shapes exchange (paper 003's "mode transition").

Long sweeps run their steps in a compiled kernel (:func:`_steps`, numba) that takes
every decision the Python step takes; a step whose decision is not clear-cut on the
kernel's own arithmetic (a near tie in the assignment or in the modes a repeated
eigenvalue is aligned onto, a MAC near or below the refinement threshold) is handed
back to the Python step. The tracks are the Python step's and the shapes agree with
its to round-off (the kernel's sums differ from NumPy's in the last bits, so a decision
tied to within round-off, which round-off decides either way, is the only one that can
differ).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linear_sum_assignment

__all__ = [
    "Event",
    "Tracking",
    "branch_of",
    "find_events",
    "renumber",
    "track_complex",
    "track_modes",
]


#: Relative eigenvalue gap below which modes form one repeated eigenvalue.
DEGENERATE = 1e-8

#: Margin (on MACs and squared overlaps, which lie in [0, 1]) below which the kernel
#: leaves a decision to the Python step: far above the round-off by which its sums
#: differ from NumPy's, far below any gap that decides a track.
_CLEAR = 1e-9

#: Steps from which a sweep is tracked by the compiled kernel: shorter sweeps take the
#: Python steps (~0.1 ms a step with two repeated eigenvalues, 12 modes), cheaper than
#: importing numba and loading the cached kernel in a fresh process (~0.5 s to 1 s).
_COMPILED_FROM = 2_000


@dataclass(frozen=True)
class Tracking:
    """Result of :func:`track_modes`.

    Attributes
    ----------
    order : ndarray of int, shape (n_points, n_tracks)
        Sorted mode index (0-based) of each track at each point.
    min_mac : ndarray, shape (n_points - 1,)
        Smallest MAC of the assignment between each point and the next.
    refined : int
        Number of extra points evaluated to resolve low-MAC steps.
    y : ndarray, shape (n_points, n_dof, n_mode)
        The shapes, with the basis of every repeated eigenvalue rotated to follow its
        neighbour (any basis of such an eigenspace is equally valid).
    """

    order: NDArray[np.intp]
    min_mac: NDArray[np.float64]
    refined: int
    y: NDArray[np.float64]


def _clusters(lam: NDArray) -> list[NDArray[np.intp]]:
    """Groups of (sorted) modes sharing one repeated eigenvalue."""
    scale = max(float(np.max(np.abs(lam))), np.finfo(float).tiny)
    out, start = [], 0
    for i in range(1, lam.size + 1):
        if i == lam.size or lam[i] - lam[i - 1] > DEGENERATE * scale:
            if i - start > 1:
                out.append(np.arange(start, i))
            start = i
    return out


def _polar(S: NDArray) -> NDArray:
    """Orthogonal factor of the polar decomposition (nearest orthogonal matrix); plain
    Python and numba alike (the kernel calls its compiled twin, :data:`_polar_compiled`)."""
    if S.shape[0] == 2 and S.shape[1] == 2:  # closed form: a double eigenvalue
        a, b, c, d = S[0, 0], S[0, 1], S[1, 0], S[1, 1]
        if a * d - b * c >= 0:
            p, q = a + d, c - b
            Q = np.array([[p, -q], [q, p]])
        else:
            p, q = a - d, c + b
            Q = np.array([[p, q], [q, -p]])
        n = math.hypot(p, q)
        return Q / n if n > 0 else np.eye(2)
    U, _, Vt = np.linalg.svd(S)
    return U @ Vt


#: What :func:`_steps` calls for :func:`_polar`: the function itself until
#: :func:`_kernel` compiles both.
_polar_compiled: Callable[[NDArray], NDArray] = _polar


def _align(clusters: list[NDArray[np.intp]], yb: NDArray, ya: NDArray) -> NDArray:
    """Rotate the basis of each repeated eigenvalue of ``b`` onto the modes of ``a``
    that span the same space (orthogonal Procrustes)."""
    yb = yb.copy()
    for c in clusters:
        P = yb[:, c].T @ ya  # overlaps with every mode of a
        J = np.sort(np.argpartition(-np.einsum("ij,ij->j", P, P), c.size - 1)[: c.size])
        yb[:, c] = yb[:, c] @ _polar(P[:, J])
    return yb


def _assign(ya: NDArray, yb: NDArray) -> tuple[NDArray[np.intp], float]:
    """Permutation p with sorted mode p[j] at b matching sorted mode j at a, and its min MAC."""
    mac = (ya.T @ yb) ** 2  # columns orthonormal: denominators are 1
    rows, cols = linear_sum_assignment(-mac)
    perm = np.empty(ya.shape[1], dtype=np.intp)
    perm[rows] = cols
    return perm, float(mac[rows, cols].min())


def _steps(
    lam: NDArray[np.float64],
    y: NDArray[np.float64],
    repeated: NDArray[np.bool_],
    order: NDArray[np.intp],
    min_mac: NDArray[np.float64],
    start: int,
    threshold: float,
    refine: bool,
) -> int:
    """Steps ``start, start + 1, ...`` of :func:`track_modes` (compiled by
    :func:`_kernel`).

    Step ``i`` aligns the repeated eigenvalues of point ``i + 1`` onto point ``i``
    (:func:`_align`, in place in ``y``), assigns its modes (:func:`_assign`) and writes
    ``order[i + 1]`` and ``min_mac[i]``. The assignment is the one-to-one map of largest
    total MAC: where every mode of ``i`` has a MAC above half its row's sum with one
    distinct mode of ``i + 1``, that map is the unique optimum (any other loses on each
    row it changes), so it is what the Hungarian algorithm returns.

    Parameters
    ----------
    lam : ndarray, shape (n_points, n_mode)
        Sorted eigenvalues (rad^2/s^2).
    y : ndarray, shape (n_points, n_dof, n_mode)
        Mass-weighted shapes, points before ``start + 1`` already aligned; updated.
    repeated : ndarray of bool, shape (n_points,)
        Whether a point has a repeated eigenvalue.
    order, min_mac : ndarray
        As in :class:`Tracking`; rows ``start + 1, ...`` and entries ``start, ...``
        written.
    start : int
        First step.
    threshold : float
        MAC below which a step is refined.
    refine : bool
        Whether low-MAC steps are refined (an ``evaluate`` and a depth are available).

    Returns
    -------
    int
        The first step not taken (``n_points - 1`` when all are): its decision is not
        clear-cut here, or it needs refinement. Nothing of it is written.
    """
    n_pts, n_dof, n_modes = y.shape
    tiny = np.finfo(np.float64).tiny
    mac = np.empty((n_modes, n_modes))
    perm = np.empty(n_modes, dtype=np.intp)
    taken = np.empty(n_modes, dtype=np.bool_)
    norms = np.empty(n_modes)
    for i in range(start, n_pts - 1):
        ya = y[i]
        yb = y[i + 1].copy()
        if repeated[i + 1]:
            lb = lam[i + 1]
            scale = max(np.max(np.abs(lb)), tiny)
            s = 0
            for e in range(1, n_modes + 1):
                if e < n_modes and not lb[e] - lb[e - 1] > DEGENERATE * scale:
                    continue  # as in _clusters
                size = e - s
                if size > 1:  # cluster s:e; P: overlaps with every mode of a
                    P = np.zeros((size, n_modes))
                    for r in range(size):
                        for j in range(n_modes):
                            acc = 0.0
                            for k in range(n_dof):
                                acc += yb[k, s + r] * ya[k, j]
                            P[r, j] = acc
                    for j in range(n_modes):
                        acc = 0.0
                        for r in range(size):
                            acc += P[r, j] * P[r, j]
                        norms[j] = acc
                    idx = np.argsort(-norms)
                    if size < n_modes and not (norms[idx[size - 1]] - norms[idx[size]] > _CLEAR):
                        return i  # the modes of a spanning the space are not clear
                    J = np.sort(idx[:size])
                    S = np.empty((size, size))
                    for r in range(size):
                        for c in range(size):
                            S[r, c] = P[r, J[c]]
                    Q = _polar_compiled(S)
                    block = yb[:, s:e].copy()
                    for k in range(n_dof):
                        for c in range(size):
                            acc = 0.0
                            for r in range(size):
                                acc += block[k, r] * Q[r, c]
                            yb[k, s + c] = acc
                s = e
        for r in range(n_modes):
            for c in range(n_modes):
                acc = 0.0
                for k in range(n_dof):
                    acc += ya[k, r] * yb[k, c]
                mac[r, c] = acc * acc
        taken[:] = False
        m = math.inf
        for r in range(n_modes):
            best = 0
            total = 0.0
            for c in range(n_modes):
                total += mac[r, c]
                if mac[r, c] > mac[r, best]:
                    best = c
            if not (2.0 * mac[r, best] - total > _CLEAR) or taken[best]:
                return i  # no clear one-to-one map: the Hungarian algorithm decides
            taken[best] = True
            perm[r] = best
            m = min(m, mac[r, best])
        if refine and m < threshold + _CLEAR:
            return i  # refined, or too close to the threshold to tell here
        y[i + 1] = yb
        for j in range(n_modes):
            order[i + 1, j] = perm[order[i, j]]
        min_mac[i] = m
    return n_pts - 1


@functools.cache
def _kernel() -> Callable[..., int]:
    """:func:`_steps` compiled by numba, imported here so that only sweeps long enough
    to gain from it pay for the import; numba caches the compiled kernel on disk."""
    import numba as nb

    global _polar_compiled
    _polar_compiled = nb.njit(cache=True)(_polar)  # before _steps: it calls it
    return nb.njit(cache=True)(_steps)


def track_modes(
    params: NDArray[np.float64],
    lam: NDArray[np.float64],
    y: NDArray[np.float64],
    evaluate: Callable[[float], tuple[NDArray, NDArray]] | None = None,
    *,
    threshold: float = 0.8,
    max_depth: int = 6,
) -> Tracking:
    """Follow modes along a sweep by shape.

    Parameters
    ----------
    params : ndarray, shape (n_points,)
        Parameter values, monotonic.
    lam : ndarray, shape (n_points, n_mode)
        Sorted eigenvalues (to recognise repeated eigenvalues).
    y : ndarray, shape (n_points, n_dof, n_mode)
        Mass-weighted (orthonormal) shapes at each point.
    evaluate : callable, optional
        ``evaluate(p) -> (lam(p), y(p))`` for refinement: where the best assignment
        between two neighbours has a MAC below ``threshold``, the step is bisected (up
        to ``max_depth`` times) and the modes are tracked through the new points.
    threshold : float
        MAC below which a step is refined.
    max_depth : int
        Most bisections of one step.

    Returns
    -------
    Tracking
        The tracks. From ``_COMPILED_FROM`` steps on, the steps run in the compiled
        :func:`_steps`; those it leaves (unclear decisions, refinement) and all steps of
        shorter sweeps run in the Python step below, with the same decisions.
    """
    n_pts, _, n_modes = y.shape
    y = y.copy()
    scale = np.maximum(np.max(np.abs(lam), axis=1), np.finfo(float).tiny)
    repeated = np.any(np.diff(lam, axis=1) <= DEGENERATE * scale[:, None], axis=1)
    order = np.empty((n_pts, n_modes), dtype=np.intp)
    order[0] = np.arange(n_modes)
    min_mac = np.ones(max(n_pts - 1, 0))
    refined = 0

    def step(
        pa: float, ya: NDArray, pb: float, lb: NDArray, yb: NDArray, depth: int, rep: bool
    ) -> tuple[NDArray, float, NDArray]:
        nonlocal refined
        if rep:
            yb = _align(_clusters(lb), yb, ya)
        perm, m = _assign(ya, yb)
        if m >= threshold or evaluate is None or depth >= max_depth:
            return perm, m, yb
        pm = 0.5 * (pa + pb)
        lm, ym = evaluate(pm)
        refined += 1
        p1, m1, ym = step(pa, ya, pm, lm, ym, depth + 1, True)
        p2, m2, yb = step(pm, ym, pb, lb, yb, depth + 1, True)
        return p2[p1], min(m1, m2), yb

    compiled = _kernel() if n_pts - 1 >= _COMPILED_FROM else None
    lam_c = np.ascontiguousarray(lam, dtype=np.float64)
    refine = evaluate is not None and max_depth > 0
    i = 0
    while i < n_pts - 1:
        if compiled is not None:  # up to the first step it leaves to the Python step
            i = compiled(lam_c, y, repeated, order, min_mac, i, float(threshold), refine)
            if i == n_pts - 1:
                break
        perm, m, y[i + 1] = step(
            float(params[i]), y[i], float(params[i + 1]), lam[i + 1], y[i + 1], 0,
            bool(repeated[i + 1]),
        )  # fmt: skip
        order[i + 1] = perm[order[i]]
        min_mac[i] = m
        i += 1
    return Tracking(order, min_mac, refined, y)


@dataclass(frozen=True)
class Event:
    """A crossing or veering between two modes along a sweep.

    ``modes`` are 1-based sorted mode numbers just before the event (for a crossing,
    the two tracks' sorted numbers on the lower-parameter side).
    """

    kind: str
    param: float
    modes: tuple[int, int]
    gap_hz: float


def find_events(
    params: NDArray[np.float64],
    freq: NDArray[np.float64],
    y: NDArray[np.float64],
    tracking: Tracking,
    *,
    veer_gap: float = 0.05,
    exchange_mac: float = 0.5,
) -> list[Event]:
    """Crossings and veerings along a tracked 1-D sweep.

    Parameters
    ----------
    params : ndarray (n_points,)
    freq : ndarray (n_points, n_mode)
        Sorted natural frequencies (Hz).
    y : ndarray (n_points, n_dof, n_mode)
        Mass-weighted shapes.
    tracking : Tracking
    veer_gap : float
        A veering needs a local minimum of the relative gap
        ``(f_{i+1} - f_i) / (f_{i+1} + f_i)`` below this value.
    exchange_mac : float
        ...and the shapes must exchange: the MAC between sorted mode ``i`` before the
        minimum and sorted mode ``i+1`` after it must exceed this value.
    """
    events: list[Event] = []
    n_pts, n_modes = freq.shape
    tf = np.take_along_axis(freq, tracking.order, axis=1)  # tracked frequencies
    for a in range(n_modes):
        for b in range(a + 1, n_modes):
            d = tf[:, a] - tf[:, b]
            # differences at round-off level are zero; a crossing may sit on a point
            d = np.where(np.abs(d) <= 1e-9 * (np.abs(tf[:, a]) + np.abs(tf[:, b])), 0.0, d)
            nz = np.nonzero(d)[0]
            sg = np.sign(d[nz])
            for q in np.nonzero(sg[:-1] != sg[1:])[0]:
                i, j = int(nz[q]), int(nz[q + 1])
                if j > i + 1:
                    p = params[i + 1]  # the frequencies coincide on a grid point
                else:
                    p = params[i] + d[i] / (d[i] - d[j]) * (params[j] - params[i])
                ma, mb = sorted((int(tracking.order[i, a]) + 1, int(tracking.order[i, b]) + 1))
                events.append(Event("crossing", float(p), (ma, mb), 0.0))
    if n_pts < 3:
        return events
    track_at = np.argsort(tracking.order, axis=1)  # sorted position -> track
    with np.errstate(divide="ignore", invalid="ignore"):
        gaps = np.where(
            freq[:, 1:] + freq[:, :-1] > 0,
            (freq[:, 1:] - freq[:, :-1]) / (freq[:, 1:] + freq[:, :-1]),
            np.inf,
        )  # (n_pts, n_modes - 1)
    inner = gaps[1:-1]
    cand = (
        (inner <= gaps[:-2]) & (inner < gaps[2:]) & (inner < veer_gap) & (inner > DEGENERATE)
    )  # interior local minima; a persistent repeated eigenvalue is not a veering
    for i, m in zip(*np.nonzero(cand), strict=True):
        i, m = int(i) + 1, int(m)
        g = gaps[:, m]
        lo, hi = freq[:, m], freq[:, m + 1]
        # shapes exchange across the minimum: compare the farthest points on each
        # side while the gap keeps growing away from it
        # window: away from the minimum while the gap grows, up to 3x its minimum (the
        # shapes of two coupled modes have exchanged by then: sin(2 angle) = 1/3)
        j0 = i
        while j0 > 0 and g[j0 - 1] >= g[j0] and g[j0] < 3 * g[i]:
            j0 -= 1
        j1 = i
        while j1 < n_pts - 1 and g[j1 + 1] >= g[j1] and g[j1] < 3 * g[i]:
            j1 += 1
        if track_at[j0, m] != track_at[j1, m]:
            continue  # the tracks swap order: a crossing, not a veering
        if float((y[j0][:, m] @ y[j1][:, m + 1]) ** 2) < exchange_mac:
            continue
        # locate the veering at the minimum of the eigenvalue gap lambda_{i+1} -
        # lambda_i inside the window (parabolic interpolation): for two coupled
        # modes that is where their shapes are an equal mix
        dl = (hi**2 - lo**2)[j0 : j1 + 1]
        k = min(max(j0 + int(np.argmin(dl)), 1), n_pts - 2)
        x0, x1, x2 = params[k - 1], params[k], params[k + 1]
        g0, g1, g2 = (hi[k + q] ** 2 - lo[k + q] ** 2 for q in (-1, 0, 1))
        den = (x0 - x1) * (x0 - x2) * (x1 - x2)
        A = (x2 * (g1 - g0) + x1 * (g0 - g2) + x0 * (g2 - g1)) / den
        B = (x2**2 * (g0 - g1) + x1**2 * (g2 - g0) + x0**2 * (g1 - g2)) / den
        p = float(-B / (2 * A)) if A > 0 else float(x1)
        p = min(max(p, float(min(x0, x2))), float(max(x0, x2)))
        events.append(Event("veering", p, (m + 1, m + 2), float(hi[k] - lo[k])))
    events.sort(key=lambda e: e.param)
    return events


def track_complex(
    freq: NDArray[np.float64], shapes: NDArray[np.complex128], mass: NDArray[np.float64]
) -> NDArray[np.intp]:
    """Follow complex (damped, gyroscopic) modes along a sweep by shape.

    The complex modes of a non-symmetric problem are not mass-orthogonal, so the steps
    of :func:`track_modes` do not apply; between neighbouring points the modes are
    assigned one-to-one (Hungarian algorithm) on the complex MAC
    ``|a^H M b|^2 / ((a^H M a)(b^H M b))``, which is blind to each shape's phase, less
    a small penalty on the relative frequency change that only decides between shapes
    the MAC cannot tell apart (a repeated eigenvalue).

    Parameters
    ----------
    freq : ndarray, shape (n_points, n_mode)
        Frequencies (Hz) at each point; NaN for a mode missing at a point.
    shapes : ndarray, shape (n_points, n_dof, n_mode)
        Complex shapes; zero where a mode is missing.
    mass : ndarray, shape (n_dof, n_dof)
        Mass matrix (kg, kg m^2) weighting the MAC.

    Returns
    -------
    ndarray of int, shape (n_points, n_mode)
        Column (mode index, 0-based) of each track at each point; track ``t`` is
        column ``t`` at the first point.
    """
    n_pts, n_modes = freq.shape
    order = np.empty((n_pts, n_modes), dtype=np.intp)
    order[0] = np.arange(n_modes)
    f = np.nan_to_num(freq, nan=-1.0)
    for i in range(n_pts - 1):
        a, b = shapes[i], shapes[i + 1]
        cross = np.abs(a.conj().T @ mass @ b) ** 2
        na = np.real(np.einsum("dm,de,em->m", a.conj(), mass, a))
        nb = np.real(np.einsum("dm,de,em->m", b.conj(), mass, b))
        den = np.outer(na, nb)
        mac = np.divide(cross, den, out=np.zeros_like(cross), where=den > 0)
        fa, fb = f[i][:, None], f[i + 1][None, :]
        scale = np.maximum(np.maximum(np.abs(fa), np.abs(fb)), np.finfo(float).tiny)
        df = np.minimum(np.abs(fa - fb) / scale, 1.0)
        rows, cols = linear_sum_assignment(-mac + 0.1 * df)
        perm = np.empty(n_modes, dtype=np.intp)
        perm[rows] = cols
        order[i + 1] = perm[order[i]]
    return order


def renumber(order: NDArray[np.intp], at: int) -> NDArray[np.intp]:
    """Tracks (columns of ``order``, as :func:`track_modes` or :func:`track_complex`
    give them) reordered so that track ``j`` is sorted mode ``j`` at point ``at``."""
    return order[:, np.argsort(order[at], kind="stable")]


def branch_of(
    sorted_mode: int,
    speed: float,
    frequency: float,
    params: NDArray[np.float64],
    tracked: NDArray[np.float64],
    order: NDArray[np.intp],
) -> int:
    """The track (0-based) a point of a sorted branch lies on.

    Parameters
    ----------
    sorted_mode : int
        Sorted mode number (1-based) at ``speed``.
    speed, frequency : float
        The point (parameter value, Hz), e.g. a crossing with an excitation line.
    params : ndarray (n_points,)
        Sampled parameter values, increasing.
    tracked : ndarray (n_points, n_track)
        Frequencies (Hz) along each track.
    order : ndarray (n_points, n_track)
        Sorted mode index (0-based) of each track at each point.

    Returns
    -------
    int
        The track whose frequency, interpolated at ``speed``, is nearest ``frequency``;
        between equally near tracks (a repeated eigenvalue), the one that is sorted mode
        ``sorted_mode`` at the nearest sample, so that each of them keeps its own row.
    """
    i = int(np.clip(np.searchsorted(params, speed) - 1, 0, params.size - 2))
    t = (speed - params[i]) / (params[i + 1] - params[i])
    f = np.nan_to_num(tracked[i] + t * (tracked[i + 1] - tracked[i]), nan=np.inf)
    dist = np.abs(f - frequency)
    near = dist <= dist.min() + 1e-6 * max(abs(frequency), 1e-300)
    k = i + int(t > 0.5)
    same = np.nonzero(near & (order[k] == sorted_mode - 1))[0]
    return int(same[0]) if same.size else int(np.argmin(dist))
