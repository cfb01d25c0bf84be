"""The tables of a nutation design (``drives.nutation``): gear blanks, material, bevel
gears, supports, meshes and tooth surfaces (paper 000 Tables 1-2, paper 001)."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, WrapValidator, model_validator

from ..design import (
    Damping,
    Length,
    Mass,
    MomentOfInertia,
    NonNegativeStiffness,
    PositiveInt,
    Spec,
    TorsionalDamping,
    TorsionalStiffness,
    angle_between,
    quantity,
)
from ..design_files import field_rules
from .accuracy_specs import GearErrorSpec
from .force_law_specs import LoadExponent, check_force_law, check_stiffness_terms, stiffness_or
from .modification_specs import Layout, ModificationSpec

__all__ = [
    "Bevel",
    "BlankSpec",
    "MaterialSpec",
    "MeshSpec",
    "Support3",
    "SurfaceSpec",
    "TiltSupport",
]


class BlankSpec(Spec):
    """Blank features of one gear for its finite-element body (``[gearN.blank]``).

    Paper 000 does not give its blanks; ``docs/assumptions.md`` records the defaults.

    Attributes
    ----------
    rim : float, optional
        Rim thickness beyond the root cone (m); default ``surface.rim`` or ``2 m_n``.
    bore : float, optional
        Bore diameter (m). Without it the body is the rim ring alone (no web).
    web : float, optional
        Web thickness along the axis (m); default ``1.5 rim``.
    hub : float, optional
        Hub outer diameter (m); default ``1.6 bore``.
    hub_length : float, optional
        Hub length along the axis (m); default ``max(2 web, face_width)``.
    """

    rim: Length | None = None
    bore: Length | None = None
    web: Length | None = None
    hub: Length | None = None
    hub_length: Length | None = None

    @model_validator(mode="after")
    def _needs_bore(self) -> BlankSpec:
        given = [n for n in ("web", "hub", "hub_length") if getattr(self, n) is not None]
        if given and self.bore is None:
            raise field_rules((given[0], "a web or hub needs a bore: give bore too"))
        return self


class MaterialSpec(Spec):
    """Isotropic linear elastic material of the gear bodies (``[material]``); default
    paper 000 §4's structural steel (E = 206 GPa, nu = 0.29, rho = 7850 kg/m^3). The
    load capacity rating's limits (issue 29): ``sigma_Hlim`` and ``sigma_Flim`` of
    ISO 6336-5:2016, default case-hardened wrought steel MQ (1500 MPa, 500 MPa), and the
    heat ``treatment`` that selects the life factor lines."""

    youngs_modulus: quantity("pressure", gt=0) = 206e9  # type: ignore[valid-type]
    poisson_ratio: float = Field(0.29, gt=-1.0, lt=0.5)
    density: quantity("density", gt=0) = 7850.0  # type: ignore[valid-type]
    # load capacity limits (issue 29): ISO 6336-5:2016 case-hardened wrought steel MQ
    sigma_Hlim: quantity("pressure", gt=0) = 1500e6  # type: ignore[valid-type]
    sigma_Flim: quantity("pressure", gt=0) = 500e6  # type: ignore[valid-type]
    treatment: Literal["case-hardened", "through-hardened", "induction-hardened", "nitrided"] = (
        "case-hardened"
    )


class Bevel(Spec):
    """One spiral bevel gear (paper 000 Table 1). ``errors``: its eccentricity at the
    mean cone point, its phase (from the mean contact point's direction, about the
    gear's own axis) and single pitch deviations on the mean circle, for the
    transmission accuracy (``kinematics.accuracy_nutation``)."""

    teeth: PositiveInt
    mass: Mass
    J_x: MomentOfInertia
    J_y: MomentOfInertia
    J_z: MomentOfInertia
    mean_radius: Length
    blank: BlankSpec | None = None
    modifications: ModificationSpec | None = None
    errors: GearErrorSpec | None = None


class Support3(Spec):
    """Support stiffness and damping of one body along x, y, z (paper 000 Table 2)."""

    k_x: NonNegativeStiffness
    k_y: NonNegativeStiffness
    k_z: NonNegativeStiffness
    c_x: Damping = 0.0
    c_y: Damping = 0.0
    c_z: Damping = 0.0


class TiltSupport(Spec):
    """Tilts of the nutating gear about its own transverse axes through the nutation
    centre (``[tilt13]``; not in paper 000): the tilting stiffness and damping of its
    crank bearings (e.g. two bearings of radial stiffness ``k`` a distance ``L`` apart
    give ``k L^2 / 2``) and, optionally, the body's tilt inertias about the nutation
    centre. Default ``J_x``, ``J_y``: each gear's own ``J_x``, ``J_y`` plus ``m e^2``, its
    mass taken at the axial distance ``e = R_m cos(delta)`` of its mean pitch point from
    the centre (paper 000 gives inertias, not mass centres)."""

    k_rx: TorsionalStiffness
    k_ry: TorsionalStiffness
    c_rx: TorsionalDamping = 0.0
    c_ry: TorsionalDamping = 0.0
    J_x: MomentOfInertia | None = None
    J_y: MomentOfInertia | None = None


_stiffness_or_contact = stiffness_or(("contact",), 'or "contact": the loaded contact\'s k(t)')


class MeshSpec(Spec):
    """One gear pair: mean mesh stiffness, optional Fourier terms (Eq. 8), damping,
    full backlash (Eq. 6) and transmission error amplitude.

    ``stiffness = "contact"`` asks for the loaded contact's k(t) at the operating point
    (paper 000 section 2.3): ``reducerlab run`` computes it from the tooth surfaces
    (``[surface]``) and puts its mean, harmonics and phases here; the other commands,
    which take the model as written, refuse it and say so.

    ``exponent`` makes the mesh force a power law of the deflection,
    ``F = k(t) (d / p) (delta / d)^p`` (``model.elements.Mesh``; ``p``: ``exponent``,
    ``d``: ``reference_deflection``, where ``k(t)`` is the tangent stiffness); with
    ``stiffness = "contact"``, ``exponent = "contact"`` takes it from the loaded
    contact at the operating torque (``analysis.contact_law``: ``k(t)`` then becomes
    the contact's tangent).
    """

    stiffness: Annotated[float | str, WrapValidator(_stiffness_or_contact)]
    harmonics: list[quantity("stiffness", ge=0)] = Field(default_factory=list)  # type: ignore[valid-type]
    phases: list[angle_between(-360, 360, closed=True)] = Field(default_factory=list)  # type: ignore[valid-type]
    damping: Damping = 0.0
    backlash: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]
    error_amplitude: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]
    exponent: LoadExponent = 1.0
    reference_deflection: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _terms(self) -> MeshSpec:
        check_force_law(self.exponent, self.reference_deflection, self.stiffness)
        if self.stiffness == "contact":
            if self.harmonics or self.phases:
                raise field_rules(("harmonics", 'come from the contact with stiffness = "contact"'))
            return self
        check_stiffness_terms(self.stiffness, self.harmonics, self.phases)
        return self


class SurfaceSpec(Spec):
    """Tooth-surface geometry of the bevel gears (paper 001), for ``reducerlab surface``.

    Optional in a nutation design; every gear of the drive is generated by the crown
    gear of its pair with these values.

    Attributes
    ----------
    profile : {"involute", "double-arc"}
        Normal basic profile: paper 001's involute (pressure angle
        ``normal_pressure_angle``, ISO 53 depths) or the GB/T 12759-1991 double
        circular arc (its own 24 deg).
    face_width : float
        Face width ``b`` along the pitch cone (m).
    normal_module : float, optional
        Normal module at the mean point (m). Default: from the mean radius of gear 1,
        ``m_n = 2 r_m cos(beta) / z_1``; when given it must agree with the mean radii.
    spiral_angle : float, optional
        Mean spiral angle ``beta_m`` (rad); default ``helix_angle``.
    rim : float, optional
        Rim thickness of the blank beyond the root cone (m); default ``2 m_n``.
    flank_modifications : {"none", "crowned"}
        Flank modifications of the gears without their own ``[gearN.modifications]``
        table: none (the conjugate flanks), or the default crowned layout at the design
        load (``contact.modifications.crowned_layout``, docs/contact.md).
    """

    profile: Literal["involute", "double-arc"] = "involute"
    face_width: Length
    normal_module: Length | None = None
    spiral_angle: angle_between(0, 60, closed=True) | None = None  # type: ignore[valid-type]
    rim: Length | None = None
    flank_modifications: Layout = "none"
