"""Generic lumped-parameter models: DOFs, elements, laws, assembly."""

from .assembly import Matrices, Model
from .dofs import FAMILIES, KINDS, Dof
from .elements import (
    Centripetal,
    Contribution,
    Coriolis,
    Coupling,
    CubicSpring,
    Element,
    Gyroscopic,
    Inertia,
    Line,
    Load,
    Mesh,
    Nutating,
    StationaryDamping,
    Support,
)
from .laws import Backlash, Constant, Fourier, PiecewisePolynomial, TimeLaw, dead_zone
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
