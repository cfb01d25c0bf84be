"""MKL PARDISO through pypardiso (issue 28): the direct solves without iterative
refinement that ``body_modes`` uses, and the library lookup."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp

from reducerlab.fe.elasticity import body_modes, import_pypardiso, pardiso_inverse

pytestmark = pytest.mark.skipif(import_pypardiso() is None, reason="pypardiso not installed")


def _laplacian(m: int) -> sp.csr_matrix:
    """The graph Laplacian of an ``m^3`` grid (7-point stencil, free boundary):
    symmetric, positive semi-definite, the constant vector its null space."""
    d = 2 * np.ones(m)
    d[[0, -1]] = 1
    one = sp.diags([-np.ones(m - 1), d, -np.ones(m - 1)], [-1, 0, 1])
    eye = sp.identity(m)
    lap = (
        sp.kron(sp.kron(one, eye), eye) + sp.kron(sp.kron(eye, one), eye)
        + sp.kron(sp.kron(eye, eye), one)
    )  # fmt: skip
    return lap.tocsr()


def test_direct_solves_match_pypardiso():
    A = (_laplacian(8) + 1e-3 * sp.identity(8**3)).tocsr()  # positive definite
    rng = np.random.default_rng(3)
    b = rng.standard_normal(A.shape[0])
    B = rng.standard_normal((A.shape[0], 5))
    ref = pardiso_inverse(A)
    fast = pardiso_inverse(A, 0)
    x = fast.matvec(b)
    assert x.shape == b.shape
    assert np.linalg.norm(A @ x - b) <= 1e-10 * np.linalg.norm(b)
    assert np.allclose(x, ref.matvec(b), rtol=1e-9, atol=1e-12 * np.abs(x).max())
    X = fast.matmat(B)
    assert X.shape == B.shape
    assert np.linalg.norm(A @ X - B) <= 1e-10 * np.linalg.norm(B)


def test_body_modes_frequencies_unchanged_by_the_refinement(monkeypatch):
    """``body_modes`` (no refinement) against the same eigen-solution on pypardiso's
    refined solves: a free grid of unit masses and springs, one rigid mode."""
    from reducerlab.fe import elasticity

    K = _laplacian(7)  # one "rigid" mode: the constant vector
    M = sp.identity(K.shape[0], format="csr")
    fast = body_modes(K, M, 5)
    orig = elasticity.pardiso_inverse
    monkeypatch.setattr(elasticity, "pardiso_inverse", lambda A, refinement=None: orig(A))
    ref = body_modes(K, M, 5)
    assert fast.rigid == ref.rigid == 1
    np.testing.assert_allclose(fast.frequencies, ref.frequencies, rtol=1e-9)
    # the lowest elastic eigenvalue of the free 7^3 grid: 2 (1 - cos(pi / 7)), thrice
    f1 = math.sqrt(2 * (1 - math.cos(math.pi / 7))) / (2 * math.pi)
    np.testing.assert_allclose(fast.frequencies[:3], f1, rtol=1e-9)
