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


def assemble(mesh: Any, material: Material = STEEL, order: int = 2) -> tuple[Any, Any, Any]:
    """Stiffness and mass matrices of a tetrahedral mesh.

    Parameters
    ----------
    mesh : skfem.MeshTet
        The body (m).
    material : Material
    order : {1, 2}
        Linear (4-node) or quadratic (10-node) tetrahedra.

    Returns
    -------
    K, M : scipy.sparse.csr_matrix
        Stiffness (N/m) and consistent mass (kg), 3 DOFs per node.
    basis : skfem.Basis
        The vector basis (DOF numbering, interpolation of shapes).
    """
    from skfem import Basis, BilinearForm, ElementTetP1, ElementTetP2, ElementVector, asm
    from skfem.helpers import ddot, dot, sym_grad, trace

    if order not in (1, 2):
        raise ReducerlabError(f"assemble: order must be 1 or 2, got {order!r}")
    element = ElementVector(ElementTetP2() if order == 2 else ElementTetP1())
    # mass: integrand of degree 2 order, exact on straight tets with intorder 2 order;
    # stiffness: products of gradients of degree order - 1, exact with 2 (order - 1) (the
    # 4-point rule for P2 instead of the 11-point one: ~3x less work on the costly form)
    basis = Basis(mesh, element, intorder=2 * order)
    basis_k = basis if order == 1 else Basis(mesh, element, intorder=2 * (order - 1))
    lam, mu = material.lame
    rho = material.rho

    @BilinearForm
    def stiffness(u, v, _):  # Hooke: sigma = 2 mu eps + lambda tr(eps) I
        eu, ev = sym_grad(u), sym_grad(v)
        return 2.0 * mu * ddot(eu, ev) + lam * trace(eu) * trace(ev)

    @BilinearForm
    def mass(u, v, _):
        return rho * dot(u, v)

    return asm(stiffness, basis_k).tocsr(), asm(mass, basis).tocsr(), basis


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
    import ctypes

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
    data = upper.data
    ia = upper.indptr.astype(np.int32) + 1  # one-based, made once for every solve
    ja = upper.indices.astype(np.int32) + 1
    i32 = ctypes.POINTER(ctypes.c_int32)
    f64 = ctypes.POINTER(ctypes.c_double)
    n = A.shape[0]

    def direct(b: Any) -> Any:
        rhs = np.asfortranarray(b, dtype=float)  # shape checked by the LinearOperator
        x = np.zeros_like(rhs)
        error = ctypes.c_int32(0)
        solver._mkl_pardiso(
            solver.pt.ctypes.data_as(ctypes.POINTER(solver._pt_type[0])),
            ctypes.byref(ctypes.c_int32(1)), ctypes.byref(ctypes.c_int32(1)),
            ctypes.byref(ctypes.c_int32(solver.mtype)), ctypes.byref(ctypes.c_int32(33)),
            ctypes.byref(ctypes.c_int32(n)), data.ctypes.data_as(f64), ia.ctypes.data_as(i32),
            ja.ctypes.data_as(i32), solver.perm.ctypes.data_as(i32),
            ctypes.byref(ctypes.c_int32(1 if rhs.ndim == 1 else rhs.shape[1])),
            solver.iparm.ctypes.data_as(i32), ctypes.byref(ctypes.c_int32(0)),
            rhs.ctypes.data_as(f64), x.ctypes.data_as(f64), ctypes.byref(error),
        )  # fmt: skip
        if error.value != 0:
            raise ModelError(f"pardiso_inverse: PARDISO's solve failed (error {error.value})")
        return np.ascontiguousarray(x)

    return spla.LinearOperator(A.shape, matvec=direct, matmat=direct, dtype=float)


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
