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

from typing import Literal

from pydantic import model_validator

from ..design import AngularVelocity, Design, PositiveInt, angle_between, field_rules
from ..errors import ReducerlabError
from ..kinematics import (
    CycloidBallDrive,
    DoubleNutationDrive,
    DriveKinematics,
    ExternalGearPair,
    KHVDrive,
    NutationDrive,
)

__all__ = ["TEETH", "KinematicsDesign"]

#: Tooth (lobe) numbers each drive needs, and the outputs it allows.
TEETH: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "nutation": (("nutating", "central"), ("central", "nutating")),
    "double_nutation": (("z1", "z2", "z3", "z4"), ("gear4",)),
    "khv": (("planet", "ring"), ("planet",)),
    "cycloid_ball": (("centre", "planetary"), ("centre", "planetary")),
    "gear_pair": (("pinion", "gear"), ("gear",)),
}
NUTATING = ("nutation", "double_nutation")


class KinematicsDesign(Design):
    """A drive described by its kinematics only.

    Attributes
    ----------
    drive : str
        ``nutation`` (single stage), ``double_nutation`` (paper 000), ``khv``
        (paper 004), ``cycloid_ball`` (paper 003) or ``gear_pair``.
    input_speed : float
        Input speed (rad/s; e.g. ``"1500 rpm"``).
    nutation_angle : float, optional
        Angle between the nutating gear's axis and the main axis (rad), nutation
        drives only.
    teeth : dict
        Tooth or lobe numbers; the keys each drive needs are in :data:`TEETH`.
    contact : {"internal", "external"}
        Bevel pitch cones nested (usual) or touching externally; nutation drives only.
    output : str, optional
        Which member is the output (see :data:`TEETH`; first entry is the default).
    """

    type: Literal["kinematics"] = "kinematics"
    drive: Literal["nutation", "double_nutation", "khv", "cycloid_ball", "gear_pair"]
    input_speed: AngularVelocity
    nutation_angle: angle_between(0, 180) | None = None  # type: ignore[valid-type]
    teeth: dict[str, PositiveInt]
    contact: Literal["internal", "external"] | None = None
    output: str | None = None

    @model_validator(mode="after")
    def _drive_fields(self) -> KinematicsDesign:
        need, outputs = TEETH[self.drive]
        missing = [k for k in need if k not in self.teeth]
        extra = [k for k in self.teeth if k not in need]
        problems = []
        if missing or extra:
            problems.append((
                "teeth",
                f"teeth for drive {self.drive!r} must be exactly {{{', '.join(need)}}}"
                + (f"; missing {missing}" if missing else "")
                + (f"; unknown {extra}" if extra else ""),
            ))  # fmt: skip
        if self.drive in NUTATING and self.nutation_angle is None:
            problems.append(
                ("nutation_angle", f"drive {self.drive!r} needs nutation_angle (e.g. '5 deg')")
            )
        if self.drive not in NUTATING and self.nutation_angle is not None:
            problems.append(("nutation_angle", f"drive {self.drive!r} has no nutation_angle"))
        if self.drive not in NUTATING and self.contact is not None:
            problems.append(("contact", f"drive {self.drive!r} has no bevel contact type"))
        if self.output is not None and self.output not in outputs:
            problems.append(
                ("output", f"output for drive {self.drive!r} must be one of {list(outputs)}")
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

    @property
    def operating_speed(self) -> float:
        """The input speed (rad/s)."""
        return float(self.input_speed)

    def kinematics(self) -> DriveKinematics:
        """The drive's :class:`~reducerlab.kinematics.DriveKinematics`."""
        z = self.teeth
        out = self.output or TEETH[self.drive][1][0]
        if self.drive == "nutation":
            return NutationDrive(
                z["nutating"], z["central"], self.nutation_angle, self.contact or "internal", out
            )
        if self.drive == "double_nutation":
            return DoubleNutationDrive(
                z["z1"], z["z2"], z["z3"], z["z4"], self.nutation_angle,
                self.contact or "internal",
            )  # fmt: skip
        if self.drive == "khv":
            return KHVDrive(z["planet"], z["ring"])
        if self.drive == "cycloid_ball":
            return CycloidBallDrive(z["centre"], z["planetary"], out)
        return ExternalGearPair(z["pinion"], z["gear"])
