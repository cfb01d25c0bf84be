"""The load distribution of a loaded tooth contact: a linear complementarity problem.

At one mesh position, ``N`` potential contact points (cells) of all tooth pairs carry
normal forces ``F >= 0`` (N). With the unloaded separations ``g`` (m), the compliance
matrix ``C`` (m/N, symmetric positive definite: tooth bending + local contact of both
gears) and the lever ``lam`` (m/rad: the normal approach of each point per unit rigid
rotation ``psi`` of the driven gear), compatibility reads

``s = C F + g - lam psi >= 0,   F >= 0,   F_i s_i = 0,   lam . F = T``

(``s``: the loaded gap; ``T``: the torque on the driven gear, N m). This is the
Karush-Kuhn-Tucker system of the strictly convex quadratic programme

``min 1/2 F^T C F + g^T F   subject to   F >= 0,  lam^T F = T``

with ``psi`` the multiplier of the load constraint (the loaded transmission error).
We solve it exactly (to round-off) by a primal active-set method (Lawson and Hanson,
*Solving Least Squares Problems*, 1974, ch. 23, extended by the one equality; the same
scheme as Conry and Seireg's simplex formulation of gear contact, ASME J. Eng. Ind. 1973):
on the active set ``A`` the equality subproblem

``C_AA F_A - lam_A psi = -g_A,   lam_A^T F_A = T``

is solved with a Cholesky factor of ``C_AA`` (Schur complement for ``psi``); negative
forces are removed by a step back along the feasible segment, and points whose gap
would close (``s_i < 0``) join the set. Each step lowers the objective of a strictly
convex programme on a feasible point, so the method ends after finitely many steps at
the unique solution. Because that method drops one point per factorisation, it is run
second: first the primal-dual active-set iteration (Hintermueller, Ito and Kunisch
2002) exchanges all wrong points at once and usually ends in a handful of steps,
started from the contact set of the neighbouring mesh position (or, cold, from the set
of the diagonal-only problem, solved exactly); only if it cycles does
the monotone method take over from its last set. Either way the answer is returned only
when the KKT conditions hold.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import LinAlgError, cho_factor, cho_solve

from ..errors import ReducerlabError

__all__ = ["ContactError", "ContactSolution", "solve_contact"]

Array = NDArray[np.float64]


class ContactError(ReducerlabError):
    """No load distribution exists or the solver did not find it (the message says why)."""


@dataclass(frozen=True)
class ContactSolution:
    """Load distribution at one mesh position.

    Attributes
    ----------
    force : ndarray, shape (N,)
        Normal force on each point (N), ``>= 0``.
    approach : float
        Rigid rotation ``psi`` of the driven gear (rad, or the unit of ``1/lam``): the
        loaded transmission error at this position.
    gap : ndarray, shape (N,)
        Loaded gap ``s = C F + g - lam psi`` (m): zero where loaded, ``>= 0`` elsewhere.
    active : ndarray of bool, shape (N,)
        Points in contact.
    iterations : int
        Active-set steps used.
    """

    force: Array
    approach: float
    gap: Array
    active: NDArray[np.bool_]
    iterations: int

    @property
    def complementarity(self) -> float:
        """``max |F_i s_i| / (sum F max|g|)`` (dimensionless, ~1e-16 at the solution)."""
        scale = float(np.sum(self.force)) * max(float(np.max(np.abs(self.gap))), 1e-300)
        return float(np.max(np.abs(self.force * self.gap))) / max(scale, 1e-300)


class _Dense:
    """A dense compliance matrix behind the interface the solver uses (see
    ``solve_contact``: ``shape``, ``diagonal``, ``block`` and ``apply``)."""

    def __init__(self, C: Array) -> None:
        self.C = C
        self.shape = C.shape

    def diagonal(self) -> Array:
        return np.diag(self.C)

    def block(self, A: NDArray[np.int64]) -> Array:
        return self.C[np.ix_(A, A)]

    def apply(self, F: Array, A: NDArray[np.int64]) -> Array:
        return self.C @ F


def _check(C, gap: ArrayLike, lever: ArrayLike, load: float) -> tuple:
    g = np.asarray(gap, dtype=float)
    lam = np.asarray(lever, dtype=float)
    n = g.size
    if g.ndim != 1 or n == 0:
        raise ContactError(f"gap: must be a non-empty 1-D array; got shape {g.shape}")
    if hasattr(C, "block") and hasattr(C, "apply"):
        op = C  # computed on demand: its entries are checked where they are made
        checked = ()
    else:
        C = np.asarray(C, dtype=float)
        op = _Dense(C)
        checked = (("compliance", C),)
    if tuple(op.shape) != (n, n):
        raise ContactError(f"compliance: must have shape ({n}, {n}); got {tuple(op.shape)}")
    if lam.shape != (n,):
        raise ContactError(f"lever: must have shape ({n},); got {lam.shape}")
    for name, a in (*checked, ("gap", g), ("lever", lam)):
        if not np.all(np.isfinite(a)):
            raise ContactError(f"{name}: must be finite (no NaN or inf)")
    if not (isinstance(load, (int, float)) and math.isfinite(load) and load > 0):
        raise ContactError(f"load: must be a finite number > 0; got {load!r}")
    return op, g, lam


#: Most points in one dense Cholesky factorisation: 12000 points are 1.15 GB and about
#: 6e11 flops; beyond 16384 the byte size of the matrix overflows the 32-bit indexing of
#: the LAPACK build scipy ships (OpenBLAS crashes in dpotrf there).
MAX_SET = 12_000


def _subproblem(C: Array, g: Array, lam: Array, A: Array, load: float) -> tuple[Array, float]:
    """``(F_A, psi)`` of the equality subproblem on the active set ``A``."""
    if A.size > MAX_SET:
        raise ContactError(
            f"the contact set has grown to {A.size} points, more than one dense "
            f"factorisation takes ({MAX_SET}); coarsen the contact grid"
        )
    try:
        # C_AA is symmetric: its transpose is the same matrix in Fortran order (no copy)
        fac = cho_factor(C.block(A).T, lower=True, overwrite_a=True, check_finite=False)
    except LinAlgError as exc:
        raise ContactError(
            "compliance: not positive definite on the contact set (two points at the same "
            "place, or a zero compliance)"
        ) from exc
    X = cho_solve(fac, np.stack([g[A], lam[A]], axis=1), check_finite=False)
    den = float(lam[A] @ X[:, 1])
    if not den > 0:
        raise ContactError("lever: the contact set cannot carry the load (lam C^-1 lam <= 0)")
    psi = (load + float(lam[A] @ X[:, 0])) / den
    return psi * X[:, 1] - X[:, 0], psi


def solve_contact(
    compliance: ArrayLike,
    gap: ArrayLike,
    lever: ArrayLike,
    load: float,
    *,
    start: ArrayLike | None = None,
    tol: float = 1e-10,
    max_iter: int | None = None,
) -> ContactSolution:
    """Exact load distribution of a frictionless contact under a given load.

    Parameters
    ----------
    compliance : array_like, shape (N, N), or an operator
        Symmetric positive definite compliance ``C`` (m/N): a matrix, or an object
        computing it on demand (``contact.cellmatrix.CellCompliance``) with ``shape``,
        ``diagonal()``, ``block(A)`` (``C_AA``) and ``apply(F, A)`` (``C F`` for ``F``
        zero outside ``A``): the solver only ever needs the columns of points that
        carry load, usually a third of the candidates.
    gap : array_like, shape (N,)
        Unloaded separation of each point ``g`` (m), measured after the rigid approach
        that closes the first point (``min g/lam = 0``; other offsets are allowed).
    lever : array_like, shape (N,)
        Normal approach per unit approach coordinate ``lam`` (m/rad); points with
        ``lam <= 0`` cannot carry load and stay open.
    load : float
        ``T = lam . F`` (N m for ``lam`` in m/rad), > 0.
    start : array_like of int or bool, optional
        Initial active set (warm start), e.g. from the previous mesh position.
    tol : float
        A point joins the contact set when its gap is below ``-tol`` times the largest
        approach ``lam psi`` (relative penetration).
    max_iter : int, optional
        Step limit; default ``3 N + 20``.

    Returns
    -------
    ContactSolution

    Raises
    ------
    ContactError
        Bad shapes or values (naming the argument), no point can carry load, or the
        active set did not settle within ``max_iter`` steps.
    """
    C, g, lam = _check(compliance, gap, lever, load)
    n = g.size
    usable = lam > 0
    if not np.any(usable):
        raise ContactError(
            "no contact: no point of the flanks approaches the mating flank under the load "
            "(check the loaded flank, the hand of spiral and the direction of the torque)"
        )
    limit = 3 * n + 20 if max_iter is None else int(max_iter)
    A = _initial_set(C, g, lam, load, usable, start)
    done = _primal_dual(C, g, lam, load, usable, A, tol, min(limit, PDAS_STEPS))
    if isinstance(done, ContactSolution):
        return done
    A, it = done
    F = np.zeros(n)
    FA, psi = _subproblem(C, g, lam, A, load)
    # make the starting point feasible: drop negative forces of the warm start
    while np.any(FA < 0) and A.size > 1:
        A = A[FA > 0] if np.any(FA > 0) else A[[int(np.argmax(FA))]]
        FA, psi = _subproblem(C, g, lam, A, load)
        it += 1
    F[A] = FA
    while True:
        it += 1
        if it > limit:
            raise ContactError(
                f"the contact solver did not settle in {limit} active-set steps "
                f"({A.size} points in contact); refine or coarsen the contact grid"
            )
        s = C.apply(F, A) + g - lam * psi
        scale = max(float(np.max(np.abs(lam[A] * psi))), float(np.max(np.abs(g[A]))), 1e-300)
        free = np.ones(n, dtype=bool)
        free[A] = False
        viol = free & usable & (s < -tol * scale)
        if not np.any(viol):
            break
        A, FA, psi_new = _enlarge(C, g, lam, load, A, viol, s)
        while True:
            if np.all(FA > 0):
                F[:] = 0.0
                F[A] = FA
                psi = psi_new
                break
            cur = F[A]
            neg = FA <= 0
            # step from the feasible F toward FA until the first force reaches zero
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = np.where(neg, cur / (cur - FA), np.inf)
            alpha = float(np.clip(np.min(ratio), 0.0, 1.0))
            newF = cur + alpha * (FA - cur)
            keep = newF > 1e-14 * max(float(np.max(newF)), 1e-300)
            if not np.any(keep):
                keep[int(np.argmax(newF))] = True
            F[:] = 0.0
            A = A[keep]
            F[A] = newF[keep]
            FA, psi_new = _subproblem(C, g, lam, A, load)
    s = C.apply(F, A) + g - lam * psi
    s[A] = 0.0
    active = np.zeros(n, dtype=bool)
    active[A] = True
    return ContactSolution(F, float(psi), s, active, it)


#: steps of the primal-dual active-set iteration before the monotone method takes over
PDAS_STEPS = 40


def _primal_dual(
    C: Array,
    g: Array,
    lam: Array,
    load: float,
    usable: Array,
    A: Array,
    tol: float,
    steps: int,
) -> ContactSolution | tuple[NDArray[np.int64], int]:
    """The primal-dual active-set iteration (Hintermueller, Ito and Kunisch, SIAM J.
    Optim. 13, 2002): each step solves on the set, then drops every point with a
    non-positive force and adds every point that would penetrate, all at once. It
    ends at the exact KKT point in a few steps on contact problems but is not
    guaranteed to (it may cycle), so after ``steps`` steps or a repeated set it hands
    its last set, made feasible, to the monotone primal method. A step at most doubles
    the set (the deepest penetrations join first), which keeps a poor start from
    bringing every candidate into one dense factorisation."""
    n = g.size
    seen: set[bytes] = set()
    it = 0
    for it in range(1, steps + 1):
        FA, psi = _subproblem(C, g, lam, A, load)
        pos = FA > 0
        F = np.zeros(n)
        F[A] = FA
        s = C.apply(F, A) + g - lam * psi
        F[A[~pos]] = 0.0
        scale = max(float(np.max(np.abs(lam[A] * psi))), float(np.max(np.abs(g[A]))), 1e-300)
        free = np.ones(n, dtype=bool)
        free[A] = False
        viol = free & usable & (s < -tol * scale)
        if np.all(pos) and not np.any(viol):
            s[A] = 0.0
            active = np.zeros(n, dtype=bool)
            active[A] = True
            return ContactSolution(F, float(psi), s, active, it)
        key = np.sort(A).tobytes()
        if key in seen:
            break
        seen.add(key)
        add = np.flatnonzero(viol)
        if add.size > max(int(pos.sum()), 16):
            # a set far too small (a poor start) loads its points so hard that nearly
            # every candidate penetrates: grow by at most as many points as the set
            # keeps, the deepest first, instead of factorising all of them at once
            add = add[np.argsort(s[add])[: max(int(pos.sum()), 16)]]
        nxt = np.concatenate([A[pos], add])
        A = nxt if nxt.size else A[[int(np.argmax(FA))]]
    return A, it


def _enlarge(
    C: Array, g: Array, lam: Array, load: float, A: Array, viol: Array, s: Array
) -> tuple[Array, Array, float]:
    """Join the penetrating points to the set ``A`` and solve on it.

    All of them join at once (one factorisation instead of one per point); those that
    would get a non-positive force leave again. If none is left, the most penetrating
    point joins alone: Lawson and Hanson's step, after which its force is positive, so
    the objective decreases and the method cannot cycle.
    """
    new = np.flatnonzero(viol)
    while new.size:
        trial = np.concatenate([A, new])
        FA, psi = _subproblem(C, g, lam, trial, load)
        ok = FA[A.size :] > 0
        if np.all(ok):
            return trial, FA, psi
        new = new[ok]
    trial = np.concatenate([A, [int(np.argmin(np.where(viol, s, np.inf)))]])
    FA, psi = _subproblem(C, g, lam, trial, load)
    return trial, FA, psi


def _initial_set(
    C: Array, g: Array, lam: Array, load: float, usable: Array, start: ArrayLike | None
) -> NDArray[np.int64]:
    """A warm start's points, or the contact set of the Winkler (diagonal) estimate."""
    if start is not None:
        s = np.asarray(start)
        idx = np.flatnonzero(s) if s.dtype == bool else s.astype(np.int64).ravel()
        if s.dtype == bool and s.shape != g.shape:
            raise ContactError(f"start: a boolean mask must have shape {g.shape}; got {s.shape}")
        if idx.size and (idx.min() < 0 or idx.max() >= g.size):
            raise ContactError(f"start: indices must lie in [0, {g.size})")
        idx = np.unique(idx[usable[idx]])
        if idx.size:
            return idx
    return _winkler_set(C.diagonal(), g, lam, load, usable)


def _winkler_set(d: Array, g: Array, lam: Array, load: float, usable: Array) -> NDArray[np.int64]:
    """Cold start: the contact set of the same problem with only the diagonal of the
    compliance (each point a spring of compliance ``d_i``, a Winkler foundation).

    ``F_i = max(0, lam_i psi - g_i) / d_i`` and ``sum lam_i F_i(psi) = T`` is piecewise
    linear and increasing in ``psi``: it is solved exactly over the sorted breakpoints
    ``g_i / lam_i``. It is only a start (on gear flanks about 60 % of the true set,
    where the coupling between points is weak against the self terms; larger where the
    coupling is long-ranged); a cold start from the single first point instead would
    load that point with the whole torque and bring nearly every candidate into the
    first step's set (one dense factorisation of all of them).
    """
    i = np.flatnonzero(usable & (d > 0))
    if i.size == 0:
        return np.array([int(np.argmax(usable))])
    brk = g[i] / lam[i]
    order = np.argsort(brk)
    brk, i = brk[order], i[order]
    a = np.cumsum(lam[i] ** 2 / d[i])  # slope of the load past each breakpoint
    b = np.cumsum(lam[i] * g[i] / d[i])
    nxt = np.append(brk[1:], np.inf)
    # load(psi) = a_k psi - b_k between breakpoints k and k + 1
    psi = (load + b) / a
    k = int(np.argmax(psi <= nxt))
    return np.sort(i[: k + 1])
