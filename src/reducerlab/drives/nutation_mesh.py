"""Lines of action of a nutation drive's bevel meshes (paper 000): the contact normal of a
spiral bevel gear (Eq. 4), the pair's mean contact point in the nutating gear's frame,
the lever through which the nutating gear's tilts change the mesh deflection, and the
drive's loads (the output torque and the fixed gear's reaction).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from ..design import OperatingPoint
from ..kinematics import DriveKinematics
from ..kinematics.torques import mesh_torques
from ..model import Load

__all__ = ["contact_normal", "contact_point", "drive_loads", "sliding_direction", "tilt_lever"]

#: The model's rotation DOF of each gear of the kinematics' torque train.
GEAR_DOFS = {
    "gear 1": "g13.rz", "gear 2": "g2.rz", "gear 3": "g13.rz", "gear 4": "g4.rz",
    "nutating gear": "g13.rz", "central gear": "g2.rz",
}  # fmt: skip


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


def sliding_direction(normal: tuple[float, float, float]) -> tuple[float, float, float]:
    """Unit tangent ``t = (y - a_y a) / |y - a_y a|`` of the flanks at the mean contact
    point: the direction in which a rotation of either gear about its own axis slides
    them (``y``, the circumferential direction at the contact point in both gears'
    frames, less its part along the normal ``a`` of :func:`contact_normal`).

    A rotation ``phi`` of a gear of mean radius ``R`` moves its flank by ``R phi y``:
    ``R a_y phi`` along the normal (the line's coefficient) and ``R w phi`` along ``t``
    with ``w = sqrt(1 - a_y^2) = t . y``; a translation ``u`` slides it by ``t . u``.
    """
    ax, ay, az = normal
    w = math.sqrt(max(1.0 - ay * ay, 0.0))
    if w == 0.0:
        raise ValueError("the contact normal is circumferential: no sliding direction")
    return (-ay * ax / w, w, -ay * az / w)


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


def drive_loads(
    kin: DriveKinematics,
    point: OperatingPoint,
    levers: Mapping[tuple[str, str], float],
    grounded: bool,
) -> list[Load]:
    """The loads of the lumped model at an operating point: the output torque and the
    fixed gear's reaction, so that no load acts along the model's rigid rotation.

    The load on the output's rotation (``g4.rz``; single-sided ``g13.rz``, the nutating
    gear's coupling) is ``-tau_out``, minus the torque flow's drive torque on it
    (:func:`~reducerlab.kinematics.torques.mesh_torques`; the model's rotations turn as
    the kinematics' relative speeds do). The reaction on the fixed gear's ``g2.rz`` is
    taken from the model's own rigid rotation, which turns the gears in the ratio of the
    mesh levers ``a_y r_m`` (their ``rz`` coefficients), not of the tooth numbers: the
    two differ where the mean radii depart from ``r2 / r1 = z2 / z1`` (within the 1e-3
    the design allows), and only the lever ratio leaves a static equilibrium
    (``docs/assumptions.md``). With ``grounded`` (a torsional support of gear 2) the
    support reacts and no reaction load is applied.

    Parameters
    ----------
    kin : DriveKinematics
        The ``double_nutation`` or ``nutation`` (output: the nutating gear) train.
    point : OperatingPoint
    levers : mapping of (str, str) to float
        ``{(mesh name, DOF): g}``, the meshes' coefficients (m) on the ``rz`` DOFs.
    grounded : bool

    Returns
    -------
    list of Load
        ``output_torque`` and ``reaction_torque`` (N m); none when unloaded.
    """
    if not point.loaded:
        return []
    flow = mesh_torques(kin, point.output_torque, point.input_speed)
    out_dof = GEAR_DOFS[next(iter(flow.meshes.values())).gears[0]]
    out_load = -flow.output_torque
    loads = [Load(out_dof, out_load, name="output_torque")]
    if grounded:
        return loads
    # rigid rotation with the nutating body turning by 1: each central gear turns by
    # -g13 / g_c of its mesh (no mesh deflection)
    turn = {"g13.rz": 1.0}
    for (mesh, dof), g in levers.items():
        if dof != "g13.rz":
            turn[dof] = -levers[(mesh, "g13.rz")] / g
    loads.append(Load("g2.rz", -out_load * turn[out_dof] / turn["g2.rz"], name="reaction_torque"))
    return loads
