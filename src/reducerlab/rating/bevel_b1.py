"""A bevel pair rated by ISO 10300-1/-2/-3:2023 method B1 (no hypoid offset), every
factor a row with its clause: the chain of :mod:`reducerlab.rating.iso10300_1`,
:mod:`~reducerlab.rating.iso10300_2` and :mod:`~reducerlab.rating.iso10300_3`, with the
ISO 6336 equations those parts share (``Z_E``, ``Z_L``, ``Z_v``, ``Z_R``, ``Z_NT``,
``Y_deltarelT``, ``Y_RrelT``, ``Y_X``, ``Y_NT``, ``Y_Sa``).

The nutation drive's pairs are **internal** virtual pairs, outside ISO 10300's scope; the
extensions made for them (curvature, ``Z_M-B``, the internal gear's tooth form, ``Z_LS = 1``
for ``eps_vbeta < 1``) are those of the modules named above and are listed in
``docs/assumptions.md`` ("Load capacity of the nutation pairs").
"""

from __future__ import annotations

import math

from ..errors import ReducerlabError
from . import iso6336_2 as q2
from . import iso6336_3 as q3
from . import iso10300_1 as p1
from . import iso10300_2 as p2
from . import iso10300_3 as p3
from .cylindrical import Factor, PairRating
from .material import GearMaterial, RatingConditions

__all__ = ["B1_LABEL", "rate_b1"]

B1_LABEL = "ISO 10300-1/-2/-3:2023 method B1 (a = 0)"
R1, R2, R3 = "ISO 10300-1:2023", "ISO 10300-2:2023", "ISO 10300-3:2023"


def rate_b1(
    *,
    teeth: tuple[int, int],
    mean_radii: tuple[float, float],
    cone_angles: tuple[float, float],
    normal_module: float,
    spiral_angle: float,
    pressure_angle: float,
    face_width: float,
    torque: float,
    speed: float,
    internal: bool,
    materials: tuple[GearMaterial, GearMaterial],
    conditions: RatingConditions,
    mounting: str = "both-straddle",
    verification: str = "light-load-test",
    effective_width: float = 0.85,
    crowning: str = "low",
) -> PairRating:
    """Rate a bevel pair by ISO 10300 method B1; arguments as
    :func:`reducerlab.rating.bevel.rate_bevel_pair`, plus the mounting and contact pattern
    check of ``K_Hbeta-be`` (:func:`iso10300_1.face_load_factor`), the effective face
    width ``b_eff / b`` (0.85, ISO 10300-1) and the profile crowning of ``Z_LS``.

    Teeth: no profile shift, the ISO 53 depths at the mean section (``h_am = m_mn``,
    ``h_fm = 1.25 m_mn``, cutter tip radius ``0.38 m_mn``); ``K_A``, ``K_v`` and
    ``K_Halpha`` (= ``K_Falpha``) are inputs of ``conditions`` (the designs hold no pitch
    deviations), ``K_F0 = 1`` (no cutter radius known), ``K_Hbeta = K_Hbeta-C``.
    """
    c = conditions
    if not 0 < effective_width <= 1:
        raise ReducerlabError(f"effective_width: must lie in (0, 1]; got {effective_width!r}")
    rows: list[Factor] = []

    def row(symbol: str, gear: str, value: float, unit: str, clause: str) -> float:
        rows.append(Factor(symbol, gear, float(value), unit, clause))
        return float(value)

    mn, bm, an, b = normal_module, spiral_angle, pressure_angle, face_width
    dm = (2 * mean_radii[0], 2 * mean_radii[1])
    v = p1.virtual_gears(
        teeth=teeth, mean_diameters=dm, cone_angles=cone_angles, normal_module=mn,
        spiral_angle=bm, pressure_angle=an, addenda=(mn, mn), face_width=b,
        effective_face_width=effective_width * b, internal=internal,
    )  # fmt: skip
    if not 1.0 < v.eps_va < 2.0:
        raise ReducerlabError(
            f"teeth: the virtual pair's transverse contact ratio {v.eps_va:.4g} must lie in "
            "(1, 2) (ISO 10300-2:2023 scope)"
        )
    row("d_v", "1", v.d_v[0], "m", f"{R1} Eq. A.3")
    row("d_v", "2", v.d_v[1], "m", f"{R1} Eq. A.4" + (" (internal)" if internal else ""))
    row("z_v", "1", v.z_v[0], "1", f"{R1} Eq. A.14")
    row("z_v", "2", v.z_v[1], "1", f"{R1} Eq. A.15")
    row("alpha_vet", "pair", v.alpha_vet, "rad", f"{R1} Eq. A.10")
    row("beta_vb", "pair", v.beta_vb, "rad", f"{R1} Eq. A.16")
    row("g_va", "pair", v.g_va, "m", f"{R1} Eq. A.18")
    row("eps_va", "pair", v.eps_va, "1", f"{R1} Eq. A.23")
    row("b_v,eff", "pair", v.b_v_eff, "m", f"{R1} Eq. A.19 (b_eff = {effective_width:g} b)")
    row("eps_vb", "pair", v.eps_vb, "1", f"{R1} Eq. A.24")
    row("eps_vg", "pair", v.eps_vg, "1", f"{R1} Eq. A.25")
    l_bm = row("l_bm", "pair", p1.contact_line_length(v, 0.0), "m", f"{R1} Eq. A.26-A.36")
    _, _, rho_rel = p1.relative_curvature(
        mean_diameters=dm, cone_angles=cone_angles, spiral_angle=bm, pressure_angle=an,
        internal=internal,
    )  # fmt: skip
    row("rho_rel", "pair", rho_rel, "m", f"{R1} Eq. A.37-A.39" + (" (internal: -)" * internal))
    ft = row("F_mt", "pair", torque / mean_radii[0], "N", f"{R1} Eq. 1 (T_1 / r_m1)")
    vmt = row("v_mt", "pair", speed * mean_radii[0], "m/s", f"{R1} Eq. 5")
    row("K_A", "pair", c.K_A, "1", f"{R1} clause 6 (input, RatingConditions)")
    row("K_v", "pair", c.K_v, "1", f"{R1} clause 7 (input: no pitch deviations in the design)")
    k_be, k_hb = p1.face_load_factor(mounting, verification)
    row("K_Hbeta-be", "pair", k_be, "1", f"{R1} Table 4 ({mounting}, {verification})")
    k_hb = row("K_Hbeta", "pair", k_hb, "1", f"{R1} Eq. 28 (K_Hbeta-C = 1.5 K_Hbeta-be)")
    k_f0 = row("K_F0", "pair", 1.0, "1", f"{R1} Eq. 33 (cutter radius unknown: 1)")
    k_fb = row("K_Fbeta", "pair", k_hb / k_f0, "1", f"{R1} Eq. 32")
    k_ha = row("K_Halpha", "pair", c.K_Halpha, "1", f"{R1} clause 9 (input; = K_Falpha, a = 0)")
    # ---- pitting
    m1, m2 = materials
    zmb = row("Z_M-B", "pair", p2.mid_zone_factor(v), "1",
              f"{R2} Eq. 6, Table 4" + (" (internal gear 2: +F_2)" * internal))  # fmt: skip
    zls_clause = f"{R2} Eq. 7-10" if v.eps_vb >= 1 else f"{R2} (eps_vbeta < 1: 1, assumed)"
    zls = row("Z_LS", "pair", p2.load_sharing_factor(v, crowning), "1", zls_clause)
    ze = row(
        "Z_E", "pair",
        q2.elasticity_factor(m1.youngs_modulus, m1.poisson_ratio, m2.youngs_modulus,
                             m2.poisson_ratio),
        "sqrt(Pa)", f"{R2} Eq. 51",
    )  # fmt: skip
    fn = row("F_n", "pair", p2.normal_force(ft, an, bm), "N", f"{R2} Eq. 3")
    sh0 = row(
        "sigma_H0", "pair",
        p2.contact_stress_nominal(normal_force=fn, l_bm=l_bm, rho_rel=rho_rel, Z_MB=zmb,
                                  Z_LS=zls, Z_E=ze),
        "Pa", f"{R2} Eq. 2",
    )  # fmt: skip
    sh = sh0 * math.sqrt(c.K_A * c.K_v * k_hb * k_ha)  # Eq. 1, a row per gear below
    hlim_soft = min(m1.sigma_Hlim, m2.sigma_Hlim)
    zl, zv = q2.lubrication_factors(hlim_soft, c.viscosity_40, vmt)
    row("Z_L", "pair", zl, "1", f"{R2} Eq. 54 (nu_40 = {c.viscosity_40 * 1e6:g} mm^2/s)")
    row("Z_v", "pair", zv, "1", f"{R2} Eq. 56")
    zr = row("Z_R", "pair", q2.roughness_factor(hlim_soft, c.rz_flank, rho_rel), "1",
             f"{R2} Eq. 58-60")  # fmt: skip
    row("Z_W", "pair", 1.0, "1", f"{R2} clause 8.3 (equal hardness: 1)")
    row("Z_X", "pair", 1.0, "1", f"{R2} clause 6.5.2 (1)")
    zk = row("Z_KP", "pair", p2.BEVEL_FACTOR, "1", f"{R2} Eq. 11 (bevel gear factor)")
    row("Z_Hyp", "pair", 1.0, "1", f"{R2} Eq. 12 (a = 0: 1)")
    # ---- bending
    yeps = row("Y_eps", "pair", p3.contact_ratio_factor(v.eps_va, v.eps_vb), "1",
               f"{R3} Eq. 27-29")  # fmt: skip
    ybs = row(
        "Y_BS", "pair",
        p3.spiral_angle_factor(face_width=v.b_v, spiral_angle=bm, beta_vb=v.beta_vb,
                               l_bm=l_bm, depths=2 * 2.25 * mn),
        "1", f"{R3} Eq. 30-35",
    )  # fmt: skip
    yls = row("Y_LS", "pair", zls**2, "1", f"{R3} Eq. 36 (Z_LS^2)")
    form1 = p3.tooth_form(
        normal_module=mn, teeth_normal=v.z_vn[0], tip_diameter_normal=v.d_van[0],
        base_diameter_normal=v.d_vbn[0], tool_addendum=1.25 * mn, tool_tip_radius=0.38 * mn,
        profile_shift=0.0, thickness_modification=0.0, pressure_angle=an,
    )  # fmt: skip
    if internal:
        form2 = p3.internal_root_form(
            normal_module=mn, pressure_angle=an, tooth_depth=2.25 * mn, dedendum=1.25 * mn
        )
        clause2 = "ISO 6336-3:2019 6.2.3 rack, load at the tip (internal gear, assumed)"
    else:
        form2 = p3.tooth_form(
            normal_module=mn, teeth_normal=v.z_vn[1], tip_diameter_normal=v.d_van[1],
            base_diameter_normal=v.d_vbn[1], tool_addendum=1.25 * mn,
            tool_tip_radius=0.38 * mn, profile_shift=0.0, thickness_modification=0.0,
            pressure_angle=an,
        )  # fmt: skip
        clause2 = f"{R3} Eq. 6-17"
    hours_s = c.hours * 3600
    speeds = (speed, speed * teeth[0] / teeth[1])
    S_H, S_F = [], []
    for i, (mat, form) in enumerate(zip(materials, (form1, form2), strict=True)):
        g = str(i + 1)
        fc = f"{R3} Eq. 6-17" if i == 0 else clause2
        n_l = row("N_L", g, speeds[i] / (2 * math.pi) * hours_s, "1", "load cycles")
        znt = row("Z_NT", g, q2.life_factor(n_l, mat.treatment), "1",
                  f"{R2} Table 6 (= ISO 6336-2:2019 Table 2)")  # fmt: skip
        row("sigma_H", g, sh, "Pa", f"{R2} Eq. 1 (the same for both gears)")
        row("sigma_Hlim", g, mat.sigma_Hlim, "Pa", "ISO 6336-5:2016 (material)")
        shg = mat.sigma_Hlim * znt * zl * zv * zr * zk
        row("sigma_HP", g, shg / c.S_Hmin, "Pa", f"{R2} Eq. 4 (S_Hmin = {c.S_Hmin:g})")
        S_H.append(row("S_H", g, shg / sh, "1", f"{R2} Eq. 5"))
        row("Y_Fa", g, form.Y_Fa, "1", fc)
        row("Y_Sa", g, form.Y_Sa, "1", f"{R3} Eq. 24-26")
        row("h_Fa", g, form.h_Fa, "m", fc)
        row("s_Fn", g, form.s_Fn, "m", fc)
        row("rho_F", g, form.rho_F, "m", fc)
        row("alpha_Fan", g, form.alpha_Fan, "rad", fc)
        sf0 = row(
            "sigma_F0", g,
            p3.root_stress_nominal(force=ft, face_width=v.b_v, normal_module=mn, form=form,
                                   factors=yeps * ybs * yls),
            "Pa", f"{R3} Eq. 2",
        )  # fmt: skip
        sf = row("sigma_F", g, sf0 * c.K_A * c.K_v * k_fb * k_ha, "Pa", f"{R3} Eq. 1")
        ynt = row("Y_NT", g, q3.life_factor(n_l, mat.treatment), "1",
                  f"{R3} Table 5 (= ISO 6336-3:2019 Table 4)")  # fmt: skip
        ydel = row("Y_deltarelT", g, q3.notch_sensitivity_factor(form.q_s), "1",
                   f"{R3} Eq. 43-45")  # fmt: skip
        yr = row("Y_RrelT", g, q3.roughness_factor_root(c.rz_root), "1", f"{R3} Eq. 40")
        yx = row("Y_X", g, q3.size_factor_root(mn), "1", f"{R3} Eq. 208")
        row("Y_ST", g, 2.0, "1", f"{R3} clause 6 (reference test gear)")
        row("sigma_Flim", g, mat.sigma_Flim, "Pa", "ISO 6336-5:2016 (material)")
        sfg = mat.sigma_Flim * 2.0 * ynt * ydel * yr * yx
        row("sigma_FP", g, sfg / c.S_Fmin, "Pa", f"{R3} Eq. 4 (S_Fmin = {c.S_Fmin:g})")
        S_F.append(row("S_F", g, sfg / sf, "1", f"{R3} Eq. 5"))
    label = B1_LABEL
    if internal:
        label += (
            "; internal virtual pair (outside ISO 10300's scope): concave rho_rel and Z_M-B, "
            "internal gear's Y_Fa/Y_Sa by the ISO 6336-3 rack"
        )
    if v.eps_vb < 1:
        label += "; eps_vbeta < 1: Z_LS = Y_LS = 1"
    return PairRating((S_H[0], S_H[1]), (S_F[0], S_F[1]), rows, label)
