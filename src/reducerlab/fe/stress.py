"""Stress recovery of quadratic tetrahedra at surface nodes, and principal stresses.

The displacement of a 10-node (P2) tetrahedron is quadratic, its strain and stress
(Hooke, ``sigma = lambda tr(eps) I + 2 mu eps``) linear inside each element and
discontinuous between elements. At a node of the body's surface the stress is taken as
the mean of the values of every element that holds the node, each evaluated at the
node itself (its reference coordinates in that element): the averaged nodal stress of
the finite-element literature (Zienkiewicz & Taylor, *The Finite Element Method*,
vol. 1, 6th ed., section 14.2, "nodal averaging"), which on a free surface is closer to
the converged value than the element's interior (quadrature-point) values.

:func:`surface_stress_operator` returns that recovery as one sparse matrix acting on the
displacement DOFs, so that many load cases cost one sparse product.

Voigt order: ``xx, yy, zz, yz, xz, xy`` (Pa). SI units throughout.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from .elasticity import Material

__all__ = ["VOIGT", "SurfaceStress", "principal_stresses", "surface_stress_operator"]

Array = NDArray[np.float64]

#: Voigt order of the six stress components (index pairs of the tensor)
VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))


@dataclass(frozen=True)
class SurfaceStress:
    """Averaged nodal stress at surface nodes as a linear map of the displacements.

    Attributes
    ----------
    points : ndarray (n, 3)
        Node positions (m).
    normals : ndarray (n, 3)
        Outward unit normals of the surface at the nodes (area-weighted mean of the
        normals of the given facets that hold each node).
    facet_of : ndarray of int (n,)
        One of the given facets (its position in the ``facets`` argument) that holds
        each node.
    operator : scipy.sparse.csr_matrix (6 n, N)
        Stress components (Pa) per unit displacement DOF (m): row ``6 i + k`` is
        component ``VOIGT[k]`` at node ``i``.
    """

    points: Array
    normals: Array
    facet_of: NDArray[np.int64]
    operator: Any


def surface_stress_operator(
    basis: Any, material: Material, facets: NDArray[np.int64]
) -> SurfaceStress:
    """The averaged nodal stress (module docstring) at the nodes of boundary ``facets``.

    Parameters
    ----------
    basis : skfem.Basis
        The vector P2 basis of :func:`reducerlab.fe.elasticity.assemble` (order 2) on a
        ``MeshTet`` or ``MeshTet2``.
    material : Material
        Lamé parameters of Hooke's law.
    facets : array of int
        Boundary facet indices of ``basis.mesh`` whose corner and mid-edge nodes are
        wanted.

    Returns
    -------
    SurfaceStress

    Raises
    ------
    ReducerlabError
        No facets, or a basis that is not a vector quadratic one.
    """
    import scipy.sparse as sp

    mesh = basis.mesh
    facets = np.unique(np.asarray(facets, dtype=np.int64))
    if facets.size == 0:
        raise ReducerlabError("surface stress: no facets given")
    scalar = basis.elem.elem
    edofs = np.asarray(basis.element_dofs)
    n_local = scalar.doflocs.shape[0]
    if n_local != 10 or edofs.shape[0] != 30:
        raise ReducerlabError("surface stress: needs the vector quadratic (P2) tetrahedron basis")
    xdofs = edofs[0::3]  # (10, elements): the x DOF names each node
    # the facets' nodes: three corners and three mid-edge nodes each
    corner = np.asarray(basis.nodal_dofs[0])[mesh.facets[:, facets]]  # (3, nf)
    mid = np.asarray(basis.edge_dofs[0])[mesh.f2e[:, facets]]  # (3, nf)
    fnodes = np.vstack([corner, mid])  # (6, nf)
    nodes, inverse = np.unique(fnodes, return_inverse=True)
    inverse = inverse.reshape(fnodes.shape)
    n = nodes.size
    # facet normals (straight facet through the corners), outward from their element
    P = mesh.p[:, mesh.facets[:, facets]]  # (3 coords, 3 corners, nf)
    nrm = np.cross((P[:, 1] - P[:, 0]).T, (P[:, 2] - P[:, 0]).T)  # (nf, 3), |.| = 2 area
    cen = mesh.p[:, mesh.t[:, mesh.f2t[0, facets]]].mean(axis=1).T
    out = np.einsum("ij,ij->i", nrm, P.mean(axis=1).T - cen) > 0
    nrm[~out] *= -1.0
    acc = np.zeros((n, 3))
    for a in range(6):
        np.add.at(acc, inverse[a], nrm)
    normals = acc / np.linalg.norm(acc, axis=1, keepdims=True)
    facet_of = np.zeros(n, dtype=np.int64)
    facet_of[inverse.ravel()] = np.tile(np.arange(facets.size), 6)
    points = np.asarray(basis.doflocs)[:, nodes].T
    # every element that holds a node contributes its stress there
    lam, mu = material.lame
    rows, cols, vals = [], [], []
    count = np.zeros(n)
    for s in range(n_local):
        pos = np.searchsorted(nodes, xdofs[s])
        hit = (pos < n) & (nodes[np.minimum(pos, n - 1)] == xdofs[s])
        elems = np.flatnonzero(hit)
        if elems.size == 0:
            continue
        node = pos[elems]
        np.add.at(count, node, 1.0)
        X = scalar.doflocs[s][:, None]  # (3, 1)
        invDF = np.asarray(basis.mapping.invDF(X, tind=elems))[..., 0]  # (3, 3, ne)
        for i in range(n_local):
            dref = scalar.lbasis(X, i)[1][:, 0]  # (3,)
            g = np.einsum("jke,j->ke", invDF, dref)  # (3, ne): global gradient
            for c in range(3):
                col = edofs[3 * i + c, elems]
                for k, (a, b) in enumerate(VOIGT):
                    v = mu * ((a == c) * g[b] + (b == c) * g[a])
                    if a == b:
                        v = v + lam * g[c]
                    if not np.any(v):
                        continue
                    rows.append(6 * node + k)
                    cols.append(col)
                    vals.append(v)
    r = np.concatenate(rows)
    w = 1.0 / count[r // 6]
    op = sp.csr_matrix(
        (np.concatenate(vals) * w, (r, np.concatenate(cols))), shape=(6 * n, basis.N)
    )
    return SurfaceStress(points, normals, facet_of, op)


def principal_stresses(sigma: Array) -> Array:
    """Principal stresses (Pa), ascending, of Voigt stress vectors.

    Parameters
    ----------
    sigma : ndarray (..., 6)
        Components in :data:`VOIGT` order (Pa).

    Returns
    -------
    ndarray (..., 3)
        Eigenvalues of the symmetric stress tensors, ascending (Pa).
    """
    s = np.asarray(sigma, dtype=float)
    if s.shape[-1] != 6:
        raise ReducerlabError(f"sigma: needs 6 Voigt components last; got shape {s.shape}")
    T = np.empty((*s.shape[:-1], 3, 3))
    for k, (a, b) in enumerate(VOIGT):
        T[..., a, b] = s[..., k]
        T[..., b, a] = s[..., k]
    return np.linalg.eigvalsh(T)
