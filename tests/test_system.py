"""The flat nonlinear export agrees with the assembled matrices and the elements."""

from __future__ import annotations

import numpy as np
import pytest

from reducerlab.drives import build_model, load_design
from reducerlab.examples import example_dir
from reducerlab.model import Backlash, Constant, Dof, Fourier, Inertia, Load, Mesh, Model, Support


def _model(backlash=0.0, law=None, error=0.0):
    dofs = [Dof("p", "x"), Dof("p", "rz"), Dof("g", "rz")]
    els = [
        Inertia("p.x", 1.1),
        Inertia("p.rz", 1e-3),
        Inertia("g.rz", 4e-3),
        Support("p.x", 2e8, 300.0),
        Mesh(
            {"p.x": 0.34, "p.rz": 0.02, "g.rz": 0.05},
            stiffness=law if law is not None else Constant(3e8),
            damping=250.0,
            backlash=Backlash.full(backlash),
            error=error,
            name="mesh",
        ),
        Load("p.rz", 5.0),
        Load("g.rz", Fourier(mean=-12.5, amplitudes=(1.0,), omega=40.0)),
    ]
    return Model(dofs, els)


def test_linear_case_matches_assembled_matrices():
    # no backlash, constant stiffness, no error: rhs = [v, M^-1 (F - C v - K q)]
    model = _model()
    sys_ = model.nonlinear()
    mats = model.matrices()
    rng = np.random.default_rng(1)
    for _ in range(5):
        t = rng.uniform(0, 1)
        q, v = rng.normal(size=3) * 1e-5, rng.normal(size=3) * 1e-2
        F = sys_.external_forces(t)
        expected = np.linalg.solve(mats.M, F - mats.C @ v - mats.K @ q)
        out = sys_.rhs(t, np.r_[q, v])
        np.testing.assert_allclose(out[:3], v)
        np.testing.assert_allclose(
            out[3:], expected, rtol=1e-10, atol=1e-12 * np.abs(expected).max()
        )


def test_mesh_force_with_backlash_error_and_time_varying_stiffness():
    law = Fourier(mean=3e8, amplitudes=(4e7,), phases=(0.2,), omega=700.0)
    err = Fourier(mean=0.0, amplitudes=(5e-6,), omega=700.0)
    model = _model(backlash=2e-5, law=law, error=err)
    s = model.nonlinear()
    g = np.array([0.34, 0.02, 0.05])
    q = np.array([1e-5, 8e-4, 3e-4])
    v = np.array([0.01, -0.2, 0.4])
    t = 0.0123
    delta = g @ q - float(err(t))
    f = delta - np.clip(delta, -1e-5, 1e-5)  # half of the full 2e-5
    expected = float(law(t)) * f + 250.0 * (g @ v - float(err.derivative(t)))
    assert s.mesh_forces(t, q, v)[0] == pytest.approx(expected, rel=1e-12)
    # inside the dead zone only damping acts
    q0 = np.zeros(3)
    assert s.mesh_forces(0.0, q0, v)[0] == pytest.approx(
        250.0 * (g @ v - float(err.derivative(0.0))), rel=1e-12
    )
    assert s.line_names == ["mesh"]
    assert s.half_backlash.tolist() == [1e-5]


def test_loads_and_flat_arrays_of_the_example():
    model = build_model(load_design(example_dir() / "gear_pair.toml"))
    s = model.nonlinear()
    assert s.G.shape == (1, 6)
    assert s.k_kind.tolist() == [1]  # Fourier
    F = s.external_forces(0.0)
    assert F[model.index["pinion.rz"]] == pytest.approx(60.0)
    # both rotations counter-clockwise: the load torque T |i| balances the input on
    # the rigid rotation (r_bp, -r_bg) direction: no net torque on the free mode
    assert F[model.index["gear.rz"]] == pytest.approx(60.0 * 60 / 25)
    from reducerlab.analysis.modal import modal

    rigid = modal(model).shapes[:, 0]
    assert abs(rigid @ F) < 1e-12 * np.abs(F).max() * np.abs(rigid).max()
    # mean mesh stiffness block + linear K = assembled mean K
    k_mean = s.k_params[0, 0]
    np.testing.assert_allclose(s.K + k_mean * np.outer(s.G[0], s.G[0]), model.matrices().K)
