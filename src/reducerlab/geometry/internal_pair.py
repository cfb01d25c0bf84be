"""Internal involute spur gear pair with profile shift (KHV drives, paper 004).

External gear 1 (the planet, ``z1`` teeth, shift ``x1``) meshes inside internal gear 2
(the ring, ``z2 > z1`` teeth, shift ``x2``). Standard relations of internal gearing
(e.g. ISO 21771 with the internal gear's signed quantities; the Chinese design handbooks
for planetary drives with a small tooth difference use the same forms):

* working pressure angle (zero backlash): ``inv a' = 2 (x2 - x1) tan a / (z2 - z1) + inv a``
* centre distance: ``a' = m (z2 - z1) cos a / (2 cos a')``
* tip radii: ``r_a1 = m z1 / 2 + m (h_a* + x1)``, ``r_a2 = m z2 / 2 - m (h_a* - x2)``
* contact ratio: ``eps = [z1 (tan a_a1 - tan a') - z2 (tan a_a2 - tan a')] / (2 pi)``

and the conditions that bound the feasible ``(x1, x2)`` region (the "closed graph"):
contact ratio >= 1, no involute interference at the planet's root (the ring tip must
meet the planet's involute above its base circle), no tooth-tip overlap interference
(the tips must clear each other as the planet is moved radially into mesh on
assembly), and tips that are not pointed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

from scipy.optimize import brentq

from ..errors import ReducerlabError

__all__ = ["Condition", "InternalGearPair", "inv", "inv_inverse"]


def inv(alpha: float) -> float:
    """Involute function ``tan(a) - a`` (a in rad)."""
    return math.tan(alpha) - alpha


def inv_inverse(value: float) -> float:
    """Pressure angle (rad) whose involute function equals ``value`` (>= 0)."""
    if not (value >= 0 and math.isfinite(value)):
        raise ReducerlabError(f"involute function value must be >= 0, got {value!r}")
    if value == 0:
        return 0.0
    # Newton on inv(a) = value (inv' = tan^2 a, inv convex on [0, pi/2)) from the
    # small-angle estimate inv(a) ~ a^3/3, which lies at or above the root: the
    # iterates decrease monotonically to it
    a = min((3.0 * value) ** (1.0 / 3.0), 1.5)
    for it in range(60):
        f = inv(a) - value
        if it == 0 and f < 0:  # the cap 1.5 fell below the root: bracket instead
            break
        step = f / math.tan(a) ** 2
        a -= step
        if abs(step) <= 1e-15 * a:
            return a
    hi = 1.5
    while inv(hi) < value:
        hi = 0.5 * (hi + math.pi / 2)
    return brentq(lambda a: inv(a) - value, 0.0, hi, xtol=1e-15, rtol=1e-15)


@dataclass(frozen=True)
class Condition:
    """One feasibility condition: its name, margin (>= 0 satisfied) and description."""

    name: str
    margin: float
    rule: str

    @property
    def ok(self) -> bool:
        return self.margin >= -1e-12


@dataclass(frozen=True)
class InternalGearPair:
    """Geometry of an internal spur gear pair with profile shift.

    Parameters
    ----------
    z1, z2 : int
        Teeth of the external gear (planet) and of the internal gear (ring), z2 > z1.
    module : float
        m (m).
    x1, x2 : float
        Profile shift coefficients (positive away from the gear's centre for the
        external gear, toward its centre for the internal gear: a positive x2 enlarges
        the ring's tip circle radius).
    addendum : float
        Addendum coefficient h_a*.
    pressure_angle : float
        Standard pressure angle (rad).
    face_width : float
        b (m).
    min_tip_thickness : float
        Smallest tooth thickness at the tip, as a fraction of m (pointed-teeth limit).
    """

    z1: int
    z2: int
    module: float
    x1: float = 0.0
    x2: float = 0.0
    addendum: float = 1.0
    pressure_angle: float = math.radians(20.0)
    face_width: float = 0.0
    min_tip_thickness: float = 0.25

    def __post_init__(self) -> None:
        for name in ("z1", "z2"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 3:
                raise ReducerlabError(f"{name}: tooth number must be an integer >= 3, got {v!r}")
        if self.z2 <= self.z1:
            raise ReducerlabError(f"z2 (ring) must exceed z1 (planet), got {self.z2} <= {self.z1}")
        for name in ("module", "addendum", "pressure_angle"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
                raise ReducerlabError(f"{name} must be a finite number > 0, got {v!r}")
        for name in ("x1", "x2"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and math.isfinite(v)):
                raise ReducerlabError(f"{name} must be a finite number, got {v!r}")
        if (
            inv(self.pressure_angle)
            + 2 * (self.x2 - self.x1) * math.tan(self.pressure_angle) / (self.z2 - self.z1)
            <= 0
        ):
            raise ReducerlabError(
                f"x2 - x1 = {self.x2 - self.x1:.4g} gives no positive working pressure angle"
            )

    # ------------------------------------------------------------- basic geometry
    @cached_property
    def working_pressure_angle(self) -> float:
        """alpha' (rad) from the zero-backlash condition."""
        a = self.pressure_angle
        return inv_inverse(inv(a) + 2 * (self.x2 - self.x1) * math.tan(a) / (self.z2 - self.z1))

    @cached_property
    def centre_distance(self) -> float:
        """Working centre distance a' (m)."""
        a, aw = self.pressure_angle, self.working_pressure_angle
        return self.module * (self.z2 - self.z1) * math.cos(a) / (2 * math.cos(aw))

    def pitch_radius(self, gear: int) -> float:
        """Reference radius m z / 2 (m)."""
        return self.module * (self.z1 if gear == 1 else self.z2) / 2

    def base_radius(self, gear: int) -> float:
        """Base radius (m)."""
        return self.pitch_radius(gear) * math.cos(self.pressure_angle)

    def tip_radius(self, gear: int) -> float:
        """Tip radius (m): outward on the planet, inward on the ring."""
        m, ha = self.module, self.addendum
        if gear == 1:
            return self.pitch_radius(1) + m * (ha + self.x1)
        return self.pitch_radius(2) - m * (ha - self.x2)

    def tip_pressure_angle(self, gear: int) -> float:
        """Pressure angle at the tip circle (rad)."""
        ratio = self.base_radius(gear) / self.tip_radius(gear)
        if ratio > 1:
            return 0.0  # ring tip inside its base circle: no involute there
        return math.acos(ratio)

    @cached_property
    def contact_ratio(self) -> float:
        """Transverse contact ratio of the internal pair."""
        aw = math.tan(self.working_pressure_angle)
        t1, t2 = math.tan(self.tip_pressure_angle(1)), math.tan(self.tip_pressure_angle(2))
        return (self.z1 * (t1 - aw) - self.z2 * (t2 - aw)) / (2 * math.pi)

    @cached_property
    def base_pitch(self) -> float:
        """p_b = pi m cos(alpha) (m)."""
        return math.pi * self.module * math.cos(self.pressure_angle)

    def tip_thickness(self, gear: int) -> float:
        """Tooth thickness on the tip circle (m)."""
        a, z = self.pressure_angle, (self.z1 if gear == 1 else self.z2)
        aa = self.tip_pressure_angle(gear)
        ra = self.tip_radius(gear)
        if gear == 1:
            half = math.pi / (2 * z) + 2 * self.x1 * math.tan(a) / z + inv(a) - inv(aa)
        else:  # internal gear: space width e2 = m (pi/2 + 2 x2 tan a) on the reference circle
            half = math.pi / (2 * z) - 2 * self.x2 * math.tan(a) / z - inv(a) + inv(aa)
        return 2 * ra * half

    # ------------------------------------------------------------- conditions
    def overlap_interference(self) -> float:
        """G_s of the tooth-tip overlap condition (rad; >= 0 means no interference).

        ``G_s = z1 (inv a_a1 + d1) - z2 (inv a_a2 + d2) + (z2 - z1) inv a'`` with
        ``cos d1 = (r_a2^2 - r_a1^2 - a'^2) / (2 r_a1 a')`` and
        ``cos d2 = (r_a2^2 + a'^2 - r_a1^2) / (2 r_a2 a')``: the angles at which the tip
        circles intersect. Where they do not: ``inf`` if the planet's tip circle lies
        inside the ring's (the tips never meet), and ``-(r_a1 - a' - r_a2) / r_a2`` if it
        encloses it (the tips overlap radially all round: interference).
        """
        ra1, ra2, aw = self.tip_radius(1), self.tip_radius(2), self.centre_distance
        c1 = (ra2**2 - ra1**2 - aw**2) / (2 * ra1 * aw)
        c2 = (ra2**2 + aw**2 - ra1**2) / (2 * ra2 * aw)
        if abs(c1) > 1 or abs(c2) > 1:
            if ra1 - aw > ra2:
                # the planet's tip circle encloses the ring's: the tips overlap radially
                # all round (a tooth difference of one or two with large addenda and
                # shifts), so teeth of different pitch counts collide away from the
                # mesh; the margin is that radial overlap over r_a2 (< 0)
                return -(ra1 - aw - ra2) / ra2
            return math.inf  # the planet's tip circle inside the ring's: they never meet
        d1, d2 = math.acos(c1), math.acos(c2)
        return (
            self.z1 * (inv(self.tip_pressure_angle(1)) + d1)
            - self.z2 * (inv(self.tip_pressure_angle(2)) + d2)
            + (self.z2 - self.z1) * inv(self.working_pressure_angle)
        )

    def conditions(self) -> list[Condition]:
        """All feasibility conditions with their margins."""
        aw = self.working_pressure_angle
        involute_margin = math.tan(self.tip_pressure_angle(2)) - (1 - self.z1 / self.z2) * math.tan(
            aw
        )
        smin = self.min_tip_thickness * self.module
        return [
            Condition("contact ratio", self.contact_ratio - 1.0, "contact ratio >= 1"),
            Condition(
                "involute interference",
                involute_margin,
                "ring tip meets the planet's involute above its base circle: "
                "tan(a_a2) >= (1 - z1/z2) tan(a')",
            ),
            Condition(
                "tip overlap interference",
                self.overlap_interference(),
                "tips clear each other on radial assembly: G_s >= 0",
            ),
            Condition(
                "pointed planet teeth",
                (self.tip_thickness(1) - smin) / self.module,
                f"planet tip thickness >= {self.min_tip_thickness:g} m",
            ),
            Condition(
                "ring tip inside base circle",
                (self.tip_radius(2) - self.base_radius(2)) / self.module,
                "ring tip circle outside its base circle (involute flank exists)",
            ),
        ]

    def check(self) -> None:
        """Raise :class:`ReducerlabError` naming every failed condition."""
        failed = [c for c in self.conditions() if not c.ok]
        if failed:
            raise ReducerlabError(
                f"(x1, x2) = ({self.x1:g}, {self.x2:g}) is outside the feasible region: "
                + "; ".join(f"{c.name} ({c.rule}; margin {c.margin:.4g})" for c in failed)
            )
