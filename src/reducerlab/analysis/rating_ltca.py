"""Load capacity from the loaded tooth contact analysis: ISO 6336-1:2019 method A style
safety factors (clause 4.1.4: load factors and stresses "from a comprehensive analysis").

For every gear pair of a design the loaded tooth contact analysis
(:func:`reducerlab.analysis.contact.contact_analysis`, with the finite-element tooth-root
stresses, ``root_stress=True``) runs over one mesh cycle at the **factored** torque
``K_A K_v T`` on the pair's gear A (pinion, planet, the nutation pair's external gear).
The face and transverse load factors ``K_Hbeta``, ``K_Halpha`` (``K_Fbeta``,
``K_Falpha``) are **not** applied: the contact analysis distributes the load over the
face and among the tooth pairs itself, which is what they approximate. Then, per gear,

* ``sigma_H,A`` = the largest interior contact pressure over the cycle (the LTCA's
  ``interior_pressure``: the flank edges and the double-arc profile corner excluded),
  one value for both gears as in ISO 6336-2 with ``Z_B = Z_D = 1``;
* ``sigma_F,A`` = the largest principal stress on the loaded fillet of that gear over the
  cycle and the modelled tooth pairs (``root_stress``);
* the permissible stresses are those of ISO 6336-2/-3:2019 method B with the same
  material and life factors, ``sigma_HG = sigma_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X`` and
  ``sigma_FG = sigma_Flim Y_ST Y_NT Y_deltarelT Y_RrelT Y_X``; ``S_H = sigma_HG /
  sigma_H,A``, ``S_F = sigma_FG / sigma_F,A`` (Eq. 7 of part 2, Eq. 6 of part 3 with the
  analysed stresses). Where method B rates the pair, its factor values are used; for a
  pair method B does not cover (double circular-arc teeth) the factors that depend on
  the tooth form are chosen as recorded in ``docs/assumptions.md`` ("Method A"):
  ``Z_R`` at ``rho_red = 10 mm`` (``R_z10 = R_z``), ``Y_deltarelT = 1`` (the reference
  notch, ``q_s = 2.5``), ``Z_W = Z_X = 1``.

No standard rates double circular-arc teeth: for them the result is only the LTCA's
stresses against the material limits of ISO 6336-5, and says so.

Cost: the finite-element tooth models and the contact grid are estimated before any work
(``contact_analysis`` refuses a run beyond the memory limit with its estimate); the
positions are bounded by :data:`MAX_POSITIONS`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ReducerlabError
from ..rating import iso6336_2 as p2
from ..rating import iso6336_3 as p3
from ..rating.cylindrical import Factor, PairRating
from ..rating.material import GearMaterial, RatingConditions

__all__ = [
    "MAX_POSITIONS",
    "METHODS",
    "STANDARD_A",
    "MethodA",
    "PairLoad",
    "judged",
    "method_a_pairs",
    "rate_from_contact",
]

#: the rating methods of ``load_capacity``: ISO 6336 method B, the LTCA-based method A,
#: both, or ``auto`` (B where the standard covers the pair, A where it does not)
METHODS = ("auto", "A", "B", "both")
#: most positions over the mesh cycle a method A rating runs
MAX_POSITIONS = 48
#: what a method A rating is
STANDARD_A = (
    "method A (ISO 6336-1:2019 4.1.4): LTCA interior pressure and FE root stress at "
    "K_A K_v T against the ISO 6336-2/-3:2019 permissible stresses"
)
#: said of a pair that no standard covers
NO_STANDARD = (
    "; no standard rates double circular-arc teeth: only the LTCA stresses against the "
    "material limits (ISO 6336-5)"
)

Stage = Callable[[str], None]
Progress = Callable[[int, int], None]


@dataclass(frozen=True)
class MethodA:
    """Settings of a method A rating (the contact analysis behind it).

    Attributes
    ----------
    positions : int
        Positions over one mesh cycle, 2 to :data:`MAX_POSITIONS` (default 8: the peak
        pressure and root stress of a cycle, not its harmonics).
    tooth_size : float or None
        Element size of the finite-element tooth models (m); default the contact
        analysis's ``0.3 m_n``.
    cell : float or None
        Contact cell (m); default the contact analysis's automatic grid.
    workers : int or None
        Processes of the contact analysis (default its own choice).
    compliance : mapping or None
        Per pair label, the tooth compliances of an earlier method A rating of the same
        design (``result.contacts[label].compliance``, built with the root-stress
        influence): the finite-element models are then skipped, only the load changes.
    """

    positions: int = 8
    tooth_size: float | None = None
    cell: float | None = None
    workers: int | None = None
    compliance: Mapping[str, Any] | None = None

    def __post_init__(self) -> None:
        n = self.positions
        if isinstance(n, bool) or not isinstance(n, int) or not 2 <= n <= MAX_POSITIONS:
            raise ReducerlabError(
                f"positions: the method A rating needs an integer in [2, {MAX_POSITIONS}]; "
                f"got {n!r}"
            )
        for name in ("tooth_size", "cell"):
            v = getattr(self, name)
            if v is not None and not (
                isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
                and v > 0
            ):  # fmt: skip
                raise ReducerlabError(f"{name}: must be a length > 0 (m) or None; got {v!r}")
        w = self.workers
        if w is not None and (isinstance(w, bool) or not isinstance(w, int) or w < 1):
            raise ReducerlabError(f"workers: must be an integer >= 1 or None; got {w!r}")

    @property
    def order(self) -> int:
        """Harmonics of the contact run's stiffness fit (not used by the rating)."""
        return min(7, (self.positions - 1) // 2)


@dataclass(frozen=True)
class PairLoad:
    """One gear pair as the method A rating loads it (SI).

    Attributes
    ----------
    label : str
        The pair's label in the rating (``pair``, ``mesh K-V``, ``pair 1``).
    index : int
        The pair of ``contact_analysis`` (1 or 2).
    gears : (str, str)
        Names of gears 1 (the contact's gear A) and 2.
    torque : float
        Nominal torque on gear 1 (N m).
    speed : float
        Gear 1's speed relative to the mesh (rad/s), for its load cycles.
    ratio : float
        ``z_2 / z_1`` (the load cycles of gear 2: ``N_L1 / ratio``).
    radius : float
        Gear 1's pitch (mean) radius (m): the pitch line velocity ``speed * radius``.
    module : float
        Normal module (m), for ``Y_X``.
    double_arc : bool
        Double circular-arc teeth (no standard covers them).
    """

    label: str
    index: int
    gears: tuple[str, str]
    torque: float
    speed: float
    ratio: float
    radius: float
    module: float
    double_arc: bool = False


def _limits_from_b(b: PairRating, gear: str) -> dict[str, float]:
    """The permissible stresses (without ``S_min``) of method B's rows of ``gear``."""
    v = b.value
    shg = v("sigma_Hlim", gear) * v("Z_NT", gear)
    shg *= v("Z_L") * v("Z_v") * v("Z_R") * v("Z_W") * v("Z_X")
    sfg = v("sigma_Flim", gear) * v("Y_ST", gear) * v("Y_NT", gear)
    sfg *= v("Y_deltarelT", gear) * v("Y_RrelT", gear) * v("Y_X", gear)
    return {"sigma_HG": shg, "sigma_FG": sfg}


def _limits_own(
    load: PairLoad, materials: tuple[GearMaterial, GearMaterial], c: RatingConditions,
    row: Callable[..., float],
) -> list[dict[str, float]]:  # fmt: skip
    """The permissible stresses of a pair method B does not rate, every factor a row
    (``docs/assumptions.md``, "Method A": the tooth-form factors chosen)."""
    H2, H3 = "ISO 6336-2:2019", "ISO 6336-3:2019"
    v = row("v", "pair", load.speed * load.radius, "m/s", "pitch line velocity (mean point)")
    hlim = min(m.sigma_Hlim for m in materials)
    zl, zv = p2.lubrication_factors(hlim, c.viscosity_40, v)
    row("Z_L", "pair", zl, "1", f"{H2} Eq. 28 (nu_40 = {c.viscosity_40 * 1e6:g} mm^2/s)")
    row("Z_v", "pair", zv, "1", f"{H2} Eq. 32")
    zr = row("Z_R", "pair", p2.roughness_factor(hlim, c.rz_flank, 10e-3), "1",
             f"{H2} Eq. 33-37 at rho_red = 10 mm (R_z10 = R_z; assumption)")  # fmt: skip
    row("Z_W", "pair", 1.0, "1", f"{H2} clause 10 (equal hardness: 1)")
    row("Z_X", "pair", 1.0, "1", f"{H2} clause 11 (1: no size effect on pitting assumed)")
    yx = row("Y_X", "pair", p3.size_factor_root(load.module), "1", f"{H3} Table 8")
    yr = row("Y_RrelT", "pair", p3.roughness_factor_root(c.rz_root), "1", f"{H3} Eq. 51-52")
    ydel = row("Y_deltarelT", "pair", 1.0, "1",
               f"{H3} Eq. 46-48 at q_s = q_sT = 2.5 (assumption: the reference notch)")  # fmt: skip
    out = []
    speeds = (load.speed, load.speed / load.ratio)
    for i, mat in enumerate(materials):
        g = str(i + 1)
        n_l = row("N_L", g, speeds[i] / (2 * math.pi) * c.hours * 3600, "1", "load cycles")
        znt = row("Z_NT", g, p2.life_factor(n_l, mat.treatment), "1", f"{H2} Table 2")
        ynt = row("Y_NT", g, p3.life_factor(n_l, mat.treatment), "1", f"{H3} Table 4")
        row("sigma_Hlim", g, mat.sigma_Hlim, "Pa", "ISO 6336-5:2016 (material)")
        row("sigma_Flim", g, mat.sigma_Flim, "Pa", "ISO 6336-5:2016 (material)")
        row("Y_ST", g, 2.0, "1", f"{H3} clause 7 (reference test gear)")
        out.append({
            "sigma_HG": mat.sigma_Hlim * znt * zl * zv * zr,
            "sigma_FG": mat.sigma_Flim * 2.0 * ynt * ydel * yr * yx,
        })  # fmt: skip
    return out


def rate_from_contact(
    contact: Any,
    load: PairLoad,
    materials: tuple[GearMaterial, GearMaterial],
    conditions: RatingConditions,
    method_b: PairRating | None = None,
) -> PairRating:
    """Method A safety factors of one pair from its contact result (run with
    ``root_stress=True`` at ``K_A K_v`` times the nominal torque).

    Parameters
    ----------
    contact : ContactResult
        The loaded contact over a mesh cycle with the root-stress variables.
    load : PairLoad
    materials : (GearMaterial, GearMaterial)
    conditions : RatingConditions
        ``K_A``, ``K_v``, life, lubricant, roughness, ``S_Hmin``, ``S_Fmin``.
    method_b : PairRating, optional
        The pair's method B rating: its material and life factors are used.

    Returns
    -------
    PairRating
        ``S_H``, ``S_F`` of gears 1 and 2, rows suffixed ``_A`` for the analysed
        stresses and safety factors.
    """
    ds = contact.data
    if "root_stress" not in ds:
        raise ReducerlabError(
            "contact: the method A rating needs the root stresses (root_stress=True)"
        )
    c = conditions
    rows: list[Factor] = []

    def row(symbol: str, gear: str, value: float, unit: str, clause: str) -> float:
        rows.append(Factor(symbol, gear, float(value), unit, clause))
        return float(value)

    H1 = "ISO 6336-1:2019 4.1.4 (method A)"
    row("T_1", "pair", load.torque, "N m", "nominal torque on gear 1")
    t_a = row("T_A", "pair", float(ds.attrs["torque_external"]), "N m",
              f"{H1}: K_A K_v T_1 (K_A = {c.K_A:g}, K_v = {c.K_v:g}; K_Hbeta, K_Halpha "
              "not applied: the LTCA distributes the load)")  # fmt: skip
    if not math.isclose(t_a, c.K_A * c.K_v * load.torque, rel_tol=1e-9):
        raise ReducerlabError(
            f"contact: run at {t_a:.6g} N m, not K_A K_v T_1 = "
            f"{c.K_A * c.K_v * load.torque:.6g} N m"
        )
    row("positions", "pair", ds.sizes["position"], "1", "LTCA positions over the mesh cycle")
    row("edge_share_max", "pair", float(ds["edge_share"].max()), "1",
        "largest load share on flank-edge cells (LTCA)")  # fmt: skip
    if method_b is not None:
        limits = [_limits_from_b(method_b, g) for g in ("1", "2")]
    else:
        limits = _limits_own(load, materials, c, row)
    sh_a = row("sigma_H_A", "pair", float(ds["interior_pressure"].max()), "Pa",
               f"{H1}: largest interior LTCA pressure over the cycle")  # fmt: skip
    rs = np.asarray(ds["root_stress"].values, float)  # gear, position, tooth pair
    S_H, S_F = [], []
    for i, lim in enumerate(limits):
        g = str(i + 1)
        sf_a = float(np.nanmax(rs[i])) if np.isfinite(rs[i]).any() else math.nan
        if not (math.isfinite(sf_a) and sf_a > 0):
            raise ReducerlabError(
                f"contact: no tensile fillet stress of {load.gears[i]} in the tooth models "
                "(the fillet lies outside them); the method A rating cannot judge its root"
            )
        row("sigma_F_A", g, sf_a, "Pa", f"{H1}: largest principal fillet stress (FE)")
        # where: a peak at a face end or far from ISO's 30 deg tangent deserves a look
        # (docs/assumptions.md, "Method A": a known mesh-dependent defect)
        at = np.unravel_index(int(np.nanargmax(rs[i])), rs[i].shape)
        for name, var, unit in (("radius", "root_stress_radius", "m"),
                                ("face", "root_stress_face", "m"),
                                ("angle", "root_stress_angle", "rad")):  # fmt: skip
            row(f"sigma_F_A_{name}", g, float(ds[var].values[i][at]), unit,
                f"where sigma_F_A is ({name}: {var})")  # fmt: skip
        row("sigma_HP_A", g, lim["sigma_HG"] / c.S_Hmin, "Pa",
            f"ISO 6336-2:2019 Eq. 5-6 (S_Hmin = {c.S_Hmin:g})")  # fmt: skip
        row("sigma_FP_A", g, lim["sigma_FG"] / c.S_Fmin, "Pa",
            f"ISO 6336-3:2019 Eq. 4-5 (S_Fmin = {c.S_Fmin:g})")  # fmt: skip
        S_H.append(row("S_H_A", g, lim["sigma_HG"] / sh_a, "1", f"{H1}: sigma_HG / sigma_H_A"))
        S_F.append(row("S_F_A", g, lim["sigma_FG"] / sf_a, "1", f"{H1}: sigma_FG / sigma_F_A"))
    standard = STANDARD_A + (NO_STANDARD if load.double_arc else "")
    return PairRating((S_H[0], S_H[1]), (S_F[0], S_F[1]), rows, standard)


def method_a_pairs(
    design: Any,
    loads: list[PairLoad],
    materials: tuple[GearMaterial, GearMaterial],
    conditions: RatingConditions,
    settings: MethodA,
    method_b: dict[str, PairRating] | None = None,
    stage: Stage | None = None,
    progress: Progress | None = None,
    contacts: dict[str, Any] | None = None,
) -> dict[str, PairRating]:
    """Method A ratings of ``loads``' pairs: one contact analysis each (root stresses on)
    at ``K_A K_v`` times the nominal torque (:func:`rate_from_contact`); each contact
    result into ``contacts`` (by pair label) when given."""
    if not loads:
        return {}
    from .contact import contact_analysis
    from .contact_setup import pair_setup

    given = settings.compliance or {}
    say = stage or (lambda _s: None)
    # every pair's finite-element models estimated before the first one is built: a
    # second pair beyond the memory limit is refused before minutes of work on the first
    for load in loads:
        if given.get(load.label) is None:
            setup = pair_setup(design, load.index)
            setup.compliance_estimate(settings.tooth_size, root_stress=True).check()
    out = {}
    for load in loads:
        say(f"method A, {load.label}: contact analysis")
        wrapped = (
            (lambda text, lb=load.label, s=say: s(f"method A, {lb}: {text}")) if stage else None
        )
        r = contact_analysis(
            design, load.index, torque=conditions.K_A * conditions.K_v * load.torque,
            positions=settings.positions, order=settings.order, cell=settings.cell,
            tooth_size=settings.tooth_size, workers=settings.workers, stage=wrapped,
            progress=progress, root_stress=True, compliance=given.get(load.label),
        )  # fmt: skip
        if contacts is not None:
            contacts[load.label] = r
        b = (method_b or {}).get(load.label)
        out[load.label] = rate_from_contact(r, load, materials, conditions, b)
    return out


def judged(
    b: PairRating | None, a: PairRating | None, gears: tuple[str, str], method: str
) -> dict[str, Any]:
    """A pair's entry of the rating result: per method its ``S_H``, ``S_F`` and standard,
    and the judged ``S_H``, ``S_F`` (the verdict's): method B's alone, method A's alone
    (a pair method B does not cover, or ``method="A"``), or with both the smaller of the
    two per gear (``method="both"``: the more cautious; ``docs/assumptions.md``)."""
    methods = {}
    for key, r in (("B", b), ("A", a)):
        if r is not None:
            methods[key] = {"S_H": list(r.S_H), "S_F": list(r.S_F), "standard": r.standard}
    if a is not None and (b is None or method == "A"):
        use, by = a, "A"
    elif a is None:
        use, by = b, "B"
    else:
        use, by = None, "min(A, B)"
    if use is not None:
        s_h, s_f, standard = list(use.S_H), list(use.S_F), use.standard
    else:
        assert a is not None and b is not None
        s_h = [min(x, y) for x, y in zip(a.S_H, b.S_H, strict=True)]
        s_f = [min(x, y) for x, y in zip(a.S_F, b.S_F, strict=True)]
        standard = f"the smaller of {b.standard} and {a.standard}"
    return {
        "standard": standard, "gears": list(gears), "S_H": s_h, "S_F": s_f,
        "judged_by": by, "methods": methods,
    }  # fmt: skip
