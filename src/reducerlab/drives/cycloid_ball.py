"""Cycloid ball planetary transmission (paper 003): lumped stiffness and the 7-DOF
translational-torsional model.

Components (paper 003 Fig. 1): 1 input shaft (eccentric ``e``), 2 centre disc (output,
epitrochoid groove, ``Z_c`` lobes), 3 planetary disc (hypotrochoid groove,
``Z_p = Z_c + 2`` lobes), 5 end cover disc (fixed to the housing through its torsional
support; joined to the planetary disc by the cross-ball equal-speed mechanism).
Coordinates in the frame rotating with the input shaft (paper 003 Eq. 3-7):

``X = [x1, u1, x2, u2, x3, u3, u5]``, ``u_i = r_i theta_i`` (``r_1 = e``).

Relative displacements (Eq. 3-5) become couplings:
``delta_23 = x2 - x3 + u2 - u3`` (cycloid-ball pairs, lumped stiffness ``K_mx``),
``delta_53 = u5 - u3`` (cross-ball mechanism, ``K_w``),
``delta_13 = x1 - x3 - u1`` (eccentric bearing, ``k_3x``);
supports ``k_1x, k_1u, k_2x, k_2u, k_5u`` and the centripetal ``-m_i Omega^2`` on
``x1, x2, x3`` (Eq. 7 ``K_omega``).

Geometry: the grooves act as pitch circles of radius ``r = Z e / 2`` (the rolling
circle radius is ``e / 2`` and ``Z_p - Z_c = 2``), which is paper 003's Table 1
(``r2 = 47.5 mm``, ``r3 = r5 = 50 mm``, ``e = 2.5 mm``); the ball count is
``(Z_c + Z_p) / 2``. See ``docs/assumptions.md``.
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
from ..errors import ReducerlabError
from ..kinematics import TRAINS, DriveKinematics
from ..model import (
    Backlash,
    Centripetal,
    Constant,
    Coriolis,
    Coupling,
    Dof,
    Fourier,
    Inertia,
    Load,
    Mesh,
    Model,
    StationaryDamping,
    Support,
)
from ..model.laws import TimeLaw
from .accuracy_specs import CrankErrorSpec, TrackErrorSpec

if TYPE_CHECKING:
    from ..contact.ball_track import BallTrack

SignedLength = quantity("length")

__all__ = ["CycloidBallDesign", "build_model", "cross_ball_stiffness", "cycloid_ball_stiffness"]


def cycloid_ball_stiffness(single_pair: float, balls: int, deformation_coefficient: float) -> float:
    """Mean lumped stiffness of the cycloid-ball pairs along x (N/m), paper 003 Eq. 1, 10.

    ``K_mx = (k_m / a) sum_i sin^2(theta_i)``; for ``Z_m`` balls evenly spread over the
    circle ``sum sin^2 = Z_m / 2``, so ``K_mx = k_m Z_m / (2 a)``. The same form gives
    the damping (Eq. 8) from the single-pair damping.
    """
    return single_pair * balls / (2.0 * deformation_coefficient)


def cycloid_ball_law(
    single_pair: float,
    balls: int,
    deformation_coefficient: float,
    short_width: float | None,
    speed: float,
    engagement_per_input: float | None = None,
) -> TimeLaw:
    """Time-varying lumped stiffness of paper 003 Eq. 10 (N/m).

    ``K_mx(t) = K (1 + (1 - K_s^-2) K_s^Z cos(Omega_m t))`` with ``K`` the mean of
    :func:`cycloid_ball_stiffness`, ``K_s`` the short-width coefficient and ``Omega_m``
    the ball-engagement frequency: ``engagement_per_input`` times the input speed
    ``speed`` (rad/s). The sum ``sum sin^2(theta_i)`` of Eq. 1 repeats whenever the
    ball set, seen from the line of centres (the frame of the eccentric), has moved on
    by one ball pitch, i.e. when a lobe of either groove has passed the line of centres:
    ``z_c |omega_c - omega_1| = z_p |omega_p - omega_1|`` (``CycloidBallDrive.
    mesh_frequencies``; 40 per input revolution for paper 003's 38/40 lobes), not once
    per input revolution as Eq. 10's ``cos(omega_1 t)`` reads (docs/assumptions.md,
    paper 003 Eq. 10). Without ``engagement_per_input`` the factor is 1 (Eq. 10 as
    printed). The law follows the model speed. Without ``K_s`` (or at zero speed) the
    law is its mean.
    """
    mean = cycloid_ball_stiffness(single_pair, balls, deformation_coefficient)
    if short_width is None or speed == 0:
        return Constant(mean)
    amp = mean * (1.0 - short_width**-2) * short_width**balls
    per = 1.0 if engagement_per_input is None else float(engagement_per_input)
    return Fourier(mean, (amp,), per * abs(speed), ref_speed=abs(speed))


def engagement_per_input(design: CycloidBallDesign) -> float:
    """Ball engagements per input revolution: the ball-engagement frequency of the
    drive's kinematics over the input speed (``z_c |omega_c / omega_1 - 1|``; 40 for
    paper 003's centre-disc output with 38/40 lobes)."""
    kin = design.kinematics()
    w = 1.0
    return float(kin.mesh_frequencies(w)["ball engagement"]) * 2.0 * math.pi / w


#: ball-set positions over one ball pitch and harmonics of the contact-derived law
CONTACT_PHASES = 32
CONTACT_HARMONICS = 6
#: Load exponent of a ball-groove contact (Hertz's point contact, F ~ delta^1.5)
HERTZ_EXPONENT = 1.5


def centre_disc_torque(design: CycloidBallDesign) -> float:
    """Torque (N m, >= 0) the ball track carries on the centre disc at the operating
    point: the output torque (centre-disc output), or its reaction ``z_c / z_p`` of it
    (planetary-disc output, the centre disc held)."""
    out = abs(design.operating_point().output_torque)
    if design.output == "planetary":
        return out * design.centre_disc.lobes / design.planetary_disc.lobes
    return out


def contact_force_law(design: CycloidBallDesign) -> tuple[TimeLaw, float, float, float]:
    """The ball track's mesh force law at the operating torque: ``K_mx(t)`` (N/m), the
    load exponent ``p``, the reference deflection ``delta_ref`` (m) and the half
    clearance ``h`` (m) of the model's power-law line (``model.elements.Mesh``:
    ``F = K_mx (delta_ref / p) (f / delta_ref)^p``, ``f = s - h`` beyond the clearance).

    ``K_mx(t)`` is the tangent stiffness of :func:`reducerlab.contact.ball_track.
    ball_loads` along ``delta_23`` (``y`` held: the lumped model has no line-of-centres
    freedom of the track) at :data:`CONTACT_PHASES` positions over one ball pitch, as a
    Fourier series of :data:`CONTACT_HARMONICS` harmonics at the ball-engagement
    frequency (the ball set moves by ``-(z_p / Z)`` of the input angle relative to the
    line of centres). The law passes through the operating point (the mean deflection
    ``s`` and force ``F = T / r_2`` over the positions) with the track's slope there,
    ``q = K_mx s / F`` (tangent over secant) choosing its shape:

    * ``q >= 1.5``: Hertz's exponent ``p = 1.5`` beyond a clearance
      ``h = s - 1.5 F / K_mx``. With zero ball clearance every line's approach is
      proportional to ``s`` and the track's force is exactly ``F ~ s^1.5`` (``q = 1.5``,
      ``h = 0``); a clearance delays the first touch and lets balls join as the load
      rises (``q > 1.5``), which the offset stands for;
    * ``1 <= q < 1.5``: ``p = q`` through the origin (a preload softens the law);
    * ``q < 1``: the linear law with the tangent stiffness (a strong preload).

    ``delta_ref = s - h`` (0 for the linear law).

    Raises
    ------
    ReducerlabError
        The design lacks the ball and groove fields, or the track has no stiffness at
        the operating torque (no load and no preload).
    """
    import numpy as np

    from ..contact.ball_track import ball_loads

    track = design.ball_track()
    torque = centre_disc_torque(design)
    n = CONTACT_PHASES
    # time samples over one engagement period: psi_0 = -2 pi j / (Z n)
    psi = -2 * math.pi * np.arange(n) / (track.balls * n)
    states = [ball_loads(track, torque, float(p), y="held") for p in psi]
    k = np.array([st.translational_stiffness for st in states])
    if not k.mean() > 0:
        raise ReducerlabError(
            "cycloid_pair.stiffness_source = 'contact': the ball track has no stiffness at "
            f"{torque:g} N m on the centre disc (no load and no preload); give a load "
            "(output_torque) or a preload (negative cycloid_pair.ball_clearance)"
        )
    c = np.fft.rfft(k) / n
    h = min(CONTACT_HARMONICS, n // 2 - 1)
    amps = tuple(float(2 * abs(c[r])) for r in range(1, h + 1))
    phases = tuple(float(np.angle(c[r])) for r in range(1, h + 1))
    speed = abs(float(design.input_speed))
    omega = engagement_per_input(design) * speed
    law: TimeLaw = (
        Constant(float(k.mean()))
        if speed == 0
        else Fourier(float(c[0].real), amps, omega, phases, ref_speed=speed)
    )
    s_op = float(np.mean([abs(st.s) for st in states]))
    force = abs(torque) / track.pitch_radius
    q = k.mean() * s_op / force if s_op > 0 and force > 0 else 0.0
    if q >= HERTZ_EXPONENT:
        h = s_op - HERTZ_EXPONENT * force / k.mean()
        # below 1e-3 of the deflection: the zero-clearance track (q = 1.5 but for the
        # means over the positions), no clearance
        h = h if h > 1e-3 * s_op else 0.0
        return law, HERTZ_EXPONENT, s_op - h, h
    if q > 1.0:
        return law, float(q), s_op, 0.0
    return law, 1.0, 0.0, 0.0  # preloaded (or at rest): the tangent law


def cross_ball_stiffness(single_pair: float, loaded_balls: int = 6) -> float:
    """Lumped torsional stiffness of the cross-ball mechanism (N/m on ``u``), Eq. 2.

    Three radial taper grooves on each side carry equal loads, so the resultant moment
    over the largest angular deflection gives ``K_w = 6 k_w`` (``loaded_balls = 6``);
    the damping follows the same form (Eq. 9).
    """
    return loaded_balls * single_pair


class InputShaft(Spec):
    """Input shaft (component 1): mass, inertia, supports (N/m on x and on u1 = e theta1);
    ``crank_errors``: the eccentric's errors (transmission accuracy,
    ``drives.accuracy_specs.CrankErrorSpec``)."""

    mass: Mass
    moment_of_inertia: MomentOfInertia
    radial_stiffness: NonNegativeStiffness
    torsional_stiffness: NonNegativeStiffness = 0.0
    radial_damping: Damping = 0.0
    torsional_damping: Damping = 0.0
    crank_errors: CrankErrorSpec | None = None


class CentreDisc(Spec):
    """Centre disc (component 2, output): epitrochoid groove with ``lobes`` lobes;
    ``track_errors``: the groove's eccentricity (``drives.accuracy_specs``)."""

    lobes: PositiveInt
    mass: Mass
    moment_of_inertia: MomentOfInertia
    radial_stiffness: NonNegativeStiffness
    torsional_stiffness: NonNegativeStiffness = 0.0
    radial_damping: Damping = 0.0
    torsional_damping: Damping = 0.0
    pitch_radius: Length | None = None
    track_errors: TrackErrorSpec | None = None


class PlanetaryDisc(Spec):
    """Planetary disc (component 3): hypotrochoid groove, on the eccentric bearing;
    ``track_errors``: the groove's eccentricity (``drives.accuracy_specs``)."""

    lobes: PositiveInt
    mass: Mass
    moment_of_inertia: MomentOfInertia
    bearing_stiffness: NonNegativeStiffness
    bearing_damping: Damping = 0.0
    pitch_radius: Length | None = None
    track_errors: TrackErrorSpec | None = None


class EndCoverDisc(Spec):
    """End cover disc (component 5): torsional support to the housing (N/m on u5)."""

    moment_of_inertia: MomentOfInertia
    torsional_stiffness: Stiffness
    torsional_damping: Damping = 0.0
    mass: Mass | None = None  # listed in paper 003 Table 1; no translational DOF uses it
    pitch_radius: Length | None = None


class CycloidBallPair(Spec):
    """Cycloid-ball meshing pairs (Eq. 1, 8, 10) and, for the ball-track contact
    (``contact.ball_track``, issue 30), the balls and grooves: ``ball_radius``,
    ``groove_conformity`` (groove section radius over ball diameter), the contact angle
    ``groove_half_angle``, ``short_width_coefficient``, ``ball_clearance`` along each
    ball's normal (negative: a preload; one value for every ball) and the elastic
    constants of balls and discs. ``stiffness_source = "contact"`` takes the model's
    ``K_mx(t)`` from the ball track at the operating torque
    (:func:`contact_force_law`) instead of Eq. 1/10 with ``ball_stiffness``.
    ``friction_coefficient``: Coulomb coefficient of the ball contacts (spin and
    sliding) for the efficiency (``analysis.cycloid_efficiency``; default 0.05)."""

    ball_stiffness: Stiffness
    deformation_coefficient: Annotated[Real, Field(gt=0, le=1)]
    balls: PositiveInt | None = None
    ball_damping: Damping = 0.0
    short_width_coefficient: Annotated[Real, Field(gt=0, lt=1)] | None = None
    groove_half_angle: angle_between(0, 90) | None = None  # type: ignore[valid-type]
    ball_radius: Length | None = None
    groove_conformity: Annotated[Real, Field(gt=0.5, lt=1)] | None = None
    ball_clearance: SignedLength = 0.0  # type: ignore[valid-type]
    youngs_modulus: quantity("pressure", gt=0) = 206e9  # type: ignore[valid-type]
    poisson_ratio: Annotated[Real, Field(gt=-1, lt=0.5)] = 0.3
    stiffness_source: Literal["lumped", "contact"] = "lumped"
    friction_coefficient: Annotated[Real, Field(ge=0, le=0.3)] | None = None


class CrossBall(Spec):
    """Cross-ball equal-speed mechanism (Eq. 2, 9)."""

    ball_stiffness: Stiffness
    loaded_balls: PositiveInt = 6
    ball_damping: Damping = 0.0


class CycloidBallDesign(Design):
    """Design of a cycloid ball transmission (``type = "cycloid_ball"``). The load is the
    output disc's: ``output_torque`` (N m) or ``output_power`` (W)."""

    type: Literal["cycloid_ball"] = "cycloid_ball"
    speed_fields: ClassVar = ("input_speed", "speed_range")
    load_fields: ClassVar = ("output_torque", "output_power")
    input_speed: AngularVelocity
    output_torque: Torque | None = None
    output_power: Power | None = None
    eccentricity: Length
    output: Literal["centre", "planetary"] = "centre"
    centripetal: bool = True
    coriolis: bool = False
    speed_range: SpeedRange | None = None  # type: ignore[valid-type]
    input_shaft: InputShaft
    centre_disc: CentreDisc
    planetary_disc: PlanetaryDisc
    end_cover_disc: EndCoverDisc
    cycloid_pair: CycloidBallPair
    cross_ball: CrossBall

    @model_validator(mode="after")
    def _geometry(self) -> CycloidBallDesign:
        if self.coriolis and not self.centripetal:
            raise field_rules((
                "centripetal",
                "coriolis = true reads the model in the rotating frame, which needs its "
                "centripetal terms too: set centripetal = true",
            ))  # fmt: skip
        zc, zp = self.centre_disc.lobes, self.planetary_disc.lobes
        problems = []
        if zp != zc + 2:
            problems.append((
                "planetary_disc.lobes",
                f"planetary_disc.lobes must be centre_disc.lobes + 2 = {zc + 2} (hypotrochoid "
                "over epitrochoid)",
            ))  # fmt: skip
        elif self.cycloid_pair.balls is not None and self.cycloid_pair.balls != self.balls:
            problems.append((
                "cycloid_pair.balls",
                f"cycloid_pair.balls must be (centre lobes + planetary lobes) / 2 = {self.balls}",
            ))  # fmt: skip
        for name, z in (("centre_disc", zc), ("planetary_disc", zp), ("end_cover_disc", zp)):
            r = getattr(self, name).pitch_radius
            want = self.pitch_radius(z)
            if r is not None and abs(r - want) > 1e-6 * want:
                problems.append((
                    f"{name}.pitch_radius",
                    f"{r * 1e3:.6g} mm disagrees with lobes x eccentricity / 2 = "
                    f"{want * 1e3:.6g} mm",
                ))  # fmt: skip
        if problems:
            raise field_rules(*problems)
        return self

    @property
    def balls(self) -> int:
        """Ball count ``(Z_c + Z_p) / 2``."""
        return (self.centre_disc.lobes + self.planetary_disc.lobes) // 2

    def pitch_radius(self, lobes: int) -> float:
        """Pitch radius ``Z e / 2`` of a groove with ``lobes`` lobes (m)."""
        return lobes * self.eccentricity / 2.0

    def kinematics(self) -> DriveKinematics:
        """Ratio and ball-passing frequency of the drive: the ``cycloid_ball`` train."""
        lobes = {"centre": self.centre_disc.lobes, "planetary": self.planetary_disc.lobes}
        return TRAINS["cycloid_ball"].build(lobes, output=self.output)

    def pitch_radii(self) -> dict[str, float]:
        """Pitch radii ``Z e / 2`` (m) of the two grooves of the ball track."""
        return {
            "centre disc": self.pitch_radius(self.centre_disc.lobes),
            "planetary disc": self.pitch_radius(self.planetary_disc.lobes),
        }

    def ball_track(self) -> BallTrack:
        """The ball track of the contact analysis (``contact.ball_track.BallTrack``)
        from ``[cycloid_pair]``.

        Raises
        ------
        ReducerlabError
            Naming the fields the contact needs that the design does not give.
        """
        from ..contact.ball_track import BallTrack

        p = self.cycloid_pair
        need = {
            "cycloid_pair.ball_radius": p.ball_radius,
            "cycloid_pair.groove_conformity": p.groove_conformity,
            "cycloid_pair.groove_half_angle": p.groove_half_angle,
            "cycloid_pair.short_width_coefficient": p.short_width_coefficient,
        }
        missing = [k for k, v in need.items() if v is None]
        if missing:
            raise ReducerlabError(
                "the ball-track contact needs " + ", ".join(missing) + " (paper 003 gives "
                "none of them; see examples/cycloid_ball.toml)"
            )
        return BallTrack(
            self.centre_disc.lobes, self.eccentricity, p.short_width_coefficient,
            p.ball_radius, p.groove_conformity, p.groove_half_angle,
            p.youngs_modulus, p.poisson_ratio, p.ball_clearance,
        )  # fmt: skip

    @property
    def mesh_stiffness(self) -> float:
        """Mean lumped stiffness ``K_mx`` of the cycloid-ball pairs (N/m), paper 003 Eq.
        1/10 with ``ball_stiffness`` (with ``stiffness_source = "contact"`` the model
        takes :func:`contact_force_law` instead)."""
        p = self.cycloid_pair
        return cycloid_ball_stiffness(p.ball_stiffness, self.balls, p.deformation_coefficient)


def _with_coriolis(
    design: CycloidBallDesign, dofs: list[Dof], elements: list, pair_damping: float
) -> tuple[list[Dof], list]:
    """Paper 003's model completed in its rotating frame: the translations ``y`` normal
    to ``x`` of the input shaft, centre disc and planetary disc, with the Coriolis
    coupling ``2 m Omega`` of each body's ``(x, y)``, the centripetal ``-m Omega^2`` on
    ``y``, isotropic bearings (``k_y = k_x``: radial ball bearings), the cycloid-ball
    pairs' stiffness along ``y`` (paper 003 Eq. 1 with ``cos^2`` for ``sin^2``: the
    same ``k_m Z_m / 2a`` for balls spread evenly over the circle, at its mean) and the
    circulatory term of the housing-fixed bearings' damping (input shaft, centre disc).
    """
    s, c, p = design.input_shaft, design.centre_disc, design.planetary_disc
    pair = design.cycloid_pair
    bodies = (("input_shaft", s.mass), ("centre_disc", c.mass), ("planetary_disc", p.mass))
    dofs = dofs + [Dof(body, "y") for body, _ in bodies]
    k_pair = cycloid_ball_stiffness(pair.ball_stiffness, design.balls, pair.deformation_coefficient)
    elements = elements + [Inertia(f"{body}.y", m) for body, m in bodies]
    elements += [
        Support("input_shaft.y", s.radial_stiffness, s.radial_damping, name="k1y"),
        Support("centre_disc.y", c.radial_stiffness, c.radial_damping, name="k2y"),
        Coupling({"input_shaft.y": 1.0, "planetary_disc.y": -1.0}, p.bearing_stiffness,
                 p.bearing_damping, name="k3y"),
        Coupling({"centre_disc.y": 1.0, "planetary_disc.y": -1.0}, k_pair, pair_damping,
                 name="cycloid_pairs_y"),
    ]  # fmt: skip
    for body, m in bodies:
        elements.append(Coriolis((f"{body}.x", f"{body}.y"), m, name=f"coriolis_{body}"))
        if design.centripetal:
            elements.append(Centripetal(f"{body}.y", m, name=f"centripetal_{body}_y"))
    for body, sup in (("input_shaft", s), ("centre_disc", c)):
        if sup.radial_damping:
            elements.append(
                StationaryDamping((f"{body}.x", f"{body}.y"), sup.radial_damping,
                                  name=f"stationary_damping_{body}")
            )  # fmt: skip
    return dofs, elements


def build_model(design: CycloidBallDesign) -> Model:
    """The 7-DOF model of paper 003 Eq. 3-7 and 11 on the generic core; with
    ``coriolis`` the 10-DOF rotating-frame model of :func:`_with_coriolis`."""
    e = design.eccentricity
    r2 = design.pitch_radius(design.centre_disc.lobes)
    r3 = design.pitch_radius(design.planetary_disc.lobes)
    r5 = r3
    s, c, p, v = (
        design.input_shaft,
        design.centre_disc,
        design.planetary_disc,
        design.end_cover_disc,
    )
    pair, cross = design.cycloid_pair, design.cross_ball
    dofs = [
        Dof("input_shaft", "x"),
        Dof("input_shaft", "u", radius=e),
        Dof("centre_disc", "x"),
        Dof("centre_disc", "u", radius=r2),
        Dof("planetary_disc", "x"),
        Dof("planetary_disc", "u", radius=r3),
        Dof("end_cover_disc", "u", radius=r5),
    ]
    damping = cycloid_ball_stiffness(pair.ball_damping, design.balls, pair.deformation_coefficient)
    # the ball track's law (tangent stiffness, Hertzian load exponent) or paper 003's
    law, exponent, reference, clearance = (
        contact_force_law(design) if pair.stiffness_source == "contact" else (None, 1.0, 0.0, 0.0)
    )
    elements = [
        Inertia("input_shaft.x", s.mass),
        Inertia("input_shaft.u", s.moment_of_inertia),
        Inertia("centre_disc.x", c.mass),
        Inertia("centre_disc.u", c.moment_of_inertia),
        Inertia("planetary_disc.x", p.mass),
        Inertia("planetary_disc.u", p.moment_of_inertia),
        Inertia("end_cover_disc.u", v.moment_of_inertia),
        Support("input_shaft.x", s.radial_stiffness, s.radial_damping, name="k1x"),
        Support("input_shaft.u", s.torsional_stiffness, s.torsional_damping, name="k1u"),
        Support("centre_disc.x", c.radial_stiffness, c.radial_damping, name="k2x"),
        Support("centre_disc.u", c.torsional_stiffness, c.torsional_damping, name="k2u"),
        Support("end_cover_disc.u", v.torsional_stiffness, v.torsional_damping, name="k5u"),
        # delta_13 = x1 - x3 - u1: eccentric bearing (paper 003 Eq. 5)
        Coupling(
            {"input_shaft.x": 1.0, "planetary_disc.x": -1.0, "input_shaft.u": -1.0},
            p.bearing_stiffness,
            p.bearing_damping,
            name="k3x",
        ),
        # delta_23 = x2 - x3 + u2 - u3: cycloid-ball pairs (Eq. 3, 1, 8, 10)
        Mesh(
            {
                "centre_disc.x": 1.0,
                "planetary_disc.x": -1.0,
                "centre_disc.u": 1.0,
                "planetary_disc.u": -1.0,
            },
            stiffness=law
            if law is not None
            else cycloid_ball_law(
                pair.ball_stiffness,
                design.balls,
                pair.deformation_coefficient,
                pair.short_width_coefficient,
                design.input_speed,
                engagement_per_input(design),
            ),
            damping=damping,
            backlash=Backlash(clearance) if clearance > 0 else None,
            name="cycloid_pairs",
            exponent=exponent,
            reference_deflection=reference,
        ),
        # delta_53 = u5 - u3: cross-ball equal-speed mechanism (Eq. 4, 2, 9)
        Coupling(
            {"end_cover_disc.u": 1.0, "planetary_disc.u": -1.0},
            cross_ball_stiffness(cross.ball_stiffness, cross.loaded_balls),
            cross_ball_stiffness(cross.ball_damping, cross.loaded_balls),
            name="cross_ball",
        ),
    ]
    if design.centripetal:
        for body, m in (
            ("input_shaft", s.mass),
            ("centre_disc", c.mass),
            ("planetary_disc", p.mass),
        ):
            elements.append(Centripetal(f"{body}.x", m, name=f"centripetal_{body}"))
    point = design.operating_point()
    if point.loaded:
        # paper 003 Eq. 7's F = [0, T_i/e, 0, -T_o/r2, 0, 0, 0]: the lossless input torque
        # on u1 = e theta1 and, on the output (centre disc, or the end cover that takes the
        # planetary disc's rotation out), the load -T_out sign(omega_out), whose work on
        # the rigid rotation (theta_out = theta_in / i) cancels the input's
        out_dof, r_out = ("centre_disc.u", r2)
        if design.output == "planetary":
            out_dof, r_out = ("end_cover_disc.u", r5)
        out = -math.copysign(point.output_torque, point.output_speed)
        elements += [
            Load("input_shaft.u", point.input_torque / e, name="input_torque"),
            Load(out_dof, out / r_out, name="output_torque"),
        ]
    if design.coriolis:
        dofs, elements = _with_coriolis(design, dofs, elements, damping)
    return Model(
        dofs,
        elements,
        speed=design.input_speed,
        name=design.name or "cycloid ball transmission",
        metadata=design.provenance,
    )
