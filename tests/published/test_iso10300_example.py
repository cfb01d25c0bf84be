"""ISO/TR 10300-30:2024 Annex A, sample 1: a spiral bevel pair without offset rated by
ISO 10300-1/-2/-3:2023 method B1.

Source: ISO/TR 10300-30:2024 "Calculation of load capacity of bevel gears - Part 30:
ISO rating system for bevel and hypoid gears - Sample calculations", Annex A "Sample 1"
(z = 14/39, Sigma = 90 deg, m_mn = 3.213 mm, beta_m = 35 deg, b = 25.4 mm, T_1 = 300 N m
at 1200 1/min, K_A = 1.1, case-hardened steel, method B1). The TR itself could not be
consulted here: inputs and printed values are those transcribed in the self-test
``Calc/SelfTest.cs`` (``RunSample1Check``) of a public ISO10300Calc C# project, which
names the TR's tables; the digits below are exactly those printed there. Only the
equations of the standard were taken from that project (our code is our own).

Each check is to half a unit of the last printed digit, except where noted at the line:
a few values are not reproduced to their last digit (the sources of the gaps, where
known, are named there). The TR gives ``Z_NT = 1`` for pitting directly (no life
requirement) and ``Y_NT = 1`` (3e6 cycles): both are passed explicitly. Hypoid offset is
not supported (refused); samples 2 and 3 (hypoid) are not checked. The transcription
notes printed errors in them (sample 2's ``K*_Halpha`` cell, sample 3's ``x_2``/``l_bm``
and ``K_v-B`` cells), none of which touch sample 1.
"""

from __future__ import annotations

import math

import pytest

from reducerlab.errors import ReducerlabError
from reducerlab.rating import iso6336_2 as q2
from reducerlab.rating import iso6336_3 as q3
from reducerlab.rating import iso10300_1 as p1
from reducerlab.rating import iso10300_2 as p2
from reducerlab.rating import iso10300_3 as p3

MM, DEG, MPA = 1e-3, math.radians(1.0), 1e6
Z = (14, 39)
T1, N1 = 300.0, 1200.0  # N m, 1/min
DM = (54.918 * MM, 152.987 * MM)
# Sigma = 90 deg: tan(delta_1) = z_1 / z_2 (the printed 19.747 / 70.253 deg to their
# digits; the TR's virtual gears follow from the exact angles, not the rounded ones)
DELTA = (math.atan(Z[0] / Z[1]), math.atan(Z[1] / Z[0]))
B, BETA, ALPHA = 25.4 * MM, 35.0 * DEG, 20.0 * DEG
# the printed m_mn = 3.213 mm is d_m1 cos(beta_m) / z_1 = 3.21327 mm rounded: the TR's
# intermediate values carry the unrounded one (d_vn1 = z_vn1 m_mn = 82.241 mm needs it)
MMN = DM[0] * math.cos(BETA) / Z[0]
HAM, HFM = (4.837 * MM, 1.590 * MM), (2.393 * MM, 5.640 * MM)
XHM, XSM, RHO_A0 = (0.505, -0.505), (0.036, -0.055), (0.8 * MM, 1.2 * MM)
K_A, FPT2, RHO = 1.1, 26e-6, 7860.0  # -, m (the wheel's f_pt), kg/m^3
E, NU = 210e9, 0.3
NU40, RZ_FLANK, RZ_ROOT = 150e-6, 8e-6, 16e-6  # m^2/s, m, m
SIGMA_HLIM, SIGMA_FLIM = 1500 * MPA, 480 * MPA
# d_m1 = 54.918 mm is printed to 5 digits (+-9.1e-6 relative) and the TR computes with
# its unrounded value (F_mt1 = 10925.3 N needs d_m1 = 54.9186 mm): every check allows
# this 1e-5 relative on top of half a unit of the last printed digit
INPUT_ROUNDING = 1e-5
# factors the TR prints rounded and that the downstream equations are checked with
PRINTED_ZLS, PRINTED_YLS = 0.935, 0.873


def _chain(Z_LS=None, Y_LS=None):
    """Sample 1 from its inputs; ``Z_LS``, ``Y_LS`` replace the computed values when
    given."""
    v = p1.virtual_gears(
        teeth=Z, mean_diameters=DM, cone_angles=DELTA, normal_module=MMN, spiral_angle=BETA,
        pressure_angle=ALPHA, addenda=HAM, face_width=B, effective_face_width=0.85 * B,
    )  # fmt: skip
    o = {"v": v}
    o["rho_t"], o["beta_B"], o["rho_rel"] = p1.relative_curvature(
        mean_diameters=DM, cone_angles=DELTA, spiral_angle=BETA, pressure_angle=ALPHA
    )
    o["l_bm"] = p1.contact_line_length(v, 0.0)
    f_mt1 = o["Fmt1"] = 2 * T1 / DM[0]
    w1 = N1 * 2 * math.pi / 60
    o["Kv"] = p1.dynamic_factor(
        speed=w1, pinion_teeth=Z[0], mean_diameters=DM, normal_pressure_angle=ALPHA,
        force=f_mt1, K_A=K_A, face_width=v.b_v, pitch_deviation=FPT2, eps_vg=v.eps_vg,
        density=RHO,
    )  # fmt: skip
    kv = o["Kv"]
    o["KHbeta_be"], o["KHbeta"] = p1.face_load_factor("one-cantilever", "light-load-test")
    # cutter radius 114.3 mm > R_m2 = 81.3 mm: K_F0 = 1 (Eq. 33)
    rm2 = DM[1] / (2 * math.sin(DELTA[1]))
    o["KF0"] = p1.lengthwise_curvature_factor(
        spiral_angle=BETA, cutter_radius=114.3 * MM, mean_cone_distance=rm2
    )
    o["KHalpha"] = p1.transverse_load_factor(
        force=f_mt1, K_A=K_A, K_v=kv, K_Hbeta=o["KHbeta"], face_width=v.b_v,
        effective_face_width=v.b_v_eff, pitch_deviation=FPT2, eps_vg=v.eps_vg,
    )  # fmt: skip
    o["ZMB"] = p2.mid_zone_factor(v)
    o["ZLS"] = p2.load_sharing_factor(v, "low")
    zls = o["ZLS"] if Z_LS is None else Z_LS
    o["ZE"] = q2.elasticity_factor(E, NU, E, NU)
    v_mt = w1 * DM[0] / 2
    o["ZL"], o["Zv"] = q2.lubrication_factors(SIGMA_HLIM, NU40, v_mt)
    o["ZR"] = q2.roughness_factor(SIGMA_HLIM, RZ_FLANK, o["rho_rel"])
    o["Fn"] = p2.normal_force(f_mt1, ALPHA, BETA)
    o["sigmaH0"] = p2.contact_stress_nominal(
        normal_force=o["Fn"], l_bm=o["l_bm"], rho_rel=o["rho_rel"], Z_MB=o["ZMB"], Z_LS=zls,
        Z_E=o["ZE"],
    )  # fmt: skip
    k_ha = o["KHalpha"]
    o["sigmaH"] = o["sigmaH0"] * math.sqrt(K_A * kv * o["KHbeta"] * k_ha)
    z_nt = 1.0  # printed directly by the TR
    o["sigmaHP1"] = SIGMA_HLIM * z_nt * o["ZL"] * o["Zv"] * o["ZR"] * p2.BEVEL_FACTOR
    o["SH1"] = o["sigmaHP1"] / o["sigmaH"]
    # ---- bending
    o["YLS"] = zls**2 if Y_LS is None else Y_LS
    o["Yeps"] = p3.contact_ratio_factor(v.eps_va, v.eps_vb)
    o["YBS"] = p3.spiral_angle_factor(
        face_width=v.b_v, spiral_angle=BETA, beta_vb=v.beta_vb, l_bm=o["l_bm"],
        depths=sum(HAM) + sum(HFM),
    )  # fmt: skip
    o["YRrelT"] = q3.roughness_factor_root(RZ_ROOT)
    y_x = q3.size_factor_root(MMN)
    y_nt = q3.life_factor(3e6)
    k_fb = o["KHbeta"] / o["KF0"]
    for k, g in enumerate(("1", "2")):
        f = p3.tooth_form(
            normal_module=MMN, teeth_normal=v.z_vn[k], tip_diameter_normal=v.d_van[k],
            base_diameter_normal=v.d_vbn[k], tool_addendum=1.25 * MMN,
            tool_tip_radius=RHO_A0[k], profile_shift=XHM[k], thickness_modification=XSM[k],
            pressure_angle=ALPHA,
        )  # fmt: skip
        o["form" + g] = f
        o["Ydelta" + g] = q3.notch_sensitivity_factor(f.q_s)
        sf0 = p3.root_stress_nominal(
            force=f_mt1, face_width=v.b_v, normal_module=MMN, form=f,
            factors=o["Yeps"] * o["YBS"] * o["YLS"],
        )  # fmt: skip
        o["sigmaF0" + g] = sf0
        o["sigmaF" + g] = sf0 * K_A * kv * k_fb * k_ha
        o["sigmaFP" + g] = SIGMA_FLIM * 2.0 * y_nt * o["Ydelta" + g] * o["YRrelT"] * y_x
        o["SF" + g] = o["sigmaFP" + g] / o["sigmaF" + g]
    return o


@pytest.fixture(scope="module")
def s1():
    return _chain()


@pytest.fixture(scope="module")
def s1_printed_factors():
    """The chain with the TR's printed ``Z_LS`` and ``Y_LS`` (see ``test_zls`` for why
    they are not reproduced to their last digit)."""
    return _chain(Z_LS=PRINTED_ZLS, Y_LS=PRINTED_YLS)


def _check(value: float, printed: str, tol: float | None = None) -> None:
    decimals = len(printed.split(".")[1]) if "." in printed else 0
    t = 0.5 * 10.0**-decimals + INPUT_ROUNDING * abs(float(printed)) if tol is None else tol
    assert value == pytest.approx(float(printed), abs=t), (value, printed)


def _get(o, key):
    v = o["v"]
    table = {
        "dv1": v.d_v[0] / MM, "dv2": v.d_v[1] / MM, "betav": v.beta_v / DEG,
        "alphavet": v.alpha_vet / DEG, "mvt": v.m_vt / MM, "zv1": v.z_v[0], "zv2": v.z_v[1],
        "betavb": v.beta_vb / DEG, "dva1": v.d_va[0] / MM, "dva2": v.d_va[1] / MM,
        "dvb1": v.d_vb[0] / MM, "dvb2": v.d_vb[1] / MM, "pvet": v.p_vet / MM,
        "gva": v.g_va / MM, "eps_va": v.eps_va, "bv_eff": v.b_v_eff / MM, "bv": v.b_v / MM,
        "eps_vb": v.eps_vb, "eps_vg": v.eps_vg, "zvn1": v.z_vn[0], "zvn2": v.z_vn[1],
        "dvn1": v.d_vn[0] / MM, "dvan1": v.d_van[0] / MM, "dvbn1": v.d_vbn[0] / MM,
        "rho_t": o["rho_t"] / MM, "betaB": o["beta_B"] / DEG, "rho_rel": o["rho_rel"] / MM,
        "lbm": o["l_bm"] / MM, "Fn": o["Fn"],
    }  # fmt: skip
    if key in table:
        return table[key]
    if key.startswith("form"):
        g, attr = key[4], key[6:]
        val = getattr(o["form" + g], attr)
        if attr in ("E", "s_Fn", "rho_F", "h_Fa"):
            return val / MM
        return val / DEG if attr in ("theta", "alpha_Fan") else val
    val = o[key]
    return val / MPA if key.startswith("sigma") else (val / MPA**0.5 if key == "ZE" else val)


# (key, printed value): to half a unit of the last printed digit
EXACT = [
    ("dv1", "58.350"), ("dv2", "452.804"), ("betav", "35.0"), ("alphavet", "23.957"),
    ("mvt", "3.923"), ("zv1", "14.875"), ("zv2", "115.431"), ("betavb", "32.615"),
    ("dva1", "68.023"), ("dva2", "455.984"), ("dvb1", "53.323"), ("dvb2", "413.796"),
    ("pvet", "11.262"), ("gva", "13.120"), ("eps_va", "1.165"), ("bv_eff", "21.590"),
    ("bv", "25.400"), ("eps_vb", "1.227"), ("eps_vg", "2.392"), ("rho_t", "13.173"),
    ("betaB", "13.468"), ("rho_rel", "12.459"), ("zvn1", "25.594"), ("zvn2", "198.613"),
    ("dvn1", "82.241"), ("dvan1", "91.915"), ("dvbn1", "77.281"), ("Fmt1", "10925.3"),
    ("Kv", "1.020"), ("KHbeta", "1.650"), ("KF0", "1.000"), ("KHalpha", "1.161"),
    ("ZMB", "0.916"), ("ZE", "191.646"), ("ZL", "0.992"), ("Zv", "0.974"), ("ZR", "0.930"),
    ("Fn", "14193.3"), ("Yeps", "0.625"), ("YBS", "1.054"), ("YRrelT", "0.972"),
    ("form1_G", "-0.496"), ("form1_H", "-0.934"), ("form1_theta", "50.783"),
    ("form1_rho_F", "1.023"),
    ("form2_q_s", "2.166"), ("Ydelta1", "1.010"), ("sigmaFP1", "942.0"),
    ("sigmaFP2", "929.8"),
]  # fmt: skip


@pytest.mark.parametrize(("key", "printed"), EXACT, ids=[k for k, _ in EXACT])
def test_printed_value(s1, key, printed):
    _check(_get(s1, key), printed)


# The tooth forms: s_Fn, alpha_Fan, h_Fa, Y_Fa, Y_Sa, q_s come out 0.01 % to 0.1 % off
# the printed digits while G, H, theta, rho_F agree to every digit: the TR
# evidently carried rounded intermediate values (the largest gap is the pinion's Y_Fa,
# 0.10 %). Tolerance 0.15 % relative. Its E = 0.385 mm is 0.26 % below ours (0.3859 mm)
# while H, which is computed from E (Eq. 9), agrees to its digits: the printed E looks
# truncated, not rounded; tolerance 0.3 %.
FORMS = [
    ("form1_E", "0.385", 3e-3), ("form1_s_Fn", "7.423", 1.5e-3),
    ("form1_alpha_Fan", "31.534", 1.5e-3), ("form1_h_Fa", "6.405", 1.5e-3),
    ("form1_Y_Fa", "2.033", 1.5e-3), ("form1_Y_Sa", "2.022", 1.5e-3),
    ("form1_q_s", "3.630", 1.5e-3), ("form2_Y_Fa", "2.480", 1.5e-3),
    ("form2_Y_Sa", "1.706", 1.5e-3),
    # l_bm = g_va / sin(beta_vb) (1 - C_lb): 22.4433 mm against 22.442 (0.006 %), the
    # TR's g_va being 13.1199 mm against our 13.1206 (both print 13.120)
    ("lbm", "22.442", 1e-4),
]  # fmt: skip


@pytest.mark.parametrize(("key", "printed", "rel"), FORMS, ids=[k for k, *_ in FORMS])
def test_tooth_form_and_contact_line(s1, key, printed, rel):
    assert _get(s1, key) == pytest.approx(float(printed), rel=rel)


def test_zls(s1):
    # Z_LS: 0.9338 against the printed 0.935 (0.13 %): the tip and root contact lines
    # (f_t = p_vet cos(beta_vb) = 9.485 mm near f_max = 11.344 mm) are steep functions
    # of f, and the TR's value is met with f_t 0.2 % larger. Tolerance 0.15 %. Its
    # Y_LS = Z_LS^2 (Eq. 36) = 0.873 implies Z_LS in [0.9341, 0.9346], not 0.935: the TR
    # is not consistent to its last digit here. Ours, 0.8722, is 0.1 % below; 0.15 %.
    assert s1["ZLS"] == pytest.approx(PRINTED_ZLS, rel=1.5e-3)
    assert s1["YLS"] == pytest.approx(PRINTED_YLS, rel=1.5e-3)


# With the TR's printed Z_LS and Y_LS the stresses follow to their printed digits except
# where noted: sigma_H0 (1169.1 vs 1168.5, 0.05 %) and the root stresses (0.1 %) inherit
# the 3-digit rounding of the printed Z_M-B, Z_LS, Y_Fa, Y_Sa (each +-0.05 %), so their
# tolerance is 0.15 % relative; S_H, S_F are ratios of checked values (0.2 %).
STRESSES = [
    ("sigmaH0", "1168.5", 1.5e-3), ("sigmaH", "1712.8", 1.5e-3),
    ("sigmaHP1", "1617.8", 5e-4), ("SH1", "0.944", 2e-3),
    ("sigmaF01", "316.5", 1.5e-3), ("sigmaF1", "680.1", 1.5e-3), ("SF1", "1.385", 2e-3),
    ("sigmaF02", "325.9", 1.5e-3), ("sigmaF2", "700.1", 1.5e-3), ("SF2", "1.328", 2e-3),
]  # fmt: skip


@pytest.mark.parametrize(("key", "printed", "rel"), STRESSES, ids=[k for k, *_ in STRESSES])
def test_stresses_with_printed_factors(s1_printed_factors, key, printed, rel):
    assert _get(s1_printed_factors, key) == pytest.approx(float(printed), rel=rel)


@pytest.mark.parametrize(("key", "printed", "rel"), STRESSES, ids=[k for k, *_ in STRESSES])
def test_stresses_from_the_inputs(s1, key, printed, rel):
    # the whole chain from the inputs: the Z_LS gap above (0.13 %, Y_LS 0.1 %) adds to
    # the tolerances
    assert _get(s1, key) == pytest.approx(float(printed), rel=rel + 1.5e-3)


def test_hypoid_offset_refused():
    with pytest.raises(ReducerlabError, match="offset"):
        p1.virtual_gears(
            teeth=Z, mean_diameters=DM, cone_angles=DELTA, normal_module=MMN,
            spiral_angle=BETA, pressure_angle=ALPHA, addenda=HAM, face_width=B,
            effective_face_width=0.85 * B, offset=15e-3,
        )  # fmt: skip
