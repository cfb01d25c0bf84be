"""Forms of the transmission-error excitation (issue 16): inside the mesh deflection
(paper 004 Eq. 2) or as the inertial load ``-/+ m_e e''(t)`` whose amplitude grows with
the square of the speed (reducerlab.model.forcing).

Oracles: for one DOF on a linear mesh, ``m q'' + c (q' - e') + k (q - e) = 0`` is, in the
deflection ``x = q - e``, ``m x'' + c x' + k x = -m e''`` (exact): both forms give the same
deflection, whose steady amplitude for ``e = E cos(W t)`` is the base-excitation closed
form ``X = m W^2 E / sqrt((k - m W^2)^2 + (c W)^2)`` (e.g. Rao, *Mechanical Vibrations*,
Sec. 3.6.2, relative motion under base excitation).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.analysis.response import response
from reducerlab.drives import build_model, load_design
from reducerlab.errors import DesignError, ModelError
from reducerlab.examples import example_dir
from reducerlab.model import (
    Dof,
    Fourier,
    Inertia,
    Mesh,
    Model,
    PiecewisePolynomial,
)
from reducerlab.model.forcing import inertial_error

MASS, K, C, E, W = 2.0, 8.0, 0.4, 1e-6, 1.6  # omega_n = 2 rad/s, zeta = 0.05


def pair(error=None) -> Model:
    law = Fourier(0.0, (E,), W, ref_speed=W) if error is None else error
    return Model(
        [Dof("a", "x")],
        [Inertia("a.x", MASS), Mesh({"a.x": 1.0}, K, C, error=law, name="mesh")],
        speed=W,
        name="pair",
    )


def steady_delta(model: Model) -> np.ndarray:
    # 400 periods: the transient decays as exp(-zeta omega_n t) = e^-157; 512 RK4 steps
    # per period (error ~ (W h)^4 ~ 1e-10 of the amplitude)
    res = response(model, periods=400, keep=4, history=4, steps_per_period=512)
    return res.data["delta"].values


def test_omega2_form_equals_the_stiffness_form_and_the_closed_form():
    stiff = steady_delta(pair())
    omega2 = steady_delta(inertial_error(pair(), "omega2"))
    X = MASS * W**2 * E / math.hypot(K - MASS * W**2, C * W)
    # amplitude of the sampled steady motion: 512 samples per period resolve the peak
    # to (pi / 512)^2 / 2 = 2e-5 relative
    assert np.ptp(omega2) / 2 == pytest.approx(X, rel=5e-5)
    np.testing.assert_allclose(omega2, stiff, rtol=0, atol=1e-6 * X)


def test_j_omega2_is_the_same_load_negated():
    omega2 = steady_delta(inertial_error(pair(), "omega2"))
    j = steady_delta(inertial_error(pair(), "j-omega2"))
    np.testing.assert_allclose(j, -omega2, rtol=0, atol=1e-6 * np.ptp(omega2))


def test_khv_load_is_m_e_omega_squared_e_and_scales_with_the_speed_squared():
    loads = {}
    for rpm in (1000, 2000):
        d = load_design(example_dir() / "khv.toml",
                        ["mesh.error_forcing=omega2", f"input_speed={rpm} rpm"])  # fmt: skip
        m = build_model(d)
        law = next(e.value for e in m.elements if e.name == "mesh:error_omega2:planet.u")
        # the equivalent mass of the line (planet u against carrier u), independently
        MV = d.inertia.planet / m.dofs[2].radius ** 2
        MH = m.matrices().M[1, 1]
        m_e = MV * MH / (MV + MH)
        assert law.amplitudes[0] == pytest.approx(
            m_e * d.mesh_frequency**2 * d.mesh.error_amplitude, rel=1e-12
        )
        assert law.omega == pytest.approx(d.mesh_frequency, rel=1e-12)
        mesh = next(e for e in m.elements if e.name == "mesh")
        assert mesh.error.mean == 0.0 and mesh.error.period == math.inf
        loads[rpm] = law
    assert loads[2000].amplitudes[0] == pytest.approx(4 * loads[1000].amplitudes[0], rel=1e-12)
    # the law itself follows a change of model speed the same way
    moved = loads[1000].at_speed(2 * loads[1000].ref_speed)
    assert moved.amplitudes[0] == pytest.approx(loads[2000].amplitudes[0], rel=1e-12)


def test_stiffness_form_is_the_default_and_changes_nothing():
    d = load_design(example_dir() / "khv.toml")
    assert d.mesh.error_forcing == "stiffness"
    m = build_model(d)
    assert inertial_error(m, "stiffness") is m
    assert not any("error_" in e.name for e in m.elements)


@pytest.mark.parametrize(
    ("kw", "message"),
    [
        ({"speed_power": 2}, "speed_power needs ref_speed"),
        ({"speed_power": 5, "ref_speed": 1.0}, "speed_power must be an integer in 0..4"),
        ({"speed_power": True, "ref_speed": 1.0}, "speed_power must be an integer"),
    ],
)
def test_fourier_speed_power_is_checked(kw, message):
    with pytest.raises(ModelError, match=message):
        Fourier(0.0, (1.0,), 1.0, **kw)


def test_bad_forms_and_laws_are_named():
    with pytest.raises(ModelError, match="error forcing must be one of"):
        inertial_error(pair(), "omega3")
    with pytest.raises(ModelError, match="no mesh named"):
        inertial_error(pair(), "omega2", ["gear"])
    saw = PiecewisePolynomial(1.0, (0.0,), ((0.0, 1e-6),))
    with pytest.raises(ModelError, match=r"mesh: the omega2 form .* needs a Fourier error"):
        inertial_error(pair(saw), "omega2")
    with pytest.raises(DesignError, match=r"mesh\.error_forcing"):
        load_design(example_dir() / "khv.toml", ["mesh.error_forcing=omega"])
