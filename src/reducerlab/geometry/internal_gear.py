"""Internal involute spur gears (the ring of a KHV drive) and their tooth outline.

The tooth **space** of an internal gear of ``z`` teeth is shaped like the tooth of an
external gear: two involutes of the base circle ``r_b = r cos(alpha)`` that converge
outward. With the profile shift ``x`` of :class:`~reducerlab.geometry.InternalGearPair`
(the convention of the zero-backlash equation ``inv a' = inv a + 2 (x2 - x1) tan a /
(z2 - z1)``: a positive ``x`` moves the basic rack's datum line out to
``r + x m``, widening the space and enlarging the tip radius):

* space width on the reference circle ``e = m (pi/2 + 2 x tan a)``; half space angle
  ``eta(r_y) = e / (2 r) + inv a - inv a_y`` (``cos a_y = r_b / r_y``), so the half
  *tooth* angle is ``tau(r_y) = pi / z - eta(r_y)`` (growing outward: the tooth is
  thickest at its root);
* tip radius (inward) ``r_a = r - m (h_a* - x)``, root radius (outward)
  ``r_f = r + m (h_f* + x)``.

**Root form (a choice, docs/assumptions.md).** A constructed root, not a generated
one: the involute runs out to the root form circle, where a circle arc of radius
``rho_f = rho_f* m`` joins it tangentially and meets the root circle tangentially (the
root land between the two fillets of a space is a circle arc on ``r_f``). The arc's
centre lies on the involute's normal at the form point, ``rho_f`` inside the space, and
``r_f - rho_f`` from the axis; the involute's normal being tangent to the base circle,
``xi_F = rho_f + sqrt((r_f - rho_f)^2 - r_b^2)`` and ``r_Ff^2 = r_b^2 + xi_F^2``.
(A rack cannot cut an internal gear: its straight tip line, far from the pitch point,
sweeps beyond the root circle; a pinion-type shaper cutter's trochoidal root is close
to such an arc, of a radius a little above its tip radius.)

Frames and conventions as :mod:`reducerlab.geometry.spur` (SI units, rad): ``z`` is the
gear axis, the face runs from ``z = -b/2`` to ``b/2``; tooth 0 is centred on ``+x``
(pointing toward the axis), tooth ``k`` is tooth 0 turned by ``2 pi k / z``; **flank
+1** is the counter-clockwise side of a tooth (polar angle ``+tau``), **flank -1** its
mirror image; normals point out of the material (into the space). Flank parameter ``u``
runs along the involute from the root form circle (``u = 0``, the *outer* end) to the
tip circle (``u = 1``, the inner end), linear in the roll length
``xi = sqrt(r_y^2 - r_b^2)``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .internal_pair import inv
from .profiles import ProfileError

__all__ = ["InternalGear"]

Array = NDArray[np.float64]


def _rot2(p: Array, angle: float) -> Array:
    c, s = math.cos(angle), math.sin(angle)
    return np.stack([c * p[..., 0] - s * p[..., 1], s * p[..., 0] + c * p[..., 1]], -1)


@dataclass(frozen=True)
class InternalGear:
    """An internal involute spur gear with a circle-arc root fillet.

    Parameters
    ----------
    teeth : int
        Number of teeth ``z`` (>= 8).
    module : float
        Module ``m`` (m).
    face_width : float
        Face width ``b`` (m).
    pressure_angle : float
        Pressure angle ``alpha`` of the basic rack (rad), default 20 deg.
    shift : float
        Profile shift coefficient ``x`` (module docstring; positive enlarges the tip
        radius).
    addendum : float
        Addendum coefficient ``h_a*``: tip radius ``r - m (h_a* - x)``.
    dedendum : float
        Dedendum coefficient ``h_f*``: root radius ``r + m (h_f* + x)``; default 1.25
        (ISO 53).
    root_fillet : float
        Root fillet radius coefficient ``rho_f*`` (module docstring); default 0.38
        (ISO 53 profile A's tool tip radius).

    Raises
    ------
    ProfileError
        A parameter out of its range, a tip inside the base circle, a pointed tooth, or
        a fillet that does not fit the space at the root.
    """

    teeth: int
    module: float
    face_width: float
    pressure_angle: float = math.radians(20.0)
    shift: float = 0.0
    addendum: float = 1.0
    dedendum: float = 1.25
    root_fillet: float = 0.38

    def __post_init__(self) -> None:
        z = self.teeth
        if isinstance(z, bool) or not isinstance(z, int | np.integer) or z < 8:
            raise ProfileError(f"teeth: must be an integer >= 8; got {z!r}")
        for name in ("module", "face_width", "addendum", "dedendum", "pressure_angle"):
            v = getattr(self, name)
            if (
                isinstance(v, bool)
                or not isinstance(v, int | float)
                or not (math.isfinite(v) and v > 0)
            ):
                raise ProfileError(f"{name}: must be a finite number > 0; got {v!r}")
        for name in ("shift", "root_fillet"):
            v = getattr(self, name)
            if (
                isinstance(v, bool)
                or not isinstance(v, int | float)
                or not (math.isfinite(v) and v >= (-math.inf if name == "shift" else 0.0))
            ):
                raise ProfileError(f"{name}: must be a finite number (>= 0 for the fillet); "
                                   f"got {v!r}")  # fmt: skip
        a = self.pressure_angle
        if not math.radians(5.0) <= a <= math.radians(40.0):
            raise ProfileError(f"pressure_angle: must be between 5 and 40 deg (in rad); got {a!r}")
        if self.tip_radius <= self.base_radius * (1 + 1e-9):
            raise ProfileError(
                f"addendum, shift: the tip radius {self.tip_radius:.6g} m must exceed the base "
                f"radius {self.base_radius:.6g} m (no involute inside the base circle)"
            )
        rho = self.root_fillet * self.module
        if not self.root_radius - rho > self.base_radius * (1 + 1e-9):
            raise ProfileError(
                f"root_fillet: the fillet radius {self.root_fillet} m leaves its centre inside "
                "the base circle"
            )
        if self.form_radius <= self.tip_radius * (1 + 1e-9):
            raise ProfileError("dedendum: the root form circle must lie outside the tip circle")
        if self.half_angle(self.tip_radius) <= 0:
            raise ProfileError(f"shift: x = {self.shift!r} gives pointed internal teeth")
        C = self._fillet_centre
        if math.atan2(C[1], C[0]) >= math.pi / self.teeth:
            raise ProfileError(
                f"root_fillet: a fillet radius of {self.root_fillet} m does not fit in the "
                "tooth space at the root (the two fillets of a space would overlap)"
            )

    # ------------------------------------------------------------------ radii
    @property
    def reference_radius(self) -> float:
        """``r = m z / 2`` (m)."""
        return self.module * self.teeth / 2

    @property
    def base_radius(self) -> float:
        """``r_b = r cos(alpha)`` (m)."""
        return self.reference_radius * math.cos(self.pressure_angle)

    @property
    def tip_radius(self) -> float:
        """``r_a = r - m (h_a* - x)`` (m), inside the reference circle."""
        return self.reference_radius - self.module * (self.addendum - self.shift)

    @property
    def root_radius(self) -> float:
        """``r_f = r + m (h_f* + x)`` (m), outside the reference circle."""
        return self.reference_radius + self.module * (self.dedendum + self.shift)

    @property
    def pitch(self) -> float:
        """Angular pitch ``2 pi / z`` (rad)."""
        return 2 * math.pi / self.teeth

    @property
    def base_pitch(self) -> float:
        """``p_b = pi m cos(alpha)`` (m)."""
        return math.pi * self.module * math.cos(self.pressure_angle)

    @property
    def space_width(self) -> float:
        """Space width on the reference circle ``e = m (pi/2 + 2 x tan a)`` (m)."""
        return self.module * (math.pi / 2 + 2 * self.shift * math.tan(self.pressure_angle))

    @property
    def base_half_angle(self) -> float:
        """``tau_b = pi/z - e/(2 r) - inv a`` (rad): the half tooth angle on the base
        circle, so that ``tau(r_y) = tau_b + inv(a_y)`` (may be negative: the involute
        does not reach the base circle inside the tooth)."""
        return (
            math.pi / self.teeth
            - self.space_width / (2 * self.reference_radius)
            - inv(self.pressure_angle)
        )

    def half_angle(self, radius: ArrayLike) -> Array:
        """Half tooth angle ``tau(r_y) = tau_b + inv(a_y)`` (rad) at radius ``r_y >= r_b``."""
        r = np.asarray(radius, dtype=float)
        ay = np.arccos(np.clip(self.base_radius / r, -1.0, 1.0))
        return self.base_half_angle + (np.tan(ay) - ay)

    @property
    def form_radius(self) -> float:
        """Root form radius ``r_Ff`` (m): where the involute meets the root fillet,
        ``r_Ff^2 = r_b^2 + xi_F^2`` with ``xi_F = rho_f + sqrt((r_f - rho_f)^2 - r_b^2)``
        (module docstring)."""
        rho = self.root_fillet * self.module
        xi = rho + math.sqrt(max((self.root_radius - rho) ** 2 - self.base_radius**2, 0.0))
        return math.hypot(self.base_radius, xi)

    def roll_length(self, radius: ArrayLike) -> Array:
        """``xi = sqrt(r_y^2 - r_b^2)`` (m)."""
        r = np.asarray(radius, dtype=float)
        return np.sqrt(np.maximum(r**2 - self.base_radius**2, 0.0))

    @property
    def form_roll(self) -> float:
        """Roll length at the root form circle (m): ``u = 0``."""
        return float(self.roll_length(self.form_radius))

    @property
    def tip_roll(self) -> float:
        """Roll length at the tip circle (m): ``u = 1``."""
        return float(self.roll_length(self.tip_radius))

    # ------------------------------------------------------------------ flank points
    def involute_points(self, n: int = 40, u: ArrayLike | None = None) -> tuple[Array, Array]:
        """Transverse points and unit normals (out of the material), shape (n, 2), of
        the involute of flank +1 of tooth 0 from the root form circle (``u = 0``) to
        the tip (``u = 1``); ``u`` outside ``[0, 1]`` continues the involute."""
        uu = np.linspace(0.0, 1.0, max(int(n), 2)) if u is None else np.asarray(u, float)
        xi = self.form_roll + uu * (self.tip_roll - self.form_roll)
        rb = self.base_radius
        ay = np.arctan(xi / rb)
        r = np.hypot(rb, xi)
        theta = self.base_half_angle + (xi / rb - ay)
        pts = r[..., None] * np.stack([np.cos(theta), np.sin(theta)], -1)
        nang = theta + math.pi / 2 + ay
        return pts, np.stack([np.cos(nang), np.sin(nang)], -1)

    @property
    def _fillet_centre(self) -> Array:
        """Centre (m) of the root fillet circle of flank +1 of tooth 0: on the involute's
        normal at the form point, ``rho_f`` from it, and ``r_f - rho_f`` from the axis."""
        rb, xi = self.base_radius, self.form_roll
        tangent_angle = self.base_half_angle + xi / rb  # polar angle of the base tangent point
        rho = self.root_fillet * self.module
        t = np.array([math.sin(tangent_angle), -math.cos(tangent_angle)])  # unwinding cw
        return rb * np.array([math.cos(tangent_angle), math.sin(tangent_angle)]) + (xi - rho) * t

    def fillet_points(self, n: int = 40) -> tuple[Array, Array]:
        """The root fillet of flank +1 of tooth 0, a circle arc of radius ``rho_f``
        tangent to the involute at the root form circle and to the root circle: points
        (m) and normals out of the material, (n, 2), from the form point to the root
        circle."""
        n = max(int(n), 2)
        rho = self.root_fillet * self.module
        C = self._fillet_centre
        if rho == 0.0:
            p = np.repeat(C[None, :], n, axis=0)
            nrm, _ = self.involute_points(2, u=np.array([0.0, 0.0]))
            return p, np.repeat(nrm[:1], n, axis=0)
        _, n0 = self.involute_points(2, u=np.array([0.0, 0.0]))
        a0 = math.atan2(-n0[0, 1], -n0[0, 0])  # from the centre to the form point
        a1 = math.atan2(C[1], C[0])  # from the centre outward: the root circle
        da = (a1 - a0 + math.pi) % (2 * math.pi) - math.pi
        ang = a0 + da * np.linspace(0.0, 1.0, n)
        d = np.stack([np.cos(ang), np.sin(ang)], -1)
        pts = C + rho * d
        pts[-1] = self.root_radius * C / np.linalg.norm(C)
        return pts, -d

    def flank_distance(self, points: ArrayLike, flank: int = 1) -> tuple[Array, Array]:
        """Signed distance (m, positive out of the material) of points (gear frame) from
        the involute of flank ``flank`` of tooth 0, and the flank parameter ``u`` of the
        foot point: for a point at radius ``rho`` and polar angle ``theta``,
        ``d = r_b (tau_b + inv(a_rho) - s theta)``, ``s`` the flank sign."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        rb = self.base_radius
        rr = np.maximum(np.hypot(p[:, 0], p[:, 1]), rb)
        theta = np.arctan2(p[:, 1], p[:, 0])
        ay = np.arccos(rb / rr)
        d = rb * (self.base_half_angle + np.tan(ay) - ay - flank * theta)
        xi = np.sqrt(rr**2 - rb**2) + d
        return d, (xi - self.form_roll) / (self.tip_roll - self.form_roll)

    def sector_teeth(self, teeth: int) -> tuple[int, ...]:
        """Tooth indices of a sector of ``teeth`` consecutive teeth, tooth 0 in the middle
        (``-(teeth // 2) ... (teeth - 1) // 2``)."""
        if isinstance(teeth, bool) or not isinstance(teeth, int) or not 1 <= teeth < self.teeth:
            raise ProfileError(f"teeth: a sector needs 1 to {self.teeth - 1} teeth; got {teeth!r}")
        return tuple(range(-(teeth // 2), (teeth - 1) // 2 + 1))

    def sector_area(self, teeth: int, outer_radius: float) -> float:
        """Exact transverse area (m^2) of ``teeth`` teeth and their rim out to
        ``outer_radius``, cut radially through the middle of the outer spaces: the
        annulus ``r_a ... r_o`` of the sector minus the spaces (by Green's theorem on the
        fillet and involute splines, 4001 points each)."""
        n = 4001
        fil, _ = self.fillet_points(n)
        ivl, _ = self.involute_points(n)
        curve = np.concatenate([ivl[::-1], fil[1:]])  # tip -> form -> root, r increasing
        r = np.hypot(curve[:, 0], curve[:, 1])
        width = math.pi / self.teeth - np.arctan2(curve[:, 1], curve[:, 0])
        f = width * r  # half space: the angle from the flank to the space centre, times r
        gap = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(r)))
        sector = 0.5 * teeth * self.pitch * (outer_radius**2 - self.tip_radius**2)
        return sector - 2 * teeth * gap
