"""Compiled (numba) assembly of isotropic linear-elastic stiffness and mass matrices.

scikit-fem assembles a bilinear form by evaluating every basis function of every
element at every quadrature point as numpy arrays and contracting them with ``einsum``,
then sums a COO triplet list of ``elements x 30 x 30`` entries into CSR: on the 25,000
curved quadratic tetrahedra of a five-tooth gear model this took 9-14 s (issue 28,
``benchmarks/RESULTS.md``, "FE tooth compliance"). The same integrals are computed here
element by element in one pass:

* the geometry of each element is its mesh's own Lagrange map (4 corner nodes of
  ``MeshTet``: affine; 10 nodes of ``MeshTet2``: isoparametric, curved), its Jacobian
  ``J = sum_a x_a (grad_ref N_a)^T`` at each quadrature point;
* the (scalar) shape functions of the element and their reference gradients at the
  quadrature points come from scikit-fem's own element (``lbasis``), the quadrature
  rule from ``skfem.quadrature.get_quadrature``, so that the integrals are the same sums
  as scikit-fem's, in another order (equal to rounding, ~1e-15 relative);
* the sparsity pattern is built once from the node graph of the mesh (3 x 3 blocks of
  a vector field, DOF ``3 s + c`` for scalar DOF ``s`` and component ``c``: the
  numbering of scikit-fem's ``ElementVector``), and each element's block entries are
  added in place.

Stiffness (Hooke, ``sigma = 2 mu eps + lambda tr(eps) I``) between ``phi_a e_i`` and
``phi_b e_j``::

    K = int lambda d_i phi_a d_j phi_b + mu (d_j phi_a d_i phi_b + delta_ij grad phi_a . grad phi_b)

and the consistent mass ``M = int rho phi_a phi_b delta_ij``, both with ``|det J|``
times the quadrature weight (scikit-fem's ``dx``). ``tests/test_fe_kernels.py``
compares them with scikit-fem's assembly.
"""

from __future__ import annotations

from typing import Any

import numba as nb
import numpy as np
from numpy.typing import NDArray

__all__ = ["BlockPattern", "block_pattern", "consistent_mass", "elastic_stiffness"]

Array = NDArray[np.float64]
IntArray = NDArray[np.int64]


@nb.njit(cache=True)
def _node_graph(cells: IntArray, n: int) -> tuple[IntArray, IntArray]:
    """CSR (pointers, sorted column indices) of the nodes sharing an element."""
    nb_, ne = cells.shape
    count = np.zeros(n + 1, dtype=np.int64)
    for e in range(ne):
        for a in range(nb_):
            count[cells[a, e] + 1] += 1
    for i in range(n):
        count[i + 1] += count[i]
    owner = np.empty(count[n], dtype=np.int64)  # node -> elements
    fill = count[:n].copy()
    for e in range(ne):
        for a in range(nb_):
            s = cells[a, e]
            owner[fill[s]] = e
            fill[s] += 1
    stamp = np.full(n, -1, dtype=np.int64)
    ptr = np.zeros(n + 1, dtype=np.int64)
    for i in range(n):  # degrees first
        deg = 0
        for k in range(count[i], count[i + 1]):
            e = owner[k]
            for a in range(nb_):
                s = cells[a, e]
                if stamp[s] != i:
                    stamp[s] = i
                    deg += 1
        ptr[i + 1] = ptr[i] + deg
    ind = np.empty(ptr[n], dtype=np.int64)
    stamp[:] = -1
    for i in range(n):
        pos = ptr[i]
        for k in range(count[i], count[i + 1]):
            e = owner[k]
            for a in range(nb_):
                s = cells[a, e]
                if stamp[s] != i:
                    stamp[s] = i
                    ind[pos] = s
                    pos += 1
        ind[ptr[i] : ptr[i + 1]].sort()
    return ptr, ind


@nb.njit(cache=True)
def _vector_pattern(ptr: IntArray, ind: IntArray) -> tuple[IntArray, IntArray]:
    """CSR pointers and columns of the 3 x 3 blocks of a node graph (DOF ``3 s + c``)."""
    n = len(ptr) - 1
    vptr = np.zeros(3 * n + 1, dtype=np.int64)
    vind = np.empty(9 * ptr[n], dtype=np.int64)
    for i in range(n):
        deg = ptr[i + 1] - ptr[i]
        for c in range(3):
            r = 3 * i + c
            start = 9 * ptr[i] + 3 * c * deg
            vptr[r + 1] = start + 3 * deg
            for k in range(deg):
                for d in range(3):
                    vind[start + 3 * k + d] = 3 * ind[ptr[i] + k] + d
    return vptr, vind


@nb.njit(cache=True)
def _slots(cells: IntArray, ptr: IntArray, ind: IntArray) -> IntArray:
    """``slot[e, a, b]``: the position of node ``b`` in node ``a``'s row, element ``e``."""
    nb_, ne = cells.shape
    out = np.empty((ne, nb_, nb_), dtype=np.int64)
    for e in range(ne):
        for a in range(nb_):
            sa = cells[a, e]
            lo0 = ptr[sa]
            for b in range(nb_):
                sb = cells[b, e]
                lo = lo0
                hi = ptr[sa + 1]
                while lo < hi:  # binary search in the sorted row
                    mid = (lo + hi) // 2
                    if ind[mid] < sb:
                        lo = mid + 1
                    else:
                        hi = mid
                out[e, a, b] = lo - lo0
    return out


@nb.njit(cache=True, inline="always")
def _jacobian(xg: Array, dg: Array, q: int, J: Array) -> float:
    """``J[i, k] = sum_a x_a[i] d_k N_a`` at quadrature point ``q``; returns ``det J``."""
    for i in range(3):
        for k in range(3):
            s = 0.0
            for a in range(xg.shape[0]):
                s += xg[a, i] * dg[a, k, q]
            J[i, k] = s
    return (
        J[0, 0] * (J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1])
        - J[0, 1] * (J[1, 0] * J[2, 2] - J[1, 2] * J[2, 0])
        + J[0, 2] * (J[1, 0] * J[2, 1] - J[1, 1] * J[2, 0])
    )


@nb.njit(cache=True)
def _stiffness(
    geo: IntArray, xyz: Array, dg: Array, cells: IntArray, db: Array, w: Array,
    ptr: IntArray, slot: IntArray, lam: float, mu: float,
) -> Array:  # fmt: skip
    ng, ne = geo.shape
    nb_, nq = cells.shape[0], len(w)
    data = np.zeros(9 * ptr[-1])
    xg = np.empty((ng, 3))
    J = np.empty((3, 3))
    inv = np.empty((3, 3))
    G = np.empty((nb_, 3))
    Ke = np.empty((nb_, nb_, 3, 3))
    for e in range(ne):
        for a in range(ng):
            for i in range(3):
                xg[a, i] = xyz[i, geo[a, e]]
        Ke[:] = 0.0
        for q in range(nq):
            det = _jacobian(xg, dg, q, J)
            r = 1.0 / det
            inv[0, 0] = (J[1, 1] * J[2, 2] - J[1, 2] * J[2, 1]) * r
            inv[0, 1] = (J[0, 2] * J[2, 1] - J[0, 1] * J[2, 2]) * r
            inv[0, 2] = (J[0, 1] * J[1, 2] - J[0, 2] * J[1, 1]) * r
            inv[1, 0] = (J[1, 2] * J[2, 0] - J[1, 0] * J[2, 2]) * r
            inv[1, 1] = (J[0, 0] * J[2, 2] - J[0, 2] * J[2, 0]) * r
            inv[1, 2] = (J[0, 2] * J[1, 0] - J[0, 0] * J[1, 2]) * r
            inv[2, 0] = (J[1, 0] * J[2, 1] - J[1, 1] * J[2, 0]) * r
            inv[2, 1] = (J[0, 1] * J[2, 0] - J[0, 0] * J[2, 1]) * r
            inv[2, 2] = (J[0, 0] * J[1, 1] - J[0, 1] * J[1, 0]) * r
            for a in range(nb_):  # physical gradients: grad_ref phi . J^-1
                for i in range(3):
                    G[a, i] = (
                        db[a, 0, q] * inv[0, i] + db[a, 1, q] * inv[1, i] + db[a, 2, q] * inv[2, i]
                    )
            dx = abs(det) * w[q]
            lw, mw = lam * dx, mu * dx
            for a in range(nb_):
                for b in range(a, nb_):
                    dot = mw * (G[a, 0] * G[b, 0] + G[a, 1] * G[b, 1] + G[a, 2] * G[b, 2])
                    for i in range(3):
                        for j in range(3):
                            Ke[a, b, i, j] += lw * G[a, i] * G[b, j] + mw * G[a, j] * G[b, i]
                        Ke[a, b, i, i] += dot
        for a in range(nb_):
            sa = cells[a, e]
            deg = ptr[sa + 1] - ptr[sa]
            for b in range(nb_):
                k = slot[e, a, b]
                for i in range(3):
                    base = 9 * ptr[sa] + 3 * i * deg + 3 * k
                    for j in range(3):
                        data[base + j] += Ke[a, b, i, j] if b >= a else Ke[b, a, j, i]
    return data


@nb.njit(cache=True)
def _mass(
    geo: IntArray, xyz: Array, dg: Array, cells: IntArray, vb: Array, w: Array,
    ptr: IntArray, slot: IntArray, rho: float,
) -> Array:  # fmt: skip
    ng, ne = geo.shape
    nb_, nq = cells.shape[0], len(w)
    data = np.zeros(9 * ptr[-1])
    xg = np.empty((ng, 3))
    J = np.empty((3, 3))
    Me = np.empty((nb_, nb_))
    for e in range(ne):
        for a in range(ng):
            for i in range(3):
                xg[a, i] = xyz[i, geo[a, e]]
        Me[:] = 0.0
        for q in range(nq):
            dx = rho * abs(_jacobian(xg, dg, q, J)) * w[q]
            for a in range(nb_):
                for b in range(nb_):
                    Me[a, b] += dx * vb[a, q] * vb[b, q]
        for a in range(nb_):
            sa = cells[a, e]
            deg = ptr[sa + 1] - ptr[sa]
            for b in range(nb_):
                k = slot[e, a, b]
                for i in range(3):
                    data[9 * ptr[sa] + 3 * i * deg + 3 * k + i] += Me[a, b]
    return data


class BlockPattern:
    """The CSR pattern of a vector (3 DOFs a node) field on a mesh's scalar DOFs.

    Parameters
    ----------
    cells : ndarray (nodes per element, elements)
        Scalar DOFs of each element (scikit-fem's ``element_dofs`` of the scalar element).
    n : int
        Number of scalar DOFs.
    """

    def __init__(self, cells: IntArray, n: int) -> None:
        self.cells = np.ascontiguousarray(cells, dtype=np.int64)
        self.ptr, ind = _node_graph(self.cells, int(n))
        self.indptr, self.indices = _vector_pattern(self.ptr, ind)
        self.slot = _slots(self.cells, self.ptr, ind)
        self.n = 3 * int(n)

    def csr(self, data: Array) -> Any:
        """The CSR matrix of ``data`` on this pattern."""
        import scipy.sparse as sp

        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n))


def block_pattern(cells: IntArray, n: int) -> BlockPattern:
    """The :class:`BlockPattern` of scalar element DOFs ``cells`` (``n`` scalar DOFs)."""
    return BlockPattern(cells, n)


def elastic_stiffness(
    pattern: BlockPattern, geo: IntArray, xyz: Array, dgeo: Array, dbasis: Array,
    weights: Array, lam: float, mu: float,
) -> Array:  # fmt: skip
    """CSR data of the isotropic elastic stiffness (N/m) on ``pattern``.

    Parameters
    ----------
    pattern : BlockPattern
    geo : ndarray (geometry nodes per element, elements)
        The elements' geometry nodes, columns of ``xyz``.
    xyz : ndarray (3, geometry nodes)
        Geometry node coordinates (m).
    dgeo : ndarray (geometry nodes per element, 3, quadrature points)
        Reference gradients of the geometry's shape functions.
    dbasis : ndarray (shape functions, 3, quadrature points)
        Reference gradients of the element's scalar shape functions.
    weights : ndarray (quadrature points,)
        Quadrature weights on the reference tetrahedron.
    lam, mu : float
        Lamé parameters (Pa).
    """
    return _stiffness(
        np.ascontiguousarray(geo, dtype=np.int64), np.ascontiguousarray(xyz, dtype=float),
        np.ascontiguousarray(dgeo, dtype=float), pattern.cells,
        np.ascontiguousarray(dbasis, dtype=float), np.ascontiguousarray(weights, dtype=float),
        pattern.ptr, pattern.slot, float(lam), float(mu),
    )  # fmt: skip


def consistent_mass(
    pattern: BlockPattern, geo: IntArray, xyz: Array, dgeo: Array, basis: Array,
    weights: Array, rho: float,
) -> Array:  # fmt: skip
    """CSR data of the consistent mass (kg) on ``pattern``; ``basis`` (shape functions,
    quadrature points) holds the scalar shape functions' values, ``rho`` the density
    (kg/m^3); the rest as :func:`elastic_stiffness`."""
    return _mass(
        np.ascontiguousarray(geo, dtype=np.int64), np.ascontiguousarray(xyz, dtype=float),
        np.ascontiguousarray(dgeo, dtype=float), pattern.cells,
        np.ascontiguousarray(basis, dtype=float), np.ascontiguousarray(weights, dtype=float),
        pattern.ptr, pattern.slot, float(rho),
    )  # fmt: skip
