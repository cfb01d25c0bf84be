"""Structural finite elements of solid bodies (gear bodies, issue 14): quadratic
tetrahedra assembled with scikit-fem, free vibration by shift-invert Lanczos."""

from .elasticity import STEEL, BodyModes, Material, assemble, body_modes

__all__ = ["STEEL", "BodyModes", "Material", "assemble", "body_modes"]
