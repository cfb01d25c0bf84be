"""Lines of action of a nutation drive's bevel meshes (paper 000): the contact normal of a
spiral bevel gear (Eq. 4), the pair's mean contact point in the nutating gear's frame and
the lever through which the nutating gear's tilts change the mesh deflection.
"""

from __future__ import annotations

import math

__all__ = ["contact_normal", "contact_point", "tilt_lever"]


def contact_normal(
    delta: float, beta: float, alpha_n: float, nutation: float = 0.0
) -> tuple[float, float, float]:
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


def contact_point(delta_c: float, nutation: float, cone_distance: float) -> tuple[float, ...]:
    """Mean contact point of a pair in the nutating gear's own frame (m).

    The point in space is the central gear's mean pitch point ``R_m (sin d_c, 0, cos d_c)``
    of the mesh frame, where paper 000 Eq. 4's central-gear normal acts (apex at the
    nutation centre); the nutating gear's frame is the mesh frame turned by the
    nutation angle about y (Eq. 4's ``a_11, a_13``), so the point there is
    ``R_y(-theta)`` of it.
    """
    x, z = cone_distance * math.sin(delta_c), cone_distance * math.cos(delta_c)
    c, s = math.cos(nutation), math.sin(nutation)
    return (x * c - z * s, 0.0, x * s + z * c)


def tilt_lever(
    delta_n: float, delta_c: float, beta: float, alpha_n: float, nutation: float, R: float
) -> tuple[float, float]:
    """``(g_rx, g_ry)`` (m): how a tilt of the nutating gear about its own transverse axes
    changes the mesh deflection, ``(p x n)_x, (p x n)_y`` with ``p`` the mean contact
    point (:func:`contact_point`, ``R`` the mean cone distance in m) and ``n`` the contact
    normal of paper 000 Eq. 4 (:func:`contact_normal`), both in the gear's own frame."""
    n = contact_normal(delta_n, beta, alpha_n)
    px, _, pz = contact_point(delta_c, nutation, R)
    return (-pz * n[1], pz * n[0] - px * n[2])
