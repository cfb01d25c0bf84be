"""Validated designs: pydantic base classes, quantity fields with units, and the Design
contract that analyses and the report call.

A design is one drive's parameters. Every drive defines a subclass of :class:`Design`
whose fields use the quantity types below; a design file gives each quantity either as
a plain number in SI or as a string with units (see :mod:`reducerlab.units`). Values are
converted to SI once, at load time. Reading files, overrides and the error messages
(``FILE: field.path = VALUE: rule``) are in :mod:`reducerlab.design_files`.
"""

from __future__ import annotations

import math
import typing
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Annotated, Any, ClassVar, Literal, Self

from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    PrivateAttr,
    model_validator,
)
from pydantic_core import PydanticCustomError

from .design_files import field_rules, set_path, validate_design
from .io import digest
from .units import QUANTITIES, parse_quantity, shown

if TYPE_CHECKING:
    from .kinematics import DriveKinematics

__all__ = [
    "Angle",
    "AngularVelocity",
    "Damping",
    "Design",
    "Force",
    "Length",
    "Mass",
    "MomentOfInertia",
    "NonNegativeDamping",
    "NonNegativeStiffness",
    "OperatingPoint",
    "PositiveInt",
    "Power",
    "Real",
    "Spec",
    "SpeedRange",
    "Stiffness",
    "Thresholds",
    "Torque",
    "angle_between",
    "field_kind",
    "quantity",
]


def _si(kind: str) -> BeforeValidator:
    def convert(value: Any) -> float:
        try:
            return parse_quantity(value, kind)
        except ValueError as exc:
            raise PydanticCustomError("quantity", str(exc)) from None

    convert.quantity_kind = kind  # type: ignore[attr-defined]  # read by field_kind
    return BeforeValidator(convert)


def field_kind(design: BaseModel, path: str) -> str | None:
    """The quantity kind (a key of :data:`reducerlab.units.QUANTITIES`) of the design
    field at dotted ``path`` (``"input_speed"`` -> ``"angular velocity"``), ``None`` for
    a plain number or a path that is not a quantity field."""
    node: Any = design
    info = None
    for key in path.split("."):
        if isinstance(node, list | tuple):
            if not key.isdigit() or int(key) >= len(node):
                return None
            node = node[int(key)]
            continue
        fields = getattr(type(node), "model_fields", None)
        if fields is None or key not in fields:
            return None
        info = fields[key]
        node = getattr(node, key)
    if info is None:
        return None
    for meta in info.metadata:
        kind = getattr(getattr(meta, "func", None), "quantity_kind", None)
        if kind is not None:
            return kind
    for arg in typing.get_args(info.annotation):  # Optional[quantity]
        for meta in getattr(arg, "__metadata__", ()):
            kind = getattr(getattr(meta, "func", None), "quantity_kind", None)
            if kind is not None:
                return kind
    return None


def quantity(kind: str, **constraints: float) -> Any:
    """Annotated float type for a physical quantity of ``kind`` with bounds in SI.

    Parameters
    ----------
    kind : str
        A key of :data:`reducerlab.units.QUANTITIES`.
    **constraints
        pydantic numeric constraints (``gt``, ``ge``, ``lt``, ``le``) in SI units.
    """
    if kind not in QUANTITIES:
        raise KeyError(kind)
    return Annotated[float, _si(kind), Field(**constraints)]


def angle_between(lo_deg: float, hi_deg: float, *, closed: bool = False) -> Any:
    """Annotated angle type (stored in rad) restricted to ``(lo_deg, hi_deg)`` degrees.

    A plain number is read as radians, as every other SI quantity; the range check then
    catches the common slip of writing degrees without a unit.
    """
    lo, hi = math.radians(lo_deg), math.radians(hi_deg)

    def check(value: float) -> float:
        inside = lo <= value <= hi if closed else lo < value < hi
        if not inside:
            brackets = "[]" if closed else "()"
            raise PydanticCustomError(
                "angle_range",
                "angle {deg}° out of range: must lie in {interval}"
                " (a plain number is read as radians; write e.g. '25 deg')",
                {
                    "deg": f"{math.degrees(value):.6g}",
                    "interval": f"{brackets[0]}{lo_deg:g}°, {hi_deg:g}°{brackets[1]}",
                },
            )
        return value

    return Annotated[float, _si("angle"), AfterValidator(check)]


Mass = quantity("mass", gt=0)
MomentOfInertia = quantity("moment of inertia", gt=0)
Length = quantity("length", gt=0)
Stiffness = quantity("stiffness", gt=0)
NonNegativeStiffness = quantity("stiffness", ge=0)
TorsionalStiffness = quantity("torsional stiffness", ge=0)
Damping = quantity("damping", ge=0)
NonNegativeDamping = Damping
TorsionalDamping = quantity("torsional damping", ge=0)
Force = quantity("force")
Torque = quantity("torque")
Power = quantity("power")
#: Speeds are bounded by the kind's range, 1e7 rad/s (about 95 million rpm), so that
#: squares stay finite.
AngularVelocity = quantity("angular velocity")
Angle = quantity("angle")
#: Counts (teeth, lobes, balls, bearings): a positive integer, at most 100000 so that the
#: geometry built from it stays finite.
PositiveInt = Annotated[int, Field(strict=True, gt=0, le=100_000)]


def _representable(value: float) -> float:
    kind = QUANTITIES["dimensionless"]
    if value != 0 and not kind.lo <= abs(value) <= kind.hi:
        raise PydanticCustomError(
            "number_range",
            "outside the representable range: 0 or a magnitude within [{lo}, {hi}]",
            {"lo": f"{kind.lo:g}", "hi": f"{kind.hi:g}"},
        )
    return value


#: A plain number that is not a physical quantity (a ratio, a projection coefficient):
#: finite, strictly a number (not a boolean or a string), and 0 or of a magnitude within
#: the range of the "dimensionless" kind of :data:`reducerlab.units.QUANTITIES`.
Real = Annotated[float, Field(strict=True, allow_inf_nan=False), AfterValidator(_representable)]


def _check_range(r: list[float]) -> list[float]:
    if len(r) != 2 or not 0 <= r[0] <= r[1]:
        raise PydanticCustomError(
            "speed_range", "must be [min, max] with 0 <= min <= max (e.g. ['1000 rpm', '2000 rpm'])"
        )
    return r


#: An operating speed range ``[min, max]`` (rad/s).
SpeedRange = Annotated[list[AngularVelocity], AfterValidator(_check_range)]  # type: ignore[valid-type]


class Spec(BaseModel):
    """Base of every design section: unknown fields are errors, instances are frozen.

    Validation is strict: a boolean field takes only ``true``/``false`` (not 1, "yes",
    "on"), a number field takes only a number (not ``true`` or a string), a list only a
    list; numbers must be finite. Quantity fields still read strings with units, since
    their converter runs before the strict float check. Plain numbers that are not
    quantities use :data:`Real` (or an explicitly bounded float).
    """

    model_config = ConfigDict(
        extra="forbid", frozen=True, validate_default=True, strict=True, allow_inf_nan=False
    )


class BifurcationRequest(Spec):
    """A bifurcation diagram the report computes (``[report.bifurcation]``): ``parameter``
    a design field or model parameter path, ``values`` a value specification
    (``"lin:300 rpm:3000 rpm:40"``, as ``reducerlab bifurcation -v``)."""

    parameter: Annotated[str, Field(min_length=1)]
    values: Annotated[str, Field(min_length=1)]
    periods: Annotated[int, Field(strict=True, ge=20, le=100_000)] = 600
    keep: Annotated[int, Field(strict=True, ge=1, le=10_000)] = 100


class RegimeMapRequest(Spec):
    """A regime map the report computes (``[report.regime_map]``): ``x`` and ``y`` are
    ``PATH=VALUES`` (as ``reducerlab regime-map -x/-y``)."""

    x: Annotated[str, Field(min_length=3)]
    y: Annotated[str, Field(min_length=3)]
    periods: Annotated[int, Field(strict=True, ge=20, le=100_000)] = 600
    keep: Annotated[int, Field(strict=True, ge=1, le=10_000)] = 64


class ReportSpec(Spec):
    """What the design report computes beyond the standard sections (``[report]``)."""

    bifurcation: BifurcationRequest | None = None
    regime_map: RegimeMapRequest | None = None


#: Share (0..1) of a mode's strain energy in a mesh line, or of its lateral motion
#: whirling forward, from which an excitation line that crosses it counts
#: (:class:`Thresholds`).
Share = Annotated[float, Field(ge=0, le=1)]


class Thresholds(Spec):
    """What the verdict (:func:`reducerlab.analysis.verdict.verdict`, ``reducerlab
    check``, the report) counts as a risk: a design's ``[check]`` table. The reasons for
    each default are in ``docs/assumptions.md`` ("The verdict's thresholds").

    Attributes
    ----------
    margin : float
        Relative distance of a natural frequency to an excitation that counts, in
        (0, 1) (0.10 = 10 %, ``check --margin``).
    mesh_strain_share : float
        A mesh-order excitation (the transmission error and mesh-stiffness variation)
        excites a mode only through its mesh lines: a crossing counts when the mode's
        strain-energy share in them, ``k_mean (g . phi)^2 / (phi^T K phi)``, reaches this
        (default 0.01: the resonant mesh deflection of such a mode is about
        ``share / (2 zeta)`` times the transmission error).
    forward_whirl_share : float
        Unbalance turns with the rotor: a ``1x input`` crossing counts when the share of
        the mode's lateral motion that whirls forward reaches this (default 0.01; a
        backward whirl of an isotropic rotor has none).
    dynamic_load_factor : float
        The largest dynamic load factor ``max |F| / mean F`` of a mesh line at the
        operating point that passes, >= 1 (default 1.5).
    separation : float
        The largest share of the time with the teeth apart that passes, in [0, 1)
        (default 0: teeth that separate are never green).
    back_impacts_risk : bool
        Back-side impacts (double-sided impacts) are a risk (default true; false: a note).
    non_periodic_risk : bool
        Quasi-periodic or chaotic motion at the operating point is a risk (default true;
        false: a note).
    consistency : float
        Largest relative difference between a lumped gear's mass or moment of inertia
        and its finite-element body's that is consistent (``reducerlab run``; default
        0.10: a natural frequency moves by about half of it, f ~ 1/sqrt(m), within the
        10 % margin).
    """

    margin: Annotated[float, Field(gt=0, lt=1)] = 0.10
    mesh_strain_share: Share = 0.01
    forward_whirl_share: Share = 0.01
    dynamic_load_factor: Annotated[float, Field(ge=1, le=1e6)] = 1.5
    separation: Annotated[float, Field(ge=0, lt=1)] = 0.0
    back_impacts_risk: bool = True
    non_periodic_risk: bool = True
    consistency: Annotated[float, Field(gt=0, lt=1)] = 0.10


#: Design tables that say how to show or judge results, not what to analyse: left out
#: of the design hash, the provenance and the inputs a result depends on.
NOT_ANALYSED = frozenset({"report", "check"})


@dataclass(frozen=True)
class OperatingPoint:
    """Where a design runs: its input speed and the load its output member carries.

    Attributes
    ----------
    input_speed : float
        rad/s, the input member's speed (signed).
    output_torque : float
        N m, the load the output member carries (``>= 0``; 0 when unloaded); it opposes
        the output's rotation.
    ratio : float or None
        ``omega_in / omega_out`` (signed); None for a design without kinematics.
    """

    input_speed: float
    output_torque: float
    ratio: float | None = None

    @property
    def output_speed(self) -> float:
        """rad/s, the output member's speed (signed; 0 without kinematics)."""
        return self.input_speed / self.ratio if self.ratio else 0.0

    @property
    def power(self) -> float:
        """W, the power delivered to the load, ``T_out |omega_out|``."""
        return self.output_torque * abs(self.output_speed)

    @property
    def input_torque(self) -> float:
        """N m, the input torque of the lossless drive, ``T_out / |i|`` (signed along the
        input speed: it drives)."""
        if not self.ratio:
            return 0.0
        return math.copysign(self.output_torque / abs(self.ratio), self.input_speed or 1.0)

    @property
    def loaded(self) -> bool:
        """Whether the output carries a load."""
        return self.output_torque > 0


class Design(Spec):
    """Base of every drive's design.

    Attributes
    ----------
    type : str
        The drive type; selects the builder (``"gear_pair"``, ...).
    name : str
        A title used in tables, figures and reports.
    check : Thresholds, optional
        The ``[check]`` table: what the verdict counts as a risk (:attr:`thresholds`).
    """

    type: str
    name: str = ""
    description: str = ""
    report: ReportSpec | None = None
    check: Thresholds | None = None
    _source: str = PrivateAttr(default="<design>")

    @property
    def source(self) -> str:
        """Where the design came from (its file for ``load_design``), quoted in front
        of every error that the builders raise about it."""
        return self._source

    @property
    def hash(self) -> str:
        """SHA-256 of the design's SI content (hex, 16 characters); the ``[report]`` and
        ``[check]`` tables (what the report draws and what the verdict counts, not what
        is analysed) are left out."""
        return digest(self.model_dump_json(exclude=set(NOT_ANALYSED)))

    @property
    def provenance(self) -> dict[str, str]:
        """``{"design": SI JSON, "design_hash": hash, "source": file}``: the metadata that
        models and results built from this design carry (one JSON dump serves both; the
        source, when known, lets an analysis's error name the file)."""
        text = self.model_dump_json(exclude=set(NOT_ANALYSED))
        out = {"design": text, "design_hash": digest(text)}
        if self._source != "<design>":
            out["source"] = self._source
        return out

    @property
    def thresholds(self) -> Thresholds:
        """What the verdict counts as a risk: the ``[check]`` table, else the defaults."""
        return self.check if self.check is not None else Thresholds()

    # -- the drive contract: what analyses and the report ask of every design --------

    @property
    def drive_name(self) -> str:
        """The drive this design describes (its ``type``; a kinematics-only design names
        its ``drive``), for titles and for choosing the papers' assumptions."""
        return self.type

    #: Where the design keeps its operating speed: the dotted paths of the input speed
    #: (rad/s) and of the optional ``speed_range`` ``[min, max]`` (rad/s); None where it
    #: has none. Each drive declares its own (``("input_speed", "speed_range")``,
    #: ``("operating.speed", "operating.speed_range")``, ...).
    speed_fields: ClassVar[tuple[str | None, str | None]] = (None, None)

    def _at(self, path: str | None) -> Any:
        node: Any = self
        for key in path.split(".") if path else ():
            node = getattr(node, key)
        return node if path else None

    @property
    def operating_speed(self) -> float:
        """The operating speed of the input member (rad/s); 0 for a design at rest."""
        return float(self._at(self.speed_fields[0]) or 0.0)

    def operating_range(self) -> tuple[float, float]:
        """The operating speed range ``(min, max)`` of the input member (rad/s): the
        design's ``speed_range`` where it gives one, else the operating speed twice."""
        rng = self._at(self.speed_fields[1])
        if rng:
            return float(rng[0]), float(rng[1])
        s = self.operating_speed
        return s, s

    def kinematics(self) -> DriveKinematics | None:
        """The drive's kinematics (ratio, member speeds, mesh frequencies), or None for
        a design that defines none (a lumped model)."""
        return None

    #: Where the design keeps its load: the dotted paths of a torque (N m) and of the
    #: output power (W), of which a design gives at most one (a 0 counts as not given);
    #: None where it has none
    #: (``("output_torque", "output_power")``, ``("operating.torque", "operating.power")``).
    load_fields: ClassVar[tuple[str | None, str | None]] = (None, None)
    #: Which member the torque field loads: ``"output"`` (its load) or ``"input"`` (the
    #: torque it transmits, a gear pair's pinion torque).
    load_at: ClassVar[Literal["output", "input"]] = "output"
    #: Fields a design type no longer takes: name -> what replaces it. A file that still
    #: gives one is refused with that message (not read with a new meaning).
    retired_fields: ClassVar[Mapping[str, str]] = {}

    @model_validator(mode="before")
    @classmethod
    def _retired(cls, data: Any) -> Any:
        if isinstance(data, Mapping):
            gone = [(k, f"no longer a field: {why}") for k, why in cls.retired_fields.items()
                    if k in data]  # fmt: skip
            if gone:
                raise field_rules(*gone)
        return data

    @model_validator(mode="after")
    def _load_rules(self) -> Self:
        tpath, ppath = self.load_fields
        torque, power = self._at(tpath), self._at(ppath)
        problems = []
        role = ("the load the output member carries" if self.load_at == "output"
                else "the torque the input member transmits")  # fmt: skip
        for path, value, unit in ((tpath, torque, "N m"), (ppath, power, "W")):
            if value is not None and value < 0:
                problems.append((
                    path, f"must be >= 0 ({unit}): {role}; its direction follows from the rotation"
                ))  # fmt: skip
        if torque and power:
            problems.append(
                (ppath, f"give the load as {tpath} or as {ppath}, not both (the other 0)")
            )
        elif power and not self.operating_speed:
            speed = self.speed_fields[0] or "input_speed"
            problems.append((ppath, f"a power needs a non-zero {speed} to give a torque"))
        if problems:
            raise field_rules(*problems)
        return self

    def operating_point(self) -> OperatingPoint:
        """The operating point: the input speed (``operating_speed``) and the output
        torque, given (``load_fields``: a torque, or a power ``P``, ``T_out = P /
        |omega_out|``) or 0 when the design gives no load.

        Returns
        -------
        OperatingPoint
        """
        speed = self.operating_speed
        tpath, ppath = self.load_fields
        torque, power = self._at(tpath), self._at(ppath)
        kin = self.kinematics() if (torque or power) else None
        if kin is None:
            return OperatingPoint(speed, 0.0, None)
        ratio = float(kin.ratio)
        if power:
            out = float(power) * abs(ratio) / abs(speed)
        else:
            out = float(torque) * (abs(ratio) if self.load_at == "input" else 1.0)
        return OperatingPoint(speed, out, ratio)

    def pitch_radii(self) -> dict[str, float]:
        """Mean or pitch radius (m) of every gear of the kinematics' torque train, by
        the train's gear names, for tangential forces; empty where the design has no
        geometry (a kinematics-only design)."""
        return {}

    @property
    def has_tooth_surfaces(self) -> bool:
        """Whether the design describes tooth surfaces that can be generated (paper 001)."""
        return False

    def with_values(self, changes: Mapping[str, Any], source: str | None = None) -> Self:
        """A validated copy with fields changed: ``{"gears.x1": 0.5, "gears.x2": None}``.

        Paths are dotted into the design's SI dump (list items by index); values are SI
        numbers or what a design file may hold there. The copy is validated again, so
        a value that breaks a rule raises :class:`~reducerlab.errors.DesignError`
        naming ``source`` (default: this design's source with the changes), the field
        and the rule.
        """
        data = self.model_dump(mode="json")
        for path, value in changes.items():
            set_path(data, path, value, "with_values")
        label = source or f"{self.source} with " + ", ".join(
            f"{k} = {shown(v)}" for k, v in changes.items()
        )
        out = validate_design(type(self), data, label)
        out._source = label
        return out
