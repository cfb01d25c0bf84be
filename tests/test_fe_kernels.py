"""The compiled FE assembly (``fe.kernels``) against scikit-fem's ``asm``, and the
forward-substitution influence matrix (``fe.elasticity.pardiso_gram``) against a
whole sparse solve (issue 28)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.linalg import splu
from skfem import MeshTet, MeshTet2

from reducerlab.errors import ReducerlabError
from reducerlab.fe.elasticity import Material, assemble, pardiso_gram

MATERIAL = Material(206e9, 0.29, 7850.0)

#: the two assemblies sum the same products in another order: rounding only
#: (observed ~5e-16 of the largest entry)
TOL = 1e-12


def _rel(A, B) -> float:
    return float(abs(A - B).max() / abs(B).max())


def _skewed() -> MeshTet:
    """A refined unit cube, sheared and stretched (elements of many shapes)."""
    m = MeshTet().refined(2)
    p = m.p.copy()
    p[0] += 0.3 * p[1] + 0.1 * p[2] ** 2
    p[2] *= 2.5
    return MeshTet(p, m.t)


@pytest.mark.parametrize("order", [1, 2])
def test_straight_tets_match_scikit_fem(order: int) -> None:
    mesh = _skewed()
    K0, M0, b0 = assemble(mesh, MATERIAL, order, _engine="skfem")
    K1, M1, b1 = assemble(mesh, MATERIAL, order)
    assert K1.shape == K0.shape and b1.N == b0.N
    assert _rel(K1, K0) < TOL
    assert _rel(M1, M0) < TOL
    assert np.array_equal(b1.element_dofs, b0.element_dofs)


def test_curved_quadratic_tets_match_scikit_fem() -> None:
    """The isoparametric (curved) map of ``MeshTet2``: Jacobians vary inside each
    element; the stiffness with the 4-point rule, the mass with the 11-point one."""
    mesh = MeshTet2.init_ball()
    K0, M0, _ = assemble(mesh, MATERIAL, 2, _engine="skfem")
    K1, M1, _ = assemble(mesh, MATERIAL, 2)
    assert _rel(K1, K0) < TOL
    assert _rel(M1, M0) < TOL
    # and the matrices are a body's: symmetric, rigid translations free of force
    assert _rel(K1.T, K1) < TOL
    ones = np.zeros(K1.shape[0])
    ones[0::3] = 1.0
    assert np.abs(K1 @ ones).max() < 1e-9 * abs(K1).max()


def test_stiffness_only() -> None:
    K, M, _ = assemble(_skewed(), MATERIAL, 2, mass=False)
    K0, _, _ = assemble(_skewed(), MATERIAL, 2, _engine="skfem")
    assert M is None and _rel(K, K0) < TOL


def test_unknown_engine() -> None:
    with pytest.raises(ReducerlabError, match="engine"):
        assemble(_skewed(), MATERIAL, 2, _engine="other")


def test_gram_by_forward_substitution_matches_a_whole_solve(monkeypatch) -> None:
    """``B^T A^-1 B`` from PARDISO's forward substitution against scipy's SuperLU
    solve of a held stiffness (well conditioned enough for 1e-9); the forward path is
    the one taken (the whole solve only for the check's single column)."""
    pypardiso = pytest.importorskip("pypardiso")
    calls = []
    real = pypardiso.PyPardisoSolver._call_pardiso

    def spy(self, A, b):
        calls.append((int(self.phase), 1 if b.ndim == 1 else b.shape[1]))
        return real(self, A, b)

    monkeypatch.setattr(pypardiso.PyPardisoSolver, "_call_pardiso", spy)
    mesh = _skewed()
    K, _, basis = assemble(mesh, MATERIAL, 2, mass=False)
    held = basis.get_dofs(lambda x: x[2] < 1e-9).all()
    free = np.setdiff1d(np.arange(K.shape[0]), held)
    A = K[free][:, free].tocsr()
    rng = np.random.default_rng(3)
    B = sp.random(A.shape[0], 7, density=0.05, random_state=rng).toarray()
    want = B.T @ splu(A.tocsc()).solve(B)
    got = pardiso_gram(A, B)
    assert got is not None
    assert np.abs(got - want).max() < 1e-9 * np.abs(want).max()
    assert np.array_equal(got, got.T)
    assert (331, 7) in calls and (33, 1) in calls and (33, 7) not in calls
