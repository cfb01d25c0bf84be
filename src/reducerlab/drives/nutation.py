"""Nutation drive with spiral bevel gears (paper 000): single- and double-sided
bending-torsional-axial lumped model.

Double-sided (paper 000 Fig. 1-2): nutating internal gears 1 and 3 are one body
("13"); gear 1 meshes the fixed external gear 2, gear 3 the output external gear 4.
Each body has ``x, y, z`` translations and the rotation ``rz`` about its axis
(paper 000 Eq. 1: 12 DOFs). Single-sided: one nutating gear ("13", gear 1) and one
external gear ("2"): 8 DOFs.

Mesh deflection (paper 000 Eq. 2-3): ``lambda = a_n . (x, y, z)_13 + a_n,y r_mn theta_13
- a_c . (x, y, z)_c - a_c,y r_mc theta_c - e(t)`` with the unit normal of the tooth
contact in the mesh frame (paper 000 Eq. 4, for a gear of pitch cone angle ``delta``,
spiral angle ``beta`` and normal pressure angle ``alpha_n``)::

    n(delta) = (-(cos d sin a + sin d sin b cos a), cos b cos a, sin d sin a - cos d sin b cos a)

and, for the nutating gear, ``n(delta)`` turned by the nutation angle ``theta`` about
y (Eq. 4's ``a_11, a_13`` with ``cos d sin b cos a`` where the text prints
``cos d sin d cos a``; see docs/assumptions.md). The mesh force acts as ``g F`` with
``g = d(lambda)/dq`` (symmetric ``K = k g g^T``), not with the signs of Eq. 7.
"""

from __future__ import annotations

import math
from typing import ClassVar, Literal

from pydantic import Field, model_validator
from scipy.optimize import brentq

from ..design import (
    AngularVelocity,
    Design,
    Length,
    PositiveInt,
    Power,
    SpeedRange,
    Torque,
    angle_between,
    quantity,
)
from ..design_files import field_rules
from ..errors import ReducerlabError
from ..kinematics import TRAINS, DriveKinematics, gyroscopic_moment
from ..kinematics.mesh import internal_cone_angles
from ..model import (
    Backlash,
    Centripetal,
    Constant,
    Coriolis,
    Dof,
    Fourier,
    Inertia,
    Load,
    Mesh,
    Model,
    Nutating,
    StationaryDamping,
    Support,
)
from ..model.laws import TimeLaw
from .nutation_mesh import contact_normal, drive_loads, sliding_direction, tilt_lever
from .nutation_specs import Bevel, MaterialSpec, MeshSpec, Support3, SurfaceSpec, TiltSupport

__all__ = ["NutationDesign", "build_model"]

#: Relative tolerance on the agreement of the mean cone distances of all gears.
CONE_DISTANCE_TOL = 1e-3


class NutationDesign(Design):
    """Design of a nutation drive (``type = "nutation"``). The load is the output's:
    ``output_torque`` (N m, on gear 4, or on the nutating gear's coupling single-sided)
    or ``output_power`` (W); the fixed gear's reaction follows from the torque flow."""

    type: Literal["nutation"] = "nutation"
    speed_fields: ClassVar = ("input_speed", "speed_range")
    load_fields: ClassVar = ("output_torque", "output_power")
    retired_fields: ClassVar = {
        "input_torque": "it loaded the fixed gear 2 (paper 000's T1), whose reaction now "
        "follows from the output load by the torque flow: give the load as output_torque "
        "or output_power (the crank's torque is then output_torque / i)"
    }
    sides: Literal["single", "double"] = "double"
    input_speed: AngularVelocity
    speed_range: SpeedRange | None = None  # type: ignore[valid-type]
    output_torque: Torque | None = None
    output_power: Power | None = None
    module: Length
    helix_angle: angle_between(0, 60, closed=True)  # type: ignore[valid-type]
    normal_pressure_angle: angle_between(5, 45)  # type: ignore[valid-type]
    nutation_angle: angle_between(0, 60) | None = None  # type: ignore[valid-type]
    nutating_bearings: PositiveInt = 2
    gyroscopic: bool = True
    tilt13: TiltSupport | None = None
    rotating_frame: bool = False
    gear1: Bevel
    gear2: Bevel
    gear3: Bevel | None = None
    gear4: Bevel | None = None
    support2: Support3
    support13: Support3
    support4: Support3 | None = None
    fixed_gear_torsional_stiffness: quantity("torsional stiffness", ge=0) = 0.0  # type: ignore[valid-type]
    mesh1: MeshSpec
    mesh2: MeshSpec | None = None
    surface: SurfaceSpec | None = None
    material: MaterialSpec = Field(default_factory=MaterialSpec)

    @model_validator(mode="after")
    def _errors_fit(self) -> NutationDesign:
        problems = []
        for k in range(1, 5):
            g = getattr(self, f"gear{k}")
            if g is not None and g.errors is not None:
                problems += g.errors.check_teeth(f"gear{k}.errors", g.teeth)
        if problems:
            raise field_rules(*problems)
        return self

    @model_validator(mode="after")
    def _geometry(self) -> NutationDesign:
        double = self.sides == "double"
        optional = ("gear3", "gear4", "support4", "mesh2")
        missing = [n for n in optional if double and getattr(self, n) is None]
        extra = [n for n in optional if not double and getattr(self, n) is not None]
        if missing:
            raise field_rules(("sides", f"a double-sided drive needs {missing}"))
        if extra:
            raise field_rules(("sides", f"a single-sided drive has no {extra}"))
        if not double and self.nutation_angle is None:
            raise field_rules(("nutation_angle", "a single-sided drive needs nutation_angle"))
        if self.input_speed <= 0:
            raise field_rules(("input_speed", "must be > 0"))
        for name in ("mesh1", "mesh2"):
            spec = getattr(self, name)
            if spec is not None and spec.stiffness == "contact" and self.surface is None:
                raise field_rules((
                    f"{name}.stiffness",
                    '"contact" needs the tooth surfaces: add a [surface] table (profile, '
                    "face_width)",
                ))  # fmt: skip
        if self.rotating_frame:
            # the housing-fixed supports (the nutating gear's bearings turn with the
            # crank, so any support13 is steady in the mesh frame)
            for name in ("support2", "support4"):
                sup = getattr(self, name)
                for q in "kc":
                    a, b = (getattr(sup, f"{q}_{x}") for x in "xy") if sup else (0.0, 0.0)
                    if not math.isclose(a, b, rel_tol=1e-9, abs_tol=0.0):
                        raise field_rules((
                            f"{name}.{q}_y",
                            f"rotating_frame needs isotropic supports ({q}_x = {q}_y): an "
                            "anisotropic support seen from the turning mesh frame is time-varying",
                        ))  # fmt: skip
        for k, pair in enumerate(self._pairs()):
            zn, zc = pair[0].teeth, pair[1].teeth
            if zn <= zc:
                raise field_rules((
                    f"gear{2 * k + 1}.teeth",
                    f"the nutating (internal) gear needs more teeth than its mate "
                    f"gear{2 * k + 2}, got {zn} <= {zc}",
                ))  # fmt: skip
        try:
            theta = self.theta  # derives / checks the cone geometry
        except ValueError as exc:  # no angle makes the mean radii agree
            raise field_rules(("gear1.mean_radius", str(exc))) from None
        distances = self.cone_distances(theta)
        ref = distances[0]
        bad = [(k, d) for k, d in enumerate(distances) if abs(d / ref - 1) > CONE_DISTANCE_TOL]
        if bad:
            listing = ", ".join(f"{d * 1e3:.5g} mm" for d in distances)
            raise field_rules((
                "nutation_angle" if self.nutation_angle is not None else "gear1.mean_radius",
                f"mean cone distances r_m / sin(delta) disagree ({listing}) at nutation angle "
                f"{math.degrees(theta):.5g} deg: the tooth numbers, mean radii and nutation "
                "angle are inconsistent",
            ))  # fmt: skip
        if self.surface is not None:
            self._check_surface(distances[0])
        return self

    def _check_surface(self, cone_distance: float) -> None:
        sf = self.surface
        assert sf is not None
        if not sf.face_width < cone_distance:
            raise field_rules((
                "surface.face_width",
                f"{sf.face_width * 1e3:.5g} mm must be smaller than the mean cone distance "
                f"{cone_distance * 1e3:.5g} mm",
            ))  # fmt: skip
        if sf.normal_module is None:
            return
        for k in range(1, self.gear_count + 1):
            m_r = self.surface_module(k)
            if abs(sf.normal_module / m_r - 1) > CONE_DISTANCE_TOL:
                raise field_rules((
                    "surface.normal_module",
                    f"surface.normal_module {sf.normal_module * 1e3:.6g} mm disagrees with the "
                    "mean radius of "
                    f"gear{k}: 2 r_m cos(beta) / z = {m_r * 1e3:.6g} mm (omit it to take each "
                    "gear's module from its mean radius)",
                ))  # fmt: skip

    @property
    def spiral_angle(self) -> float:
        """Mean spiral angle of the tooth surfaces (rad): ``surface.spiral_angle`` or
        ``helix_angle``."""
        sf = self.surface
        return self.helix_angle if sf is None or sf.spiral_angle is None else sf.spiral_angle

    def surface_module(self, gear: int = 1) -> float:
        """Normal module at the mean point implied by a gear's mean radius (m):
        ``2 r_m cos(beta) / z`` (the same for both gears of a pair)."""
        g = getattr(self, f"gear{gear}")
        return 2 * g.mean_radius * math.cos(self.spiral_angle) / g.teeth

    @property
    def has_tooth_surfaces(self) -> bool:
        """Whether the ``[surface]`` table gives the tooth-surface geometry (paper 001)."""
        return self.surface is not None

    def tooth_generation(self, gear: int, profile: str | None = None):
        """Crown gear and bevel gear that generate gear ``gear`` (1-4) of the drive.

        Parameters
        ----------
        gear : int
            1 or 3: nutating internal gears; 2 or 4: external gears.
        profile : {"involute", "double-arc"}, optional
            Overrides ``surface.profile``.

        Returns
        -------
        (CrownGear, BevelGear)
        """
        from ..geometry import (
            BevelGear,
            CrownGear,
            DoubleCircularArcProfile,
            InvoluteProfile,
        )

        if self.surface is None:
            raise ValueError(
                "the design has no 'surface' table (profile, face_width): add one, see "
                "examples/nutation_surface.toml"
            )
        if gear not in range(1, self.gear_count + 1):
            raise ValueError(
                f"gear must be 1..{self.gear_count} for a {self.sides}-sided drive; got {gear}"
            )
        kind = profile or self.surface.profile
        pair = (gear - 1) // 2
        # one module per pair (from its nutating gear's mean radius when not given): both
        # gears of a pair must be generated by the same crown gear to be conjugate
        m_n = self.surface.normal_module or self.surface_module(2 * pair + 1)
        if kind == "involute":
            prof = InvoluteProfile(m_n, self.normal_pressure_angle)
        elif kind == "double-arc":
            prof = DoubleCircularArcProfile(m_n)
        else:
            raise ValueError(f"profile must be 'involute' or 'double-arc'; got {kind!r}")
        d_nut, d_cen = self.cones(self.theta)[pair]
        spec = self._pairs()[pair][(gear - 1) % 2]
        delta = d_nut if gear % 2 == 1 else d_cen
        bevel = BevelGear(spec.teeth, delta, "internal" if gear % 2 == 1 else "external")
        crown = CrownGear.for_gear(
            prof, spec.teeth, delta, self.spiral_angle, self.surface.face_width
        )
        return crown, bevel

    @property
    def gear_count(self) -> int:
        """Bevel gears of the drive: 4 double-sided, 2 single-sided."""
        return 4 if self.sides == "double" else 2

    def _pairs(self) -> list[tuple[Bevel, Bevel]]:
        pairs = [(self.gear1, self.gear2)]
        if self.sides == "double":
            pairs.append((self.gear3, self.gear4))  # type: ignore[arg-type]
        return pairs

    def cones(self, theta: float) -> list[tuple[float, float]]:
        """Pitch cone angles ``(delta_nutating, delta_central)`` of each pair (rad)."""
        return [internal_cone_angles(n.teeth, c.teeth, theta) for n, c in self._pairs()]

    def cone_distances(self, theta: float) -> list[float]:
        """Mean cone distance ``r_m / sin(delta)`` of every gear (m)."""
        out = []
        for (n, c), (dn, dc) in zip(self._pairs(), self.cones(theta), strict=True):
            out += [n.mean_radius / math.sin(dn), c.mean_radius / math.sin(dc)]
        return out

    @property
    def theta(self) -> float:
        """Nutation angle (rad): given, or the one at which the mean cone distances of the
        two pairs agree (double-sided drive)."""
        if self.nutation_angle is not None:
            return self.nutation_angle

        def f(th: float) -> float:
            d = self.cone_distances(th)
            return d[0] - d[2]

        lo, hi = math.radians(0.05), math.radians(60)
        if f(lo) * f(hi) > 0:
            raise ValueError(
                "no nutation angle in (0.05, 60) deg makes the two pairs' mean cone distances "
                "agree: give nutation_angle or check the mean radii"
            )
        return brentq(f, lo, hi, xtol=1e-14)

    def kinematics(self) -> DriveKinematics:
        """Ratio and mesh frequencies (gear 2 fixed; output gear 4, or the nutating gear's
        net rotation through a coupling for a single-sided drive): the
        ``double_nutation`` or ``nutation`` train."""
        if self.sides == "double":
            teeth = {f"z{k}": getattr(self, f"gear{k}").teeth for k in range(1, 5)}
            return TRAINS["double_nutation"].build(teeth, self.theta)
        teeth = {"nutating": self.gear1.teeth, "central": self.gear2.teeth}
        return TRAINS["nutation"].build(teeth, self.theta, output="nutating")

    def pitch_radii(self) -> dict[str, float]:
        """Mean radii ``r_m`` (m) by the kinematics' gear names."""
        if self.sides == "double":
            return {f"gear {k}": getattr(self, f"gear{k}").mean_radius for k in range(1, 5)}
        return {"nutating gear": self.gear1.mean_radius, "central gear": self.gear2.mean_radius}


def _law(spec: MeshSpec, omega: float, speed: float, name: str) -> TimeLaw:
    if spec.stiffness == "contact":
        raise ReducerlabError(
            f'{name}.stiffness = "contact": the mesh stiffness comes from the loaded tooth '
            "contact at the operating point, which `reducerlab run` computes (or write a number, "
            "e.g. with `reducerlab contact --write-design`)"
        )
    if not spec.harmonics:
        return Constant(spec.stiffness)
    return Fourier(spec.stiffness, tuple(spec.harmonics), omega, tuple(spec.phases),
                   ref_speed=speed)  # fmt: skip


def build_model(design: NutationDesign) -> Model:
    """The 12-DOF (double) or 8-DOF (single) model of paper 000 on the generic core.

    With ``tilt13`` the nutating gear also tilts (``rx, ry``: 14 or 10 DOFs), the meshes
    couple its tilts through the contact point's lever arm and, with ``gyroscopic``, its
    steady precession adds the :class:`~reducerlab.model.Nutating` terms. With
    ``rotating_frame`` every body's ``x, y`` is read in the mesh frame, which turns with
    the input crank: Coriolis and centripetal terms for all bodies and the circulatory
    term of the housing-fixed supports' damping (gears 2 and 4; the nutating gear's
    bearings turn with the crank). See docs/assumptions.md.
    """
    kin = design.kinematics()
    th = kin.nutation_angle  # design.theta, without solving for it a second time
    b, an = design.helix_angle, design.normal_pressure_angle
    double = design.sides == "double"
    bodies = ["g2", "g13"] + (["g4"] if double else [])
    tilt = design.tilt13
    dofs = []
    for body in bodies:
        kinds = (
            ("x", "y", "z", "rx", "ry", "rz") if body == "g13" and tilt else ("x", "y", "z", "rz")
        )
        dofs += [Dof(body, k) for k in kinds]
    g3 = design.gear3 if double else None
    nutating = (design.gear1, g3) if g3 else (design.gear1,)
    m13 = sum(g.mass for g in nutating)
    J13 = sum(g.J_z for g in nutating)
    bodies_data = [("g2", design.gear2.mass, design.gear2.J_z, design.support2, 1)]
    bodies_data.append(("g13", m13, J13, design.support13, design.nutating_bearings))
    if double:
        bodies_data.append(("g4", design.gear4.mass, design.gear4.J_z, design.support4, 1))  # type: ignore[union-attr]
    elements: list = []
    for body, m, J, sup, n_b in bodies_data:
        elements += [Inertia(f"{body}.{q}", m) for q in "xyz"] + [Inertia(f"{body}.rz", J)]
        for q in "xyz":
            elements.append(
                Support(
                    f"{body}.{q}",
                    n_b * getattr(sup, f"k_{q}"),
                    n_b * getattr(sup, f"c_{q}"),
                    name=f"support_{body}_{q}",
                )
            )
        if design.rotating_frame:  # mesh frame turning at the input speed (ratio 1)
            elements.append(Coriolis((f"{body}.x", f"{body}.y"), m, name=f"coriolis_{body}"))
            elements += [
                Centripetal(f"{body}.{q}", m, name=f"centripetal_{body}_{q}") for q in "xy"
            ]
            if body != "g13" and sup.c_x:
                elements.append(
                    StationaryDamping((f"{body}.x", f"{body}.y"), n_b * sup.c_x,
                                      name=f"stationary_damping_{body}")
                )  # fmt: skip
    cone = design.cone_distances(th)
    if tilt is not None:
        # about the nutation centre: parallel-axis terms of each gear (see TiltSupport)
        pairs_ = zip(nutating, design.cones(th), strict=True)
        shift = sum(
            g.mass * (cone[2 * k] * math.cos(dn)) ** 2 for k, (g, (dn, _)) in enumerate(pairs_)
        )
        J13x = tilt.J_x if tilt.J_x is not None else sum(g.J_x for g in nutating) + shift
        J13y = tilt.J_y if tilt.J_y is not None else sum(g.J_y for g in nutating) + shift
        elements += [Inertia("g13.rx", J13x), Inertia("g13.ry", J13y)]
        elements.append(Support("g13.rx", tilt.k_rx, tilt.c_rx, name="support_g13_rx"))
        elements.append(Support("g13.ry", tilt.k_ry, tilt.c_ry, name="support_g13_ry"))
    if design.fixed_gear_torsional_stiffness:
        elements.append(
            Support("g2.rz", design.fixed_gear_torsional_stiffness, name="support_g2_rz")
        )
    mesh_hz = list(kin.mesh_frequencies(design.input_speed).values())
    pairs = [(design.gear1, design.gear2, "g2", design.mesh1)]
    if double:
        pairs.append((design.gear3, design.gear4, "g4", design.mesh2))  # type: ignore[arg-type]
    for j, ((n, c, cbody, spec), (dn, dc)) in enumerate(zip(pairs, design.cones(th), strict=True)):
        a_n = contact_normal(dn, b, an, th)
        a_c = contact_normal(dc, b, an)
        g = {
            "g13.x": a_n[0], "g13.y": a_n[1], "g13.z": a_n[2], "g13.rz": a_n[1] * n.mean_radius,
            f"{cbody}.x": -a_c[0], f"{cbody}.y": -a_c[1], f"{cbody}.z": -a_c[2],
            f"{cbody}.rz": -a_c[1] * c.mean_radius,
        }  # fmt: skip
        if tilt is not None:
            g["g13.rx"], g["g13.ry"] = tilt_lever(dn, dc, b, an, th, cone[2 * j + 1])
        t_n, t_c = sliding_direction(a_n), sliding_direction(a_c)
        slide = {
            "g13.x": t_n[0], "g13.y": t_n[1], "g13.z": t_n[2], "g13.rz": t_n[1] * n.mean_radius,
            f"{cbody}.x": -t_c[0], f"{cbody}.y": -t_c[1], f"{cbody}.z": -t_c[2],
            f"{cbody}.rz": -t_c[1] * c.mean_radius,
        }  # fmt: skip
        omega = 2 * math.pi * mesh_hz[j]
        error = Fourier(0.0, (spec.error_amplitude,), omega, ref_speed=design.input_speed)
        elements.append(
            Mesh(
                g,
                stiffness=_law(spec, omega, design.input_speed, f"mesh{j + 1}"),
                damping=spec.damping,
                backlash=Backlash.full(spec.backlash),
                error=error,
                name=f"mesh{j + 1}",
                exponent=spec.exponent,
                reference_deflection=spec.reference_deflection,
                sliding=slide,
            )
        )
    if design.gyroscopic and tilt is not None:
        # steady precession of the nutating body (paper 002's Euler rates), linearised
        dpsi = kin.nutating_motion(design.input_speed).dpsi
        gyro = Nutating(
            ("g13.rx", "g13.ry", "g13.rz"),
            polar=J13,
            diametral=0.5 * (J13x + J13y),
            nutation=th,
            spin_ratio=dpsi / design.input_speed,
            name="gyroscopic",
        )
        elements.append(gyro)
        # the moment that holds the precession, as the crank's bearings feel it
        elements.append(Load("g13.ry", -gyro.steady_moment(design.input_speed), name="L13"))
    elif design.gyroscopic:
        # L1, L3 (Eq. 7): gyroscopic moments of the nutating gears in steady precession,
        # applied as paper 000 does, as L / r_m on y13
        dpsi = kin.nutating_motion(design.input_speed).dpsi
        total = 0.0
        for gear in nutating:
            M = gyroscopic_moment((gear.J_x, gear.J_y, gear.J_z), 0.0, th, 0.0,
                                  design.input_speed, 0.0, dpsi, frame="fixed")  # fmt: skip
            total += float((M[0] ** 2 + M[1] ** 2) ** 0.5) / gear.mean_radius
        if total:
            elements.append(Load("g13.y", total, name="gyroscopic"))
    levers = {(e.name, d): g for e in elements if isinstance(e, Mesh)
              for d, g in e.coefficients.items() if d.endswith(".rz")}  # fmt: skip
    grounded = design.fixed_gear_torsional_stiffness > 0
    elements += drive_loads(kin, design.operating_point(), levers, grounded)
    return Model(
        dofs,
        elements,
        speed=design.input_speed,
        name=design.name or f"{design.sides}-sided nutation drive",
        metadata=design.provenance,
    )
