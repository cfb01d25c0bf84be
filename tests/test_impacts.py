"""Tooth separation and impact diagnostics (analysis/impacts.py, response attributes).

Oracle: the single-DOF gear pair with backlash of the gear-rattle literature (Kahraman
and Singh, J. Sound Vib. 142, 1990, 49-75), ``x'' + 2 zeta x' + f(x) = F_m + F_a cos(W t)``
with ``f`` the dead zone of half width 1. While the teeth stay in drive-side contact the
motion is the linear oscillator's, ``x = 1 + F_m + A cos(W t - phi)`` with
``A = F_a / sqrt((1 - W^2)^2 + (2 zeta W)^2)``: the teeth never separate when ``A < F_m``
and do when ``A > F_m`` (their no-impact boundary). The separated motion is checked
against the event-located DOP853 reference integrator.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.analysis.impacts import IMPACT_CLASSES, contact_states, mesh_mode
from reducerlab.analysis.response import response
from reducerlab.dynamics.coordinates import static_state, to_system
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.reference import simulate_reference
from reducerlab.errors import ReducerlabError
from reducerlab.model import Backlash, Dof, Fourier, Inertia, Load, Mesh, Model

ZETA, FM = 0.05, 0.1


def rattle_model(omega: float, fa: float) -> Model:
    return Model(
        [Dof("a", "x")],
        [
            Inertia("a.x", 1.0),
            Mesh({"a.x": 1.0}, 1.0, 2 * ZETA, backlash=Backlash.half(1.0)),
            Load("a.x", Fourier(FM, (fa,), omega)),
        ],
        name="rattle",
    )


def linear_amplitude(omega: float, fa: float) -> float:
    return fa / math.hypot(1 - omega**2, 2 * ZETA * omega)


def test_sampled_sine_has_the_closed_form_shares_and_counts():
    # delta = m + A sin(2 pi t) over 7 periods: apart while |delta| <= b, i.e. for the
    # phases with sin in [(-b - m)/A, (b - m)/A]; the share is the arcsine measure
    # (1e5 samples per period resolve each of the 4 state changes per period to 1e-5:
    # shares to 5e-5)
    m, A, b = 0.2, 1.5, 1.0
    t = np.linspace(0, 7, 700_001)[:-1]
    d = m + A * np.sin(2 * np.pi * t)
    st = contact_states(d, b, 7.0)
    share = lambda lo, hi: (math.asin(hi) - math.asin(lo)) / math.pi  # noqa: E731
    assert st.separation_fraction == pytest.approx(share((-b - m) / A, (b - m) / A), abs=5e-5)
    assert st.back_contact_fraction == pytest.approx(share(-1, (-b - m) / A), abs=5e-5)
    assert st.contact_losses == pytest.approx(1.0)
    assert st.back_impacts == pytest.approx(1.0)
    assert st.impact_class == "double-sided impact"
    # shallower: separates, never reaches the back flank
    st = contact_states(1.6 + 0.8 * np.sin(2 * np.pi * t), b, 7.0)
    assert st.impact_class == "single-sided impact" and st.back_impacts == 0
    st = contact_states(2.0 + 0.8 * np.sin(2 * np.pi * t), b, 7.0)
    assert (st.impact_class, st.separation_fraction, st.contact_losses) == ("no impact", 0, 0)
    # loaded on the negative side: the mirror image gives the same states
    mirrored = contact_states(-d, b, 7.0, side=-1)
    assert mirrored == contact_states(d, b, 7.0)
    # no backlash: nothing can separate
    assert contact_states(d, 0.0, 7.0).impact_class == IMPACT_CLASSES[0]


@pytest.mark.parametrize(
    "args, rule",
    [
        ((np.array([]), 1.0, 1.0), "non-empty"),
        ((np.array([0.0, np.nan]), 1.0, 1.0), "finite"),
        ((np.zeros(3), -1.0, 1.0), "half_backlash"),
        ((np.zeros(3), 1.0, 0.0), "periods"),
        ((np.zeros(3), 1.0, 1.0, 0.5), "side"),
    ],
)
def test_bad_input_is_named(args, rule):
    with pytest.raises(ReducerlabError, match=rule):
        contact_states(*args)


def test_mesh_mode_of_the_single_dof_pair_is_sqrt_k_over_m():
    s = to_system(rattle_model(0.8, 0.01))
    hz, share = mesh_mode(s, 0)
    assert hz == pytest.approx(1 / (2 * math.pi), rel=1e-12)
    assert share == pytest.approx(1.0, rel=1e-12)


def linear_orbit_start(omega: float, fa: float) -> np.ndarray:
    """State at t = 0 on the no-impact orbit x = 1 + F_m + A cos(W t - phi)."""
    A = linear_amplitude(omega, fa)
    phi = math.atan2(2 * ZETA * omega, 1 - omega**2)
    return np.array([1 + FM + A * math.cos(phi), A * omega * math.sin(phi)])


@pytest.mark.parametrize("ratio", [0.9, 1.1])
def test_no_impact_boundary_of_kahraman_and_singh(ratio):
    # F_a chosen so that the linear amplitude is 0.9 or 1.1 times the mean force; the
    # run starts on the linear orbit (y0), where the no-impact motion exists
    omega = 0.8
    fa = ratio * FM * math.hypot(1 - omega**2, 2 * ZETA * omega)
    res = response(
        rattle_model(omega, fa), periods=300, keep=10, history=10, steps_per_period=256,
        y0=linear_orbit_start(omega, fa),
    )  # fmt: skip
    a = res.data.attrs
    assert a["mesh_mode_hz"] == pytest.approx(1 / (2 * math.pi), rel=1e-12)
    assert a["frequency_ratio"] == pytest.approx(omega, rel=1e-12)
    if ratio < 1:
        assert a["impact_class"] == "no impact"
        assert a["separation_fraction"] == 0 and a["contact_losses_per_period"] == 0
        # and the motion is the linear closed form at every sample (RK4 at 256 steps
        # per period: error ~(W h)^4 ~ 1e-8 of the amplitude; asserted 1e-6)
        t = res.data["time"].values
        A = linear_amplitude(omega, fa)
        phi = math.atan2(2 * ZETA * omega, 1 - omega**2)
        exact = 1 + FM + A * np.cos(omega * t - phi)
        np.testing.assert_allclose(res.data["delta"].values, exact, rtol=0, atol=1e-6 * A)
    else:
        assert a["impact_class"] != "no impact"
        assert a["separation_fraction"] > 0
        assert a["contact_losses_per_period"] == pytest.approx(1.0)


def test_coexisting_rattle_is_reached_from_rest_but_not_from_the_linear_orbit():
    # Below the no-impact boundary (A = 0.9 F_m) the linear orbit coexists with a
    # rattling one: the start at static equilibrium, whose transient separates the
    # teeth, settles on the rattle; the start on the linear orbit stays there. This is
    # why response takes y0 (the jumps and hysteresis of the rattle literature).
    omega = 0.8
    fa = 0.9 * FM * math.hypot(1 - omega**2, 2 * ZETA * omega)
    rest = response(rattle_model(omega, fa), periods=300, keep=10, history=10).data.attrs
    orbit = response(
        rattle_model(omega, fa), periods=300, keep=10, history=10,
        y0=linear_orbit_start(omega, fa),
    ).data.attrs  # fmt: skip
    assert orbit["impact_class"] == "no impact"
    assert rest["impact_class"] != "no impact" and rest["separation_fraction"] > 0.05


def test_response_y0_is_checked():
    with pytest.raises(ReducerlabError, match="y0 must be 2 finite numbers"):
        response(rattle_model(0.8, 0.01), periods=10, keep=2, history=2, y0=[1.0])


def test_elastic_force_is_zero_while_apart_and_damping_acts_across_the_gap():
    res = response(rattle_model(1.2, 0.2), periods=300, keep=8, history=8, steps_per_period=512)
    ds = res.data
    apart = np.abs(ds["delta"].values) <= 1.0
    assert apart.any()
    assert np.all(ds["elastic_force"].values[apart] == 0.0)
    np.testing.assert_allclose(ds["damping_force"].values, 2 * ZETA * ds["delta_velocity"].values)
    np.testing.assert_allclose(
        ds["mesh_force"].values, ds["elastic_force"].values + ds["damping_force"].values
    )


def test_separation_agrees_with_the_event_located_reference():
    # the period-4 rattle (W = 1.2, F_a = 0.2): shares and counts from the
    # kernel's steps against the DOP853 reference sampled as finely; the sampling of
    # either resolves a crossing to one step in 1024 per period, so the shares agree
    # to ~1e-3 and the counts exactly
    omega, fa = 1.2, 0.2
    model = rattle_model(omega, fa)
    res = response(model, periods=400, keep=8, history=8, steps_per_period=1024)
    a = res.data.attrs
    s = to_system(model)
    T = 2 * math.pi / omega
    # the kernel's state at the start of the history (same start, steps and periods)
    ens = ensemble([s], periods=392, keep=1, steps_per_period=1024, y0=static_state(s))
    y0 = ens.poincare[0, -1]
    t = np.arange(1, 8 * 1024 + 1) * (T / 1024)
    ref = simulate_reference(s, t, y0, rtol=1e-11, atol=1e-13)
    st = contact_states(ref[:, 0], 1.0, 8.0)
    assert st.impact_class == a["impact_class"] != "no impact"
    assert a["separation_fraction"] > 0.05
    assert st.separation_fraction == pytest.approx(a["separation_fraction"], abs=2e-3)
    assert st.back_contact_fraction == pytest.approx(a["back_contact_fraction"], abs=2e-3)
    assert st.contact_losses == a["contact_losses_per_period"]
    assert st.back_impacts == a["back_impacts_per_period"]


def test_paper_004_drive_separates_at_1500_rpm():
    # docs/assumptions.md (paper 004): examples/khv.toml at 1500 rpm. The mean mesh load
    # presses the flanks of negative deflection together; the teeth leave them once per
    # mesh period and stay apart about a third of the time (the mesh force, which
    # includes the viscous force across the gap, never reads zero; the elastic force
    # does). Measured: 29.4 % apart (31.2 % of the samples at 32 steps per period), one
    # contact loss per period, no back-side impact.
    from reducerlab.drives import load_design

    res = response(load_design("examples/khv.toml"), periods=600, keep=20, history=20)
    a = res.data.attrs
    assert a["mean_mesh_force"] < 0
    assert a["impact_class"] == "single-sided impact"
    assert 0.25 < a["separation_fraction"] < 0.35
    assert a["contact_losses_per_period"] == pytest.approx(1.0)
    assert a["back_impacts_per_period"] == 0
    elastic = res.data["elastic_force"].values
    # the elastic force is zero at the samples inside the gap: their share agrees with
    # the interpolated share to within a sample (1/32 of a period, 2 crossings)
    assert np.mean(elastic == 0.0) == pytest.approx(a["separation_fraction"], abs=2 / 32)
    assert np.all(res.data["mesh_force"].values != 0.0)


def test_continuation_shows_the_hysteresis_of_the_no_impact_boundary():
    # Kahraman and Singh's jump: F_a fixed so that the linear amplitude is A = 0.09, the
    # mean force F_m swept. Above A the no-impact orbit exists; below it the teeth must
    # separate. Descending from F_m = 0.3 (no impact from rest), the sweep stays on the
    # no-impact orbit down to F_m = 0.1 (its Poincare point is the closed form
    # 1 + F_m + A cos(phi) at t = kT); ascending from F_m = 0.06 (rattle), it stays on
    # the rattle up to 0.12 although the no-impact orbit exists there: two attractors,
    # reached only by continuation, drawn as two sweeps.
    from reducerlab.analysis.bifurcation import bifurcation
    from reducerlab.analysis.sweep import Axis

    omega, A = 0.8, 0.09
    fa = A * math.hypot(1 - omega**2, 2 * ZETA * omega)
    model = Model(
        [Dof("a", "x")],
        [
            Inertia("a.x", 1.0),
            Mesh({"a.x": 1.0}, 1.0, 2 * ZETA, name="mesh", backlash=Backlash.half(1.0)),
            Load("a.x", 0.1, name="mean"),
            Load("a.x", Fourier(0.0, (fa,), omega), name="alt"),
        ],
        name="rattle",
    )
    vals = [0.06, 0.08, 0.1, 0.12, 0.2, 0.3]
    res = bifurcation(model, Axis("mean.value", vals), periods=300, keep=6, scale=1.0,
                      continuation="both")  # fmt: skip
    up, down = res.data["poincare"].values, res.data["poincare_down"].values
    phi = math.atan2(2 * ZETA * omega, 1 - omega**2)
    for i, fm in enumerate(vals):
        if fm > A:  # the descending sweep: the no-impact orbit, exactly
            np.testing.assert_allclose(down[i], 1 + fm + A * math.cos(phi), atol=1e-6)
    for i in (2, 3):  # F_m = 0.1, 0.12: coexistence, the ascending sweep rattles
        assert np.all(up[i] < 1.0) and np.all(down[i] > 1.0)
    # where only one attractor exists the sweeps agree
    np.testing.assert_allclose(up[[0, 1, 4, 5]], down[[0, 1, 4, 5]], atol=1e-6)
    assert res.data.attrs["continuation"] == "both"
    np.testing.assert_allclose(res.data["frequency_ratio"].values, omega, rtol=1e-12)
    np.testing.assert_allclose(res.data["mesh_mode_hz"].values, 1 / (2 * math.pi), rtol=1e-12)
    assert len(res.plot().axes[0].get_legend().get_texts()) == 2
    with pytest.raises(ReducerlabError, match="continuation must be"):
        bifurcation(model, Axis("mean.value", vals), periods=10, keep=2, continuation="left")


def test_random_starts_reveal_the_coexisting_rattle():
    # bifurcation(seeds=...): each value also runs from random starts around its static
    # equilibrium. On the softening side of the resonance (k = 1.1, the linear amplitude
    # inside the no-impact boundary) the run from rest finds the no-impact orbit and
    # random starts find the coexisting rattle (Kahraman and Singh's two attractors);
    # far on the hardening side (k = 0.45) the no-impact orbit is the only attractor.
    from reducerlab.analysis.bifurcation import bifurcation
    from reducerlab.analysis.sweep import Axis

    omega = 0.8
    model = rattle_model(omega, 0.9 * FM * math.hypot(1 - omega**2, 2 * ZETA * omega))
    res = bifurcation(model, Axis("mesh:a.x.stiffness", (0.45, 1.1)), periods=300, keep=16,
                      seeds=12, exponents=True)  # fmt: skip
    assert res.impacts() == ["no impact", "no impact"]
    seeds = res.data["impact_class_seeds"].values
    assert np.all(seeds[0] == 0)  # every start ends without impacts at k = 0.45
    assert np.any(seeds[1] > 0)
    assert res.coexisting().tolist() == [False, True]
    assert res.data["poincare_seeds"].shape == (2, 12, 16)
    # the same value gets the same starts in any chunk and run
    again = bifurcation(model, Axis("mesh:a.x.stiffness", (1.1,)), periods=300, keep=16,
                        seeds=12, exponents=True)  # fmt: skip
    np.testing.assert_array_equal(again.data["poincare_seeds"].values[0],
                                  res.data["poincare_seeds"].values[1])  # fmt: skip
    with pytest.raises(ReducerlabError, match="seeds must be an integer >= 0"):
        bifurcation(model, Axis("mesh:a.x.stiffness", (1.1,)), periods=10, keep=2, seeds=-1)


def test_shares_are_resolved_between_samples():
    # a coarse sampling (32 samples per period, as 32 RK4 steps): counting samples
    # resolves a share only to 1/32 = 3e-2; with the deflection linear between samples
    # the crossings fall inside their intervals and the shares meet the arcsine closed
    # form to O(h^2) (measured 2e-3; asserted 5e-3)
    m, A, b = 0.2, 1.5, 1.0
    t = np.arange(7 * 32 + 1) / 32
    d = m + A * np.sin(2 * np.pi * t + 0.3)
    st = contact_states(d, b, 7.0, times=t)
    share = lambda lo, hi: (math.asin(hi) - math.asin(lo)) / math.pi  # noqa: E731
    assert st.separation_fraction == pytest.approx(share((-b - m) / A, (b - m) / A), abs=5e-3)
    assert st.back_contact_fraction == pytest.approx(share(-1, (-b - m) / A), abs=5e-3)
    with pytest.raises(ReducerlabError, match="times: must be increasing"):
        contact_states(d, b, 7.0, times=t[::-1])
