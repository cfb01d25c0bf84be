"""Kinematics-only designs (``type = "kinematics"``): drive type, tooth numbers,
nutation angle and input speed — enough for ratios, member speeds, mesh frequencies
and cone angles before a drive's full dynamic design exists.

::

    type = "kinematics"
    drive = "double_nutation"
    input_speed = "1500 rpm"
    nutation_angle = "5 deg"
    teeth = { z1 = 28, z2 = 26, z3 = 32, z4 = 30 }
"""

from __future__ import annotations

from typing import ClassVar, Literal

from pydantic import model_validator

from ..design import AngularVelocity, Design, PositiveInt, Power, Torque, angle_between
from ..design_files import field_rules
from ..errors import ReducerlabError
from ..kinematics import TRAINS, DriveKinematics

__all__ = ["KinematicsDesign"]


class KinematicsDesign(Design):
    """A drive described by its kinematics only.

    Attributes
    ----------
    drive : str
        A kinematic train of :data:`~reducerlab.kinematics.TRAINS`: ``nutation`` (single
        stage), ``double_nutation`` (paper 000), ``khv`` (paper 004), ``cycloid_ball``
        (paper 003) or ``gear_pair``.
    input_speed : float
        Input speed (rad/s; e.g. ``"1500 rpm"``).
    nutation_angle : float, optional
        Angle between the nutating gear's axis and the main axis (rad), nutation
        drives only.
    teeth : dict
        Tooth or lobe numbers; the keys each drive needs are its train's ``teeth``.
    contact : {"internal", "external"}
        Bevel pitch cones nested (usual) or touching externally; nutation drives only.
    output : str, optional
        Which member is the output (one of the train's ``outputs``; the first is the
        default).
    output_torque, output_power : float, optional
        The load the output member carries (N m) or the power it delivers (W), at most
        one: the torque flow's operating point (``reducerlab.analysis.torque_flow``).
    """

    type: Literal["kinematics"] = "kinematics"
    speed_fields: ClassVar = ("input_speed", None)
    load_fields: ClassVar = ("output_torque", "output_power")
    drive: Literal[tuple(TRAINS)]  # type: ignore[valid-type]
    input_speed: AngularVelocity
    nutation_angle: angle_between(0, 180) | None = None  # type: ignore[valid-type]
    teeth: dict[str, PositiveInt]
    contact: Literal["internal", "external"] | None = None
    output: str | None = None
    output_torque: Torque | None = None
    output_power: Power | None = None

    @model_validator(mode="after")
    def _drive_fields(self) -> KinematicsDesign:
        train = TRAINS[self.drive]
        problems = []
        rule = train.teeth_rule(self.teeth)
        if rule is not None:
            problems.append(("teeth", rule))
        if train.nutating and self.nutation_angle is None:
            problems.append(
                ("nutation_angle", f"drive {self.drive!r} needs nutation_angle (e.g. '5 deg')")
            )
        if not train.nutating and self.nutation_angle is not None:
            problems.append(("nutation_angle", f"drive {self.drive!r} has no nutation_angle"))
        if not train.nutating and self.contact is not None:
            problems.append(("contact", f"drive {self.drive!r} has no bevel contact type"))
        if self.output is not None and self.output not in train.outputs:
            problems.append(
                ("output", f"output for drive {self.drive!r} must be one of {list(train.outputs)}")
            )
        if self.input_speed == 0:
            problems.append(("input_speed", "input_speed must not be zero"))
        if problems:
            raise field_rules(*problems)
        try:
            self.kinematics()
        except ReducerlabError as exc:
            raise field_rules(("teeth", str(exc))) from None
        return self

    @property
    def drive_name(self) -> str:
        """The drive the kinematics describe (``drive``)."""
        return self.drive

    def kinematics(self) -> DriveKinematics:
        """The drive's :class:`~reducerlab.kinematics.DriveKinematics`, built by its train."""
        return TRAINS[self.drive].build(self.teeth, self.nutation_angle, self.contact, self.output)
