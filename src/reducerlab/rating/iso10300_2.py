"""Bevel gears, ISO 10300-2:2023 method B1: surface durability (pitting).

Contact stress at the mean point of the middle contact line (clause 6, Eq. 1 to 3)::

    F_n      = F_mt1 / (cos(alpha_n) cos(beta_m1))
    sigma_H0 = sqrt(F_n / (l_bm rho_rel)) Z_M-B Z_LS Z_E
    sigma_H  = sigma_H0 sqrt(K_A K_v K_Hbeta K_Halpha)

permissible stress and safety factor (Eq. 4, 5)::

    sigma_HG = sigma_Hlim Z_NT Z_X Z_L Z_v Z_R Z_W Z_KP Z_Hyp,
    S_H = sigma_HG / sigma_H

with the bevel gear factor ``Z_KP = 1.2`` (Eq. 11) and the hypoid factor ``Z_Hyp = 1``
for ``a = 0`` (Eq. 12). ``Z_E`` (Eq. 51), ``Z_L``, ``Z_v``, ``Z_R`` (Eq. 54 to 60) are the
equations of ISO 6336-2:2019 with ``v_mt`` and ``rho_rel`` in place of the pitch line
velocity and ``rho_red``: :mod:`reducerlab.rating.iso6336_2` evaluates them. SI units
(m, N, Pa).
"""

from __future__ import annotations

import math

from ..errors import ReducerlabError
from . import iso10300_1 as p1

__all__ = [
    "BEVEL_FACTOR",
    "contact_stress_nominal",
    "load_sharing_factor",
    "mid_zone_factor",
    "normal_force",
]

#: bevel gear factor Z_KP of ISO 10300-2:2023 Eq. 11 (method B1)
BEVEL_FACTOR = 1.2


def mid_zone_factor(v: p1.VirtualGears) -> float:
    """Mid-zone factor ``Z_M-B`` (ISO 10300-2:2023 Eq. 6 and Table 4).

    ``Z_M-B = tan(alpha_vet) / sqrt([sqrt((d_va1/d_vb1)^2 - 1) - F_1 pi / z_v1]
    [sqrt((d_va2/d_vb2)^2 - 1) - F_2 pi / z_v2])`` with ``F_1 = F_2 = eps_va`` for
    ``eps_vbeta >= 1``, ``F_1 = 2``, ``F_2 = 2 (eps_va - 1)`` for ``eps_vbeta = 0`` and
    linear in ``eps_vbeta`` between. For an internal gear 2 its bracket becomes
    ``sqrt((d_va2/d_vb2)^2 - 1) + F_2 pi / z_v2`` (its roll angle grows from the tip
    towards the root): the same ratio of the curvature at the pitch point to that at the
    mid-zone point (``docs/assumptions.md``).
    """
    ea, eb = v.eps_va, v.eps_vb
    if eb >= 1.0:
        f1 = f2 = ea
    else:
        f1 = 2.0 + (ea - 2.0) * eb
        f2 = 2.0 * ea - 2.0 + (2.0 - ea) * eb
    t1 = math.sqrt((v.d_va[0] / v.d_vb[0]) ** 2 - 1) - f1 * math.pi / v.z_v[0]
    s2 = -1.0 if v.internal else 1.0
    t2 = math.sqrt((v.d_va[1] / v.d_vb[1]) ** 2 - 1) - s2 * f2 * math.pi / v.z_v[1]
    if not (t1 > 0 and t2 > 0):
        raise ReducerlabError("teeth: the mid-zone point lies below a base circle")
    return math.tan(v.alpha_vet) / math.sqrt(t1 * t2)


def load_sharing_factor(v: p1.VirtualGears, crowning: str = "low") -> float:
    """Load sharing factor ``Z_LS`` (ISO 10300-2:2023 Eq. 7 to 10).

    Peak loads on the tip, middle and root contact lines ``p*_i = 1 - |f_i / f_max|^e_LS``
    (Eq. 7; ``e_LS = 3`` for low, 1.5 for high profile crowning, Table 5), the areas
    ``A*_i = pi p*_i l_bi / 4`` (Eq. 8) and ``Z_LS = sqrt(A*_m / (A*_t + A*_m + A*_r))``
    (Eq. 10), the contact lines from :func:`iso10300_1.contact_line_positions` and
    :func:`iso10300_1.contact_line_length`.

    For ``eps_vbeta < 1`` the Table A.2 positions are not implemented and ``Z_LS = 1``
    (no load sharing credited: a conservative choice, ``docs/assumptions.md``).
    """
    if crowning not in ("low", "high"):
        raise ReducerlabError(f"crowning: 'low' or 'high'; got {crowning!r}")
    if v.eps_vb < 1.0:
        return 1.0
    e_ls = 3.0 if crowning == "low" else 1.5
    f_max = p1.f_max_of(v)
    areas = []
    for f in p1.contact_line_positions(v):
        p = max(1.0 - abs(f / f_max) ** e_ls, 0.0)
        areas.append(math.pi / 4 * p * p1.contact_line_length(v, f))
    return math.sqrt(areas[1] / sum(areas))


def normal_force(tangential_force: float, pressure_angle: float, spiral_angle: float) -> float:
    """Nominal normal force ``F_n = F_mt1 / (cos(alpha_n) cos(beta_m1))`` (ISO 10300-2:2023
    Eq. 3 as corrected by ISO/TR 10300-30:2024), N."""
    return tangential_force / (math.cos(pressure_angle) * math.cos(spiral_angle))


def contact_stress_nominal(
    *, normal_force: float, l_bm: float, rho_rel: float, Z_MB: float, Z_LS: float, Z_E: float
) -> float:
    """``sigma_H0 = sqrt(F_n / (l_bm rho_rel)) Z_M-B Z_LS Z_E`` (ISO 10300-2:2023 Eq. 2),
    Pa for ``F_n`` in N, ``l_bm``, ``rho_rel`` in m and ``Z_E`` in sqrt(Pa)."""
    if not (l_bm > 0 and rho_rel > 0):
        raise ReducerlabError(f"l_bm, rho_rel: must be > 0; got {l_bm!r}, {rho_rel!r}")
    return math.sqrt(normal_force / (l_bm * rho_rel)) * Z_MB * Z_LS * Z_E
