"""Load capacity of a cylindrical spur pair, external or internal (ISO 6336-2/-3:2019
method B): every factor with its clause, and the safety factors ``S_H`` and ``S_F`` of
both gears.

:func:`rate_spur_pair` rates a :class:`~reducerlab.geometry.spur.SpurPair` (the
``gear_pair`` design); :func:`rate_internal_pair` an
:class:`~reducerlab.geometry.internal_pair.InternalGearPair` (the KHV drive: planet in
ring). The load is the torque on gear 1 (pinion, planet) and the speed its speed
relative to the carrier (the mesh's own speed); SI units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import ReducerlabError
from ..geometry.internal_pair import InternalGearPair
from ..geometry.spur import SpurGear, SpurPair
from . import iso6336_2 as p2
from . import iso6336_3 as p3
from .material import GearMaterial, RatingConditions

__all__ = [
    "DEFAULTS",
    "STEEL",
    "Factor",
    "MeshData",
    "PairRating",
    "rate_internal_pair",
    "rate_mesh",
    "rate_spur_pair",
]

#: the default material of both gears (case-hardened steel MQ, ISO 6336-5)
STEEL = GearMaterial()
#: the default rating conditions (:class:`~reducerlab.rating.material.RatingConditions`)
DEFAULTS = RatingConditions()


@dataclass(frozen=True)
class Factor:
    """One row of a rating: ``symbol`` of ``gear`` (``"pair"``, ``"1"``, ``"2"``), its
    ``value`` (SI), ``unit`` (SI) and the ``clause`` (standard, edition, equation)."""

    symbol: str
    gear: str
    value: float
    unit: str
    clause: str


@dataclass(frozen=True)
class PairRating:
    """Safety factors ``S_H`` and ``S_F`` of gears 1 and 2 and every factor behind them."""

    S_H: tuple[float, float]
    S_F: tuple[float, float]
    factors: list[Factor] = field(default_factory=list)
    standard: str = "ISO 6336-2:2019 / ISO 6336-3:2019, method B"

    def value(self, symbol: str, gear: str = "pair") -> float:
        """The value of ``symbol`` for ``gear``."""
        for f in self.factors:
            if f.symbol == symbol and f.gear == gear:
                return f.value
        raise ReducerlabError(f"symbol: no factor {symbol!r} for gear {gear!r}")


@dataclass(frozen=True)
class MeshData:
    """A cylindrical pair as the rating sees it (SI): teeth (``z_2 < 0`` internal),
    reference, tip and base diameters, transverse and working pressure angles, contact
    ratio, face width, normal module, tooth depth, the tooth forms of both gears, helix
    angle and overlap ratio, and for virtual gears the real speed ratio and speed that
    count the load cycles."""

    z: tuple[int, int]  # z2 < 0 for an internal gear
    d: tuple[float, float]  # reference diameters (m, > 0)
    da: tuple[float, float]
    db: tuple[float, float]
    alpha: float
    alpha_w: float
    eps: float
    b: float
    m: float
    depth: float  # tooth depth h (m)
    forms: tuple[p3.ToothForm, p3.ToothForm]
    beta: float = 0.0  # helix angle (rad); alpha, alpha_w are then transverse angles
    eps_beta: float = 0.0  # overlap ratio
    cycle_ratio: float | None = None  # n_1 / n_2 for the load cycles (default |u|)
    cycle_speed: float | None = None  # gear 1's speed for its load cycles (default: speed)


def _check_load(torque: float, speed: float) -> None:
    if not (math.isfinite(torque) and torque > 0):
        raise ReducerlabError(f"torque: must be a finite number > 0 (N m); got {torque!r}")
    if not (math.isfinite(speed) and speed > 0):
        raise ReducerlabError(f"speed: must be a finite number > 0 (rad/s); got {speed!r}")


def rate_spur_pair(
    pair: SpurPair,
    torque: float,
    speed: float,
    materials: tuple[GearMaterial, GearMaterial] = (STEEL, STEEL),
    conditions: RatingConditions = DEFAULTS,
) -> PairRating:
    """Rate an external spur pair: ``torque`` on the pinion (N m), pinion ``speed``
    (rad/s); tooth forms from the generated teeth (:func:`iso6336_3.spur_tooth_form`)."""
    _check_load(torque, speed)
    g1, g2 = pair.pinion, pair.wheel
    mesh = MeshData(
        z=(g1.teeth, g2.teeth),
        d=(2 * g1.reference_radius, 2 * g2.reference_radius),
        da=(2 * g1.tip_radius, 2 * g2.tip_radius),
        db=(2 * g1.base_radius, 2 * g2.base_radius),
        alpha=g1.pressure_angle,
        alpha_w=pair.working_pressure_angle,
        eps=pair.contact_ratio,
        b=min(g1.face_width, g2.face_width),
        m=g1.module,
        depth=min(g.tip_radius - g.root_radius for g in (g1, g2)),
        forms=(p3.spur_tooth_form(pair, "pinion"), p3.spur_tooth_form(pair, "wheel")),
    )
    return rate_mesh(mesh, torque, speed, materials, conditions)


def rate_internal_pair(
    pair: InternalGearPair,
    torque: float,
    speed: float,
    materials: tuple[GearMaterial, GearMaterial] = (STEEL, STEEL),
    conditions: RatingConditions = DEFAULTS,
    dedendum: float = 1.25,
    root_fillet: float = 0.38,
) -> PairRating:
    """Rate an internal spur pair (gear 1 external in ring gear 2): ``torque`` on gear 1
    (N m), ``speed`` its speed relative to the carrier (rad/s). Gear 1's tooth form from
    its generated tooth (ISO 53 rack ``dedendum``, ``root_fillet``); the ring's by the
    rack approximation of ISO 6336-3 (:func:`iso6336_3.internal_tooth_form`)."""
    _check_load(torque, speed)
    m, a = pair.module, pair.pressure_angle
    if not pair.face_width > 0:
        raise ReducerlabError("face_width: the internal pair needs a face width > 0")
    try:
        g1 = SpurGear(
            pair.z1, m, pair.face_width, a, pair.x1, addendum=pair.addendum,
            dedendum=dedendum, root_fillet=root_fillet,
        )  # fmt: skip
    except ReducerlabError as e:
        raise ReducerlabError(f"x1 (planet): {e}") from None
    eps = pair.contact_ratio
    form1 = p3.tooth_form(
        teeth=pair.z1, module=m, pressure_angle=a, shift=pair.x1,
        tip_diameter=2 * pair.tip_radius(1), contact_ratio=eps, dedendum=dedendum,
        root_fillet=root_fillet,
    )  # fmt: skip
    # the ring: radii grow from its tip outwards; its outer point of single contact lies
    # (eps - 1) p_b along the line of action from its tip contact
    rb2, ra2 = pair.base_radius(2), pair.tip_radius(2)
    r2 = pair.pitch_radius(2)
    rf2 = r2 + m * (dedendum + pair.x2)
    xi_en2 = math.sqrt(max(ra2**2 - rb2**2, 0.0)) + (eps - 1) * pair.base_pitch
    r_en2 = math.hypot(rb2, xi_en2)
    form2 = p3.internal_tooth_form(
        module=m, pressure_angle=a,
        tooth_thickness=m * (math.pi / 2 - 2 * pair.x2 * math.tan(a)),
        reference_height=rf2 - r2, tooth_depth=rf2 - ra2, load_height=rf2 - r_en2,
        root_fillet=root_fillet,
    )  # fmt: skip
    mesh = MeshData(
        z=(pair.z1, -pair.z2),
        d=(2 * pair.pitch_radius(1), 2 * r2),
        da=(2 * pair.tip_radius(1), 2 * ra2),
        db=(2 * pair.base_radius(1), 2 * rb2),
        alpha=a,
        alpha_w=pair.working_pressure_angle,
        eps=eps,
        b=pair.face_width,
        m=m,
        depth=min(g1.tip_radius - g1.root_radius, rf2 - ra2),
        forms=(form1, form2),
    )
    return rate_mesh(mesh, torque, speed, materials, conditions)


def rate_mesh(
    mesh: MeshData,
    torque: float,
    speed: float,
    materials: tuple[GearMaterial, GearMaterial],
    c: RatingConditions,
) -> PairRating:
    """Rate ``mesh`` under ``torque`` on gear 1 (N m) at gear 1's ``speed`` (rad/s): the
    ISO 6336-2/-3:2019 method B chain, every factor a row of the result."""
    rows: list[Factor] = []
    H2, H3, H1 = "ISO 6336-2:2019", "ISO 6336-3:2019", "ISO 6336-1:2019"

    def row(symbol: str, gear: str, value: float, unit: str, clause: str) -> float:
        rows.append(Factor(symbol, gear, float(value), unit, clause))
        return float(value)

    z1, z2 = mesh.z
    d1 = mesh.d[0]
    u = z2 / z1
    ft = row("F_t", "pair", 2 * torque / d1, "N", f"{H1} Eq. 1 (2 T_1 / d_1)")
    v = row("v", "pair", speed * d1 / 2, "m/s", f"{H1} (pitch line velocity)")
    row("eps_alpha", "pair", mesh.eps, "1", "ISO 21771 (transverse contact ratio)")
    for name in ("K_A", "K_v", "K_Hbeta", "K_Halpha"):
        row(name, "pair", getattr(c, name), "1", f"{H1} (input, RatingConditions)")
    kfb = row(
        "K_Fbeta", "pair", p3.face_load_factor_root(c.K_Hbeta, mesh.b, mesh.depth), "1",
        f"{H3} Eq. 35-36",
    )  # fmt: skip
    # ---- pitting
    m1, m2 = materials
    beta_b = math.asin(
        math.sin(mesh.beta) * math.cos(math.atan(math.tan(mesh.alpha) * math.cos(mesh.beta)))
    )
    zh = row("Z_H", "pair", p2.zone_factor(mesh.alpha, mesh.alpha_w, beta_b), "1", f"{H2} Eq. 9")
    ze = row(
        "Z_E", "pair",
        p2.elasticity_factor(m1.youngs_modulus, m1.poisson_ratio, m2.youngs_modulus,
                             m2.poisson_ratio),
        "sqrt(Pa)", f"{H2} Eq. 23",
    )  # fmt: skip
    if mesh.beta:
        row("eps_beta", "pair", mesh.eps_beta, "1", "ISO 21771 (overlap ratio)")
    zeps = row("Z_eps", "pair", p2.contact_ratio_factor(mesh.eps, mesh.eps_beta), "1",
               f"{H2} Eq. 10-12")  # fmt: skip
    zbeta = row("Z_beta", "pair", p2.helix_factor(mesh.beta), "1", f"{H2} Eq. 13")
    zb, zd = p2.single_pair_factors(
        tip_diameters=mesh.da, base_diameters=mesh.db, teeth=mesh.z, alpha_wt=mesh.alpha_w,
        eps_alpha=mesh.eps, eps_beta=mesh.eps_beta,
    )  # fmt: skip
    row("Z_B", "1", zb, "1", f"{H2} Eq. 14-16")
    row("Z_D", "2", zd, "1", f"{H2} Eq. 17-19")
    sh0 = row(
        "sigma_H0", "pair",
        p2.contact_stress_nominal(Z_H=zh, Z_E=ze, Z_eps=zeps, Z_beta=zbeta,
                                  tangential_load=ft, pinion_diameter=d1, face_width=mesh.b,
                                  ratio=u),
        "Pa", f"{H2} Eq. 2",
    )  # fmt: skip
    k_h = math.sqrt(c.K_A * c.K_v * c.K_Hbeta * c.K_Halpha)
    rb = (0.5 * mesh.db[0] * math.tan(mesh.alpha_w), 0.5 * mesh.db[1] * math.tan(mesh.alpha_w))
    rho_red = rb[0] * rb[1] / (rb[1] + rb[0]) if z2 > 0 else rb[0] * rb[1] / (rb[1] - rb[0])
    row("rho_red", "pair", rho_red, "m", f"{H2} Eq. 35")
    hlim_soft = min(m1.sigma_Hlim, m2.sigma_Hlim)
    zl, zv = p2.lubrication_factors(hlim_soft, c.viscosity_40, v)
    row("Z_L", "pair", zl, "1", f"{H2} Eq. 28 (nu_40 = {c.viscosity_40 * 1e6:g} mm^2/s)")
    row("Z_v", "pair", zv, "1", f"{H2} Eq. 32")
    zr = row("Z_R", "pair", p2.roughness_factor(hlim_soft, c.rz_flank, rho_red), "1",
             f"{H2} Eq. 33-37")  # fmt: skip
    row("Z_W", "pair", 1.0, "1", f"{H2} clause 10 (equal hardness: 1)")
    row("Z_X", "pair", 1.0, "1", f"{H2} clause 11 (1: no size effect on pitting assumed)")
    ratio = abs(u) if mesh.cycle_ratio is None else mesh.cycle_ratio
    n1 = speed if mesh.cycle_speed is None else mesh.cycle_speed
    speeds = (n1, n1 / ratio)
    ybeta = p3.helix_factor(mesh.eps_beta, mesh.beta)
    eps_n = mesh.eps / math.cos(beta_b) ** 2  # virtual contact ratio eps_alpha_n
    S_H, S_F = [], []
    hours_s = c.hours * 3600
    for i, (mat, zbd, form) in enumerate(zip(materials, (zb, zd), mesh.forms, strict=True)):
        g = str(i + 1)
        n_l = row("N_L", g, speeds[i] / (2 * math.pi) * hours_s, "1", "load cycles")
        sh = row("sigma_H", g, zbd * sh0 * k_h, "Pa", f"{H2} Eq. 3-4")
        znt = row("Z_NT", g, p2.life_factor(n_l, mat.treatment), "1", f"{H2} Table 2")
        shg = mat.sigma_Hlim * znt * zl * zv * zr
        row("sigma_Hlim", g, mat.sigma_Hlim, "Pa", "ISO 6336-5:2016 (material)")
        row("sigma_HP", g, shg / c.S_Hmin, "Pa", f"{H2} Eq. 5-6 (S_Hmin = {c.S_Hmin:g})")
        S_H.append(row("S_H", g, shg / sh, "1", f"{H2} Eq. 7"))
        # ---- bending
        row("Y_F", g, form.Y_F, "1", f"{H3} Eq. 8")
        row("Y_S", g, form.Y_S, "1", f"{H3} Eq. 26")
        row("h_Fe", g, form.h_Fe, "m", f"{H3} Eq. 18")
        row("s_Fn", g, form.s_Fn, "m", f"{H3} Eq. 16")
        row("rho_F", g, form.rho_F, "m", f"{H3} Eq. 17")
        row("alpha_Fen", g, form.alpha_Fen, "rad", f"{H3} Eq. 24")
        row("Y_beta", g, ybeta, "1", f"{H3} Eq. 32")
        yb = row(
            "Y_B", g,
            p3.rim_factor(c.rim_thickness, mesh.depth, internal=(i == 1 and z2 < 0),
                          module=mesh.m),
            "1", f"{H3} Eq. 37-40",
        )  # fmt: skip
        ydt = row("Y_DT", g, p3.deep_tooth_factor(eps_n, c.accuracy_grade), "1",
                  f"{H3} Eq. 41-43")  # fmt: skip
        sf0 = row("sigma_F0", g, p3.root_stress_nominal(ft, mesh.b, mesh.m, form, ybeta, yb, ydt),
                  "Pa", f"{H3} Eq. 3")  # fmt: skip
        sf = row("sigma_F", g, sf0 * c.K_A * c.K_v * kfb * c.K_Halpha, "Pa", f"{H3} Eq. 2")
        ynt = row("Y_NT", g, p3.life_factor(n_l, mat.treatment), "1", f"{H3} Table 4")
        ydel = row("Y_deltarelT", g, p3.notch_sensitivity_factor(form.q_s), "1",
                   f"{H3} Eq. 46-48")  # fmt: skip
        yr = row("Y_RrelT", g, p3.roughness_factor_root(c.rz_root), "1", f"{H3} Eq. 51-52")
        yx = row("Y_X", g, p3.size_factor_root(mesh.m), "1", f"{H3} Table 8")
        row("Y_ST", g, 2.0, "1", f"{H3} clause 7 (reference test gear)")
        row("sigma_Flim", g, mat.sigma_Flim, "Pa", "ISO 6336-5:2016 (material)")
        sfg = mat.sigma_Flim * 2.0 * ynt * ydel * yr * yx
        row("sigma_FP", g, sfg / c.S_Fmin, "Pa", f"{H3} Eq. 4-5 (S_Fmin = {c.S_Fmin:g})")
        S_F.append(row("S_F", g, sfg / sf, "1", f"{H3} Eq. 6"))
    return PairRating((S_H[0], S_H[1]), (S_F[0], S_F[1]), rows)
