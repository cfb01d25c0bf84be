"""Load capacity of a bevel pair: ISO 10300-1/-2/-3:2023 method B1 (default) or, on
request, the ISO 10300-1 virtual cylindrical gears rated by ISO 6336-2/-3:2019 method B.

``rate_bevel_pair(..., method="B1")`` (:func:`reducerlab.rating.bevel_b1.rate_b1`)
applies the bevel-specific factors of method B1 for bevel gears without hypoid offset:
the virtual cylindrical gears of ISO 10300-1 Annex A with the length of the middle
contact line ``l_bm`` (inclined contact lines) and the relative curvature ``rho_rel``;
the mid-zone factor ``Z_M-B``, load sharing factor ``Z_LS``, bevel gear factor ``Z_KP``
and ``Z_Hyp`` of ISO 10300-2; the tooth form at the tip (``Y_Fa``, ``Y_Sa``), ``Y_eps``,
``Y_BS`` and ``Y_LS`` of ISO 10300-3; ``K_Hbeta-C = 1.5 K_Hbeta-be`` and ``K_Fbeta =
K_Hbeta / K_F0`` of ISO 10300-1. The equations are in :mod:`~reducerlab.rating.iso10300_1`,
:mod:`~reducerlab.rating.iso10300_2`, :mod:`~reducerlab.rating.iso10300_3`, checked against
ISO/TR 10300-30:2024 sample 1 (``tests/published/test_iso10300_example.py``).
``K_v`` and ``K_Halpha`` stay inputs (``RatingConditions``): the designs hold no pitch
deviations, which their method B needs (the functions are there,
:func:`iso10300_1.dynamic_factor`, :func:`iso10300_1.transverse_load_factor`).

``method="iso6336"`` keeps the earlier approximation: the mean section's virtual gears
``d_v = d_m / cos(delta)``, ``z_v = z / cos(delta)``, helix angle ``beta_m``, rated by the
cylindrical gear equations of ISO 6336 method B (``Z_H``, ``Z_eps``, ``Z_beta``, load at
the outer point of single contact) -- no ``Z_M-B``, ``Z_LS``, ``Y_LS``, ``Y_BS``.

For the nutation drive's pairs (an internal bevel gear, the nutating gear, around an
external one, axes ``Sigma`` = the nutation angle apart, both cone angles below 90 deg)
the virtual pair is an **internal** helical pair: the external bevel gear's virtual gear
inside the internal one's (``z_v,i - z_v,e`` small). ISO 10300 covers external bevel
and hypoid gears; internal bevel pairs lie outside its scope. What method B1 needs and
does not define for them is chosen in ``docs/assumptions.md`` ("Load capacity of the
nutation pairs") and named in the result's label: the concave relative curvature, the
internal gear's ``Z_M-B`` bracket and tooth form (the ISO 6336-3 rack, load at the tip),
and ``Z_LS = Y_LS = 1`` where ``eps_vbeta < 1`` (the nutation examples' 0.57).

Scope of ISO 10300-2 that the nutation pairs keep: virtual transverse contact ratio
``eps_va < 2`` (checked), no profile shift, and within the range where the standard asks
for confirmation by experience beyond it (mean spiral angle <= 45 deg, effective pressure
angle <= 30 deg, face width <= 13 m_mn: the examples' 25 deg, 20 deg and 5 m_mn).

Assumptions: zero profile shift and the ISO 53 depths of the tooth surfaces
(``geometry.profiles.InvoluteProfile``: ``h_a* = 1``, ``h_f* = 1.25``, ``rho_f* =
0.38``) at the mean section, no tooth thickness modification, effective pressure angle
equal to the normal pressure angle (no limit pressure angle).
"""

from __future__ import annotations

import math

from ..errors import ReducerlabError
from . import iso6336_3 as p3
from .bevel_b1 import rate_b1
from .cylindrical import DEFAULTS, STEEL, MeshData, PairRating, rate_mesh
from .material import GearMaterial, RatingConditions

__all__ = ["METHODS", "rate_bevel_pair", "virtual_pair"]

#: the rating methods of :func:`rate_bevel_pair`
METHODS = ("B1", "iso6336")


def virtual_pair(
    *,
    teeth: tuple[int, int],
    mean_radii: tuple[float, float],
    cone_angles: tuple[float, float],
    normal_module: float,
    spiral_angle: float,
    pressure_angle: float,
    internal: bool,
) -> dict[str, float]:
    """The virtual cylindrical gears of a bevel pair at the mean section (ISO 10300-1:2014
    clause 6): gear 1 the external (driving side of the rating), gear 2 the other.

    Returns ``d_v1, d_v2`` (m), ``z_v1, z_v2``, ``d_va``, ``d_vb``, ``a_v`` (m),
    ``alpha_vet`` (rad), ``beta_vb`` (rad), ``eps_va``, ``p_vet`` (m).
    """
    (z1, z2), (r1, r2), (d1c, d2c) = teeth, mean_radii, cone_angles
    for name, v in (("normal_module", normal_module), ("mean_radius", min(r1, r2))):
        if not (math.isfinite(v) and v > 0):
            raise ReducerlabError(f"{name}: must be > 0; got {v!r}")
    if not all(0 < d < math.radians(89.0) for d in (d1c, d2c)):
        raise ReducerlabError(
            "cone_angles: the virtual cylindrical gears need pitch cone angles below 89 deg"
        )
    mn, bm, an = normal_module, spiral_angle, pressure_angle
    dv1, dv2 = 2 * r1 / math.cos(d1c), 2 * r2 / math.cos(d2c)
    zv1, zv2 = z1 / math.cos(d1c), z2 / math.cos(d2c)
    avet = math.atan(math.tan(an) / math.cos(bm))
    bvb = math.asin(math.sin(bm) * math.cos(an))
    ham = mn  # h_a* = 1
    dva1 = dv1 + 2 * ham
    dva2 = dv2 - 2 * ham if internal else dv2 + 2 * ham
    dvb1, dvb2 = dv1 * math.cos(avet), dv2 * math.cos(avet)
    av = (dv2 - dv1) / 2 if internal else (dv1 + dv2) / 2
    p_vet = math.pi * mn / math.cos(bm) * math.cos(avet)
    t1 = math.sqrt(dva1**2 - dvb1**2) / 2
    t2 = math.sqrt(max(dva2**2 - dvb2**2, 0.0)) / 2
    g = (t1 - t2 + av * math.sin(avet)) if internal else (t1 + t2 - av * math.sin(avet))
    return {
        "d_v1": dv1, "d_v2": dv2, "z_v1": zv1, "z_v2": zv2, "d_va1": dva1, "d_va2": dva2,
        "d_vb1": dvb1, "d_vb2": dvb2, "a_v": av, "alpha_vet": avet, "beta_vb": bvb,
        "eps_va": g / p_vet, "p_vet": p_vet,
    }  # fmt: skip


def rate_bevel_pair(
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
    internal: bool = True,
    materials: tuple[GearMaterial, GearMaterial] = (STEEL, STEEL),
    conditions: RatingConditions = DEFAULTS,
    method: str = "B1",
    mounting: str = "both-straddle",
    verification: str = "light-load-test",
) -> PairRating:
    """Rate a bevel pair: ISO 10300 method B1 or its virtual cylindrical gears by ISO 6336
    (see the module docstring).

    Parameters
    ----------
    teeth, mean_radii, cone_angles : tuple
        Of gear 1 (the external bevel gear) and gear 2 (internal when ``internal``):
        teeth, mean pitch radii ``r_m`` (m), pitch cone angles ``delta`` (rad).
    normal_module, spiral_angle, pressure_angle : float
        ``m_mn`` (m), ``beta_m`` and ``alpha_n`` (rad) at the mean section.
    face_width : float
        ``b`` (m).
    torque : float
        Torque on gear 1 (N m); the tangential force at the mean radius
        ``F_mt = T / r_m1`` is that of its virtual gear.
    speed : float
        Gear 1's speed relative to the other gear's axis frame (rad/s; the nutation
        drive: the mesh frequency over the teeth).
    method : str
        ``"B1"``: ISO 10300-1/-2/-3:2023 method B1; ``"iso6336"``: the virtual
        cylindrical gears rated by ISO 6336-2/-3:2019 method B.
    mounting, verification : str
        Method B1's mounting factor ``K_Hbeta-be`` (ISO 10300-1 Table 4): the mounting
        (``both-straddle``, ``one-cantilever``, ``both-cantilever``) and the contact
        pattern check (``full-load``, ``light-load-test``, ``light-load-assembly``).
    """
    if method not in METHODS:
        raise ReducerlabError(f"method: one of {', '.join(METHODS)}; got {method!r}")
    if method == "B1":
        for name, val in (("torque", torque), ("speed", speed), ("face_width", face_width)):
            if not (math.isfinite(val) and val > 0):
                raise ReducerlabError(f"{name}: must be a finite number > 0; got {val!r}")
        return rate_b1(
            teeth=teeth, mean_radii=mean_radii, cone_angles=cone_angles,
            normal_module=normal_module, spiral_angle=spiral_angle,
            pressure_angle=pressure_angle, face_width=face_width, torque=torque, speed=speed,
            internal=internal, materials=materials, conditions=conditions,
            mounting=mounting, verification=verification,
        )  # fmt: skip
    v = virtual_pair(
        teeth=teeth, mean_radii=mean_radii, cone_angles=cone_angles,
        normal_module=normal_module, spiral_angle=spiral_angle,
        pressure_angle=pressure_angle, internal=internal,
    )  # fmt: skip
    mn, bm, an, b = normal_module, spiral_angle, pressure_angle, face_width
    if not (math.isfinite(b) and b > 0):
        raise ReducerlabError(f"face_width: must be > 0; got {b!r}")
    eps = v["eps_va"]
    if not 1.0 < eps < 2.0:
        # ISO 10300-2/-3:2014 scope: virtual cylindrical gears with eps_va < 2
        raise ReducerlabError(
            f"teeth: the virtual pair's transverse contact ratio {eps:.4g} must lie in (1, 2) "
            "(ISO 10300-2:2014 scope)"
        )
    form1 = p3.tooth_form(
        teeth=v["z_v1"], module=mn, pressure_angle=an, shift=0.0, tip_diameter=v["d_va1"],
        contact_ratio=eps, helix_angle=bm,
    )  # fmt: skip
    if internal:
        # the internal virtual gear in its normal section (a rack approximation anyway):
        # radii of the normal-section virtual gear, its outer point of single contact
        # (eps_alpha_n - 1) p_bn outwards from its tip contact
        cb2 = math.cos(v["beta_vb"]) ** 2
        r_n = v["d_v2"] / (2 * cb2)
        r_bn = r_n * math.cos(an)
        r_an = r_n - mn
        r_fn = r_n + 1.25 * mn
        xi = math.sqrt(max(r_an**2 - r_bn**2, 0.0)) + (eps / cb2 - 1) * math.pi * mn * math.cos(an)
        form2 = p3.internal_tooth_form(
            module=mn, pressure_angle=an, tooth_thickness=math.pi * mn / 2,
            reference_height=1.25 * mn, tooth_depth=2.25 * mn,
            load_height=r_fn - math.hypot(r_bn, xi),
        )  # fmt: skip
    else:
        form2 = p3.tooth_form(
            teeth=v["z_v2"], module=mn, pressure_angle=an, shift=0.0, tip_diameter=v["d_va2"],
            contact_ratio=eps, helix_angle=bm,
        )  # fmt: skip
    mesh = MeshData(
        z=(v["z_v1"], -v["z_v2"] if internal else v["z_v2"]),  # type: ignore[arg-type]
        d=(v["d_v1"], v["d_v2"]),
        da=(v["d_va1"], v["d_va2"]),
        db=(v["d_vb1"], v["d_vb2"]),
        alpha=v["alpha_vet"],
        alpha_w=v["alpha_vet"],
        eps=eps,
        b=b,
        m=mn,
        depth=2.25 * mn,
        forms=(form1, form2),
        beta=bm,
        eps_beta=b * math.sin(bm) / (math.pi * mn),
        cycle_ratio=teeth[1] / teeth[0],
        cycle_speed=speed,
    )
    # F_mt = T / r_m1 on the virtual gear of reference diameter d_v1: the torque that
    # gives it on d_v1
    t_virtual = torque / mean_radii[0] * v["d_v1"] / 2
    # the virtual gear turns so that its pitch line velocity is the real one, omega r_m1
    w_virtual = speed * mean_radii[0] / (v["d_v1"] / 2)
    r = rate_mesh(mesh, t_virtual, w_virtual, materials, conditions)
    return PairRating(
        r.S_H,
        r.S_F,
        r.factors,
        "ISO 10300-1:2014 virtual cylindrical gears rated by ISO 6336-2/-3:2019 method B "
        "(method iso6336, not ISO 10300 method B1: no Z_M-B, Z_LS, Z_KP, Y_LS, Y_BS)",
    )
