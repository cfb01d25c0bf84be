"""Load integration of the FE tooth model without scikit-fem's inverse mapping (issue 26,
item 8b): ``contact.compliance.facet_quadrature`` and the flank loads built on it.

scikit-fem's ``FacetBasis`` finds the reference coordinates of its facet quadrature
points by a Newton iteration (``MappingIsoparametric.invF``) that fails on valid but
strongly curved quadratic tetrahedra ("Newton iteration didn't converge"); gmsh's
parallel mesher makes one now and then, so ``reducerlab contact`` failed once in a few
runs. The quadrature here takes the reference points from the facets' own corners.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

skfem = pytest.importorskip("skfem")

from skfem import Basis, ElementTetP2, ElementVector, FacetBasis  # noqa: E402
from skfem.mapping import MappingIsoparametric  # noqa: E402

from reducerlab.contact.compliance import (  # noqa: E402
    FacetQuadratureError,
    facet_quadrature,
    flank_influence,
)
from reducerlab.errors import ReducerlabError  # noqa: E402
from reducerlab.fe.elasticity import STEEL  # noqa: E402

VECTOR = ElementVector(ElementTetP2())


def bent_block() -> object:
    """A block ``[0, 1] x [0, 1] x [0, 0.5]`` bent about the y axis onto radii 2..2.5
    (m): 54 quadratic tetrahedra with curved faces (their mid-edge nodes on the arcs)."""
    m1 = skfem.MeshTet.init_tensor(np.linspace(0, 1, 4), np.linspace(0, 1, 4), [0.0, 0.25, 0.5])
    m2 = skfem.MeshTet2.from_mesh(m1)
    x, y, z = m2.doflocs
    R = 2.0 + z
    return skfem.MeshTet2(np.array([R * np.sin(x / 2), y, R * np.cos(x / 2)]), m2.t)


#: Mid-edge node offsets of the unit tetrahedron (m, edges 01 12 02 03 13 23): a valid
#: element (the Jacobian determinant varies by a factor 2.2 over it, positive everywhere)
#: whose facets scikit-fem's Newton iteration cannot invert.
CURVED = np.array(
    [
        [0.06, 0.13, -0.14],
        [-0.12, 0.07, -0.03],
        [-0.07, -0.02, -0.14],
        [-0.13, -0.11, 0.07],
        [0.11, -0.01, 0.14],
        [0.11, -0.11, -0.1],
    ]
)


def curved_tet() -> object:
    meshio = pytest.importorskip("meshio")
    from skfem.io.meshio import from_meshio

    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    pairs = ((0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3))
    mids = np.array([(corners[i] + corners[j]) / 2 for i, j in pairs]) + CURVED
    return from_meshio(meshio.Mesh(np.r_[corners, mids], [("tetra10", np.arange(10)[None])]))


def test_same_quadrature_as_facet_basis_on_a_curved_mesh():
    """Where scikit-fem's FacetBasis works, the quadrature is the same: points, area
    elements, normals, shape-function values and DOFs, to rounding."""
    mesh = bent_block()
    basis = Basis(mesh, VECTOR)
    bf = mesh.boundary_facets()
    q = facet_quadrature(basis, bf, intorder=4)
    fb = FacetBasis(mesh, VECTOR, facets=bf, intorder=4)
    np.testing.assert_allclose(q.points, np.asarray(fb.global_coordinates()), atol=1e-14)
    np.testing.assert_allclose(q.dx, fb.dx, rtol=1e-13)
    np.testing.assert_allclose(q.normals, np.asarray(fb.normals), atol=1e-12)
    np.testing.assert_array_equal(q.dofs, fb.element_dofs)
    for i in range(fb.Nbfun):  # vector function i: component i % 3 of scalar i // 3
        v = np.asarray(fb.basis[i][0])
        np.testing.assert_allclose(v[i % 3], q.values[i // 3], atol=1e-12)
        assert not np.any(np.delete(v, i % 3, axis=0))
    # the bent block's surface: 2 (1 x 0.5) ends, 2 side faces of the annular sector
    # (angle 1/2 rad, radii 2..2.5) and the cylinders of radius 2 and 2.5 (length 1/2)
    side = 0.5 * 0.5 * (2.5**2 - 2.0**2)
    area = 2 * 0.5 + 2 * side + 0.5 * (2.0 + 2.5)
    assert q.dx.sum() == pytest.approx(area, rel=1e-4)


def test_load_vectors_unchanged_on_a_normal_mesh():
    """The flank loads by the new quadrature are those of the FacetBasis integration
    that ``_bump_loads`` used before (same formula, written out here)."""
    import scipy.sparse as sp

    from reducerlab.contact import compliance

    mesh = bent_block()
    basis = Basis(mesh, VECTOR)
    centres = np.array([[2.5 * math.sin(0.25), 0.5, 2.5 * math.cos(0.25)]])  # outer cylinder
    normals = centres / np.linalg.norm(centres) * [1, 0, 1]
    a = 0.3
    F = compliance._bump_loads(basis, mesh, centres, normals, a)
    # the previous implementation (FacetBasis on all boundary facets near the load)
    fb = FacetBasis(mesh, VECTOR, facets=mesh.boundary_facets(), intorder=4)
    x = np.asarray(fb.global_coordinates()).reshape(3, -1).T
    n = np.asarray(fb.normals).reshape(3, -1).T
    r2 = np.sum((x - centres[0]) ** 2, axis=1) / a**2
    B = np.where((r2 < 1) & (n @ normals[0] > 0.5), (1 - r2) ** 2, 0.0)
    nf, nq = fb.dx.shape
    rows = np.repeat(fb.element_dofs[:, :, None], nq, axis=2)
    cols = np.broadcast_to(np.arange(nf * nq).reshape(nf, nq), rows.shape)
    ref = np.zeros(basis.N)
    for c in range(3):
        vals = np.stack([np.asarray(fb.basis[i][0])[c] for i in range(fb.Nbfun)]) * fb.dx
        S = sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(basis.N, nf * nq))
        ref -= S @ (B * normals[0, c])
    ref /= compliance._force_of(ref, basis, normals[0])
    np.testing.assert_allclose(F[:, 0], ref, atol=1e-12 * np.abs(ref).max())
    assert compliance._force_of(F[:, 0], basis, normals[0]) == pytest.approx(1.0)


def test_curved_element_that_defeats_the_newton_iteration():
    """The root cause, reproduced: on this valid curved tetrahedron scikit-fem's
    FacetBasis raises "Newton iteration didn't converge"; the facet quadrature needs no
    inverse and integrates the closed surface exactly (``int n dA = 0`` and
    ``int x . n dA / 3`` = the volume, polynomials of degree 2 and 4 on quadratic faces)."""
    mesh = curved_tet()
    basis = Basis(mesh, VECTOR, intorder=4)
    # a valid element: the Jacobian determinant is positive all over it
    X = np.random.default_rng(3).dirichlet(np.ones(4), 20000)[:, 1:].T
    det = basis.mapping.detDF(np.c_[X, np.eye(3), np.zeros((3, 1))])
    assert det.min() > 0.4 * det.max()
    with pytest.raises(Exception, match="Newton iteration didn't converge"):
        FacetBasis(mesh, VECTOR, intorder=4)
    q = facet_quadrature(basis, mesh.boundary_facets(), intorder=4)
    flux = np.einsum("cfq,fq->c", q.normals, q.dx)
    assert np.abs(flux).max() < 1e-14
    volume = np.einsum("cfq,cfq,fq->", q.points, q.normals, q.dx) / 3
    assert volume == pytest.approx(float(np.sum(basis.dx)), rel=1e-12)
    # the shape functions sum to one at every facet point (a partition of unity)
    np.testing.assert_allclose(q.values.sum(axis=0), 1.0, atol=1e-12)


def held_bottom(basis):
    """DOFs of the bent block's inner cylinder (radius 2)."""
    x = basis.mesh.p
    on = np.abs(np.hypot(x[0], x[2]) - 2.0) < 1e-9
    bf = basis.mesh.boundary_facets()
    facets = bf[np.all(on[basis.mesh.facets[:, bf]], axis=0)]
    return np.asarray(basis.get_dofs(facets=facets).all(), dtype=np.int64)


def test_no_newton_iteration_in_the_tooth_model(monkeypatch):
    """The load integration never calls the inverse mapping: with it made to fail as it
    did, the influence coefficients still come out (symmetric, positive diagonal)."""

    def newton_fails(self, x, tind=None, **_):
        raise Exception("Newton iteration didn't converge up to TOL=1e-12")

    from reducerlab.contact import compliance

    mesh = bent_block()
    points = np.array([[2.5 * math.sin(t), 0.5, 2.5 * math.cos(t)] for t in (0.2, 0.3)])
    normals = points / np.linalg.norm(points, axis=1)[:, None] * [1, 0, 1]
    basis = Basis(mesh, VECTOR)
    free = compliance._bump_loads(basis, mesh, points, normals, 0.2)
    monkeypatch.setattr(MappingIsoparametric, "invF", newton_fails)
    np.testing.assert_array_equal(compliance._bump_loads(basis, mesh, points, normals, 0.2), free)
    K, dofs = flank_influence(mesh, held_bottom, points, normals, [0.0], 0.2, STEEL)
    assert K.shape == (2, 2) and dofs == mesh.doflocs.shape[1] * 3
    assert np.all(np.isfinite(K)) and K[0, 1] == K[1, 0]


def test_a_corrupt_mesh_is_a_clear_error_naming_the_gear(monkeypatch):
    """Facet points that the elements do not reproduce (here forced by shifting the
    facets' map) are a ReducerlabError naming the gear and what to change, not a
    traceback of scikit-fem."""
    original = MappingIsoparametric.G
    monkeypatch.setattr(
        MappingIsoparametric, "G", lambda self, X, find=None: original(self, X, find) + 1e-3
    )
    mesh = bent_block()
    points = np.array([[2.5 * math.sin(0.25), 0.5, 2.5 * math.cos(0.25)]])
    normals = points / np.linalg.norm(points) * [1, 0, 1]
    with pytest.raises(FacetQuadratureError) as info:
        flank_influence(mesh, held_bottom, points, normals, [0.0], 0.2, STEEL,
                        name="internal gear (z = 32)")  # fmt: skip
    message = str(info.value)
    assert isinstance(info.value, ReducerlabError)
    assert "internal gear (z = 32)" in message and "--tooth-size" in message
    assert "off their facets" in message
