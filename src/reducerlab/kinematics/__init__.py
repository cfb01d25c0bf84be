"""Kinematics: rotations and frames, Euler-angle motion of a nutating gear, relative
motion at the mesh, and transmission ratios of every drive, derived from the rolling of
pitch cones (see ``docs/kinematics.md``); :data:`TRAINS` registers every drive kind's train."""

from .euler import (
    angular_acceleration_body,
    angular_acceleration_fixed,
    angular_velocity_body,
    angular_velocity_fixed,
    gyroscopic_moment,
)
from .mesh import (
    external_cone_angles,
    internal_cone_angles,
    nutation_angle_from_cones,
    relative_rotation_axis,
    relative_velocity,
)
from .registry import TRAINS, Train
from .rotations import Transform, euler_zxz, rot_x, rot_y, rot_z, skew, unskew
from .trains import (
    CycloidBallDrive,
    DoubleNutationDrive,
    DriveKinematics,
    ExternalGearPair,
    KHVDrive,
    NutationDrive,
)

__all__ = [
    "TRAINS",
    "CycloidBallDrive",
    "DoubleNutationDrive",
    "DriveKinematics",
    "ExternalGearPair",
    "KHVDrive",
    "NutationDrive",
    "Train",
    "Transform",
    "angular_acceleration_body",
    "angular_acceleration_fixed",
    "angular_velocity_body",
    "angular_velocity_fixed",
    "euler_zxz",
    "external_cone_angles",
    "gyroscopic_moment",
    "internal_cone_angles",
    "nutation_angle_from_cones",
    "relative_rotation_axis",
    "relative_velocity",
    "rot_x",
    "rot_y",
    "rot_z",
    "skew",
    "unskew",
]
