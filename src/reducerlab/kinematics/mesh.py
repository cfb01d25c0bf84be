"""Relative motion at the mesh and pitch-cone geometry of bevel pairs.

Two gears turning about axes through the common cone apex ``O`` have a relative
angular velocity ``w_rel = w_2 - w_1``, itself through ``O``: the instantaneous axis of
relative rotation. Pure rolling of the pitch cones means that this axis is their common
generatrix (the pitch line): every point on it has zero relative velocity.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError
from .rotations import skew

__all__ = [
    "external_cone_angles",
    "internal_cone_angles",
    "nutation_angle_from_cones",
    "relative_rotation_axis",
    "relative_velocity",
]


def relative_velocity(
    omega_1: ArrayLike, omega_2: ArrayLike, r: ArrayLike, R_01: ArrayLike | None = None
) -> NDArray[np.float64]:
    """Velocity of gear 1 relative to gear 2 at a point (m/s), paper 002.

    ``v_12 = (W_1 - W_2) r`` in the fixed frame S0, or, with ``R_01`` (the rotation from
    the gear-1 frame S1 to S0) and ``r`` given in S1, expressed in S1:
    ``v_12^1 = R_01^T (W_1^0 - W_2^0) R_01 r^1``.

    Parameters
    ----------
    omega_1, omega_2 : array_like, shape (..., 3)
        Angular velocities in S0 (rad/s).
    r : array_like, shape (..., 3)
        Point (m), in S0, or in S1 when ``R_01`` is given.
    R_01 : array_like, shape (..., 3, 3), optional
    """
    W = skew(np.asarray(omega_1, float) - np.asarray(omega_2, float))
    r = np.asarray(r, float)
    if R_01 is None:
        return (W @ r[..., None])[..., 0]
    R = np.asarray(R_01, float)
    return (np.swapaxes(R, -1, -2) @ W @ R @ r[..., None])[..., 0]


def relative_rotation_axis(omega_1: ArrayLike, omega_2: ArrayLike) -> NDArray[np.float64]:
    """Unit direction of ``omega_2 - omega_1``: the instantaneous axis of relative rotation.

    For rolling pitch cones it is their pitch line.
    """
    d = np.asarray(omega_2, float) - np.asarray(omega_1, float)
    n = np.linalg.norm(d, axis=-1, keepdims=True)
    if np.any(n == 0):
        raise ReducerlabError("the two angular velocities are equal: no relative rotation")
    return d / n


def _check(z1: float, z2: float, shaft_angle: float) -> None:
    if not (z1 > 0 and z2 > 0):
        raise ReducerlabError(f"tooth numbers must be > 0, got {z1}, {z2}")
    if not 0 < shaft_angle < math.pi:
        raise ReducerlabError(
            f"shaft angle must lie in (0°, 180°), got {math.degrees(shaft_angle):g}°"
        )


def external_cone_angles(z1: float, z2: float, shaft_angle: float) -> tuple[float, float]:
    """Pitch cone angles (rad) of an external bevel pair: ``delta_1 + delta_2 = Sigma``.

    ``sin(delta_1) / sin(delta_2) = z1 / z2`` (equal pitch at the common cone distance),
    hence ``tan(delta_1) = sin(Sigma) / (z2 / z1 + cos(Sigma))``.
    """
    _check(z1, z2, shaft_angle)
    d1 = math.atan2(z1 * math.sin(shaft_angle), z2 + z1 * math.cos(shaft_angle))
    return d1, shaft_angle - d1


def internal_cone_angles(
    z_internal: float, z_external: float, shaft_angle: float
) -> tuple[float, float]:
    """Pitch cone angles (rad) ``(delta_internal, delta_external)`` of an internal pair.

    The external gear's cone lies inside the internal gear's cone, both opening the
    same way: ``delta_i - delta_e = Sigma`` with ``Sigma`` the angle between the axes
    (the nutation angle of a nutation drive), and ``sin(delta_i) / sin(delta_e) =
    z_i / z_e``, hence ``tan(delta_e) = z_e sin(Sigma) / (z_i - z_e cos(Sigma))``.
    """
    _check(z_internal, z_external, shaft_angle)
    if z_internal <= z_external:
        raise ReducerlabError(
            f"the internal gear needs more teeth than the external one "
            f"(got {z_internal} <= {z_external})"
        )
    de = math.atan2(
        z_external * math.sin(shaft_angle), z_internal - z_external * math.cos(shaft_angle)
    )
    return de + shaft_angle, de


def nutation_angle_from_cones(
    delta_a: float, delta_b: float, contact: str = "internal"
) -> tuple[float, float]:
    """Inverse of the cone-angle relations: ``(Sigma, z_a / z_b)`` from two cone angles.

    ``Sigma = |delta_a - delta_b|`` for an internal pair, ``delta_a + delta_b`` for an
    external one; the tooth ratio is ``sin(delta_a) / sin(delta_b)``.
    """
    if contact not in ("internal", "external"):
        raise ReducerlabError(f"contact must be 'internal' or 'external', got {contact!r}")
    for d in (delta_a, delta_b):
        if not 0 < d < math.pi:
            raise ReducerlabError(f"cone angles must lie in (0°, 180°), got {math.degrees(d):g}°")
    sigma = abs(delta_a - delta_b) if contact == "internal" else delta_a + delta_b
    return sigma, math.sin(delta_a) / math.sin(delta_b)
