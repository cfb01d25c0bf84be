"""The torque flow of a drive at its operating point: where the load goes, by virtual work
through the drive's own kinematics.

The design gives its input speed and its load (the output torque or the power,
:meth:`~reducerlab.design.Design.operating_point`); the kinematics give every gear's
speed relative to the carrier, and the meshes of the series train pass one carrier-frame
power ``P' = T_out (omega_out - omega_H)``, so each mesh's torque on a gear is
``P' / (omega_g - omega_H)`` (:mod:`reducerlab.kinematics.torques`). Lossless:
``P_in = P_out``. Closed forms it reproduces (``tests/test_torque_flow.py``):

* double-sided nutation drive (paper 000; gear 2 fixed, output gear 4):
  ``T4 = T_out``, ``T3 = T1 = T_out z3/z4``, ``T2 = T_out z2 z3 / (z1 z4)``,
  ``i = 1 / (1 - z2 z3 / (z1 z4))``;
* single-sided nutation drive (gear 2 fixed, output the nutating gear's net rotation
  through a coupling): ``T1 = T_out``, ``T2 = T_out z2/z1``, ``i = z1 / (z1 - z2)``;
* KHV drive (paper 004; carrier input, ring fixed, planet output through the W
  mechanism): ``T_V = T_out``, ``T_K = T_out z_K / z_V``, ``T_in = T_out / |i|``;
* gear pair: ``T_gear = T_out``, ``T_pinion = T_out z1 / z2``;
* cycloid ball drive (paper 003): the total torque through the ball track only
  (``T_centre``, ``T_planetary = T_centre z_p / z_c``), not how the balls share it.

A mesh's tangential force is the torque on its external gear (on the first gear where
both are external) over that gear's mean (bevel) or reference pitch radius (the
design's :meth:`~reducerlab.design.Design.pitch_radii`); a kinematics-only design has
no radii and gives none.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..design import Design
from ..errors import ReducerlabError
from ..kinematics.torques import mesh_torques
from ..numformat import Column, Table, Value, quantity_table
from ..units import RPM

__all__ = ["MeshLoad", "TorqueFlow", "torque_flow"]


@dataclass(frozen=True)
class MeshLoad:
    """The load of one mesh at the operating point.

    Attributes
    ----------
    gears : (str, str)
        The gear nearer the output (driven) and its mate (driving), by the kinematics'
        names (``"gear 4"``, ``"planet V"``).
    torques : (float, float)
        N m, the mesh's torque on each gear about its own axis, signed along the gear's
        positive rotation (the axis its speed is measured about).
    external : str or None
        The external gear of an internal pair: the one whose torque
        :func:`reducerlab.analysis.contact.contact_analysis` takes (gear 2 for pair 1,
        gear 4 for pair 2 of the nutation drive); None when both gears are external.
    tangential_force : float or None
        N, ``|T| / r`` on the external gear (the first gear where both are external)
        at its mean or pitch radius; None without radii.
    carrier_power : float
        W, the power the mesh passes in the carrier frame.
    """

    gears: tuple[str, str]
    torques: tuple[float, float]
    external: str | None
    tangential_force: float | None
    carrier_power: float

    def torque(self, gear: str) -> float:
        """The mesh's torque on ``gear`` (N m, signed)."""
        if gear not in self.gears:
            raise ReducerlabError(f"gear {gear!r} is not in this mesh; its gears: {self.gears}")
        return self.torques[self.gears.index(gear)]

    @property
    def external_torque(self) -> float | None:
        """N m, the magnitude of the torque on the external gear (None without one)."""
        return None if self.external is None else abs(self.torque(self.external))


@dataclass(frozen=True)
class TorqueFlow:
    """A drive's torques at its operating point (lossless).

    Attributes
    ----------
    input_speed, output_speed : float
        rad/s, signed.
    ratio : float
        ``omega_in / omega_out`` (signed).
    output_torque : float
        N m, the load the output member carries (``>= 0``).
    input_torque : float
        N m, ``P / |omega_in|`` (``T_out / |i|``): the input torque of the lossless drive.
    power : float
        W, ``T_out |omega_out|`` = ``P_in`` = ``P_out``.
    fixed : str or None
        The member the housing holds (None for a gear pair).
    reaction_torque : float or None
        N m, the torque the housing exerts on ``fixed`` about its axis (signed).
    meshes : dict of str to MeshLoad
        By the model's mesh element names (``"mesh1"``, ``"mesh2"``, ``"mesh"``,
        ``"cycloid_pairs"``), from the output on.
    """

    input_speed: float
    output_speed: float
    ratio: float
    output_torque: float
    input_torque: float
    power: float
    fixed: str | None
    reaction_torque: float | None
    meshes: dict[str, MeshLoad]

    def table(self) -> str:
        """A plain-text table of the flow: the operating point, then the mesh torques."""
        rows: list[tuple[str, Any, str]] = [
            ("ratio", Value(self.ratio, "ratio"), ""),
            ("input speed", self.input_speed * RPM, "rpm"),
            ("output speed", self.output_speed * RPM, "rpm"),
            ("output torque", self.output_torque, "N m"),
            ("input torque", self.input_torque, "N m"),
            ("power", self.power, "W"),
        ]
        if self.fixed is not None and self.reaction_torque is not None:
            rows.append((f"reaction on {self.fixed}", self.reaction_torque, "N m"))
        meshes = Table([Column("mesh", kind="text"), Column("gear", kind="text"),
                        Column("torque", "N m", "torque"), Column("F_t", "N", "force"),
                        Column("external", kind="text")])  # fmt: skip
        for name, m in self.meshes.items():
            at = m.external or m.gears[0]  # where F_t acts (MeshLoad.tangential_force)
            for g, t in zip(m.gears, m.torques, strict=True):
                force = m.tangential_force if g == at else None
                meshes.add(name, g, t, force, "yes" if g == m.external else "")
        return "\n".join([quantity_table(rows).text(), meshes.text()])


def torque_flow(design: Design) -> TorqueFlow:
    """The torque flow of ``design`` at its operating point.

    Parameters
    ----------
    design : Design
        A design with kinematics; its load (``operating_point().output_torque``) may be
        0, which gives zero torques.

    Returns
    -------
    TorqueFlow

    Raises
    ------
    ReducerlabError
        For a design without kinematics (a lumped model) or not a Design.
    """
    if not isinstance(design, Design):
        raise ReducerlabError(f"torque_flow: needs a Design, got {type(design).__name__}")
    kin = design.kinematics()
    if kin is None:
        raise ReducerlabError(
            f"torque_flow: {design.source}: design type {design.type!r} has no drive "
            "kinematics, so no torque flow"
        )
    point = design.operating_point()
    flow = mesh_torques(kin, point.output_torque, point.input_speed)
    radii = design.pitch_radii()
    meshes = {}
    for name, m in flow.meshes.items():
        gear = m.external or m.gears[0]
        r = radii.get(gear)
        force = None if r is None else abs(m.torque(gear)) / r
        meshes[name] = MeshLoad(m.gears, m.torques, m.external, force, m.carrier_power)
    ratio = float(kin.ratio)
    w_out = point.input_speed / ratio
    return TorqueFlow(
        input_speed=point.input_speed,
        output_speed=w_out,
        ratio=ratio,
        output_torque=point.output_torque,
        input_torque=point.output_torque / abs(ratio),
        power=point.output_torque * abs(w_out),
        fixed=flow.fixed,
        reaction_torque=flow.reaction_torque,
        meshes=meshes,
    )
