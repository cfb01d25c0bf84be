"""A spur gear pair on elastic bearings: bending-torsional, 6 DOFs.

The generic example of reducerlab's core (issue 2). Each gear has two translations
``x, y`` in the plane of rotation and the rotation ``rz``; both rotations are measured
counter-clockwise about +z (the pinion drives counter-clockwise, the gear then turns
clockwise, i.e. negative). The relative displacement along the line of action is

``delta = (x_p - x_g) sin(alpha) + (y_p - y_g) cos(alpha) + r_bp rz_p + r_bg rz_g - e(t)``

with the base radii ``r_b = m z cos(alpha) / 2``. With rigid bearings the only elastic
mode is torsional with ``omega^2 = k (r_bp^2 / J_p + r_bg^2 / J_g)``.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Annotated, ClassVar, Literal

from pydantic import Field, model_validator

from ..design import (
    AngularVelocity,
    Damping,
    Design,
    Length,
    Mass,
    MomentOfInertia,
    NonNegativeStiffness,
    PositiveInt,
    Power,
    Real,
    Spec,
    SpeedRange,
    Stiffness,
    Torque,
    angle_between,
    quantity,
)
from ..design_files import field_rules
from ..errors import DesignError, ReducerlabError
from ..kinematics import TRAINS, DriveKinematics
from ..model import Backlash, Constant, Dof, Fourier, Inertia, Load, Mesh, Model, Support
from ..model.laws import TimeLaw
from .accuracy_specs import GearErrorSpec
from .modification_specs import Layout, ModificationSpec
from .rating_material import GearMaterialSpec

if TYPE_CHECKING:
    from ..geometry.spur import SpurPair

__all__ = ["Bearing", "Gear", "GearMesh", "GearPairDesign", "Operating", "build_model"]


class Bearing(Spec):
    """Radial bearing stiffness and damping of one gear (N/m, N s/m)."""

    stiffness_x: NonNegativeStiffness
    stiffness_y: NonNegativeStiffness
    damping_x: Damping = 0.0
    damping_y: Damping = 0.0


#: Profile shift coefficient x (ISO 21771), the range a spur gear can be cut with.
Shift = Annotated[Real, Field(ge=-1.0, le=2.0)]


class Gear(Spec):
    """One gear body; ``shift`` is its profile shift coefficient ``x`` (ISO 21771);
    ``modifications`` its loaded flank's crowning and reliefs (``[pinion.modifications]``,
    ``drives.modification_specs``); ``errors`` its eccentricity and pitch deviations
    (``[pinion.errors]``, ``drives.accuracy_specs``)."""

    teeth: PositiveInt
    mass: Mass
    moment_of_inertia: MomentOfInertia
    bearing: Bearing
    shift: Shift = 0.0
    modifications: ModificationSpec | None = None
    errors: GearErrorSpec | None = None


class GearMesh(Spec):
    """Tooth mesh of the pair.

    ``stiffness`` is the mean mesh stiffness; ``stiffness_harmonics`` and
    ``stiffness_phases`` are the amplitudes and phases of paper 000 Eq. 8 at the mesh
    frequency. ``backlash`` is the full clearance (dead zone ``|delta| <= b/2``).

    The tooth geometry (needed by the contact analysis and the load-capacity rating, not
    by the lumped model): ``face_width`` ``b``, and the basic rack of ISO 53 in units of
    the module, ``addendum`` ``h_aP*`` (1.0), ``dedendum`` ``h_fP*`` (1.25) and
    ``root_fillet`` ``rho_fP*`` (0.38, profile A). ``flank_modifications``: ``"crowned"``
    gives each gear without its own ``modifications`` table the default crowned layout
    at the design load (docs/contact.md), ``"none"`` (default) leaves it unmodified.
    """

    module: Length
    pressure_angle: angle_between(0, 45)  # type: ignore[valid-type]
    face_width: Length | None = None
    addendum: Annotated[Real, Field(gt=0, le=1.5)] = 1.0
    dedendum: Annotated[Real, Field(gt=0, le=2.0)] = 1.25
    root_fillet: Annotated[Real, Field(ge=0, le=0.6)] = 0.38
    flank_modifications: Layout = "none"
    stiffness: Stiffness
    damping: Damping = 0.0
    backlash: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]
    #: assembly error (transmission accuracy): actual minus nominal centre distance; it
    #: changes the backlash, not the transmission error (kinematics.accuracy_assembly)
    centre_distance_error: quantity("length", ge=-1e-3, le=1e-3) = 0.0  # type: ignore[valid-type]
    stiffness_harmonics: list[quantity("stiffness", ge=0)] = Field(default_factory=list)  # type: ignore[valid-type]
    stiffness_phases: list[angle_between(-360, 360, closed=True)] = Field(  # type: ignore[valid-type]
        default_factory=list
    )

    @model_validator(mode="after")
    def _phases_match(self) -> GearMesh:
        if self.stiffness_phases and len(self.stiffness_phases) != len(self.stiffness_harmonics):
            raise field_rules((
                "stiffness_phases",
                f"has {len(self.stiffness_phases)} entries but stiffness_harmonics has "
                f"{len(self.stiffness_harmonics)}; give one phase per harmonic or none",
            ))  # fmt: skip
        total = sum(self.stiffness_harmonics)
        if total > self.stiffness:
            raise field_rules((
                "stiffness_harmonics",
                f"add up to {total:.6g} N/m, more than the mean stiffness "
                f"{self.stiffness:.6g} N/m, so k(t) would become negative",
            ))  # fmt: skip
        return self


class Operating(Spec):
    """Operating point: pinion speed and the load, as the torque the pinion transmits
    (N m) or the power (W), at most one; optionally the operating speed range
    ``[min, max]`` used by the resonance check."""

    speed: AngularVelocity = 0.0
    torque: Torque | None = None
    power: Power | None = None
    speed_range: SpeedRange | None = None  # type: ignore[valid-type]


class GearPairDesign(Design):
    """Design of a spur gear pair on bearings (``type = "gear_pair"``)."""

    type: Literal["gear_pair"] = "gear_pair"
    speed_fields: ClassVar = ("operating.speed", "operating.speed_range")
    load_fields: ClassVar = ("operating.torque", "operating.power")
    load_at: ClassVar = "input"
    pinion: Gear
    gear: Gear
    mesh: GearMesh
    operating: Operating = Operating()
    material: GearMaterialSpec = GearMaterialSpec()  # [material]: load capacity (issue 29)

    @model_validator(mode="after")
    def _harmonics_need_speed(self) -> GearPairDesign:
        if self.mesh.stiffness_harmonics and self.operating.speed <= 0:
            raise field_rules((
                "operating.speed",
                "mesh.stiffness_harmonics need operating.speed > 0 to set the mesh frequency",
            ))  # fmt: skip
        return self

    @model_validator(mode="after")
    def _errors_fit(self) -> GearPairDesign:
        problems = []
        for name in ("pinion", "gear"):
            g = getattr(self, name)
            if g.errors is not None:
                problems += g.errors.check_teeth(f"{name}.errors", g.teeth)
        if problems:
            raise field_rules(*problems)
        return self

    @model_validator(mode="after")
    def _reliefs_fit(self) -> GearPairDesign:
        """Relief lengths within each gear's active profile (its involute's roll length
        from the root form circle to the tip), checked at load time."""
        given = [n for n in ("pinion", "gear") if getattr(self, n).modifications is not None]
        if not given or self.mesh.face_width is None:
            return self
        try:
            pair = self.spur_pair()
        except DesignError:
            return self  # the tooth geometry's own error comes where the teeth are used
        problems = []
        for name in given:
            if getattr(self, name).modifications.corner_relief > 0:
                problems.append((
                    f"{name}.modifications.corner_relief",
                    "an involute profile has no corner to relieve (the double arc's has)",
                ))  # fmt: skip
            if getattr(self, name).modifications.transition_relief > 0:
                problems.append((
                    f"{name}.modifications.transition_relief",
                    "an involute profile has no transition arc to relieve (the double arc's "
                    "has)",
                ))  # fmt: skip
            g = pair.pinion if name == "pinion" else pair.wheel
            roll = g.tip_roll - g.form_roll
            spec = getattr(self, name).modifications
            for f in ("tip_relief_length", "root_relief_length"):
                if getattr(spec, f) > roll * (1 + 1e-12):
                    problems.append((
                        f"{name}.modifications.{f}",
                        f"runs beyond the flank: the active profile is {roll * 1e3:.4g} mm "
                        "(roll length from the root form circle to the tip)",
                    ))  # fmt: skip
        if problems:
            raise field_rules(*problems)
        return self

    def base_radius(self, which: Literal["pinion", "gear"]) -> float:
        """Base-circle radius ``m z cos(alpha) / 2`` (m)."""
        z = getattr(self, which).teeth
        return self.mesh.module * z * math.cos(self.mesh.pressure_angle) / 2.0

    @property
    def input_speed(self) -> float:
        """Input (pinion) speed (rad/s)."""
        return self.operating.speed

    def kinematics(self) -> DriveKinematics:
        """Kinematics of the pair (pinion input): the ``gear_pair`` train."""
        return TRAINS["gear_pair"].build({"pinion": self.pinion.teeth, "gear": self.gear.teeth})

    def spur_pair(self) -> SpurPair:
        """The involute geometry of the pair (:class:`~reducerlab.geometry.spur.SpurPair`)
        at its zero-backlash centre distance; needs ``mesh.face_width``.

        Raises
        ------
        DesignError
            ``mesh.face_width`` not given, or teeth that the rack cannot cut (undercut,
            pointed), named by field.
        """
        from ..geometry.spur import SpurGear, SpurPair

        m = self.mesh
        if m.face_width is None:
            raise DesignError(
                "mesh.face_width: is needed for the tooth geometry (contact analysis, "
                'load capacity); give e.g. face_width = "20 mm"'
            )
        gears = []
        for name in ("pinion", "gear"):
            g = getattr(self, name)
            try:
                gears.append(SpurGear(
                    g.teeth, m.module, m.face_width, m.pressure_angle, g.shift,
                    addendum=m.addendum, dedendum=m.dedendum, root_fillet=m.root_fillet,
                ))  # fmt: skip
            except ReducerlabError as e:
                raise DesignError(f"{name}.shift (with [mesh]'s rack): {e}") from None
        return SpurPair(*gears)

    def pitch_radii(self) -> dict[str, float]:
        """Reference pitch radii ``m z / 2`` (m)."""
        return {g: self.mesh.module * getattr(self, g).teeth / 2 for g in ("pinion", "gear")}


def build_model(design: GearPairDesign) -> Model:
    """Six-DOF bending-torsional model of a spur gear pair.

    Parameters
    ----------
    design : GearPairDesign

    Returns
    -------
    Model
        DOFs ``pinion.x, pinion.y, pinion.rz, gear.x, gear.y, gear.rz``; elements
        ``mesh`` and one support per bearing direction, plus the operating torques.
    """
    alpha = design.mesh.pressure_angle
    s, c = math.sin(alpha), math.cos(alpha)
    rbp, rbg = design.base_radius("pinion"), design.base_radius("gear")
    dofs = [Dof(b, k) for b in ("pinion", "gear") for k in ("x", "y", "rz")]
    kin = design.kinematics()
    law: TimeLaw
    if design.mesh.stiffness_harmonics:
        omega_mesh = 2 * math.pi * kin.mesh_frequencies(design.operating.speed)["mesh"]
        law = Fourier(
            mean=design.mesh.stiffness,
            amplitudes=tuple(design.mesh.stiffness_harmonics),
            phases=tuple(design.mesh.stiffness_phases),
            omega=omega_mesh,
            ref_speed=design.operating.speed,
        )
    else:
        law = Constant(design.mesh.stiffness)
    elements: list = []
    for body in ("pinion", "gear"):
        g = getattr(design, body)
        elements += [
            Inertia(f"{body}.x", g.mass),
            Inertia(f"{body}.y", g.mass),
            Inertia(f"{body}.rz", g.moment_of_inertia),
            Support(f"{body}.x", g.bearing.stiffness_x, g.bearing.damping_x),
            Support(f"{body}.y", g.bearing.stiffness_y, g.bearing.damping_y),
        ]
    elements.append(
        Mesh(
            {
                "pinion.x": s,
                "pinion.y": c,
                "pinion.rz": rbp,
                "gear.x": -s,
                "gear.y": -c,
                "gear.rz": rbg,
            },
            stiffness=law,
            damping=design.mesh.damping,
            backlash=Backlash.full(design.mesh.backlash),
            name="mesh",
            # sliding at the pitch point (gear on +x): t = (-cos a, sin a) along the
            # flanks, a rotation slides them by r_w sin(a) = r_b tan(a) per radian
            sliding={
                "pinion.x": -c,
                "pinion.y": s,
                "pinion.rz": rbp * s / c,
                "gear.x": c,
                "gear.y": -s,
                "gear.rz": rbg * s / c,
            },
        )
    )
    point = design.operating_point()
    if point.loaded:
        # the gear turns at omega / i (i < 0): the load torque opposes that rotation,
        # so it acts counter-clockwise, T_out = T |i|; no net torque on the rigid rotation
        elements += [
            Load("pinion.rz", point.output_torque / abs(kin.ratio), name="input_torque"),
            Load("gear.rz", point.output_torque, name="load_torque"),
        ]
    return Model(
        dofs,
        elements,
        speed=design.operating.speed,
        name=design.name or "spur gear pair",
        metadata=design.provenance,
    )
