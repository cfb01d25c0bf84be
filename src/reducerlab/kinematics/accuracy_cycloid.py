"""Rigid transmission error of a cycloid ball track from offsets of its grooves and crank.

Frame of the eccentric (``contact.ball_track``; docs/assumptions.md "Paper 003"): the
centre disc's axis ``O`` at the origin, the line of centres along ``+y`` (the planetary
disc's centre at ``E = e y``), the pitch point at ``P = -r_2 y`` (``r_2 = z_c e / 2``,
``r_3 = z_p e / 2`` from ``E``). The frame turns with the input angle ``phi``
(counter-clockwise positive). Ball ``i`` lies where the two grooves (the ball-centre
paths: the centre disc's epitrochoid, the planetary disc's hypotrochoid) touch, and
their common normal there, ``n_i = (sin theta_i, cos theta_i)``, passes through ``P``.

**First order.** Moving the centre disc's groove by ``c_2`` and the planetary disc's by
``c_3`` opens ball ``i``'s fit by ``(c_2 - c_3) . n_i`` along its normal. A rotation
``delta_2`` of the centre disc about ``O`` moves its groove at the ball along ``n_i`` by
``r_2 sin(theta_i) delta_2`` (the normal's lever about ``O``), one ``delta_3`` of the
planetary disc about ``E`` by ``r_3 sin(theta_i) delta_3``. Ball ``i`` stays in both
grooves (the curves stay tangent) when

``r_2 sin(theta_i) delta_2 - r_3 sin(theta_i) delta_3 + c . n_i = 0``,
``c = c_2 - c_3``,

so ball ``i`` alone would set ``delta_2 = -(c_x + c_y cot(theta_i)) / r_2`` (centre disc
output, the planetary disc held from turning). The part common to every ball is the
offset's projection ``c_x`` on the transmission direction (the pitch point's direction
of motion, normal to the line of centres) over the lever ``r_2``:

``delta_2 = -c_x / r_2`` (centre output), ``delta_3 = c_x / r_3`` (planetary output,
the centre disc fixed).

The rest, ``c_y cos(theta_i)`` along the normals, no rotation can take up: an offset
along the line of centres changes the balls' clearances (loosens the balls on one side
of the line of centres and tightens those on the other), as a centre-distance error
changes a gear pair's backlash, and gives no transmission error to first order.
``tests/test_transmission_accuracy_drives.py`` checks each ball's law against the exact
tangency of the perturbed trochoids.

**The offsets** (in the frame of the eccentric, ``x`` component), from a vector of size
``a`` whose direction is ``pi/2 + phase + angle`` in the housing (``angle``: the
rotation of the body carrying it; ``phase`` from the line of centres at zero input):
``a cos(pi/2 + phase + angle - phi) = -a sin(phase + angle - phi)``.

* a groove's eccentricity turns with its disc (``angle``: the disc's rotation);
* the crank's axis off the centre disc's axis is fixed in the housing (``angle = 0``)
  and moves the planetary disc (``c_3``) with it;
* the crank's radius error lies along the line of centres (no transmission error); its
  tangential offset is a constant ``-t`` along ``x`` (a constant angle).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError

__all__ = ["ball_lead", "centres_offset", "output_error", "transmission_offset"]

Array = NDArray[np.float64]


def transmission_offset(size: float, phase: float, angle: ArrayLike, phi: ArrayLike) -> Array:
    """``x`` component (m) in the frame of the eccentric of an offset of ``size`` (m)
    pointing at ``pi/2 + phase + angle`` in the housing, the frame turned by ``phi``:
    ``-size sin(phase + angle - phi)`` (module docstring)."""
    a = np.asarray(angle, float)
    p = np.asarray(phi, float)
    return -float(size) * np.sin(float(phase) + a - p)


def centres_offset(size: float, phase: float, angle: ArrayLike, phi: ArrayLike) -> Array:
    """``y`` component (m, along the line of centres) of the same offset as
    :func:`transmission_offset`: ``size cos(phase + angle - phi)``; it changes ball
    ``i``'s clearance by ``c_y cos(theta_i)`` along its normal, not the output angle."""
    a = np.asarray(angle, float)
    p = np.asarray(phi, float)
    return float(size) * np.cos(float(phase) + a - p)


def output_error(offset_x: ArrayLike, output: str, r_centre: float, r_planetary: float) -> Array:
    """Rotation (rad, counter-clockwise) of the output disc that keeps the balls in both
    grooves when the centre disc's groove leads the planetary disc's by ``offset_x``
    (m) along ``x``: ``-c_x / r_2`` (``output = "centre"``), ``c_x / r_3``
    (``"planetary"``).

    Raises
    ------
    ReducerlabError
        ``output`` not ``"centre"`` or ``"planetary"``; a radius not positive.
    """
    if not (r_centre > 0 and r_planetary > 0):
        raise ReducerlabError(
            f"pitch radii: must be > 0 (m); got r_2 = {r_centre!r}, r_3 = {r_planetary!r}"
        )
    c = np.asarray(offset_x, float)
    if output == "centre":
        return -c / r_centre
    if output == "planetary":
        return c / r_planetary
    raise ReducerlabError(f"output: must be 'centre' or 'planetary'; got {output!r}")


def ball_lead(
    offset: ArrayLike, sin_theta: ArrayLike, cos_theta: ArrayLike, r_centre: float
) -> Array:
    """Centre disc rotation (rad) with which ball ``i`` alone stays in both grooves, the
    planetary disc held: ``-(c_x sin(theta_i) + c_y cos(theta_i)) / (r_2 sin(theta_i))``
    (module docstring).

    Parameters
    ----------
    offset : array_like
        ``(c_x, c_y)`` (m): the centre disc's groove minus the planetary disc's, in the
        frame of the eccentric.
    sin_theta, cos_theta : array_like
        The balls' normal directions (``BallTrack.directions``).
    r_centre : float
        ``r_2`` (m).
    """
    cx, cy = np.asarray(offset, float)
    s = np.asarray(sin_theta, float)
    return -(cx * s + cy * np.asarray(cos_theta, float)) / (r_centre * s)
