"""Elements of a lumped-parameter model, all behind one interface.

An element names the DOFs it acts on and returns its local contributions
(:class:`Contribution`): mass, damping and stiffness blocks, nonlinear lines of action
(meshes) and loads. The assembler adds every element the same way; it never asks what
type an element is.

Lines of action follow sympy.mechanics' "scalar law times a geometry": a vector ``g`` of
projection coefficients turns the scalar relative displacement ``delta = g . q - e(t)``
into generalised forces ``g * F`` with ``F = k(t) f(delta) + c d(delta)/dt``, so the
mean stiffness block is ``k g g^T`` (paper 000 Eq. 2-7, paper 004 Eq. 2).

The speed-dependent elements of spinning bodies and rotating frames (centripetal,
gyroscopic, Coriolis, nutating, stationary damping) are in :mod:`reducerlab.model.rotating`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError
from .dofs import Dof
from .laws import Backlash, Constant, TimeLaw

__all__ = [
    "Contribution",
    "Coupling",
    "CubicSpring",
    "Element",
    "Inertia",
    "Line",
    "Load",
    "Mesh",
    "Support",
    "check_power_law",
    "require_finite",
    "require_nonnegative",
]


@dataclass(frozen=True)
class Line:
    """A nonlinear line of action in local coordinates of its element.

    Attributes
    ----------
    g : ndarray
        Projection coefficients on the element's DOFs (m/m or m/rad).
    stiffness : TimeLaw
        ``k(t)`` (N/m).
    damping : float
        ``c`` (N s/m) acting on ``d(delta)/dt``.
    backlash : Backlash
        Dead zone of ``f(delta)``; half width 0 means permanent contact.
    error : TimeLaw
        Transmission error ``e(t)`` (m).
    cubic : float
        Cubic stiffness ``k3`` (N/m^3): the force gains ``k3 f(delta)^3``.
    exponent : float
        Load exponent ``p`` of the elastic force (1: linear; 1.5: Hertzian point
        contact); see :class:`Mesh`.
    reference : float
        Deflection ``delta_ref`` (m) at which ``k(t)`` is the tangent stiffness of a
        line with ``p != 1`` (0 when ``p = 1``).
    """

    g: NDArray[np.float64]
    stiffness: TimeLaw
    damping: float
    backlash: Backlash
    error: TimeLaw
    cubic: float = 0.0
    exponent: float = 1.0
    reference: float = 0.0


@dataclass(frozen=True)
class Contribution:
    """Local blocks an element adds to the model (``n`` = number of element DOFs).

    ``mass``, ``damping``, ``stiffness`` are ``(n, n)`` arrays or None; ``lines`` are the
    element's nonlinear lines of action (their mean stiffness and damping are *not* in
    ``stiffness``/``damping``); ``loads`` pairs a local DOF index with a law of time
    (N or N m).
    """

    mass: NDArray | None = None
    damping: NDArray | None = None
    stiffness: NDArray | None = None
    lines: tuple[Line, ...] = ()
    loads: tuple[tuple[int, TimeLaw], ...] = ()


class Element(ABC):
    """Interface of all model elements.

    Subclasses are frozen dataclasses whose numeric fields are the element's parameters
    (addressable as ``"element_name.field"`` for sensitivities and sweeps).
    """

    name: str

    @property
    @abstractmethod
    def dofs(self) -> tuple[str, ...]:
        """Names (``"body.kind"``) of the DOFs the element acts on, in local order."""

    @abstractmethod
    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        """Local blocks, given the element's :class:`Dof` objects and the speed (rad/s)."""


def _number(value: object) -> float | None:
    """Real part of a real or complex scalar, or None if ``value`` is not a number."""
    if isinstance(value, bool) or not isinstance(value, int | float | complex | np.number):
        return None
    return float(np.real(value))


def require_finite(owner: str, name: str, value: float) -> None:
    """Raise a :class:`~reducerlab.errors.ModelError` naming ``owner`` and ``name`` unless
    ``value`` is a finite number (the real part of a complex one)."""
    v = _number(value)
    if v is None or not np.isfinite(v):
        raise ModelError(f"{owner}: {name} must be a finite number, got {value!r}")


def require_nonnegative(owner: str, name: str, value: float) -> None:
    """Raise a :class:`~reducerlab.errors.ModelError` naming ``owner`` and ``name`` unless
    ``value`` is a finite number >= 0 (the real part of a complex one)."""
    v = _number(value)
    if v is None or not (np.isfinite(v) and v >= 0):
        raise ModelError(f"{owner}: {name} must be a finite number >= 0, got {value!r}")


#: Range of a mesh law's load exponent: 1 (linear) to 3 (beyond every contact law;
#: below 1 the tangent stiffness would be infinite at first touch)
EXPONENT_RANGE = (1.0, 3.0)


def check_power_law(owner: str, exponent: float, reference: float) -> None:
    """Raise a :class:`~reducerlab.errors.ModelError` naming ``owner`` unless the load
    exponent lies in :data:`EXPONENT_RANGE` and, where it is not 1, the reference
    deflection (m) is a finite number > 0."""
    p = _number(exponent)
    lo, hi = EXPONENT_RANGE
    if p is None or not (lo <= p <= hi):
        raise ModelError(
            f"{owner}: exponent must be a number in [{lo:g}, {hi:g}], got {exponent!r}"
        )
    r = _number(reference)
    if r is None or not np.isfinite(r) or r < 0:
        raise ModelError(f"{owner}: reference_deflection must be a finite number >= 0 m, "
                         f"got {reference!r}")  # fmt: skip
    if p != 1.0 and r <= 0:
        raise ModelError(f"{owner}: reference_deflection must be > 0 m where exponent != 1 "
                         f"(the deflection at which the stiffness law is the tangent); got "
                         f"{reference!r}")  # fmt: skip


def _coefficients(owner: str, coef: Mapping[str, float]) -> dict[str, float]:
    out = dict(coef)
    if not out:
        raise ModelError(f"{owner}: needs at least one coefficient")
    for dof, g in out.items():
        v = _number(g)
        if v is None or not np.isfinite(v):
            raise ModelError(f"{owner}: coefficient of {dof!r} must be a finite number, got {g!r}")
    return out


def _as_law(value: TimeLaw | float, owner: str, what: str) -> TimeLaw:
    if isinstance(value, TimeLaw):
        return value
    try:
        return Constant(value)
    except (TypeError, ValueError) as exc:
        raise ModelError(f"{owner}: {what} must be a number or a TimeLaw, got {value!r}") from exc


@dataclass(frozen=True)
class Inertia(Element):
    """Mass (kg) on a translational DOF or moment of inertia (kg m^2) on a rotational one.

    On an equivalent linear displacement ``u = r theta`` a moment of inertia ``J``
    becomes the mass ``J / r^2`` (paper 003 Eq. 7, paper 004 Eq. 2).

    Parameters
    ----------
    dof : str
        DOF name.
    value : float
        kg for x, y, z; kg m^2 for rx, ry, rz and u.
    name : str
        Element name; defaults to ``"inertia:<dof>"``.
    """

    dof: str
    value: float
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", f"inertia:{self.dof}")
        v = _number(self.value)
        if v is None or not (np.isfinite(v) and v > 0):
            raise ModelError(
                f"{self.name}: value must be a finite number > 0 (kg, or kg m^2 for a "
                f"rotation), got {self.value!r}"
            )

    @property
    def dofs(self) -> tuple[str, ...]:
        return (self.dof,)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        (d,) = dofs
        m = self.value / d.radius**2 if d.kind == "u" else self.value
        return Contribution(mass=np.array([[m]]))


@dataclass(frozen=True)
class Coupling(Element):
    """Linear spring-damper on a linear combination of DOFs (a shaft, a bearing, ...).

    ``K = k g g^T``, ``C = c g g^T`` with ``g`` the coefficients (paper 003 ``K_m`` rows,
    paper 004's shafts ``k_DH (X_D - X_H)``).

    Parameters
    ----------
    coefficients : mapping of str to float
        DOF name -> coefficient of the stretch ``s = sum g_i q_i``.
    stiffness : float
        ``k`` (N/m if ``s`` is a length, N m/rad if an angle).
    damping : float
        ``c`` in the same force-per-rate unit.
    name : str
        Element name; defaults to ``"coupling:<dofs>"``.
    """

    coefficients: Mapping[str, float]
    stiffness: float
    damping: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", "coupling:" + "-".join(dict(self.coefficients)))
        coef = _coefficients(self.name, self.coefficients)
        object.__setattr__(self, "coefficients", coef)
        require_nonnegative(self.name, "stiffness", self.stiffness)
        require_nonnegative(self.name, "damping", self.damping)

    @property
    def dofs(self) -> tuple[str, ...]:
        return tuple(self.coefficients)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        g = np.array(list(self.coefficients.values()))
        gg = np.outer(g, g)
        return Contribution(stiffness=self.stiffness * gg, damping=self.damping * gg)


@dataclass(frozen=True)
class Support(Element):
    """Spring and damper from one DOF to ground (a bearing in one direction).

    Parameters
    ----------
    dof : str
        DOF name.
    stiffness : float
        N/m (translations, u) or N m/rad (rotations).
    damping : float
        N s/m or N m s/rad.
    """

    dof: str
    stiffness: float
    damping: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", f"support:{self.dof}")
        require_nonnegative(self.name, "stiffness", self.stiffness)
        require_nonnegative(self.name, "damping", self.damping)

    @property
    def dofs(self) -> tuple[str, ...]:
        return (self.dof,)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        return Contribution(
            stiffness=np.array([[self.stiffness]]), damping=np.array([[self.damping]])
        )


@dataclass(frozen=True)
class Mesh(Element):
    """A gear mesh: a line of action with time-varying stiffness, backlash and error.

    The relative displacement along the line of action is
    ``delta = sum_i g_i q_i - e(t)`` (paper 000 Eq. 2-3, paper 004 Eq. 3) and the mesh
    force ``F = k(t) f(delta) + c d(delta)/dt`` (paper 000 Eq. 5) acts on the DOFs as
    ``g F``. Positive ``delta`` is compression of the driving flank.

    Parameters
    ----------
    coefficients : mapping of str to float
        DOF name -> projection coefficient ``g_i`` (m/m for translations and u,
        m/rad for rotations, i.e. a radius).
    stiffness : TimeLaw or float
        ``k(t)`` (N/m); a number means a constant law. Modal analysis uses its mean.
    damping : float
        Mesh damping ``c`` (N s/m).
    backlash : Backlash, optional
        Clearance; None for permanent contact (``f(delta) = delta``).
    error : TimeLaw or float
        Static transmission error ``e(t)`` (m); 0 by default.
    exponent : float
        Load exponent ``p`` of the elastic force, ``1 <= p <= 3``; 1 (linear) by default.
    reference_deflection : float
        ``delta_ref`` (m, > 0 where ``p != 1``): the deflection at which ``k(t)`` is the
        tangent stiffness.
    sliding : mapping of str to float, optional
        DOF name -> coefficient ``s_i`` of the relative sliding displacement of the two
        flanks at the line's mean contact point, ``s = sum_i s_i q_i`` (m per unit DOF),
        tangent to the flanks in the direction a rotation of either gear about its own
        axis slides them (the quasi-static torsion test's Coulomb friction,
        ``analysis.torsion_friction``). Its DOFs must be among ``coefficients``; None
        (default) for a line whose contact rolls without sliding or is not modelled.
    """

    coefficients: Mapping[str, float]
    stiffness: TimeLaw | float
    damping: float = 0.0
    backlash: Backlash | None = None
    error: TimeLaw | float = 0.0
    name: str = ""
    exponent: float = 1.0
    reference_deflection: float = 0.0
    sliding: Mapping[str, float] | None = None

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", "mesh:" + "-".join(dict(self.coefficients)))
        coef = _coefficients(self.name, self.coefficients)
        object.__setattr__(self, "coefficients", coef)
        if self.sliding is not None:
            slide = _coefficients(f"{self.name} (sliding)", self.sliding)
            stray = sorted(set(slide) - set(coef))
            if stray:
                raise ModelError(
                    f"{self.name}: sliding coefficients must be on the line's own DOFs "
                    f"{sorted(coef)}; got {stray}"
                )
            object.__setattr__(self, "sliding", slide)
        object.__setattr__(self, "stiffness", _as_law(self.stiffness, self.name, "stiffness"))
        object.__setattr__(self, "error", _as_law(self.error, self.name, "error"))
        if self.backlash is None:
            object.__setattr__(self, "backlash", Backlash(0.0))
        elif not isinstance(self.backlash, Backlash):
            raise ModelError(f"{self.name}: backlash must be a Backlash, got {self.backlash!r}")
        mean = np.real(self.stiffness.mean)
        if not (np.isfinite(mean) and mean > 0):
            raise ModelError(f"{self.name}: mean stiffness must be > 0 N/m, got {mean!r}")
        low = self.stiffness.lower_bound()  # type: ignore[union-attr]
        if low is not None and low < 0:
            raise ModelError(
                f"{self.name}: the stiffness law goes down to {low:.6g} N/m: a mesh stiffness "
                "must stay >= 0 (for a Fourier law: the amplitudes add up to more than the mean)"
            )
        require_nonnegative(self.name, "damping", self.damping)
        check_power_law(self.name, self.exponent, self.reference_deflection)

    @property
    def dofs(self) -> tuple[str, ...]:
        return tuple(self.coefficients)

    @property
    def g(self) -> NDArray:
        """Projection coefficients in local order."""
        return np.array(list(self.coefficients.values()))

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        line = Line(
            g=self.g,
            stiffness=self.stiffness.at_speed(speed),  # type: ignore[union-attr]
            damping=self.damping,
            backlash=self.backlash,  # type: ignore[arg-type]
            error=self.error.at_speed(speed),  # type: ignore[union-attr]
            # real parts: a complex step of a sensitivity leaves the linear analyses alone
            exponent=float(np.real(self.exponent)),
            reference=float(np.real(self.reference_deflection))
            if np.real(self.exponent) != 1
            else 0.0,
        )
        return Contribution(lines=(line,))


@dataclass(frozen=True)
class CubicSpring(Element):
    """A spring with a cubic term along a projection: ``F = k1 delta + k3 delta^3 +
    c d(delta)/dt``, ``delta = sum_i g_i q_i`` (a Duffing-type restoring force; a
    negative ``k1`` with a positive ``k3`` gives the double well).

    It is a nonlinear line like a mesh (no backlash, no error): time integration uses
    the cubic term, linear analyses (modal, sweeps) only ``k1``.

    Parameters
    ----------
    coefficients : mapping of str to float
        DOF name -> projection coefficient ``g_i`` (m/m or m/rad).
    stiffness : float
        Linear stiffness ``k1`` (N/m), any sign.
    cubic : float
        Cubic stiffness ``k3`` (N/m^3), any sign.
    damping : float
        ``c`` (N s/m), >= 0.
    """

    coefficients: Mapping[str, float]
    stiffness: float
    cubic: float
    damping: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", "spring:" + "-".join(dict(self.coefficients)))
        object.__setattr__(self, "coefficients", _coefficients(self.name, self.coefficients))
        for fld in ("stiffness", "cubic"):
            v = getattr(self, fld)
            if not (isinstance(v, int | float) and np.isfinite(v)):
                raise ModelError(f"{self.name}: {fld} must be a finite number, got {v!r}")
        require_nonnegative(self.name, "damping", self.damping)

    @property
    def dofs(self) -> tuple[str, ...]:
        return tuple(self.coefficients)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        line = Line(
            g=np.array(list(self.coefficients.values())),
            stiffness=Constant(float(self.stiffness)),
            damping=self.damping,
            backlash=Backlash(0.0),
            error=Constant(0.0),
            cubic=float(self.cubic),
        )
        return Contribution(lines=(line,))


@dataclass(frozen=True)
class Load(Element):
    """External generalised force on one DOF (N, or N m on a rotation).

    On an equivalent linear displacement ``u = r theta`` give the force ``T / r``
    (paper 003 Eq. 7 ``F``, paper 004 ``P_D``).
    """

    dof: str
    value: TimeLaw | float = field(default=0.0)
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", f"load:{self.dof}")
        object.__setattr__(self, "value", _as_law(self.value, self.name, "value"))

    @property
    def dofs(self) -> tuple[str, ...]:
        return (self.dof,)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        return Contribution(loads=((0, self.value.at_speed(speed)),))  # type: ignore[union-attr]
