"""Bevel gears, ISO 10300-3:2023 method B1: tooth root strength.

Tooth root stress of the virtual gears in the normal section, the load at the tooth tip
(clause 6, Eq. 1 to 5)::

    sigma_F0 = F_vmt / (b_v m_mn) Y_Fa Y_Sa Y_eps Y_BS Y_LS
    sigma_F  = sigma_F0 K_A K_v K_Fbeta K_Falpha
    sigma_FG = sigma_Flim Y_ST Y_NT Y_deltarelT Y_RrelT Y_X,   S_F = sigma_FG / sigma_F

with ``Y_ST = 2`` and ``Y_LS = Z_LS^2`` (Eq. 36). The tooth form (6.4.1.2, Eq. 6 to 17)
is that of a generated external gear: :func:`tooth_form`. ``Y_Sa`` (Eq. 24 to 26),
``Y_deltarelT`` (Eq. 43 to 45), ``Y_RrelT`` (Eq. 40) and ``Y_X`` (Eq. 208) are the
equations of ISO 6336-3:2019 (:mod:`reducerlab.rating.iso6336_3`). SI units (m, rad, N,
Pa).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import ReducerlabError
from . import iso6336_3 as p63

__all__ = [
    "RootForm",
    "contact_ratio_factor",
    "root_stress_nominal",
    "spiral_angle_factor",
    "tooth_form",
]


@dataclass(frozen=True)
class RootForm:
    """Tooth form quantities of ISO 10300-3:2023 6.4.1.2 for the load at the tip (SI).

    ``E`` (m), ``G``, ``H`` (Eq. 7 to 9), ``theta`` (rad, Eq. 10), ``s_Fn``, ``rho_F``,
    ``h_Fa`` (m, Eq. 11 to 14), ``alpha_Fan`` (rad, Eq. 15), ``Y_Fa`` (Eq. 6), ``Y_Sa``
    (Eq. 24) and ``q_s = s_Fn / (2 rho_F)`` (Eq. 26); ``E``, ``G``, ``H`` and ``theta``
    are ``nan`` for an internal gear's rack form.
    """

    E: float
    G: float
    H: float
    theta: float
    s_Fn: float
    rho_F: float
    h_Fa: float
    alpha_Fan: float
    Y_Fa: float
    Y_Sa: float
    q_s: float


def _inv(a: float) -> float:
    return math.tan(a) - a


def tooth_form(
    *,
    normal_module: float,
    teeth_normal: float,
    tip_diameter_normal: float,
    base_diameter_normal: float,
    tool_addendum: float,
    tool_tip_radius: float,
    profile_shift: float,
    thickness_modification: float,
    pressure_angle: float,
    normal_pressure_angle: float | None = None,
    protuberance: float = 0.0,
) -> RootForm:
    """Tooth form factor ``Y_Fa`` and stress correction factor ``Y_Sa`` of a generated
    bevel gear, the load at the tip of its virtual gear in the normal section
    (ISO 10300-3:2023 Eq. 6 to 17, 24 to 26).

    ``E = (pi/4 - x_sm) m_mn - h_a0 tan(alpha_e) - rho_a0 (1 - sin(alpha_e)) /
    cos(alpha_e) - s_pr`` (Eq. 7), ``G = rho_a0 / m_mn - h_a0 / m_mn + x_hm`` (Eq. 8),
    ``H = 2 / z_vn (pi/2 - E / m_mn) - pi/3`` (Eq. 9), ``theta = 2 G / z_vn tan(theta) -
    H`` (Eq. 10, fixed point from pi/6), ``s_Fn = m_mn [z_vn sin(pi/3 - theta) + sqrt(3)
    (G / cos(theta) - rho_a0 / m_mn)]`` (Eq. 11), ``rho_F = rho_a0 + 2 G^2 m_mn /
    (cos(theta) (z_vn cos^2(theta) - 2 G))`` (Eq. 13), ``alpha_an = arccos(d_vbn /
    d_van)`` (Eq. 16), ``gamma_a = (pi/2 + 2 (x_hm tan(alpha_e) + x_sm)) / z_vn +
    inv(alpha_e) - inv(alpha_an)`` (Eq. 17), ``alpha_Fan = alpha_an - gamma_a`` (Eq. 15),
    ``h_Fa = m_mn / 2 [(cos(gamma_a) - sin(gamma_a) tan(alpha_Fan)) d_van / m_mn - z_vn
    cos(pi/3 - theta) - G / cos(theta) + rho_a0 / m_mn]`` (Eq. 14), ``Y_Fa = 6 (h_Fa /
    m_mn) cos(alpha_Fan) / ((s_Fn / m_mn)^2 cos(alpha_n))`` (Eq. 6).

    Parameters
    ----------
    normal_module : float
        ``m_mn`` (m).
    teeth_normal : float
        ``z_vn`` of the gear's virtual gear in the normal section.
    tip_diameter_normal, base_diameter_normal : float
        ``d_van``, ``d_vbn`` (m).
    tool_addendum, tool_tip_radius : float
        ``h_a0`` and ``rho_a0`` of the cutter (m).
    profile_shift, thickness_modification : float
        ``x_hm`` and ``x_sm``.
    pressure_angle : float
        Effective pressure angle ``alpha_e`` of the flank (rad).
    normal_pressure_angle : float or None
        ``alpha_n`` of Eq. 6 (rad); defaults to ``pressure_angle``.
    protuberance : float
        ``s_pr`` (m).
    """
    mn = float(normal_module)
    zn = float(teeth_normal)
    for name, val in (("normal_module", mn), ("teeth_normal", zn)):
        if not (math.isfinite(val) and val > 0):
            raise ReducerlabError(f"{name}: must be a finite number > 0; got {val!r}")
    ae = float(pressure_angle)
    an = ae if normal_pressure_angle is None else float(normal_pressure_angle)
    ha0, rho0 = tool_addendum, tool_tip_radius
    xh, xs = profile_shift, thickness_modification
    E = (math.pi / 4 - xs) * mn - ha0 * math.tan(ae) - rho0 * (1 - math.sin(ae)) / math.cos(ae)
    E -= protuberance
    G = rho0 / mn - ha0 / mn + xh
    H = 2 / zn * (math.pi / 2 - E / mn) - math.pi / 3
    theta = math.pi / 6
    for _ in range(200):
        new = 2 * G / zn * math.tan(theta) - H
        if abs(new - theta) < 1e-14:
            theta = new
            break
        theta = new
    else:
        raise ReducerlabError("teeth_normal: the root fillet angle iteration (Eq. 10) diverged")
    c = math.cos(theta)
    s_fn = mn * (zn * math.sin(math.pi / 3 - theta) + math.sqrt(3) * (G / c - rho0 / mn))
    rho_f = rho0 + 2 * G * G * mn / (c * (zn * c * c - 2 * G))
    dvan, dvbn = tip_diameter_normal, base_diameter_normal
    if not 0 < dvbn < dvan:
        raise ReducerlabError("tip_diameter_normal: must exceed the base diameter")
    a_an = math.acos(dvbn / dvan)
    g_a = (math.pi / 2 + 2 * (xh * math.tan(ae) + xs)) / zn + _inv(ae) - _inv(a_an)
    a_fan = a_an - g_a
    h_fa = (
        mn
        / 2
        * (
            (math.cos(g_a) - math.sin(g_a) * math.tan(a_fan)) * dvan / mn
            - zn * math.cos(math.pi / 3 - theta)
            - G / c
            + rho0 / mn
        )
    )
    if not (s_fn > 0 and rho_f > 0 and h_fa > 0):
        raise ReducerlabError("teeth_normal: the tooth form has no critical section")
    y_fa = 6 * (h_fa / mn) * math.cos(a_fan) / ((s_fn / mn) ** 2 * math.cos(an))
    y_sa, q_s = p63.stress_correction(s_fn, h_fa, rho_f)
    return RootForm(E, G, H, theta, s_fn, rho_f, h_fa, a_fan, y_fa, y_sa, q_s)


def internal_root_form(
    *, normal_module: float, pressure_angle: float, tooth_depth: float, dedendum: float
) -> RootForm:
    """An internal gear's ``Y_Fa``, ``Y_Sa`` (outside ISO 10300-3, which rates external
    bevel gears): the rack construction of ISO 6336-3:2019 6.2.3
    (:func:`iso6336_3.internal_tooth_form`, 60 deg fillet tangent) with the load at the
    tip, as ISO 10300-3 places it (``docs/assumptions.md``). Lengths in m, no profile
    shift, root fillet ``0.38 m_mn``."""
    mn = float(normal_module)
    f = p63.internal_tooth_form(
        module=mn, pressure_angle=pressure_angle, tooth_thickness=math.pi * mn / 2,
        reference_height=dedendum, tooth_depth=tooth_depth * (1 + 1e-12),
        load_height=tooth_depth,
    )  # fmt: skip
    nan = math.nan
    return RootForm(nan, nan, nan, nan, f.s_Fn, f.rho_F, f.h_Fe, f.alpha_Fen, f.Y_F, f.Y_S, f.q_s)


def contact_ratio_factor(eps_va: float, eps_vb: float) -> float:
    """Contact ratio factor ``Y_eps`` (ISO 10300-3:2023 Eq. 27 to 29): ``0.25 + 0.75 /
    eps_va - eps_vb (0.75 / eps_va - 0.375)`` for ``eps_vb < 1``, 0.625 from 1 on."""
    if eps_vb >= 1.0:
        return 0.625
    return 0.25 + 0.75 / eps_va - eps_vb * (0.75 / eps_va - 0.375)


def spiral_angle_factor(
    *, face_width: float, spiral_angle: float, beta_vb: float, l_bm: float, depths: float
) -> float:
    """Bevel spiral angle factor ``Y_BS`` (ISO 10300-3:2023 Eq. 30 to 35).

    ``b_a = b_v / cos(beta_v)`` (Eq. 34), ``l_bb = l_bm cos(beta_vb) / cos(beta_v)``
    (Eq. 35), ``x = 2 b_a / (h_m1 + h_m2)``, ``a_BS = -0.0182 x^2 + 0.4736 x - 0.32``,
    ``b_BS = -0.0032 x^2 + 0.0526 x + 0.712``, ``c_BS = -0.0050 x^2 + 0.0850 x + 0.54``
    (Eq. 31 to 33) and ``Y_BS = a_BS / c_BS (l_bb / b_a - 1.05 b_BS)^2 + 1`` (Eq. 30);
    ``Y_BS = 1`` for ``beta_v = 0`` (straight bevels). ``depths``: ``h_m1 + h_m2``, the
    mean whole depths (m).
    """
    if spiral_angle <= 0.0:
        return 1.0
    ba = face_width / math.cos(spiral_angle)
    lbb = l_bm * math.cos(beta_vb) / math.cos(spiral_angle)
    x = 2 * ba / depths
    a = -0.0182 * x * x + 0.4736 * x - 0.32
    b = -0.0032 * x * x + 0.0526 * x + 0.712
    c = -0.0050 * x * x + 0.0850 * x + 0.54
    return a / c * (lbb / ba - 1.05 * b) ** 2 + 1.0


def root_stress_nominal(
    *, force: float, face_width: float, normal_module: float, form: RootForm, factors: float
) -> float:
    """``sigma_F0 = F_vmt / (b_v m_mn) Y_Fa Y_Sa Y_eps Y_BS Y_LS`` (ISO 10300-3:2023 Eq. 2),
    Pa; ``factors`` is the product ``Y_eps Y_BS Y_LS``."""
    return force / (face_width * normal_module) * form.Y_Fa * form.Y_Sa * factors
