"""Transmission ratios: closed forms, conventions, and simulated rolling of the pitch cones."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate
from hypothesis import given, settings
from hypothesis import strategies as st

from reducerlab.errors import ReducerlabError
from reducerlab.kinematics import (
    CycloidBallDrive,
    DoubleNutationDrive,
    ExternalGearPair,
    KHVDrive,
    NutationDrive,
    angular_velocity_fixed,
    euler_zxz,
    external_cone_angles,
    internal_cone_angles,
    nutation_angle_from_cones,
    relative_rotation_axis,
    rot_z,
    skew,
    unskew,
)


def test_published_tooth_numbers():
    # paper 000: z1..z4 = 28, 26, 32, 30: i = z1 z4 / (z1 z4 - z2 z3) = 840 / 8
    assert DoubleNutationDrive(28, 26, 32, 30, math.radians(5)).ratio == 105.0
    # paper 004: planet 30, ring 33: i = z_V / (z_V - z_K) = -10 (output reversed)
    assert KHVDrive(30, 33).ratio == -10.0
    # paper 003: centre 38, planetary 40, planetary held: i = 38 / (38 - 40) = -19
    assert CycloidBallDrive(38, 40).ratio == -19.0
    assert CycloidBallDrive(38, 40).balls == 39
    assert CycloidBallDrive(38, 40, output="planetary").ratio == 20.0
    assert ExternalGearPair(25, 60).ratio == -2.4


def test_nutation_closed_forms_and_signs():
    th = math.radians(4)
    # held nutating gear, internal cones: i = z_c / (z_c - z_n)
    assert NutationDrive(59, 60, th).ratio == 60.0
    assert NutationDrive(61, 60, th).ratio == -60.0  # more teeth on the nutating gear
    # central gear fixed, output through a CV coupling: i = z_n / (z_n - z_c)
    assert NutationDrive(101, 100, th, output="nutating").ratio == 101.0
    # external cones: i = z_c / (z_c + z_n) for the held case
    assert NutationDrive(20, 30, math.radians(80), contact="external").ratio == 30 / 50


@settings(max_examples=50, deadline=None)
@given(
    st.integers(10, 120),
    st.integers(1, 4),
    st.floats(0.5, 25.0),
    st.floats(0.5, 25.0),
    st.sampled_from(["central", "nutating"]),
)
def test_ratio_does_not_depend_on_nutation_angle(z, dz, th1, th2, output):
    a = NutationDrive(z, z + dz, math.radians(th1), output=output)
    b = NutationDrive(z, z + dz, math.radians(th2), output=output)
    assert a.ratio == b.ratio
    # but the cone angles do
    assert a.cone_angles() != b.cone_angles() or th1 == th2


def test_planar_limit_is_willis():
    # the KHV drive is the nutation drive (output through the coupling) at zero angle
    for zv, zk in ((30, 33), (49, 50), (70, 72)):
        nut = NutationDrive(zv, zk, math.radians(1e-3), output="nutating")
        assert nut.ratio == pytest.approx(KHVDrive(zv, zk).ratio, rel=1e-12)


def test_speeds_and_mesh_frequencies_are_consistent():
    d = DoubleNutationDrive(28, 26, 32, 30, math.radians(5))
    w = 1500 * 2 * math.pi / 60
    s = d.speeds(w)
    assert s["gear 4 (output)"] == pytest.approx(w / d.ratio, rel=1e-12)
    # tooth passing seen from the carrier is the same on both members of a mesh:
    # mesh 1: z1 |psi'| = z2 |omega_H - 0|; mesh 2: z3 |psi'| = z4 |omega_H - omega_4|
    f = d.mesh_frequencies(w)
    assert f["mesh 1 (gears 1-2)"] == pytest.approx(26 * w / (2 * math.pi), rel=1e-12)
    assert f["mesh 2 (gears 3-4)"] == pytest.approx(
        30 * abs(w - s["gear 4 (output)"]) / (2 * math.pi), rel=1e-12
    )
    k = KHVDrive(30, 33)
    assert k.mesh_frequencies(w)["mesh K-V"] == pytest.approx(
        30 * abs(k.speeds(w)["planet V relative to carrier"]) / (2 * math.pi)
    )


@settings(max_examples=60, deadline=None)
@given(st.integers(8, 150), st.integers(1, 6), st.floats(0.5, 60.0))
def test_cone_angles_and_inverse(z, dz, th_deg):
    th = math.radians(th_deg)
    di, de = internal_cone_angles(z + dz, z, th)
    assert di - de == pytest.approx(th, abs=1e-12)
    assert math.sin(di) / math.sin(de) == pytest.approx((z + dz) / z, rel=1e-12)
    sigma, ratio = nutation_angle_from_cones(di, de, "internal")
    assert sigma == pytest.approx(th, abs=1e-12) and ratio == pytest.approx((z + dz) / z)
    d1, d2 = external_cone_angles(z, z + dz, th)
    assert d1 + d2 == pytest.approx(th) and math.sin(d1) / math.sin(d2) == pytest.approx(
        z / (z + dz)
    )


def test_bad_kinematic_input():
    with pytest.raises(ReducerlabError, match="positive integer"):
        NutationDrive(0, 60, 0.1)
    with pytest.raises(ReducerlabError, match="different tooth numbers"):
        NutationDrive(60, 60, 0.1)
    with pytest.raises(ReducerlabError, match="nutation angle"):
        NutationDrive(59, 60, 0.0)
    with pytest.raises(ReducerlabError, match="contact must be"):
        NutationDrive(59, 60, 0.1, contact="side")
    with pytest.raises(ReducerlabError, match="more teeth than the planet"):
        KHVDrive(33, 30)
    with pytest.raises(ReducerlabError, match="two lobes more"):
        CycloidBallDrive(38, 39)
    with pytest.raises(ReducerlabError, match="output does not turn"):
        DoubleNutationDrive(30, 30, 30, 30, 0.1)
    with pytest.raises(ReducerlabError, match="internal gear needs more teeth"):
        internal_cone_angles(20, 30, 0.1)


# --------------------------------------------------------------------------------------
# Simulation of the motion: integrate the Euler kinematics, then check on the rotation
# matrices themselves (finite differences, independent of our velocity formulas) that
# the pitch line has zero relative velocity at every instant.


def _integrate_orientation(motion, t):
    """Integrate R' = W(t) R with W from the fixed-frame Euler velocity formulas."""

    def rhs(tt, y):
        R = y.reshape(3, 3)
        phi = motion.dphi * tt
        w = angular_velocity_fixed(phi, motion.theta, motion.dphi, 0.0, motion.dpsi)
        return (skew(w) @ R).ravel()

    R0 = euler_zxz(0.0, motion.theta, 0.0)
    sol = scipy.integrate.solve_ivp(
        rhs, (t[0], t[-1]), R0.ravel(), t_eval=t, rtol=1e-12, atol=1e-13, method="DOP853"
    )
    return sol.y.T.reshape(-1, 3, 3)


CASES = [
    NutationDrive(59, 60, math.radians(5)),
    NutationDrive(61, 60, math.radians(3)),
    NutationDrive(101, 100, math.radians(8), output="nutating"),
    NutationDrive(36, 37, math.radians(12), output="nutating"),
    NutationDrive(20, 30, math.radians(80), contact="external"),
    NutationDrive(25, 40, math.radians(90), contact="external", output="nutating"),
]


@pytest.mark.parametrize("drive", CASES, ids=lambda d: f"{d.z_nutating}-{d.z_central}-{d.output}")
def test_simulated_rolling_of_pitch_cones(drive):
    w_in = 2 * math.pi * 25.0  # 1500 rpm
    motion = drive.nutating_motion(w_in)
    w_c = drive.speeds(w_in)["central gear"]
    t = np.linspace(0.0, 2 * 2 * math.pi / w_in, 97)  # two input revolutions
    R_n = _integrate_orientation(motion, t)
    # the integrated orientation is the Euler-angle motion
    np.testing.assert_allclose(R_n, euler_zxz(*motion.angles(t)), atol=1e-9)
    # spatial angular velocities from differences of the exact rotation matrices
    h = 1e-7
    phi, th, _ = motion.angles(t)
    Rn_p, Rn_m = (euler_zxz(motion.dphi * (t + s), th, motion.dpsi * (t + s)) for s in (h, -h))
    Wn = (Rn_p - Rn_m) / (2 * h) @ np.swapaxes(R_n, 1, 2)
    Rc, Rc_p, Rc_m = (rot_z(w_c * (t + s)) for s in (0.0, h, -h))
    Wc = (Rc_p - Rc_m) / (2 * h) @ np.swapaxes(Rc, 1, 2)
    p = drive.pitch_line(phi)
    R_cone = 0.05  # 50 mm cone distance
    v_rel = ((Wn - Wc) @ (R_cone * p)[..., None])[..., 0]
    scale = w_in * R_cone  # peripheral speed scale (m/s)
    # finite-difference round-off ~ eps / h * R ~ 1e-10 m/s: zero to 1e-7 of the scale
    assert np.max(np.abs(v_rel)) < 1e-7 * scale
    # off the pitch line the relative velocity is not zero (the check can fail)
    q = np.cross(p, [0.0, 0.0, 1.0])
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    off = ((Wn - Wc) @ (R_cone * q)[..., None])[..., 0]
    assert np.min(np.linalg.norm(off, axis=-1)) > 1e-3 * scale
    # the instantaneous axis of relative rotation is the pitch line
    axis = relative_rotation_axis(unskew(Wc), unskew(Wn))
    np.testing.assert_allclose(np.abs(np.sum(axis * p, axis=-1)), 1.0, atol=1e-8)


def test_simulated_rolling_of_the_double_sided_drive():
    d = DoubleNutationDrive(28, 26, 32, 30, math.radians(5))
    w_in = 2 * math.pi * 25.0
    motion = d.nutating_motion(w_in)
    w4 = d.speeds(w_in)["gear 4 (output)"]
    cones = d.cone_angles()
    t = np.linspace(0.0, 0.08, 41)
    phi, th, _ = motion.angles(t)
    w_n = angular_velocity_fixed(phi, th, motion.dphi, 0.0, motion.dpsi)
    u = np.stack([np.sin(phi), -np.cos(phi), 0 * phi], axis=-1)
    zeta = np.array([0.0, 0.0, 1.0])
    # gears 1 and 3 are the internal members: pitch line away from b's side. Mesh 1
    # opens toward -zeta (both axes flipped), mesh 2 toward +zeta.
    p1 = -math.cos(cones["gear 2"]) * zeta + math.sin(cones["gear 2"]) * u
    p2 = math.cos(cones["gear 4"]) * zeta - math.sin(cones["gear 4"]) * u
    for p, w_c in ((p1, 0.0), (p2, w4)):
        rel = w_n - w_c * zeta
        assert np.max(np.linalg.norm(np.cross(rel, p), axis=-1)) < 1e-9 * w_in
    # cone geometry of each side matches its tooth ratio
    assert math.sin(cones["gear 1"]) / math.sin(cones["gear 2"]) == pytest.approx(28 / 26)
    assert math.sin(cones["gear 3"]) / math.sin(cones["gear 4"]) == pytest.approx(32 / 30)


def test_tooth_counts_rolled_over_one_revolution_agree():
    # rolling without slip: teeth passed on both members of a mesh are equal
    for d in CASES:
        w = 1.0
        dpsi = d.nutating_motion(w).dpsi
        w_c = d.speeds(w)["central gear"]
        turns_n = abs(dpsi) * 2 * math.pi  # spin of the nutating gear relative to carrier
        turns_c = abs(w_c - w) * 2 * math.pi  # central gear relative to carrier
        assert d.z_nutating * turns_n == pytest.approx(d.z_central * turns_c, rel=1e-12)


def test_cycloid_ball_trochoid_phase_relation():
    # Epitrochoid on the centre disc: x(t) = A e^{it} - d e^{imt}, m = z_c + 1;
    # hypotrochoid on the planetary disc: y(s) = A e^{is} + d e^{-ims}; planetary disc
    # centre at e e^{i phi}, not rotating; centre disc turned by alpha. Balls sit where
    # both grooves meet with s = t + alpha, which needs alpha = -2 (phi - phi0) / z_c:
    # the derived ratio -z_c / 2 = z_c / (z_c - z_p).
    zc, zp = 38, 40
    drive = CycloidBallDrive(zc, zp)
    m, rho = zc + 1, 1.25e-3
    A, e, d = m * rho, 2 * rho, 1.8 * rho
    phi0 = math.pi
    for phi in np.linspace(0.0, 2 * math.pi, 9):
        alpha = (phi - phi0) / drive.ratio
        # the phase condition of the derivation: -2 d cos(.) e^{-i z_c alpha / 2} = e e^{i phi}
        # holds for real cos values when e^{-i z_c alpha/2} = -e^{i phi} e^{i k pi}
        phase = np.exp(-1j * zc * alpha / 2) / (-np.exp(1j * phi))
        assert abs(phase.imag) < 1e-9
        sign = phase.real
        x0 = np.arccos(np.clip(sign * e / (2 * d), -1, 1))
        k = np.arange(m)
        balls = []
        for branch in (x0, -x0):
            tt = (branch - (m + 1) * alpha / 2 + 2 * np.pi * k) / m
            B = np.exp(1j * alpha) * (A * np.exp(1j * tt) - d * np.exp(1j * m * tt))
            # on the planetary disc's hypotrochoid at s = t + alpha:
            s = tt + alpha
            Y = e * np.exp(1j * phi) + A * np.exp(1j * s) + d * np.exp(-1j * m * s)
            np.testing.assert_allclose(B, Y, atol=1e-15)
            balls.append(B)
        assert np.unique(np.round(np.concatenate(balls), 12)).size == 2 * m  # 2 x 39 crossings
    # a wrong ratio breaks the phase condition (the test can fail)
    alpha = (0.3 - phi0) / (2 * drive.ratio)
    phase = np.exp(-1j * zc * alpha / 2) / (-np.exp(1j * 0.3))
    assert abs(phase.imag) > 1e-3


@pytest.mark.parametrize("theta_deg", [5.0, 175.0])
def test_paper_002_printed_ratio_violates_rolling(theta_deg):
    # Paper 002: omega_1H = omega_H / (1 - (N_f/N_n) cos th), i = N_f / (N_n - N_f cos th).
    # Rolling without slip needs equal teeth passed on both gears relative to the
    # carrier: N_n |psi'| = N_f |omega_1 - omega_H|. The printed pair breaks it for
    # either reading of th (th or pi - th); ours satisfies it (docs/assumptions.md).
    nf, nn, th, w = 60, 59, math.radians(theta_deg), 1.0
    spin = w / (1 - nf / nn * math.cos(th))
    out = w * (nn - nf * math.cos(th)) / nf
    assert abs(nn * spin - nf * abs(out - w)) > 0.1 * nn * abs(spin)
    ours = NutationDrive(nn, nf, math.radians(5.0))
    s = ours.speeds(w)
    assert nn * abs(s["nutating gear: spin psi'"]) == pytest.approx(
        nf * abs(s["central gear"] - w), rel=1e-12
    )
