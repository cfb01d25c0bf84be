"""KHV planetary drive with a small tooth-number difference (paper 004).

Carrier H (input, driven by D through a shaft) carries planet V, which meshes inside
the fixed ring K; the planet's rotation reaches the load L through the
equal-angular-velocity mechanism W (a torsional shaft). 4 torsional DOFs in equivalent
displacements along the line of action (paper 004 Eq. 1):
``X_D = theta_D r_bH, X_H = theta_H r_bH, X_V = theta_V r_bV, X_L = theta_L r_bV``,
with ``r_bV`` the planet's base radius and ``r_bH = a' cos(alpha')`` (= the difference
of the base radii: the carrier moves the planet's base circle along the line of action
by ``a' cos(alpha') theta_H``). Eq. 2: shafts ``k_DH (X_D - X_H)``, ``k_VL (X_V - X_L)``,
mesh ``k_m(t) f(X_V - X_H - e(t), b) + c_m (...)'``.

The internal pair's geometry (profile shift, working pressure angle, contact ratio,
interference) is :class:`reducerlab.geometry.InternalGearPair`; the mesh stiffness is
ISO 6336-1 (Eq. 7-8) with the single/double-tooth parabolic law (Eq. 9), or with
``[mesh] stiffness = "contact"`` the internal pair's loaded tooth contact k(t) at the
operating torque (``analysis.contact``, filled in by ``reducerlab run``), or a mean
stiffness with its mesh harmonics written into the design (paper 000 Eq. 8, as
``reducerlab contact --write-design`` writes them).
"""

from __future__ import annotations

import math
from typing import Annotated, ClassVar, Literal

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, WrapValidator, model_validator

from ..contact.iso6336 import pitch_point_stiffness, single_double_law
from ..design import (
    AngularVelocity,
    Design,
    Length,
    Mass,
    MomentOfInertia,
    PositiveInt,
    Power,
    Real,
    Spec,
    SpeedRange,
    Torque,
    angle_between,
    quantity,
)
from ..design_files import field_rules
from ..errors import ReducerlabError
from ..geometry import InternalGearPair
from ..kinematics import TRAINS, DriveKinematics
from ..model import Backlash, Constant, Coupling, Dof, Fourier, Inertia, Load, Mesh, Model
from ..model.forcing import inertial_error
from ..model.laws import TimeLaw
from .accuracy_specs import CrankErrorSpec, GearErrorSpec
from .force_law_specs import LoadExponent, check_force_law, check_stiffness_terms, stiffness_or
from .modification_specs import Layout, ModificationSpec
from .rating_material import GearMaterialSpec

__all__ = ["PAPER_LINE", "KHVDesign", "build_model", "relative_coordinates"]

#: The points M and N of paper 004 Fig. 3; x2 is on the straight line through them when
#: a design gives x1 only.
PAPER_LINE = (0.416, 0.601, 0.835, 0.995)
Shift = Annotated[Real, Field(ge=-1.5, le=3.0)]
Ratio = Annotated[Real, Field(ge=0, lt=1)]
TorsionalStiffness = quantity("torsional stiffness", gt=0)


class Gears(Spec):
    """The internal pair: planet V (external) in ring K (internal), Table 1.

    ``planet_modifications``, ``ring_modifications``: the loaded flanks' crowning and
    reliefs (``drives.modification_specs``); ``flank_modifications = "crowned"`` gives a
    gear without its table the default crowned layout (docs/contact.md). They take
    effect in the internal pair's loaded contact analysis. ``planet_errors``,
    ``ring_errors``: eccentricity and pitch deviations (``drives.accuracy_specs``), for
    the transmission accuracy; ``crank_errors``: the carrier's radius error, tangential
    offset and axis offset (``drives.accuracy_specs.CrankErrorSpec``).
    """

    planet_teeth: PositiveInt
    ring_teeth: PositiveInt
    module: Length
    addendum: Annotated[Real, Field(gt=0, le=1.5)] = 1.0
    pressure_angle: angle_between(5, 45) = math.radians(20.0)  # type: ignore[valid-type]
    face_width: Length
    x1: Shift
    x2: Shift | None = None
    shift_line: Annotated[list[Real], Field(min_length=4, max_length=4)] = Field(
        default_factory=lambda: list(PAPER_LINE)
    )
    flank_modifications: Layout = "none"
    planet_modifications: ModificationSpec | None = None
    ring_modifications: ModificationSpec | None = None
    planet_errors: GearErrorSpec | None = None
    ring_errors: GearErrorSpec | None = None
    crank_errors: CrankErrorSpec | None = None

    @model_validator(mode="after")
    def _teeth(self) -> Gears:
        if self.ring_teeth <= self.planet_teeth:
            raise field_rules(("ring_teeth", f"must exceed planet_teeth ({self.planet_teeth})"))
        if self.shift_line[0] == self.shift_line[2]:
            raise field_rules(("shift_line", "needs two points with different x1"))
        problems = []
        for name, z in (("planet", self.planet_teeth), ("ring", self.ring_teeth)):
            spec = getattr(self, f"{name}_errors")
            if spec is not None:
                problems += spec.check_teeth(f"{name}_errors", z)
        if problems:
            raise field_rules(*problems)
        return self

    @property
    def shift2(self) -> float:
        """x2: given, or on the line through the two points of ``shift_line``."""
        if self.x2 is not None:
            return self.x2
        a1, a2, b1, b2 = self.shift_line
        return a2 + (b2 - a2) * (self.x1 - a1) / (b1 - a1)

    def pair(self) -> InternalGearPair:
        """The geometry of the internal pair."""
        return InternalGearPair(
            self.planet_teeth,
            self.ring_teeth,
            self.module,
            self.x1,
            self.shift2,
            addendum=self.addendum,
            pressure_angle=self.pressure_angle,
            face_width=self.face_width,
        )


class Inertias(Spec):
    """Moments of inertia (Table 2) and the planet's mass (not in the paper)."""

    drive: MomentOfInertia
    carrier: MomentOfInertia
    planet: MomentOfInertia
    load: MomentOfInertia
    planet_mass: Mass


class Shafts(Spec):
    """Torsional stiffness of the input shaft (D-H) and of the W mechanism (V-L)."""

    input_stiffness: TorsionalStiffness  # type: ignore[valid-type]
    output_stiffness: TorsionalStiffness  # type: ignore[valid-type]
    damping_ratio: Ratio = 0.0


#: the words ``[mesh] stiffness`` takes besides a number
SOURCES = ("iso", "contact")
_stiffness_source = stiffness_or(
    SOURCES, 'or "iso": paper 004 Eq. 7-9; "contact": the loaded contact\'s k(t)'
)


class MeshSpec(Spec):
    """Mesh stiffness, damping ratio, backlash (half width, as paper 004 Eq. 11) and
    error Eq. 12.

    ``stiffness`` is where k(t) comes from: ``"iso"`` (default) ISO 6336-1's pitch-point
    stiffness with paper 004's single/double-tooth law (Eq. 7-9); ``"contact"`` the
    internal pair's loaded tooth contact at the operating torque (the mean ``k_m``, the
    ``harmonics`` ``k_r`` and ``phases`` ``phi_r`` of paper 000 Eq. 8 at the mesh
    frequency), which ``reducerlab run`` computes and puts here (the commands that take
    the model as written refuse it and say so); or a mean stiffness (N/m) with its
    ``harmonics`` and ``phases``, as ``reducerlab contact --write-design`` writes them.

    ``error_forcing`` is how the error excites the drive: ``"stiffness"`` inside the mesh
    deflection (paper 004 Eq. 2), or ``"omega2"`` / ``"j-omega2"`` as the inertial load
    ``-/+ m_e e''(t)`` on the mesh line, whose amplitude grows with the square of the
    speed (:mod:`reducerlab.model.forcing`).

    ``exponent`` and ``reference_deflection`` make the mesh force a power law of the
    deflection (:mod:`reducerlab.drives.force_law_specs`); ``exponent = "contact"`` with
    ``stiffness = "contact"`` takes them from the loaded contact.
    """

    stiffness: Annotated[float | str, WrapValidator(_stiffness_source)] = "iso"
    harmonics: list[quantity("stiffness", ge=0)] = Field(default_factory=list)  # type: ignore[valid-type]
    phases: list[angle_between(-360, 360, closed=True)] = Field(default_factory=list)  # type: ignore[valid-type]
    damping_ratio: Ratio = 0.0
    half_backlash: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]
    error_amplitude: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]
    error_phase: angle_between(-360, 360, closed=True) = 0.0  # type: ignore[valid-type]
    error_forcing: Literal["stiffness", "omega2", "j-omega2"] = "stiffness"
    time_varying: bool = True
    exponent: LoadExponent = 1.0
    reference_deflection: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _terms(self) -> MeshSpec:
        check_force_law(self.exponent, self.reference_deflection, self.stiffness)
        if isinstance(self.stiffness, str):
            if self.harmonics or self.phases:
                raise field_rules((
                    "harmonics" if self.harmonics else "phases",
                    f"go with a mean stiffness (N/m), not with stiffness = "
                    f'"{self.stiffness}" (which gives its own k(t))',
                ))  # fmt: skip
            return self
        check_stiffness_terms(self.stiffness, self.harmonics, self.phases)
        return self


class KHVDesign(Design):
    """Design of a KHV drive (``type = "khv"``).

    The load is the output's: ``load_torque`` (N m, paper 004's ``T_L``) or
    ``output_power`` (W). ``input_torque`` (paper 004's ``T_D``) defaults to the lossless
    torque flow's ``T_L / |i|``, which balances the load; paper 004's Table 2 gives both
    as 50 N m, which does not (``docs/assumptions.md``).
    """

    type: Literal["khv"] = "khv"
    speed_fields: ClassVar = ("input_speed", "speed_range")
    load_fields: ClassVar = ("load_torque", "output_power")
    input_speed: AngularVelocity
    input_torque: Torque | None = None
    load_torque: Torque | None = None
    output_power: Power | None = None
    speed_range: SpeedRange | None = None  # type: ignore[valid-type]
    gears: Gears
    inertia: Inertias
    shafts: Shafts
    mesh: MeshSpec = MeshSpec()
    material: GearMaterialSpec = GearMaterialSpec()  # [material]: load capacity (issue 29)

    @model_validator(mode="after")
    def _feasible(self) -> KHVDesign:
        if self.input_speed <= 0:
            raise field_rules(("input_speed", "must be > 0 (the mesh period follows from it)"))
        try:
            pair = self.gears.pair()
            pair.check()
        except ReducerlabError as exc:
            raise field_rules(("gears", str(exc))) from None
        if not 1.0 < pair.contact_ratio < 2.0:
            raise field_rules((
                "gears",
                f"contact ratio {pair.contact_ratio:.4g} outside (1, 2), where the "
                "single/double-tooth law of paper 004 applies",
            ))  # fmt: skip
        return self

    def kinematics(self) -> DriveKinematics:
        """Carrier input, ring fixed, planet output: the ``khv`` train."""
        teeth = {"planet": self.gears.planet_teeth, "ring": self.gears.ring_teeth}
        return TRAINS["khv"].build(teeth)

    def pitch_radii(self) -> dict[str, float]:
        """Reference pitch radii ``m z / 2`` (m) of the planet and the ring."""
        g = self.gears
        return {"planet V": g.module * g.planet_teeth / 2, "ring K": g.module * g.ring_teeth / 2}

    @property
    def mesh_frequency(self) -> float:
        """Mesh angular frequency ``z_K omega_H`` (rad/s)."""
        return 2 * math.pi * self.kinematics().mesh_frequencies(self.input_speed)["mesh K-V"]

    def with_shift(self, x1: float, source: str | None = None) -> KHVDesign:
        """This design with the ring's shift coefficient ``x1`` and the planet's ``x2``
        on the design's shift line (paper 004 Fig. 3), validated (Fig. 5 compares
        several).

        Raises
        ------
        DesignError
            When the shifted pair breaks a rule (interference, contact ratio, ...).
        """
        return self.with_values({"gears.x1": x1, "gears.x2": None}, source)

    def pitch_stiffness(self) -> float:
        """ISO 6336 single-pair stiffness at the pitch point k_C (N/m), Eq. 7-8."""
        g = self.gears
        return pitch_point_stiffness(
            g.face_width, g.planet_teeth, g.ring_teeth, g.x1, g.shift2, internal=True
        )

    def stiffness_law(self):
        """ISO mesh stiffness over a mesh period (Eq. 9, intervals derived), whatever
        ``mesh.stiffness`` says (the model's own law: :meth:`mesh_law`)."""
        period = 2 * math.pi / self.mesh_frequency
        return single_double_law(
            self.pitch_stiffness(), self.gears.pair().contact_ratio, period, self.input_speed
        )

    @property
    def contact_stiffness(self) -> bool:
        """Whether the model's k(t) is to come from the loaded contact
        (``mesh.stiffness = "contact"``, which ``reducerlab run`` fills in)."""
        return self.mesh.stiffness == "contact"

    def mesh_law(self) -> TimeLaw:
        """The model's mesh stiffness k(t) (N/m): the ISO law (:meth:`stiffness_law`)
        for ``stiffness = "iso"``, else paper 000 Eq. 8
        ``k_m + sum_r k_r cos(r omega_m t + phi_r)`` at the mesh frequency.

        Raises
        ------
        ReducerlabError
            ``stiffness = "contact"``: the loaded contact is computed by ``reducerlab
            run`` (or written as numbers by ``reducerlab contact --write-design``).
        """
        mesh = self.mesh
        if mesh.stiffness == "iso":
            return self.stiffness_law()
        if mesh.stiffness == "contact":
            raise ReducerlabError(
                'mesh.stiffness = "contact": the mesh stiffness comes from the internal '
                "pair's loaded tooth contact at the operating torque, which `reducerlab run` "
                "computes (or write numbers, e.g. with `reducerlab contact --write-design`)"
            )
        if not mesh.harmonics:
            return Constant(float(mesh.stiffness))
        phases = tuple(mesh.phases) or (0.0,) * len(mesh.harmonics)
        return Fourier(float(mesh.stiffness), tuple(mesh.harmonics), self.mesh_frequency,
                       phases, ref_speed=self.input_speed)  # fmt: skip


def _reduced_mass(a: float, b: float) -> float:
    return a * b / (a + b)


def build_model(design: KHVDesign) -> Model:
    """The 4-DOF torsional model of paper 004 Eq. 1-2 on the generic core."""
    pair = design.gears.pair()
    aw = pair.working_pressure_angle
    rbH = pair.centre_distance * math.cos(aw)
    rbV = pair.base_radius(1)
    inertia, shafts, mesh = design.inertia, design.shafts, design.mesh
    MD = inertia.drive / rbH**2
    MH = (inertia.carrier + inertia.planet_mass * rbH**2 / math.cos(aw) ** 2) / rbH**2
    MV = inertia.planet / rbV**2
    ML = inertia.load / rbV**2
    kDH = shafts.input_stiffness / rbH**2
    kVL = shafts.output_stiffness / rbV**2
    law = design.mesh_law()
    if not mesh.time_varying:
        law = Constant(law.mean)
    cDH = 2 * shafts.damping_ratio * math.sqrt(kDH * _reduced_mass(MD, MH))
    cVL = 2 * shafts.damping_ratio * math.sqrt(kVL * _reduced_mass(MV, ML))
    cm = 2 * mesh.damping_ratio * math.sqrt(law.mean * _reduced_mass(MV, MH))
    wm = design.mesh_frequency
    error = Fourier(
        0.0, (mesh.error_amplitude,), wm, (mesh.error_phase - math.pi / 2,),
        ref_speed=design.input_speed,
    )  # fmt: skip  # e sin(wm t + phi)
    dofs = [
        Dof("drive", "u", radius=rbH),
        Dof("carrier", "u", radius=rbH),
        Dof("planet", "u", radius=rbV),
        Dof("load", "u", radius=rbV),
    ]
    elements = [
        Inertia("drive.u", inertia.drive),
        Inertia("carrier.u", MH * rbH**2),
        Inertia("planet.u", inertia.planet),
        Inertia("load.u", inertia.load),
        Coupling({"drive.u": 1.0, "carrier.u": -1.0}, kDH, cDH, name="input_shaft"),
        Coupling({"planet.u": 1.0, "load.u": -1.0}, kVL, cVL, name="output_mechanism"),
        Mesh(
            {"planet.u": 1.0, "carrier.u": -1.0},
            stiffness=law,
            damping=cm,
            backlash=Backlash.half(mesh.half_backlash),
            error=error,
            name="mesh",
            exponent=mesh.exponent,
            reference_deflection=mesh.reference_deflection,
            # at the pitch point the flanks slide by tan(a_w) per unit of the line's
            # rotational deflection (carrier held: the planet's rho = r_bV tan(a_w));
            # the conjugate motion (planet.u = carrier.u) rolls without sliding
            sliding={"planet.u": math.tan(aw), "carrier.u": -math.tan(aw)},
        ),
    ]
    # X = theta r_b: the rigid motion turns every X alike, so T_D / r_bH = T_L / r_bV
    # (r_bV / r_bH = |i|) leaves the load on it zero: the torque flow's T_D = T_L / |i|
    point = design.operating_point()
    T_D = abs(point.input_torque) if design.input_torque is None else design.input_torque
    if T_D:
        elements.append(Load("drive.u", T_D / rbH, name="drive_torque"))
    if point.output_torque:
        elements.append(Load("load.u", -point.output_torque / rbV, name="load_torque"))
    model = Model(
        dofs,
        elements,
        speed=design.input_speed,
        name=design.name or "KHV drive",
        metadata=design.provenance,
    )
    return inertial_error(model, mesh.error_forcing, ["mesh"])


def relative_coordinates() -> tuple[NDArray[np.float64], list[str]]:
    """Paper 004 Eq. 3: ``X_DH = X_D - X_H``, ``X_VH = X_V - X_H``, ``X_VL = X_V - X_L``
    as a matrix ``T`` over ``[X_D, X_H, X_V, X_L]`` (without ``e(t)``, which stays in
    the mesh law), for :meth:`reducerlab.model.NonlinearSystem.reduced`."""
    T = np.array([[1.0, -1.0, 0.0, 0.0], [0.0, -1.0, 1.0, 0.0], [0.0, 0.0, 1.0, -1.0]])
    return T, ["X_DH", "X_VH", "X_VL"]
