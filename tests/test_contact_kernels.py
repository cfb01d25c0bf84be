"""The compiled contact-matrix kernels against their definitions written in numpy."""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.contact.compliance import ToothCompliance
from reducerlab.contact.halfspace import influence_matrix, rectangle_influence
from reducerlab.errors import ReducerlabError

E_STAR = 1.13e11


def _reference(P, U, V, hu, hv, labels):
    """``influence_matrix`` entry by entry from its docstring: the offset projected on
    cell j's axes, stretched to the chord, through the numpy ``rectangle_influence``."""
    W = np.cross(U, V)
    d = P[:, None, :] - P[None, :, :]
    dx = np.einsum("ijk,jk->ij", d, U)
    dy = np.einsum("ijk,jk->ij", d, V)
    dz = np.einsum("ijk,jk->ij", d, W)
    r2 = dx**2 + dy**2
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(r2 > 0, np.sqrt(1 + dz**2 / r2), 1.0)
    dx, dy = dx * s, dy * s
    dx = np.where((r2 == 0) & (dz != 0), np.abs(dz), dx)
    f = rectangle_influence(dx, dy, hu[None, :], hv[None, :])
    C = f / (math.pi * E_STAR * 4 * hu * hv)[None, :]
    C[labels[:, None] != labels[None, :]] = 0.0
    return 0.5 * (C + C.T)


def test_half_space_kernel_is_the_numpy_definition_on_a_curved_cloud():
    # 300 cells of unequal sizes on a sphere of radius 10 mm, three bodies, spread so
    # that both the closed form (near) and the multipole expansion (beyond 12 half
    # sides) are used: the kernel equals the definition to round-off (1e-12 relative).
    rng = np.random.default_rng(11)
    n = 300
    theta = rng.uniform(-0.3, 0.3, n)
    phi = rng.uniform(-0.3, 0.3, n)
    R = 0.01
    P = R * np.column_stack(
        [np.sin(theta), np.cos(theta) * np.sin(phi), np.cos(theta) * np.cos(phi)]
    )
    N = P / R
    U = np.cross([0.0, 1.0, 0.0], N)
    U /= np.linalg.norm(U, axis=1)[:, None]
    V = np.cross(N, U)
    hu = rng.uniform(2e-5, 8e-5, n)
    hv = rng.uniform(2e-5, 8e-5, n)
    labels = rng.integers(0, 3, n)
    C = influence_matrix(P, U, V, hu, hv, E_STAR, same_body=labels)
    ref = _reference(P, U, V, hu, hv, labels)
    np.testing.assert_allclose(C, ref, rtol=1e-12, atol=1e-12 * ref.max())
    # both branches were exercised
    d = np.linalg.norm(P[:, None] - P[None], axis=2)
    assert np.any(d < 12 * hu.max()) and np.any(d > 12 * hu.max())


def _compliance(rng):
    u_nodes = np.linspace(0.0, 1.0, 4)
    v_nodes = np.linspace(0.0, 1.0, 5)
    L = 3 * u_nodes.size * v_nodes.size
    A = rng.normal(size=(L, L))
    return ToothCompliance(u_nodes, v_nodes, (-1, 0, 1), A @ A.T * 1e-10, 1, 1e-3)


def _dense_w(comp, tooth, u, v):
    """The bilinear interpolation matrix from the load points, written out."""
    nu, nv = comp.u_nodes.size, comp.v_nodes.size
    W = np.zeros((len(tooth), len(comp.teeth) * nu * nv))
    for i in range(len(tooth)):
        iu = min(max(int(np.searchsorted(comp.u_nodes, u[i])) - 1, 0), nu - 2)
        iv = min(max(int(np.searchsorted(comp.v_nodes, v[i])) - 1, 0), nv - 2)
        tu = (u[i] - comp.u_nodes[iu]) / (comp.u_nodes[iu + 1] - comp.u_nodes[iu])
        tv = (v[i] - comp.v_nodes[iv]) / (comp.v_nodes[iv + 1] - comp.v_nodes[iv])
        base = comp.teeth.index(int(tooth[i])) * nu * nv
        for a, wa in ((0, 1 - tu), (1, tu)):
            for b, wb in ((0, 1 - tv), (1, tv)):
                W[i, base + (iu + a) * nv + iv + b] += wa * wb
    return W


def test_cell_compliance_is_half_space_plus_w_k_w_transpose():
    # CellCompliance makes columns on demand: the half-space matrix of the cells
    # (influence_matrix) plus W_A K_A W_A^T + W_B K_B W_B^T with W the bilinear
    # interpolation from each gear's load points (written out here; points beyond the
    # node range extrapolate linearly). Columns made in any order, the diagonal, C_AA
    # and C F agree with that dense matrix to round-off.
    from reducerlab.contact.cellmatrix import CellCompliance

    rng = np.random.default_rng(5)
    comp_a, comp_b = _compliance(rng), _compliance(rng)
    n = 80
    tooth = rng.choice([-1, 0, 1], n)
    P = np.column_stack([rng.uniform(0, 4e-3, n), rng.uniform(0, 8e-3, n), np.zeros(n)])
    U = np.tile([1.0, 0.0, 0.0], (n, 1))
    V = np.tile([0.0, 1.0, 0.0], (n, 1))
    h = np.full(n, 5e-5)
    ua, va = rng.uniform(-0.1, 1.1, n), rng.uniform(0.0, 1.0, n)
    ub, vb = rng.uniform(0.0, 1.0, n), rng.uniform(0.0, 1.0, n)
    Wa, Wb = _dense_w(comp_a, tooth, ua, va), _dense_w(comp_b, tooth, ub, vb)
    ref = influence_matrix(P, U, V, h, h, E_STAR, same_body=tooth)
    ref = ref + Wa @ comp_a.matrix @ Wa.T + Wb @ comp_b.matrix @ Wb.T
    bending = [(comp_a, tooth, ua, va), (comp_b, tooth, ub, vb)]
    C = CellCompliance(P, U, V, h, h, E_STAR, tooth, bending)
    tol = 1e-12 * np.abs(ref).max()
    np.testing.assert_allclose(C.diagonal(), np.diag(ref), rtol=1e-12, atol=tol)
    A = np.array([7, 3, 41, 12, 60])
    np.testing.assert_allclose(C.block(A), ref[np.ix_(A, A)], rtol=1e-10, atol=tol)
    assert C.columns_made == A.size
    F = np.zeros(n)
    F[A] = rng.uniform(1, 2, A.size)
    np.testing.assert_allclose(C.apply(F, A), ref @ F, rtol=1e-10, atol=tol * F.sum())
    np.testing.assert_allclose(C.dense(), ref, rtol=1e-10, atol=tol)
    # interpolation reproduces a node exactly
    cols, w = comp_a.stencil([0], [comp_a.u_nodes[2]], [comp_a.v_nodes[3]])
    nu, nv = comp_a.u_nodes.size, comp_a.v_nodes.size
    assert w.sum() == pytest.approx(1.0)
    assert cols[0][np.argmax(w[0])] == 1 * nu * nv + 2 * nv + 3


def test_stencil_rejects_a_tooth_outside_the_model():
    comp = _compliance(np.random.default_rng(0))
    with pytest.raises(ReducerlabError, match="tooth pairs must be among"):
        comp.stencil([2], [0.5], [0.5])
