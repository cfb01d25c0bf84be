"""Basic tooth profiles (paper 001) and the logarithmic spiral tooth line."""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.errors import DesignError
from reducerlab.geometry.profiles import (
    GBT12759_1991,
    CallableProfile,
    DoubleCircularArcProfile,
    InvoluteProfile,
    ProfileError,
    SplineProfile,
)
from reducerlab.geometry.spiral import LogSpiral

M = 2e-3
A20 = math.radians(20)


def inv(a):
    return np.tan(a) - a


def test_involute_profile_lies_on_the_analytic_involute():
    """Paper 001 Eq. 5 with a finite r: every flank point is on the involute of the base
    circle r_b = r cos(alpha): polar angle about the centre (-r, s/2) equals
    inv(alpha) - inv(alpha_k) with cos(alpha_k) = r_b / r_k, and the normal is tangent to
    the base circle. Tolerance 1e-12: only round-off in trigonometric functions."""
    r = 50e-3  # 25 m: the root circle (r - 1.25 m) lies above the base circle
    p = InvoluteProfile(M, A20, pitch_radius=r)
    names = p.segment_names
    k = names.index("involute")
    lo, hi = ([0.0, *p.breaks, 1.0])[k : k + 2]
    u = np.linspace(lo, hi, 200)[1:]
    rk, ang = p.involute_polar(u)
    rb = r * math.cos(A20)
    ak = np.arccos(rb / rk)
    np.testing.assert_allclose(ang, inv(A20) - inv(ak), atol=1e-12)
    q = p.evaluate(u)
    cx, cy = -r, 0.5 * p.s
    # distance from the base-circle centre to the normal line through the point
    dist = np.abs((q.x - cx) * q.ny - (q.y - cy) * q.nx)
    np.testing.assert_allclose(dist, rb, rtol=1e-12)
    # pitch point: x = 0, y = s/2 = pi m / 4, flank inclined at alpha to the x axis
    u0 = p.pitch_parameter()
    q0 = p.evaluate([u0])
    assert q0.y[0] == pytest.approx(math.pi * M / 4, rel=1e-12)
    assert math.atan2(-q0.dy[0], q0.dx[0]) == pytest.approx(A20, abs=1e-12)
    assert p.thickness == pytest.approx(math.pi * M / 2, rel=1e-12)


def test_involute_rack_limit_and_fillet():
    """r = inf is the straight basic rack y = s/2 - x tan(alpha); the ISO 53 fillet
    (0.38 m) is tangent to the flank and to the root line x = -1.25 m."""
    p = InvoluteProfile(M, A20)
    assert p.segment_names == ("root line", "fillet", "involute")
    u = np.linspace(p.breaks[-1], 1, 50)
    q = p.evaluate(u)
    np.testing.assert_allclose(q.y, math.pi * M / 4 - q.x * math.tan(A20), atol=1e-15)
    assert p.x_range() == pytest.approx((-1.25 * M, 1.0 * M), abs=1e-15)
    # tangent continuity at both joints (normals equal on both sides)
    for b in p.breaks:
        n1, n2 = p.evaluate([b - 1e-9]), p.evaluate([b + 1e-9])
        assert n1.nx[0] * n2.nx[0] + n1.ny[0] * n2.ny[0] == pytest.approx(1, abs=1e-7)
    # fillet radius from its curvature
    uf = np.linspace(p.breaks[0], p.breaks[1], 7)[1:-1]
    assert np.allclose(_curvature(p, uf), 1 / (0.38 * M), rtol=1e-5)


def _curvature(p, u, h=1e-6):
    a, b = p.evaluate(u - h), p.evaluate(u + h)
    ta = np.arctan2(a.dy, a.dx)
    tb = np.arctan2(b.dy, b.dx)
    q = p.evaluate(u)
    return np.abs(np.angle(np.exp(1j * (tb - ta)))) / (2 * h * np.hypot(q.dx, q.dy))


def test_double_circular_arc_gbt12759():
    """GB/T 12759-1991: arcs of radius 1.3 m (convex) and 1.42 m (concave); both contact
    points at h_k = 0.5451 m with the normal at the pressure angle 24 deg; tooth height
    0.9 m + 1.1 m; the transition is tangent to the convex arc."""
    p = DoubleCircularArcProfile(M)
    assert p.segment_names == ("fillet", "concave", "transition", "convex")
    edges = [0.0, *p.breaks, 1.0]
    mid = lambda k: np.linspace(edges[k], edges[k + 1], 9)[2:-2]  # noqa: E731
    assert np.allclose(_curvature(p, mid(3)), 1 / (1.3 * M), rtol=1e-5)
    assert np.allclose(_curvature(p, mid(1)), 1 / (1.42 * M), rtol=1e-5)
    assert p.x_range() == pytest.approx((-1.1 * M, 0.9 * M), abs=1e-15)
    k = GBT12759_1991
    hk_convex = k.convex_radius * math.sin(k.pressure_angle) + k.convex_centre_height
    hk_concave = k.concave_radius * math.sin(k.pressure_angle) - k.concave_centre_height
    assert hk_convex == pytest.approx(hk_concave, abs=2e-5)  # standard rounds to 1e-4
    # the flank point at height h_k on the convex arc has its normal at 24 deg
    u = np.linspace(edges[3], 1, 20001)
    q = p.evaluate(u)
    i = np.argmin(abs(q.x - hk_convex * M))
    assert math.degrees(math.atan2(q.nx[i], q.ny[i])) == pytest.approx(24, abs=0.01)
    # convex/transition joint is tangent, transition/concave is a corner (the standard's
    # transition arc, radius 0.505 m here, 0.5031 m printed)
    b = p.breaks
    n1, n2 = p.evaluate([b[2] - 1e-10]), p.evaluate([b[2] + 1e-10])
    assert n1.nx[0] * n2.nx[0] + n1.ny[0] * n2.ny[0] == pytest.approx(1, abs=1e-8)
    assert p.transition_radius / M == pytest.approx(0.5031, abs=0.003)
    assert p.fillet_radius / M == pytest.approx(0.403, abs=1e-3)


def test_double_arc_rack_against_the_standards_printed_values():
    """GB/T 12759-1991 basic rack, m_n 1.5-3 mm (values from memory of the standard's
    table, docs/tooth_surfaces.md): the derived quantities it prints follow from its
    coefficients. Tolerances: the standard prints 4 decimals (5e-5 m_n rounding, 1e-4
    allowed); angles to the second of arc, and its coefficients' rounding moves them by
    a few seconds (measured 5-6"), 15" allowed."""
    p = DoubleCircularArcProfile(M)
    k = GBT12759_1991
    a = k.pressure_angle
    # contact point height h_k* = 0.5450 (printed) on both arcs
    assert k.convex_radius * math.sin(a) + k.convex_centre_height == pytest.approx(0.5450, abs=1e-4)
    assert k.concave_radius * math.sin(a) - k.concave_centre_height == pytest.approx(
        0.5450, abs=1e-4
    )
    # convex chordal thickness at h_k: s_a* = 1.1173; backlash j* = 0.06 = concave space
    # width at h_k minus s_a*
    # (l_a*, rounded to 1e-4, enters twice: +-1e-4, plus the print's 5e-5: 1.5e-4)
    s_a = 2 * (k.convex_radius * math.cos(a) - k.convex_centre_offset)
    assert s_a == pytest.approx(1.1173, abs=1.5e-4)
    e_f = 2 * (k.concave_radius * math.cos(a) - k.concave_centre_offset)
    assert e_f - s_a == pytest.approx(0.06, abs=2e-4)  # l_a*, l_f* each twice
    # process angles delta_1 = 6 deg 20' 52", delta_2 = 9 deg 25' 31"
    d1, d2 = (math.degrees(x) * 3600 for x in p.process_angles)
    assert d1 == pytest.approx(6 * 3600 + 20 * 60 + 52, abs=15)
    assert d2 == pytest.approx(9 * 3600 + 25 * 60 + 31, abs=15)
    # the profile's own points: the convex arc ends at h_ja*, the concave at -h_jf*, the
    # flank at the tip and root heights, contact normals at 24 deg on both arcs
    b = p.breaks
    x = p.evaluate(np.array([b[1], b[2], 0.0, 1.0])).x / M
    np.testing.assert_allclose(x, [-k.transition_concave_height, k.transition_convex_height,
                                   -k.dedendum, k.addendum], atol=1e-12)  # fmt: skip
    for lo, hi, h in ((b[2], 1.0, 0.5451), (b[0], b[1], -0.5451)):
        u = np.linspace(lo, hi, 20001)
        q = p.evaluate(u)
        i = np.argmin(abs(q.x - h * M))
        assert math.degrees(math.atan2(abs(q.nx[i]), q.ny[i])) == pytest.approx(24, abs=0.01)
    # transition radius: printed 0.5031; the arc tangent to the convex end and through
    # the concave end comes out 0.5049 (0.36 % off, docs/assumptions.md)
    assert p.transition_radius / M == pytest.approx(0.5031, rel=0.005)


def test_double_arc_corners_are_the_breaks_where_the_tangent_turns():
    """Tangency of GB/T 12759's joints: fillet/concave and transition/convex tangent
    (curvature jumps only: 1/0.403 -> 1/1.42 and 1/0.505 -> 1/1.3 per m_n), the
    concave/transition joint a corner. Its turn is the angle between the transition
    arc's tangent and the concave arc's at -h_jf*, computed here from the centres
    independently of the profile code."""
    p = DoubleCircularArcProfile(M)
    assert len(p.breaks) == 3 and len(p.turns) == 3
    assert p.corners == (p.breaks[1],)  # concave -> transition only
    assert p.turns[0] < 1e-10 and p.turns[2] < 1e-10
    # curvature does jump at the tangent joints (they are breaks, not corners)
    for bk, (r0, r1) in zip((p.breaks[0], p.breaks[2]),
                            ((p.fillet_radius, 1.42 * M), (p.transition_radius, 1.3 * M)),
                            strict=True):  # fmt: skip
        c = _curvature(p, np.array([bk - 2e-3, bk + 2e-3]))
        np.testing.assert_allclose(c, [1 / r0, 1 / r1], rtol=1e-4)
    # independent turn: tangents of the two circles at the concave end P2
    k = GBT12759_1991
    F = np.array([k.concave_centre_height, math.pi / 2 + k.concave_centre_offset])
    cj = math.asin((k.concave_centre_height + k.transition_concave_height) / k.concave_radius)
    P2 = F - k.concave_radius * np.array([math.sin(cj), math.cos(cj)])
    bj = math.asin((k.transition_convex_height - k.convex_centre_height) / k.convex_radius)
    n1 = np.array([math.sin(bj), math.cos(bj)])
    P1 = np.array([k.convex_centre_height, -k.convex_centre_offset]) + k.convex_radius * n1
    C = P1 + p.transition_radius / M * n1  # transition centre, outside the tooth
    r_c, r_t = P2 - F, P2 - C  # radii to P2 of both circles
    turn = math.acos(abs(r_c @ r_t) / (np.linalg.norm(r_c) * np.linalg.norm(r_t)))
    assert p.turns[1] == pytest.approx(turn, abs=1e-9)
    assert math.degrees(p.turns[1]) == pytest.approx(46.02, abs=0.01)
    # the involute profile has no corner
    assert InvoluteProfile(M, A20).corners == ()


def test_flanks_mirror_and_normals_outward():
    p = DoubleCircularArcProfile(M)
    u = np.linspace(0, 1, 101)
    a, b = p.evaluate(u, 1), p.evaluate(u, -1)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.y, -b.y)
    # outward: moving along the normal leaves the tooth |y| < w(x) (away from y = 0)
    assert np.all(a.ny[1:] > 0) and np.all(b.ny[1:] < 0)  # u = 0: root bottom, normal +x
    assert a.nx[0] == pytest.approx(1.0)
    with pytest.raises(ProfileError, match="flank"):
        p.evaluate(u, 0)


def test_spline_and_callable_profiles_reproduce_the_rack():
    """A user profile through points of the straight rack flank (plus nothing else)
    reproduces it: a cubic spline through collinear points is the line itself."""
    x = np.linspace(-1.2 * M, M, 12)
    pts = np.c_[x, math.pi * M / 4 - x * math.tan(A20)]
    sp = SplineProfile(pts, M)
    u = np.linspace(0, 1, 77)
    q = sp.evaluate(u)
    np.testing.assert_allclose(q.y, math.pi * M / 4 - q.x * math.tan(A20), atol=1e-15)
    assert sp.thickness == pytest.approx(math.pi * M / 2, rel=1e-12)
    cp = CallableProfile(
        lambda t: (
            -1.2 * M + 2.2 * M * t,
            math.pi * M / 4 - (-1.2 * M + 2.2 * M * t) * math.tan(A20),
        ),
        M,
    )
    qc = cp.evaluate(u)
    np.testing.assert_allclose(qc.nx, math.sin(A20), atol=1e-9)
    np.testing.assert_allclose(qc.ny, math.cos(A20), atol=1e-9)


def test_bad_profiles_are_rejected():
    x = np.linspace(-M, M, 20)
    good = np.c_[x, 0.8 * M - 0.3 * x]
    # wrong flank order: tip first
    with pytest.raises(ProfileError, match="wrong flank order") as e:
        SplineProfile(good[::-1], M, name="user")
    assert "user.points" in str(e.value)
    assert isinstance(e.value, ValueError) and isinstance(e.value, DesignError)
    # flank on the wrong side of the centreline (the -1 flank given)
    with pytest.raises(ProfileError, match="y > 0"):
        SplineProfile(good * [1, -1], M)
    # a loop: the flank crosses itself
    t = np.linspace(0, 1, 40)
    loop = np.c_[
        -M + 2 * M * t + 0.6 * M * np.sin(4 * np.pi * t),
        0.8 * M + 0.5 * M * np.cos(4 * np.pi * t) - 0.2 * M * t,
    ]
    with pytest.raises(ProfileError, match="intersect itself"):
        SplineProfile(loop, M)
    # pitch line crossed more than once
    wave = np.c_[0.3 * M * np.sin(3 * np.pi * t) + 0.01 * M * t - 0.0001 * M, 0.8 * M - 0.3 * M * t]
    with pytest.raises(ProfileError, match="exactly once"):
        SplineProfile(wave, M)
    # the flank overlaps the next tooth
    with pytest.raises(ProfileError, match="half a normal pitch"):
        SplineProfile(np.c_[x, 2 * M - 0.1 * x], M)
    with pytest.raises(ProfileError, match=r"involute\.root_fillet"):
        InvoluteProfile(M, A20, root_fillet=1.2)
    with pytest.raises(ProfileError, match="pressure_angle"):
        InvoluteProfile(M, math.radians(70))
    with pytest.raises(ProfileError, match="base circle"):
        InvoluteProfile(M, A20, pitch_radius=4 * M, root_fillet=0.0)


@pytest.mark.parametrize("beta_deg", [-35.0, 0.0, 10.0, 25.0, 50.0])
def test_log_spiral_has_a_constant_spiral_angle(beta_deg):
    """The angle between the tangent (finite differences of points, not the analytic
    tangent) and the radius vector is beta at every cone distance (paper 001 Eq. 2).
    Central differences with h = 1e-6 R: error ~1e-10 rad."""
    beta = math.radians(beta_deg)
    sp = LogSpiral(beta, 40e-3, delta_theta=0.3)
    rho = np.linspace(30e-3, 50e-3, 21)
    h = 1e-6 * 40e-3
    t = sp.point(rho + h) - sp.point(rho - h)
    p = sp.point(rho)
    cross = p[:, 0] * t[:, 1] - p[:, 1] * t[:, 0]
    ang = np.arctan2(cross, np.einsum("ij,ij->i", t, p))  # signed, from radius to tangent
    np.testing.assert_allclose(ang, beta, atol=2e-9)
    # cone distance is rho; the mean point sits at polar angle -delta_theta (theta = 0)
    np.testing.assert_allclose(np.linalg.norm(p, axis=1), rho, rtol=1e-14)
    assert sp.polar_angle(40e-3) == pytest.approx(-0.3, abs=1e-15)
    # rho = R_m exp(theta cot beta) (paper 001's form)
    if beta_deg:
        th = sp.theta(rho)
        np.testing.assert_allclose(rho, 40e-3 * np.exp(th / math.tan(beta)), rtol=1e-13)


def test_bad_profile_arguments_name_the_field():
    """Regression: non-numeric arguments and user callables of the wrong shape used to
    raise bare TypeError/ValueError from numpy."""
    with pytest.raises(ProfileError, match=r"involute\.module: must be a real number"):
        InvoluteProfile("2 mm")
    with pytest.raises(ProfileError, match=r"involute\.thickness: must be a real number"):
        InvoluteProfile(M, thickness="wide")
    with pytest.raises(ProfileError, match=r"double_arc\.module: must be a real number"):
        DoubleCircularArcProfile(None)
    with pytest.raises(ProfileError, match=r"user\.func: must map an array u"):
        CallableProfile(lambda u: (u,), M, name="user")
    with pytest.raises(ProfileError, match=r"user\.derivative: must map an array u"):
        CallableProfile(lambda u: (u, u), M, derivative=lambda u: None, name="user")
