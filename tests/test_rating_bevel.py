"""Bevel pairs rated on their virtual cylindrical gears (ISO 10300-1:2014 virtual gears,
ISO 6336-2/-3:2019 method B): limits and relations that the virtual gears must keep.

* ISO 10300-1: for a shaft angle of 90 deg the virtual pair's ratio is ``u_v = u^2``
  (``d_v = d_m / cos(delta)``, ``tan(delta_1) = 1 / u``).
* As the pitch cones flatten (``delta -> 0``) a bevel gear becomes a cylindrical gear: a
  straight bevel pair then rates exactly as the spur pair of the same teeth (external)
  or as the internal spur pair (internal), through independent code paths
  (``rate_spur_pair`` builds the generated SpurGear teeth, ``rate_internal_pair`` the
  InternalGearPair).
"""

from __future__ import annotations

import math

import pytest

from reducerlab.analysis.rating import load_capacity
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.geometry.internal_pair import InternalGearPair
from reducerlab.geometry.spur import SpurGear, SpurPair
from reducerlab.rating.bevel import rate_bevel_pair, virtual_pair
from reducerlab.rating.cylindrical import rate_internal_pair, rate_spur_pair

M, B, A = 0.003, 0.02, math.radians(20.0)
FLAT = 1e-7  # rad: a pitch cone this flat is a cylinder to 1e-14 (1 - cos)


def test_ratio_of_the_virtual_pair_at_ninety_degrees():
    u = 2.5
    d1 = math.atan(1 / u)
    v = virtual_pair(
        teeth=(20, 50), mean_radii=(0.03, 0.075), cone_angles=(d1, math.pi / 2 - d1),
        normal_module=M, spiral_angle=0.0, pressure_angle=A, internal=False,
    )  # fmt: skip
    assert v["d_v2"] / v["d_v1"] == pytest.approx(u**2, rel=1e-12)
    assert v["z_v2"] / v["z_v1"] == pytest.approx(u**2, rel=1e-12)


@pytest.mark.parametrize("internal", [False, True])
def test_flat_cones_rate_as_the_cylindrical_pair(internal):
    # 30 in 80 internal: a feasible unshifted internal pair with eps_alpha = 1.94 < 2
    z1, z2 = (30, 80) if internal else (20, 40)
    common = dict(
        teeth=(z1, z2), mean_radii=(M * z1 / 2, M * z2 / 2), cone_angles=(FLAT, FLAT),
        normal_module=M, spiral_angle=0.0, pressure_angle=A, face_width=B, torque=80.0,
        speed=150.0, internal=internal, method="iso6336",
    )  # fmt: skip
    bevel = rate_bevel_pair(**common)
    if internal:
        ref = rate_internal_pair(InternalGearPair(z1, z2, M, 0.0, 0.0, face_width=B), 80.0, 150.0)
    else:
        ref = rate_spur_pair(SpurPair(SpurGear(z1, M, B), SpurGear(z2, M, B)), 80.0, 150.0)
    # the same equations on the same numbers: agreement to rounding
    for k in range(2):
        assert bevel.S_H[k] == pytest.approx(ref.S_H[k], rel=1e-12)
        assert bevel.S_F[k] == pytest.approx(ref.S_F[k], rel=1e-12)
    for sym in ("Y_F", "Y_S", "h_Fe", "s_Fn", "rho_F"):
        for g in ("1", "2"):
            assert bevel.value(sym, g) == pytest.approx(ref.value(sym, g), rel=1e-12)
    assert "not ISO 10300 method B1" in bevel.standard


def test_outside_the_scope_of_iso_10300_refused():
    # ISO 10300-2:2014 scope: virtual transverse contact ratio below 2 (the internal
    # 20 in 40 pair has 2.15)
    with pytest.raises(ReducerlabError, match="ISO 10300-2:2023 scope"):
        rate_bevel_pair(
            teeth=(20, 40), mean_radii=(M * 10, M * 20), cone_angles=(FLAT, FLAT),
            normal_module=M, spiral_angle=0.0, pressure_angle=A, face_width=B, torque=80.0,
            speed=150.0, internal=True,
        )  # fmt: skip


def test_nutation_design_rated_and_double_arc_refused():
    d = load_design(example_dir() / "nutation_surface.toml")
    r = load_capacity(d)
    p = r.pairs()["pair 1"]
    assert p["gears"] == ["gear 2", "gear 1"]
    # the torque flow's 1942 N on the external gear's mean radius (mesh1's force)
    assert r.value("F_mt") == pytest.approx(55.714285714 / 0.0286878, rel=1e-9)
    assert "method B1" in p["standard"] and "internal virtual pair" in p["standard"]
    # eps_vbeta = 0.57 < 1: no load sharing credited (docs/assumptions.md)
    assert r.value("Z_LS") == 1.0 and r.value("Y_LS") == 1.0
    assert r.value("K_Hbeta") == pytest.approx(1.5 * 1.05)
    assert all(s > 1 for s in p["S_H"] + p["S_F"])
    arcs = d.with_values({"surface.profile": "double-arc"})
    with pytest.raises(ReducerlabError, match=r"surface\.profile: .*method A"):
        load_capacity(arcs, method="B")  # method A (the default "auto"): test_rating_ltca
    # a torque on the input shaft: the flow's output is i times it
    half = load_capacity(d, torque=60.0 / abs(d.kinematics().ratio) / 2)
    assert half.value("F_mt") == pytest.approx(r.value("F_mt") / 2, rel=1e-9)


def test_rating_limits_are_no_input_of_the_body_and_contact_results():
    # sigma_Hlim, sigma_Flim and the treatment do not change a gear body's modes or the
    # loaded contact: cached results stay valid when only the limits change
    import json

    from reducerlab.inputs import inputs_of

    d = load_design(example_dir() / "nutation_surface.toml")
    dump = json.loads(d.provenance["design"])
    for kind, attrs in (("body-modal", {"gear": 1}), ("contact", {"pair": 1})):
        rec = inputs_of(kind, dump, attrs)
        assert "material.youngs_modulus" in rec and "material.density" in rec
        assert not any(k.startswith(("material.sigma", "material.treatment")) for k in rec)


@pytest.mark.parametrize("internal", [False, True])
def test_mid_zone_factor_is_the_curvature_ratio_of_pitch_and_mid_point(internal):
    # Z_M-B = sqrt(rho_rel(C) / rho_rel(M)) on the transverse line of action, with M the
    # middle of the path of contact for eps_vbeta >= 1 (F_1 = F_2 = eps_va): the roll
    # distances rho_i from the tangency points T_i, rho_2 - rho_1 = T_1T_2 (internal) or
    # rho_1 + rho_2 = T_1T_2 (external), built here from the tip circles directly
    from reducerlab.rating import iso10300_1 as p1
    from reducerlab.rating import iso10300_2 as p2

    z = (30, 70)
    dl = (math.radians(12.0), math.radians(28.0))
    dm = (M * z[0] / math.cos(math.radians(30)), M * z[1] / math.cos(math.radians(30)))
    v = p1.virtual_gears(
        teeth=z, mean_diameters=dm, cone_angles=dl, normal_module=M,
        spiral_angle=math.radians(30.0), pressure_angle=A, addenda=(M, M), face_width=0.04,
        effective_face_width=0.034, internal=internal,
    )  # fmt: skip
    assert v.eps_vb >= 1.0
    rb = (v.d_vb[0] / 2, v.d_vb[1] / 2)
    ta = math.tan(v.alpha_vet)
    r1e = math.sqrt(v.d_va[0] ** 2 - v.d_vb[0] ** 2) / 2  # gear 1's tip contact
    r2a = math.sqrt(v.d_va[1] ** 2 - v.d_vb[1] ** 2) / 2  # gear 2's tip contact
    if internal:
        t12 = (rb[1] - rb[0]) * ta
        r1m = (r1e + (r2a - t12)) / 2
        r2m = r1m + t12
    else:
        t12 = (rb[0] + rb[1]) * ta
        r1m = (r1e + (t12 - r2a)) / 2
        r2m = t12 - r1m
    ratio = (rb[0] * ta * rb[1] * ta) / (r1m * r2m)
    assert p2.mid_zone_factor(v) == pytest.approx(math.sqrt(ratio), rel=1e-12)
    # the curvature: 1/rho_t = cos^2(beta) / sin(alpha_e) * 2 (1/d_v1 -+ 1/d_v2)
    rho_t, _, _ = p1.relative_curvature(
        mean_diameters=dm, cone_angles=dl, spiral_angle=math.radians(30.0),
        pressure_angle=A, internal=internal,
    )  # fmt: skip
    s = -1 if internal else 1
    inv = math.cos(math.radians(30.0)) ** 2 / math.sin(A) * 2 * (1 / v.d_v[0] + s / v.d_v[1])
    assert rho_t == pytest.approx(1 / inv, rel=1e-12)


def test_narrow_face_middle_contact_line_spans_the_face():
    # eps_vbeta < 1 (the nutation examples): the middle contact line crosses the
    # effective face before it crosses the path of contact; its length is the face's
    # b_v,eff / cos(beta_vb) shortened by C_lb (docs/assumptions.md), and Z_LS = 1
    from reducerlab.rating import iso10300_1 as p1
    from reducerlab.rating import iso10300_2 as p2

    v = p1.virtual_gears(
        teeth=(40, 44), mean_diameters=(0.08, 0.088), cone_angles=(0.3, 0.33),
        normal_module=M, spiral_angle=math.radians(25.0), pressure_angle=A, addenda=(M, M),
        face_width=5 * M, effective_face_width=0.85 * 5 * M, internal=True,
    )  # fmt: skip
    assert v.eps_vb < 1.0
    k = 1 - math.sqrt(0.85)
    assert v.b_v_eff / math.cos(v.beta_vb) < v.g_va / math.sin(v.beta_vb)
    assert p1.contact_line_length(v, 0.0) == pytest.approx(
        v.b_v_eff / math.cos(v.beta_vb) * (1 - k), rel=1e-12
    )
    assert p2.load_sharing_factor(v) == 1.0
    with pytest.raises(ReducerlabError, match="eps_vbeta"):
        p1.contact_line_positions(v)


def test_bevel_method_and_mounting_checked():
    common = dict(
        teeth=(30, 80), mean_radii=(M * 15, M * 40), cone_angles=(0.2, 0.5),
        normal_module=M, spiral_angle=0.3, pressure_angle=A, face_width=B, torque=80.0,
        speed=150.0, internal=False,
    )  # fmt: skip
    with pytest.raises(ReducerlabError, match="method: one of B1, iso6336"):
        rate_bevel_pair(**common, method="B2")
    with pytest.raises(ReducerlabError, match="mounting: one of"):
        rate_bevel_pair(**common, mounting="floating")
    with pytest.raises(ReducerlabError, match="verification: one of"):
        rate_bevel_pair(**common, verification="none")
    r = rate_bevel_pair(**common)
    assert r.standard.startswith("ISO 10300-1/-2/-3:2023 method B1")
    # the B1 rows carry their clauses; K_Hbeta-C = 1.5 K_Hbeta-be
    assert r.value("K_Hbeta") == pytest.approx(1.5 * r.value("K_Hbeta-be"))
    for sym in ("Z_M-B", "Z_LS", "Z_KP", "Y_BS", "Y_LS", "Y_eps", "l_bm", "rho_rel"):
        assert any(f.symbol == sym and "ISO 10300" in f.clause for f in r.factors), sym


def test_nutation_face_load_factor_is_no_input():
    from reducerlab.rating.material import RatingConditions

    d = load_design(example_dir() / "nutation_surface.toml")
    with pytest.raises(ReducerlabError, match=r"K_Hbeta .*K_Hbeta-C"):
        load_capacity(d, conditions=RatingConditions(K_Hbeta=1.3))


def test_dynamic_factor_joins_its_sectors():
    # ISO 10300-1 K_v-B: the intermediate sector (Eq. 20) interpolates between the main
    # resonance value at N = 1.25 and the supercritical one at N = 1.5, so K_v is
    # continuous there; below N = 0.75 it grows linearly from 1 (Eq. 15)
    from reducerlab.rating import iso10300_1 as p1

    dm = (0.055, 0.153)
    args = dict(
        pinion_teeth=14, mean_diameters=dm, normal_pressure_angle=A, force=1e4, K_A=1.1,
        face_width=0.0254, pitch_deviation=26e-6, eps_vg=2.39,
    )  # fmt: skip
    m1, m2 = (math.pi * 7860.0 * d**2 / (8 * math.cos(A) ** 2) for d in dm)
    w_e = math.sqrt(20e9 / (m1 * m2 / (m1 + m2))) / 14  # N = 1 (C_F = 1 at this load)

    def kv(n):
        return p1.dynamic_factor(speed=n * w_e, **args)

    eps = 1e-9
    assert kv(1.25 - eps) == pytest.approx(kv(1.25 + eps), abs=1e-7)
    assert kv(1.5 - eps) == pytest.approx(kv(1.5 + eps), abs=1e-7)
    assert kv(0.5) - 1 == pytest.approx(2 * (kv(0.25) - 1), rel=1e-12)
