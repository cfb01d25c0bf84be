"""Speed-dependent elements of bodies seen in rotating frames or spinning: centripetal
stiffness, gyroscopic and Coriolis coupling, a nutating body in steady precession, and
the circulatory stiffness of a damper fixed in the housing.

Each scales with the model speed ``Omega`` (rad/s) through the ``speed`` argument of
:meth:`~reducerlab.model.Element.contribution`: skew velocity blocks linear in ``Omega``,
stiffnesses in ``Omega`` or ``Omega^2``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ModelError
from .dofs import Dof
from .elements import Contribution, Element, require_finite, require_nonnegative

__all__ = ["Centripetal", "Coriolis", "Gyroscopic", "Nutating", "StationaryDamping"]


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
        require_nonnegative(self.name, "mass", self.mass)
        require_finite(self.name, "ratio", self.ratio)

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
    the body's :class:`~reducerlab.model.Inertia` on ``rx`` and ``ry``.

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
        require_nonnegative(self.name, "polar", self.polar)
        require_finite(self.name, "spin_ratio", self.spin_ratio)

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
        require_nonnegative(self.name, "mass", self.mass)
        require_finite(self.name, "ratio", self.ratio)

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
    ``rz`` are the body's :class:`~reducerlab.model.Inertia` elements.

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
        require_nonnegative(self.name, "polar", self.polar)
        require_nonnegative(self.name, "diametral", self.diametral)
        for field_ in ("nutation", "spin_ratio", "precession_ratio"):
            require_finite(self.name, field_, getattr(self, field_))

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
    quarter turn), so besides its damping ``c u'`` (the :class:`~reducerlab.model.Support`)
    it adds the skew stiffness ``c Omega_f [[0, -1], [1, 0]]`` (Friswell et al., *Dynamics
    of Rotating Machines*, 2010, Sec. 5.6: stationary damping in rotating coordinates).
    Exact for an isotropic damper (``c_x = c_y``).

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
        require_nonnegative(self.name, "damping", self.damping)
        require_finite(self.name, "ratio", self.ratio)

    @property
    def dofs(self) -> tuple[str, ...]:
        return tuple(self.pair)

    def contribution(self, dofs: Sequence[Dof], speed: float) -> Contribution:
        _body_check(self.name, dofs, ("x", "y"), "stationary damping")
        k = self.damping * self.ratio * speed
        return Contribution(stiffness=np.array([[0.0, -k], [k, 0.0]]))
