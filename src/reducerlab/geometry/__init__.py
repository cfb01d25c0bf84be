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

# paper 001, issue 9 item 4: closed gear solids and their export (trimesh imported lazily)
from .export import export_mesh, export_point_cloud, export_step, load_mesh  # noqa: E402
from .solid import (  # noqa: E402
    Blank,
    GearSolid,
    SolidError,
    TriangleMesh,
    build_gear_solid,
    independent_volume_estimate,
)

__all__ += [
    "Blank",
    "GearSolid",
    "SolidError",
    "TriangleMesh",
    "build_gear_solid",
    "export_mesh",
    "export_point_cloud",
    "export_step",
    "independent_volume_estimate",
    "load_mesh",
]
