"""Load capacity of a design's gear pairs: pitting and tooth root safety factors
(issue 29).

``load_capacity(design, torque=..., power=..., conditions=...)`` rates

* a ``gear_pair`` design's spur pair (ISO 6336-2/-3:2019 method B,
  :func:`reducerlab.rating.cylindrical.rate_spur_pair`), the load the pinion's torque
  at ``operating.speed``;
* a ``khv`` design's internal pair, planet in ring
  (:func:`reducerlab.rating.cylindrical.rate_internal_pair`), the load the planet's
  torque (the drive's output torque: the planet drives the output through the W
  mechanism) at the planet's speed relative to the carrier;
* a ``nutation`` design's bevel pairs by ISO 10300-1/-2/-3:2023 method B1
  (:func:`reducerlab.rating.bevel.rate_bevel_pair`: virtual cylindrical gears with
  ``l_bm`` and ``rho_rel``, ``Z_M-B``, ``Z_LS``, ``Z_KP``, ``Y_Fa``, ``Y_Sa``, ``Y_eps``,
  ``Y_BS``, ``Y_LS``, ``K_Hbeta-C``; the internal pair's extensions in
  ``docs/assumptions.md``),
  the load each pair's torque from the lossless torque flow.

The result lists every factor with its value, unit and clause, and ``S_H``, ``S_F`` per
gear (``pair``: which pair, ``gear``: ``1`` or ``2`` of that pair).

``method`` adds or replaces these by method A, the safety factors from the loaded tooth
contact analysis and its FE root stresses (:mod:`reducerlab.analysis.rating_ltca`):
by default (``auto``) for the pairs method B does not cover, the double circular-arc
nutation pairs, which no standard rates.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from functools import partial
from typing import Any, ClassVar

import numpy as np
import xarray as xr

from ..design import Design
from ..errors import ReducerlabError
from ..numformat import Column, Table, Value, fmt, unit_kind
from ..rating.cylindrical import PairRating, rate_internal_pair, rate_spur_pair
from ..rating.material import GearMaterial, RatingConditions
from ..results import Result, provenance
from .rating_ltca import METHODS, MethodA, PairLoad, judged, method_a_pairs

__all__ = ["RatingResult", "design_materials", "load_capacity"]


class RatingResult(Result):
    """Load capacity of a design's gear pairs.

    ``data`` has dimension ``factor`` with ``pair`` (label of the pair), ``symbol``,
    ``gear`` (``pair``, ``1``, ``2``), ``value`` (SI), ``unit`` and ``clause`` (the
    standard, edition and equation); attributes ``pairs`` (JSON: per pair its standard,
    ``S_H`` and ``S_F`` of gears 1 and 2, the gears' names), ``torque`` and the
    provenance.
    """

    kind: ClassVar[str] = "rating"
    #: method A's contact results by pair label (in memory only, not in the netCDF file)
    contacts: dict[str, Any] | None = None

    def pairs(self) -> dict[str, dict[str, Any]]:
        """Per pair: ``standard``, ``gears`` (names), ``S_H`` and ``S_F`` (gear 1, 2: the
        judged values), ``judged_by`` (``A``, ``B`` or ``min(A, B)``) and ``methods``
        (per method ``A``/``B`` computed: its ``S_H``, ``S_F`` and standard)."""
        return dict(json.loads(self.data.attrs["pairs"]))

    def value(self, symbol: str, gear: str = "pair", pair: str | None = None) -> float:
        """The value (SI) of ``symbol`` for ``gear`` of ``pair`` (default: the first)."""
        ds = self.data
        pair = pair or next(iter(self.pairs()))
        m = (ds["symbol"].values == symbol) & (ds["gear"].values == gear)
        m &= ds["pair"].values == pair
        if not m.any():
            raise ReducerlabError(f"symbol: no factor {symbol!r} of gear {gear!r} in {pair!r}")
        return float(ds["value"].values[m][0])

    @property
    def minimum_safety(self) -> dict[str, float]:
        """The smallest ``S_H`` and ``S_F`` over all gears of all pairs."""
        p = self.pairs().values()
        return {"S_H": min(min(v["S_H"]) for v in p), "S_F": min(min(v["S_F"]) for v in p)}

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the pairs' safety factors and every factor row."""
        ds = self.data
        rows = [
            {
                "pair": str(ds["pair"].values[i]),
                "symbol": str(ds["symbol"].values[i]),
                "gear": str(ds["gear"].values[i]),
                "value": float(ds["value"].values[i]),
                "unit": str(ds["unit"].values[i]),
                "clause": str(ds["clause"].values[i]),
            }
            for i in range(ds.sizes["factor"])
        ]
        return {"pairs": self.pairs(), "factors": rows}

    def figure(self) -> Any:
        """Bars of ``S_H`` and ``S_F`` per gear against their minimums
        (:func:`reducerlab.plot.rating.plot_rating`)."""
        from ..plot.rating import plot_rating

        return plot_rating(self)

    def table(self) -> str:
        """Plain-text table: per pair the safety factors, then every factor (MPa and mm
        where SI would print Pa and m)."""
        lines = []
        ds = self.data
        for label, p in self.pairs().items():
            g1, g2 = p["gears"]
            lines.append(f"{label}: {p['standard']}")
            sf = partial(fmt, kind="safety")
            lines.append(
                f"  S_H: {g1} {sf(p['S_H'][0])}, {g2} {sf(p['S_H'][1])}   "
                f"S_F: {g1} {sf(p['S_F'][0])}, {g2} {sf(p['S_F'][1])}"
                + (f"   (judged by {p['judged_by']})" if len(p.get("methods", {})) > 1 else "")
            )
            for key, m in p.get("methods", {}).items() if len(p.get("methods", {})) > 1 else ():
                lines.append(
                    f"    method {key}: S_H {sf(m['S_H'][0])}, {sf(m['S_H'][1])}   "
                    f"S_F {sf(m['S_F'][0])}, {sf(m['S_F'][1])}"
                )
            t = Table([Column("symbol", kind="text"), Column("gear", kind="text"), Column("value"),
                       Column("unit", kind="text"), Column("clause", kind="text")])  # fmt: skip
            for i in np.nonzero(ds["pair"].values == label)[0]:
                unit, v = str(ds["unit"].values[i]), float(ds["value"].values[i])
                if unit == "Pa":
                    unit, v = "MPa", v / 1e6
                elif unit == "m":
                    unit, v = "mm", v * 1e3
                elif unit == "sqrt(Pa)":
                    unit, v = "sqrt(MPa)", v / 1e3
                elif unit == "rad":
                    unit, v = "deg", math.degrees(v)
                gear = str(ds["gear"].values[i])
                symbol = str(ds["symbol"].values[i])
                kind = "safety" if symbol.startswith(("S_H", "S_F")) else unit_kind(unit)
                t.add(symbol, {"1": g1, "2": g2}.get(gear, gear), Value(v, kind), unit,
                      str(ds["clause"].values[i]))  # fmt: skip
            lines.append(t.text(indent="  "))
        return "\n".join(lines)


def design_materials(design: Design) -> GearMaterial:
    """The rating material of a design's ``[material]`` table."""
    m = getattr(design, "material", None)
    if m is None:
        raise ReducerlabError("material: this design has no [material] table")
    return GearMaterial(
        youngs_modulus=float(m.youngs_modulus),
        poisson_ratio=float(m.poisson_ratio),
        sigma_Hlim=float(m.sigma_Hlim),
        sigma_Flim=float(m.sigma_Flim),
        treatment=str(m.treatment),
    )


def _pinion_torque(design: Design, torque: float | None, power: float | None) -> float | None:
    if torque is not None and power is not None:
        raise ReducerlabError("torque/power: give at most one of them")
    if torque is not None:
        if not (math.isfinite(torque) and torque > 0):
            raise ReducerlabError(f"torque: must be > 0 (N m); got {torque!r}")
        return float(torque)
    if power is not None:
        if not (math.isfinite(power) and power > 0):
            raise ReducerlabError(f"power: must be > 0 (W); got {power!r}")
        return None  # resolved per design from its speed
    return None


def load_capacity(
    design: Design,
    *,
    torque: float | None = None,
    power: float | None = None,
    conditions: RatingConditions | None = None,
    method: str = "auto",
    ltca: MethodA | None = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> RatingResult:
    """Rate every gear pair of ``design`` (ISO 6336-2/-3:2019; ISO 10300-1/-2/-3:2023
    method B1 for bevel pairs; method A from the loaded tooth contact analysis,
    :mod:`reducerlab.analysis.rating_ltca`).

    Parameters
    ----------
    design : Design
        A ``gear_pair``, ``khv`` or ``nutation`` design.
    torque, power : float, optional
        The load, at most one: the torque (N m) on the pair's driving gear (gear_pair:
        the pinion; khv: the planet; nutation: the input shaft, spread by the torque
        flow), or the power (W) at the design's speed. Default: the design's own load.
    conditions : RatingConditions, optional
        K-factors, life, lubricant, roughness, minimum safety factors; defaults
        documented in :class:`~reducerlab.rating.material.RatingConditions`.
    method : {"auto", "A", "B", "both"}
        ``B``: ISO 6336 method B only (milliseconds; refuses double-arc teeth). ``A``:
        the LTCA-based method A only (a contact analysis with root stresses per pair:
        minutes). ``both``: both, judged by the smaller safety factor. ``auto``
        (default): B where the standard covers the pair, A where it does not (the
        double circular-arc pairs).
    ltca : MethodA, optional
        Settings of method A's contact analyses (positions, tooth element size, cell,
        workers); default :class:`~reducerlab.analysis.rating_ltca.MethodA`.
    stage, progress : callable, optional
        Passed to the contact analyses of method A (``stage(text)``,
        ``progress(done, total)``).

    Raises
    ------
    ReducerlabError
        No load (neither given nor in the design), a design type without gear pairs to
        rate, or geometry outside the standard's range, naming the field.
    """
    c = conditions or RatingConditions()
    if method not in METHODS:
        raise ReducerlabError(f"method: one of {', '.join(METHODS)}; got {method!r}")
    if ltca is not None and not isinstance(ltca, MethodA):
        raise ReducerlabError(f"ltca: a MethodA (rating_ltca) or None; got {ltca!r}")
    _pinion_torque(design, torque, power)
    kind = getattr(design, "type", "")
    if kind not in ("gear_pair", "khv", "nutation"):
        raise ReducerlabError(
            f"type: the load capacity rating covers gear_pair, khv and nutation designs; "
            f"got {kind!r}"
        )
    mat = design_materials(design)
    ratings: dict[str, tuple[PairRating, tuple[str, str]]] = {}
    if kind == "gear_pair":
        speed = float(design.operating.speed)  # type: ignore[attr-defined]
        if not speed > 0:
            raise ReducerlabError("operating.speed: must be > 0 for the rating (load cycles)")
        t = _load(design, torque, power, speed, lambda p: p.input_torque)
        pair = design.spur_pair()  # type: ignore[attr-defined]
        ratings["pair"] = (rate_spur_pair(pair, t, speed, (mat, mat), c), ("pinion", "gear"))
        g1 = pair.pinion
        loads = [PairLoad("pair", 1, ("pinion", "gear"), t, speed, pair.wheel.teeth / g1.teeth,
                          g1.reference_radius, g1.module)]  # fmt: skip
    elif kind == "khv":
        g = design.gears  # type: ignore[attr-defined]
        w_h = float(design.input_speed)  # type: ignore[attr-defined]
        # ring fixed: the planet turns relative to the carrier at -(z_K / z_V) omega_H
        rel = abs(w_h) * g.ring_teeth / g.planet_teeth
        t = _load(design, torque, power, None, lambda p: p.output_torque)
        pair = g.pair()
        ratings["mesh K-V"] = (
            rate_internal_pair(pair, t, rel, (mat, mat), c),
            ("planet V", "ring K"),
        )
        ratio = g.ring_teeth / g.planet_teeth
        loads = [PairLoad("mesh K-V", 1, ("planet V", "ring K"), t, rel, ratio,
                          pair.pitch_radius(1), pair.module)]  # fmt: skip
    else:  # nutation
        b, loads = _nutation(design, mat, c, torque, power, method)
        ratings.update(b)
    if method == "B":
        return _result(design, ratings, c)
    want = [ld for ld in loads if method != "auto" or ld.label not in ratings]
    rated_b = {k: r for k, (r, _) in ratings.items()}
    contacts: dict[str, Any] = {}
    a = method_a_pairs(design, want, (mat, mat), c, ltca or MethodA(), rated_b, stage, progress,
                       contacts)  # fmt: skip
    out = _result(design, ratings, c, a, {ld.label: ld.gears for ld in loads}, method)
    out.contacts = contacts
    return out


def _nutation(
    design: Any,
    mat: GearMaterial,
    c: RatingConditions,
    torque: float | None,
    power: float | None,
    method: str = "B",
) -> tuple[dict[str, tuple[PairRating, tuple[str, str]]], list[PairLoad]]:
    """Each bevel pair of a nutation design by ISO 10300 method B1
    (:func:`reducerlab.rating.bevel.rate_bevel_pair`), loaded by the torque flow, and the
    pairs' loads for method A (double-arc pairs: method A only)."""
    from ..rating.bevel import rate_bevel_pair
    from .torque_flow import torque_flow

    if c.K_Hbeta != RatingConditions().K_Hbeta:
        raise ReducerlabError(
            "K_Hbeta (--khbeta): the nutation pairs' face load factor is ISO 10300-1's "
            "K_Hbeta-C = 1.5 K_Hbeta-be of the mounting (method B1), not an input; "
            f"leave it at its default {RatingConditions().K_Hbeta:g}"
        )
    sf = design.surface
    if sf is None:
        raise ReducerlabError(
            "surface: the rating needs the tooth geometry of a [surface] table "
            "(profile, face_width)"
        )
    arcs = sf.profile != "involute"
    if arcs and method == "B":
        raise ReducerlabError(
            f"surface.profile: the ISO rating (method B) covers involute teeth; got "
            f"{sf.profile!r}: rate double-arc teeth by method A (method='A' or 'auto', "
            "reducerlab rating --method A)"
        )
    if torque is not None or power is not None:
        w_in = abs(float(design.input_speed))
        t_in = torque if torque is not None else float(power) / w_in
        ratio = abs(float(design.kinematics().ratio))
        design = design.with_values({"output_torque": t_in * ratio, "output_power": None})
    flow = torque_flow(design)
    if not flow.output_torque:
        raise ReducerlabError(
            "torque/power: give the load (--torque or --power), or a load in the design "
            "(output_torque or output_power)"
        )
    theta = design.theta
    freqs = list(design.kinematics().mesh_frequencies(design.input_speed).values())
    out, loads = {}, []
    for k, (d_nut, d_cen) in enumerate(design.cones(theta)):
        nut, cen = getattr(design, f"gear{2 * k + 1}"), getattr(design, f"gear{2 * k + 2}")
        mesh = flow.meshes[f"mesh{k + 1}"]
        m_n = sf.normal_module or design.surface_module(2 * k + 1)
        w_rel = 2 * math.pi * freqs[k] / cen.teeth
        names = (f"gear {2 * k + 2}", f"gear {2 * k + 1}")
        t_ext = abs(float(mesh.external_torque))
        loads.append(PairLoad(f"pair {k + 1}", k + 1, names, t_ext, w_rel, nut.teeth / cen.teeth,
                              cen.mean_radius, m_n, arcs))  # fmt: skip
        if arcs:
            continue
        r = rate_bevel_pair(
            teeth=(cen.teeth, nut.teeth), mean_radii=(cen.mean_radius, nut.mean_radius),
            cone_angles=(d_cen, d_nut), normal_module=m_n, spiral_angle=design.spiral_angle,
            pressure_angle=design.normal_pressure_angle, face_width=sf.face_width,
            torque=abs(float(mesh.external_torque)), speed=w_rel, internal=True,
            materials=(mat, mat), conditions=c,
        )  # fmt: skip
        out[f"pair {k + 1}"] = (r, names)
    return out, loads


def _load(design: Design, torque, power, speed, pick) -> float:
    if torque is not None:
        return float(torque)
    if power is not None:
        if speed is None:
            point = design.operating_point()
            w_out = abs(point.output_speed)
            return float(power) / w_out
        return float(power) / speed
    point = design.operating_point()
    if not point.loaded:
        raise ReducerlabError(
            "torque/power: give the load (--torque or --power), or a load in the design "
            f"({' or '.join(design.load_fields)})"
        )
    return abs(float(pick(point)))


def _result(
    design: Design,
    ratings: dict[str, tuple[PairRating, tuple[str, str]]],
    c: RatingConditions,
    method_a: dict[str, PairRating] | None = None,
    names: dict[str, tuple[str, str]] | None = None,
    method: str = "B",
) -> RatingResult:
    a = method_a or {}
    order = list(names) if names else list(ratings)
    rows = [(label, f) for label in order if label in ratings for f in ratings[label][0].factors]
    rows += [(label, f) for label in order if label in a for f in a[label].factors]
    pairs = {}
    for label in order:
        b = ratings[label][0] if label in ratings else None
        gears = names[label] if names else ratings[label][1]
        pairs[label] = judged(b, a.get(label), gears, method)
    ds = xr.Dataset(
        {
            "pair": ("factor", np.array([p for p, _ in rows], dtype=str)),
            "symbol": ("factor", np.array([f.symbol for _, f in rows], dtype=str)),
            "gear": ("factor", np.array([f.gear for _, f in rows], dtype=str)),
            "value": ("factor", np.array([f.value for _, f in rows], dtype=float)),
            "unit": ("factor", np.array([f.unit for _, f in rows], dtype=str)),
            "clause": ("factor", np.array([f.clause for _, f in rows], dtype=str)),
        },
        attrs={
            "title": "Load capacity (pitting, tooth root)",
            "pairs": json.dumps(pairs),
            "method": method,
            "conditions": json.dumps(c.__dict__),
            **provenance(design.provenance),
        },
    )
    return RatingResult(ds)
