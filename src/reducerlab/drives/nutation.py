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
from typing import Literal

from pydantic import Field, model_validator
from scipy.optimize import brentq

from ..design import (
    AngularVelocity,
    Damping,
    Design,
    Length,
    Mass,
    MomentOfInertia,
    NonNegativeStiffness,
    PositiveInt,
    Spec,
    SpeedRange,
    Stiffness,
    Torque,
    angle_between,
    quantity,
)
from ..kinematics import DoubleNutationDrive, NutationDrive, gyroscopic_moment
from ..kinematics.mesh import internal_cone_angles
from ..model import Backlash, Constant, Dof, Fourier, Inertia, Load, Mesh, Model, Support
from ..model.laws import TimeLaw

__all__ = ["NutationDesign", "build_model", "contact_normal"]

#: Relative tolerance on the agreement of the mean cone distances of all gears.
CONE_DISTANCE_TOL = 1e-3


def contact_normal(delta: float, beta: float, alpha_n: float, nutation: float = 0.0):
    """Unit contact normal ``(a_x, a_y, a_z)`` of a bevel gear (paper 000 Eq. 4).

    Parameters
    ----------
    delta : float
        Pitch cone angle (rad).
    beta, alpha_n : float
        Spiral (helix) angle and normal pressure angle (rad).
    nutation : float
        Rotation about y of the nutating gear's frame (rad); 0 for a central gear.
    """
    A = math.cos(delta) * math.sin(alpha_n) + math.sin(delta) * math.sin(beta) * math.cos(alpha_n)
    C = math.sin(delta) * math.sin(alpha_n) - math.cos(delta) * math.sin(beta) * math.cos(alpha_n)
    x, z = -A, C
    c, s = math.cos(nutation), math.sin(nutation)
    return (x * c + z * s, math.cos(beta) * math.cos(alpha_n), -x * s + z * c)


class Bevel(Spec):
    """One spiral bevel gear (paper 000 Table 1)."""

    teeth: PositiveInt
    mass: Mass
    J_x: MomentOfInertia
    J_y: MomentOfInertia
    J_z: MomentOfInertia
    mean_radius: Length


class Support3(Spec):
    """Support stiffness and damping of one body along x, y, z (paper 000 Table 2)."""

    k_x: NonNegativeStiffness
    k_y: NonNegativeStiffness
    k_z: NonNegativeStiffness
    c_x: Damping = 0.0
    c_y: Damping = 0.0
    c_z: Damping = 0.0


class MeshSpec(Spec):
    """One gear pair: mean mesh stiffness, optional Fourier terms (Eq. 8), damping,
    full backlash (Eq. 6) and transmission error amplitude."""

    stiffness: Stiffness
    harmonics: list[quantity("stiffness", ge=0)] = Field(default_factory=list)  # type: ignore[valid-type]
    phases: list[angle_between(-360, 360, closed=True)] = Field(default_factory=list)  # type: ignore[valid-type]
    damping: Damping = 0.0
    backlash: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]
    error_amplitude: quantity("length", ge=0) = 0.0  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _terms(self) -> MeshSpec:
        if self.phases and len(self.phases) != len(self.harmonics):
            raise ValueError(
                f"phases has {len(self.phases)} entries, harmonics {len(self.harmonics)}"
            )
        if sum(self.harmonics) > self.stiffness:
            raise ValueError("harmonics add up to more than the mean stiffness")
        return self


class NutationDesign(Design):
    """Design of a nutation drive (``type = "nutation"``)."""

    type: Literal["nutation"] = "nutation"
    sides: Literal["single", "double"] = "double"
    input_speed: AngularVelocity
    speed_range: SpeedRange | None = None  # type: ignore[valid-type]
    input_torque: Torque = 0.0
    output_torque: Torque = 0.0
    module: Length
    helix_angle: angle_between(0, 60, closed=True)  # type: ignore[valid-type]
    normal_pressure_angle: angle_between(5, 45)  # type: ignore[valid-type]
    nutation_angle: angle_between(0, 60) | None = None  # type: ignore[valid-type]
    nutating_bearings: PositiveInt = 2
    gyroscopic: bool = True
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

    @model_validator(mode="after")
    def _geometry(self) -> NutationDesign:
        double = self.sides == "double"
        optional = ("gear3", "gear4", "support4", "mesh2")
        missing = [n for n in optional if double and getattr(self, n) is None]
        extra = [n for n in optional if not double and getattr(self, n) is not None]
        if missing:
            raise ValueError(f"a double-sided drive needs {missing}")
        if extra:
            raise ValueError(f"a single-sided drive has no {extra}")
        if not double and self.nutation_angle is None:
            raise ValueError("a single-sided drive needs nutation_angle")
        if self.input_speed <= 0:
            raise ValueError("input_speed must be > 0")
        for pair in self._pairs():
            zn, zc = pair[0].teeth, pair[1].teeth
            if zn <= zc:
                raise ValueError(
                    f"the nutating (internal) gear needs more teeth than its mate, got {zn} <= {zc}"
                )
        theta = self.theta  # derives / checks the cone geometry
        distances = self.cone_distances(theta)
        ref = distances[0]
        bad = [(k, d) for k, d in enumerate(distances) if abs(d / ref - 1) > CONE_DISTANCE_TOL]
        if bad:
            listing = ", ".join(f"{d * 1e3:.5g} mm" for d in distances)
            raise ValueError(
                f"mean cone distances r_m / sin(delta) disagree ({listing}) at nutation angle "
                f"{math.degrees(theta):.5g} deg: the tooth numbers, mean radii and nutation "
                "angle are inconsistent"
            )
        return self

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

    def kinematics(self) -> DoubleNutationDrive | NutationDrive:
        """Ratio and mesh frequencies (gear 2 fixed; output gear 4, or the nutating gear's
        net rotation through a coupling for a single-sided drive)."""
        if self.sides == "double":
            return DoubleNutationDrive(
                self.gear1.teeth, self.gear2.teeth, self.gear3.teeth, self.gear4.teeth,  # type: ignore[union-attr]
                self.theta,
            )  # fmt: skip
        return NutationDrive(self.gear1.teeth, self.gear2.teeth, self.theta, output="nutating")


def _law(spec: MeshSpec, omega: float, speed: float) -> TimeLaw:
    if not spec.harmonics:
        return Constant(spec.stiffness)
    return Fourier(spec.stiffness, tuple(spec.harmonics), omega, tuple(spec.phases),
                   ref_speed=speed)  # fmt: skip


def build_model(design: NutationDesign) -> Model:
    """The 12-DOF (double) or 8-DOF (single) model of paper 000 on the generic core."""
    th = design.theta
    b, an = design.helix_angle, design.normal_pressure_angle
    double = design.sides == "double"
    bodies = ["g2", "g13"] + (["g4"] if double else [])
    dofs = [Dof(body, k) for body in bodies for k in ("x", "y", "z", "rz")]
    g3 = design.gear3 if double else None
    m13 = design.gear1.mass + (g3.mass if g3 else 0.0)
    J13 = design.gear1.J_z + (g3.J_z if g3 else 0.0)
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
    if design.fixed_gear_torsional_stiffness:
        elements.append(
            Support("g2.rz", design.fixed_gear_torsional_stiffness, name="support_g2_rz")
        )
    kin = design.kinematics()
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
        omega = 2 * math.pi * mesh_hz[j]
        error = Fourier(0.0, (spec.error_amplitude,), omega, ref_speed=design.input_speed)
        elements.append(
            Mesh(
                g,
                stiffness=_law(spec, omega, design.input_speed),
                damping=spec.damping,
                backlash=Backlash.full(spec.backlash),
                error=error,
                name=f"mesh{j + 1}",
            )
        )
    if design.gyroscopic:
        # L1, L3 (Eq. 7): gyroscopic moments of the nutating gears in steady precession,
        # applied as paper 000 does, as L / r_m on y13
        dpsi = kin.nutating_motion(design.input_speed).dpsi
        total = 0.0
        for gear in (design.gear1, g3) if g3 else (design.gear1,):
            M = gyroscopic_moment((gear.J_x, gear.J_y, gear.J_z), 0.0, th, 0.0,
                                  design.input_speed, 0.0, dpsi, frame="fixed")  # fmt: skip
            total += float((M[0] ** 2 + M[1] ** 2) ** 0.5) / gear.mean_radius
        if total:
            elements.append(Load("g13.y", total, name="gyroscopic"))
    if design.input_torque:
        elements.append(Load("g2.rz", design.input_torque, name="T1"))
    if design.output_torque and double:
        elements.append(Load("g4.rz", -design.output_torque, name="T4"))
    return Model(
        dofs,
        elements,
        speed=design.input_speed,
        name=design.name or f"{design.sides}-sided nutation drive",
        metadata={"design": design.model_dump_json(), "design_hash": design.hash},
    )
