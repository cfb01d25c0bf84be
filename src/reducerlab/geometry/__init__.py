"""Gear geometry: involute functions and internal gear pairs with profile shift."""

from .internal_pair import InternalGearPair, inv, inv_inverse

__all__ = ["InternalGearPair", "inv", "inv_inverse"]

# paper 001: basic profiles, crown gear, enveloped nutation spiral bevel gear surfaces
from .bevel_surface import (
    BevelGear,
    FlankSurface,
    SurfaceReport,
    ToothSurface,
    crown_to_gear,
    generate_flank,
    generate_tooth,
    nutation_bevel_pair,
)
from .profiles import (
    BasicProfile,
    CallableProfile,
    DoubleCircularArcProfile,
    InvoluteProfile,
    ProfileError,
    SplineProfile,
)
from .spiral import CrownGear, LogSpiral

__all__ += [
    "BasicProfile",
    "BevelGear",
    "CallableProfile",
    "CrownGear",
    "DoubleCircularArcProfile",
    "FlankSurface",
    "InvoluteProfile",
    "LogSpiral",
    "ProfileError",
    "SplineProfile",
    "SurfaceReport",
    "ToothSurface",
    "crown_to_gear",
    "generate_flank",
    "generate_tooth",
    "nutation_bevel_pair",
]
