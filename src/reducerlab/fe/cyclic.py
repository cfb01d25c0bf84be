"""Modes of a cyclically symmetric body from one of its sectors (issue 28).

A gear meshed by :func:`~reducerlab.fe.gear_mesh.mesh_gear` is ``z`` identical tooth
sectors: sector ``j`` is sector 0 turned by ``j`` pitches ``theta = 2 pi / z`` about the
axis ``z``, and sector 0's second (slave) wall is sector 1's first (master) wall, node for
node. The stiffness and mass matrices of such a structure are block circulant, and the
discrete Fourier transform over the sectors block-diagonalises them *exactly* (Thomas
1979; the ANSYS theory reference's "cyclic symmetry analysis"): every mode of the whole
body belongs to one harmonic index (nodal diameter) ``k = 0 .. floor(z / 2)`` and its
displacement in sector ``j`` is

    u_j = R(j theta) u_0 exp(i k j theta),                                        (1)

``R(a)`` the rotation of a displacement vector by ``a`` about ``z``. On sector 0 the
slave wall's nodes therefore follow the master wall's (Bloch condition),

    u_s = exp(i k theta) R(theta) u_m,                                            (2)

so that with ``q`` the DOFs of sector 0 without its slave wall, ``u = T_k q``,
``T_k = T_0 + exp(i k theta) T_1`` (``T_0`` the identity on the own nodes, ``T_1`` the
rotation (2) onto the slave nodes), and the modes of harmonic ``k`` are those of the
Hermitian sector eigenproblem

    K_k q = omega^2 M_k q,   K_k = T_k^H K T_k = A + e^{ik theta} B + e^{-ik theta} B^T,  (3)

``A = T_0^T K T_0 + T_1^T K T_1`` and ``B = T_0^T K T_1`` real and assembled once (the
same for ``M``). ``k = 0`` and ``k = z/2`` give real problems whose modes are single
modes of the whole body; every ``0 < k < z/2`` gives a complex one whose each eigenvalue
is a *double* eigenvalue of the whole body, the real and imaginary parts of (1) being
the two (mass-orthogonal, equal-mass) members of the pair.

Nothing is approximated: (3) is the full model's eigenproblem, reordered. The results
differ from the full model's only by rounding (the full model assembles the rotated
copies of the sector's elements) and by the eigen-solver's convergence.

References
----------
D. L. Thomas, "Dynamics of rotationally periodic structures", International Journal for
Numerical Methods in Engineering 14 (1979) 81-102, eqs. (1)-(3) and the real/imaginary
pairs. ANSYS Mechanical APDL Theory Reference, "Cyclic Symmetry Analysis".
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from ..budget import Estimate
from ..errors import ModelError, ReducerlabError
from .elasticity import RIGID_SCALE, SHIFT, import_pypardiso, mkl_pardiso

__all__ = [
    "CyclicModes",
    "Sector",
    "cyclic_estimate",
    "cyclic_modes",
    "harmonics",
    "rotate",
    "sector_of",
]

Array = NDArray[np.float64]
Stage = Callable[[str], None]


#: Peak memory of a sector problem over that of a real solution of the same DOFs
#: (``mesh_estimate``'s): the complex problem factorised as its real equivalent of twice
#: the size (about four times the factor), with the reduced matrices beside it.
SECTOR_FACTOR = 5.0
#: Bytes per DOF of the whole mesh that a cyclic solution needs besides the modes'
#: shapes: the points, the tetrahedra, the nodal masses, the patterning's and the mode
#: classification's temporaries. With :data:`SECTOR_FACTOR`, calibrated on the default
#: mesh of the double-sided example's gear 2 (164502 DOFs, 901 MB peak measured by
#: ``benchmarks/bench_body_cyclic.py``; estimated 904 MiB for ten modes).
WHOLE_BYTES = 3000.0
#: Bytes per DOF of the whole mesh and mode: the expanded shape (8) and the copies the
#: expansion and the mode classification make of it.
MODE_BYTES = 40.0


def cyclic_estimate(whole: Estimate, sector: Estimate, count: int) -> Estimate:
    """The work and memory of a solution by cyclic symmetry (:func:`cyclic_modes`) from
    ``mesh_estimate``'s estimates of the ``whole`` gear and of one ``sector``: the work
    is still the whole gear's DOFs, under the same bound (its mesh and shapes are kept
    for the mode names, renders and VTU files); the memory that of the sector problem
    (:data:`SECTOR_FACTOR`) and of the whole mesh with ``count`` expanded shapes."""
    memory = SECTOR_FACTOR * sector.memory + whole.work * (WHOLE_BYTES + MODE_BYTES * count)
    return Estimate(
        f"{whole.what}, solved by cyclic symmetry on one tooth sector", memory, whole.work,
        whole.unit, whole.work_limit, whole.control, whole.lower_bound,
    )  # fmt: skip


def rotate(v: Array, angle: float) -> Array:
    """Vectors ``v`` (..., 3) turned by ``angle`` (rad) about ``z`` (counter-clockwise
    seen from ``+z``): ``R(angle) v``."""
    c, s = math.cos(angle), math.sin(angle)
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1], v[..., 2]], -1)


def harmonics(teeth: int) -> range:
    """The harmonic indices ``k = 0 .. floor(z / 2)`` of a ``z``-sector body."""
    return range(teeth // 2 + 1)


def is_pair(k: int, teeth: int) -> bool:
    """Whether harmonic ``k`` gives repeated pairs of the whole body (``0 < k < z/2``)."""
    return 0 < 2 * k < teeth


@dataclass(frozen=True)
class Sector:
    """Sector 0 of a mesh that is the periodic pattern of ``teeth`` sectors.

    Attributes
    ----------
    points : ndarray (own + slaves, 3)
        The sector's own points (m: the whole mesh's points ``0 .. own - 1``), then the
        nodes of its slave wall (the whole mesh's sector-1 copies of ``master``).
    tets : ndarray (m, 10)
        The sector's quadratic tetrahedra, indices into ``points``.
    own : int
        Points of each sector in the whole mesh (sector ``j``'s are ``j own .. (j+1)
        own - 1``, sector 0's turned by ``j`` pitches).
    master : ndarray (slaves,)
        The own point (master wall) that each slave node is a turned copy of.
    teeth : int
        ``z``, the number of sectors.
    """

    points: Array
    tets: NDArray[np.int64]
    own: int
    master: NDArray[np.int64]
    teeth: int

    @property
    def pitch(self) -> float:
        """``theta = 2 pi / z`` (rad)."""
        return 2 * math.pi / self.teeth

    def skfem(self) -> Any:
        """The sector as a :class:`skfem.MeshTet2` (quadratic, curved geometry)."""
        import meshio
        from skfem.io.meshio import from_meshio

        return from_meshio(meshio.Mesh(self.points, [("tetra10", self.tets)]))

    def tile(self, values: Array) -> Array:
        """Per-point ``values`` of the sector (own points first, then the slave nodes)
        as those of the whole mesh: a slave node's value added to its master's (the
        whole mesh's node belongs to both neighbouring sectors), the result repeated for
        the ``z`` sectors. For quantities that do not turn with the sector (nodal masses)."""
        own = values[: self.own] + np.bincount(self.master, values[self.own :], minlength=self.own)
        return np.tile(own, self.teeth)


def sector_of(points: Array, tets: NDArray[np.int64], teeth: int, sector_tets: int) -> Sector:
    """Sector 0 of the whole mesh ``points, tets`` (a :class:`~reducerlab.fe.gear_mesh.
    GearBodyMesh` of all ``teeth`` sectors), after checking that the mesh is exactly the
    periodic pattern of it: sector ``j``'s tetrahedra are sector 0's with their points
    shifted by ``j own`` (modulo the whole), and its points are sector 0's turned by ``j``
    pitches.

    Raises
    ------
    ReducerlabError
        A mesh that is not such a pattern (a part of a gear, an edited mesh).
    """
    n, z = len(points), int(teeth)
    own, rest = divmod(n, z) if z >= 3 else (0, 1)
    if rest or own == 0 or len(tets) != z * sector_tets:
        raise ReducerlabError(
            f"cyclic symmetry: the mesh ({n} points, {len(tets)} tetrahedra) is not the "
            f"closed pattern of {z} sectors of {sector_tets} tetrahedra (need z >= 3)"
        )
    first = np.asarray(tets[:sector_tets], dtype=np.int64)
    shift = own * np.arange(z, dtype=np.int64)[:, None, None]
    if not np.array_equal(np.asarray(tets).reshape(z, sector_tets, -1), (first[None] + shift) % n):
        raise ReducerlabError("cyclic symmetry: the sectors' tetrahedra are not one pattern")
    pitch = 2 * math.pi / z
    p = np.asarray(points, dtype=float).reshape(z, own, 3)
    turned = np.stack([rotate(p[0], j * pitch) for j in range(z)])
    if np.max(np.abs(turned - p)) > 1e-9 * max(float(np.max(np.abs(p))), 1e-300):
        raise ReducerlabError("cyclic symmetry: the sectors' points are not turned copies")
    outside = first >= own
    slave = np.unique(first[outside])
    if len(slave) and slave.max() >= 2 * own:
        raise ReducerlabError("cyclic symmetry: sector 0 reaches past its neighbour")
    local = first.copy()
    local[outside] = own + np.searchsorted(slave, first[outside])
    return Sector(np.concatenate([p[0], points[slave]]), local, own, slave - own, z)


class _Harmonic:
    """The parts ``A, B`` of (3) for ``K`` and ``M`` on the free own DOFs ``q``."""

    def __init__(self, sector: Sector, K: Any, M: Any, dofs: NDArray[np.int64], fixed: Any) -> None:
        own, ns = sector.own, len(sector.master)
        n_dof = K.shape[0]
        if dofs.shape != (own + ns, 3) or np.any(dofs < 0):
            raise ReducerlabError("cyclic symmetry: every sector point needs its three DOFs")
        nq = 3 * own
        t0 = sp.csr_matrix((np.ones(nq), (dofs[:own].ravel(), np.arange(nq))), shape=(n_dof, nq))
        c, s = math.cos(sector.pitch), math.sin(sector.pitch)
        R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        rows = np.repeat(dofs[own:], 3, axis=1).ravel()  # slave DOF a, for b = 0, 1, 2
        cols = (3 * sector.master[:, None, None] + np.arange(3)[None, None, :]).repeat(3, 1)
        vals = np.broadcast_to(R, (ns, 3, 3)).ravel()
        t1 = sp.csr_matrix((vals, (rows, cols.ravel())), shape=(n_dof, nq))
        # fixed points: a fixed slave node fixes its master (the same node of the body)
        point = np.empty(n_dof, dtype=np.int64)
        point[dofs.ravel()] = np.repeat(np.arange(own + ns), 3)
        held = np.zeros(own, dtype=bool)
        if fixed is not None and len(fixed):
            pts = np.unique(point[np.asarray(fixed, dtype=np.int64)])
            held[pts[pts < own]] = True
            held[sector.master[pts[pts >= own] - own]] = True
        self.free = np.flatnonzero(~np.repeat(held, 3))
        t0, t1 = t0[:, self.free].tocsc(), t1[:, self.free].tocsc()
        self.parts = [
            ((t0.T @ X @ t0 + t1.T @ X @ t1).tocsr(), (t0.T @ X @ t1).tocsr()) for X in (K, M)
        ]
        self.pitch, self.teeth = sector.pitch, sector.teeth
        # the upper triangle of every K_k - tau M_k has one pattern (that of A, B and B^T
        # together): each part's upper-triangular values laid out on it once, so that a
        # pencil is three vector sums (:meth:`pencil`)
        parts = [X for A, B in self.parts for X in (A, B, B.T.tocsr())]
        total = abs(parts[0])
        for X in parts[1:]:
            total = total + abs(X)  # absolute values: no entry cancels out of the pattern
        up = sp.triu(total, format="csr")
        up.sort_indices()
        n = up.shape[0]
        keys = np.repeat(np.arange(n, dtype=np.int64), np.diff(up.indptr)) * n + up.indices
        self._pattern = (up.indptr, up.indices, n)
        self._values = []
        for X in parts:
            x = sp.triu(X, format="coo")
            values = np.zeros(len(keys))
            values[np.searchsorted(keys, x.row.astype(np.int64) * n + x.col)] = x.data
            self._values.append(values)

    def pencil(self, k: int, tau: float) -> Any:
        """The upper triangle of ``K_k - tau M_k`` (CSR, sorted, the same pattern for
        every ``k`` and ``tau``)."""
        aK, bK, cK, aM, bM, cM = self._values
        a, b, c = aK - tau * aM, bK - tau * bM, cK - tau * cM
        if 2 * k == self.teeth or k == 0:
            data = a + (-1.0 if k else 1.0) * (b + c)
        else:
            e = complex(math.cos(k * self.pitch), math.sin(k * self.pitch))
            data = a + e * b + e.conjugate() * c
        indptr, indices, n = self._pattern
        out = sp.csr_matrix((data, indices, indptr), shape=(n, n))
        out.has_sorted_indices = True
        return out

    def matrices(self, k: int) -> tuple[Any, Any]:
        """``K_k, M_k`` of (3): real for ``k = 0`` and ``k = z/2``, else complex."""
        out = []
        for A, B in self.parts:
            if 2 * k == self.teeth or k == 0:
                out.append((A + (-1.0 if k else 1.0) * (B + B.T)).tocsr())
            else:
                e = complex(math.cos(k * self.pitch), math.sin(k * self.pitch))
                out.append((A + e * B + e.conjugate() * B.T).tocsr())
        return out[0], out[1]


@dataclass(frozen=True)
class CyclicModes:
    """Elastic modes of the whole body found by cyclic symmetry.

    Attributes
    ----------
    frequencies : ndarray (modes,)
        Hz, ascending; a repeated pair as two equal entries.
    shapes : ndarray (z own, 3, modes)
        Mode shapes at the whole mesh's points (m per unit modal mass: ``phi^T M phi =
        1`` on the whole body), a pair as the real and imaginary parts of (1).
    harmonic : ndarray (modes,)
        Harmonic index ``k`` of each mode.
    rigid : int
        Rigid-body modes found and removed, a pair counted twice (a free body: 6).
    sector_dofs : int
        Free DOFs of each sector problem (3).
    """

    frequencies: Array
    shapes: Array
    harmonic: NDArray[np.int64]
    rigid: int
    sector_dofs: int


def cyclic_modes(
    sector: Sector,
    K: Any,
    M: Any,
    dofs: NDArray[np.int64],
    count: int = 10,
    *,
    fixed: NDArray[np.int64] | None = None,
    rigid_tol: float = 1e-6,
    stage: Stage | None = None,
    screen: bool = True,
) -> CyclicModes:
    """The first ``count`` elastic modes of the whole body from its sector (module
    docstring).

    Every harmonic ``k = 0 .. floor(z/2)`` is solved by shift-invert Lanczos
    (:func:`scipy.sparse.linalg.eigsh`; complex Hermitian for ``0 < k < z/2``) for as
    many modes as the whole body could take from it (``count`` single modes, or
    ``ceil(count / 2)`` pairs; the rigid ones of a free body on top: two at ``k = 0``,
    axial translation and rotation about the axis, two at ``k = 1``, each a pair of
    lateral translations or tilts); the lowest ``count`` over all harmonics are kept, a
    pair counted twice, as :func:`~reducerlab.fe.elasticity.body_modes` counts them on
    the whole body. Shift and rigid threshold are those of ``body_modes`` with the
    scale ``min(K_ii / M_ii)`` taken on the ``k = 0`` problem.

    Parameters
    ----------
    sector : Sector
    K, M : sparse matrices
        Stiffness (N/m) and mass (kg) of the sector alone (its slave wall free).
    dofs : ndarray (points, 3)
        The DOF numbers of ``x, y, z`` at each of ``sector.points``
        (:func:`~reducerlab.fe.elasticity.point_dofs`).
    count : int
        Elastic modes wanted.
    fixed : array of int, optional
        Sector DOFs held at zero; all three DOFs of their points are held, and a held
        slave node holds its master (a cyclic support: bore, mounting face).
    rigid_tol : float
        Relative eigenvalue below which a mode is rigid.
    stage : callable, optional
        ``stage(description)`` at each harmonic.
    screen : bool
        Count the eigenvalues of each harmonic below the ``count``-th lowest ``lambda``
        found so far, as the negative pivots of ``K_k - lambda M_k`` (Sylvester's law of
        inertia, :class:`_Inertia`): a harmonic with none is skipped (one factorisation
        instead of a factorisation and a Lanczos run), one with some is asked for as
        many and one more (the first of the two asks). The result is the same either
        way: a skipped harmonic's modes are never kept.
    """
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise ReducerlabError(f"cyclic_modes: count must be a positive integer, got {count!r}")
    say = stage or (lambda _s: None)
    z = sector.teeth
    h = _Harmonic(sector, K, M, dofs, fixed)
    free = fixed is None or not len(fixed)
    found: list[tuple[float, int, NDArray[Any]]] = []
    rigid, scale, sigma = 0, math.nan, math.nan
    inertia = _Inertia()
    try:
        for k in harmonics(z):
            top = _count_th(found, count, z)
            # Sylvester's law of inertia: the negative eigenvalues of K_k - top M_k are the
            # modes of harmonic k below the count-th lowest so far (one factorisation, no
            # Lanczos): none, and the harmonic has nothing to give; else as many are asked
            # for (and one more, which confirms that none was missed)
            below = None
            if screen and not math.isinf(top):
                below = inertia(h.pencil(k, top), upper=True)
            if below == 0:
                say(f"harmonic {k} of {z // 2}: {len(h.free)} sector DOFs, all above the "
                    f"{count}th mode (no negative pivot at its eigenvalue)")  # fmt: skip
                continue
            say(f"harmonic {k} of {z // 2}: {len(h.free)} sector DOFs (shift-invert Lanczos)")
            Kk, Mk = h.matrices(k)
            if k == 0:
                d = Kk.diagonal() / Mk.diagonal()
                scale = float(np.min(d[d > 0]))
                sigma = -SHIFT * scale
            pair = is_pair(k, z)
            want = (math.ceil(count / 2) if pair else count) + (2 if free and k <= 1 else 0)
            if want >= Kk.shape[0] - 1:
                raise ReducerlabError(
                    f"cyclic_modes: the sector has {Kk.shape[0]} free DOFs, too few for "
                    f"{count} modes"
                )
            # once ``count`` modes are in hand, a harmonic is first asked for two modes (and
            # its rigid ones): more only when those lie below the count-th lowest so far
            rigid_k = 2 if free and k <= 1 else 0
            first = 2 + rigid_k if below is None else below + 1
            wants = (want,) if math.isinf(top) or want <= first else (first, want)
            opinv = inertia.inverse(h.pencil(k, sigma), upper=True)
            lam, vec = _eigen(Kk, Mk, wants, sigma, lambda lam, top=top: bool(lam[-1] >= top),
                              opinv)  # fmt: skip
            is_rigid = np.abs(lam) <= rigid_tol * RIGID_SCALE * scale
            rigid += int(is_rigid.sum()) * (2 if pair else 1)
            if np.any(lam[~is_rigid] < 0):
                raise ModelError("cyclic_modes: negative eigenvalue of an elastic body (bad mesh?)")
            found += [(float(lam[i]), k, vec[:, i]) for i in np.flatnonzero(~is_rigid)]
    finally:
        inertia.close()
    found.sort(key=lambda item: item[0])
    lams: list[float] = []
    ks: list[int] = []
    shapes: list[Array] = []
    for lam_i, k, v in found:
        if len(lams) >= count:
            break
        for part in _expand(sector, h.free, k, v):
            lams.append(lam_i)
            ks.append(k)
            shapes.append(part)
    f = np.sqrt(np.array(lams[:count])) / (2 * math.pi)
    return CyclicModes(
        f, np.stack(shapes[:count], axis=-1), np.array(ks[:count]), rigid, len(h.free)
    )


def _count_th(found: list[tuple[float, int, Any]], count: int, teeth: int) -> float:
    """The ``count``-th lowest eigenvalue found so far, pairs counted twice (infinite
    while fewer are found)."""
    n = 0
    for lam, k, _ in sorted(found, key=lambda item: item[0]):
        n += 2 if is_pair(k, teeth) else 1
        if n >= count:
            return lam
    return math.inf


def _expand(sector: Sector, free: NDArray[np.int64], k: int, v: NDArray[Any]) -> list[Array]:
    """The whole body's mode(s) of the sector mode ``v`` (on the free own DOFs) by (1),
    each of unit modal mass: one for a real harmonic, the real and imaginary parts of a
    pair (each of mass ``z / 2`` for ``v^H M_k v = 1``)."""
    z, own = sector.teeth, sector.own
    q = np.zeros(3 * own, dtype=v.dtype)
    q[free] = v
    u0 = q.reshape(own, 3)
    pair = is_pair(k, z)
    parts: list[Array] = []
    for take in (np.real, np.imag) if pair else (np.real,):
        out = np.empty((z * own, 3))
        for j in range(z):
            phase = complex(math.cos(k * j * sector.pitch), math.sin(k * j * sector.pitch))
            out[j * own : (j + 1) * own] = rotate(take(u0 * phase), j * sector.pitch)
        parts.append(out * math.sqrt((2.0 if pair else 1.0) / z))
    return parts


def _eigen(K: Any, M: Any, wants: tuple[int, ...], sigma: float, enough: Callable[[Array], bool],
           opinv: Any = None) -> tuple[Array, NDArray[Any]]:  # fmt: skip
    """The eigenpairs of ``K q = lambda M q`` nearest ``sigma`` (ascending, ``q^H M q =
    1``): ``wants[0]`` of them, then ``wants[1]`` (on the same factorisation) unless
    ``enough(lambdas)`` says the first were enough. ``opinv``: ``(K - sigma M)^-1`` as a
    LinearOperator (default :func:`_inverse`, SuperLU)."""
    import scipy.sparse.linalg as spla

    if opinv is None:
        opinv = _inverse((K - sigma * M).tocsc())
    for i, want in enumerate(wants):
        ncv = min(K.shape[0] - 1, max(2 * want + 1, 12 if i + 1 < len(wants) else 20))
        try:
            lam, vec = spla.eigsh(K, k=want, M=M, sigma=sigma, which="LM", OPinv=opinv, ncv=ncv)
        except (RuntimeError, ValueError, spla.ArpackError) as exc:
            raise ModelError(f"cyclic_modes: the eigen-solver failed ({exc})") from None
        order = np.argsort(np.real(lam))
        lam, vec = np.real(lam[order]), vec[:, order]
        if enough(lam):
            break
    norm = np.sqrt(np.real(np.einsum("ij,ij->j", vec.conj(), M @ vec)))
    return lam, vec / norm


class _Inertia:
    """The number of negative eigenvalues of a real symmetric or complex Hermitian sparse
    matrix (Sylvester's law of inertia: the negative pivots of its ``L D L^H``), or None
    where the factorisation cannot tell (the caller then solves the harmonic as if it
    could not be screened). By MKL PARDISO where pypardiso is installed (the ``fast``
    extra): its Cholesky factorisation (``mtype`` 2 or 4, the symbolic analysis kept for
    the next matrix of the same pattern and type: the complex harmonics share one)
    succeeds, 0, or stops at a pivot that is not positive, None (its indefinite
    ``L D L^T``, which counts them, took 4-5 times as long). Else by scipy's SuperLU
    with diagonal pivots: the negative ones, None where rows were interchanged.

    On gear 2's sector (6294 DOFs, 2026-11-26) PARDISO's numerical factorisation takes a
    quarter of SuperLU's complex ``splu``, its analysis (METIS) about one of them. The
    same handle factorises the shift-invert operator of a harmonic that the screen
    keeps (:meth:`inverse`).
    """

    def __init__(self) -> None:
        self._solver: Any = None
        self._key: tuple[Any, ...] | None = None
        self._csr: tuple[Any, Any, Any] = (None, None, None)

    def __call__(self, A: Any, upper: bool = False) -> int | None:
        """The number of negative eigenvalues of ``A`` (square, sparse, real symmetric or
        complex Hermitian; ``upper``: its upper triangle alone, CSR with sorted
        indices), or None where the factorisation cannot tell."""
        error = self._factor(A, upper)
        if error is None or error not in (0, -4):  # -4: a pivot not positive: not definite
            return _superlu_negatives(_whole(A) if upper else A)
        return 0 if error == 0 else None

    def inverse(self, A: Any, upper: bool = False) -> Any:
        """``A^-1`` (real symmetric or complex Hermitian positive definite, sparse) as a
        LinearOperator: PARDISO's Cholesky factor on the same handle (the analysis of
        the screen's matrix of the same pattern reused; the screen's factor is replaced)
        and its solves without iterative refinement, or :func:`_inverse` (SuperLU)
        without pypardiso or where the Cholesky factorisation fails.

        On gear 2's sector (6294 DOFs, 2026-11-26, one thread) a complex factorisation
        took 0.2 s against SuperLU's 0.55-0.7 s and a solve 10-12 ms against 14-15 ms;
        the solutions agree to 1e-11 relative."""
        import scipy.sparse.linalg as spla

        if self._factor(A, upper) != 0:
            self._release()
            return _inverse((_whole(A) if upper else A).tocsc())
        mtype = 4 if self._key[0] else 2  # type: ignore[index]
        dtype = complex if self._key[0] else float  # type: ignore[index]
        data, ia, ja = self._csr

        def solve(b: Any) -> Any:
            rhs = np.asfortranarray(b, dtype=dtype)
            x = np.zeros_like(rhs)
            nrhs = 1 if rhs.ndim == 1 else rhs.shape[1]
            error, _ = self._solver(mtype, 33, data, ia, ja, rhs, x, nrhs)
            if error != 0:
                raise ModelError(f"cyclic_modes: PARDISO's solve failed (error {error})")
            return np.ascontiguousarray(x)

        return spla.LinearOperator(A.shape, matvec=solve, matmat=solve, dtype=dtype)

    def _factor(self, A: Any, upper: bool = False) -> int | None:
        """PARDISO's Cholesky factorisation of ``A`` (``upper``: given as its upper
        triangle) on the handle (the symbolic analysis kept while the pattern and type
        stay): its error code (0 success, -4 a pivot not positive), or None without
        pypardiso."""
        if upper:
            up = A
        else:
            up = sp.triu(A, format="csr")
            up.sort_indices()
        if self._solver is None:
            self._solver = _pardiso()
        if self._solver is False:
            return None
        complex_ = np.iscomplexobj(up.data)
        data = np.ascontiguousarray(up.data, dtype=complex if complex_ else float)
        ia = (up.indptr + 1).astype(np.int32)
        ja = (up.indices + 1).astype(np.int32)
        key = (complex_, up.shape[0], ia.tobytes(), ja.tobytes())
        phase = 22 if key == self._key else 12  # numerical factorisation only, or both
        if phase == 12:
            self._release()
        error, _ = self._solver(4 if complex_ else 2, phase, data, ia, ja)
        self._key = key if error in (0, -4) else None
        self._csr = (data, ia, ja)
        if error not in (0, -4):
            self._release()
        return int(error)

    def _release(self) -> None:
        if self._key is not None and self._solver:
            self._solver(4 if self._key[0] else 2, -1, None, None, None)
        self._key = None

    def close(self) -> None:
        """Free PARDISO's memory."""
        self._release()


def _pardiso() -> Any:
    """``call(mtype, phase, data, ia, ja, b=None, x=None, nrhs=1) -> (error, iparm)`` on
    one MKL PARDISO handle (one-based CSR of the upper triangle, defaults of ``iparm``;
    a solve, given ``b`` and ``x``, without iterative refinement), or False without
    pypardiso."""
    try:
        pypardiso = import_pypardiso()
        if pypardiso is None:
            return False
        lib = pypardiso.PyPardisoSolver()  # finds MKL's runtime library
    except (ImportError, OSError):
        return False
    if not callable(getattr(lib, "_mkl_pardiso", None)):  # a pypardiso without the handle
        return False
    pt = np.zeros(64, dtype=np.int64)
    iparm = np.zeros(64, dtype=np.int32)  # iparm[0] = 0: PARDISO's defaults
    perm = np.zeros(1, dtype=np.int32)
    n_now = [0]

    def call(mtype: int, phase: int, data: Any, ia: Any, ja: Any, b: Any = None,
             x: Any = None, nrhs: int = 1) -> tuple[int, Any]:  # fmt: skip
        if data is not None:
            n_now[0] = len(ia) - 1
        if b is None:  # a factorisation or release: dummy right-hand side
            b = np.zeros(2 * max(n_now[0], 1))
            x = np.zeros_like(b)
            return mkl_pardiso(lib, pt, mtype, phase, n_now[0], data, ia, ja, perm, iparm, b,
                               x), iparm  # fmt: skip
        # a solve: the factorisation's parameters (written back into iparm) read as
        # given (iparm[0] = 1), without iterative refinement (iparm[7] = 0)
        solve = iparm.copy()
        solve[0], solve[7] = 1, 0
        return mkl_pardiso(lib, pt, mtype, phase, n_now[0], data, ia, ja, perm, solve, b, x,
                           nrhs), iparm  # fmt: skip

    return call


def _whole(U: Any) -> Any:
    """The Hermitian matrix of its upper triangle ``U`` (CSR)."""
    return (U + U.conj().T - sp.diags(U.diagonal())).tocsr()


def _superlu_negatives(A: Any) -> int | None:
    """:class:`_Inertia` by SuperLU: the negative diagonal pivots, None where rows were
    interchanged (or the matrix is exactly singular)."""
    import scipy.sparse.linalg as spla

    try:
        lu = spla.splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options={"SymmetricMode": True})  # fmt: skip
    except RuntimeError:
        return None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return None
    return int(np.sum(np.real(lu.U.diagonal()) < 0))


def _inverse(A: Any) -> Any:
    """``A^-1`` (real symmetric or complex Hermitian positive definite ``A``, CSC) as a
    LinearOperator, factorised once by scipy's SuperLU: symmetric mode, diagonal pivots,
    minimum degree on ``A^T + A`` (on the sector problems 0.2-0.7 s a factorisation and
    3-15 ms a solve at 6300 DOFs): the fallback of :meth:`_Inertia.inverse` (PARDISO)."""
    import scipy.sparse.linalg as spla

    lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                   options={"SymmetricMode": True})  # fmt: skip
    return spla.LinearOperator(A.shape, matvec=lu.solve, matmat=lu.solve, dtype=A.dtype)
