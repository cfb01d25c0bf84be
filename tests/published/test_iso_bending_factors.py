"""Tooth-root (bending) factors of ``reducerlab.rating.iso6336_3`` against a published
worked example: ISO/TR 10300-30 Sample 1 (spiral bevel pair without offset, z 14/39,
method B1).

Source: ISO/TR 10300-30, Sample 1, Part 3 (tooth root) results, as transcribed with the
example's input data in the self-test of a public ISO 10300 calculator (the C# file
``SelfTest.cs`` of an "ISO10300Calc" project; the TR itself could not be consulted
here). Why a bevel example checks ISO 6336-3: ISO 10300-3 rates the tooth root of the
virtual cylindrical gears with the same relative factors as ISO 6336-3 defines them
(``Y_deltarelT`` from the notch parameter ``q_s`` with the slip-layer thickness of
ISO 6336-3 Table 7, ``Y_RrelT`` from ``R_z``, ``Y_X``, ``Y_NT``, ``Y_ST = 2``), the
same stress correction factor equation (``Y_S`` from ``L = s_Fn / h_F`` and ``q_s``,
with ISO 10300's tip-load arm ``h_Fa``) and the same tooth form factor expression
(``6 (h_F/m) cos(alpha_F) / ((s_Fn/m)^2 cos(alpha_n))`` with ``h_Fa``, ``alpha_Fan``).
No public transcription of the bending digits of ISO/TR 6336-30 example 1 was found
(searched: the gfsReboucas/Drivetrain transcription stops at pitting; a German gear
library packages the TR's example 1 for its geometry values only).

Sample 1's data used here: case-hardened steel, ``sigma_Flim = 480 MPa``, root
roughness ``R_z = 16 um``, ``m_mn = 3.213 mm``, ``alpha_n = 20 deg``, ``N_L = 3e6``
load cycles (``Y_NT = 1``); pinion ``s_Fn = 7.423 mm``, ``rho_F = 1.023 mm``,
``h_Fa = 6.405 mm``, ``alpha_Fan = 31.534 deg`` -> printed ``q_s = 3.630``,
``Y_Sa = 2.022``, ``Y_Fa = 2.033``, ``Y_deltarelT = 1.010``, ``Y_RrelT = 0.972``,
``sigma_FP1 = 942.0 MPa``; wheel ``q_s = 2.166`` -> ``sigma_FP2 = 929.8 MPa``
(``sigma_FP = sigma_Flim Y_ST Y_NT Y_deltarelT Y_RrelT Y_X``: ISO 10300-3 prints the
permissible stress without ``S_Fmin``; ``S_F = sigma_FP / sigma_F``).

Also the 30 deg tangent construction (``theta``, ``s_Fn``, ``rho_F``) on the example's
virtual normal pinion (:func:`test_critical_section_of_sample_1_pinion`).

Not checked by any published digits (none found): ISO 6336-3's load point and bending
arm ``h_Fe`` at ``d_en`` (ISO 10300 loads the tip), ``Y_beta``, ``Y_B``, ``Y_DT``,
``K_Fbeta``, ``Y_NT`` away from 3e6 cycles, ``Y_X`` above 5 mm, ``Y_RrelT`` below 1 um
and for other materials, ``Y_deltarelT``'s slip layers of other materials.

Tolerances: half a unit of the last printed digit, plus what the rounding of the
printed inputs (half a unit of their last digit) moves the result, stated per line.
"""

from __future__ import annotations

import math

import pytest

from reducerlab.rating import iso6336_3 as p3

MN = 3.213e-3
ALPHA_N = math.radians(20.0)
SIGMA_FLIM = 480e6
RZ_ROOT = 16e-6
S_FN, RHO_F, H_FA, ALPHA_FAN = 7.423e-3, 1.023e-3, 6.405e-3, math.radians(31.534)
QS1, QS2 = 3.630, 2.166


def _sigma_fp(q_s: float) -> float:
    """ISO 6336-3:2019 Eq. 4 without S_Fmin: sigma_Flim Y_ST Y_NT Y_deltarelT Y_RrelT Y_X."""
    return (
        SIGMA_FLIM * 2.0 * p3.life_factor(3e6, "case-hardened")
        * p3.notch_sensitivity_factor(q_s) * p3.roughness_factor_root(RZ_ROOT)
        * p3.size_factor_root(MN)
    )  # fmt: skip


def test_relative_factors_of_sample_1():
    # Y_RrelT: printed 0.972 (R_z = 16 um is exact input)
    assert p3.roughness_factor_root(RZ_ROOT) == pytest.approx(0.972, abs=0.0005)
    # Y_deltarelT of the pinion: printed 1.010; q_s printed to 3 decimals moves it by
    # 1e-5 at most
    assert p3.notch_sensitivity_factor(QS1) == pytest.approx(1.010, abs=0.0005 + 1e-5)
    # Y_NT at 3e6 cycles (the knee of case-hardened steel) and Y_X at m_n <= 5 mm
    assert p3.life_factor(3e6, "case-hardened") == pytest.approx(1.0, abs=1e-12)
    assert p3.size_factor_root(MN) == 1.0


def test_permissible_root_stresses_of_sample_1():
    # sigma_FP1 printed 942.0, sigma_FP2 929.8 MPa: +-0.05 MPa (last digit) + 0.01 MPa
    # (q_s printed to 3 decimals: dY_deltarelT ~ 5e-6 per 0.0005 of q_s, x 960 MPa)
    assert _sigma_fp(QS1) == pytest.approx(942.0e6, abs=0.06e6)
    assert _sigma_fp(QS2) == pytest.approx(929.8e6, abs=0.06e6)
    # the pinion's printed q_s is s_Fn / (2 rho_F) of its printed tooth form
    q_s = S_FN / (2 * RHO_F)
    assert q_s == pytest.approx(QS1, abs=0.0005 + 0.002)


def test_stress_correction_and_form_factor_equations_of_sample_1():
    y_s, q_s = p3.stress_correction(S_FN, H_FA, RHO_F)
    # q_s = s_Fn / (2 rho_F) = 3.628 from the printed s_Fn, rho_F (each +-0.0005 mm:
    # +-0.002 on q_s); printed 3.630
    assert q_s == pytest.approx(QS1, abs=0.0005 + 0.002)
    # Y_Sa printed 2.022; the inputs' rounding moves Y_S by up to 3e-4
    assert y_s == pytest.approx(2.022, abs=0.0005 + 0.0004)
    # Y_Fa printed 2.033 (computed 2.0326); s_Fn, h_Fa to +-0.0005 mm and alpha_Fan to
    # +-0.0005 deg move Y_F by up to 2.2e-4 relative, 4.5e-4
    y_f = p3.form_factor(H_FA, S_FN, ALPHA_FAN, MN, ALPHA_N)
    assert y_f == pytest.approx(2.033, abs=0.0005 + 0.00045)


def test_critical_section_of_sample_1_pinion():
    """ISO 6336-3's 30 deg tangent construction (Eq. 11-17: E, G, H, theta, s_Fn, rho_F)
    on Sample 1's virtual normal pinion: ``z_vn = 25.594``, ``m_mn = 3.213 mm``,
    ``x_hm = 0.505``, tool ``h_fP = 1.25 m_mn``, edge radius ``rho_a0 = 0.8 mm``; printed
    ``theta = 50.783 deg``, ``s_Fn = 7.423 mm``, ``rho_F = 1.023 mm``. ISO 10300-3's
    ``E = (pi/4 - x_sm) m_mn - h_fP tan(alpha_n) + s_pr / cos(alpha_n) - (1 - sin
    alpha_n) rho_a0 / cos(alpha_n)`` carries the thickness modification ``x_sm = 0.036``
    (``s_pr = 0``), which ISO 6336-3's ``E`` (its ``x`` the generating shift) does not;
    it enters exactly as a residual undercut ``s_pr = -x_sm m_mn cos(alpha_n)`` would,
    which is how it is passed here. ``tip_diameter`` and ``contact_ratio`` (``d_van1``,
    ``eps_va``) only place ISO 6336-3's load point, not checked (ISO 10300 loads the tip).

    Tolerances: half a unit of the last printed digit plus the sum of what the rounding
    of the printed inputs (``z_vn``, ``x_hm``, ``x_sm``, ``m_mn`` to half their last
    digit) moves each value, computed by perturbing them: theta 0.0048 deg, s_Fn 0.0049
    mm (``x_sm`` to three decimals alone 0.0031 mm), rho_F 0.0005 mm.
    """
    f = p3.tooth_form(
        teeth=25.594, module=MN, pressure_angle=ALPHA_N, shift=0.505, tip_diameter=91.915e-3,
        contact_ratio=1.165, dedendum=1.25, root_fillet=0.8e-3 / MN,
        residual_undercut=-0.036 * MN * math.cos(ALPHA_N),
    )  # fmt: skip
    assert math.degrees(f.theta) == pytest.approx(50.783, abs=0.0005 + 0.0048)  # 50.7834
    assert f.s_Fn == pytest.approx(S_FN, abs=(0.0005 + 0.0049) * 1e-3)  # 7.4195 mm
    assert f.rho_F == pytest.approx(RHO_F, abs=(0.0005 + 0.0005) * 1e-3)  # 1.0228 mm
