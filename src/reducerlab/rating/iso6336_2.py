"""Surface durability (pitting), ISO 6336-2:2019 method B (spur and helical gears).

Edition implemented: **ISO 6336-2:2019** (third edition). SI units inside: stresses in
Pa, ``Z_E`` in ``sqrt(Pa)``, lengths in m, speeds in m/s; the lubricant viscosity
``nu_40`` and the roughness ``R_z`` enter the empirical factors in their standard units
(mm^2/s, um), converted at the call (see each function).

Contact stress (clause 5, Eq. 1 to 4)::

    sigma_H0 = Z_H Z_E Z_eps Z_beta sqrt(F_t / (d_1 b) (u + 1) / u)
    sigma_H1 = Z_B sigma_H0 sqrt(K_A K_v K_Hbeta K_Halpha)   (pinion)
    sigma_H2 = Z_D sigma_H0 sqrt(K_A K_v K_Hbeta K_Halpha)   (wheel)

Permissible stress (Eq. 5, 6) and safety factor (Eq. 7)::

    sigma_HG = sigma_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X,   sigma_HP = sigma_HG / S_Hmin,
    S_H = sigma_HG / sigma_H

with ``u = z_2 / z_1`` negative for an internal pair.
"""

from __future__ import annotations

import math

from ..errors import ReducerlabError

__all__ = [
    "contact_ratio_factor",
    "contact_stress_nominal",
    "elasticity_factor",
    "helix_factor",
    "life_factor",
    "lubrication_factors",
    "roughness_factor",
    "single_pair_factors",
    "zone_factor",
]


def _check(name: str, value: float, *, low: float = 0.0, strict: bool = True) -> float:
    v = float(value)
    ok = math.isfinite(v) and (v > low if strict else v >= low)
    if not ok:
        rule = f"> {low:g}" if strict else f">= {low:g}"
        raise ReducerlabError(f"{name}: must be a finite number {rule}; got {value!r}")
    return v


def zone_factor(alpha_t: float, alpha_wt: float, beta_b: float = 0.0) -> float:
    """Zone factor ``Z_H = sqrt(2 cos(beta_b) cos(alpha_wt) / (cos^2(alpha_t)
    sin(alpha_wt)))`` (ISO 6336-2:2019 Eq. 9); angles in rad."""
    return math.sqrt(
        2 * math.cos(beta_b) * math.cos(alpha_wt) / (math.cos(alpha_t) ** 2 * math.sin(alpha_wt))
    )


def elasticity_factor(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Elasticity factor ``Z_E = sqrt(1 / (pi ((1 - nu1^2) / E1 + (1 - nu2^2) / E2)))``
    (ISO 6336-2:2019 Eq. 23), in ``sqrt(Pa)`` for ``E`` in Pa (steel/steel, 206 GPa,
    0.3: 189.8e3 sqrt(Pa) = 189.8 sqrt(N/mm^2))."""
    for name, v in (("E1", E1), ("E2", E2)):
        _check(name, v)
    for name, v in (("nu1", nu1), ("nu2", nu2)):
        if not 0.0 <= float(v) < 0.5:
            raise ReducerlabError(f"{name}: Poisson's ratio must be in [0, 0.5); got {v!r}")
    return math.sqrt(1.0 / (math.pi * ((1 - nu1**2) / E1 + (1 - nu2**2) / E2)))


def contact_ratio_factor(eps_alpha: float, eps_beta: float = 0.0) -> float:
    """Contact ratio factor ``Z_eps`` (ISO 6336-2:2019 Eq. 10 to 12): spur
    ``sqrt((4 - eps_a) / 3)``; helical ``eps_b < 1``: ``sqrt((4 - eps_a) / 3 (1 - eps_b)
    + eps_b / eps_a)``; ``eps_b >= 1``: ``sqrt(1 / eps_a)``."""
    ea = _check("contact_ratio", eps_alpha)
    eb = _check("overlap_ratio", eps_beta, strict=False)
    if eb >= 1.0:
        return math.sqrt(1.0 / ea)
    return math.sqrt((4 - ea) / 3 * (1 - eb) + eb / ea)


def helix_factor(helix_angle: float) -> float:
    """Helix angle factor ``Z_beta = 1 / sqrt(cos(beta))`` (ISO 6336-2:2019 Eq. 13)."""
    return 1.0 / math.sqrt(math.cos(helix_angle))


def single_pair_factors(
    *,
    tip_diameters: tuple[float, float],
    base_diameters: tuple[float, float],
    teeth: tuple[int, int],
    alpha_wt: float,
    eps_alpha: float,
    eps_beta: float = 0.0,
) -> tuple[float, float]:
    """Single pair tooth contact factors ``(Z_B, Z_D)`` (ISO 6336-2:2019 Eq. 14 to 19).

    ``M_1 = tan(a_wt) / sqrt([sqrt(d_a1^2 / d_b1^2 - 1) - 2 pi / z_1]
    [sqrt(d_a2^2 / d_b2^2 - 1) - (eps_a - 1) 2 pi / z_2])`` and ``M_2`` with the gears
    swapped; spur: ``Z_B = max(1, M_1)``, ``Z_D = max(1, M_2)``; helical ``eps_b >= 1``: 1;
    ``0 < eps_b < 1``: ``M - eps_b (M - 1)`` (at least 1). An internal wheel
    (``teeth[1] < 0``): ``Z_D = 1``.
    """
    (da1, da2), (db1, db2), (z1, z2) = tip_diameters, base_diameters, teeth
    if z2 < 0:
        da2, db2, z2i = abs(da2), abs(db2), abs(z2)
        m1_den = (math.sqrt((da1 / db1) ** 2 - 1) - 2 * math.pi / z1) * (
            math.sqrt((da2 / db2) ** 2 - 1) + (eps_alpha - 1) * 2 * math.pi / z2i
        )
        m1 = math.tan(alpha_wt) / math.sqrt(m1_den) if m1_den > 0 else 1.0
        m2 = 1.0
    else:
        r1 = math.sqrt((da1 / db1) ** 2 - 1)
        r2 = math.sqrt((da2 / db2) ** 2 - 1)
        m1 = math.tan(alpha_wt) / math.sqrt(
            (r1 - 2 * math.pi / z1) * (r2 - (eps_alpha - 1) * 2 * math.pi / z2)
        )
        m2 = math.tan(alpha_wt) / math.sqrt(
            (r2 - 2 * math.pi / z2) * (r1 - (eps_alpha - 1) * 2 * math.pi / z1)
        )
    if eps_beta >= 1.0:
        return 1.0, 1.0
    zb = max(1.0, m1 - eps_beta * (m1 - 1))
    zd = max(1.0, m2 - eps_beta * (m2 - 1)) if z2 > 0 else 1.0
    return zb, zd


def contact_stress_nominal(
    *,
    Z_H: float,
    Z_E: float,
    Z_eps: float,
    Z_beta: float,
    tangential_load: float,
    pinion_diameter: float,
    face_width: float,
    ratio: float,
) -> float:
    """Nominal contact stress ``sigma_H0 = Z_H Z_E Z_eps Z_beta sqrt(F_t / (d_1 b)
    (u + 1) / u)`` (ISO 6336-2:2019 Eq. 2), Pa; ``ratio = z_2 / z_1`` (< 0 internal)."""
    ft = _check("tangential_load", tangential_load)
    d1 = _check("pinion_diameter", pinion_diameter)
    b = _check("face_width", face_width)
    u = float(ratio)
    if not (math.isfinite(u) and abs(u) >= 1.0):
        raise ReducerlabError(f"ratio: |u| = |z2 / z1| must be >= 1; got {ratio!r}")
    return Z_H * Z_E * Z_eps * Z_beta * math.sqrt(ft / (d1 * b) * (u + 1) / u)


def life_factor(cycles: float, treatment: str = "case-hardened") -> float:
    """Life factor for contact stress ``Z_NT`` (ISO 6336-2:2019 Table 2, log-log lines).

    ``treatment``: ``"case-hardened"`` (also through-hardened St, V, GGG, GTS and
    induction hardened: static 1.6 up to 1e5 cycles, 1.0 at 5e7, 0.85 at 1e10 and
    beyond, the line "without pitting allowed, normal lubrication") or ``"nitrided"``
    (1.3 up to 1e5, 1.0 at 2e6, 0.85 at 1e10).
    """
    n = _check("cycles", cycles)
    if treatment in ("case-hardened", "through-hardened", "induction-hardened"):
        n_static, z_static, n_ref = 1e5, 1.6, 5e7
    elif treatment == "nitrided":
        n_static, z_static, n_ref = 1e5, 1.3, 2e6
    else:
        raise ReducerlabError(
            f"treatment: one of case-hardened, through-hardened, induction-hardened, "
            f"nitrided; got {treatment!r}"
        )
    if n <= n_static:
        return z_static
    if n <= n_ref:
        return (n_ref / n) ** (math.log(z_static) / math.log(n_ref / n_static))
    n = min(n, 1e10)
    return (n_ref / n) ** (math.log(1 / 0.85) / math.log(1e10 / n_ref))


def _c_zl(sigma_hlim: float) -> float:
    """``C_ZL`` of ISO 6336-2:2019 Eq. 29 to 31 (``sigma_Hlim`` in Pa)."""
    s = sigma_hlim / 1e6
    if s < 850:
        return 0.83
    if s > 1200:
        return 0.91
    return s / 4375 + 0.6357


def lubrication_factors(sigma_hlim: float, nu40: float, velocity: float) -> tuple[float, float]:
    """Lubricant and velocity factors ``(Z_L, Z_v)`` (ISO 6336-2:2019 Eq. 28 and 32).

    ``Z_L = C_ZL + 4 (1 - C_ZL) / (1.2 + 134 / nu_40)^2`` and
    ``Z_v = C_Zv + 2 (1 - C_Zv) / sqrt(0.8 + 32 / v)``, ``C_Zv = C_ZL + 0.02``, with
    ``nu_40`` the kinematic viscosity at 40 C in **m^2/s** (converted to mm^2/s) and
    ``v`` the pitch line velocity in m/s; ``sigma_Hlim`` in Pa (the softer material's).
    """
    _check("sigma_Hlim", sigma_hlim)
    nu = _check("viscosity_40", nu40) * 1e6
    v = _check("pitch_line_velocity", velocity)
    czl = _c_zl(sigma_hlim)
    zl = czl + 4 * (1 - czl) / (1.2 + 134 / nu) ** 2
    czv = czl + 0.02
    zv = czv + 2 * (1 - czv) / math.sqrt(0.8 + 32 / v)
    return zl, zv


def roughness_factor(sigma_hlim: float, rz: float, rho_red: float) -> float:
    """Roughness factor ``Z_R = (3 / R_z10)^C_ZR`` (ISO 6336-2:2019 Eq. 33 to 37).

    ``R_z10 = R_z (10 / rho_red)^(1/3)`` with ``R_z`` the mean peak-to-valley roughness
    of the pair ``(R_z1 + R_z2) / 2`` in **m** (converted to um), ``rho_red`` the
    relative radius of curvature at the pitch point in m (converted to mm);
    ``C_ZR = 0.15`` (``sigma_Hlim < 850`` MPa), ``0.32 - 0.0002 sigma_Hlim`` (850 to
    1200), ``0.08`` (above).
    """
    _check("sigma_Hlim", sigma_hlim)
    rz_um = _check("roughness_rz", rz) * 1e6
    rho_mm = _check("rho_red", rho_red) * 1e3
    s = sigma_hlim / 1e6
    czr = 0.15 if s < 850 else (0.08 if s > 1200 else 0.32 - 0.0002 * s)
    rz10 = rz_um * (10 / rho_mm) ** (1 / 3)
    return (3 / rz10) ** czr
