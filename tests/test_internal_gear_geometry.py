"""Internal gear pair geometry (paper 004's KHV): involute relations, contact ratio by an
independent construction of the path of contact, interference conditions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reducerlab.errors import ReducerlabError
from reducerlab.geometry import InternalGearPair, inv, inv_inverse

M = 3.5e-3


def test_involute_function_and_inverse():
    assert inv(math.radians(20)) == pytest.approx(0.014904383867336446, rel=1e-14)
    for a in np.linspace(0.01, 1.3, 50):
        assert inv_inverse(inv(a)) == pytest.approx(a, rel=1e-12)
    with pytest.raises(ReducerlabError):
        inv_inverse(-1.0)


def test_zero_shift_is_the_standard_centre_distance():
    g = InternalGearPair(30, 33, M, 0.0, 0.0, addendum=0.8)
    assert g.working_pressure_angle == pytest.approx(math.radians(20), abs=1e-12)
    assert g.centre_distance == pytest.approx(M * 3 / 2, rel=1e-12)
    # equal shifts keep the standard centre distance and pressure angle (x2 - x1 = 0)
    h = InternalGearPair(30, 33, M, 0.5, 0.5, addendum=0.8)
    assert h.centre_distance == pytest.approx(M * 3 / 2, rel=1e-12)
    assert h.tip_radius(1) == pytest.approx(M * 15 + M * 1.3)
    assert h.tip_radius(2) == pytest.approx(M * 16.5 - M * 0.3)


def _path_of_contact(g: InternalGearPair) -> float:
    """Length (m) of the path of contact, built from circles and a line only."""
    aw = g.working_pressure_angle
    a = g.centre_distance
    O2, O1 = np.array([0.0, 0.0]), np.array([a, 0.0])
    rb1, rb2, ra1, ra2 = g.base_radius(1), g.base_radius(2), g.tip_radius(1), g.tip_radius(2)
    n = np.array([-math.cos(aw), math.sin(aw)])  # unit normal of the line of action
    t = np.array([-n[1], n[0]])
    c = n @ O2 - rb2  # line: n . p = c, tangent to both base circles on the same side
    assert n @ O1 - c == pytest.approx(rb1, rel=1e-12)
    p0 = c * n
    s_t1, s_t2 = (O1 - p0) @ t, (O2 - p0) @ t  # tangent points
    s_p = -p0[1] / t[1]  # pitch point: on the centre line (y = 0)
    s = np.linspace(s_t1 - 40 * g.module, s_t1 + 40 * g.module, 800001)
    side = (np.sign(s - s_t1) == np.sign(s_p - s_t1)) & (np.sign(s - s_t2) == np.sign(s_p - s_t2))
    pts = p0 + s[:, None] * t
    inside_planet_tip = np.linalg.norm(pts - O1, axis=1) <= ra1
    on_ring_tooth = np.linalg.norm(pts - O2, axis=1) >= ra2
    mask = side & inside_planet_tip & on_ring_tooth
    return float(np.count_nonzero(mask) * (s[1] - s[0]))


@pytest.mark.parametrize(
    ("z1", "z2", "x1", "x2", "ha"),
    [(30, 33, 0.416, 0.601, 0.8), (30, 33, 0.835, 0.995, 0.8), (40, 44, 0.6, 0.9, 0.8),
     (30, 36, 0.3, 0.5, 1.0), (60, 62, 0.9, 1.2, 0.7)],
)  # fmt: skip
def test_contact_ratio_against_the_path_of_contact(z1, z2, x1, x2, ha):
    g = InternalGearPair(z1, z2, M, x1, x2, addendum=ha)
    eps_numeric = _path_of_contact(g) / g.base_pitch
    # grid of 80 modules / 8e5 points: 3.5e-7 m per step against a base pitch of
    # 1.03e-2 m, so counting grid points is exact to ~7e-5 in eps
    assert g.contact_ratio == pytest.approx(eps_numeric, abs=1e-4)


def test_paper_004_limit_points_sit_on_the_tip_overlap_boundary():
    # M(0.416, 0.601) and N(0.835, 0.995) (paper 004 Fig. 3, Table 1): our G_s is
    # 1.5e-4 and 1.6e-3 rad there, i.e. on the tip-overlap interference limit to the
    # 3 decimals the paper prints (a 0.001 change of x2 moves G_s by ~1e-2).
    for x1, x2 in ((0.416, 0.601), (0.835, 0.995)):
        g = InternalGearPair(30, 33, M, x1, x2, addendum=0.8)
        assert 0 <= g.overlap_interference() < 2e-3
        g.check()
        worse = InternalGearPair(30, 33, M, x1, x2 - 0.01, addendum=0.8)
        assert worse.overlap_interference() < 0


def test_enclosing_tip_circles_are_tip_interference():
    # z 30/31 at the example's shifts (x1 0.626 on paper 004's M-N line, x2 0.798): the
    # planet's tip circle (57.49 mm about its centre, 2.15 mm from the ring's) encloses
    # the ring's (54.24 mm): the tips overlap radially all round; the rigid drive-flank
    # scan (contact.internal_pair.tooth_pair_clearances, run before this check refused
    # the design) found planet tooth 10 inside ring tooth 10 by 66 um and tooth 11 by
    # 399 um. The G_s formula has no intersection angle there; it used to read that as
    # "the tips never meet" and passed the design.
    g = InternalGearPair(30, 31, M, 0.626, 0.7984701670644392, addendum=0.8)
    ra1, ra2, aw = g.tip_radius(1), g.tip_radius(2), g.centre_distance
    assert ra1 - aw > ra2
    assert g.overlap_interference() == pytest.approx(-(ra1 - aw - ra2) / ra2, rel=1e-12)
    with pytest.raises(ReducerlabError, match="tip overlap interference"):
        g.check()


def test_infeasible_designs_are_refused_with_the_condition_named():
    g = InternalGearPair(30, 33, M, 0.0, 0.0, addendum=0.8)  # zero shift, 3 teeth apart
    with pytest.raises(ReducerlabError, match="tip overlap interference"):
        g.check()
    # a huge planet shift makes pointed teeth
    with pytest.raises(ReducerlabError, match="pointed planet teeth"):
        InternalGearPair(30, 33, M, 2.5, 2.7, addendum=0.8).check()
    with pytest.raises(ReducerlabError, match=r"z2 \(ring\) must exceed z1"):
        InternalGearPair(33, 30, M)
    with pytest.raises(ReducerlabError, match="module must be"):
        InternalGearPair(30, 33, -1.0)


@settings(max_examples=60, deadline=None)
@given(st.integers(20, 80), st.integers(1, 6), st.floats(0.0, 1.0), st.floats(0.0, 0.6))
def test_working_pressure_angle_satisfies_the_backlash_free_condition(z1, dz, x1, dx):
    g = InternalGearPair(z1, z1 + dz, M, x1, x1 + dx, addendum=0.8)
    a, aw = g.pressure_angle, g.working_pressure_angle
    assert inv(aw) == pytest.approx(inv(a) + 2 * dx * math.tan(a) / dz, rel=1e-12)
    # centre distance times cos(aw) is the base-radius difference
    assert g.centre_distance * math.cos(aw) == pytest.approx(
        g.base_radius(2) - g.base_radius(1), rel=1e-12
    )
