"""Transmission ratios and member speeds of every drive, derived from rolling.

Derivation (``docs/kinematics.md``): a nutating gear spins about its own axis ``b``
(rate ``psi'``) while its axis precesses about the main axis ``zeta`` with the input
(rate ``omega_H``), so ``w_n = omega_H zeta + psi' b``; a central gear turns about
``zeta`` at ``omega_c``. Their pitch cones (apex O, half angles ``delta_c``,
``delta_n``, ``sin(delta_c)/sin(delta_n) = z_c/z_n``) roll without slip when the
relative angular velocity is parallel to the pitch line ``p``. Crossing with ``p``:

``psi' = -sigma (omega_H - omega_c) z_c / z_n``

with ``sigma = +1`` when the cones are nested (internal contact: p on the same side
of both axes) and ``-1`` when they touch externally. The ratio depends on the tooth
numbers only; the nutation angle fixes the cone angles, not the ratio. The planar
drives (KHV, cycloid ball) are the same relation at zero nutation angle (Willis).

All ratios are ``i = omega_input / omega_output`` (signed: negative means the output
turns against the input).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError
from ..units import TWO_PI
from .mesh import external_cone_angles, internal_cone_angles

__all__ = [
    "CycloidBallDrive",
    "DoubleNutationDrive",
    "DriveKinematics",
    "ExternalGearPair",
    "GearMesh",
    "KHVDrive",
    "NutatingMotion",
    "NutationDrive",
    "rolling_spin",
]


def _sigma(contact: str) -> int:
    if contact == "internal":
        return 1
    if contact == "external":
        return -1
    raise ReducerlabError(f"contact must be 'internal' or 'external', got {contact!r}")


def _teeth(**z: int) -> None:
    for name, v in z.items():
        if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < 1:
            raise ReducerlabError(f"{name}: tooth number must be a positive integer, got {v!r}")


def _angle(name: str, value: object) -> None:
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating):
        raise ReducerlabError(f"{name} must be a number in rad, got {value!r}")
    if not 0 < float(value) < math.pi:
        raise ReducerlabError(f"{name} must lie in (0°, 180°), got {math.degrees(value):g}°")


def _external(a: tuple[str, int], b: tuple[str, int], contact: str) -> str | None:
    """The external gear of a bevel pair (the one with fewer teeth in nested cones);
    None for externally touching cones (both external)."""
    if contact == "external":
        return None
    return a[0] if a[1] < b[1] else b[0]


def _pair_cones(z_n: int, z_c: int, theta: float, contact: str) -> tuple[float, float]:
    """Pitch cone angles ``(delta_nutating, delta_central)`` (rad) of one bevel pair."""
    if contact == "external":
        return external_cone_angles(z_n, z_c, theta)
    if z_n > z_c:
        return internal_cone_angles(z_n, z_c, theta)
    dc, dn = internal_cone_angles(z_c, z_n, theta)
    return dn, dc


def _nutating_speeds(member: str, omega_h: float, dpsi: float, theta: float) -> dict[str, float]:
    """Spin, net rotation and ``|omega_H zeta + psi' b|`` of a nutating ``member`` (rad/s)."""
    w = math.sqrt(max(omega_h**2 + dpsi**2 + 2 * omega_h * dpsi * math.cos(theta), 0.0))
    return {
        f"{member}: spin psi'": dpsi,
        f"{member}: net rotation phi' + psi'": omega_h + dpsi,
        f"{member}: |omega|": w,
    }


def rolling_spin(
    omega_h: float, omega_c: float, z_c: int, z_n: int, contact: str = "internal"
) -> float:
    """Spin rate ``psi'`` (rad/s) of a nutating gear rolling on a central gear.

    ``psi' = -sigma (omega_H - omega_c) z_c / z_n`` (see module docstring).
    """
    return -_sigma(contact) * (omega_h - omega_c) * z_c / z_n


@dataclass(frozen=True)
class NutatingMotion:
    """Steady precession of a nutating gear: ``phi' = omega_H``, constant ``theta``,
    constant spin ``psi'`` (ZXZ Euler angles, rad and rad/s)."""

    dphi: float
    theta: float
    dpsi: float

    def angles(self, t: ArrayLike) -> tuple[NDArray, NDArray, NDArray]:
        """Euler angles ``(phi, theta, psi)`` at times ``t`` (s), zero at ``t = 0``."""
        t = np.asarray(t, float)
        return self.dphi * t, np.full_like(t, self.theta), self.dpsi * t


@dataclass(frozen=True)
class GearMesh:
    """One mesh of a drive's series train, as the torque flow walks it.

    Attributes
    ----------
    name : str
        The mesh element's name in the drive's model (``"mesh1"``, ``"mesh"``,
        ``"cycloid_pairs"``).
    driven, driving : str
        The gear nearer the output (it receives the carrier-frame power) and its mate.
    external : str or None
        The external gear of an internal pair (the one whose torque a loaded-contact
        analysis takes); None when both gears are external.
    """

    name: str
    driven: str
    driving: str
    external: str | None = None


class DriveKinematics(ABC):
    """Kinematics of a drive: ratio, member speeds, mesh frequencies, cone angles."""

    #: Human-readable drive name.
    title: str = ""

    @property
    @abstractmethod
    def ratio(self) -> float:
        """``omega_input / omega_output`` (signed)."""

    @abstractmethod
    def speeds(self, omega_in: float) -> dict[str, float]:
        """Absolute angular speed (rad/s) of every member at input speed ``omega_in``."""

    @abstractmethod
    def mesh_frequencies(self, omega_in: float) -> dict[str, float]:
        """Tooth (or ball) engagement frequency of every mesh (Hz)."""

    def cone_angles(self) -> dict[str, float]:
        """Pitch cone angles (rad) of bevel gears; empty for planar drives."""
        return {}

    def nutating_motion(self, omega_in: float) -> NutatingMotion | None:
        """Euler-angle rates of the nutating member, if there is one."""
        return None

    # -- the series train the torque flow walks (:mod:`reducerlab.kinematics.torques`) --

    def carrier_speed(self, omega_in: float) -> float:
        """Speed of the carrier (crank, eccentric, planet carrier) about the main axis
        (rad/s); the input's by default."""
        return omega_in

    @abstractmethod
    def relative_speeds(self, omega_in: float) -> dict[str, float]:
        """Speed of every gear of :meth:`torque_train` about its own axis relative to the
        carrier (rad/s): ``omega_g - omega_H`` for a gear on the main axis, the spin
        ``psi'`` for a nutating gear."""

    @abstractmethod
    def torque_train(self) -> tuple[GearMesh, ...]:
        """The meshes of the series train from the output member to the member the
        housing holds, named as the drive's model names its mesh elements."""

    @property
    def fixed_member(self) -> str | None:
        """The gear the housing holds (the last driving gear of :meth:`torque_train`),
        or None when the train ends at the input."""
        return self.torque_train()[-1].driving


@dataclass(frozen=True)
class NutationDrive(DriveKinematics):
    """Single-stage nutation drive: a nutating bevel gear meshing a central bevel gear.

    Parameters
    ----------
    z_nutating, z_central : int
        Tooth numbers.
    nutation_angle : float
        Angle between the nutating gear's axis and the main axis (rad), both axes
        pointing toward the openings of their pitch cones.
    contact : {"internal", "external"}
        Nested cones (the usual nutation drive, small tooth difference) or externally
        touching cones.
    output : {"central", "nutating"}
        ``"central"``: the nutating gear is held from net rotation (pin or constant-
        velocity coupling to the housing) and the central gear is the output.
        ``"nutating"``: the central gear is fixed and the output is the net rotation
        of the nutating gear, ``phi + psi``, taken through a constant-velocity coupling.
    """

    z_nutating: int
    z_central: int
    nutation_angle: float
    contact: str = "internal"
    output: str = "central"
    title: str = "single-stage nutation drive"

    def __post_init__(self) -> None:
        _teeth(z_nutating=self.z_nutating, z_central=self.z_central)
        _sigma(self.contact)
        if self.output not in ("central", "nutating"):
            raise ReducerlabError(f"output must be 'central' or 'nutating', got {self.output!r}")
        _angle("nutation angle", self.nutation_angle)
        if self.contact == "internal" and self.z_nutating == self.z_central:
            raise ReducerlabError("an internal pair needs different tooth numbers")
        if self.z_nutating == self.z_central and self.output == "nutating":
            raise ReducerlabError("equal tooth numbers give no output rotation")
        self.cone_angles()  # validates geometry

    def _rates(self, omega_in: float) -> tuple[float, float]:
        """``(psi', omega_c)``."""
        s = _sigma(self.contact)
        if self.output == "central":
            dpsi = -omega_in  # no net rotation: psi = -phi
            return dpsi, omega_in + s * dpsi * self.z_nutating / self.z_central
        dpsi = rolling_spin(omega_in, 0.0, self.z_central, self.z_nutating, self.contact)
        return dpsi, 0.0

    @property
    def ratio(self) -> float:
        s, zn, zc = _sigma(self.contact), self.z_nutating, self.z_central
        if self.output == "central":  # omega_c = omega_H (1 - sigma z_n / z_c)
            return float(Fraction(zc, zc - s * zn))
        return float(Fraction(zn, zn - s * zc))  # omega_out = omega_H (1 - sigma z_c / z_n)

    def speeds(self, omega_in: float) -> dict[str, float]:
        dpsi, wc = self._rates(omega_in)
        return {
            "input (crank)": omega_in,
            **_nutating_speeds("nutating gear", omega_in, dpsi, self.nutation_angle),
            "central gear": wc,
        }

    def mesh_frequencies(self, omega_in: float) -> dict[str, float]:
        dpsi, _ = self._rates(omega_in)
        return {"mesh": self.z_nutating * abs(dpsi) / TWO_PI}

    def cone_angles(self) -> dict[str, float]:
        dn, dc = _pair_cones(self.z_nutating, self.z_central, self.nutation_angle, self.contact)
        return {"nutating gear": dn, "central gear": dc}

    def nutating_motion(self, omega_in: float) -> NutatingMotion:
        return NutatingMotion(omega_in, self.nutation_angle, self._rates(omega_in)[0])

    def relative_speeds(self, omega_in: float) -> dict[str, float]:
        dpsi, wc = self._rates(omega_in)
        return {"nutating gear": dpsi, "central gear": wc - omega_in}

    def torque_train(self) -> tuple[GearMesh, ...]:
        """Mesh ``mesh1``: the output (central gear, or the nutating gear through its
        coupling) driven by its mate, which the housing holds (the central gear, or the
        nutating gear through its pin)."""
        ext = _external(("nutating gear", self.z_nutating), ("central gear", self.z_central),
                        self.contact)  # fmt: skip
        if self.output == "central":
            return (GearMesh("mesh1", "central gear", "nutating gear", ext),)
        return (GearMesh("mesh1", "nutating gear", "central gear", ext),)

    def pitch_line(self, phi: ArrayLike) -> NDArray[np.float64]:
        """Unit pitch line (fixed frame) when the precession angle is ``phi`` (rad).

        It lies in the plane of the main axis and the nutating gear's axis
        ``b = (sin th sin phi, -sin th cos phi, cos th)``, at the central cone angle
        from the main axis: on the side away from ``b`` when the nutating gear is the
        internal one, on ``b``'s side otherwise.
        """
        phi = np.asarray(phi, float)
        dc = self.cone_angles()["central gear"]
        u = np.stack([np.sin(phi), -np.cos(phi), np.zeros_like(phi)], axis=-1)
        zeta = np.array([0.0, 0.0, 1.0])
        side = -1.0 if (self.contact == "internal" and self.z_nutating > self.z_central) else 1.0
        return math.cos(dc) * zeta + side * math.sin(dc) * u


@dataclass(frozen=True)
class DoubleNutationDrive(DriveKinematics):
    """Double-sided nutation drive of paper 000.

    Nutating gears 1 and 3 are one body; gear 1 meshes the fixed gear 2, gear 3 meshes
    the output gear 4. ``psi' = -sigma omega_H z2/z1`` from mesh 1 and
    ``omega_4 = omega_H + sigma psi' z3/z4`` from mesh 2, so
    ``i = z1 z4 / (z1 z4 - z2 z3)`` whatever the (common) contact type.
    """

    z1: int
    z2: int
    z3: int
    z4: int
    nutation_angle: float
    contact: str = "internal"
    title: str = "double-sided nutation drive"

    def __post_init__(self) -> None:
        _teeth(z1=self.z1, z2=self.z2, z3=self.z3, z4=self.z4)
        _sigma(self.contact)
        if self.z1 * self.z4 == self.z2 * self.z3:
            raise ReducerlabError("z1 z4 = z2 z3: the output does not turn")
        _angle("nutation angle", self.nutation_angle)
        self.cone_angles()

    def _rates(self, omega_in: float) -> tuple[float, float]:
        s = _sigma(self.contact)
        dpsi = rolling_spin(omega_in, 0.0, self.z2, self.z1, self.contact)
        return dpsi, omega_in + s * dpsi * self.z3 / self.z4

    @property
    def ratio(self) -> float:
        return float(Fraction(self.z1 * self.z4, self.z1 * self.z4 - self.z2 * self.z3))

    def speeds(self, omega_in: float) -> dict[str, float]:
        dpsi, w4 = self._rates(omega_in)
        return {
            "input (crank)": omega_in,
            **_nutating_speeds("nutating gears 1+3", omega_in, dpsi, self.nutation_angle),
            "gear 2 (fixed)": 0.0,
            "gear 4 (output)": w4,
        }

    def mesh_frequencies(self, omega_in: float) -> dict[str, float]:
        dpsi, _ = self._rates(omega_in)
        return {
            "mesh 1 (gears 1-2)": self.z1 * abs(dpsi) / TWO_PI,
            "mesh 2 (gears 3-4)": self.z3 * abs(dpsi) / TWO_PI,
        }

    def cone_angles(self) -> dict[str, float]:
        d1, d2 = _pair_cones(self.z1, self.z2, self.nutation_angle, self.contact)
        d3, d4 = _pair_cones(self.z3, self.z4, self.nutation_angle, self.contact)
        return {"gear 1": d1, "gear 2": d2, "gear 3": d3, "gear 4": d4}

    def nutating_motion(self, omega_in: float) -> NutatingMotion:
        return NutatingMotion(omega_in, self.nutation_angle, self._rates(omega_in)[0])

    def relative_speeds(self, omega_in: float) -> dict[str, float]:
        dpsi, w4 = self._rates(omega_in)
        return {"gear 1": dpsi, "gear 2": -omega_in, "gear 3": dpsi, "gear 4": w4 - omega_in}

    def torque_train(self) -> tuple[GearMesh, ...]:
        """``mesh2`` (gear 4, the output, driven by gear 3), then ``mesh1`` (gear 1,
        one body with gear 3, driven by the fixed gear 2)."""
        c = self.contact
        ext2 = _external(("gear 3", self.z3), ("gear 4", self.z4), c)
        ext1 = _external(("gear 1", self.z1), ("gear 2", self.z2), c)
        return (
            GearMesh("mesh2", "gear 4", "gear 3", ext2),
            GearMesh("mesh1", "gear 1", "gear 2", ext1),
        )


@dataclass(frozen=True)
class KHVDrive(DriveKinematics):
    """KHV planetary drive with a small tooth difference (paper 004).

    Carrier H is the input, ring K is fixed, the planet V meshes K internally and its
    absolute rotation is the output (equal-angular-velocity mechanism W). Willis:
    ``(omega_V - omega_H) / (omega_K - omega_H) = z_K / z_V``, so
    ``i = z_V / (z_V - z_K)``.
    """

    z_planet: int
    z_ring: int
    title: str = "KHV planetary drive"

    def __post_init__(self) -> None:
        _teeth(z_planet=self.z_planet, z_ring=self.z_ring)
        if self.z_ring <= self.z_planet:
            raise ReducerlabError(
                f"the ring needs more teeth than the planet (got {self.z_ring} <= {self.z_planet})"
            )

    @property
    def ratio(self) -> float:
        return float(Fraction(self.z_planet, self.z_planet - self.z_ring))

    def speeds(self, omega_in: float) -> dict[str, float]:
        wv = omega_in / self.ratio
        return {
            "carrier H (input)": omega_in,
            "planet V (absolute, output)": wv,
            "planet V relative to carrier": wv - omega_in,
            "ring K (fixed)": 0.0,
        }

    def mesh_frequencies(self, omega_in: float) -> dict[str, float]:
        return {"mesh K-V": self.z_ring * abs(omega_in) / TWO_PI}

    def relative_speeds(self, omega_in: float) -> dict[str, float]:
        return {"planet V": omega_in / self.ratio - omega_in, "ring K": -omega_in}

    def torque_train(self) -> tuple[GearMesh, ...]:
        """``mesh``: the planet (output through the W mechanism) driven by the fixed ring."""
        return (GearMesh("mesh", "planet V", "ring K", "planet V"),)


@dataclass(frozen=True)
class CycloidBallDrive(DriveKinematics):
    """Cycloid ball transmission (paper 003).

    The centre disc carries an epitrochoid groove with ``z_centre`` lobes, the
    planetary disc (on the eccentric) a hypotrochoid with ``z_planetary = z_centre + 2``
    lobes, with ``z_centre + 1`` balls between them. The grooves act as pitch circles
    of radii proportional to the lobe numbers (paper 003 Table 1: r = 1.25 mm x Z and
    e = r3 - r2); a trochoid phase argument gives the same relation
    (``docs/kinematics.md``).

    Parameters
    ----------
    z_centre, z_planetary : int
        Lobe numbers of the epitrochoid and hypotrochoid grooves.
    output : {"centre", "planetary"}
        ``"centre"`` (paper 003): the planetary disc is held from rotation by the
        cross-ball equal-speed mechanism, the centre disc is the output,
        ``i = z_c / (z_c - z_p)``. ``"planetary"``: the centre disc is fixed and the
        planetary disc's rotation is taken out through the equal-speed mechanism,
        ``i = z_p / (z_p - z_c)``.
    """

    z_centre: int
    z_planetary: int
    output: str = "centre"
    title: str = "cycloid ball transmission"

    def __post_init__(self) -> None:
        _teeth(z_centre=self.z_centre, z_planetary=self.z_planetary)
        if self.z_planetary != self.z_centre + 2:
            raise ReducerlabError(
                "the hypotrochoid needs two lobes more than the epitrochoid "
                f"(z_planetary = z_centre + 2), got {self.z_planetary} and {self.z_centre}"
            )
        if self.output not in ("centre", "planetary"):
            raise ReducerlabError(f"output must be 'centre' or 'planetary', got {self.output!r}")

    @property
    def balls(self) -> int:
        """Number of balls, ``(z_centre + z_planetary) / 2``."""
        return (self.z_centre + self.z_planetary) // 2

    @property
    def ratio(self) -> float:
        zc, zp = self.z_centre, self.z_planetary
        return float(Fraction(zc, zc - zp) if self.output == "centre" else Fraction(zp, zp - zc))

    def speeds(self, omega_in: float) -> dict[str, float]:
        out = omega_in / self.ratio
        centre, planetary = (out, 0.0) if self.output == "centre" else (0.0, out)
        return {
            "input shaft (eccentric)": omega_in,
            "centre disc": centre,
            "planetary disc": planetary,
            "end cover disc": 0.0,
        }

    def mesh_frequencies(self, omega_in: float) -> dict[str, float]:
        s = self.speeds(omega_in)
        return {
            "ball engagement": self.z_centre * abs(s["centre disc"] - omega_in) / TWO_PI,
        }

    def relative_speeds(self, omega_in: float) -> dict[str, float]:
        s = self.speeds(omega_in)
        return {m: s[m] - omega_in for m in ("centre disc", "planetary disc")}

    def torque_train(self) -> tuple[GearMesh, ...]:
        """``cycloid_pairs``: the output disc driven through the ball track by the disc
        the housing holds (the planetary disc through the cross-ball mechanism and the
        end cover, or the centre disc). The epitrochoid (centre disc) is read as the
        external member. The track is one mesh: how the balls share its torque is not
        resolved here."""
        out, held = ("centre disc", "planetary disc")
        if self.output == "planetary":
            out, held = held, out
        return (GearMesh("cycloid_pairs", out, held, "centre disc"),)


@dataclass(frozen=True)
class ExternalGearPair(DriveKinematics):
    """An external spur pair, pinion input: ``i = -z_gear / z_pinion``."""

    z_pinion: int
    z_gear: int
    title: str = "external gear pair"

    def __post_init__(self) -> None:
        _teeth(z_pinion=self.z_pinion, z_gear=self.z_gear)

    @property
    def ratio(self) -> float:
        return float(Fraction(-self.z_gear, self.z_pinion))

    def speeds(self, omega_in: float) -> dict[str, float]:
        return {"pinion (input)": omega_in, "gear (output)": omega_in / self.ratio}

    def mesh_frequencies(self, omega_in: float) -> dict[str, float]:
        return {"mesh": self.z_pinion * abs(omega_in) / TWO_PI}

    def carrier_speed(self, omega_in: float) -> float:
        """No carrier: the fixed frame (0)."""
        return 0.0

    def relative_speeds(self, omega_in: float) -> dict[str, float]:
        return {"pinion": omega_in, "gear": omega_in / self.ratio}

    def torque_train(self) -> tuple[GearMesh, ...]:
        """``mesh``: the gear driven by the pinion (the input: no fixed member)."""
        return (GearMesh("mesh", "gear", "pinion"),)

    @property
    def fixed_member(self) -> str | None:
        return None
