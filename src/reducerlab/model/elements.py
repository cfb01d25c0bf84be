"""Elements of a lumped-parameter model, all behind one interface.

An element names the DOFs it acts on and returns its local contributions
(:class:`Contribution`): mass, damping and stiffness blocks, nonlinear lines of action
(meshes) and loads. The assembler adds every element the same way; it never asks what
type an element is.

Lines of action follow sympy.mechanics' "scalar law times a geometry": a vector ``g`` of
projection coefficients turns the scalar relative displacement ``delta = g . q - e(t)``
into generalised forces ``g * F`` with ``F = k(t) f(delta) + c d(delta)/dt``, so the
mean stiffness block is ``k g g^T`` (paper 000 Eq. 2-7, paper 004 Eq. 2).
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
    "Centripetal",
    "Contribution",
    "Coupling",
    "CubicSpring",
    "Element",
    "Inertia",
    "Line",
    "Load",
    "Mesh",
    "Support",
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
    """

    g: NDArray[np.float64]
    stiffness: TimeLaw
    damping: float
    backlash: Backlash
    error: TimeLaw
    cubic: float = 0.0


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


def _finite(owner: str, name: str, value: float) -> None:
    v = _number(value)
    if v is None or not np.isfinite(v):
        raise ModelError(f"{owner}: {name} must be a finite number, got {value!r}")


def _nonneg(owner: str, name: str, value: float) -> None:
    v = _number(value)
    if v is None or not (np.isfinite(v) and v >= 0):
        raise ModelError(f"{owner}: {name} must be a finite number >= 0, got {value!r}")


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
        _nonneg(self.name, "stiffness", self.stiffness)
        _nonneg(self.name, "damping", self.damping)

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
        _nonneg(self.name, "stiffness", self.stiffness)
        _nonneg(self.name, "damping", self.damping)

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
    """

    coefficients: Mapping[str, float]
    stiffness: TimeLaw | float
    damping: float = 0.0
    backlash: Backlash | None = None
    error: TimeLaw | float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", "mesh:" + "-".join(dict(self.coefficients)))
        coef = _coefficients(self.name, self.coefficients)
        object.__setattr__(self, "coefficients", coef)
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
        _nonneg(self.name, "damping", self.damping)

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
        _nonneg(self.name, "damping", self.damping)

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
class Centripetal(Element):
    """Speed-dependent stiffness ``-m Omega^2`` of a mass seen in a frame rotating at the
    model speed ``Omega`` (paper 003 Eq. 6-7, matrix ``K_omega``).

    Parameters
    ----------
    dof : str
        Translational DOF in the rotating frame.
    mass : float
        kg.
    ratio : float
        Rotation speed of the frame as a multiple of the model speed (1 by default).
    """

    dof: str
    mass: float
    ratio: float = 1.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", f"centripetal:{self.dof}")
        _nonneg(self.name, "mass", self.mass)
        _finite(self.name, "ratio", self.ratio)

    @property
    def dofs(self) -> tuple[str, ...]:
        return (self.dof,)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        (d,) = dofs
        if d.is_rotation:
            raise ModelError(f"{self.name}: centripetal terms act on translations, not {d.name}")
        omega = self.ratio * speed
        return Contribution(stiffness=np.array([[-self.mass * omega**2]]))


def _body_check(owner: str, dofs: Sequence[Dof], kinds: tuple[str, ...], what: str) -> None:
    """``dofs`` must be one body's DOFs of ``kinds``, in that order."""
    if tuple(d.kind for d in dofs) != kinds or len({d.body for d in dofs}) != 1:
        raise ModelError(
            f"{owner}: {what} act on one body's ({', '.join(kinds)}), got "
            f"({', '.join(d.name for d in dofs)})"
        )


@dataclass(frozen=True)
class Gyroscopic(Element):
    """Gyroscopic coupling of a rigid body spinning about its own axis (z).

    A body of polar moment of inertia ``polar`` spinning at ``Omega_s = spin_ratio *
    Omega`` (``Omega``: the model speed) couples its tilts ``rx, ry``:
    ``J_d rx'' + J_p Omega_s ry' = M_x``, ``J_d ry'' - J_p Omega_s rx' = M_y`` (Friswell,
    Penny, Garvey and Lees, *Dynamics of Rotating Machines*, 2010, Eq. 3.29; Lalanne and
    Ferraris, *Rotordynamics Prediction in Engineering*, 1998, Ch. 2): the skew velocity
    block ``Omega_s J_p [[0, 1], [-1, 0]]`` on ``(rx, ry)``, which splits each tilting
    frequency into a forward and a backward whirl. The diametral inertia ``J_d`` is
    the body's :class:`Inertia` on ``rx`` and ``ry``.

    Parameters
    ----------
    dofs : (str, str)
        The body's ``rx`` and ``ry`` DOFs.
    polar : float
        ``J_p`` (kg m^2), >= 0.
    spin_ratio : float
        Spin speed over the model speed (the drive's kinematics: e.g. -1392.86 / 1500
        for the nutating gear's spin in paper 000's drive); 1 by default.
    """

    pair: tuple[str, str]
    polar: float
    spin_ratio: float = 1.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", f"gyroscopic:{self.pair[0].split('.')[0]}")
        _nonneg(self.name, "polar", self.polar)
        _finite(self.name, "spin_ratio", self.spin_ratio)

    @property
    def dofs(self) -> tuple[str, ...]:
        return tuple(self.pair)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        _body_check(self.name, dofs, ("rx", "ry"), "gyroscopic moments")
        g = self.polar * self.spin_ratio * speed
        return Contribution(damping=np.array([[0.0, g], [-g, 0.0]]))


@dataclass(frozen=True)
class Coriolis(Element):
    """Coriolis coupling of a mass seen in a frame rotating at ``Omega_f = ratio *
    Omega`` about z: ``m (x'' - 2 Omega_f y') = F_x``, ``m (y'' + 2 Omega_f x') = F_y``
    (the rotating-carrier terms of Lin and Parker, J. Vib. Acoust. 121, 1999, 316-321);
    the skew velocity block ``2 m Omega_f [[0, -1], [1, 0]]`` on ``(x, y)``. Add the
    centripetal stiffness ``-m Omega_f^2`` with :class:`Centripetal` on each DOF.

    Parameters
    ----------
    pair : (str, str)
        The body's ``x`` and ``y`` DOFs (in the rotating frame).
    mass : float
        kg, >= 0.
    ratio : float
        Frame speed over the model speed; 1 by default.
    """

    pair: tuple[str, str]
    mass: float
    ratio: float = 1.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", f"coriolis:{self.pair[0].split('.')[0]}")
        _nonneg(self.name, "mass", self.mass)
        _finite(self.name, "ratio", self.ratio)

    @property
    def dofs(self) -> tuple[str, ...]:
        return tuple(self.pair)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        _body_check(self.name, dofs, ("x", "y"), "Coriolis forces")
        g = 2.0 * self.mass * self.ratio * speed
        return Contribution(damping=np.array([[0.0, -g], [g, 0.0]]))


@dataclass(frozen=True)
class Nutating(Element):
    """Gyroscopic coupling of an axisymmetric body in steady precession, in the frame of
    its crank.

    The body's axis is held at the nutation angle ``theta`` from the main axis by a crank
    turning at ``Omega_p = precession_ratio * Omega`` (``Omega``: the model speed), and
    the body spins at ``psi' = spin_ratio * Omega`` relative to the crank (paper 002's
    Euler angles ``phi' = Omega_p``, ``theta``, ``psi'``). Its tilts ``rx, ry`` about its
    own transverse axes and its spin perturbation ``rz``, all measured in the crank
    frame, obey the linearised Euler equations (derived from ``T = 1/2 w^T J w`` with
    ``R = R_z(Omega_p t) R_y(theta) R_x(rx) R_y(ry) R_z(psi' t + rz)``)::

        J_d rx'' + g ry'                              + k_x rx = M_x
        J_d ry'' - g rx' + J_p Omega_p sin(theta) rz' + k_y ry = M_y
        J_p rz''         - J_p Omega_p sin(theta) ry'          = M_z

    with the axial spin ``w_3 = psi' + Omega_p cos(theta)``, ``g = J_p w_3 - 2 J_d Omega_p
    cos(theta)``, ``k_x = Omega_p cos(theta) (J_p w_3 - J_d Omega_p cos(theta))`` and
    ``k_y = Omega_p (J_p psi' cos(theta) + (J_p - J_d) Omega_p cos(2 theta))``: a skew
    velocity block (linear in ``Omega``) and a speed-squared stiffness. The steady moment
    the crank supplies, ``Omega_p sin(theta) (J_p w_3 - J_d Omega_p cos(theta))`` about
    ``ry``, is paper 000's ``L_1`` (Eq. 7, from :func:`~reducerlab.kinematics.gyroscopic_moment`)
    and is a load, not part of this element. At ``theta = 0`` and ``Omega_p = 0`` it
    reduces to :class:`Gyroscopic`. The inertias ``J_d`` on ``rx, ry`` and ``J_p`` on
    ``rz`` are the body's :class:`Inertia` elements.

    Parameters
    ----------
    triple : (str, str, str)
        The body's ``rx``, ``ry`` and ``rz`` DOFs.
    polar, diametral : float
        ``J_p`` and ``J_d`` (kg m^2) about the body's centre, >= 0.
    nutation : float
        ``theta`` (rad).
    spin_ratio : float
        ``psi' / Omega``: the body's spin relative to its crank.
    precession_ratio : float
        ``Omega_p / Omega``; 1 by default (the crank is the input shaft).
    """

    triple: tuple[str, str, str]
    polar: float
    diametral: float
    nutation: float
    spin_ratio: float
    precession_ratio: float = 1.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", f"nutating:{self.triple[0].split('.')[0]}")
        _nonneg(self.name, "polar", self.polar)
        _nonneg(self.name, "diametral", self.diametral)
        for field_ in ("nutation", "spin_ratio", "precession_ratio"):
            _finite(self.name, field_, getattr(self, field_))

    @property
    def dofs(self) -> tuple[str, ...]:
        return tuple(self.triple)

    def axial_spin_ratio(self) -> float:
        """``w_3 / Omega = psi' / Omega + (Omega_p / Omega) cos(theta)``: the body's
        absolute spin about its own axis per unit model speed."""
        return self.spin_ratio + self.precession_ratio * np.cos(self.nutation)

    def coefficients(self, speed: float) -> tuple[float, float, float, float]:
        """``(g, h, k_x, k_y)``: tilt gyroscopic coefficient, tilt-spin coefficient
        ``J_p Omega_p sin(theta)`` (N m s) and the two tilt stiffnesses (N m / rad)."""
        Jp, Jd = self.polar, self.diametral  # numpy functions: complex-step safe
        c, s = np.cos(self.nutation), np.sin(self.nutation)
        wp, spin = self.precession_ratio * speed, self.spin_ratio * speed
        w3 = spin + wp * c
        g = Jp * w3 - 2.0 * Jd * wp * c
        kx = wp * c * (Jp * w3 - Jd * wp * c)
        ky = wp * (Jp * spin * c + (Jp - Jd) * wp * np.cos(2.0 * self.nutation))
        return g, Jp * wp * s, kx, ky

    def steady_moment(self, speed: float) -> float:
        """Moment about ``ry`` (N m) that keeps the body in its steady precession,
        ``Omega_p sin(theta) (J_p w_3 - J_d Omega_p cos(theta))`` (Euler's equations)."""
        wp = self.precession_ratio * speed
        c = np.cos(self.nutation)
        w3 = self.spin_ratio * speed + wp * c
        return wp * np.sin(self.nutation) * (self.polar * w3 - self.diametral * wp * c)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        _body_check(self.name, dofs, ("rx", "ry", "rz"), "nutating-body terms")
        g, h, kx, ky = self.coefficients(speed)
        C = np.array([[0.0, g, 0.0], [-g, 0.0, h], [0.0, -h, 0.0]])
        K = np.array([[kx, 0.0, 0.0], [0.0, ky, 0.0], [0.0, 0.0, 0.0]])
        return Contribution(damping=C, stiffness=K)


@dataclass(frozen=True)
class StationaryDamping(Element):
    """Circulatory stiffness of a damper fixed in the housing, seen from a frame rotating
    at ``Omega_f = ratio * Omega`` about z.

    A support damper ``c`` acts on the fixed-frame velocity ``u' + Omega_f J u`` of a
    body whose displacement ``u = (x, y)`` is measured in the rotating frame (``J`` the
    quarter turn), so besides its damping ``c u'`` (the :class:`Support`) it adds the skew
    stiffness ``c Omega_f [[0, -1], [1, 0]]`` (Friswell et al., *Dynamics of Rotating
    Machines*, 2010, Sec. 5.6: stationary damping in rotating coordinates). Exact for an
    isotropic damper (``c_x = c_y``).

    Parameters
    ----------
    pair : (str, str)
        The body's ``x`` and ``y`` DOFs (in the rotating frame).
    damping : float
        ``c`` (N s/m), >= 0.
    ratio : float
        Frame speed over the model speed; 1 by default.
    """

    pair: tuple[str, str]
    damping: float
    ratio: float = 1.0
    name: str = ""

    def __post_init__(self) -> None:
        if not self.name:
            object.__setattr__(self, "name", f"stationary_damping:{self.pair[0].split('.')[0]}")
        _nonneg(self.name, "damping", self.damping)
        _finite(self.name, "ratio", self.ratio)

    @property
    def dofs(self) -> tuple[str, ...]:
        return tuple(self.pair)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        _body_check(self.name, dofs, ("x", "y"), "stationary damping")
        k = self.damping * self.ratio * speed
        return Contribution(stiffness=np.array([[0.0, -k], [k, 0.0]]))


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
