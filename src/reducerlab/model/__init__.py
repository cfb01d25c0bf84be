"""Generic lumped-parameter models: DOFs, elements, laws, assembly."""

from .assembly import Matrices, Model
from .dofs import FAMILIES, KINDS, Dof
from .elements import (
    Contribution,
    Coupling,
    CubicSpring,
    Element,
    Inertia,
    Line,
    Load,
    Mesh,
    Support,
)
from .laws import Backlash, Constant, Fourier, PiecewisePolynomial, TimeLaw, dead_zone
from .rotating import Centripetal, Coriolis, Gyroscopic, Nutating, StationaryDamping
from .system import NonlinearSystem

__all__ = [
    "FAMILIES",
    "KINDS",
    "Backlash",
    "Centripetal",
    "Constant",
    "Contribution",
    "Coriolis",
    "Coupling",
    "CubicSpring",
    "Dof",
    "Element",
    "Fourier",
    "Gyroscopic",
    "Inertia",
    "Line",
    "Load",
    "Matrices",
    "Mesh",
    "Model",
    "NonlinearSystem",
    "Nutating",
    "PiecewisePolynomial",
    "StationaryDamping",
    "Support",
    "TimeLaw",
    "dead_zone",
]
