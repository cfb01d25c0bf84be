"""Nutation spiral bevel gear surfaces enveloped from the crown gear (paper 001)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.geometry.bevel_surface import (
    BevelGear,
    crown_to_gear,
    generate_flank,
    generate_tooth,
    nutation_bevel_pair,
    paper001_family_point,
)
from reducerlab.geometry.profiles import DoubleCircularArcProfile, InvoluteProfile, ProfileError
from reducerlab.geometry.spiral import CrownGear
from reducerlab.kinematics.mesh import relative_velocity

M = 2e-3
BETA = math.radians(25)
# paper 000/001 drive: external gear 26 teeth, internal 28, nutation angle 5 deg
EXT, INT = nutation_bevel_pair(26, 28, math.radians(5))
PROFILES = {
    "involute": InvoluteProfile(M, math.radians(20)),
    "double_arc": DoubleCircularArcProfile(M),
}


def crown_for(profile, delta_theta=0.0):
    return CrownGear.for_gear(profile, EXT.teeth, EXT.cone_angle, BETA, 10e-3, delta_theta)


def test_pair_cone_angles_share_one_crown_gear():
    """Both gears roll on the same crown gear: z / sin(delta) is the same."""
    assert INT.cone_angle - EXT.cone_angle == pytest.approx(math.radians(5), abs=1e-14)
    assert EXT.teeth / math.sin(EXT.cone_angle) == pytest.approx(
        INT.teeth / math.sin(INT.cone_angle), rel=1e-13
    )


@pytest.mark.parametrize("gear", [EXT, INT], ids=["external", "internal"])
@pytest.mark.parametrize("name", ["involute", "double_arc"])
def test_generated_surfaces_satisfy_meshing_and_design(name, gear):
    """Meshing residual <= 1e-9 relative (the Newton iteration stops at 1e-13); grid
    normals parallel to the envelope normals (cos > 0.9999 on a 41 x 31 grid: the
    finite-difference error of the grid normal is O(h^2) ~ 1e-5); normals outward;
    pitch points on the pitch cone; thickness and spiral angle at the mean point equal to
    the design measured on the crown gear's pitch plane (rolling is an isometry, so to
    round-off and the 1e-12 spline error: 1e-9 relative). No undercut, no pointed tooth."""
    crown = crown_for(PROFILES[name], delta_theta=0.05)
    T = generate_tooth(crown, gear)
    r = T.report
    assert r.ok, r.summary()
    assert r.max_residual <= 1e-9
    assert r.normal_min_cos > 0.9999
    assert r.outward_fraction == 1.0
    assert r.pitch_cone_error < 1e-12
    assert r.thickness_measured == pytest.approx(r.thickness_design, rel=1e-9)
    assert r.spiral_angle_measured == pytest.approx(r.spiral_angle_design, abs=1e-9)
    assert not (r.undercut or r.pointed or r.self_intersecting)
    assert r.top_land > 0.2 * M
    if gear.kind == "external":
        # the basic tooth itself: its pitch-line thickness and the centreline's angle
        assert r.thickness_measured == pytest.approx(PROFILES[name].thickness, rel=1e-9)
        assert r.spiral_angle_measured == pytest.approx(BETA, abs=1e-9)
    else:
        # the space of the basic tooth: a normal pitch minus the thickness, up to the
        # curvature of the pitch cone against the crown's pitch plane (measured 1.1e-4)
        s = PROFILES[name].thickness
        assert r.thickness_measured == pytest.approx(math.pi * M - s, rel=1e-3)
    assert T.points.shape == (2, len(T.flanks[0].u), 31, 3)
    n = np.linalg.norm(T.normals, axis=-1)
    np.testing.assert_allclose(n, 1.0, atol=1e-14)


def test_envelope_points_are_the_crown_surface_moved_rigidly():
    """Each generated point is M_{i<-C}(phi_C) r_C with the named-frame composition of
    ``kinematics.rotations`` (an independent path from the vectorised formulas); its
    residual, recomputed from ``relative_velocity`` in the gear frame, vanishes; and
    phi_C agrees with the closed-form root of the crown-gear meshing equation
    (Willis: the normal meets the pitch line): tan(phi) = m_y / m_x, m = r_C x n_C."""
    prof = PROFILES["double_arc"]
    crown = crown_for(prof, 0.1)
    u = np.linspace(0.05, 0.95, 7)
    rho = np.linspace(*crown.rho_range, 5)
    for gear in (EXT, INT):
        f = generate_flank(crown, gear, u, rho, -1, 0)
        rC, nC = crown.points(u[:, None], rho[None, :], -1, 0)
        for i in range(len(u)):
            for j in range(len(rho)):
                Mt = crown_to_gear(gear, f.phi_crown[i, j])
                assert Mt.to == f"S{gear.index}" and Mt.frm == "SC"
                np.testing.assert_allclose(Mt.apply(rC[i, j]), f.points[i, j], atol=1e-15)
                n_i = gear.material_sign * Mt.apply_vector(nC[i, j])
                np.testing.assert_allclose(n_i, f.normals[i, j], atol=1e-14)
        m = np.cross(rC, nC)
        phi = np.arctan2(m[..., 1], m[..., 0])
        d = np.angle(np.exp(1j * (phi - f.phi_crown)))
        assert np.all(np.minimum(abs(d), abs(abs(d) - math.pi)) < 1e-12)
        # residual in the gear frame: v = d r_i / d phi_C from a finite difference of the
        # rigid motion (central, h = 1e-6: truncation 1e-13)
        h = 1e-6
        for i, j in [(0, 0), (3, 2), (6, 4)]:
            pc = f.phi_crown[i, j]
            v = (
                crown_to_gear(gear, pc + h).apply(rC[i, j])
                - crown_to_gear(gear, pc - h).apply(rC[i, j])
            ) / (2 * h)
            assert abs(v @ f.normals[i, j]) / np.linalg.norm(v) < 1e-8
        # rolling: no relative velocity on the pitch line +y_0 (kinematics module)
        w_c = np.array([0.0, 0.0, -1.0])
        a = crown_to_gear(gear, 0.0).rotation.T @ [0.0, 0.0, 1.0]  # gear axis in S0
        np.testing.assert_allclose(
            a, [0, math.cos(gear.cone_angle), -math.sin(gear.cone_angle)], atol=1e-15
        )
        v = relative_velocity(w_c, a / math.sin(gear.cone_angle), [0.0, 0.04, 0.0])
        np.testing.assert_allclose(v, 0, atol=1e-17)


def test_paper001_closed_form_external_matches_internal_is_a_mirror():
    """Paper 001 Eq. 7 (the family of crown surfaces in S_i) is, for the external gear
    (i = 1), exactly our rigid motion M_{1<-C} of the crown surface. For i = 2 it is not
    a rigid motion: it equals diag(1, 1, -1) M_{2<-C} applied to the opposite flank's
    crown point, a mirror image (determinant -1) of the crown tooth."""
    prof = PROFILES["involute"]
    crown = crown_for(prof, 0.1)
    rng = np.random.default_rng(3)
    u = rng.uniform(0, 1, 30)
    rho = rng.uniform(*crown.rho_range, 30)
    phc = rng.uniform(-2, 2, 30)
    for gear in (EXT, INT):
        phi_i = phc / math.sin(gear.cone_angle)
        for flank in (1, -1):
            p = prof.evaluate(u, flank)
            paper = paper001_family_point(
                gear.index,
                p.x,
                p.y,
                rho,
                BETA,
                crown.mean_cone_distance,
                gear.cone_angle,
                phi_i,
                phc,
                0.1,
            )
            rC, _ = crown.points(u, rho, flank)
            rC_other, _ = crown.points(u, rho, -flank)
            ours = np.array([crown_to_gear(gear, a).apply(r) for a, r in zip(phc, rC, strict=True)])
            other = np.array(
                [crown_to_gear(gear, a).apply(r) for a, r in zip(phc, rC_other, strict=True)]
            )
            if gear.index == 1:
                np.testing.assert_allclose(paper, ours, atol=1e-16)
            else:
                assert np.max(abs(paper - ours)) > 1e-3  # not the rigid image
                np.testing.assert_allclose(paper, other * [1, 1, -1], atol=1e-16)
    # at fixed angles, the printed i = 2 map of the symmetric tooth (both flanks) has
    # the linear part diag(1,1,-1) M_{2<-C}: determinant -1
    R = np.diag([1.0, 1.0, -1.0]) @ crown_to_gear(INT, 0.3).rotation
    assert np.linalg.det(R) == pytest.approx(-1.0, abs=1e-14)


def test_undercut_and_pointed_teeth_are_detected():
    """Few teeth on a small cone: virtual tooth number z / cos(delta) ~ 6 < 17 with
    the 20 deg rack, so the crown gear's tip folds the generated root (undercut, with a
    self-intersecting section); the top land of the same tooth stays ~0.44 m, as for a
    6-tooth spur gear (0.47 m). A long addendum (2 m) on 8 teeth gives a pointed tooth.
    A 40-tooth gear on a 60 deg cone (z_v = 80) has neither."""
    prof = InvoluteProfile(M, math.radians(20))
    g = BevelGear(6, math.radians(15))
    crown = CrownGear.for_gear(prof, 6, g.cone_angle, 0.0, 6e-3)
    # 81 profile points: the swallowtail of the fold is ~0.1 m wide, coarser grids miss it
    r = generate_tooth(crown, g, n_profile=81).report
    assert r.undercut and r.self_intersecting and not r.pointed
    assert r.undercut_u[1] < prof.pitch_parameter()  # at the root, below the pitch line
    assert r.top_land / M == pytest.approx(0.44, abs=0.05)
    assert any("undercut" in p for p in r.problems)
    long = InvoluteProfile(M, math.radians(20), addendum=2.0)
    g8 = BevelGear(8, math.radians(60))
    r = generate_tooth(CrownGear.for_gear(long, 8, g8.cone_angle, 0.0, 6e-3), g8).report
    assert r.pointed and r.top_land < 0
    g40 = BevelGear(40, math.radians(60))
    r = generate_tooth(CrownGear.for_gear(prof, 40, g40.cone_angle, BETA, 6e-3), g40).report
    assert r.ok and not r.undercut and not r.pointed and not r.self_intersecting


def test_bad_gear_inputs():
    with pytest.raises(ProfileError, match=r"gear\.cone_angle"):
        BevelGear(20, math.radians(95))
    with pytest.raises(ProfileError, match=r"gear\.kind"):
        BevelGear(20, 0.5, "planetary")
    with pytest.raises(ProfileError, match="pair"):
        nutation_bevel_pair(28, 26, math.radians(5))
    with pytest.raises(ProfileError, match="face_width"):
        CrownGear(PROFILES["involute"], BETA, 0.04, 0.05, 35.0)


def test_bad_generation_inputs_name_the_field():
    """Regression: a crown gear of another gear, non-1-D or out-of-range grids and grid
    sizes < 2 used to run (wrong teeth, NaN surfaces) or fail with numpy errors."""
    crown = crown_for(PROFILES["involute"])
    with pytest.raises(ProfileError, match=r"crown\.teeth: z_C sin\(delta\) must equal"):
        generate_tooth(crown, BevelGear(10, 0.3), n_profile=3, n_face=3)
    with pytest.raises(ProfileError, match=r"n_face: must be an integer >= 2"):
        generate_tooth(crown, EXT, n_face=1)
    with pytest.raises(ProfileError, match=r"n_profile: must be an integer >= 2"):
        generate_tooth(crown, EXT, n_profile=0)
    with pytest.raises(ProfileError, match=r"u: must be a 1-D array"):
        generate_flank(crown, EXT, 0.5, [0.04])
    with pytest.raises(ProfileError, match=r"u: must be a 1-D array"):
        generate_tooth(crown, EXT, u=[[0.1, 0.2]])
    with pytest.raises(ProfileError, match=r"rho: values must be > 0"):
        generate_flank(crown, EXT, [0.5], [-1.0, 0.04])
    with pytest.raises(ProfileError, match=r"^teeth: must be >= 1"):
        CrownGear.for_gear(PROFILES["involute"], 0, 0.8, BETA, 0.01)
