"""Defaults are results: the kernel's Poincaré points against an independent tight
reference (event-located DOP853, ``simulate_reference``, rtol 1e-12) in impact cases.

Systems: the single-DOF gear pair with backlash of the gear-rattle literature (Kahraman
and Singh, J. Sound Vib. 142, 1990, 49-75), ``x'' + 0.1 x' + f(x) = 0.1 + F_a cos(W t)``,
``f`` the dead zone of half width 1 (teeth separate every period in the impact cases),
and the double-well Duffing oscillator of Jordan and Smith (smooth, for contrast).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.dynamics.accuracy import accurate_steps
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.guards import state_bounds
from reducerlab.dynamics.prepare import prepare as _prepare
from reducerlab.dynamics.reference import simulate_reference
from reducerlab.errors import ReducerlabError
from test_chaos_literature import duffing, rattle  # the same literature systems

CASES = {
    # (system, forcing frequency): impact cases first
    "rattle period-4, W 1.2, F_a 0.2": (rattle(1.2, 0.2), 1.2),
    "rattle W 0.8, F_a 0.12": (rattle(0.8, 0.12), 0.8),
    "rattle without separation, W 1.5, F_a 0.05": (rattle(1.5, 0.05), 1.5),
    "Duffing gamma 0.2": (duffing(0.2), 1.2),
}


def poincare_error(s, omega, steps=None, accuracy=1e-6, periods=400, count=19):
    """Largest error of ``count`` Poincaré points after ``periods`` periods from
    x = 1.1 (relative to the displacement scale of ensemble's bounds), against the
    reference started from the kernel's first kept point."""
    T = 2 * math.pi / omega
    y0 = np.array([1.1, 0.0])
    res = ensemble([s], periods=periods, keep=count + 1, steps_per_period=steps, y0=y0,
                   accuracy=accuracy)  # fmt: skip
    P = res.poincare[0]
    ref = simulate_reference(s, np.arange(1, count + 1) * T, P[0], rtol=1e-12, atol=1e-14)
    d = state_bounds([s], P[:1], np.array([T]))[0] / 1e6
    return float(np.max(np.abs(P[1 : count + 1] - ref) / d))


def test_event_location_keeps_rk4_fourth_order_through_impacts():
    # Stepping to each backlash crossing (kernel_step.event_times) removes the kink from
    # inside the steps: halving the step divides the error by ~16 (measured 17) where
    # plain fixed steps gave first order at each crossing (an error of 2e-4 at 128
    # steps per period, measured before the change); asserted ratio >= 8
    s, omega = CASES["rattle period-4, W 1.2, F_a 0.2"]
    e64 = poincare_error(s, omega, steps=64)
    e128 = poincare_error(s, omega, steps=128)
    assert e128 <= 5e-7
    assert e64 / e128 >= 8


def test_fourth_order_through_impacts_with_piecewise_stiffness_and_error_laws():
    # The KHV drive (paper 004) rattling at x1 = 0.55: a piecewise mesh-stiffness law
    # and a Fourier transmission error, whose rows at the crossing sub-steps are
    # interpolated from the step's table (kernel_step.restep, quadratic: O(h^3) in the
    # laws over one sub-step per crossing). Against the event-located DOP853 reference
    # halving the step divides the error by ~16 (measured 12-22 over x1 0.45-0.75 for
    # 32-256 steps); asserted >= 8, and the teeth do separate in the periods checked.
    from reducerlab.analysis.parameters import Evaluator, resolve
    from reducerlab.drives import build_model, load_design
    from reducerlab.dynamics.coordinates import static_state, to_system
    from reducerlab.examples import example_dir
    from reducerlab.model.laws import evaluate_flat

    design = load_design(example_dir() / "khv.toml")
    model = build_model(design)
    s = to_system(Evaluator(design, model, (resolve(design, model, "gears.x1"),)).model_at([0.55]))
    res = ensemble([s], periods=100, keep=1, y0=static_state(s), steps_per_period=128)
    start, T, P = res.poincare[0, -1], float(res.period[0]), 6
    t = np.arange(1, P + 1) * T
    ref = simulate_reference(s, t, start, rtol=1e-12, atol=1e-16)
    scale = np.max(np.abs(ref), axis=0)
    err = {}
    for n in (64, 128):
        got = ensemble([s], periods=P, keep=P, y0=start, steps_per_period=n).poincare[0, 1:]
        err[n] = float(np.max(np.abs(got - ref) / scale))
    assert err[128] <= 1e-7
    assert err[64] / err[128] >= 8
    tt = np.linspace(T / 200, P * T, 200 * P)
    q = simulate_reference(s, tt, start, rtol=1e-10, atol=1e-16)[:, : s.n]
    e = np.array([evaluate_flat(int(s.e_kind[0]), s.e_params[0], x)[0] for x in tt])
    delta = q @ s.G[0] - e
    assert np.any(np.abs(delta) <= s.half_backlash[0])  # apart
    assert np.any(np.abs(delta) > s.half_backlash[0])  # in contact


@pytest.mark.parametrize("name", list(CASES))
def test_default_steps_deliver_the_stated_accuracy(name):
    # docs/reliability.md: the default accuracy is 1e-6 of the motion's scale for the
    # Poincaré points (measured 7e-8 .. 3e-7 on these four)
    s, omega = CASES[name]
    assert poincare_error(s, omega) <= 1e-6


def test_a_tighter_accuracy_takes_more_steps_and_delivers():
    s, omega = CASES["rattle W 0.8, F_a 0.12"]
    T = 2 * math.pi / omega
    y0 = np.array([[1.1, 0.0]])
    prep = _prepare([s], None, None)
    b = state_bounds([s], y0, np.array([T]))
    loose = accurate_steps(prep, [s], y0, b, 1e-4)
    tight = accurate_steps(prep, [s], y0, b, 1e-8)
    assert tight > 2 * loose
    assert poincare_error(s, omega, accuracy=1e-8) <= 1e-8


@pytest.mark.parametrize("bad", [0.0, -1e-6, 1.0, float("nan"), "1e-6"])
def test_accuracy_is_checked(bad):
    s, _ = CASES["rattle W 0.8, F_a 0.12"]
    with pytest.raises(ReducerlabError, match="accuracy must be a number in"):
        ensemble([s], periods=10, keep=2, y0=np.array([1.1, 0.0]), accuracy=bad)


def test_fine_steps_read_the_stiffness_jumps_on_the_right_side():
    # Regression (issue 16): the step boundaries at the jumps of a piecewise stiffness
    # law were placed at phases rounded to 1e-12, and with more than ~5000 steps per
    # period the samples "just inside" a step (1e-9 of it) then read the law on the
    # wrong side of the jump: a first-order error (6e-6 of the state scale at 8192
    # steps, where 2048 steps are exact to 1e-14), which made the accuracy-driven step
    # count run away to its cap. Refinement must now change nothing beyond round-off.
    from reducerlab.analysis.members import axis_members
    from reducerlab.analysis.sweep import Axis
    from reducerlab.drives import build_model, load_design
    from reducerlab.dynamics.coordinates import static_states
    from reducerlab.dynamics.guards import state_bounds
    from reducerlab.examples import example_dir

    d = load_design(example_dir() / "khv.toml", ["mesh.damping_ratio=0.005"])
    axis = Axis("input_speed", ("1550 rpm", "1650 rpm"))
    values, members, _ = axis_members(d, build_model(d), axis, "test")
    systems = members(values)
    y0 = static_states(systems)
    ends = [
        ensemble(systems, periods=41, keep=1, y0=y0, steps_per_period=n).poincare[:, -1]
        for n in (2048, 8192)
    ]
    res = ensemble(systems, periods=1, keep=1, y0=y0, steps_per_period=32)
    scale = state_bounds(systems, y0, res.period, factor=1.0)
    assert np.max(np.abs(ends[0] - ends[1]) / scale) < 1e-11


# A period-2 rattle orbit that loses contact in every other period only (issue 26):
# the superharmonic (3 W ~ 1) grazing region of the same oscillator, found by a
# parameter scan (W 0.26-0.5, F_a 0.95-1.3 times the grazing amplitude).
ALTERNATING = (0.345, 0.098745)


def test_period_two_orbit_with_alternating_contact_loss_is_what_it_says():
    s = rattle(*ALTERNATING)
    T = 2 * math.pi / ALTERNATING[0]
    P = ensemble([s], periods=400, keep=4, y0=np.array([1.1, 0.0])).poincare[0]
    d = state_bounds([s], P[:1], np.array([T]))[0] / 1e6
    assert np.max(np.abs(P[2:] - P[:-2]) / d) < 1e-6  # period 2 ...
    assert np.min(np.abs(P[1] - P[0]) / d) > 1e-3  # ... not period 1
    t = np.linspace(T / 400, 2 * T, 800)
    x = simulate_reference(s, t, P[0], rtol=1e-12, atol=1e-14)[:, 0].reshape(2, 400)
    lows = np.sort(np.append(x.min(axis=1), P[0, 0]))
    # one period dips into the backlash (|x| < 1: the teeth apart), the other stays in
    # contact (measured minima 0.9817 and 1.0013)
    assert lows[0] < 0.99 and lows[1] > 1.0005


@pytest.mark.parametrize("pilot", [39, 40, 41, 42])
def test_the_accuracy_check_covers_the_orbit_whatever_the_pilot_parity(pilot):
    # checking one period after the pilot saw the impact period or not depending on the
    # pilot's parity (182 or 187 steps here); the check now covers the orbit's period
    s = rattle(*ALTERNATING)
    T = 2 * math.pi / ALTERNATING[0]
    y0 = np.array([[1.1, 0.0]])
    prep = _prepare([s], None, None)
    b = state_bounds([s], y0, np.array([T]))
    assert accurate_steps(prep, [s], y0, b, 1e-6, pilot) == accurate_steps(prep, [s], y0, b)


def test_period_two_orbit_with_alternating_contact_loss_meets_the_accuracy():
    assert poincare_error(rattle(*ALTERNATING), ALTERNATING[0]) <= 1e-6
