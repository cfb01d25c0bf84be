"""Generic lumped-parameter models: DOFs, elements, laws, assembly."""

from .assembly import Matrices, Model
from .dofs import FAMILIES, KINDS, Dof
from .elements import (
    Centripetal,
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
from .system import NonlinearSystem

__all__ = [
    "FAMILIES",
    "KINDS",
    "Backlash",
    "Centripetal",
    "Constant",
    "Contribution",
    "Coupling",
    "CubicSpring",
    "Dof",
    "Element",
    "Fourier",
    "Inertia",
    "Line",
    "Load",
    "Matrices",
    "Mesh",
    "Model",
    "NonlinearSystem",
    "PiecewisePolynomial",
    "Support",
    "TimeLaw",
    "dead_zone",
]
