"""Linear elastodynamics of solid bodies: quadratic tetrahedra, free vibration.

The first piece of the gear-body modal analysis (issue 14, paper 000 §4): mass and
stiffness of an isotropic elastic body meshed with tetrahedra, assembled by scikit-fem
with 10-node (P2) elements, and its natural frequencies by shift-invert Lanczos
(``scipy.sparse.linalg.eigsh``). Free-free bodies have six rigid-body modes; they are
found by their eigenvalue (below ``rigid_tol * 1e-3 min(K_ii / M_ii)``) and removed,
so the first elastic modes are what a user asks for.

SI units throughout: metres, pascals, kg/m^3; frequencies in Hz only in results.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError, ReducerlabError

__all__ = [
    "STEEL",
    "BodyModes",
    "Material",
    "assemble",
    "body_modes",
    "pardiso_gram",
    "pardiso_gram_solve",
    "pardiso_inverse",
    "point_dofs",
]


@dataclass(frozen=True)
class Material:
    """An isotropic linear elastic material.

    Parameters
    ----------
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-), in (-1, 0.5).
    rho : float
        Density (kg/m^3).
    """

    E: float
    nu: float
    rho: float

    def __post_init__(self) -> None:
        for name, value in (("E", self.E), ("rho", self.rho)):
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ReducerlabError(f"Material: {name} must be a number, got {value!r}")
            if not (math.isfinite(value) and value > 0):
                raise ReducerlabError(f"Material: {name} must be finite and > 0, got {value!r}")
        nu = self.nu
        if isinstance(nu, bool) or not isinstance(nu, int | float) or not -1.0 < nu < 0.5:
            raise ReducerlabError(f"Material: nu must be a number in (-1, 0.5), got {nu!r}")

    @property
    def lame(self) -> tuple[float, float]:
        """Lamé parameters ``(lambda, mu)`` (Pa)."""
        lam = self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))
        mu = self.E / (2 * (1 + self.nu))
        return lam, mu


#: Shift of the shift-invert Lanczos, as a fraction of ``min(K_ii / M_ii)``.
SHIFT = 1e-6
#: A mode is rigid when ``|lambda| <= rigid_tol * RIGID_SCALE * min(K_ii / M_ii)``.
RIGID_SCALE = 1e-3

#: Factorisations of the shift-invert operator (:func:`body_modes`).
SOLVERS = ("auto", "scipy", "pardiso")

#: Paper 000 §4: structural steel, E = 206 GPa, nu = 0.29, rho = 7850 kg/m^3.
STEEL = Material(206e9, 0.29, 7850.0)


def assemble(
    mesh: Any, material: Material = STEEL, order: int = 2, *, mass: bool = True,
    _engine: str = "compiled",
) -> tuple[Any, Any, Any]:  # fmt: skip
    """Stiffness and mass matrices of a tetrahedral mesh.

    The integrals are computed by the compiled kernels of :mod:`reducerlab.fe.kernels`
    with scikit-fem's elements, quadrature rules and DOF numbering (the matrices equal
    scikit-fem's ``asm`` to rounding: ``tests/test_fe_kernels.py``; 5-10x faster on
    the gear models, ``benchmarks/fe_compliance_speed.py``).

    Parameters
    ----------
    mesh : skfem.MeshTet or skfem.MeshTet2
        The body (m): straight (``MeshTet``) or curved, isoparametric (``MeshTet2``).
    material : Material
    order : {1, 2}
        Linear (4-node) or quadratic (10-node) tetrahedra.
    mass : bool
        Assemble the mass matrix too (``M`` is None otherwise: the tooth compliance
        needs the stiffness only).
    _engine : {"compiled", "skfem"}
        Private: ``"skfem"`` assembles with scikit-fem's ``asm`` (the reference of the
        tests and the benchmark).

    Returns
    -------
    K, M : scipy.sparse.csr_matrix
        Stiffness (N/m) and consistent mass (kg, or None), 3 DOFs per node.
    basis : skfem.Basis
        The vector basis (DOF numbering, element maps, interpolation of shapes); its
        quadrature is one point a tetrahedron (the matrices are integrated with their
        own rules), not meant for integrating.
    """
    from skfem import Basis, ElementTetP1, ElementTetP2, ElementVector

    if order not in (1, 2):
        raise ReducerlabError(f"assemble: order must be 1 or 2, got {order!r}")
    if _engine not in ("compiled", "skfem"):
        raise ReducerlabError(f"assemble: unknown engine {_engine!r}")
    scalar = ElementTetP2() if order == 2 else ElementTetP1()
    element = ElementVector(scalar)
    if _engine == "skfem":
        basis = Basis(mesh, element, intorder=2 * order)
        K, M = _assemble_skfem(mesh, element, basis, material, order, mass)
        return K, M, basis
    from skfem.quadrature import get_quadrature

    from .kernels import block_pattern, consistent_mass, elastic_stiffness

    # the basis is for the DOF numbering, the element maps and interpolation: scikit-fem
    # evaluates every shape function at every quadrature point of it when it is built,
    # so it gets one point (the centroid; 1/11 of the work of the mass's rule)
    centroid = (np.full((3, 1), 0.25), np.array([1.0 / 6.0]))
    basis = Basis(mesh, element, quadrature=centroid)
    vector = np.asarray(basis.element_dofs)
    cells = vector[0::3] // 3  # ElementVector: DOF 3 s + c of scalar DOF s, component c
    if not all(np.array_equal(vector[c::3], 3 * cells + c) for c in range(3)):
        raise ReducerlabError("assemble: unexpected DOF numbering of the vector basis")
    pattern = block_pattern(cells, basis.N // 3)
    geo = np.asarray(mesh.dofs.element_dofs)
    xyz = np.asarray(mesh.doflocs, dtype=float)
    gelem = mesh.elem()  # the geometry's own Lagrange element (P1 straight, P2 curved)

    def tables(intorder: int) -> tuple[Any, Any, Any, Any]:
        X, W = get_quadrature(mesh.refdom, intorder)
        dgeo = np.stack([gelem.lbasis(X, a)[1] for a in range(geo.shape[0])])
        pairs = [scalar.lbasis(X, a) for a in range(cells.shape[0])]
        return np.stack([v for v, _ in pairs]), np.stack([d for _, d in pairs]), dgeo, W

    lam, mu = material.lame
    # mass: integrand of degree 2 order, exact on straight tets with intorder 2 order;
    # stiffness: products of gradients of degree order - 1, exact with 2 (order - 1) (the
    # 4-point rule for P2 instead of the 11-point one), and P1 with 2 as before
    _, db, dgeo, W = tables(2 * max(order - 1, 1))
    K = pattern.csr(elastic_stiffness(pattern, geo, xyz, dgeo, db, W, lam, mu))
    M = None
    if mass:
        vb, _, dgeo, W = tables(2 * order)
        M = pattern.csr(consistent_mass(pattern, geo, xyz, dgeo, vb, W, material.rho))
    return K, M, basis


def _assemble_skfem(
    mesh: Any, element: Any, basis: Any, material: Material, order: int, mass: bool
) -> tuple[Any, Any]:
    """:func:`assemble` by scikit-fem's ``asm`` (the reference)."""
    from skfem import Basis, BilinearForm, asm
    from skfem.helpers import ddot, dot, sym_grad, trace

    basis_k = basis if order == 1 else Basis(mesh, element, intorder=2 * (order - 1))
    lam, mu = material.lame
    rho = material.rho

    @BilinearForm
    def stiffness(u, v, _):  # Hooke: sigma = 2 mu eps + lambda tr(eps) I
        eu, ev = sym_grad(u), sym_grad(v)
        return 2.0 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev)

    @BilinearForm
    def mass_form(u, v, _):
        return rho * dot(u, v)

    return asm(stiffness, basis_k).tocsr(), asm(mass_form, basis).tocsr() if mass else None


@dataclass(frozen=True)
class BodyModes:
    """Elastic natural frequencies (Hz) and mass-normalised shapes of a body.

    Attributes
    ----------
    frequencies : ndarray (modes,)
        Hz, ascending; rigid-body modes removed (free-free) or absent (fixed).
    shapes : ndarray (dofs, modes)
        Mass-normalised displacement shapes (``phi^T M phi = 1``), in the basis' DOFs.
    rigid : int
        Number of rigid-body modes found and removed.
    """

    frequencies: NDArray[np.float64]
    shapes: NDArray[np.float64]
    rigid: int


def body_modes(
    K: Any,
    M: Any,
    count: int = 10,
    *,
    fixed: NDArray[np.int64] | None = None,
    rigid_tol: float = 1e-6,
    solver: str = "auto",
) -> BodyModes:
    """The first ``count`` elastic modes of ``K phi = omega^2 M phi``.

    Shift-invert Lanczos about a small negative shift ``sigma`` (``K - sigma M`` is
    positive definite even for a free body, so one sparse factorisation serves). A mode is
    rigid when its eigenvalue is below ``rigid_tol * 1e-3 min(K_ii / M_ii)`` (a free
    solid body has six); they are removed from the result.

    Parameters
    ----------
    K, M : sparse matrices
        Stiffness (N/m) and mass (kg).
    count : int
        Elastic modes wanted.
    fixed : array of int, optional
        DOFs held at zero (a fixed bore or mounting face); none for free-free.
    rigid_tol : float
        Relative eigenvalue below which a mode is rigid.
    solver : {"auto", "scipy", "pardiso"}
        Factorisation of ``K - sigma M``: MKL PARDISO through the optional pypardiso
        (``auto`` when it is installed; 3.5x faster solve on a gear mesh) or scipy's
        SuperLU.
    """
    import scipy.sparse.linalg as spla

    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise ReducerlabError(f"body_modes: count must be a positive integer, got {count!r}")
    if solver not in SOLVERS:
        raise ReducerlabError(f"body_modes: solver must be one of {SOLVERS}, got {solver!r}")
    n = K.shape[0]
    free = np.arange(n)
    if fixed is not None and len(fixed):
        free = np.setdiff1d(free, np.asarray(fixed, dtype=np.int64))
        K, M = K[free][:, free], M[free][:, free]
    want = count + 6
    if want >= K.shape[0] - 1:
        raise ReducerlabError(
            f"body_modes: the mesh has {K.shape[0]} free DOFs, too few for {count} modes"
        )
    # shift: a small fraction of the smallest "element" eigenvalue scale K_ii / M_ii.
    # Close to zero (1e-6 of it) so that the wanted low modes are well separated in the
    # inverted spectrum 1/(lambda - sigma): a shift of 1e-3 of the element scale lay far
    # beyond the first modes of a slender body and cost ~3x the Lanczos iterations.
    d = K.diagonal() / M.diagonal()
    scale = float(np.min(d[d > 0]))
    sigma = -SHIFT * scale
    # solves without PARDISO's iterative refinement (pardiso_inverse): 3-4x faster, the
    # frequencies equal to 1e-11
    opinv = pardiso_inverse(K - sigma * M, 0) if solver in ("auto", "pardiso") else None
    if solver == "pardiso" and opinv is None:
        raise ReducerlabError(
            "body_modes: solver 'pardiso' needs pypardiso (pip install pypardiso)"
        )
    try:
        lam, vec = spla.eigsh(K, k=want, M=M, sigma=sigma, which="LM", OPinv=opinv)
    except (RuntimeError, ValueError, spla.ArpackError) as exc:
        raise ModelError(f"body_modes: the eigen-solver failed ({exc})") from None
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order]
    rigid = np.abs(lam) <= rigid_tol * RIGID_SCALE * scale
    lam, vec = lam[~rigid][:count], vec[:, ~rigid][:, :count]
    if np.any(lam < 0):
        raise ModelError("body_modes: negative eigenvalue of an elastic body (bad mesh?)")
    shapes = np.zeros((n, vec.shape[1]))
    shapes[free] = vec
    return BodyModes(np.sqrt(lam) / (2 * math.pi), shapes, int(rigid.sum()))


def import_pypardiso() -> Any:
    """The pypardiso module, or None when it is not installed.

    pypardiso looks for MKL's runtime library when it is imported: where
    ``ctypes.util.find_library`` does not find it (a virtual environment), it globs the
    whole ``sys.prefix`` tree recursively, 1.5-3 s in this project's environment (issue
    28: more than a tooth sector's eigen-solution). The library is looked up first where
    pip and conda put it (``lib/``, ``Library/bin``), without recursion, and named to
    pypardiso by its ``PYPARDISO_MKL_RT`` variable (a value already set is kept)."""
    import glob
    import os
    import sys

    if "PYPARDISO_MKL_RT" not in os.environ:
        for folder in ("lib", "Lib", "Library/bin"):
            found = sorted(glob.glob(os.path.join(sys.prefix, folder, "*mkl_rt*")), key=len)
            found = [f for f in found if not f.endswith((".a", ".lib"))]
            if found:
                os.environ["PYPARDISO_MKL_RT"] = found[0]
                break
    try:
        import pypardiso
    except (ImportError, OSError):
        return None
    return pypardiso


def mkl_pardiso(
    solver: Any, pt: Any, mtype: int, phase: int, n: int, data: Any, ia: Any, ja: Any,
    perm: Any, iparm: Any, b: Any, x: Any, nrhs: int = 1,
) -> int:  # fmt: skip
    """One call of MKL PARDISO through the library handle of a pypardiso solver
    (``solver._mkl_pardiso``), for the phases and matrix types pypardiso's own methods do
    not offer (a solve without refinement, complex Hermitian factorisations); one-based
    CSR ``ia, ja`` of the upper triangle; None for an array PARDISO does not read in
    ``phase``. Returns PARDISO's error code (0: success)."""
    import ctypes

    i32 = ctypes.POINTER(ctypes.c_int32)
    pt_type = ctypes.c_int64 if pt.dtype == np.int64 else ctypes.c_int32

    def ref(v: int) -> Any:
        return ctypes.byref(ctypes.c_int32(v))

    def vp(a: Any) -> Any:
        return ctypes.c_void_p(0) if a is None else a.ctypes.data_as(ctypes.c_void_p)

    def ip(a: Any) -> Any:
        return i32() if a is None else a.ctypes.data_as(i32)

    error = ctypes.c_int32(0)
    solver._mkl_pardiso(
        pt.ctypes.data_as(ctypes.POINTER(pt_type)), ref(1), ref(1), ref(mtype), ref(phase),
        ref(n), vp(data), ip(ia), ip(ja), ip(perm), ref(nrhs), ip(iparm), ref(0), vp(b),
        vp(x), ctypes.byref(error),
    )  # fmt: skip
    return int(error.value)


def pardiso_inverse(A: Any, refinement: int | None = None) -> Any:
    """``A^-1`` as a LinearOperator by MKL PARDISO (symmetric positive definite ``A``,
    factorised once), or None when pypardiso is not installed.

    ``refinement``: None solves through pypardiso's ``solve`` (PARDISO's defaults: up to
    two steps of iterative refinement a solve, each a further pair of triangular solves,
    and pypardiso's comparison of ``A`` with the factorised matrix on every call);
    an integer calls PARDISO's solve phase directly with at most that many refinement
    steps. :func:`body_modes` takes 0: a solve 3-4x faster on gear 2's whole mesh
    (124 ms against 458 ms, relative residual 9e-12 against 7e-12) and its frequencies
    equal to 1.1e-11 (``docs/assumptions.md``, "Eigen-solver's linear solves")."""
    pypardiso = import_pypardiso()
    if pypardiso is None:
        return None
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    upper = sp.triu(A, format="csr")
    upper.sort_indices()
    solver = pypardiso.PyPardisoSolver(mtype=2)  # real symmetric positive definite
    solver.factorize(upper)

    if refinement is None:

        def solve(b: Any) -> Any:
            return np.asarray(solver.solve(upper, np.asarray(b, dtype=float)), dtype=float)

        return spla.LinearOperator(A.shape, matvec=solve, matmat=solve, dtype=float)

    # iparm holds the values PARDISO used for the factorisation (its defaults written
    # back); iparm[0] = 1 makes it read them, iparm[7] the refinement steps
    solver.set_iparm(1, 1)
    solver.set_iparm(8, int(refinement))
    ia = upper.indptr.astype(np.int32) + 1  # one-based, made once for every solve
    ja = upper.indices.astype(np.int32) + 1

    def direct(b: Any) -> Any:
        rhs = np.asfortranarray(b, dtype=float)  # shape checked by the LinearOperator
        x = np.zeros_like(rhs)
        nrhs = 1 if rhs.ndim == 1 else rhs.shape[1]
        error = mkl_pardiso(solver, solver.pt, solver.mtype, 33, A.shape[0], upper.data, ia,
                            ja, solver.perm, solver.iparm, rhs, x, nrhs)  # fmt: skip
        if error != 0:
            raise ModelError(f"pardiso_inverse: PARDISO's solve failed (error {error})")
        return np.ascontiguousarray(x)

    return spla.LinearOperator(A.shape, matvec=direct, matmat=direct, dtype=float)


def _phase_solver(A: Any) -> tuple[Any, Any] | None:
    """A PARDISO solver (symmetric positive definite) whose phases can be called one by
    one, and the upper triangle of ``A`` it factorises; None when pypardiso, its MKL
    runtime library or its phase calls are missing (the caller's plain solves)."""
    pypardiso = import_pypardiso()
    if pypardiso is None:
        return None
    try:
        solver = pypardiso.PyPardisoSolver(mtype=2)
    except OSError:  # no MKL runtime library
        return None
    if not all(callable(getattr(solver, f, None)) for f in ("_call_pardiso", "set_phase")):
        return None
    import scipy.sparse as sp

    upper = sp.triu(A, format="csr")
    upper.sort_indices()
    return solver, upper


def pardiso_gram(A: Any, B: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """``B^T A^-1 B`` of a symmetric positive definite sparse ``A`` by MKL PARDISO's
    Cholesky factor ``P A P^T = L L^T`` and its forward substitution alone, or None when
    pypardiso is not installed (or finds no MKL runtime library).

    With ``Y = L^-1 P B``, ``B^T A^-1 B = Y^T Y``: half the triangular solves of
    ``A^-1 B``, and PARDISO's forward substitution of many right-hand sides at once is
    far faster than its whole solve (phase 331 against 33: 2.4 s against 20 s for the
    162 loads of a gear's tooth compliance, ``benchmarks/RESULTS.md``, "FE tooth
    compliance"). The first column is checked against a whole solve (a factor that is
    not ``L L^T`` would fail it: then every column is solved whole).

    Parameters
    ----------
    A : sparse matrix (n, n)
        Symmetric positive definite (e.g. a held stiffness, N/m).
    B : ndarray (n, k)
        Right-hand sides (e.g. loads, N).

    Returns
    -------
    ndarray (k, k)
        ``B^T A^-1 B`` (e.g. influence coefficients, m/N), symmetric.
    """
    made = _phase_solver(A)
    if made is None:
        return None
    solver, upper = made
    b = np.asfortranarray(B, dtype=float)
    try:
        solver.factorize(upper)
        # pypardiso's solve() runs phase 33 (or 13) whatever is set; its _call_pardiso
        # runs the phase set: 331, the forward substitution alone
        solver.set_phase(331)
        Y = np.asarray(solver._call_pardiso(upper, b), dtype=float)
        G = Y.T @ Y
        solver.set_phase(33)
        x0 = np.asarray(solver._call_pardiso(upper, np.asfortranarray(b[:, :1])), dtype=float)
        g0 = b.T @ x0[:, 0]
        if not np.allclose(G[:, 0], g0, rtol=1e-8, atol=1e-10 * float(np.max(np.abs(g0)))):
            G = b.T @ np.asarray(solver._call_pardiso(upper, b), dtype=float)
    finally:
        solver.free_memory(everything=True)  # PARDISO's own memory (the factor)
    return 0.5 * (G + G.T)


def pardiso_gram_solve(
    A: Any, B: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """``B^T A^-1 B`` and ``X = A^-1 B`` of a symmetric positive definite sparse ``A``
    by one MKL PARDISO Cholesky factorisation ``P A P^T = L L^T``, or None when
    pypardiso (or its phase calls) is not there.

    The forward substitution ``Y = L^-1 P B`` gives the Gram matrix ``Y^T Y`` as in
    :func:`pardiso_gram`; the backward substitution of ``Y`` alone (PARDISO phase 333)
    gives ``X``, both without iterative refinement. ``X``'s first column is checked
    against a whole solve (phase 33; relative 1e-8): where it fails, every column is
    solved whole.

    Parameters
    ----------
    A : sparse matrix (n, n)
        Symmetric positive definite (e.g. a held stiffness, N/m).
    B : ndarray (n, k)
        Right-hand sides (e.g. loads, N).

    Returns
    -------
    G : ndarray (k, k)
        ``B^T A^-1 B`` (e.g. influence coefficients, m/N), symmetric.
    X : ndarray (n, k)
        ``A^-1 B`` (e.g. displacements, m).
    """
    made = _phase_solver(A)
    if made is None:
        return None
    solver, upper = made
    b = np.asfortranarray(B, dtype=float)
    try:
        solver.factorize(upper)
        solver.set_phase(331)  # forward substitution
        Y = np.asfortranarray(solver._call_pardiso(upper, b), dtype=float)
        G = Y.T @ Y
        solver.set_phase(333)  # backward substitution
        X = np.asarray(solver._call_pardiso(upper, Y), dtype=float)
        del Y
        solver.set_phase(33)
        x0 = np.asarray(solver._call_pardiso(upper, np.asfortranarray(b[:, :1])), dtype=float)
        scale = float(np.max(np.abs(x0)))
        if not np.allclose(X[:, 0], x0[:, 0], rtol=1e-8, atol=1e-8 * scale):
            X = np.asarray(solver._call_pardiso(upper, b), dtype=float)
            G = b.T @ X
    finally:
        solver.free_memory(everything=True)
    return 0.5 * (G + G.T), X


def point_dofs(basis: Any, tets: NDArray[np.int64], n_points: int) -> NDArray[np.int64]:
    """The DOF numbers ``(n_points, 3)`` of ``x, y, z`` at each point of a 10-node
    tetrahedral mesh (``tets``: corners, then the mid-edge nodes of edges 0-1, 1-2, 0-2,
    0-3, 1-3, 2-3) in the vector P2 ``basis`` built on it by :func:`assemble`; -1 for a
    point that no tetrahedron uses.

    scikit-fem numbers the tetrahedra's corners first, in ascending order of their
    index among the points, and the mid-edge nodes by its own edge list
    (``basis.mesh.edges``); each mid-edge node is matched to its edge by the edge's two
    corners.
    """
    out = np.full((n_points, 3), -1, dtype=np.int64)
    corners = np.unique(tets[:, :4])
    for c in range(3):
        out[corners, c] = basis.nodal_dofs[c]
    local = np.searchsorted(corners, tets[:, :4])  # scikit-fem vertex numbers
    pairs = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))  # VTK order of columns 4..9
    a = np.concatenate([local[:, i] for i, _ in pairs])
    b = np.concatenate([local[:, j] for _, j in pairs])
    node = np.concatenate([tets[:, 4 + k] for k in range(6)])
    nv = len(corners)
    key = np.minimum(a, b) * nv + np.maximum(a, b)
    e = np.sort(basis.mesh.edges, axis=0)
    ekey = e[0] * nv + e[1]
    order = np.argsort(ekey)
    pos = np.searchsorted(ekey[order], key)
    if np.any(pos >= len(ekey)) or np.any(ekey[order][np.minimum(pos, len(ekey) - 1)] != key):
        raise ReducerlabError("point_dofs: an edge of the mesh is missing from the FE basis")
    edge = order[pos]
    for c in range(3):
        out[node, c] = basis.edge_dofs[c][edge]
    return out
