"""Rigid transmission error of a nutation drive from its bevel gears' errors.

Frame: the crank's (the mesh frame of paper 000), in which every gear turns about a
fixed axis (the central gears about the main axis, the nutating body about its tilted
axis) through ``theta_X = w_X theta_in`` with ``w_X`` the kinematics' relative speed
(``DriveKinematics.relative_speeds``); each pair touches at its mean contact point, fixed
in this frame. The drive model's mesh deflection (paper 000 Eq. 2-4, ``drives.nutation``)
is ``lambda = a_n . u_n + a_y r_mn theta_n - a_c . u_c - a_y r_mc theta_c``, with
``a = (a_x, a_y, a_z)`` the contact normal of each gear in its own frame (x toward the
mean point, y tangential, z along its axis; ``a_y = cos(beta) cos(alpha_n)`` for all).
A rigid drive keeps ``lambda = 0``.

**Errors as equivalent rotations.** An eccentricity ``e`` of gear X at its mean cone
point (the mean circle's centre off the axis), pointing at ``psi = theta_X + phi0``
from the mean contact point's direction about the gear's axis (the model's ``rz``
sense), translates the flank by ``e (cos psi, sin psi, 0)``, which enters ``lambda``
as ``a_x e cos(psi) + a_y e sin(psi)``: the runout projected on the contact normal. Over
the lever ``a_y r_m`` that is the rotation

``epsilon_X = (e / r_mX) (sin(psi) + (a_x / a_y) cos(psi))``,

``a_x / a_y = -(cos(delta) tan(alpha_n) + sin(delta) sin(beta)) / cos(beta)`` (the
radial component of the normal: the transverse pressure angle's ``cos(delta)`` part and
the spiral's ``sin(delta)`` part; -0.66 .. -0.68 for the double-sided example's cone
angles of 47 to 56 deg, so a runout counts ``sqrt(1 + (a_x / a_y)^2)`` = 1.2 times its
tangential part). A tooth ``k`` ahead by its cumulative pitch deviation
``F_k`` (on the mean circle, in the gear's turning sense) is the rotation
``sgn(w_X) F_k / r_mX`` (the tooth nearest the mean contact point in mesh, as for the
cylindrical gears of :mod:`reducerlab.kinematics.accuracy`).

**Through the two stages.** Each mesh keeps ``r_mn (d theta_n + epsilon_n) =
r_mc (d theta_c + epsilon_c)``. Double-sided: gear 2 is fixed (exact in the crank
frame: the crank is the input), so mesh 1 sets the nutating body's error
``d theta_13 = (r_m2 / r_m1) epsilon_2 - epsilon_1`` and mesh 2 passes it to the output
gear 4, ``d theta_4 = (r_m3 / r_m4)(d theta_13 + epsilon_3) - epsilon_4``. Single-sided
(the nutating gear's net rotation is the output, through its coupling):
``d theta_13 = (r_m2 / r_m1) epsilon_2 - epsilon_1``. The output's error in its own
turning sense is ``sgn(i)`` times it (the crank turns exactly; ``theta`` is about the
same axis sense as the absolute rotation).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError
from .accuracy import cumulative_pitch, tooth_in_mesh

__all__ = ["eccentricity_rotation", "output_rotation", "pitch_rotation", "radial_ratio"]

Array = NDArray[np.float64]


def eccentricity_rotation(
    eccentricity: float, phase: float, angle: ArrayLike, radial_ratio: float, mean_radius: float
) -> Array:
    """``epsilon = (e / r_m)(sin(psi) + (a_x / a_y) cos(psi))``, ``psi = theta + phi0``
    (rad; module docstring).

    Parameters
    ----------
    eccentricity : float
        ``e`` (m) at the mean cone point.
    phase : float
        ``phi0`` (rad) from the mean contact point's direction, about the gear's axis.
    angle : array_like
        ``theta_X`` (rad), the gear's rotation in the crank frame.
    radial_ratio : float
        ``a_x / a_y`` of the gear's contact normal in its own frame.
    mean_radius : float
        ``r_m`` (m), > 0.
    """
    if not mean_radius > 0:
        raise ReducerlabError(f"mean radius: must be > 0 (m); got {mean_radius!r}")
    psi = np.asarray(angle, float) + float(phase)
    return float(eccentricity) / mean_radius * (np.sin(psi) + radial_ratio * np.cos(psi))


def pitch_rotation(
    pitch: tuple[float, ...], angle: ArrayLike, teeth: int, mean_radius: float, sense: int
) -> Array:
    """``sgn(w) F_k / r_m`` (rad) of the tooth ``k`` in mesh (module docstring); zeros
    without pitch deviations. ``sense``: +1 or -1, the gear's turning sense in the
    crank frame."""
    a = np.asarray(angle, float)
    if not pitch:
        return np.zeros_like(a)
    if sense not in (1, -1):
        raise ReducerlabError(f"sense: must be +1 or -1; got {sense!r}")
    return sense * cumulative_pitch(pitch)[tooth_in_mesh(a, teeth)] / mean_radius


def output_rotation(
    eps: Mapping[str, ArrayLike], radii: Mapping[str, float], double: bool
) -> Array:
    """The output's rotation error in the crank frame (rad, the model's ``rz`` sense)
    from the gears' equivalent rotations ``eps`` (``"gear 1"`` .. ``"gear 4"``, missing
    ones zero) and mean radii ``radii`` (m): the two stages of the module docstring."""
    zero = np.zeros(1)

    def e(name: str) -> Array:
        return np.asarray(eps.get(name, zero), float)

    body = radii["gear 2"] / radii["gear 1"] * e("gear 2") - e("gear 1")
    if not double:
        return body
    return radii["gear 3"] / radii["gear 4"] * (body + e("gear 3")) - e("gear 4")


def radial_ratio(cone_angle: float, spiral_angle: float, normal_pressure_angle: float) -> float:
    """``a_x / a_y = -(cos(delta) tan(alpha_n) + sin(delta) sin(beta)) / cos(beta)`` of
    paper 000 Eq. 4's normal (module docstring)."""
    d, b, a = cone_angle, spiral_angle, normal_pressure_angle
    return -(math.cos(d) * math.tan(a) + math.sin(d) * math.sin(b)) / math.cos(b)
