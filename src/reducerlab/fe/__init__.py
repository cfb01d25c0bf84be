"""Structural finite elements of solid bodies (gear bodies, issue 14): quadratic
tetrahedra assembled with scikit-fem, free vibration by shift-invert Lanczos (of the
whole body, or by cyclic symmetry of one sector: ``fe.cyclic``), gear meshes built with
gmsh, mode-type names, VTU output."""

from .elasticity import STEEL, BodyModes, Material, assemble, body_modes
from .gear_mesh import BlankFeatures, GearBodyMesh, MeshError, MeshSizes, mesh_gear
from .modetypes import ModeType, classify_mode, classify_modes
from .vtu import write_vtu

__all__ = [
    "STEEL",
    "BlankFeatures",
    "BodyModes",
    "GearBodyMesh",
    "Material",
    "MeshError",
    "MeshSizes",
    "ModeType",
    "assemble",
    "body_modes",
    "classify_mode",
    "classify_modes",
    "mesh_gear",
    "write_vtu",
]
