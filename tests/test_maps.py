"""One-period maps (dynamics/maps.py, issue 16): drives whose teeth stay in contact
are linear time-periodic systems, fast-forwarded by their monodromy map.

Oracles: the linear oscillator's closed forms (steady amplitude
``F / |k - m W^2 + i c W|`` and largest Lyapunov exponent ``-c / 2m``); Floquet theory
(the exponent of a linear periodic system is the log of the monodromy's spectral radius
over the period); and the RK4 kernel itself, which the map must reproduce to round-off
wherever it is used, and which takes over wherever the teeth would separate (the
Kahraman-Singh pair on both sides of its no-impact boundary).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.dynamics.coordinates import static_states
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.guards import state_bounds
from reducerlab.dynamics.maps import margin as _margin
from reducerlab.errors import ReducerlabError
from reducerlab.model import Backlash, Dof, Fourier, Inertia, Load, Mesh, Model, Support

W = 0.8


def forced(c: float = 0.1, k1: float = 0.0) -> Model:
    """x'' + c x' + (1 + k1 cos W t) x = 0.3 + 0.05 cos W t on a mesh without backlash."""
    return Model(
        [Dof("a", "x")],
        [
            Inertia("a.x", 1.0),
            Mesh({"a.x": 1.0}, Fourier(1.0, (k1,), W), c, name="m"),
            Load("a.x", Fourier(0.3, (0.05,), W)),
        ],
    )


def rattle(ratio: float, zeta: float = 0.05, fm: float = 0.1) -> Model:
    """Kahraman-Singh pair with the linear amplitude ``ratio`` times the mean force."""
    fa = ratio * fm * math.hypot(1 - W**2, 2 * zeta * W)
    return Model(
        [Dof("a", "x")],
        [
            Inertia("a.x", 1.0),
            Mesh({"a.x": 1.0}, 1.0, 2 * zeta, backlash=Backlash.half(1.0)),
            Load("a.x", Fourier(fm, (fa,), W)),
        ],
    )


def both(systems, **kw):
    return ensemble(systems, method="maps", **kw), ensemble(systems, method="rk4", **kw)


def test_linear_oscillator_closed_forms_and_the_rk4_run():
    s = [forced().nonlinear()]
    kw = dict(periods=300, keep=100, history=2, steps_per_period=256, exponents=True)
    fast, slow = both(s, **kw)
    assert fast.mapped.tolist() == [True] and slow.mapped.tolist() == [False]
    np.testing.assert_allclose(fast.poincare, slow.poincare, rtol=0, atol=1e-13)
    np.testing.assert_allclose(fast.history, slow.history, rtol=0, atol=1e-13)
    # steady amplitude of the forced response (RK4 at 256 steps: 1e-9; the sampled
    # peak of 512 history samples: (pi / 256)^2 / 2 = 8e-5 relative)
    X = 0.05 / math.hypot(1 - W**2, 0.1 * W)
    x = fast.history[0, :, 0]
    assert np.ptp(x) / 2 == pytest.approx(X, rel=2e-4)
    # largest Lyapunov exponent of a damped linear oscillator: -c / 2 (both exponents of
    # the underdamped pair). The finite-time estimate over 100 periods carries the
    # swing of the scaled separation norm (velocities scaled by W, the motion turning
    # at omega_d = 1): |log(omega_d / W)| = 0.22 over 100 T = 785 s, 3e-4 1/s at most
    assert fast.exponent[0] == pytest.approx(-0.05, abs=3e-4)
    # RK4's pairs carry their 1e-9 separation as a difference of two states: round-off
    # of eps / 1e-9 = 2e-7 per period in the logged ratio; the map propagates it exactly
    assert fast.exponent[0] == pytest.approx(slow.exponent[0], rel=1e-5)


def test_parametric_oscillator_exponent_is_floquets():
    # damped Mathieu oscillator: the exponent of the map equals log(spectral radius of
    # the monodromy) / T (Floquet), computed here independently by integrating the two
    # fundamental solutions with scipy
    from scipy.integrate import solve_ivp

    c, k1 = 0.05, 0.4
    T = 2 * math.pi / W

    def rhs(t, y):
        return [y[1], -c * y[1] - (1 + k1 * math.cos(W * t)) * y[0]]

    cols = [solve_ivp(rhs, (0, T), e, rtol=1e-12, atol=1e-14).y[:, -1] for e in np.eye(2)]
    floquet = math.log(max(abs(np.linalg.eigvals(np.array(cols).T)))) / T
    res = ensemble([forced(c, k1).nonlinear()], periods=400, keep=200, exponents=True,
                   method="maps")  # fmt: skip
    assert res.mapped[0]
    # the finite-time Benettin estimate over 200 periods converges to the Floquet
    # exponent as 1/(200 T): a few 1e-4 1/s here
    assert res.exponent[0] == pytest.approx(floquet, abs=1e-3)


def test_teeth_in_contact_are_mapped_and_rattling_teeth_are_integrated():
    # below the no-impact boundary, started on its steady state, the teeth stay in
    # contact: mapped, and the same as RK4; above it they separate every period: the
    # map refuses the member and RK4 integrates it (bit-identical to an RK4 run)
    systems = [rattle(0.6).nonlinear(), rattle(1.3).nonlinear()]
    # the linear orbit x = 1 + F_m + A cos(W t - phi) at t = 0 (test_impacts.py)
    A, phi = 0.6 * 0.1, math.atan2(2 * 0.05 * W, 1 - W**2)
    y0 = np.array([[1.1 + A * math.cos(phi), A * W * math.sin(phi)], [1.1, 0.0]])
    kw = dict(periods=300, keep=10, history=3, y0=y0, exponents=True)
    fast, slow = both(systems, **kw)
    assert fast.mapped.tolist() == [True, False]
    scale = state_bounds(systems, y0, fast.period, factor=1.0)
    err = np.abs(fast.poincare - slow.poincare) / scale[:, None, :]
    assert err[0].max() < 1e-12
    assert np.array_equal(fast.poincare[1], slow.poincare[1])
    assert np.array_equal(fast.history[1], slow.history[1])
    assert fast.exponent[1] == slow.exponent[1]


def test_a_transient_that_separates_the_teeth_is_not_mapped():
    # started 3 clearances off its equilibrium, the pair rattles in its first periods
    # before settling in contact: the map's check sees the separation, and the member
    # is integrated by RK4 from the start
    s = [rattle(0.6).nonlinear()]
    y0 = static_states(s) + np.array([[-3.0, 0.0]])
    fast, slow = both(s, periods=200, keep=5, y0=y0)
    assert not fast.mapped[0]
    assert np.array_equal(fast.poincare, slow.poincare)


def test_hermite_interior_of_a_step_is_checked():
    # one line, half backlash 1, two step ends at distance +0.1 beyond it, but leaving
    # the first and entering the second with rates that carry the cubic through the
    # gap in between: the margin is negative although both ends are in contact
    D = np.zeros((2, 1, 2))
    Dv = np.zeros((2, 1, 2))
    d = np.array([[1.1], [1.1]])
    dv = np.array([[-2.0], [2.0]])
    m = _margin(D, Dv, d, dv, np.array([1.0]), np.zeros(2), np.array([1.0]), np.array([1.0]))
    assert m == pytest.approx(0.1 - 0.5, abs=1e-12)  # the cubic's minimum: 0.1 - 2/4
    dv_slow = np.array([[-0.1], [0.1]])
    m = _margin(D, Dv, d, dv_slow, np.array([1.0]), np.zeros(2), np.array([1.0]), np.array([1.0]))
    assert m > 0


def test_method_is_checked_and_non_periodic_runs_use_rk4():
    s = [forced().nonlinear()]
    with pytest.raises(ReducerlabError, match="method must be 'auto', 'rk4' or 'maps'"):
        ensemble(s, periods=4, keep=1, method="floquet")
    # a second law at an incommensurate frequency: no one-period map, RK4 everywhere
    m = Model(
        [Dof("a", "x")],
        [Inertia("a.x", 1.0), Support("a.x", 1.0, 0.1),
         Load("a.x", Fourier(0.0, (0.1,), W)), Load("a.x", Fourier(0.0, (0.1,), W * 2**0.5),
                                                     name="second")],
    )  # fmt: skip
    res = ensemble([m.nonlinear()], periods=40, keep=2, method="maps", period=2 * math.pi / W)
    assert not res.mapped[0]


def test_auto_does_not_build_maps_for_teeth_that_separate_at_once(monkeypatch):
    """Teeth that rattle from the first period (the Kahraman-Singh pair above its
    no-impact boundary): ``auto`` runs RK4 alone, bit-identical to ``rk4``, without
    building a map (which would fail in its first period after 2n + 1 periods of
    work); teeth that stay in contact are still mapped; ``maps`` still tries."""
    import reducerlab.dynamics.maps as maps_module

    built = []
    real = maps_module.affine_maps
    monkeypatch.setattr(
        maps_module, "affine_maps", lambda *a, **k: built.append(1) or real(*a, **k)
    )
    s = [rattle(1.3).nonlinear()]
    kw = dict(periods=300, keep=10, history=3)
    auto = ensemble(s, method="auto", **kw)
    assert not built and not auto.mapped[0]
    rk4 = ensemble(s, method="rk4", **kw)
    assert np.array_equal(auto.poincare, rk4.poincare)
    assert np.array_equal(auto.history, rk4.history)
    ensemble(s, method="maps", **kw)
    assert built  # forced: tried, and refused in the run
    built.clear()
    A, phi = 0.6 * 0.1, math.atan2(2 * 0.05 * W, 1 - W**2)
    y0 = np.array([[1.1 + A * math.cos(phi), A * W * math.sin(phi)]])
    quiet = ensemble([rattle(0.6).nonlinear()], method="auto", y0=y0, **kw)
    assert built and quiet.mapped[0]


def test_members_with_the_same_laws_run_as_alone():
    """Members whose laws, steps and period are the same share one law table in the
    kernel (``kernel_laws.tabulate``; the ``2n + 1`` trajectories of a map too): each
    member's run, RK4 or mapped, is bit-identical to its run alone, where the damping
    (not a law) differs, where a law differs, and with backlash events."""
    kw = dict(periods=60, keep=4, history=1, steps_per_period=256)
    groups = [
        [forced(0.1).nonlinear(), forced(0.2).nonlinear(), forced(0.2, 0.3).nonlinear(),
         forced(0.2, 0.3).nonlinear(), forced(0.1, 0.3).nonlinear()],
        [rattle(1.3).nonlinear(), rattle(1.3).nonlinear(), rattle(0.6).nonlinear()],
    ]  # fmt: skip
    for systems, methods in zip(groups, (("rk4", "maps"), ("rk4",)), strict=True):
        for method in methods:
            together = ensemble(systems, method=method, **kw)
            for e, s in enumerate(systems):
                alone = ensemble([s], method=method, **kw)
                assert np.array_equal(together.poincare[e], alone.poincare[0])
                assert np.array_equal(together.history[e], alone.history[0])
