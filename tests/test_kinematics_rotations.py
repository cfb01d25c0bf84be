"""Rotations, transforms and Euler kinematics against finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reducerlab.errors import ReducerlabError
from reducerlab.kinematics import (
    Transform,
    angular_acceleration_body,
    angular_acceleration_fixed,
    angular_velocity_body,
    angular_velocity_fixed,
    euler_zxz,
    gyroscopic_moment,
    relative_velocity,
    rot_x,
    rot_y,
    rot_z,
    skew,
    unskew,
)

angle = st.floats(-10.0, 10.0, allow_nan=False)


@settings(max_examples=100, deadline=None)
@given(angle, angle, angle)
def test_rotations_orthonormal_with_det_plus_one(a, b, c):
    for R in (rot_x(a), rot_y(b), rot_z(c), euler_zxz(a, b, c)):
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-14)
        assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)


def test_rotation_sense_is_right_handed():
    np.testing.assert_allclose(rot_z(math.pi / 2) @ [1, 0, 0], [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(rot_x(math.pi / 2) @ [0, 1, 0], [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(rot_y(math.pi / 2) @ [0, 0, 1], [1, 0, 0], atol=1e-15)


def test_vectorised_shapes():
    phi = np.linspace(0, 1, 7)
    assert euler_zxz(phi, 0.1, phi).shape == (7, 3, 3)
    assert angular_velocity_body(0.1, phi, 1.0, 0.0, 2.0).shape == (7, 3)


def test_skew_is_the_cross_product():
    w, r = np.array([0.3, -1.2, 2.0]), np.array([1.5, 0.2, -0.7])
    np.testing.assert_allclose(skew(w) @ r, np.cross(w, r))
    np.testing.assert_allclose(unskew(skew(w)), w)


def test_transforms_name_their_frames_and_compose():
    M10 = Transform.from_rotation(rot_z(0.4), to="S1", frm="S0", translation=[0.1, 0, 0])
    M21 = Transform.from_rotation(rot_x(0.3), to="S2", frm="S1")
    M20 = M21 @ M10
    assert (M20.to, M20.frm) == ("S2", "S0")
    p = np.array([0.2, -0.5, 0.9])
    np.testing.assert_allclose(M20.apply(p), M21.apply(M10.apply(p)))
    back = M20.inverse()
    assert (back.to, back.frm) == ("S0", "S2")
    np.testing.assert_allclose(back.apply(M20.apply(p)), p, atol=1e-15)
    np.testing.assert_allclose((back @ M20).matrix, np.eye(4), atol=1e-15)
    with pytest.raises(ReducerlabError, match="frame 'S0' does not match 'S2'"):
        M10 @ M21


def _fd_R(phi, theta, psi, dphi, dtheta, dpsi, t=0.0, h=1e-6):
    def R(tt):
        return euler_zxz(phi + dphi * tt, theta + dtheta * tt, psi + dpsi * tt)

    Rdot = (R(t + h) - R(t - h)) / (2 * h)
    return R(t), Rdot


@settings(max_examples=60, deadline=None)
@given(angle, st.floats(0.05, 3.0), angle, angle, angle, angle)
def test_angular_velocity_matches_finite_differences(phi, theta, psi, dphi, dtheta, dpsi):
    # spatial: W = R' R^T; body: W_b = R^T R'. Central difference h = 1e-6 s:
    # truncation ~ h^2 |w|^3 ~ 1e-9, round-off ~ eps / h ~ 1e-10 (|w| <= 10 rad/s)
    R, Rdot = _fd_R(phi, theta, psi, dphi, dtheta, dpsi)
    w_fixed = unskew(Rdot @ R.T)
    w_body = unskew(R.T @ Rdot)
    np.testing.assert_allclose(
        angular_velocity_fixed(phi, theta, dphi, dtheta, dpsi), w_fixed, atol=1e-7
    )
    np.testing.assert_allclose(
        angular_velocity_body(theta, psi, dphi, dtheta, dpsi), w_body, atol=1e-7
    )


@settings(max_examples=40, deadline=None)
@given(
    st.floats(0.05, 3.0),
    angle,
    *[st.floats(-3, 3) for _ in range(6)],
)
def test_angular_acceleration_matches_finite_differences(theta, psi, a, b, c, aa, bb, cc):
    # angles follow parabolas in time; differentiate the body angular velocity
    h = 1e-5

    def w(t):
        return angular_velocity_body(
            theta + b * t + bb * t * t / 2, psi + c * t + cc * t * t / 2,
            a + aa * t, b + bb * t, c + cc * t,
        )  # fmt: skip

    fd = (w(h) - w(-h)) / (2 * h)
    dw = angular_acceleration_body(theta, psi, a, b, c, aa, bb, cc)
    np.testing.assert_allclose(dw, fd, atol=1e-6)

    phi = 0.4

    def wf(t):
        return angular_velocity_fixed(
            phi + a * t + aa * t * t / 2, theta + b * t + bb * t * t / 2,
            a + aa * t, b + bb * t, c + cc * t,
        )  # fmt: skip

    fd = (wf(h) - wf(-h)) / (2 * h)
    dwf = angular_acceleration_fixed(phi, theta, psi, a, b, c, aa, bb, cc)
    np.testing.assert_allclose(dwf, fd, atol=1e-6)


def test_gyroscopic_moment_of_axisymmetric_steady_precession():
    # classic top: M = Omega sin(th) [J_a (psi' + Omega cos th) - J_t Omega cos th]
    # along the line of nodes (fixed frame: (cos phi, sin phi, 0))
    Jt, Ja, Om, dpsi, th, phi = 0.54197e-3, 0.9869e-3, 157.0, -146.0, math.radians(5), 0.7
    M = gyroscopic_moment((Jt, Jt, Ja), phi, th, 0.3, Om, 0.0, dpsi, frame="fixed")
    mag = Om * math.sin(th) * (Ja * (dpsi + Om * math.cos(th)) - Jt * Om * math.cos(th))
    expected = mag * np.array([math.cos(phi), math.sin(phi), 0.0])
    np.testing.assert_allclose(M, expected, rtol=1e-12, atol=1e-15 * abs(mag))


def test_gyroscopic_moment_equals_rate_of_angular_momentum():
    # general body, unsteady motion: M_fixed = d/dt (R J R^T w_fixed), by differences
    J = np.array([[2.0, 0.1, -0.05], [0.1, 1.5, 0.2], [-0.05, 0.2, 3.0]]) * 1e-3
    p0 = np.array([0.3, 0.4, -0.2])  # phi, theta, psi
    v = np.array([3.0, 0.7, -5.0])  # rates
    acc = np.array([1.0, -0.4, 2.0])

    def H(t):
        ang = p0 + v * t + acc * t * t / 2
        rate = v + acc * t
        R = euler_zxz(*ang)
        w = angular_velocity_fixed(ang[0], ang[1], *rate)
        return R @ J @ R.T @ w

    h = 1e-5
    fd = (H(h) - H(-h)) / (2 * h)
    M = gyroscopic_moment(J, *p0, *v, *acc, frame="fixed")
    np.testing.assert_allclose(M, fd, rtol=1e-7, atol=1e-12)
    with pytest.raises(ReducerlabError, match="symmetric 3x3"):
        gyroscopic_moment(np.ones((2, 2)), *p0, *v)
    with pytest.raises(ReducerlabError, match="frame must be"):
        gyroscopic_moment(J, *p0, *v, frame="space")


def test_relative_velocity_paper_002_form():
    # v12^1 = M01^T (W1 - W2) M01 r^1 equals the S0 velocity mapped back into S1
    w1 = np.array([0.0, 0.0, 1.4])
    w2 = angular_velocity_fixed(0.8, 0.1, 150.0, 0.0, -140.0)
    R01 = rot_z(0.37)
    r1 = np.array([0.03, -0.01, 0.02])
    v0 = relative_velocity(w1, w2, R01 @ r1)
    np.testing.assert_allclose(relative_velocity(w1, w2, r1, R01), R01.T @ v0, atol=1e-15)
    np.testing.assert_allclose(v0, np.cross(w1 - w2, R01 @ r1))
