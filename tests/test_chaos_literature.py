"""Motion classification on systems whose behaviour is known from the literature.

* The double-well Duffing oscillator ``x'' + 0.3 x' - x + x^3 = gamma cos(1.2 t)``
  (Jordan & Smith, *Nonlinear Ordinary Differential Equations*, 4th ed., 2007, Sec.
  13.3 and its figures of the Duffing attractors; the same sequence is in most texts):
  period 1 at gamma = 0.20, period 2 at 0.28, period 4 at 0.29, period 5 at 0.37,
  chaos at 0.50 and period 2 at 0.65, a period-doubling cascade between 0.26 and 0.29
  whose interval ratio tends to Feigenbaum's 4.669.
* The single-DOF gear pair with backlash of the gear-rattle literature (Kahraman &
  Singh, J. Sound Vib. 142 (1990) 49-75), in its dimensionless form
  ``x'' + 2 zeta x' + f(x) = F_m + F_a cos(Omega t)``, ``f`` the dead zone of half
  width 1: linear (no tooth separation) when the alternating force is small against
  the mean, chaotic rattle at light load and strong excitation. Their figures are not
  reproducible number by number from the text we have, so the chaotic case is checked
  against our independent event-driven reference integrator as well.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.analysis.motion import classify
from reducerlab.analysis.motion import period_of as _period_of
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.lyapunov import lyapunov
from reducerlab.dynamics.reference import simulate_reference
from reducerlab.model import (
    Backlash,
    CubicSpring,
    Dof,
    Fourier,
    Inertia,
    Load,
    Mesh,
    Model,
    Support,
)

W = 1.2  # Duffing forcing frequency (rad/s)


def duffing(gamma: float):
    els = [
        Inertia("a.x", 1.0),
        Support("a.x", 0.0, 0.3),
        CubicSpring({"a.x": 1.0}, -1.0, 1.0),
        Load("a.x", Fourier(0.0, (gamma,), W)),
    ]
    return Model([Dof("a", "x")], els).nonlinear()


def rattle(omega: float, fa: float, fm: float = 0.1, zeta: float = 0.05):
    els = [
        Inertia("a.x", 1.0),
        Mesh({"a.x": 1.0}, 1.0, 2 * zeta, backlash=Backlash.half(1.0)),
        Load("a.x", Fourier(fm, (fa,), omega)),
    ]
    return Model([Dof("a", "x")], els).nonlinear()


def test_duffing_sequence_of_jordan_and_smith():
    gammas = [0.20, 0.28, 0.29, 0.37, 0.50, 0.65]
    systems = [duffing(g) for g in gammas]
    y0 = np.array([1.0, 0.0])
    # 200 steps per period (h = 0.026 s against the unit natural time scale) and 600
    # periods, 300 of them transient, as the textbook figures
    res = ensemble(systems, periods=600, keep=60, steps_per_period=200, y0=y0)
    lam = lyapunov(systems, periods=600, transient=300, steps_per_period=200, y0=y0)
    labels = [
        classify(row, float(x), W / (2 * math.pi))
        for row, x in zip(res.poincare[:, :60, 0], lam, strict=True)
    ]
    assert labels == ["period-1", "period-2", "period-4", "period-5", "chaotic", "period-2"]
    # the periodic attractors contract (the exponent is at most -delta/2 = -0.15 on
    # average for a period-1 orbit far from bifurcation), the chaotic one stretches
    assert lam[0] == pytest.approx(-0.15, abs=0.01)
    assert lam[4] > 0.03


def test_duffing_period_doubling_cascade_approaches_feigenbaum():
    gammas = np.linspace(0.25, 0.30, 101)
    res = ensemble(
        [duffing(g) for g in gammas], periods=1000, keep=64, steps_per_period=128,
        y0=np.array([1.0, 0.0]),
    )  # fmt: skip
    period = np.array([_period_of(row, 1e-4, 16) for row in res.poincare[:, :64, 0]])
    first = {p: gammas[np.argmax(period == p)] for p in (1, 2, 4, 8)}
    assert all((period == p).any() for p in (1, 2, 4, 8))
    # doublings in order, each at a larger forcing
    assert first[1] < first[2] < first[4] < first[8]
    # ... with shrinking intervals: ratio 4.669 (Feigenbaum) in the limit; with two
    # intervals and a 0.0005 grid the measured ratio is 4.8 +- 1.3
    ratio = (first[4] - first[2]) / (first[8] - first[4])
    assert 3.5 < ratio < 6.5
    # chaos (no period <= 16) just past the cascade
    assert (period[gammas > 0.2935] == 0).any()


def test_gear_rattle_without_separation_is_the_linear_oscillator():
    # F_a small against F_m: the teeth never separate, the motion is the linear response
    # x = 1 + F_m + Re[F_a e^(i W t) / (1 - W^2 + 2 i zeta W)] (clearance 1 taken up),
    # and every perturbation decays as exp(-zeta t): largest exponent -zeta = -0.05
    omega, fa, fm, zeta = 0.5, 0.05, 0.1, 0.05
    s = rattle(omega, fa, fm, zeta)
    y0 = np.array([1.1, 0.0])
    res = ensemble([s], periods=300, keep=20, steps_per_period=128, y0=y0)
    pts = res.poincare[0, :20, 0]
    assert classify(pts, -0.05, omega / (2 * math.pi)) == "period-1"
    exact = 1 + fm + (fa / complex(1 - omega**2, 2 * zeta * omega)).real
    # RK4 at 128 steps per period (h = 0.098 against the unit natural frequency): local
    # error ~ (h w)^5 / 120 = 8e-8 of the amplitude (0.067) per step, accumulated over
    # the ~200 steps of the decay time 1/zeta: ~1e-6 of 0.067, so atol 1e-6 (measured
    # 2.4e-8)
    np.testing.assert_allclose(pts, exact, atol=1e-6)
    lam = lyapunov([s], periods=300, transient=100, steps_per_period=128, y0=y0)
    assert lam[0] == pytest.approx(-zeta, rel=1e-2)


def test_gear_rattle_chaos_confirmed_by_the_reference_integrator():
    omega, fa = 1.5, 0.3
    s = rattle(omega, fa)
    T = 2 * math.pi / omega
    y0 = np.array([1.1, 0.0])
    lam = lyapunov([s], periods=600, transient=300, steps_per_period=256, y0=y0)[0]
    res = ensemble([s], periods=400, keep=60, steps_per_period=256, y0=y0)
    assert classify(res.poincare[0, :60, 0], lam, 1 / T) == "chaotic"
    # independent check: two DOP853 trajectories with event-located impacts, 1e-9 apart
    # on the attractor, separate exponentially at about the same rate
    start = res.poincare[0, 0]
    t = np.arange(1, 41) * T
    a = simulate_reference(s, t, start, rtol=1e-12, atol=1e-14)
    b = simulate_reference(s, t, start + np.array([1e-9, 0.0]), rtol=1e-12, atol=1e-14)
    sep = np.linalg.norm(a - b, axis=1)
    grow = (sep > 1e-8) & (sep < 1e-3)  # exponential phase, above the noise floor
    slope = np.polyfit(t[grow], np.log(sep[grow]), 1)[0]
    # finite-time exponents scatter by tens of percent around the mean over the
    # attractor: the reference slope and the kernel's exponent agree to a factor 2
    assert slope > 0.02 and lam > 0.02
    assert 0.5 < slope / lam < 2.0


def test_gear_rattle_periodic_poincare_points_match_the_reference():
    # a period-4 rattle (strong nonlinearity, impacts every period): the kernel's
    # Poincare points at 1024 steps per period agree with the event-driven reference.
    # The kernel steps to each backlash crossing (the dead-zone kink would otherwise
    # lower RK4 to first order there): ~1e-10 here against an orbit spanning ~2
    # (asserted 1e-8; tests/test_accuracy.py checks the default step count)
    omega, fa = 1.2, 0.2
    s = rattle(omega, fa)
    T = 2 * math.pi / omega
    y0 = np.array([1.1, 0.0])
    res = ensemble([s], periods=400, keep=8, steps_per_period=1024, y0=y0)
    pts = res.poincare[0, :8, 0]
    assert _period_of(pts, 1e-6, 8) == 4
    ref = simulate_reference(s, np.arange(1, 9) * T, res.poincare[0, 0])
    np.testing.assert_allclose(ref[:, 0], res.poincare[0, 1:9, 0], atol=1e-8)
