"""A lumped model written out in the design file: any topology, no builder needed.

``type = "lumped"`` lists DOFs and elements directly, with units::

    type = "lumped"
    name = "motor - shaft - load"

    [[dofs]]
    body = "motor"
    kind = "rz"

    [[elements]]
    type = "inertia"
    dof = "motor.rz"
    moment_of_inertia = "4e-4 kg*m^2"

    [[elements]]
    type = "coupling"
    coefficients = { "motor.rz" = 1, "load.rz" = -1 }
    torsional_stiffness = "1.8e4 N*m/rad"

Translations take ``mass``, ``stiffness`` (N/m), ``damping`` (N s/m) and ``force``;
rotations take ``moment_of_inertia``, ``torsional_stiffness``, ``torsional_damping``
and ``torque``. A ``u`` DOF (equivalent linear displacement at ``radius``) takes
either inertia; its springs are linear. Projection coefficients are plain numbers in
SI (m/m, or m/rad on a rotation, i.e. a radius).
"""

from __future__ import annotations

import math
from typing import Annotated, ClassVar, Literal

from pydantic import Field, model_validator

from ..design import (
    AngularVelocity,
    Damping,
    Design,
    Force,
    Length,
    Mass,
    MomentOfInertia,
    NonNegativeStiffness,
    Real,
    Spec,
    SpeedRange,
    Stiffness,
    Torque,
    TorsionalDamping,
    TorsionalStiffness,
    angle_between,
    quantity,
)
from ..design_files import field_rules
from ..errors import DesignError, ModelError
from ..model import (
    Backlash,
    Centripetal,
    Constant,
    Coriolis,
    Coupling,
    Dof,
    Fourier,
    Gyroscopic,
    Inertia,
    Load,
    Mesh,
    Model,
    Nutating,
    StationaryDamping,
    Support,
)
from ..model.laws import TimeLaw

__all__ = ["LumpedDesign", "build_model"]

Coefficients = Annotated[dict[str, Real], Field(min_length=1)]
Frequency = quantity("frequency", gt=0)
Phase = angle_between(-360, 360, closed=True)


class DofSpec(Spec):
    """One DOF: ``body``, ``kind`` (x, y, z, rx, ry, rz, u) and, for u, ``radius``."""

    body: str
    kind: Literal["x", "y", "z", "rx", "ry", "rz", "u"]
    radius: Length | None = None

    @model_validator(mode="after")
    def _radius(self) -> DofSpec:
        if self.kind == "u" and self.radius is None:
            raise field_rules(("radius", "a 'u' DOF needs a radius (e.g. radius = \"45 mm\")"))
        if self.kind != "u" and self.radius is not None:
            raise field_rules(("radius", f"only kind 'u' takes a radius, not kind {self.kind!r}"))
        return self

    @property
    def name(self) -> str:
        return f"{self.body}.{self.kind}"


class InertiaSpec(Spec):
    """``mass`` (kg) or ``moment_of_inertia`` (kg m^2) on one DOF."""

    type: Literal["inertia"]
    dof: str
    mass: Mass | None = None
    moment_of_inertia: MomentOfInertia | None = None
    name: str = ""


class SupportSpec(Spec):
    """Spring-damper to ground on one DOF."""

    type: Literal["support"]
    dof: str
    stiffness: NonNegativeStiffness | None = None
    damping: Damping | None = None
    torsional_stiffness: TorsionalStiffness | None = None
    torsional_damping: TorsionalDamping | None = None
    name: str = ""


class CouplingSpec(Spec):
    """Spring-damper on ``sum coefficients[i] * q_i`` (a length or an angle)."""

    type: Literal["coupling"]
    coefficients: Coefficients
    stiffness: NonNegativeStiffness | None = None
    damping: Damping | None = None
    torsional_stiffness: TorsionalStiffness | None = None
    torsional_damping: TorsionalDamping | None = None
    name: str = ""


class MeshSpec(Spec):
    """Gear mesh along a line of action (paper 000 Eq. 2-8).

    ``stiffness`` is the mean; ``harmonics`` and ``phases`` the Fourier terms at the
    mesh frequency, given as ``frequency`` (Hz) or as ``order`` (multiple of the
    model speed, e.g. the tooth number). ``backlash`` is the full clearance.
    """

    type: Literal["mesh"]
    coefficients: Coefficients
    stiffness: Stiffness
    damping: Damping = 0.0
    backlash: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]
    error: quantity("length") = 0.0  # type: ignore[valid-type]
    harmonics: list[quantity("stiffness", ge=0)] = Field(default_factory=list)  # type: ignore[valid-type]
    phases: list[Phase] = Field(default_factory=list)  # type: ignore[valid-type]
    frequency: Frequency | None = None  # type: ignore[valid-type]
    order: Annotated[Real, Field(gt=0)] | None = None
    name: str = ""

    @model_validator(mode="after")
    def _law(self) -> MeshSpec:
        if self.phases and len(self.phases) != len(self.harmonics):
            raise field_rules(
                ("phases", f"phases has {len(self.phases)} entries but harmonics has "
                 f"{len(self.harmonics)}")
            )  # fmt: skip
        if self.harmonics and (self.frequency is None) == (self.order is None):
            raise field_rules(("harmonics", "need exactly one of frequency (Hz) or order"))
        if sum(self.harmonics) > self.stiffness:
            raise field_rules((
                "harmonics",
                f"add up to {sum(self.harmonics):.6g} N/m, more than the mean stiffness "
                f"{self.stiffness:.6g} N/m, so k(t) would become negative",
            ))  # fmt: skip
        return self


class CentripetalSpec(Spec):
    """``-mass * (ratio * speed)^2`` on a translational DOF (paper 003 Eq. 7)."""

    type: Literal["centripetal"]
    dof: str
    mass: Mass
    ratio: Annotated[Real, Field(gt=0)] = 1.0
    name: str = ""


class GyroscopicSpec(Spec):
    """Gyroscopic coupling of a body spinning about its axis: ``pair`` is its (rx, ry)
    DOFs, ``polar_moment`` its polar moment of inertia, ``spin_ratio`` its spin over the
    model speed (:class:`~reducerlab.model.Gyroscopic`)."""

    dof_kinds: ClassVar[tuple[str, ...]] = ("rx", "ry")  # of ``pair`` / ``triple``
    type: Literal["gyroscopic"]
    pair: Annotated[list[str], Field(min_length=2, max_length=2)]
    polar_moment: MomentOfInertia
    spin_ratio: Real = 1.0
    name: str = ""


class CoriolisSpec(Spec):
    """Coriolis coupling of a mass in a frame rotating at ``ratio`` x the model speed:
    ``pair`` is its (x, y) DOFs in that frame (:class:`~reducerlab.model.Coriolis`; add
    ``centripetal`` elements for the -m Omega^2 terms)."""

    dof_kinds: ClassVar[tuple[str, ...]] = ("x", "y")  # of ``pair`` / ``triple``
    type: Literal["coriolis"]
    pair: Annotated[list[str], Field(min_length=2, max_length=2)]
    mass: Mass
    ratio: Real = 1.0
    name: str = ""


class NutatingSpec(Spec):
    """Gyroscopic terms of an axisymmetric body on a crank in steady precession:
    ``triple`` is its (rx, ry, rz) DOFs in the crank frame; ``spin_ratio`` its spin
    relative to the crank and ``precession_ratio`` the crank's speed, both over the model
    speed (:class:`~reducerlab.model.Nutating`)."""

    dof_kinds: ClassVar[tuple[str, ...]] = ("rx", "ry", "rz")  # of ``pair`` / ``triple``
    type: Literal["nutating"]
    triple: Annotated[list[str], Field(min_length=3, max_length=3)]
    polar_moment: MomentOfInertia
    diametral_moment: MomentOfInertia
    nutation_angle: angle_between(0, 90)  # type: ignore[valid-type]
    spin_ratio: Real
    precession_ratio: Real = 1.0
    name: str = ""


class StationaryDampingSpec(Spec):
    """Circulatory stiffness of a housing-fixed damper ``damping`` seen from a frame
    rotating at ``ratio`` x the model speed: ``pair`` is the body's (x, y) DOFs in that
    frame (:class:`~reducerlab.model.StationaryDamping`)."""

    dof_kinds: ClassVar[tuple[str, ...]] = ("x", "y")  # of ``pair`` / ``triple``
    type: Literal["stationary_damping"]
    pair: Annotated[list[str], Field(min_length=2, max_length=2)]
    damping: Damping
    ratio: Real = 1.0
    name: str = ""


class LoadSpec(Spec):
    """Constant ``force`` (N) or ``torque`` (N m) on one DOF."""

    type: Literal["load"]
    dof: str
    force: Force | None = None
    torque: Torque | None = None
    name: str = ""


ElementSpec = Annotated[
    InertiaSpec
    | SupportSpec
    | CouplingSpec
    | MeshSpec
    | CentripetalSpec
    | GyroscopicSpec
    | CoriolisSpec
    | NutatingSpec
    | StationaryDampingSpec
    | LoadSpec,
    Field(discriminator="type"),
]


class LumpedDesign(Design):
    """A model written out element by element (``type = "lumped"``)."""

    type: Literal["lumped"] = "lumped"
    speed_fields: ClassVar = ("speed", "speed_range")
    speed: AngularVelocity = 0.0
    speed_range: SpeedRange | None = None  # type: ignore[valid-type]
    dofs: list[DofSpec] = Field(min_length=1)
    elements: list[ElementSpec] = Field(min_length=1)

    @model_validator(mode="after")
    def _consistent(self) -> LumpedDesign:
        kinds = {d.name: d.kind for d in self.dofs}
        problems: list[tuple[str, str]] = []

        for i, e in enumerate(self.elements):
            where = f"elements.{i}"
            if hasattr(e, "coefficients"):
                field, names = "coefficients", list(e.coefficients)
            elif hasattr(e, "pair"):
                field, names = "pair", list(e.pair)
            elif hasattr(e, "triple"):
                field, names = "triple", list(e.triple)
            else:
                field, names = "dof", [e.dof]
            unknown = [n for n in names if n not in kinds]
            if unknown:
                problems.append(
                    (f"{where}.{field}", f"unknown DOF {unknown}; DOFs are {list(kinds)}")
                )
                continue
            if field in ("pair", "triple"):
                want = list(e.dof_kinds)
                bodies = {n.split(".")[0] for n in names}
                if [kinds[n] for n in names] != want or len(bodies) != 1:
                    problems.append((f"{where}.{field}", f"must be one body's "
                                     f"{', '.join(want)} DOFs, in that order"))  # fmt: skip
                continue
            rot = [kinds[n] in ("rx", "ry", "rz", "u") for n in names]
            problems += [(f"{where}.{f}", rule) for f, rule in _unit_rules(e, rot, kinds[names[0]])]
        if problems:
            raise field_rules(*problems)
        return self


def _exactly_one(e: Spec, a: str, b: str) -> list[tuple[str, str]]:
    given = [f for f in (a, b) if getattr(e, f) is not None]
    if len(given) != 1:
        return [(a, f"give exactly one of {a} or {b}")]
    return []


def _unit_rules(e: Spec, rot: list[bool], kind: str) -> list[tuple[str, str]]:
    """Which quantities an element gives for the kind of its DOFs: ``(field, rule)``."""
    out: list[tuple[str, str]] = []
    if isinstance(e, InertiaSpec):
        out += _exactly_one(e, "mass", "moment_of_inertia")
        if not out and kind in ("rx", "ry", "rz") and e.mass is not None:
            out.append(("mass", f"{e.dof} is a rotation: give moment_of_inertia, not mass"))
        if not out and kind in ("x", "y", "z") and e.moment_of_inertia is not None:
            out.append(
                ("moment_of_inertia", f"{e.dof} is a translation: give mass, not moment_of_inertia")
            )
    elif isinstance(e, SupportSpec | CouplingSpec):
        lin = e.stiffness is not None or e.damping is not None
        tor = e.torsional_stiffness is not None or e.torsional_damping is not None
        field = "stiffness" if lin else "torsional_stiffness"
        if lin == tor:
            out.append((
                field,
                "give stiffness/damping (linear) or torsional_stiffness/torsional_damping "
                "(angular), not both or neither",
            ))  # fmt: skip
        elif isinstance(e, SupportSpec) and tor and kind not in ("rx", "ry", "rz"):
            out.append((field, f"{e.dof} is not a rotation: use stiffness/damping"))
        elif isinstance(e, SupportSpec) and lin and kind in ("rx", "ry", "rz"):
            out.append((field, f"{e.dof} is a rotation: use torsional_stiffness/torsional_damping"))
        elif isinstance(e, CouplingSpec) and tor and not all(rot):
            out.append((
                field,
                "a torsional coupling joins rotations (and u DOFs with coefficients in 1/m), "
                "not translations",
            ))  # fmt: skip
    elif isinstance(e, LoadSpec):
        out += _exactly_one(e, "force", "torque")
        if not out and (e.torque is not None) != (kind in ("rx", "ry", "rz")):
            want = "torque" if kind in ("rx", "ry", "rz") else "force"
            out.append(("torque" if e.torque is not None else "force", f"{e.dof} takes a {want}"))
    elif isinstance(e, CentripetalSpec) and kind not in ("x", "y", "z"):
        out.append(("dof", f"centripetal terms act on translations, not {e.dof}"))
    return out


def _value(a: float | None, b: float | None) -> float:
    return a if a is not None else (b if b is not None else 0.0)


def build_model(design: LumpedDesign) -> Model:
    """Turn the written-out model into a :class:`~reducerlab.model.Model`."""
    elements = []
    try:
        dofs = [Dof(d.body, d.kind, d.radius) for d in design.dofs]
        radius = {d.name: d.radius for d in dofs}
        for e in design.elements:
            kw = {"name": e.name} if e.name else {}
            if isinstance(e, InertiaSpec):
                if e.moment_of_inertia is not None:
                    value = e.moment_of_inertia
                else:  # a mass on u is the equivalent mass J / r^2
                    value = e.mass * (radius[e.dof] ** 2 if radius[e.dof] else 1.0)
                elements.append(Inertia(e.dof, value, **kw))
            elif isinstance(e, SupportSpec):
                k = _value(e.stiffness, e.torsional_stiffness)
                c = _value(e.damping, e.torsional_damping)
                elements.append(Support(e.dof, k, c, **kw))
            elif isinstance(e, CouplingSpec):
                k = _value(e.stiffness, e.torsional_stiffness)
                c = _value(e.damping, e.torsional_damping)
                elements.append(Coupling(e.coefficients, k, c, **kw))
            elif isinstance(e, MeshSpec):
                elements.append(_mesh(e, design.speed, kw))
            elif isinstance(e, CentripetalSpec):
                elements.append(Centripetal(e.dof, e.mass, e.ratio, **kw))
            elif isinstance(e, GyroscopicSpec):
                elements.append(Gyroscopic(tuple(e.pair), e.polar_moment, e.spin_ratio, **kw))
            elif isinstance(e, CoriolisSpec):
                elements.append(Coriolis(tuple(e.pair), e.mass, e.ratio, **kw))
            elif isinstance(e, NutatingSpec):
                elements.append(
                    Nutating(tuple(e.triple), e.polar_moment, e.diametral_moment,
                             e.nutation_angle, e.spin_ratio, e.precession_ratio, **kw)
                )  # fmt: skip
            elif isinstance(e, StationaryDampingSpec):
                elements.append(StationaryDamping(tuple(e.pair), e.damping, e.ratio, **kw))
            else:
                elements.append(Load(e.dof, _value(e.force, e.torque), **kw))
        return Model(
            dofs,
            elements,
            speed=design.speed,
            name=design.name or "lumped model",
            metadata=design.provenance,
        )
    except ModelError as exc:
        raise DesignError(f"design {design.name!r}: {exc}") from None


def _mesh(e: MeshSpec, speed: float, kw: dict) -> Mesh:
    law: TimeLaw
    if e.harmonics:
        if e.frequency is not None:  # fixed in time, whatever the speed
            law = Fourier(e.stiffness, tuple(e.harmonics), 2 * math.pi * e.frequency,
                          tuple(e.phases))  # fmt: skip
        else:  # a multiple of the input speed: follows the model speed
            if not speed > 0:
                raise ModelError(
                    f"mesh {e.name!r}: order needs speed > 0 to set the mesh frequency"
                )
            law = Fourier(e.stiffness, tuple(e.harmonics), e.order * speed, tuple(e.phases),
                          ref_speed=speed)  # fmt: skip
    else:
        law = Constant(e.stiffness)
    return Mesh(
        e.coefficients,
        stiffness=law,
        damping=e.damping,
        backlash=Backlash.full(e.backlash),
        error=e.error,
        **kw,
    )
