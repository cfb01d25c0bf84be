"""Hertz contact: closed forms for elliptical, circular and line contacts, and the stresses
on the axis under the centre of the contact (oracles for the discretised contact of
:mod:`reducerlab.contact.halfspace`).

Sources (Johnson, *Contact Mechanics*, Cambridge 1985):

* Elliptical pressure ``p = p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` and its surface
  displacement ``u = (L - M x^2 - N y^2)/(pi E*)`` inside the ellipse (§3.7; ``L, M, N``
  in complete elliptic integrals of the eccentricity ``e``, ``b/a = sqrt(1 - e^2)``
  for ``a >= b``); matching the gap ``h = A x^2 + B y^2`` gives the Hertz solution (§4.2):
  ``B/A = ((a/b)^2 E(e) - K(e)) / (K(e) - E(e))``, ``a^3 = 3 F (K - E)/(2 pi e^2 A E*)``,
  ``p0 = 3F/(2 pi a b)``, ``delta = 3 F K(e)/(2 pi a E*)``.
* Circle (``A = B = 1/(2R)``): ``a = (3FR/(4E*))^(1/3)``, ``p0 = 3F/(2 pi a^2)``,
  ``delta = a^2/R`` (§4.2); the stresses on the axis (§3.4, Eq. 3.45).
* Line contact, half-width ``b = sqrt(4 w R/(pi E*))``, ``p0 = 2 w/(pi b)`` (§4.3), and the
  stresses under its centre (McEwen 1949; Johnson §4.3).

The elliptic integrals are evaluated in Carlson's symmetric form (``K = R_F(0, k^2, 1)``,
``(K - E)/e^2 = R_D(0, k^2, 1)/3`` with ``k = b/a``), which has no cancellation at small
eccentricity; see Carlson, Numer. Algorithms 10 (1995) 13-26 and DLMF §19.25.
Everything is SI; stresses are positive in tension, depths ``z`` positive into the body.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq, minimize_scalar
from scipy.special import elliprd, elliprf

from ..errors import ReducerlabError

__all__ = [
    "HertzContact",
    "HertzLine",
    "axis_stresses",
    "hertz_crossed_cylinders",
    "hertz_elliptic",
    "hertz_line",
    "hertz_sphere_plane",
    "max_axis_von_mises",
]

Array = NDArray[np.float64]


def _positive(name: str, value: float, unit: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise ReducerlabError(f"{name} must be a number ({unit}), got {value!r}") from exc
    if not (math.isfinite(v) and v > 0):
        raise ReducerlabError(f"{name} must be finite and > 0 {unit}, got {value!r}")
    return v


@dataclass(frozen=True)
class HertzContact:
    """Hertz solution of a point (elliptical) contact.

    Attributes
    ----------
    force : float
        Normal force ``F`` (N).
    A, B : float
        Relative curvature constants of the gap ``h = A x^2 + B y^2`` (1/m).
    E_star : float
        Combined modulus ``E*`` (Pa).
    a, b : float
        Semi-axes of the contact ellipse along x and y (m).
    p0 : float
        Peak pressure ``3F/(2 pi a b)`` (Pa).
    delta : float
        Approach of distant points of the two bodies (m).
    """

    force: float
    A: float
    B: float
    E_star: float
    a: float
    b: float
    p0: float
    delta: float

    @property
    def eccentricity(self) -> float:
        """``e = sqrt(1 - (minor/major)^2)`` of the contact ellipse (-)."""
        lo, hi = sorted((self.a, self.b))
        return math.sqrt(max(0.0, 1.0 - (lo / hi) ** 2))

    @property
    def mean_pressure(self) -> float:
        """``F/(pi a b) = 2 p0/3`` (Pa)."""
        return self.force / (math.pi * self.a * self.b)

    def pressure(self, x: ArrayLike, y: ArrayLike) -> Array:
        """Contact pressure ``p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` (Pa), zero outside (x, y in m)."""
        x = np.asarray(x, dtype=float)
        y = np.asarray(y, dtype=float)
        q = 1.0 - (x / self.a) ** 2 - (y / self.b) ** 2
        return self.p0 * np.sqrt(np.maximum(q, 0.0))


@dataclass(frozen=True)
class HertzLine:
    """Hertz solution of a line contact (plane strain): the contact strip ``|y| <= b``
    along the x axis (the limit ``a -> inf`` of :class:`HertzContact`).

    Attributes
    ----------
    force_per_length : float
        Normal load per unit length of the line ``w`` (N/m).
    R : float
        Effective radius ``1/R = 1/R1 + 1/R2`` (m).
    E_star : float
        Combined modulus (Pa).
    b : float
        Half-width ``sqrt(4 w R/(pi E*))`` (m).
    p0 : float
        Peak pressure ``2 w/(pi b)`` (Pa).
    """

    force_per_length: float
    R: float
    E_star: float
    b: float
    p0: float

    def pressure(self, y: ArrayLike) -> Array:
        """Contact pressure ``p0 sqrt(1 - y^2/b^2)`` (Pa), zero outside (y in m, across)."""
        y = np.asarray(y, dtype=float)
        return self.p0 * np.sqrt(np.maximum(1.0 - (y / self.b) ** 2, 0.0))


def _kd(k2: float) -> tuple[float, float]:
    """``K(e)`` and ``D(e) = (K - E)/e^2`` for ``k2 = 1 - e^2 = (minor/major)^2``
    (DLMF 19.25.1: ``K = R_F(0, k2, 1)``, ``(K - E)/e^2 = R_D(0, k2, 1)/3``)."""
    return float(elliprf(0.0, k2, 1.0)), float(elliprd(0.0, k2, 1.0)) / 3.0


def _ratio(k2: float) -> float:
    """Curvature ratio ``B/A >= 1`` that gives the axis ratio ``k2 = (b/a)^2`` (``a``
    major): Johnson's ``((a/b)^2 E - K)/(K - E)`` rewritten without cancellation as
    ``(K - D)/(k2 D)`` (``K - D = int cos^2/sqrt(1 - e^2 sin^2) > 0``)."""
    K, D = _kd(k2)
    return (K - D) / (k2 * D)


def hertz_elliptic(force: float, A: float, B: float, E_star: float) -> HertzContact:
    """Hertz contact of two bodies with the initial gap ``h = A x^2 + B y^2``.

    The pressure ``p0 sqrt(1 - x^2/a^2 - y^2/b^2)`` displaces the surfaces by
    ``(L - M x^2 - N y^2)/(pi E*)`` inside the ellipse (Johnson 1985 §3.7); the contact
    condition ``u = delta - A x^2 - B y^2`` gives, with ``a`` the major semi-axis (along
    the smaller curvature), ``e^2 = 1 - b^2/a^2`` and the complete elliptic integrals
    ``K(e), E(e)`` (Johnson 1985 §4.2):

    * ``B/A = ((a/b)^2 E - K)/(K - E)``, solved for ``e`` with Brent's method,
    * ``a^3 = 3 F (K - E) / (2 pi e^2 A E*)``, ``b = a sqrt(1 - e^2)``,
    * ``p0 = 3 F/(2 pi a b)``, ``delta = 3 F K/(2 pi a E*)``.

    For ``A = B`` these reduce to the circle of :func:`hertz_sphere_plane`.

    Parameters
    ----------
    force : float
        Normal force ``F`` (N), > 0.
    A, B : float
        Relative curvature constants along x and y (1/m), > 0, in any order.
    E_star : float
        Combined modulus (Pa), > 0.

    Returns
    -------
    HertzContact
        With the semi-axis ``a`` along x and ``b`` along y.
    """
    F = _positive("force", force, "N")
    A = _positive("A", A, "1/m")
    B = _positive("B", B, "1/m")
    E = _positive("E_star", E_star, "Pa")
    lo, hi = min(A, B), max(A, B)
    ratio = hi / lo
    if ratio == 1.0:
        k2 = 1.0
    else:
        y_lo = 0.5 / ratio
        while _ratio(y_lo) < ratio:
            y_lo *= 0.01
        t = brentq(
            lambda s: _ratio(math.exp(s)) - ratio, math.log(y_lo), 0.0, xtol=1e-15, rtol=1e-15
        )
        k2 = math.exp(t)
    K, D = _kd(k2)
    major = (3.0 * F * D / (2.0 * math.pi * lo * E)) ** (1.0 / 3.0)
    minor = major * math.sqrt(k2)
    a, b = (major, minor) if A <= B else (minor, major)
    p0 = 3.0 * F / (2.0 * math.pi * a * b)
    delta = 3.0 * F * K / (2.0 * math.pi * major * E)
    return HertzContact(F, A, B, E, a, b, p0, delta)


def hertz_sphere_plane(force: float, radius: float, E_star: float) -> HertzContact:
    """Sphere of radius ``R`` on a plane (or two spheres with ``1/R = 1/R1 + 1/R2``).

    ``a = (3FR/(4E*))^(1/3)``, ``p0 = 3F/(2 pi a^2)``, ``delta = a^2/R`` (Johnson 1985
    §4.2); computed as :func:`hertz_elliptic` with ``A = B = 1/(2R)``.

    Parameters
    ----------
    force : float
        Normal force (N).
    radius : float
        Sphere (relative) radius ``R`` (m).
    E_star : float
        Combined modulus (Pa).
    """
    R = _positive("radius", radius, "m")
    return hertz_elliptic(force, 0.5 / R, 0.5 / R, E_star)


def hertz_crossed_cylinders(force: float, R1: float, R2: float, E_star: float) -> HertzContact:
    """Two cylinders with axes crossed at 90 degrees: cylinder 1 (radius ``R1``) along
    y, cylinder 2 (radius ``R2``) along x, so ``A = 1/(2 R1)``, ``B = 1/(2 R2)``
    (Johnson 1985 §4.1-4.2); see :func:`hertz_elliptic`.

    Parameters
    ----------
    force : float
        Normal force (N).
    R1, R2 : float
        Cylinder radii (m).
    E_star : float
        Combined modulus (Pa).
    """
    R1 = _positive("R1", R1, "m")
    R2 = _positive("R2", R2, "m")
    return hertz_elliptic(force, 0.5 / R1, 0.5 / R2, E_star)


def hertz_line(force_per_length: float, R_eff: float, E_star: float) -> HertzLine:
    """Line contact of two parallel cylinders (Johnson 1985 §4.3).

    ``b = sqrt(4 w R/(pi E*))``, ``p0 = 2 w/(pi b)``.

    Parameters
    ----------
    force_per_length : float
        Load per unit length ``w`` (N/m).
    R_eff : float
        Effective radius ``1/R = 1/R1 + 1/R2`` (m).
    E_star : float
        Combined modulus (Pa).
    """
    w = _positive("force_per_length", force_per_length, "N/m")
    R = _positive("R_eff", R_eff, "m")
    E = _positive("E_star", E_star, "Pa")
    b = math.sqrt(4.0 * w * R / (math.pi * E))
    return HertzLine(w, R, E, b, 2.0 * w / (math.pi * b))


def _depths(z: ArrayLike) -> Array:
    try:
        z = np.asarray(z, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ReducerlabError(f"z must be numeric depths (m), got {z!r:.80}") from exc
    if not np.all(np.isfinite(z)) or np.any(z < 0):
        raise ReducerlabError("z must be finite depths >= 0 m (positive into the body)")
    return z


def _nu(nu: float) -> float:
    try:
        v = float(nu)
    except (TypeError, ValueError) as exc:
        raise ReducerlabError(f"nu must be a number, got {nu!r}") from exc
    if not -1.0 < v <= 0.5:
        raise ReducerlabError(f"Poisson's ratio nu must be in (-1, 0.5], got {nu!r}")
    return v


def _circle_axis(a: float, p0: float, z: Array, nu: float) -> tuple[Array, Array, Array]:
    """Johnson (1985) §3.4, Eq. 3.45: ``sigma_r = sigma_theta = p0 [-(1 + nu)(1 - (z/a)
    atan(a/z)) + (1/2)(1 + z^2/a^2)^-1]``, ``sigma_z = -p0 (1 + z^2/a^2)^-1``."""
    s = z / a
    with np.errstate(divide="ignore"):
        at = np.where(s > 0, s * np.arctan(1.0 / np.where(s > 0, s, 1.0)), 0.0)
    sz = -p0 / (1.0 + s * s)
    sr = p0 * (-(1.0 + nu) * (1.0 - at)) - 0.5 * sz
    return sr, sr.copy(), sz


def _ellipse_axis(a: float, b: float, p0: float, z: Array, nu: float) -> tuple[Array, Array, Array]:
    """Principal stresses on the axis under an elliptical Hertz pressure.

    From Love's potentials of the normal load, ``psi = int int p/rho`` and
    ``psi1 = int int p ln(rho + z)`` (Johnson 1985 §3.2):
    ``sigma_x = [2 nu psi_z - z psi_xx - (1 - 2nu) psi1_xx]/(2 pi)``,
    ``sigma_z = [psi_z - z psi_zz]/(2 pi)``, and the potential of the ellipsoidal
    pressure (Johnson 1985 §3.7) ``psi = (pi a b p0/2) int_lam^inf (1 - x^2/(a^2 + w)
    - y^2/(b^2 + w) - z^2/w) dw/sqrt((a^2 + w)(b^2 + w) w)``, ``lam = z^2`` on the axis.
    Differentiating under the integral (``psi1_xx = -int_z^inf psi_xx dz``) and writing the
    integrals in Carlson's form (``w = z^2 + t``; DLMF 19.16.5):

    ``sigma_z = -p0 a b / sqrt((a^2 + z^2)(b^2 + z^2))``,
    ``sigma_x = (a b p0/2) [-2 nu z J0 + z Jx - (1 - 2 nu) Ix]`` (y alike),
    ``J0 = 2/3 R_D(a^2 + z^2, b^2 + z^2, z^2)``, ``Jx = 2/3 R_D(b^2 + z^2, z^2, a^2 + z^2)``,
    ``Ix = 2/(sqrt(a^2 + z^2)(sqrt(a^2 + z^2) + sqrt(b^2 + z^2))) - z Jx``.

    At ``z = 0``: ``sigma_x = -p0 [2 nu + (1 - 2 nu) b/(a + b)]`` (Johnson 1985 §3.7). The
    result equals the elliptic-integral closed forms of Thomas & Hoersch (1930) and
    Sackfield & Hills (1983, J. Strain Anal. 18); it is checked against a numerical
    integration of the Boussinesq point-force stresses over the pressure in the tests.
    """
    a2, b2 = a * a, b * b
    z2 = z * z
    Ap, Bp = a2 + z2, b2 + z2
    sA, sB = np.sqrt(Ap), np.sqrt(Bp)
    sz = -p0 * a * b / (sA * sB)
    pos = z > 0
    zs = np.where(pos, z, 1.0)
    z2s = zs * zs
    J0 = (2.0 / 3.0) * elliprd(a2 + z2s, b2 + z2s, z2s)
    Jx = (2.0 / 3.0) * elliprd(b2 + z2s, z2s, a2 + z2s)
    Jy = (2.0 / 3.0) * elliprd(a2 + z2s, z2s, b2 + z2s)
    sAs, sBs = np.sqrt(a2 + z2s), np.sqrt(b2 + z2s)
    Ix = 2.0 / (sAs * (sAs + sBs)) - zs * Jx
    Iy = 2.0 / (sBs * (sAs + sBs)) - zs * Jy
    k = 0.5 * a * b * p0
    c = 1.0 - 2.0 * nu
    sx = k * (-2.0 * nu * zs * J0 + zs * Jx - c * Ix)
    sy = k * (-2.0 * nu * zs * J0 + zs * Jy - c * Iy)
    sx = np.where(pos, sx, -p0 * (2.0 * nu + c * b / (a + b)))
    sy = np.where(pos, sy, -p0 * (2.0 * nu + c * a / (a + b)))
    return sx, sy, sz


def _line_axis(b: float, p0: float, z: Array, nu: float) -> tuple[Array, Array, Array]:
    """McEwen (1949), Johnson (1985) §4.3: ``sigma_y = -(p0/b) [(b^2 + 2 z^2)/sqrt(b^2 +
    z^2) - 2 z]`` (across), ``sigma_z = -p0 b/sqrt(b^2 + z^2)``, plane strain along the line
    ``sigma_x = nu (sigma_y + sigma_z)``."""
    r = np.sqrt(b * b + z * z)
    sy = -(p0 / b) * ((b * b + 2.0 * z * z) / r - 2.0 * z)
    sz = -p0 * b / r
    return nu * (sy + sz), sy, sz


def axis_stresses(
    contact: HertzContact | HertzLine, z: ArrayLike, nu: float
) -> tuple[Array, Array, Array]:
    """Principal stresses ``(sigma_x, sigma_y, sigma_z)`` (Pa) on the z axis under the
    centre of a Hertz contact, at depths ``z`` (m, >= 0).

    * Circle (``a == b``): Johnson (1985) §3.4, Eq. 3.45 (closed form).
    * Ellipse: the exact closed form from Love's potentials of the ellipsoidal pressure
      (Johnson 1985 §3.2, §3.7) in Carlson's elliptic integrals, equivalent to Thomas &
      Hoersch (1930) / Sackfield & Hills (1983); see :func:`_ellipse_axis`.
    * Line (:class:`HertzLine`, strip ``|y| <= b``): McEwen (1949), plane strain.

    Parameters
    ----------
    contact : HertzContact or HertzLine
    z : array_like
        Depths (m), >= 0.
    nu : float
        Poisson's ratio of the body, in (-1, 0.5].

    Returns
    -------
    tuple of ndarray
        ``sigma_x, sigma_y, sigma_z`` (Pa, compression negative), shaped like ``z``.
    """
    z = _depths(z)
    nu = _nu(nu)
    if isinstance(contact, HertzLine):
        return _line_axis(contact.b, contact.p0, z, nu)
    if not isinstance(contact, HertzContact):
        raise ReducerlabError(
            f"contact must be a HertzContact or HertzLine, got {type(contact).__name__}"
        )
    if contact.a == contact.b:
        return _circle_axis(contact.a, contact.p0, z, nu)
    return _ellipse_axis(contact.a, contact.b, contact.p0, z, nu)


def max_axis_von_mises(contact: HertzContact | HertzLine, nu: float) -> tuple[float, float]:
    """Largest von Mises stress on the axis under the centre of a Hertz contact.

    A scan of 201 depths over ``[0, 3 c]`` (``c`` the smaller semi-axis or the
    half-width), then Brent's bounded minimisation between the neighbours of the best
    point (to ``1e-9 c``). With ``nu = 0.3``: circle ``0.62 p0`` at ``0.48 a`` (twice
    Johnson's maximum shear ``tau1 = 0.31 p0`` at ``0.48 a``, 1985 §3.4, since
    ``sigma_x = sigma_y`` there); line contact ``0.56 p0`` at ``0.70 b`` (Tresca's
    ``tau1 = 0.30 p0`` lies at ``0.78 b``, Johnson 1985 §4.3).

    Parameters
    ----------
    contact : HertzContact or HertzLine
    nu : float
        Poisson's ratio, in (-1, 0.5].

    Returns
    -------
    value : float
        Maximum von Mises stress (Pa).
    depth : float
        Its depth (m).
    """
    nu = _nu(nu)
    c = contact.b if isinstance(contact, HertzLine) else min(contact.a, contact.b)

    def vm(z: ArrayLike) -> Array:
        sx, sy, sz = axis_stresses(contact, z, nu)
        return np.sqrt(0.5 * ((sx - sy) ** 2 + (sy - sz) ** 2 + (sz - sx) ** 2))

    zs = np.linspace(0.0, 3.0 * c, 201)
    v = vm(zs)
    k = int(np.argmax(v))
    lo, hi = zs[max(k - 1, 0)], zs[min(k + 1, zs.size - 1)]
    res = minimize_scalar(
        lambda t: -float(vm(np.array(t))), bounds=(lo, hi), method="bounded",
        options={"xatol": 1e-9 * c},
    )  # fmt: skip
    if -res.fun >= v[k]:
        return -float(res.fun), float(res.x)
    return float(v[k]), float(zs[k])
