"""Bevel gears, ISO 10300-1:2023 method B1: the virtual cylindrical gears of Annex A and
the general load factors ``K_v`` (method B), ``K_Hbeta-C``, ``K_F0`` and ``K_Halpha``
(method B).

Scope: bevel gears **without hypoid offset** (``a = 0``), so that both members have the
same mean spiral angle ``beta_m`` and the virtual gears' helix angle is ``beta_v =
beta_m``; the drive flank is rated, with its effective pressure angle ``alpha_e`` (no
limit pressure angle: ``alpha_lim = 0``). A hypoid offset is refused. An *internal*
virtual pair (the nutation drive's bevel pairs, outside the standard's scope) is built by
the same equations with the signs of an internal cylindrical pair (see
:func:`virtual_gears` and ``docs/assumptions.md``).

SI units throughout (m, rad, N, Pa, kg); empirical limits given in the standard in mm or
um are converted where they are used. ISO/TR 10300-30:2024 Annex A (sample 1) is the
oracle of ``tests/published/test_iso10300_example.py``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import ReducerlabError

__all__ = [
    "VirtualGears",
    "contact_line_length",
    "contact_line_positions",
    "dynamic_factor",
    "face_load_factor",
    "lengthwise_curvature_factor",
    "relative_curvature",
    "transverse_load_factor",
    "virtual_gears",
]


def _pos(name: str, value: float) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0):
        raise ReducerlabError(f"{name}: must be a finite number > 0; got {value!r}")
    return v


@dataclass(frozen=True)
class VirtualGears:
    """The virtual cylindrical gear pair of a bevel pair (ISO 10300-1:2023 Annex A), SI.

    Pairs of values are (gear 1, gear 2); gear 1 is the external member (the pinion),
    gear 2 is internal when ``internal``. Diameters and tooth numbers are magnitudes.

    Attributes
    ----------
    d_v, d_va, d_vb : tuple of float
        Reference, tip and base diameters (m), Eq. A.3 to A.9.
    z_v : tuple of float
        Virtual numbers of teeth ``z / cos(delta)`` (Eq. A.14, A.15).
    beta_v, beta_vb, alpha_vet : float
        Helix angle ``beta_v = beta_m`` (Eq. A.8), base helix angle (Eq. A.16), transverse
        pressure angle (Eq. A.10), rad.
    m_vt, p_vet, g_va : float
        Transverse module ``d_v1 / z_v1`` (Eq. A.13), transverse base pitch (Eq. A.17),
        length of the path of contact (Eq. A.18), m.
    b_v, b_v_eff : float
        Face width and effective face width of the virtual gears (m), Eq. A.19, A.22.
    eps_va, eps_vb, eps_vg : float
        Transverse, face and virtual contact ratios (Eq. A.23 to A.25).
    z_vn, d_vn, d_van, d_vbn : tuple of float
        The virtual gears in the normal section: teeth, reference, tip and base diameters
        (Eq. A.41 to A.45).
    internal : bool
        Gear 2 internal.
    """

    d_v: tuple[float, float]
    d_va: tuple[float, float]
    d_vb: tuple[float, float]
    z_v: tuple[float, float]
    beta_v: float
    beta_vb: float
    alpha_vet: float
    m_vt: float
    p_vet: float
    g_va: float
    b_v: float
    b_v_eff: float
    eps_va: float
    eps_vb: float
    eps_vg: float
    z_vn: tuple[float, float]
    d_vn: tuple[float, float]
    d_van: tuple[float, float]
    d_vbn: tuple[float, float]
    internal: bool = False


def virtual_gears(
    *,
    teeth: tuple[int, int],
    mean_diameters: tuple[float, float],
    cone_angles: tuple[float, float],
    normal_module: float,
    spiral_angle: float,
    pressure_angle: float,
    addenda: tuple[float, float],
    face_width: float,
    effective_face_width: float,
    internal: bool = False,
    offset: float = 0.0,
) -> VirtualGears:
    """The virtual cylindrical gears of a bevel pair without offset (ISO 10300-1:2023
    Annex A, Eq. A.3 to A.25 and A.41 to A.46).

    Parameters
    ----------
    teeth : tuple of int
        ``z_1, z_2``.
    mean_diameters : tuple of float
        Mean pitch diameters ``d_m1, d_m2`` (m).
    cone_angles : tuple of float
        Pitch cone angles ``delta_1, delta_2`` (rad), each in (0, 90 deg).
    normal_module : float
        Mean normal module ``m_mn`` (m).
    spiral_angle : float
        Mean spiral angle ``beta_m`` (rad), ``0 <= beta_m < 90 deg``.
    pressure_angle : float
        Effective pressure angle ``alpha_e`` of the rated flank (rad).
    addenda : tuple of float
        Mean addenda ``h_am1, h_am2`` (m).
    face_width : float
        Face width ``b`` (m); ``b_v = b`` for ``a = 0`` (Eq. A.22).
    effective_face_width : float
        ``b_2,eff`` (m), ``0 < b_2,eff <= b`` (ISO 10300-1 gives 0.85 b without a
        contact pattern check); ``b_v,eff = b_2,eff`` for ``a = 0`` (Eq. A.19).
    internal : bool
        Gear 2 internal: ``d_va2 = d_v2 - 2 h_am2``, centre distance ``(d_v2 - d_v1) /
        2``, and gear 2's part of the path of contact taken with the internal sign.
    offset : float
        Hypoid offset ``a`` (m); only 0 is supported.
    """
    if offset != 0.0:
        raise ReducerlabError(
            f"offset: hypoid gears (a != 0) are not supported by this ISO 10300 method B1 "
            f"implementation; got a = {offset!r} m"
        )
    z1, z2 = teeth
    if not (int(z1) == z1 and int(z2) == z2 and z1 >= 5 and z2 >= 5):
        raise ReducerlabError(f"teeth: two integers >= 5; got {teeth!r}")
    dm1, dm2 = (_pos("mean_diameter", d) for d in mean_diameters)
    for d in cone_angles:
        if not (math.isfinite(d) and 0 < d < math.radians(89.0)):
            raise ReducerlabError(f"cone_angles: each in (0, 89 deg); got {cone_angles!r}")
    mn = _pos("normal_module", normal_module)
    bm, ae = float(spiral_angle), _pos("pressure_angle", pressure_angle)
    if not 0 <= bm < math.radians(60.0):
        raise ReducerlabError(f"spiral_angle: must lie in [0, 60 deg); got {spiral_angle!r}")
    b = _pos("face_width", face_width)
    b_eff = _pos("effective_face_width", effective_face_width)
    if b_eff > b:
        raise ReducerlabError(f"effective_face_width: must be <= face_width {b!r} m")
    ha1, ha2 = addenda
    c1, c2 = math.cos(cone_angles[0]), math.cos(cone_angles[1])
    dv = (dm1 / c1, dm2 / c2)  # Eq. A.1/A.2 (A.3, A.4 at Sigma = 90 deg)
    zv = (z1 / c1, z2 / c2)  # Eq. A.14, A.15
    s2 = -1.0 if internal else 1.0
    dva = (dv[0] + 2 * ha1, dv[1] + s2 * 2 * ha2)  # Eq. A.6
    avet = math.atan(math.tan(ae) / math.cos(bm))  # Eq. A.10
    dvb = (dv[0] * math.cos(avet), dv[1] * math.cos(avet))  # Eq. A.9
    bvb = math.asin(math.sin(bm) * math.cos(ae))  # Eq. A.16
    # transverse module and base pitch (Eq. A.13, A.17) from the mean section, m_vt =
    # d_v1 / z_v1 = d_m1 / z_1 (= m_mn / cos(beta_m) for a consistent m_mn)
    m_vt = dv[0] / zv[0]
    p_vet = math.pi * m_vt * math.cos(avet)
    if dva[1] <= dvb[1]:
        raise ReducerlabError("addenda: gear 2's tip circle lies inside its base circle")
    part = [0.5 * (math.sqrt(dva[k] ** 2 - dvb[k] ** 2) - dv[k] * math.sin(avet)) for k in (0, 1)]
    g_va = part[0] + s2 * part[1]  # Eq. A.18
    eps_va = g_va / p_vet  # Eq. A.23
    eps_vb = b_eff * math.sin(bm) / (math.pi * mn)  # Eq. A.24
    zvn1 = zv[0] / (math.cos(bvb) ** 2 * math.cos(bm))  # Eq. A.41
    zvn = (zvn1, zvn1 * zv[1] / zv[0])  # Eq. A.42
    dvn = (zvn[0] * mn, zvn[1] * mn)  # Eq. A.43
    dvan = (dvn[0] + 2 * ha1, dvn[1] + s2 * 2 * ha2)  # Eq. A.44
    dvbn = (dvn[0] * math.cos(ae), dvn[1] * math.cos(ae))  # Eq. A.45
    return VirtualGears(
        d_v=dv, d_va=dva, d_vb=dvb, z_v=zv, beta_v=bm, beta_vb=bvb, alpha_vet=avet,
        m_vt=m_vt, p_vet=p_vet, g_va=g_va, b_v=b, b_v_eff=b_eff,
        eps_va=eps_va, eps_vb=eps_vb, eps_vg=eps_va + eps_vb, z_vn=zvn, d_vn=dvn,
        d_van=dvan, d_vbn=dvbn, internal=internal,
    )  # fmt: skip


def contact_line_length(v: VirtualGears, f: float) -> float:
    """Length ``l_b`` of the contact line at the distance ``f`` (m) from the centre of the
    zone of action (ISO 10300-1:2023 A.2.7, Eq. A.26 to A.36, ``a = 0``), m.

    The line at ``f`` crosses the zone of action (``g_va`` by ``b_v,eff``) with length
    ``l_b0`` (Eq. A.27 to A.32: ``b_v,eff`` for ``beta_vb = 0``, else ``g_va /
    sin(beta_vb)``, the same for every ``f``; where the face is too narrow for that,
    ``b_v,eff / cos(beta_vb) < g_va / sin(beta_vb)``, the line across the face, an
    assumption of ours); the inclined contact lines are shortened towards the
    zone's corners by ``C_lb = sqrt((f / f_max)^2 + (1 - sqrt(b_v,eff / b_v))^2 (1 -
    (f / f_max)^2))``: ``l_b = l_b0 (1 - C_lb)`` (Eq. A.26, A.35, A.36). Lines beyond
    ``|f| >= f_max`` have zero length.
    """
    bvb, g, be = v.beta_vb, v.g_va, v.b_v_eff
    f_max = f_max_of(v)
    if abs(f) >= f_max:
        return 0.0
    # the line's ends on the zone's boundary (Eq. A.27 to A.32): a straight bevel's line
    # spans the face, an inclined one crosses the path of contact over g_va / sin(beta_vb)
    # -- or, where that is longer, the effective face over b_v,eff / cos(beta_vb)
    # (narrow faces, eps_vbeta < 1: our reading, docs/assumptions.md)
    l_b0 = be if bvb == 0.0 else min(g / math.sin(bvb), be / math.cos(bvb))
    k = 1.0 - math.sqrt(be / v.b_v)
    r2 = (f / f_max) ** 2
    c_lb = math.sqrt(r2 + k * k * (1.0 - r2))
    return l_b0 * (1.0 - c_lb)


def f_max_of(v: VirtualGears) -> float:
    """Largest distance of a contact line from the centre of the zone of action,
    ``f_max = (g_va + b_v,eff tan(beta_vb)) cos(beta_vb) / 2`` (ISO 10300-1:2023
    Eq. A.33, A.34 for ``a = 0``), m."""
    return 0.5 * (v.g_va + v.b_v_eff * math.tan(v.beta_vb)) * math.cos(v.beta_vb)


def contact_line_positions(v: VirtualGears) -> tuple[float, float, float]:
    """Distances ``(f_t, f_m, f_r)`` (m) of the tip, middle and root contact lines from the
    centre of the zone of action (ISO 10300-1:2023 Table A.2, branch ``eps_vbeta >= 1``):
    ``f_m = 0``, ``f_t = -f_r = p_vet cos(beta_vb)``.

    Raises for ``eps_vbeta < 1``: that branch of Table A.2 is not implemented here (its
    users take ``Z_LS = 1``, see :func:`reducerlab.rating.iso10300_2.load_sharing_factor`).
    """
    if v.eps_vb < 1.0:
        raise ReducerlabError(
            f"eps_vbeta: {v.eps_vb:.4g} < 1, the Table A.2 branch for eps_vbeta < 1 is not "
            "implemented"
        )
    ft = v.p_vet * math.cos(v.beta_vb)
    return ft, 0.0, -ft


def relative_curvature(
    *,
    mean_diameters: tuple[float, float],
    cone_angles: tuple[float, float],
    spiral_angle: float,
    pressure_angle: float,
    internal: bool = False,
) -> tuple[float, float, float]:
    """Radius of relative curvature at the mean point (ISO 10300-1:2023 A.2.8, ``a = 0``,
    ``alpha_lim = 0``): returns ``(rho_t, beta_B, rho_rel)``.

    ``1 / rho_t = cos^2(beta_m) / sin(alpha_e) (1 / (R_m1 tan(delta_1)) +- 1 / (R_m2
    tan(delta_2)))`` (Eq. A.39; ``R_m tan(delta) = d_m / (2 cos(delta))``; minus for an
    internal gear 2, whose flank is concave), the inclination of the contact line
    ``tan(beta_B) = tan(beta_v) sin(alpha_e)`` (Eq. A.38) and ``rho_rel = rho_t
    cos^2(beta_B)`` (Eq. A.37), all lengths in m.
    """
    (dm1, dm2), (d1, d2) = mean_diameters, cone_angles
    bm, ae = spiral_angle, pressure_angle
    k1 = 2 * math.cos(d1) / _pos("mean_diameter", dm1)
    k2 = 2 * math.cos(d2) / _pos("mean_diameter", dm2)
    inv = math.cos(bm) ** 2 / math.sin(ae) * (k1 - k2 if internal else k1 + k2)
    if not inv > 0:
        raise ReducerlabError("mean_diameters: the internal gear 2 must be the larger one")
    rho_t = 1.0 / inv
    beta_b = math.atan(math.tan(bm) * math.sin(ae))
    return rho_t, beta_b, rho_t * math.cos(beta_b) ** 2


def _cv(eps_g: float) -> tuple[float, float, float, float, float]:
    """``(c_v1 + c_v2, c_v3, c_v4, c_v5 + c_v6, c_v7)`` of ISO 10300-1:2023 Table 3."""
    if eps_g <= 2.0:
        c12, c3, c4, c56 = 0.32 + 0.34, 0.23, 0.90, 0.47 + 0.47
    else:
        c12, c3 = 0.32 + 0.57 / (eps_g - 0.3), 0.096 / (eps_g - 1.56)
        c4 = (0.57 - 0.05 * eps_g) / (eps_g - 1.44)
        c56 = 0.47 + 0.12 / (eps_g - 1.74)
    if eps_g <= 1.5:
        c7 = 0.75
    elif eps_g <= 2.5:
        c7 = 0.125 * math.sin(math.pi * (eps_g - 2.0)) + 0.875
    else:
        c7 = 1.0
    return c12, c3, c4, c56, c7


def running_in_allowance(f_pt: float) -> float:
    """Running-in allowance ``y_alpha = 0.075 f_pt <= 3 um`` (ISO 10300-1:2023 Eq. 51,
    case-hardened or nitrided steel), ``f_pt`` and the result in m."""
    return min(0.075 * float(f_pt), 3e-6)


def _c_f(load_per_width: float) -> float:
    """Correction factor ``C_F`` (ISO 10300-1:2023 Eq. 12, 13): 1 from ``F K_A / b`` =
    100 N/mm (1e5 N/m) up, proportional below."""
    return min(1.0, load_per_width / 1e5)


def dynamic_factor(
    *,
    speed: float,
    pinion_teeth: int,
    mean_diameters: tuple[float, float],
    normal_pressure_angle: float,
    force: float,
    K_A: float,
    face_width: float,
    pitch_deviation: float,
    eps_vg: float,
    density: float = 7860.0,
) -> float:
    """Dynamic factor ``K_v-B`` (ISO 10300-1:2023 clause 7.7.3, method B).

    Relative masses per face width ``m_i* = pi rho d_mi^2 / (8 cos^2(alpha_n))`` (Eq. 14),
    ``m_red = m_1* m_2* / (m_1* + m_2*)`` (Eq. 10), mesh stiffness ``c_gamma = 20 C_F``
    N/(mm um) (Eq. 11), the pinion's resonance speed ``omega_E1 = sqrt(c_gamma / m_red)
    / z_1`` (Eq. 9 in rad/s), ``N = omega_1 / omega_E1`` (Eq. 8); with ``c' = 14 C_F``
    N/(mm um) (Eq. 18) and ``f_p,eff = f_pt - y_alpha`` (Eq. 17): ``K_v = N K + 1``,
    ``K = X c_v12 + c_v3`` (sub-critical, ``N <= 0.75``, Eq. 15, 16); ``K_v = c_v12 X + c_v4
    + 1`` (main resonance, Eq. 19); linear between 1.25 and 1.5 (Eq. 20); ``c_v56 X + c_v7
    + 1`` above (Eq. 21), ``X = b_v f_p,eff c' / (F K_A)``, ``c_v`` of Table 3.

    Parameters
    ----------
    speed : float
        Pinion speed ``omega_1`` (rad/s).
    pinion_teeth : int
        ``z_1``.
    mean_diameters : tuple of float
        ``d_m1, d_m2`` (m).
    normal_pressure_angle : float
        ``alpha_n`` (rad).
    force : float
        Tangential force of the virtual gears ``F_vmt`` (N).
    K_A : float
        Application factor.
    face_width : float
        ``b_v`` (m): the face width of ``X`` and ``C_F`` (with ``b_v,eff`` in their place
        sample 1 of ISO/TR 10300-30 gives 1.018, not its printed 1.020).
    pitch_deviation : float
        Single pitch deviation ``f_pt`` (m), the wheel's (ISO 10300-1 9.3.1).
    eps_vg : float
        Virtual contact ratio.
    density : float
        ``rho`` (kg/m^3).
    """
    ca2 = math.cos(normal_pressure_angle) ** 2
    m1, m2 = (math.pi * _pos("density", density) * d**2 / (8 * ca2) for d in mean_diameters)
    m_red = m1 * m2 / (m1 + m2)
    b = _pos("face_width", face_width)
    load = _pos("force", force) * _pos("K_A", K_A)
    cf = _c_f(load / b)
    c_gamma, c_prime = 20e9 * cf, 14e9 * cf  # N/(mm um) -> Pa
    n_ratio = _pos("speed", speed) * pinion_teeth / math.sqrt(c_gamma / m_red)
    fp_eff = max(float(pitch_deviation) - running_in_allowance(pitch_deviation), 0.0)
    x = b * fp_eff * c_prime / load
    c12, c3, c4, c56, c7 = _cv(eps_vg)
    if n_ratio <= 0.75:
        return n_ratio * (x * c12 + c3) + 1.0
    main, sup = x * c12 + c4 + 1.0, x * c56 + c7 + 1.0
    if n_ratio <= 1.25:
        return main
    if n_ratio < 1.5:
        return sup + (main - sup) * (1.5 - n_ratio) / 0.25
    return sup


#: mounting factor K_Hbeta-be (ISO 10300-1:2023 Table 4): rows the contact pattern check
#: ("full load" each gear, "light load" test, "light load" assembly), columns the mounting
#: (both members straddle mounted, one cantilever, both cantilever)
MOUNTING_FACTORS = {
    "full-load": (1.00, 1.00, 1.00),
    "light-load-test": (1.05, 1.10, 1.25),
    "light-load-assembly": (1.20, 1.32, 1.50),
}
MOUNTINGS = ("both-straddle", "one-cantilever", "both-cantilever")


def face_load_factor(mounting: str, verification: str) -> tuple[float, float]:
    """``(K_Hbeta-be, K_Hbeta-C)``: mounting factor (ISO 10300-1:2023 Table 4) and the face
    load factor method C ``K_Hbeta-C = 1.5 K_Hbeta-be`` (Eq. 28).

    ``mounting``: one of ``both-straddle``, ``one-cantilever``, ``both-cantilever``;
    ``verification``: the contact pattern check, one of ``full-load``,
    ``light-load-test``, ``light-load-assembly``.
    """
    if mounting not in MOUNTINGS:
        raise ReducerlabError(f"mounting: one of {', '.join(MOUNTINGS)}; got {mounting!r}")
    if verification not in MOUNTING_FACTORS:
        raise ReducerlabError(
            f"verification: one of {', '.join(MOUNTING_FACTORS)}; got {verification!r}"
        )
    k_be = MOUNTING_FACTORS[verification][MOUNTINGS.index(mounting)]
    return k_be, 1.5 * k_be


def lengthwise_curvature_factor(
    *, spiral_angle: float, cutter_radius: float | None, mean_cone_distance: float
) -> float:
    """Lengthwise curvature factor for bending ``K_F0`` (ISO 10300-1:2023 Eq. 33 to 35):
    1 for straight bevels, an unknown cutter radius or ``r_c0 > R_m``; otherwise
    ``0.211 (r_c0 / R_m)^q + 0.789``, ``q = 0.279 / log10(sin(beta_m))``, within [1, 1.15].
    Lengths in m; ``K_Fbeta = K_Hbeta / K_F0`` (Eq. 32)."""
    if cutter_radius is None or spiral_angle <= 0.0:
        return 1.0
    rm = _pos("mean_cone_distance", mean_cone_distance)
    rc = _pos("cutter_radius", cutter_radius)
    if rc > rm:
        return 1.0
    q = 0.279 / math.log10(math.sin(spiral_angle))
    return min(max(0.211 * (rc / rm) ** q + 0.789, 1.0), 1.15)


def transverse_load_factor(
    *,
    force: float,
    K_A: float,
    K_v: float,
    K_Hbeta: float,
    face_width: float,
    effective_face_width: float,
    pitch_deviation: float,
    eps_vg: float,
) -> float:
    """Transverse load factor ``K_Halpha* `` method B for ``a = 0`` (ISO 10300-1:2023
    Eq. 46 to 48): ``F_mtH = F_vmt K_A K_v K_Hbeta`` and, with ``X = c_gamma (f_pt -
    y_alpha) / (F_mtH / b_v)``, ``0.9 + 0.4 (eps_vg / 2) X`` for ``eps_vg <= 2``, ``0.9 +
    0.4 sqrt(2 (eps_vg - 1) / eps_vg) X`` above. ``K_Falpha = K_Halpha`` for ``a = 0``;
    values below 1 are raised to 1 (the note of Eq. 41). Forces N, lengths m."""
    load = _pos("force", force) * K_A
    c_gamma = 20e9 * _c_f(load / _pos("effective_face_width", effective_face_width))
    f_mth = load * K_v * K_Hbeta
    fp_eff = max(float(pitch_deviation) - running_in_allowance(pitch_deviation), 0.0)
    x = c_gamma * fp_eff / (f_mth / _pos("face_width", face_width))
    if eps_vg <= 2.0:
        k = 0.9 + 0.4 * (eps_vg / 2) * x
    else:
        k = 0.9 + 0.4 * math.sqrt(2 * (eps_vg - 1) / eps_vg) * x
    return max(k, 1.0)
