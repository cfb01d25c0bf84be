"""Mesh torques of a drive by virtual work through its own kinematics.

Seen from the carrier (the input crank, eccentric or planet carrier; the fixed frame
for a gear pair), every gear turns about its own axis at its speed relative to the
carrier ``w_g`` (a central gear ``omega_g - omega_H``; a nutating gear its spin
``psi'``), and the meshes of a series train pass one and the same power
``P' = T (omega_out - omega_H)``: the power the output member receives, ``T`` the
torque that drives it. A lossless mesh passes ``P'`` on unchanged, so each mesh exerts

``tau_driven = P' / w_driven``  on the gear nearer the output, and
``tau_driving = -P' / w_driving``  on its mate,

about each gear's own axis, signed along the gear's positive rotation (the axis its
speed is measured about). A body carrying two gears (the nutating gears 1 and 3 of a
double-sided nutation drive) then balances about its axis by itself
(``tau_1 + tau_3 = 0``), and the moments about the main axis balance
(``T_in = tau_out + tau_fixed``, ``T_in = P / omega_in``): tested, not assumed
(``tests/test_torque_flow.py``). The closed forms follow, e.g. the double-sided
nutation drive (gear 2 fixed, output gear 4): ``|tau_4| = T_out``,
``|tau_3| = |tau_1| = T_out z3/z4``, ``|tau_2| = T_out z2 z3 / (z1 z4)``.

Each drive's kinematics (:class:`~reducerlab.kinematics.DriveKinematics`) names its
series train (``torque_train()``, from the output member to the member the housing
holds), the carrier speed and the gears' relative speeds; :func:`mesh_torques` walks it.
The torques depend on the tooth numbers only, not on the speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import ReducerlabError
from .trains import DriveKinematics, GearMesh

__all__ = ["GearMesh", "MeshTorque", "TrainTorques", "mesh_torques"]


@dataclass(frozen=True)
class MeshTorque:
    """The torques one mesh exerts on its two gears.

    Attributes
    ----------
    gears : (str, str)
        Driven gear, driving gear.
    torques : (float, float)
        N m, the mesh's torque on each gear about its own axis, signed along the gear's
        positive rotation.
    relative_speeds : (float, float)
        rad/s, each gear's speed about its own axis relative to the carrier.
    carrier_power : float
        W, the power the mesh passes in the carrier frame (0 at rest).
    external : str or None
        See :class:`GearMesh`.
    """

    gears: tuple[str, str]
    torques: tuple[float, float]
    relative_speeds: tuple[float, float]
    carrier_power: float
    external: str | None

    def torque(self, gear: str) -> float:
        """The mesh's torque on ``gear`` (N m, signed)."""
        if gear not in self.gears:
            raise ReducerlabError(f"gear {gear!r} is not in this mesh; its gears: {self.gears}")
        return self.torques[self.gears.index(gear)]


@dataclass(frozen=True)
class TrainTorques:
    """A drive's torques at one operating point (lossless).

    Attributes
    ----------
    output_torque : float
        N m, the drive torque on the output member, signed along its rotation axis
        (``T_out`` times the sign of the output speed: it drives the load).
    input_torque : float
        N m, the torque on the input member, signed (``P / omega_in``).
    fixed : str or None
        The member the housing holds (the last driving gear of the train); None for a
        drive whose train ends at its input (a gear pair).
    reaction_torque : float or None
        N m, the torque the housing exerts on ``fixed`` about its axis (signed), None
        without a fixed member.
    meshes : dict of str to MeshTorque
        By the model's mesh element names, from the output on.
    """

    output_torque: float
    input_torque: float
    fixed: str | None
    reaction_torque: float | None
    meshes: dict[str, MeshTorque]


def mesh_torques(kin: DriveKinematics, output_torque: float, omega_in: float = 0.0) -> TrainTorques:
    """Torques of every mesh of ``kin``'s series train under an output load.

    Parameters
    ----------
    kin : DriveKinematics
    output_torque : float
        N m, the load the output member carries (``>= 0``); it opposes the output's
        rotation.
    omega_in : float
        rad/s, the input speed: sets the carrier-frame powers and the direction of
        rotation (at rest, 0, the torques are those of a positive input speed).

    Returns
    -------
    TrainTorques
    """
    if not (math.isfinite(output_torque) and output_torque >= 0):
        raise ReducerlabError(f"output_torque: must be a torque >= 0 (N m); got {output_torque!r}")
    w_in = omega_in if omega_in else 1.0
    scale = omega_in / w_in  # 0 at rest: no power, same torques
    w_h = kin.carrier_speed(w_in)
    w_out = w_in / kin.ratio
    tau_out = math.copysign(output_torque, w_out)
    p_rel = tau_out * (w_out - w_h)  # W at w_in
    rel = kin.relative_speeds(w_in)
    meshes: dict[str, MeshTorque] = {}
    last = None
    for m in kin.torque_train():
        a, b = rel[m.driven], rel[m.driving]
        torques = (p_rel / a + 0.0, -p_rel / b + 0.0)
        meshes[m.name] = MeshTorque(
            (m.driven, m.driving), torques, (a * scale, b * scale), p_rel * scale, m.external
        )
        last = (m.driving, torques[1])
    fixed = kin.fixed_member
    reaction = None
    if fixed is not None and last is not None and last[0] == fixed:
        reaction = -last[1] + 0.0
    input_torque = output_torque * abs(w_out) / w_in  # lossless: P / omega_in
    return TrainTorques(tau_out, input_torque, fixed, reaction, meshes)
