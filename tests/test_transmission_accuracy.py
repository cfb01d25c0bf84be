"""Transmission accuracy (issue 31): rigid-kinematics output angle error from the gears'
eccentricities and pitch deviations, against an exact geometric simulation of two
eccentric base circles and against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.transmission_accuracy import (
    ARCSEC,
    TransmissionAccuracyResult,
    transmission_accuracy,
)
from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.errors import DesignError, ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.kinematics.accuracy import (
    GearErrors,
    cumulative_pitch,
    line_angle,
    mesh_lead,
    order_spectrum,
)
from reducerlab.results import Result

GEAR = example_dir() / "gear_pair.toml"
KHV = example_dir() / "khv.toml"
UM = 1e-6


def _exact_lead(theta_p, rbp, rbg, aw, ep, pp, eg, pg):
    """Exact driven-gear lead (rad, clockwise) of an external involute pair whose base
    circles are eccentric, pinion turning counter-clockwise by ``theta_p``.

    Independent of the first-order law: the rigid involute contact lies on the common
    (crossed) tangent of the two base circles, the drive flank's tangent (the one below
    the line of centres); the unwound lengths from each tangent point to the contact add
    up to the tangent's length ``L = sqrt(d^2 - (rbp + rbg)^2)``, with
    ``rbp (theta_p - a_p) + rbg (theta_g - a_g) + L = const`` (``a``: angles of the
    tangent points, ``d``, ``lambda``: the actual centre distance and direction).
    Solved for ``theta_g`` by Newton's method to round-off.
    """
    a = (rbp + rbg) / math.cos(aw)

    def part(tg):
        P = ep * np.stack([np.cos(theta_p + pp), np.sin(theta_p + pp)])
        G = np.array([a, 0.0])[:, None] + eg * np.stack([np.cos(tg + pg), np.sin(tg + pg)])
        D = G - P
        d = np.hypot(*D)
        lam = np.arctan2(D[1], D[0])
        g = np.arccos((rbp + rbg) / d)
        return -(rbp * (lam - g - theta_p) + rbg * (lam + np.pi - g)) - np.sqrt(
            d**2 - (rbp + rbg) ** 2
        )

    c0 = -(rbp * (-aw) + rbg * (np.pi - aw)) - a * math.sin(aw)
    tg = -rbp / rbg * theta_p
    for _ in range(50):
        tg = tg + (part(tg) + rbg * tg - c0) / (-rbg)
    assert np.abs(part(tg) + rbg * tg - c0).max() < 1e-15
    return -(tg + rbp / rbg * theta_p)


@pytest.mark.parametrize(("ep", "pp", "eg", "pg"),
                         [(10 * UM, 0.3, 0.0, 0.0), (0.0, 0.0, 10 * UM, 0.7),
                          (7 * UM, -1.1, 4 * UM, 2.5)])  # fmt: skip
def test_eccentric_pair_matches_the_exact_common_tangent(ep, pp, eg, pg):
    rbp, rbg, aw = 0.035, 0.08, math.radians(21.5)
    th = np.linspace(0, 2 * math.pi * rbg / rbp, 3001)
    exact = _exact_lead(th, rbp, rbg, aw, ep, pp, eg, pg)
    tau = line_angle(-1, False, aw)  # the gear turns clockwise
    s = mesh_lead(th, -rbp / rbg * th, GearErrors(25, ep, pp), GearErrors(60, eg, pg), tau, 0.3)
    # first order in e / r_b: the residual is of relative size e / r_b ~ 3e-4
    e = ep + eg
    assert np.abs(s / rbg - exact).max() < 3 * (e / rbp) * (e / rbg)
    assert np.ptp(exact) > 1.9 * max(ep, eg) / rbg  # amplitude e (not e cos alpha)


def _exact_internal_lead(theta_a, rba, rbb, aw, ea, pa, eb, pb):
    """Exact lead (rad, in B's clockwise sense) of a pinion B inside a ring A, both
    turning clockwise (the KHV mesh in the carrier frame), eccentric base circles.

    The rigid contact lies on the direct common tangent whose tangent points sit at
    ``lambda - gamma`` on both circles (``cos(gamma) = (rba - rbb) / d``), beyond the
    pinion's tangent point; the unwound lengths differ by the tangent's length
    ``L = sqrt(d^2 - (rba - rbb)^2)``:
    ``rba (theta_a - a_t) - rbb (theta_b - a_t) - L = const``. Newton to round-off.
    """
    a = (rba - rbb) / math.cos(aw)

    def part(tb):
        OA = ea * np.stack([np.cos(theta_a + pa), np.sin(theta_a + pa)])
        OB = np.array([a, 0.0])[:, None] + eb * np.stack([np.cos(tb + pb), np.sin(tb + pb)])
        D = OB - OA
        d = np.hypot(*D)
        at = np.arctan2(D[1], D[0]) - np.arccos((rba - rbb) / d)
        return rba * (theta_a - at) + rbb * at - np.sqrt(d**2 - (rba - rbb) ** 2)

    c0 = (rba - rbb) * aw - a * math.sin(aw)
    tb = rba / rbb * theta_a
    for _ in range(50):
        tb = tb + (part(tb) - rbb * tb - c0) / rbb
    assert np.abs(part(tb) - rbb * tb - c0).max() < 1e-15
    return -(tb - rba / rbb * theta_a)


@pytest.mark.parametrize(("ea", "pa", "eb", "pb"),
                         [(10 * UM, 0.3, 0.0, 0.0), (0.0, 0.0, 10 * UM, 0.7),
                          (7 * UM, -1.1, 4 * UM, 2.5)])  # fmt: skip
def test_internal_pair_matches_the_exact_common_tangent(ea, pa, eb, pb):
    # the KHV example's pair: ring 33 and planet 30 teeth, m 3.5 mm, alpha_w 30.5 deg
    rba, rbb, aw = 0.05427, 0.04933, math.radians(30.5)
    th = -np.linspace(0, 4 * math.pi, 3001)  # the ring turns clockwise in the carrier
    exact = _exact_internal_lead(th, rba, rbb, aw, ea, pa, eb, pb)
    tau = line_angle(-1, True, aw)
    s = mesh_lead(th, rba / rbb * th, GearErrors(33, ea, pa), GearErrors(30, eb, pb), tau, 0.3)
    # second order: relative to the tangent's short length L = a sin(alpha_w) ~ 2.9 mm
    e, L = ea + eb, (rba - rbb) * math.tan(aw)
    assert np.abs(s / rbb - exact).max() < 2 * (e / L) * (e / rbb)
    assert np.ptp(exact) > 1.9 * max(ea, eb) / rbb


def test_line_angle_closed_forms_and_bad_input():
    aw = math.radians(20)
    assert line_angle(-1, False, aw) == pytest.approx(math.pi / 2 - aw)
    assert line_angle(1, False, aw) == pytest.approx(-(math.pi / 2 - aw))
    assert line_angle(-1, True, aw) == pytest.approx(-(math.pi / 2 + aw))
    with pytest.raises(ReducerlabError, match="turning_b"):
        line_angle(0, False, aw)
    with pytest.raises(ReducerlabError, match="working pressure angle"):
        line_angle(1, False, 2.0)


def _with(path, values):
    return load_design(path).with_values(values)


def test_gear_eccentricity_is_a_once_per_revolution_sine():
    e, phase = 5 * UM, math.radians(30)
    d = _with(GEAR, {"gear.errors": {"eccentricity": e, "eccentricity_phase": phase}})
    r = transmission_accuracy(d, samples=1024)
    rb = d.base_radius("gear")
    u = r.data["output_angle"].values
    # closed form: the gear turns clockwise (psi_B = -u + phase), tau = pi/2 - alpha_w;
    # lead of the gear = -e cos(psi_B - tau) / r_bg (zero shifts: alpha_w = alpha)
    alpha = d.mesh.pressure_angle
    expect = -e * np.cos(-u + phase - (math.pi / 2 - alpha)) / rb
    assert r.data["error"].values == pytest.approx(expect, abs=1e-12 * e / rb)
    assert r.peak_to_peak == pytest.approx(2 * e / rb / ARCSEC, rel=1e-4)  # sampling
    orders, amp = r.data["order"].values, r.data["amplitude"].values
    assert amp[1] == pytest.approx(e / rb / ARCSEC, rel=1e-12)
    assert np.all(amp[orders != 1] < 1e-9 * amp[1])
    assert r.data["input_order"].values[1] == pytest.approx(1 / 2.4)


def test_two_eccentricities_add_with_their_phases():
    ep, eg = 3 * UM, 5 * UM
    both = transmission_accuracy(_with(GEAR, {
        "pinion.errors": {"eccentricity": ep, "eccentricity_phase": 1.0},
        "gear.errors": {"eccentricity": eg, "eccentricity_phase": -0.4}}), samples=512)  # fmt: skip
    p = transmission_accuracy(
        _with(GEAR, {"pinion.errors": {"eccentricity": ep, "eccentricity_phase": 1.0}}), 512
    )
    g = transmission_accuracy(
        _with(GEAR, {"gear.errors": {"eccentricity": eg, "eccentricity_phase": -0.4}}), 512
    )
    err = both.data["error"].values
    assert err == pytest.approx(p.data["error"].values + g.data["error"].values, abs=1e-18)
    # the pinion's: amplitude ep / r_bg at 2.4 pinion turns per output turn
    d = load_design(GEAR)
    u = p.data["output_angle"].values
    psi = 2.4 * u + 1.0
    tau = math.pi / 2 - d.mesh.pressure_angle  # line_angle(-1, False, alpha)
    assert p.data["error"].values == pytest.approx(
        ep * np.cos(psi - tau) / d.base_radius("gear"), abs=1e-12
    )


def test_zero_errors_give_zero():
    for path in (GEAR, KHV):
        r = transmission_accuracy(load_design(path), samples=256)
        assert not np.any(r.data["error"].values) and r.peak_to_peak == 0.0


def test_pitch_deviations_give_the_cumulative_pitch_curve():
    z = 60
    k = np.arange(z)
    f = 2 * UM * np.sin(2 * math.pi * 3 * k / z) + 1 * UM * (-1.0) ** k  # closes
    f -= f.mean()
    d = _with(GEAR, {"gear.errors": {"pitch_deviations": list(f)}})
    r = transmission_accuracy(d, samples=z * 16 + 7)  # odd: no sample on a tooth change
    F = np.concatenate([[0.0], np.cumsum(f)[:-1]])
    assert cumulative_pitch(f) == pytest.approx(F, abs=1e-20)
    # the gear turns once an output revolution: tooth round(u z / 2 pi) is in mesh; a
    # tooth ahead makes the driven gear lag: -cos(alpha) F_k / r_bg
    u = r.data["output_angle"].values
    tooth = np.mod(np.floor(u * z / (2 * math.pi) + 0.5).astype(int), z)
    expect = -math.cos(d.mesh.pressure_angle) * F[tooth] / d.base_radius("gear")
    assert r.data["error"].values == pytest.approx(expect, abs=1e-18)
    assert r.peak_to_peak == pytest.approx(
        math.cos(d.mesh.pressure_angle) * np.ptp(F) / d.base_radius("gear") / ARCSEC
    )


def test_khv_ring_and_planet_eccentricities_through_the_kinematics():
    er, ev = 5 * UM, 3 * UM
    planet = {"eccentricity": ev, "eccentricity_phase": 0.5}
    d = _with(KHV, {"gears.ring_errors": {"eccentricity": er}, "gears.planet_errors": planet})
    r = transmission_accuracy(d, samples=2048)
    rb = d.gears.pair().base_radius(1)  # the planet's: the output's error is s / r_bV
    amp = r.data["amplitude"].values
    # one output turn: the carrier turns |i| = z_V / (z_K - z_V) = 10 times; in its frame
    # the ring turns 10 times (order 10 = input order 1), the planet 10 + 1 = 11 times
    zv, zk = 30, 33
    assert zv / (zk - zv) == 10
    assert amp[10] == pytest.approx(er / rb / ARCSEC, rel=1e-12)
    assert amp[11] == pytest.approx(ev / rb / ARCSEC, rel=1e-12)
    assert r.data["input_order"].values[10] == pytest.approx(1.0)
    others = np.delete(amp, [10, 11])
    assert np.all(others < 1e-9 * amp[10])
    assert [k for k, _ in r.largest_orders(2)] == [10, 11]


def test_order_spectrum_of_a_cosine():
    x = np.linspace(0, 2 * math.pi, 64, endpoint=False)
    _, a = order_spectrum(0.5 + 3 * np.cos(5 * x + 1) + np.cos(32 * x))
    assert a[0] == pytest.approx(0.5) and a[5] == pytest.approx(3) and a[32] == pytest.approx(1)
    with pytest.raises(ReducerlabError, match="at least 4"):
        order_spectrum([1.0, 2.0])


def test_bad_input_is_named():
    with pytest.raises(DesignError, match=r"gear\.errors\.pitch_deviations.*60 teeth"):
        _with(GEAR, {"gear.errors": {"pitch_deviations": [1e-6, -1e-6]}})
    with pytest.raises(DesignError, match=r"pitch_deviations.*not 0"):
        _with(GEAR, {"gear.errors": {"pitch_deviations": [1e-6] * 60}})
    with pytest.raises(DesignError, match=r"gears\.ring_errors\.pitch_deviations"):
        _with(KHV, {"gears.ring_errors": {"pitch_deviations": [0.0] * 30}})
    with pytest.raises(DesignError, match=r"pinion\.errors\.eccentricity"):
        _with(GEAR, {"pinion.errors": {"eccentricity": -1e-6}})
    with pytest.raises(DesignError, match=r"pinion\.errors\.eccentricity"):
        _with(GEAR, {"pinion.errors": {"eccentricity": 5}})  # 5 m: meant um
    with pytest.raises(ReducerlabError, match="samples"):
        transmission_accuracy(load_design(GEAR), samples=10)
    with pytest.raises(ReducerlabError, match="gear_pair, khv"):
        transmission_accuracy(load_design(example_dir() / "torsional_chain.toml"))
    with pytest.raises(ReducerlabError, match="pitch"):
        GearErrors(3, pitch=(1e-6, -1e-6))


def test_cli_writes_and_reloads(tmp_path):
    out = tmp_path / "acc"
    r = CliRunner().invoke(app, ["accuracy", str(KHV), "--samples", "256", "-o", str(out),
                                 "--set", "gears.ring_errors.eccentricity=5 um"])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "peak to peak" in r.output
    res = Result.load(out / "accuracy.nc")
    assert isinstance(res, TransmissionAccuracyResult)
    assert res.peak_to_peak == pytest.approx(
        2 * 5e-6 / load_design(KHV).gears.pair().base_radius(1) / ARCSEC, rel=1e-3
    )
    assert {p.name for p in out.iterdir()} >= {
        "accuracy.nc",
        "accuracy.json",
        "accuracy.txt",
        "accuracy.png",
    }
