"""Assembly errors of a gear mesh: centre distance, the carrier's (crank's) errors.

The mesh frame, the line of centres from gear A's axis to gear B's and ``tau`` (the
direction along which A pushes B) are those of :mod:`reducerlab.kinematics.accuracy`.

**Centre distance.** Involute flanks keep a constant ratio whatever the centre
distance: the contact stays on the common tangent of the base circles, whose wrapped
lengths change by constants only. A centre-distance error ``delta_a`` of a pair (or a
radius error of the KHV drive's crank, which carries the planet's axis) therefore gives
no transmission error at any order (a constant angle at most, here none: the tangent
turns about the pitch point); it changes the working pressure angle,
``cos(alpha_w') = r_bSigma / a'`` (``r_bSigma = r_bA + r_bB``, external; ``r_bA - r_bB``,
internal), and the normal backlash by (the base tooth thicknesses fixed)

``delta j_n = +- 2 r_bSigma (inv(alpha_w') - inv(alpha_w)) ~ +- 2 sin(alpha_w) delta_a``

(``+`` external: the gears move apart; ``-`` internal: the pinion moves into the ring).

**Planet axis offset.** An offset ``(d_r, d_t)`` of B's axis in the mesh frame (along
and counter-clockwise normal to the line of centres) moves B's base circle by a
constant vector: a constant lead ``s = -(d_r cos(tau) + d_t sin(tau))`` (exact for the
ratio, which stays constant; first order for the lead).

**Crank axis offset.** The carrier turning about an axis ``h`` off the fixed ring's
axis (a housing-fixed vector, direction ``phi_h`` from the crank at zero input): in the
carrier frame the ring's axis sits at ``-h`` turned back by the carrier's angle, that
is, with the ring's own rotation ``phi_A`` there: the ring's eccentricity law with the
phase ``phi_h + pi``, ``s = -h cos(phi_A + phi_h - tau)``.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError

__all__ = ["axis_offset_lead", "backlash_change", "planet_axis_lead"]

Array = NDArray[np.float64]


def _inv(alpha: float) -> float:
    return math.tan(alpha) - alpha


def planet_axis_lead(radial: float, tangential: float, line_angle: float) -> float:
    """Constant lead ``s = -(d_r cos(tau) + d_t sin(tau))`` (m) of B's flank from an
    offset of its axis (module docstring)."""
    return -(float(radial) * math.cos(line_angle) + float(tangential) * math.sin(line_angle))


def axis_offset_lead(angle_a: ArrayLike, offset: float, phase: float, line_angle: float) -> Array:
    """Lead ``s = -h cos(phi_A + phi_h - tau)`` (m) of the crank's axis off the fixed
    gear A's axis, ``phi_A`` the rotation of A in the carrier frame (module docstring)."""
    a = np.asarray(angle_a, float)
    return -float(offset) * np.cos(a + float(phase) - line_angle)


def backlash_change(
    centre_distance_error: float,
    base_radius_sum: float,
    working_pressure_angle: float,
    internal: bool,
) -> float:
    """Change of the normal backlash (m) from a centre-distance error (module docstring).

    Parameters
    ----------
    centre_distance_error : float
        ``delta_a`` (m), signed.
    base_radius_sum : float
        ``r_bA + r_bB`` (external) or ``r_bA - r_bB`` (internal), m.
    working_pressure_angle : float
        ``alpha_w`` (rad) at the nominal centre distance.
    internal : bool

    Raises
    ------
    ReducerlabError
        The changed centre distance no longer reaches the base circles' sum
        (``a' <= r_bSigma``).
    """
    a0 = base_radius_sum / math.cos(working_pressure_angle)
    a1 = a0 + float(centre_distance_error)
    if not a1 > base_radius_sum:
        raise ReducerlabError(
            f"centre distance error: {centre_distance_error * 1e3:.4g} mm leaves a centre "
            f"distance {a1 * 1e3:.4g} mm, not beyond the base radii's {base_radius_sum * 1e3:.4g}"
            " mm"
        )
    change = (
        2 * base_radius_sum * (_inv(math.acos(base_radius_sum / a1)) - _inv(working_pressure_angle))
    )
    return -change if internal else change
