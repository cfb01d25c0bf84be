"""Validity of curved quadratic tetrahedra: the Jacobian of the isoparametric map.

A 10-node tetrahedron maps the reference tetrahedron ``xi, eta, zeta >= 0,
xi + eta + zeta <= 1`` to space by ``x(xi) = sum_a N_a(xi) x_a`` with the quadratic
Lagrange shape functions ``N_a = l_a (2 l_a - 1)`` at the corners and ``4 l_a l_b`` at
the mid-edge nodes (``l``: barycentric coordinates); its Jacobian ``det(dx/dxi)`` is a
cubic polynomial over the element. gmsh places the mid-edge nodes of boundary edges on
the curved CAD surfaces (``setOrder(2)``), and where a surface turns sharply within one
element (the bevel teeth's root at an end face, the double-arc profile's corner) a
mid-edge node can move so far that the Jacobian falls to zero or below inside the
element: the map folds, the element's stiffness and above all its stress recovery are
meaningless (the 7e5 MPa "root stress" of a double-arc tooth model of 0.8 mm elements,
docs/assumptions.md).

:func:`jacobian_ratio` measures each element by ``min det J / det J_0`` over the
35 points of the degree-4 lattice of the reference tetrahedron (corners, mid-edges,
face and interior points), ``det J_0`` the Jacobian of the straight-sided tetrahedron
of the same corners: 1 for straight edges, <= 0 for a folded element.
:func:`mend_curved_tets` straightens the edges of elements below
:data:`MIN_JACOBIAN_RATIO` (their mid-edge nodes back to the chord midpoints, the
corners are valid tetrahedra) and refuses a mesh it cannot mend.

Units: whatever the points are in (ratios are dimensionless).
"""

from __future__ import annotations

import itertools

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError

__all__ = ["MIN_JACOBIAN_RATIO", "TET10_EDGES", "jacobian_ratio", "mend_curved_tets"]

Array = NDArray[np.float64]

#: The corners of the mid-edge nodes 4..9 of a 10-node tetrahedron (VTK/meshio order).
TET10_EDGES = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))

#: Elements whose Jacobian ratio falls below this are straightened: gmsh's own high-order
#: optimiser treats elements below a scaled Jacobian of 0.1 as bad
#: (``Mesh.HighOrderThresholdMin``, default 0.1); docs/assumptions.md.
MIN_JACOBIAN_RATIO = 0.1


def _lattice(n: int = 4) -> Array:
    """Points ``(i, j, k) / n`` of the reference tetrahedron, ``i + j + k <= n``."""
    pts = [(i, j, k) for i, j, k in itertools.product(range(n + 1), repeat=3) if i + j + k <= n]
    return np.array(pts, dtype=float) / n


def _shape_gradients(xi: Array) -> Array:
    """Gradients (s, 10, 3) of the quadratic shape functions at reference points
    ``xi`` (s, 3), nodes in VTK order."""
    lam = np.column_stack([1.0 - xi.sum(axis=1), xi])  # (s, 4) barycentric
    dl = np.array([[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    g = np.empty((xi.shape[0], 10, 3))
    g[:, :4] = (4.0 * lam - 1.0)[:, :, None] * dl[None]
    for e, (a, b) in enumerate(TET10_EDGES):
        g[:, 4 + e] = 4.0 * (lam[:, a, None] * dl[b] + lam[:, b, None] * dl[a])
    return g


_GRAD = _shape_gradients(_lattice())


def jacobian_ratio(points: Array, tets: NDArray[np.int64]) -> Array:
    """``min det J / det J_0`` of each quadratic tetrahedron (module docstring).

    Parameters
    ----------
    points : ndarray (n, 3)
        Node coordinates.
    tets : ndarray of int (m, 10)
        Corners then mid-edge nodes (:data:`TET10_EDGES`), positively oriented corners.

    Returns
    -------
    ndarray (m,)
        1 for a straight-sided element; <= 0 where the curved element folds.
    """
    X = np.asarray(points, dtype=float)[np.asarray(tets)]  # (m, 10, 3)
    J = np.einsum("mna,snb->msab", X, _GRAD)
    det = np.linalg.det(J)
    c = X[:, :4]
    d0 = np.einsum("ij,ij->i", np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), c[:, 3] - c[:, 0])
    return det.min(axis=1) / d0


def mend_curved_tets(
    points: Array, tets: NDArray[np.int64], what: str, limit: float = MIN_JACOBIAN_RATIO
) -> tuple[Array, int]:
    """Straighten the edges of the quadratic tetrahedra whose Jacobian ratio is below
    ``limit``: their mid-edge nodes go to the midpoints of their edges' corners (the
    neighbours sharing an edge follow: the mesh stays conforming), repeated until every
    element passes (at most five rounds).

    Parameters
    ----------
    points : ndarray (n, 3)
        Node coordinates (not modified).
    tets : ndarray of int (m, 10)
        Elements (:func:`jacobian_ratio`).
    what : str
        The part, named in the error message.
    limit : float
        Least Jacobian ratio kept (:data:`MIN_JACOBIAN_RATIO`).

    Returns
    -------
    points : ndarray (n, 3)
        The mended coordinates (a copy).
    mended : int
        Number of elements straightened.

    Raises
    ------
    ReducerlabError
        Corners that are not a positively oriented tetrahedron (zero or negative
        volume), or elements still below ``limit`` after five rounds.
    """
    P = np.array(points, dtype=float)
    T = np.asarray(tets)
    c = P[T[:, :4]]
    d0 = np.einsum("ij,ij->i", np.cross(c[:, 1] - c[:, 0], c[:, 2] - c[:, 0]), c[:, 3] - c[:, 0])
    if np.any(d0 <= 0):
        raise ReducerlabError(
            f"{what}: {np.count_nonzero(d0 <= 0)} tetrahedra have corners of zero or "
            "negative volume (degenerate or inverted elements)"
        )
    r = jacobian_ratio(P, T)
    mended = np.zeros(len(T), dtype=bool)
    for _ in range(5):
        bad = np.flatnonzero(r < limit)
        if bad.size == 0:
            return P, int(mended.sum())
        mended[bad] = True
        for e, (a, b) in enumerate(TET10_EDGES):
            P[T[bad, 4 + e]] = 0.5 * (P[T[bad, a]] + P[T[bad, b]])
        r = jacobian_ratio(P, T)
    worst = float(r.min())
    raise ReducerlabError(
        f"{what}: {np.count_nonzero(r < limit)} quadratic tetrahedra keep a Jacobian ratio "
        f"below {limit} (worst {worst:.3g}) even with straight edges (sliver elements); "
        "change the element sizes"
    )
