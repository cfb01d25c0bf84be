"""Load sharing among the balls of a cycloid ball track (issue 30; paper 003).

Geometry (paper 003 Fig. 1-2; derivation in ``docs/assumptions.md``, "Paper 003"): the
centre disc's epitrochoid groove (``z_c`` lobes) and the planetary disc's hypotrochoid
(``z_p = z_c + 2`` lobes), trochoids of offset ``d = e/2`` about a base circle of radius
``R_b = Z e / (2 K)`` (``K`` the short-width coefficient, ``Z = z_c + 1`` balls), pass
through the ``Z`` ball centres *tangent* to each other. In the frame of the eccentric,
with the centre disc's axis ``O`` at the origin, the line of centres along ``+y``
(paper 003's ``y``; the planetary disc's centre at ``e y``), the balls lie evenly on the
circle of radius ``R_b`` about the midpoint ``M = (e/2) y``, at the angles ``psi_i =
psi_0 + 2 pi i / Z`` measured at ``M`` from the direction of the pitch point ``P = -r_2
y`` (``r_2 = z_c e / 2``). By the law of gearing every contact normal passes through
``P``: the normal of ball ``i`` makes the angle ``theta_i`` with the line of centres,

``sin(theta_i) = sin(psi_i) / sqrt(1 + K^2 - 2 K cos(psi_i))``,
``cos(theta_i) = (K - cos(psi_i)) / sqrt(1 + K^2 - 2 K cos(psi_i))``,

and its lever arm about the centre disc's axis is ``r_2 sin(theta_i)`` (paper 003 Eq. 1
sums ``sin^2(theta_i)``). As the input turns by ``phi`` the ball set moves by
``d psi_0 = -(z_p / Z) d phi`` relative to the line of centres (one ball pitch per
``1/z_p`` input revolution: the ball-engagement period).

Contact: each ball lies in both grooves, whose sections (gothic arches of radius ``r_g
= 2 f r_b``, conformity ``f``) touch it at the contact angle ``beta`` out of the disc
plane (paper 003's half angle of the groove), on either side: a ball is squeezed along
its normal line between the centre disc's groove wall on one side and the planetary
disc's on the other. Line ``+`` (centre disc's wall on the pitch point's side of the
ball, ``-n_i``) carries when the centre disc moves along ``+n_i`` relative to the
planetary disc, line ``-`` the other way. Each line is two Hertz contacts in series
(Johnson 1985 §4.2, :func:`~reducerlab.contact.hertz.hertz_elliptic`), ``F = K_h
delta^(3/2)``, ``K_h = (K_2^(-2/3) + K_3^(-2/3))^(-3/2)``; a contact's relative
curvatures are ``1/r_b - 1/r_g`` across the groove and ``1/r_b + k_g`` along it, where
the groove wall's lengthwise curvature ``k_g = kappa_w cos(beta) / (1 - kappa_w r_b
cos(beta))`` follows from the ball-centre path's curvature ``kappa_w`` toward the wall
(the trochoids' curvature at the ball, in closed form:

``kappa_2 = K (1 + Z K^2 - (Z + 1) K cos psi) / (Z d D^(3/2))`` (centre disc),
``kappa_3 = K (1 - Z K^2 + (Z - 1) K cos psi) / (Z d D^(3/2))`` (planetary disc),
``D = 1 + K^2 - 2 K cos psi``, ``d = e/2``; line ``+``: ``kappa_w = kappa_2`` and
``-kappa_3``, line ``-``: ``-kappa_2`` and ``kappa_3``). Where ``kappa_w r_b
cos(beta) >= 1`` the wall on the inside of the path's turn is undercut (the groove cut
along the trochoid removes it): that line of that ball carries nothing, and
:meth:`BallTrack.undercut` reports it (for ``K`` near 1 the trochoids turn within a
fraction of a millimetre next to the pitch point).

Load sharing: a small relative displacement of the centre disc against the planetary
disc at the pitch point, ``s`` along ``x`` (paper 003's ``delta_23 = x2 - x3 + u2 -
u3``: rotations about ``P`` move no ball along its normal) and ``y`` along the line of
centres, approaches the lines of ball ``i`` by

``delta_i(+-) = +- cos(beta) (sin(theta_i) s + cos(theta_i) y) - c_i``

(``c_i``: the ball's clearance along its normal, negative for a preload: an interference
that loads both lines). The torque ``T`` on the centre disc is the generalised force
``T / r_2`` on ``s``; ``y`` is free (the planetary disc floats on the eccentric
bearing: no net force along the line of centres) or held. The equilibrium minimises
the convex energy ``sum (2/5) K_h <delta>^(5/2) - (T / r_2) s`` over the lines
(Newton's method with a backtracking line search): the loaded balls, their forces and
the tangent stiffness ``J = sum 1.5 K_h delta^(1/2) g g^T`` (``g = +- cos(beta) (sin
theta_i, cos theta_i)``), condensed on ``s`` when ``y`` is free: the translational
stiffness of paper 003's ``K_mx`` (N/m) and the torsional stiffness ``r_2^2 K_mx``
about the centre disc's axis (N m/rad).

Paper 003 Eq. 1 is the preloaded, zero-clearance limit of straight grooves
(``groove_curvature=False``, one ``K_h`` for every line): every line loaded to the same
approach ``delta_0``, ``y`` held, the tangent stiffness is ``k_m sum sin^2(theta_i)``
with ``k_m = 3 K_h delta_0^(1/2) cos^2(beta)`` (two lines a ball), whose mean over a
ball pitch is ``k_m Z / 2`` (Eq. 10; the paper divides by its deformation coefficient
``a``, a normalisation of ``delta_max`` that the contact model has no counterpart for).

Units: SI (m, N, N m, rad).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError
from .hertz import hertz_elliptic

__all__ = ["BallLoads", "BallTrack", "ball_loads", "track_stiffness"]

Array = NDArray[np.float64]


def _positive(field_name: str, value: object, unit: str) -> float:
    if isinstance(value, bool):
        raise ReducerlabError(f"{field_name}: must be a number > 0 ({unit}); got {value!r}")
    try:
        v = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ReducerlabError(
            f"{field_name}: must be a number > 0 ({unit}); got {value!r}"
        ) from None
    if not (math.isfinite(v) and v > 0):
        raise ReducerlabError(f"{field_name}: must be a number > 0 ({unit}); got {value!r}")
    return v


@dataclass(frozen=True)
class BallTrack:
    """Ball track of a cycloid ball transmission (paper 003).

    Parameters
    ----------
    centre_lobes : int
        Lobes ``z_c`` of the centre disc's epitrochoid (``Z = z_c + 1`` balls, the
        planetary disc ``z_c + 2`` lobes).
    eccentricity : float
        ``e`` (m).
    short_width : float
        Short-width coefficient ``K = Z e / (2 R_b)``, in (0, 1).
    ball_radius : float
        ``r_b`` (m).
    conformity : float
        Groove section radius over ball diameter, ``f = r_g / (2 r_b)``, in (0.5, 1).
    contact_angle : float
        ``beta`` (rad), the contact normal's angle out of the disc plane, in [0, pi/2).
    youngs_modulus, poisson_ratio : float
        Of balls and discs (Pa, -).
    clearance : float or array_like
        Clearance ``c_i`` (m) of each ball along its normal (one value for all);
        negative: an interference that preloads both of its lines.
    groove_curvature : bool
        Take the grooves' lengthwise curvature into the Hertz contacts (default); False:
        straight grooves, one ``K_h`` for every line (paper 003's uniform ``k_m``).
    """

    centre_lobes: int
    eccentricity: float
    short_width: float
    ball_radius: float
    conformity: float
    contact_angle: float
    youngs_modulus: float = 206e9
    poisson_ratio: float = 0.3
    clearance: ArrayLike = 0.0
    groove_curvature: bool = True
    _c: Array = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        z = self.centre_lobes
        if isinstance(z, bool) or not isinstance(z, (int, np.integer)) or z < 2:
            raise ReducerlabError(f"centre_lobes: must be an integer >= 2; got {z!r}")
        _positive("eccentricity", self.eccentricity, "m")
        _positive("ball_radius", self.ball_radius, "m")
        k = _positive("short_width", self.short_width, "-")
        if not k < 1:
            raise ReducerlabError(f"short_width: must lie in (0, 1); got {k!r}")
        f = _positive("conformity", self.conformity, "-")
        if not 0.5 < f < 1:
            raise ReducerlabError(
                f"conformity: groove radius over ball diameter must lie in (0.5, 1); got {f!r}"
            )
        b = float(self.contact_angle)
        if not (math.isfinite(b) and 0 <= b < 0.5 * math.pi):
            raise ReducerlabError(
                f"contact_angle: must lie in [0, 90) deg; got {math.degrees(b):g} deg"
            )
        _positive("youngs_modulus", self.youngs_modulus, "Pa")
        nu = float(self.poisson_ratio)
        if not -1 < nu < 0.5:
            raise ReducerlabError(f"poisson_ratio: must lie in (-1, 0.5); got {nu!r}")
        try:
            c = np.broadcast_to(np.asarray(self.clearance, dtype=float), (self.balls,))
        except ValueError:
            raise ReducerlabError(
                f"clearance: one value or one per ball ({self.balls}); got shape "
                f"{np.shape(self.clearance)}"
            ) from None
        if not np.all(np.isfinite(c)):
            raise ReducerlabError("clearance: must be finite (m)")
        object.__setattr__(self, "_c", np.array(c))

    @property
    def balls(self) -> int:
        """``Z = z_c + 1``."""
        return int(self.centre_lobes) + 1

    @property
    def pitch_radius(self) -> float:
        """Centre disc's pitch radius ``r_2 = z_c e / 2`` (m), the distance of the pitch
        point from its axis."""
        return self.centre_lobes * self.eccentricity / 2

    @property
    def ball_circle_radius(self) -> float:
        """``R_b = Z e / (2 K)`` (m), the radius of the circle of ball centres."""
        return self.balls * self.eccentricity / (2 * self.short_width)

    @property
    def clearances(self) -> Array:
        """``c_i`` (m), one per ball."""
        return self._c.copy()

    def directions(self, phase: float = 0.0) -> tuple[Array, Array]:
        """``(sin(theta_i), cos(theta_i))`` of the balls' contact normals against the
        line of centres, ball 0 at ``psi_0 = phase`` (rad) from the pitch point's
        direction (module docstring)."""
        psi = float(phase) + 2 * math.pi * np.arange(self.balls) / self.balls
        k = self.short_width
        r = np.sqrt(1 + k * k - 2 * k * np.cos(psi))
        return np.sin(psi) / r, (k - np.cos(psi)) / r

    def phase_of_input(self, angle: float, phase0: float = 0.0) -> float:
        """``psi_0`` (rad) after the input turned by ``angle`` (rad) from ``phase0``:
        ``-(z_p / Z) angle``."""
        return phase0 - (self.centre_lobes + 2) / self.balls * float(angle)

    def path_curvatures(self, phase: float = 0.0) -> tuple[Array, Array]:
        """Curvatures (1/m) of the ball-centre paths in the centre disc's and the
        planetary disc's grooves at each ball, ``kappa_2`` and ``kappa_3`` of the module
        docstring (positive: curving toward the pitch point's side of the ball)."""
        psi = float(phase) + 2 * math.pi * np.arange(self.balls) / self.balls
        k, z = self.short_width, self.balls
        den = z * 0.5 * self.eccentricity * (1 + k * k - 2 * k * np.cos(psi)) ** 1.5
        k2 = k * (1 + z * k * k - (z + 1) * k * np.cos(psi)) / den
        k3 = k * (1 - z * k * k + (z - 1) * k * np.cos(psi)) / den
        return k2, k3

    def _contact_constant(self, kappa: float) -> float:
        """``F / delta^(3/2)`` (N/m^1.5) of one ball-groove contact whose ball-centre
        path curves by ``kappa`` (1/m) toward the wall; 0 where the wall is undercut."""
        rb, cb = self.ball_radius, math.cos(self.contact_angle)
        rg = 2 * self.conformity * rb
        if kappa * rb * cb >= 1.0:
            return 0.0
        k_g = kappa * cb / (1.0 - kappa * rb * cb)
        e_star = self.youngs_modulus / (2 * (1 - self.poisson_ratio**2))
        one = hertz_elliptic(1.0, 0.5 * (1 / rb + k_g), 0.5 * (1 / rb - 1 / rg), e_star)
        return 1.0 / one.delta**1.5

    @property
    def contact_modulus(self) -> float:
        """``E* = E / (2 (1 - nu^2))`` (Pa) of a ball-groove contact (equal materials)."""
        return self.youngs_modulus / (2 * (1 - self.poisson_ratio**2))

    def contact_curvatures(self, phase: float = 0.0) -> Array:
        """Relative curvature constants ``(A, B)`` (1/m) of every ball-groove contact:
        ``A = (1/r_b + k_g) / 2`` along the groove, ``B = (1/r_b - 1/r_g) / 2`` across it
        (module docstring), shape ``(Z, 2, 2, 2)``: ball, line (``+``, ``-``), wall
        (centre disc, planetary disc), ``(A, B)``; NaN where the wall is undercut."""
        rb, cb = self.ball_radius, math.cos(self.contact_angle)
        rg = 2 * self.conformity * rb
        if self.groove_curvature:
            k2, k3 = self.path_curvatures(phase)
        else:
            k2 = k3 = np.zeros(self.balls)
        kw = np.stack([np.stack([k2, -k3], 1), np.stack([-k2, k3], 1)], 1)  # (Z, line, wall)
        with np.errstate(divide="ignore", invalid="ignore"):
            k_g = kw * cb / (1.0 - kw * rb * cb)
        A = np.where(kw * rb * cb >= 1.0, np.nan, 0.5 * (1 / rb + k_g))
        return np.stack([A, np.full_like(A, 0.5 * (1 / rb - 1 / rg))], axis=-1)

    @property
    def straight_constant(self) -> float:
        """``K_h`` (N/m^1.5) of a line of straight grooves: two equal contacts in series,
        ``K_1 / 2^(3/2)``."""
        return self._contact_constant(0.0) / 2**1.5

    def hertz_constants(self, phase: float = 0.0) -> Array:
        """``K_h`` (N/m^1.5) of lines ``+`` and ``-`` of every ball, shape ``(Z, 2)``
        (module docstring); 0 for a line with an undercut wall."""
        if not self.groove_curvature:
            return np.full((self.balls, 2), self.straight_constant)
        k2, k3 = self.path_curvatures(phase)
        out = np.zeros((self.balls, 2))
        for i in range(self.balls):
            for j, (w2, w3) in enumerate(((k2[i], -k3[i]), (-k2[i], k3[i]))):
                a, b = self._contact_constant(w2), self._contact_constant(w3)
                if a > 0 and b > 0:
                    out[i, j] = (a ** (-2 / 3) + b ** (-2 / 3)) ** -1.5
        return out

    def undercut(self, phase: float = 0.0) -> Array:
        """``(Z, 2)`` booleans: the lines whose groove wall is undercut at ``phase``."""
        return self.hertz_constants(phase) == 0


@dataclass(frozen=True)
class BallLoads:
    """Equilibrium of a ball track under a torque (SI units).

    Attributes
    ----------
    torque : float
        On the centre disc (N m).
    phase : float
        ``psi_0`` (rad).
    s, y : float
        Relative displacement at the pitch point across and along the line of centres
        (m).
    approach : ndarray
        ``delta_i`` (m) of lines ``+`` and ``-``, shape ``(Z, 2)``; negative where a
        line is clear, ``-inf`` where its groove wall is undercut.
    force : ndarray
        Normal force of each line (N), ``(Z, 2)``.
    translational_stiffness : float
        Tangent ``d(T / r_2) / ds`` (N/m), paper 003's ``K_mx``, with ``y`` condensed
        when free.
    torsional_stiffness : float
        ``r_2^2`` times it (N m/rad), about the centre disc's axis.
    radial_stiffness : float
        Tangent stiffness along the line of centres (N/m; ``J_yy``).
    iterations : int
        Newton steps taken.
    """

    torque: float
    phase: float
    s: float
    y: float
    approach: Array
    force: Array
    translational_stiffness: float
    torsional_stiffness: float
    radial_stiffness: float
    iterations: int

    @property
    def loaded(self) -> int:
        """Number of balls carrying load (on either line)."""
        return int(np.count_nonzero(np.any(self.force > 0, axis=1)))

    @property
    def loaded_lines(self) -> int:
        """Number of contact lines carrying load (two a ball at most)."""
        return int(np.count_nonzero(self.force > 0))

    @property
    def max_force(self) -> float:
        """Largest ball force (N)."""
        return float(self.force.max())


def ball_loads(
    track: BallTrack,
    torque: float,
    phase: float = 0.0,
    y: Literal["free", "held"] = "free",
    tol: float = 1e-10,
) -> BallLoads:
    """Loads of every ball of ``track`` under ``torque`` (N m) on the centre disc, the
    ball set at ``phase`` (rad), by minimising the track's energy (module docstring).

    Raises
    ------
    ReducerlabError
        A bad torque or ``y``; no equilibrium (a torque that no ball can carry, e.g.
        every ball clear on the loaded side).
    """
    if isinstance(torque, bool):
        raise ReducerlabError(f"torque: must be a number (N m); got {torque!r}")
    try:
        T = float(torque)
    except (TypeError, ValueError):
        raise ReducerlabError(f"torque: must be a number (N m); got {torque!r}") from None
    if not math.isfinite(T):
        raise ReducerlabError(f"torque: must be finite (N m); got {torque!r}")
    if y not in ("free", "held"):
        raise ReducerlabError(f"y: must be 'free' or 'held'; got {y!r}")
    sin, cos = track.directions(phase)
    cb = math.cos(track.contact_angle)
    Z = track.balls
    g1 = cb * np.stack([sin, cos], axis=1)  # (Z, 2): d delta(+) / d (s, y)
    G = np.concatenate([g1, -g1])  # lines + then lines -, (2Z, 2)
    if y == "held":
        G = G[:, :1]
    kh = track.hertz_constants(phase).T.ravel()  # (2Z,): + lines, then - lines
    c = np.concatenate([track.clearances, track.clearances])
    live = kh > 0
    G, c_l, k_l = G[live], c[live], kh[live]
    Q = np.zeros(G.shape[1])
    Q[0] = T / track.pitch_radius

    def energy(q: Array) -> float:
        d = np.maximum(G @ q - c_l, 0.0)
        return float(0.4 * np.sum(k_l * d**2.5) - Q @ q)

    # start: the lines on the loaded side carry the torque with y = 0 and no clearance
    q = np.zeros(G.shape[1])
    lever = np.maximum(np.sign(T) * G[:, 0], 0.0)
    if T != 0 and np.any(lever > 0):
        q[0] = np.sign(T) * (abs(Q[0]) / np.sum(k_l * lever**2.5)) ** (2 / 3)
    k_ref = float(np.max(k_l)) if k_l.size else 1.0
    scale = max(abs(Q[0]), k_ref * float(np.max(np.abs(c_l), initial=0.0)) ** 1.5, 1e-300)
    it = 0
    for it in range(1, 201):  # noqa: B007 - the count is reported
        d = G @ q - c_l
        on = d > 0
        dp = np.where(on, d, 0.0)
        grad = G.T @ (k_l * dp**1.5) - Q
        if np.linalg.norm(grad) <= tol * scale:
            break
        H = 1.5 * (G[on].T * (k_l[on] * np.sqrt(dp[on]))) @ G[on]
        reg = 1e-12 * max(float(np.trace(H)), k_ref * 1e-6)
        step = -np.linalg.solve(H + reg * np.eye(len(q)), grad)
        # backtracking on the energy, with its round-off allowed for (near the minimum
        # the decrease is far below the energy's own rounding)
        e0, t = energy(q), 1.0
        noise = 1e-13 * (0.4 * float(np.sum(k_l * dp**2.5)) + abs(float(Q @ q)))
        while energy(q + t * step) > e0 + 1e-4 * t * float(grad @ step) + noise and t > 1e-6:
            t *= 0.5
        q = q + t * step
    else:
        raise ReducerlabError(
            f"ball_loads: no equilibrium for T = {T:g} N m at phase {phase:g} rad "
            "(no ball can carry it: check the clearances)"
        )
    d_all = np.full(2 * Z, -np.inf)
    d_all[live] = G @ q - c_l
    force = np.zeros(2 * Z)
    force[live] = k_l * np.maximum(d_all[live], 0.0) ** 1.5
    on = d_all > 0
    Gf = np.concatenate([g1, -g1])
    J = 1.5 * (Gf[on].T * (kh[on] * np.sqrt(d_all[on]))) @ Gf[on]
    if y == "free":
        k_s = J[0, 0] - (J[0, 1] ** 2 / J[1, 1] if J[1, 1] > 0 else 0.0)
    else:
        k_s = float(J[0, 0])
    r2 = track.pitch_radius
    return BallLoads(
        T, float(phase), float(q[0]), float(q[1]) if y == "free" else 0.0,
        d_all.reshape(2, Z).T.copy(), force.reshape(2, Z).T.copy(),
        float(k_s), float(k_s * r2 * r2), float(J[1, 1]), it,
    )  # fmt: skip


def track_stiffness(
    track: BallTrack,
    torques: ArrayLike,
    phases: int = 8,
    y: Literal["free", "held"] = "free",
) -> dict[str, Array]:
    """Loaded balls, largest ball force and tangent stiffnesses of ``track`` against
    torque, at ``phases`` ball-set positions over one ball pitch.

    Returns
    -------
    dict
        ``torque`` (N m, (n,)), ``phase`` (rad, (p,)), and on ``(n, p)``: ``loaded``
        (balls), ``max_force`` (N), ``translational_stiffness`` (N/m),
        ``torsional_stiffness`` (N m/rad).
    """
    t = np.atleast_1d(np.asarray(torques, dtype=float))
    if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)):
        raise ReducerlabError("torques: must be a non-empty list of finite torques (N m)")
    if isinstance(phases, bool) or not isinstance(phases, (int, np.integer)) or phases < 1:
        raise ReducerlabError(f"phases: must be an integer >= 1; got {phases!r}")
    ph = 2 * math.pi / track.balls * np.arange(phases) / phases
    out = {k: np.zeros((t.size, ph.size)) for k in
           ("loaded", "max_force", "translational_stiffness", "torsional_stiffness")}  # fmt: skip
    for i, T in enumerate(t):
        for j, p in enumerate(ph):
            r = ball_loads(track, float(T), float(p), y)
            out["loaded"][i, j] = r.loaded
            out["max_force"][i, j] = r.max_force
            out["translational_stiffness"][i, j] = r.translational_stiffness
            out["torsional_stiffness"][i, j] = r.torsional_stiffness
    return {"torque": t, "phase": ph, **out}
