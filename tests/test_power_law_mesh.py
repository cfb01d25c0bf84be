"""Load-dependent (power-law) mesh force in the compiled kernel (issue 30).

A mesh line with load exponent ``p`` has the elastic force
``k(t) (d / p) sgn(f) (|f| / d)^p`` (``model.elements.Mesh``); ``p = 1.5`` is Hertz's
point contact. The oracles are closed forms of the Hertzian oscillator:

* the free conservative oscillator ``m x'' + K sgn(x) |x|^p = 0`` of amplitude ``A`` has
  the period ``T = 4 sqrt(m (p + 1) / (2 K)) A^((1 - p) / 2) I_p`` with
  ``I_p = int_0^1 (1 - u^(p+1))^(-1/2) du = sqrt(pi) Gamma(1 + 1/(p+1)) /
  Gamma(1/2 + 1/(p+1))`` (energy integral; 1.47164 for ``p = 1.5``);
* a mass bouncing with speed ``v`` between two Hertzian walls ``2 h`` apart spends the
  contact time ``t_c = 2.9432 delta* / v``, ``delta* = (5 m v^2 / (4 K))^(2/5)`` on
  each wall (Johnson, Contact Mechanics, 1985, section 11.4, Eq. 11.24: "2.94"), so
  its period is ``4 h / v + 2 t_c``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import gamma

from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.reference import simulate_reference
from reducerlab.errors import ModelError
from reducerlab.model import Model
from reducerlab.model.dofs import Dof
from reducerlab.model.elements import Inertia, Load, Mesh
from reducerlab.model.laws import Backlash, Fourier
from reducerlab.model.system import power_force

MASS = 2.0  # kg
K_HERTZ = 3e9  # N/m^1.5
P = 1.5
D_REF = 1e-5  # m
K_REF = P * K_HERTZ * D_REF ** (P - 1)  # N/m: the tangent of K x^1.5 at D_REF


def integral(p: float) -> float:
    """``int_0^1 (1 - u^(p+1))^(-1/2) du`` in closed form (Beta function)."""
    n = p + 1
    return math.sqrt(math.pi) * gamma(1 + 1 / n) / gamma(0.5 + 1 / n)


def free_period(amplitude: float, p: float = P, k: float = K_HERTZ) -> float:
    """Period (s) of ``m x'' + k sgn(x) |x|^p = 0`` at amplitude ``amplitude`` (m)."""
    return 4 * math.sqrt(MASS * (p + 1) / (2 * k)) * amplitude ** ((1 - p) / 2) * integral(p)


def oscillator(half_backlash: float = 0.0, p: float = P) -> Model:
    """One mass on a power-law line to the ground."""
    k_ref = p * K_HERTZ * D_REF ** (p - 1)
    mesh = Mesh({"a.x": 1.0}, k_ref, backlash=Backlash(half_backlash) if half_backlash else None,
                exponent=p, reference_deflection=D_REF)  # fmt: skip
    return Model([Dof("a", "x")], [Inertia("a.x", MASS), mesh])


def test_integral_of_the_hertzian_oscillator_is_johnsons_constant():
    # 2 I_1.5 = 2.9432: Johnson's 2.94 for the duration of a Hertzian impact
    assert integral(1.5) == pytest.approx(1.47164, abs=1e-5)
    assert 2 * integral(1.5) == pytest.approx(2.94, abs=0.005)
    # p = 1: the linear oscillator, I = pi / 2
    assert integral(1.0) == pytest.approx(math.pi / 2, rel=1e-12)


def test_power_force_is_the_hertz_law_with_the_tangent_at_the_reference():
    for f in (1e-7, 3e-6, D_REF, 4e-5):
        assert power_force(K_REF, f, P, D_REF) == pytest.approx(K_HERTZ * f**1.5, rel=1e-12)
        assert power_force(K_REF, -f, P, D_REF) == pytest.approx(-K_HERTZ * f**1.5, rel=1e-12)
    h = 1e-12
    slope = power_force(K_REF, D_REF + h, P, D_REF) - power_force(K_REF, D_REF - h, P, D_REF)
    assert slope / (2 * h) == pytest.approx(K_REF, rel=1e-5)
    assert power_force(K_REF, 2e-6, 1.0, 0.0) == K_REF * 2e-6


def test_free_hertzian_oscillator_keeps_its_closed_form_period():
    # The kernel at its default accuracy (1e-6 of the displacement scale per Poincare
    # point) returns to the start after every closed-form period: the sign change of the
    # deflection (where the force's second derivative is singular) is located as a
    # backlash crossing is.
    A = 2e-5
    T = free_period(A)
    y0 = np.array([A, 0.0])
    r = ensemble([oscillator().nonlinear()], periods=20, keep=20, period=T, y0=y0)
    err = np.abs(r.poincare[0, :, 0] - A) / A
    # measured 6.8e-8 per period, growing linearly (a phase error): 20 periods within
    # 20 times the accuracy target
    assert err.max() < 20 * 1e-6
    assert np.abs(r.poincare[0, :, 1]).max() < 20 * 1e-6 * A * 2 * math.pi / T


def test_hertzian_impacts_across_backlash_keep_johnsons_contact_time():
    h, v = 5e-6, 0.01  # m, m/s
    delta_star = (5 * MASS * v * v / (4 * K_HERTZ)) ** 0.4
    t_c = 2 * integral(1.5) * delta_star / v  # Johnson's 2.94 delta* / v
    assert t_c == pytest.approx(free_period(delta_star) / 2, rel=1e-12)
    T = 4 * h / v + 2 * t_c
    y0 = np.array([0.0, v])
    r = ensemble([oscillator(h).nonlinear()], periods=20, keep=20, period=T, y0=y0)
    # back at the centre with the same speed after every period; measured 1.3e-7 of h
    # per period (linear growth)
    assert np.abs(r.poincare[0, :, 0]).max() < 20 * 1e-6 * h
    assert np.abs(r.poincare[0, :, 1] - v).max() < 20 * 1e-6 * v


@pytest.mark.parametrize("half_backlash", [0.0, 5e-6])
def test_located_sign_changes_keep_fourth_order(half_backlash):
    # error after one period at N and 2N fixed steps: RK4's 16x (measured 12-30x); without
    # the located crossing the singular force derivative would cost orders
    if half_backlash:
        v = 0.01
        A = (5 * MASS * v * v / (4 * K_HERTZ)) ** 0.4
        T, y0, scale = 4 * half_backlash / v + free_period(A), np.array([0.0, v]), v
    else:
        A = 2e-5
        T, y0, scale = free_period(A), np.array([A, 0.0]), A * 2 * math.pi / free_period(A)
    s = oscillator(half_backlash).nonlinear()
    errs = []
    for N in (100, 200, 400):
        r = ensemble([s], periods=1, keep=1, period=T, y0=y0, steps_per_period=N)
        errs.append(abs(r.poincare[0, -1, 1] - y0[1]) / scale)
    assert errs[0] / errs[1] > 10 and errs[1] / errs[2] > 10


def test_kernel_matches_the_event_driven_reference_with_pumped_stiffness_and_damping():
    # two masses, a power-law mesh with a time-varying tangent stiffness, backlash,
    # damping and a sinusoidal load: the compiled kernel against DOP853 with events
    # (dynamics.reference, model.system.power_force)
    k_law = Fourier(K_REF, (0.2 * K_REF,), 2 * math.pi * 300.0)
    m = Model(
        [Dof("a", "x"), Dof("b", "x")],
        [Inertia("a.x", 1.0), Inertia("b.x", 1.5),
         Mesh({"a.x": 1.0, "b.x": -1.0}, k_law, damping=50.0, backlash=Backlash(2e-6),
              exponent=P, reference_deflection=D_REF),
         Load("a.x", Fourier(200.0, (150.0,), 2 * math.pi * 300.0)),
         Load("b.x", -200.0)],
    )  # fmt: skip
    from reducerlab.dynamics.coordinates import to_system

    s = to_system(m)
    T = 1 / 300.0
    r = ensemble([s], periods=30, keep=5, history=0, period=T, steps_per_period=800)
    ref = simulate_reference(s, np.arange(25, 31) * T, np.zeros(2 * s.n))
    scale = np.abs(ref[:, : s.n]).max()
    assert np.abs(r.poincare[0, :, : s.n] - ref[:, : s.n]).max() < 1e-5 * scale


def test_power_law_lines_are_integrated_by_rk4_not_the_linear_maps():
    r = ensemble([oscillator(5e-6).nonlinear()], periods=60, keep=2, period=1e-3,
                 y0=np.array([0.0, 0.01]), method="auto")  # fmt: skip
    assert r.mapped is None or not r.mapped.any()


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"exponent": 0.5, "reference_deflection": 1e-5}, r"exponent must be a number in \[1, 3\]"),
        ({"exponent": 3.5, "reference_deflection": 1e-5}, r"exponent must be"),
        ({"exponent": float("nan"), "reference_deflection": 1e-5}, r"exponent must be"),
        ({"exponent": 1.5}, r"reference_deflection must be > 0 m where exponent != 1"),
        ({"exponent": 1.5, "reference_deflection": -1e-6}, r"reference_deflection must be"),
        ({"exponent": 1.5, "reference_deflection": float("inf")}, r"reference_deflection"),
    ],
)
def test_bad_power_law_names_the_field(kw, match):
    with pytest.raises(ModelError, match=rf"mesh:a\.x: {match}"):
        Mesh({"a.x": 1.0}, 1e8, **kw)


def test_static_start_of_power_law_lines_is_their_equilibrium():
    # a loaded mass on a Hertzian line with backlash: the start (dynamics.coordinates.
    # static_state) is the exact static deflection h + (F / K)^(2/3), not the linear
    # tangent's F / k
    from reducerlab.dynamics.coordinates import static_state, to_system

    h, load = 3e-6, 40.0  # m, N
    m = oscillator(h)
    m = Model(m.dofs, [*m.elements, Load("a.x", load)])
    s = to_system(m)
    x = static_state(s)[0]
    assert x == pytest.approx(h + (load / K_HERTZ) ** (2 / 3), rel=1e-9)
    r = ensemble([s], periods=5, keep=5, period=1e-3, y0=static_state(s))
    assert np.abs(r.poincare[0, :, 0] - x).max() < 1e-9 * x  # at rest: it stays
