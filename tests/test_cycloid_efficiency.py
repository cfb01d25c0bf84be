"""The cycloid-ball drive's efficiency from the spin and sliding of its balls (issue 31):
the full-slip friction integral against its closed forms, the loss's scaling, a hand sum
of the loss at one phase by an independent path, the example's number and bad input."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.cycloid_efficiency import ball_track_motion, cycloid_efficiency
from reducerlab.analysis.efficiency import efficiency
from reducerlab.cli import app
from reducerlab.contact.ball_track import ball_loads
from reducerlab.contact.hertz import hertz_elliptic
from reducerlab.contact.spin_friction import full_slip_power, spin_moment
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir

EXAMPLE = example_dir() / "cycloid_ball.toml"


@pytest.fixture(scope="module")
def design():
    return load_design(EXAMPLE)


def test_spin_moment_of_a_circle_is_johnsons_closed_form():
    h = hertz_elliptic(250.0, 400.0, 400.0, 1.1e11)
    mu = 0.07
    want = 3 * math.pi / 16 * mu * 250.0 * h.a
    assert spin_moment(h.a, h.b, h.p0, mu) == pytest.approx(want, rel=1e-6)


def test_spin_moment_of_a_slender_ellipse_tends_to_three_eighths():
    """``b << a``: ``r -> |x|`` and ``M -> (3/8) mu F a`` (a the major semi-axis); the
    circle's 3 pi / 16 = 0.589 above it, the ratio falling with the slenderness."""
    a, p0, mu = 1e-3, 1e9, 0.1
    ratios = []
    for b in (1e-3, 0.5e-3, 0.1e-3, 1e-6):
        F = 2 * math.pi * a * b * p0 / 3
        ratios.append(float(spin_moment(a, b, p0, mu, nodes=200)) / (mu * F * a))
    assert ratios[0] == pytest.approx(3 * math.pi / 16, rel=1e-6)
    assert all(x > y for x, y in itertools.pairwise(ratios))
    assert ratios[-1] == pytest.approx(3 / 8, rel=1e-3)


def test_pure_sliding_is_mu_F_s_and_spin_adds_little_to_fast_sliding():
    h = hertz_elliptic(100.0, 300.0, 3000.0, 1.1e11)
    mu = 0.05
    slide = float(full_slip_power(h.a, h.b, h.p0, [0.3, -0.4], 0.0, mu))
    assert slide == pytest.approx(mu * 100.0 * 0.5, rel=1e-10)
    both = float(full_slip_power(h.a, h.b, h.p0, [0.5, 0.0], 10.0, mu))
    spin = float(spin_moment(h.a, h.b, h.p0, mu)) * 10.0
    assert mu * 100.0 * 0.5 < both < mu * 100.0 * 0.5 + spin


def _hand_slip(design, phase: float, w_in: float) -> np.ndarray:
    """``S`` of lines +, - by finite differences in the housing frame: the ball centre's
    velocity against the discs' material velocities at the two contact points."""
    t = design.ball_track()
    s = design.kinematics().speeds(w_in)
    wc, wp = s["centre disc"], s["planetary disc"]
    e, Z, R = t.eccentricity, t.balls, t.ball_circle_radius
    r2, rb, beta = t.pitch_radius, t.ball_radius, t.contact_angle
    rate = t.centre_lobes / Z * (wc - w_in)  # ball set in the eccentric's frame

    def rot(ang, v):
        c, s_ = math.cos(ang), math.sin(ang)
        return np.array([c * v[0] - s_ * v[1], s_ * v[0] + c * v[1]])

    def centre(i, time):
        psi = phase + rate * time + 2 * math.pi * i / Z
        return rot(w_in * time, np.array([R * math.sin(psi), e / 2 - R * math.cos(psi)]))

    out = np.zeros((Z, 2))
    dt = 1e-5 / w_in
    for i in range(Z):
        c = centre(i, 0.0)
        vc = (centre(i, dt) - centre(i, -dt)) / (2 * dt)
        m = c - np.array([0.0, -r2])
        m /= np.linalg.norm(m)
        tan = np.array([-m[1], m[0]])
        o3 = np.array([0.0, e])
        v_o3 = w_in * np.array([-o3[1], o3[0]])
        for j, sigma in enumerate((1.0, -1.0)):
            x2 = c - sigma * rb * math.cos(beta) * m
            x3 = c + sigma * rb * math.cos(beta) * m
            v2 = wc * np.array([-x2[1], x2[0]])
            v3 = v_o3 + wp * np.array([-(x3 - o3)[1], (x3 - o3)[0]])
            out[i, j] = (2 * vc - v2 - v3) @ tan
    return out


def test_loss_at_one_phase_is_the_hand_sum_over_the_balls(design):
    w = design.operating_speed
    phase, T, mu = 0.0, 50.0, 0.05
    res = cycloid_efficiency(design, mu=mu, torques=[T], phases=1)
    slip, spin = ball_track_motion(design, phase, w)
    hand = _hand_slip(design, phase, w)
    assert np.abs(slip - hand).max() < 1e-6 * np.abs(hand).max()
    track = design.ball_track()
    F = ball_loads(track, T, phase).force
    slide = mu * float(np.sum(F * np.abs(hand)))
    assert float(res.data["slide_loss"][0]) == pytest.approx(slide, rel=1e-6)
    # spin alone: a midpoint-rule Hertz integral of each contact (A, B by hand)
    rb, rg = track.ball_radius, 2 * track.conformity * track.ball_radius
    cb = math.cos(track.contact_angle)
    k2, k3 = track.path_curvatures(phase)
    e_star = track.youngs_modulus / (2 * (1 - track.poisson_ratio**2))
    g = (np.arange(400) + 0.5) / 400 * 2 - 1
    X, Y = np.meshgrid(g, g)
    inside = X**2 + Y**2 < 1
    spin_sum = 0.0
    for i, j in zip(*np.nonzero(F), strict=True):
        for kw in ((k2[i], -k3[i]), (-k2[i], k3[i]))[j]:
            h = hertz_elliptic(F[i, j], 0.5 * (1 / rb + kw * cb / (1 - kw * rb * cb)),
                               0.5 * (1 / rb - 1 / rg), e_star)  # fmt: skip
            p = h.p0 * np.sqrt(np.where(inside, 1 - X**2 - Y**2, 0.0))
            r = np.hypot(h.a * X, h.b * Y)
            M = mu * float(np.sum(p * r)) * h.a * h.b * (2 / 400) ** 2
            spin_sum += M * abs(spin) / 2
    assert float(res.data["spin_loss"][0]) == pytest.approx(spin_sum, rel=2e-3)
    total = float(res.data["mesh_loss"][0, 0])
    assert slide - spin_sum < total < slide + spin_sum


def test_loss_is_proportional_to_mu_and_speed(design):
    a = cycloid_efficiency(design, mu=0.05, torques=[20.0, 50.0], phases=3,
                           speeds=[50.0, 100.0])  # fmt: skip
    b = cycloid_efficiency(design, mu=0.1, torques=[20.0, 50.0], phases=3)
    assert np.allclose(b.data["mesh_loss"], 2 * a.data["mesh_loss"], rtol=1e-12)
    las = a.data["loss_at_speed"].values
    assert np.allclose(las[:, 1], 2 * las[:, 0], rtol=1e-12)
    fast = load_design(EXAMPLE, ['input_speed="3000 rpm"'])
    c = cycloid_efficiency(fast, mu=0.05, torques=[20.0, 50.0], phases=3)
    assert np.allclose(c.data["mesh_loss"], 3 * a.data["mesh_loss"], rtol=1e-9)
    assert np.allclose(c.efficiency, a.efficiency, rtol=1e-12)


def test_the_command_takes_the_ball_track(tmp_path):
    out = tmp_path / "eff"
    r = CliRunner().invoke(app, ["efficiency", str(EXAMPLE), "--torques", "50 N*m",
                                 "--positions", "4", "-o", str(out)])  # fmt: skip
    assert r.exit_code == 0, r.output
    res = cycloid_efficiency(load_design(EXAMPLE), torques=[50.0], phases=4)
    assert f"{float(res.efficiency[0]):.4f}" in r.output
    assert (out / "efficiency.json").exists()


def test_the_designs_coefficient_and_the_dispatch(design):
    d = load_design(EXAMPLE, ["cycloid_pair.friction_coefficient=0.1"])
    a = cycloid_efficiency(d, torques=[50.0], phases=2)
    assert a.data.attrs["mu"] == 0.1
    with pytest.raises(ReducerlabError, match="cycloid_efficiency"):
        efficiency(design, mu=0.1, torques=[50.0], positions=3)
    with pytest.raises(ReducerlabError, match=r"cycloid_pair\.friction_coefficient"):
        load_design(EXAMPLE, ["cycloid_pair.friction_coefficient=0.5"])


def test_the_examples_efficiency_at_its_design_load(design):
    """The example at 50 N m, 1000 rpm, mu = 0.05: the ball track alone loses well under
    one percent (number in docs/efficiency.md); the sliding along the grooves dominates
    the spin."""
    res = cycloid_efficiency(design, torques=[50.0], phases=8)
    eta = float(res.efficiency[0])
    assert 0.99 < eta < 1.0
    assert res.data.attrs["design_torque"] == 50.0
    assert float(res.data["output_torque"][0]) == pytest.approx(50.0)
    assert float(res.data["slide_loss"][0]) > 5 * float(res.data["spin_loss"][0])


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"mu": -0.1}, "mu"),
        ({"torques": [-5.0]}, "torques"),
        ({"phases": 0}, "phases"),
        ({"speeds": [0.0]}, "speeds"),
        ({"loads": 0}, "loads"),
    ],
)
def test_bad_input_is_named(design, kwargs, field):
    with pytest.raises(ReducerlabError, match=field):
        cycloid_efficiency(design, **kwargs)


def test_a_gear_design_is_refused():
    with pytest.raises(ReducerlabError, match="cycloid_ball"):
        cycloid_efficiency(load_design(example_dir() / "gear_pair.toml"))
    with pytest.raises(ReducerlabError, match="nodes"):
        spin_moment(1e-3, 1e-3, 1e9, 0.1, nodes=2)
    with pytest.raises(ReducerlabError, match="semi-axes"):
        spin_moment(0.0, 1e-3, 1e9, 0.1)


@pytest.mark.parametrize("phase", [0.0, 0.05])
def test_the_sliding_residual_with_the_planetary_disc_as_output(phase):
    """Centre disc held, planetary disc out: the same hand path, other disc speeds."""
    d = load_design(EXAMPLE, ['output="planetary"'])
    slip, spin = ball_track_motion(d, phase, d.operating_speed)
    hand = _hand_slip(d, phase, d.operating_speed)
    assert np.abs(slip - hand).max() < 1e-6 * np.abs(hand).max()
    s = d.kinematics().speeds(d.operating_speed)
    beta = d.ball_track().contact_angle
    assert spin == pytest.approx((s["centre disc"] - s["planetary disc"]) * math.sin(beta))
