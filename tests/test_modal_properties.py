"""Properties of assembly and modal analysis on random models (hypothesis)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import torsional_pair
from reducerlab.analysis.modal import frequency_sensitivity, mac, modal
from reducerlab.model import Coupling, Dof, Inertia, Mesh, Model, Support

pos = st.floats(min_value=0.1, max_value=10.0)
stiff = st.floats(min_value=1e5, max_value=1e8)
coef = st.floats(min_value=-1.0, max_value=1.0).filter(lambda c: abs(c) > 0.05)


@st.composite
def random_models(draw) -> Model:
    """Random bodies with x/y/rz DOFs, supports, couplings and meshes."""
    nb = draw(st.integers(2, 4))
    dofs = [Dof(f"b{i}", k) for i in range(nb) for k in ("x", "y", "rz")]
    els = []
    for d in dofs:
        els.append(Inertia(d.name, draw(pos) if d.kind != "rz" else draw(pos) * 1e-3))
        if draw(st.booleans()):
            els.append(Support(d.name, draw(stiff)))
    for i in range(nb - 1):
        names = [d.name for d in dofs if d.body in (f"b{i}", f"b{i + 1}")]
        g = {n: draw(coef) * (0.05 if n.endswith("rz") else 1.0) for n in names}
        if draw(st.booleans()):
            els.append(Mesh(g, stiffness=draw(stiff), name=f"mesh{i}"))
        else:
            els.append(Coupling(g, draw(stiff), name=f"shaft{i}"))
    return Model(dofs, els)


SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@SETTINGS
@given(random_models())
def test_matrices_symmetric_and_K_psd(model):
    mats = model.matrices()
    assert np.array_equal(mats.M, mats.M.T)
    assert np.array_equal(mats.K, mats.K.T)
    assert np.array_equal(mats.C, mats.C.T)
    w = np.linalg.eigvalsh(mats.K)
    # PSD up to round-off of the assembled sums
    assert w.min() >= -1e-12 * max(1.0, w.max())


@SETTINGS
@given(random_models(), st.randoms(use_true_random=False))
def test_invariance_to_dof_and_element_order(model, rnd):
    dofs = list(model.dofs)
    els = list(model.elements)
    rnd.shuffle(dofs)
    rnd.shuffle(els)
    shuffled = Model(dofs, els)
    a, b = modal(model), modal(shuffled)
    # eigh's absolute eigenvalue error is ~ eps * max|lambda|; compare at 1e-12 of it
    lam_a, lam_b = a.data["eigenvalue"].values, b.data["eigenvalue"].values
    np.testing.assert_allclose(lam_b, lam_a, rtol=1e-9, atol=1e-12 * np.abs(lam_a).max())
    # the same shapes, matched by DOF name (MAC = 1 on the diagonal for simple modes)
    m = mac(a, b).values
    lam = a.data["eigenvalue"].values
    gaps = np.diff(lam) > 1e-6 * max(lam.max(), 1.0)
    simple = np.r_[True, gaps] & np.r_[gaps, True] & (a.data["rigid"].values == 0)
    assert np.allclose(np.diag(m)[simple], 1.0, atol=1e-8)


@SETTINGS
@given(random_models())
def test_shapes_mass_orthonormal_and_energy_shares_sum_to_one(model):
    res = modal(model)
    M = model.matrices().M
    phi = res.shapes
    np.testing.assert_allclose(phi.T @ M @ phi, np.eye(model.n), atol=1e-9)
    np.testing.assert_allclose(res.data["kinetic_energy"].sum("dof"), 1.0, rtol=1e-9)
    elastic = res.data["rigid"].values == 0
    strain = res.data["element_energy"].sum("element").values
    # the element energies sum to phi^T K phi / lambda: its round-off is that of the
    # eigen-solver, ~ n eps max|lambda|, relative to each mode's lambda (a soft mode of a
    # stiff model loses digits); 1e3 n eps max|lambda| / lambda bounds it with margin,
    # capped at 1e-6 so that the check never becomes empty for a very soft mode
    lam = (2 * np.pi * res.frequencies[elastic]) ** 2
    tol = np.clip(1e3 * model.n * np.finfo(float).eps * lam.max() / lam, 1e-9, 1e-6)
    assert np.all(np.abs(strain[elastic] - 1.0) <= tol)
    assert np.all(np.abs(res.data["shape_max"]).max("dof") == pytest.approx(1.0))


def _fd(model, path, h_rel=1e-5):
    v = float(model.parameter(path))
    h = h_rel * abs(v)
    fp = modal(model.with_parameter(path, v + h)).frequencies
    fm = modal(model.with_parameter(path, v - h)).frequencies
    return (fp - fm) / (2 * h)


@SETTINGS
@given(random_models(), st.data())
def test_sensitivity_equals_finite_differences(model, data):
    res = modal(model)
    lam = res.data["eigenvalue"].values
    scale = max(lam.max(), 1.0)
    # central differences of sorted eigenvalues are only valid for well-separated modes
    gaps = np.diff(lam) > 1e-3 * scale
    ok = np.r_[True, gaps] & np.r_[gaps, True] & (res.data["rigid"].values == 0)
    paths = [p for e in model.elements for p in (f"{e.name}.stiffness", f"{e.name}.value")]
    paths = [p for p in paths if _has(model, p)]
    path = data.draw(st.sampled_from(paths))
    sens = frequency_sensitivity(model, [path], res).data["dfdp"].values[:, 0]
    h_rel = 1e-6
    fd = _fd(model, path, h_rel)
    # Central difference with h = 1e-6 p. Truncation: modes are at least 1e-3 lambda_max
    # apart, so the curvature term is ~ (h / gap)^2 ~ 1e-6 relative. Round-off: eigh's
    # absolute eigenvalue error ~ 1e-14 lambda_max gives df ~ 1e-14 lambda_max /
    # (8 pi^2 f) per solve, divided by h. Compare to 1e-4 relative plus that floor; a
    # wrong eigenvalue-derivative formula misses by O(1).
    h = h_rel * abs(float(model.parameter(path)))
    f = np.where(ok, np.abs(res.frequencies), 1.0)
    noise = 1e-14 * scale / (8 * np.pi**2 * f) / h
    err = np.abs(sens - fd)
    assert np.all(err[ok] <= 1e-4 * np.abs(fd[ok]) + noise[ok]), (sens[ok], fd[ok], noise[ok])


def _has(model, path):
    try:
        model.parameter(path)
    except Exception:
        return False
    return True


def test_sensitivity_of_speed_and_nested_law_parameters():
    from reducerlab.model import Centripetal, Fourier

    dofs = [Dof("a", "x"), Dof("b", "rz")]
    law = Fourier(mean=3e7, amplitudes=(2e6,), omega=100.0)
    els = [
        Inertia("a.x", 1.3),
        Inertia("b.rz", 2e-3),
        Support("a.x", 4e6),
        Centripetal("a.x", 1.3),
        Mesh({"a.x": 1.0, "b.rz": 0.04}, stiffness=law, name="m"),
    ]
    model = Model(dofs, els, speed=300.0)
    res = modal(model)
    s = frequency_sensitivity(model, ["speed", "m.stiffness.mean", "m.stiffness"], res)
    d = s.data["dfdp"].values
    np.testing.assert_allclose(d[:, 1], d[:, 2])  # law path means its mean
    np.testing.assert_allclose(d[:, 0], _fd(model, "speed"), rtol=1e-5)
    np.testing.assert_allclose(d[:, 1], _fd(model, "m.stiffness"), rtol=1e-5)


def test_relative_stiffness_sensitivity_is_half_the_strain_energy_share(pair):
    # Rayleigh: d(lambda)/dk * k / lambda = strain-energy share of the element, and
    # (k/f) df/dk = half of that
    res = modal(pair)
    s = frequency_sensitivity(pair, ["mesh.stiffness"], res)
    assert s.data["relative"].values[1, 0] == pytest.approx(0.5, rel=1e-12)
    assert np.isnan(s.data["relative"].values[0, 0])  # rigid mode


def test_degenerate_pair_gets_directional_derivatives():
    # two identical uncoupled oscillators: one repeated eigenvalue; raising one spring
    # splits it: derivatives are 0 (the other) and 1/m (this one), sorted ascending
    m, k = 2.0, 5e5
    model = Model(
        [Dof("a", "x"), Dof("b", "x")],
        [Inertia("a.x", m), Inertia("b.x", m), Support("a.x", k, name="ka"), Support("b.x", k)],
    )
    s = frequency_sensitivity(model, ["ka.stiffness"])
    np.testing.assert_allclose(s.data["dlambda"].values[:, 0], [0.0, 1.0 / m], atol=1e-15)


def test_mac_identity_and_orthogonality():
    model = torsional_pair()
    res = modal(model)
    m = mac(res, res).values
    np.testing.assert_allclose(np.diag(m), 1.0, rtol=1e-12)
    # rigid rotation (r2, -r1) against the elastic mode: not orthogonal without weight
    assert 0.01 < m[0, 1] < 0.99
    mw = mac(res, res, weight=model.matrices().M).values
    np.testing.assert_allclose(mw, np.eye(2), atol=1e-12)
    with pytest.raises(Exception, match="different DOFs"):
        other = modal(Model([Dof("q", "x")], [Inertia("q.x", 1.0), Support("q.x", 1.0)]))
        mac(res, other)
