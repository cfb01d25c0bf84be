"""Logarithmic spiral tooth line and the hypothetical crown gear of paper 001.

Frame ``S_C`` of the crown gear: origin at the common cone apex ``O``, ``k_C`` along
the crown gear's axis, pitch plane ``z_C = 0``. The tooth line of the crown gear is the
logarithmic spiral of paper 001, Eq. 2, ``rho = R_m exp(theta cot(beta))`` at the polar
angle ``gamma = theta - Delta_theta``. We parametrise it by the cone distance ``rho``
itself (``theta = tan(beta) ln(rho / R_m)``), which also covers ``beta = 0`` (a straight
radial tooth line) and makes the face width an interval of ``rho``. Paper 001 writes
``e^{theta cot(beta)}`` with the scale absorbed; here ``theta = 0`` is the mean point
``rho = R_m``.

The crown gear's tooth surface (paper 001, Eqs. 3-4) sweeps the basic profile along the
spiral: the normal section at the spiral point ``P(rho)`` has the axes
``i_n -> k_C`` (tooth height), ``j_n -> j = t x k_C`` (across the tooth) and
``k_n -> t``, the spiral's unit tangent at the angle ``phi = gamma + beta``:

``r_C = P(rho) + y(u) j(rho) + x(u) k_C``
``= [y sin(phi) + rho cos(gamma), -y cos(phi) + rho sin(gamma), x]``

which is paper 001's Eq. 4 with ``y = y_n -+ s/2`` and ``rho = e^{theta cot(beta)}``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .profiles import BasicProfile, profile_error

__all__ = ["CrownGear", "CrownSurface", "LogSpiral"]

Array = NDArray[np.float64]


def _check(field: str, ok: bool, rule: str, value: object) -> None:
    """Raise :func:`profiles.profile_error`'s :class:`ProfileError` unless ``ok``."""
    if not ok:
        raise profile_error(field, rule, value)


@dataclass(frozen=True)
class LogSpiral:
    """Logarithmic spiral ``rho = R_m exp(theta cot(beta))`` in the plane ``z = 0``.

    Parameters
    ----------
    spiral_angle : float
        ``beta`` (rad), the constant angle between the tangent and the radius vector;
        positive: the spiral turns counter-clockwise (about ``+z``) as ``rho`` grows.
        ``|beta| < 80 deg``.
    mean_radius : float
        ``R_m`` (m): the cone distance of the mean point, where ``theta = 0``.
    delta_theta : float
        ``Delta_theta`` (rad), paper 001's initial rotation: the mean point lies at the
        polar angle ``-Delta_theta``.
    """

    spiral_angle: float
    mean_radius: float
    delta_theta: float = 0.0

    def __post_init__(self) -> None:
        b = self.spiral_angle
        _check("spiral_angle", abs(b) < math.radians(80), "|beta| must be < 80 deg", b)
        _check("mean_radius", self.mean_radius > 0, "must be > 0 (m)", self.mean_radius)

    def theta(self, rho: ArrayLike) -> Array:
        """Paper 001's spiral parameter ``theta = tan(beta) ln(rho / R_m)`` (rad)."""
        return math.tan(self.spiral_angle) * np.log(np.asarray(rho, float) / self.mean_radius)

    def polar_angle(self, rho: ArrayLike) -> Array:
        """``gamma = theta - Delta_theta`` (rad), the polar angle of ``P(rho)``."""
        return self.theta(rho) - self.delta_theta

    def point(self, rho: ArrayLike) -> Array:
        """``P(rho)`` (m), shape (..., 3), paper 001's Eq. 2 without the thickness offset."""
        r = np.asarray(rho, float)
        g = self.polar_angle(r)
        return np.stack([r * np.cos(g), r * np.sin(g), np.zeros_like(g)], axis=-1)

    def tangent(self, rho: ArrayLike) -> Array:
        """Unit tangent ``t = (cos(phi), sin(phi), 0)``, ``phi = gamma + beta``."""
        phi = self.polar_angle(rho) + self.spiral_angle
        return np.stack([np.cos(phi), np.sin(phi), np.zeros_like(phi)], axis=-1)

    def derivative(self, rho: ArrayLike) -> Array:
        """``dP/drho = t / cos(beta)`` (dimensionless)."""
        return self.tangent(rho) / math.cos(self.spiral_angle)


@dataclass(frozen=True)
class CrownSurface:
    """Points of a crown gear flank on a ``(u, rho)`` grid, in ``S_C``.

    Attributes
    ----------
    points : ndarray, shape (nu, nrho, 3)
        ``r_C`` (m), paper 001 Eq. 4.
    normals : ndarray, shape (nu, nrho, 3)
        Unit normals pointing out of the basic tooth ``T``.
    u, rho : ndarray
        Profile parameter (-) and spiral cone distance (m) grids, shape (nu,), (nrho,).
    flank : int
        ``+1`` or ``-1``.
    tooth : int
        Index of the crown tooth (rotated by ``tooth * 2 pi / z_C``).
    """

    points: Array
    normals: Array
    u: Array
    rho: Array
    flank: int
    tooth: int


@dataclass(frozen=True)
class CrownGear:
    """The hypothetical crown gear of paper 001 (pitch plane, log-spiral tooth lines).

    Parameters
    ----------
    profile : BasicProfile
        Normal basic tooth profile (its ``x`` along ``k_C``).
    spiral_angle : float
        ``beta_m`` (rad) of the tooth centreline (a log spiral: the same everywhere).
    mean_cone_distance : float
        ``R_m`` (m).
    face_width : float
        ``b`` (m); the teeth span ``R_m - b/2 <= rho <= R_m + b/2``.
    teeth : float
        ``z_C`` of the crown gear (need not be an integer: ``z / sin(delta)``).
    delta_theta : float
        Paper 001's ``Delta_theta`` (rad).
    """

    profile: BasicProfile
    spiral_angle: float
    mean_cone_distance: float
    face_width: float
    teeth: float
    delta_theta: float = 0.0

    def __post_init__(self) -> None:
        R, b = self.mean_cone_distance, self.face_width
        _check("mean_cone_distance", R > 0, "must be > 0 (m)", R)
        _check("face_width", 0 < b < R, "must lie in (0, mean cone distance) (m)", b)
        _check("teeth", self.teeth >= 2, "crown gear teeth must be >= 2", self.teeth)
        _ = self.spiral  # validates the angle

    @classmethod
    def for_gear(
        cls,
        profile: BasicProfile,
        teeth: int,
        cone_angle: float,
        spiral_angle: float,
        face_width: float,
        delta_theta: float = 0.0,
    ) -> CrownGear:
        """Crown gear generating a bevel gear of ``teeth`` and pitch ``cone_angle`` (rad).

        ``z_C = z / sin(delta)`` and ``R_m = z_C m_n / (2 cos(beta))``, so that the normal
        pitch at the mean point is ``pi m_n`` of the profile.
        """
        _check("cone_angle", 0 < cone_angle < math.pi / 2, "must lie in (0, 90) deg", cone_angle)
        _check("teeth", teeth >= 1, "must be >= 1", teeth)
        _check(
            "spiral_angle",
            abs(spiral_angle) < math.radians(80),
            "|beta| must be < 80 deg",
            spiral_angle,
        )
        zc = teeth / math.sin(cone_angle)
        R = zc * profile.module / (2 * math.cos(spiral_angle))
        return cls(profile, spiral_angle, R, face_width, zc, delta_theta)

    @property
    def spiral(self) -> LogSpiral:
        """The tooth centreline of tooth 0."""
        return LogSpiral(self.spiral_angle, self.mean_cone_distance, self.delta_theta)

    @property
    def angular_pitch(self) -> float:
        """``2 pi / z_C`` (rad)."""
        return 2 * math.pi / self.teeth

    @property
    def rho_range(self) -> tuple[float, float]:
        """Inner and outer cone distance of the face (m)."""
        h = 0.5 * self.face_width
        return self.mean_cone_distance - h, self.mean_cone_distance + h

    def surface(
        self, u: ArrayLike, rho: ArrayLike, flank: int = 1, tooth: float = 0
    ) -> CrownSurface:
        """Crown gear flank (paper 001 Eq. 4) on the grid ``u`` x ``rho``.

        Parameters
        ----------
        u : array_like, shape (nu,)
            Profile parameters in ``[0, 1]``.
        rho : array_like, shape (nrho,)
            Cone distances of the spiral points (m).
        flank : {+1, -1}
        tooth : float
            Crown tooth index; tooth ``k`` is tooth 0 turned by ``k 2 pi / z_C`` about
            ``k_C`` (half-integers give tooth-space centrelines).
        """
        pts, nrm = self.points(
            np.asarray(u, float)[:, None], np.asarray(rho, float)[None, :], flank, tooth
        )
        return CrownSurface(
            pts, nrm, np.asarray(u, float), np.asarray(rho, float), flank, int(tooth)
        )

    def points(
        self, u: ArrayLike, rho: ArrayLike, flank: int = 1, tooth: float = 0
    ) -> tuple[Array, Array]:
        """``(r_C, n_C)`` at broadcast ``u``, ``rho`` (paper 001 Eq. 4), shapes (..., 3)."""
        p = self.profile.evaluate(u, flank)
        r = np.asarray(rho, float)
        gamma = self.spiral.polar_angle(r) + tooth * self.angular_pitch
        phi = gamma + self.spiral_angle
        sp, cp = np.sin(phi), np.cos(phi)
        # j = (sin phi, -cos phi, 0), k = (0, 0, 1)
        x = p.y * sp + r * np.cos(gamma)
        y = -p.y * cp + r * np.sin(gamma)
        z = np.broadcast_to(p.x, x.shape)
        nx = p.ny * sp
        ny = -p.ny * cp
        nz = np.broadcast_to(p.nx, nx.shape)
        return np.stack([x, y, z], axis=-1), np.stack([nx, ny, nz], axis=-1)

    def pitch_curve(self, rho: ArrayLike, flank: int = 1, tooth: float = 0) -> Array:
        """Flank points on the pitch plane (profile's pitch point) at ``rho`` (m), (..., 3)."""
        u0 = self.profile.pitch_parameter()
        return self.points(np.full(np.shape(rho), u0), rho, flank, tooth)[0]
