"""Flank pairs in mesh: exact surfaces, their placement, and the unloaded separation.

The tooth contact analysis works on any two gears whose flanks can be evaluated exactly
at scattered parameters. A flank is parametrised by ``(u, v)`` in ``[u_lo, u_hi] x
[0, 1]`` (``u`` along the profile from root to tip, ``v`` along the face from toe to
heel) and evaluated in its gear's frame (``z`` = gear axis); the pair says which
rotations of tooth 0 of each gear form tooth pair ``k`` (``MeshPair.tooth_angles``; for
the nutation pair crown tooth ``k`` generates tooth ``k`` of both gears, each tooth 0
turned by ``-2 pi k / z``).

A :class:`MeshPair` places both gears in one fixed frame at a mesh position (the
rotation ``phi`` of gear A) and names the flank of A that carries the grid of
potential contact points and the mating flank of B. :func:`separations` measures, for
each grid point ``P`` of A with outward normal ``n``, the distance ``t`` along ``n`` to
B's flank (``P + t n`` on B, solved by Newton's method in B's parameters and ``t``),
and the lever ``lam = -dt/dpsi`` of a rigid rotation ``psi`` of gear B about its own
(possibly misaligned) axis. ``t / lam`` is the rotation of B that closes the gap at
``P``; its minimum over all points is the unloaded transmission error.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from ..errors import ReducerlabError
from ..geometry.bevel_surface import BevelGear, axis_frame, envelope
from ..geometry.solid import cone_coordinates, default_blank
from ..geometry.spiral import CrownGear
from ..kinematics.rotations import rot_x, rot_z
from .modifications import PairModifications, modified

__all__ = [
    "BevelFlank",
    "Flank",
    "GearPose",
    "MeshPair",
    "Misalignment",
    "NutationPair",
    "Separation",
    "separations",
]

Array = NDArray[np.float64]


class Flank(Protocol):
    """One flank of tooth 0 of a gear, evaluated exactly in the gear's frame."""

    teeth: int
    u_range: tuple[float, float]

    def evaluate(self, u: Array, v: Array) -> tuple[Array, Array]:
        """Points (m) and unit outward normals, shape (n, 3), at parameters (n,)."""
        ...

    def inside(self, points: Array) -> NDArray[np.bool_]:
        """Which points (gear frame) lie on the gear's real tooth (within the blank)."""
        ...


@dataclass(frozen=True)
class BevelFlank:
    """A flank of a crown-generated nutation bevel gear (paper 001).

    Parameters
    ----------
    crown : CrownGear
    gear : BevelGear
    flank : {+1, -1}
        Flank of the crown tooth (``geometry.profiles``); crown tooth 0's flank ``f``
        generates a flank of the external gear's tooth 0 and the mating flank of the
        internal gear.
    addendum : float, optional
        Tooth height above the pitch cone ``h_a`` (m) of both gears (the face cones);
        default the basic profile's tip height.

    ``u`` is the crown profile parameter over the heights ``[-h_a, h_a]`` where the two
    gears' teeth overlap, ``v`` the crown spiral's cone distance over the face.
    """

    crown: CrownGear
    gear: BevelGear
    flank: int = 1
    addendum: float | None = None
    u_range: tuple[float, float] = field(init=False)

    def __post_init__(self) -> None:
        if self.flank not in (1, -1):
            raise ReducerlabError(f"flank: must be +1 or -1; got {self.flank!r}")
        prof = self.crown.profile
        h_a = self.blank.face if self.gear.kind == "external" else -self.blank.face
        # the profile parameter where the crown profile is at height -h_a
        u = np.linspace(0.0, 1.0, 2001)
        x = prof.evaluate(u).x
        lo = float(np.interp(-h_a, x, u)) if x[0] < -h_a else 0.0
        object.__setattr__(self, "u_range", (lo, 1.0))

    @property
    def teeth(self) -> int:
        return self.gear.teeth

    @property
    def tip_end(self) -> int:
        """Which end of ``u_range`` is the tooth's tip: +1 (``u_hi``) for the external
        gear, -1 (``u_lo``) for the internal gear (the crown profile runs from the
        external gear's root to its tip, and from the internal gear's tip to its root)."""
        return 1 if self.gear.kind == "external" else -1

    @property
    def blank(self):
        """The gear's blank (face and root cones, toe and heel), ``geometry.solid``."""
        return default_blank(self.crown, self.gear, addendum=self.addendum)

    def evaluate(self, u: Array, v: Array) -> tuple[Array, Array]:
        lo, hi = self.crown.rho_range
        uu = np.clip(np.asarray(u, float).ravel(), 0.0, 1.0)
        rho = lo + (hi - lo) * np.asarray(v, float).ravel()
        rC, nC = self.crown.points(uu, rho, self.flank, 0)
        pts, nrm, _, res, _ = envelope(rC, nC, self.gear)
        if not np.all(np.abs(res) <= 1e-9):
            bad = int(np.sum(~(np.abs(res) <= 1e-9)))
            raise ReducerlabError(
                f"surface: the meshing equation has no solution for {bad} flank points"
            )
        return pts, nrm

    def inside(self, points: Array) -> NDArray[np.bool_]:
        bl = self.blank
        L, h, _ = cone_coordinates(points, self.gear.cone_angle)
        tol = 1e-9 * bl.back
        in_face = (bl.front - tol <= L) & (bl.back + tol >= L)
        if self.gear.kind == "external":
            return in_face & (h <= bl.face + tol)
        return in_face & (h >= bl.face - tol)


@dataclass(frozen=True)
class GearPose:
    """A gear's placement in the fixed frame: ``x_fixed = rotation @ x_gear + origin``;
    its axis of rotation ``axis`` (unit, fixed frame) passes through ``origin``."""

    rotation: Array
    origin: Array
    axis: Array


@dataclass(frozen=True)
class Misalignment:
    """Assembly errors of gear B relative to its nominal place (all optional).

    Attributes
    ----------
    axial_a, axial_b : float
        Shifts of gear A and gear B along their own axes (m), positive away from the
        cone apex.
    offset : float
        Shift of gear B perpendicular to the plane of the two axes (m): the hypoid
        offset ``E``.
    shaft_angle : float
        Error of the shaft angle (rad): gear B turned about the normal of the plane of
        the axes through the apex.
    """

    axial_a: float = 0.0
    axial_b: float = 0.0
    offset: float = 0.0
    shaft_angle: float = 0.0

    def __post_init__(self) -> None:
        for name in ("axial_a", "axial_b", "offset", "shaft_angle"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise ReducerlabError(f"misalignment.{name}: must be a finite number; got {v!r}")
        if abs(self.shaft_angle) > math.radians(2):
            raise ReducerlabError(
                f"misalignment.shaft_angle: must be within +-2 deg (an assembly error); got "
                f"{math.degrees(self.shaft_angle):g} deg"
            )

    @property
    def none(self) -> bool:
        return not any((self.axial_a, self.axial_b, self.offset, self.shaft_angle))


class MeshPair(Protocol):
    """Two gears in mesh: the flanks, their placement and the torque ratio."""

    flank_a: Flank
    flank_b: Flank

    def poses(self, phi: float) -> tuple[GearPose, GearPose]:
        """Both gears' placement when gear A has turned by ``phi`` (rad)."""
        ...

    @property
    def torque_ratio(self) -> float:
        """``T_B / T_A`` of the frictionless conjugate pair."""
        ...

    def tooth_angles(self, k: int) -> tuple[float, float]:
        """Rotations (rad) about their axes that take tooth 0 of A and of B to the
        teeth of tooth pair ``k``."""
        ...


@dataclass(frozen=True)
class NutationPair:
    """External gear A and internal gear B of a nutation bevel pair (paper 001) in the
    generating frame ``S0`` of ``geometry.bevel_surface``.

    Both gears are enveloped by the same crown gear; at the crown angle ``phi_C`` the
    external gear has turned by ``phi_C / sin(delta_A)`` and the internal gear by
    ``phi_C / sin(delta_B)`` (``x_0 = B(delta)^T Rz(phi_i) x_i``), so the unloaded pair
    is conjugate. The mesh position is gear A's angle ``phi``.

    ``modifications`` (``contact.modifications``) removes material from the loaded
    flanks (crowning, tip and root relief): the flanks ``flank_a``, ``flank_b`` are then
    the modified ones, and ``unmodified`` is the pair without them.
    """

    crown: CrownGear
    external: BevelGear
    internal: BevelGear
    flank: int = 1
    misalignment: Misalignment = field(default_factory=Misalignment)
    addendum: float | None = None
    modifications: PairModifications = field(default_factory=PairModifications)

    def __post_init__(self) -> None:
        if self.external.kind != "external" or self.internal.kind != "internal":
            raise ReducerlabError(
                "pair: needs an external gear A and an internal gear B (nutation bevel pair)"
            )
        for g in (self.external, self.internal):
            z = self.crown.teeth * math.sin(g.cone_angle)
            if not math.isclose(z, g.teeth, rel_tol=1e-9):
                raise ReducerlabError(
                    f"pair: the crown gear (z_C = {self.crown.teeth:.6g}) does not generate the "
                    f"{g.kind} gear of {g.teeth} teeth (z_C sin(delta) = {z:.6g})"
                )
        if not isinstance(self.modifications, PairModifications):
            raise ReducerlabError(
                "modifications: must be a PairModifications (contact.modifications); got "
                f"{type(self.modifications).__name__}"
            )

    @functools.cached_property
    def flank_a(self) -> Flank:
        """The external gear's loaded flank (modified by ``modifications.a``)."""
        plain = BevelFlank(self.crown, self.external, self.flank, self.addendum)
        return modified(plain, self.modifications.a, "modifications.a")

    @functools.cached_property
    def flank_b(self) -> Flank:
        """The internal gear's loaded flank (modified by ``modifications.b``)."""
        plain = BevelFlank(self.crown, self.internal, self.flank, self.addendum)
        return modified(plain, self.modifications.b, "modifications.b")

    @property
    def unmodified(self) -> NutationPair:
        """The same pair without flank modifications (the tooth compliance's pair)."""
        if self.modifications.none:
            return self
        return replace(self, modifications=PairModifications())

    @property
    def torque_ratio(self) -> float:
        return self.internal.teeth / self.external.teeth

    def tooth_angles(self, k: int) -> tuple[float, float]:
        # crown tooth k generates tooth k of both gears: tooth 0 turned by -2 pi k / z
        return -2 * math.pi * k / self.external.teeth, -2 * math.pi * k / self.internal.teeth

    @property
    def phase(self) -> float:
        """Crown angle (rad) at which the mean pitch point of tooth 0 is generated: mesh
        position ``phi = 0`` puts tooth pair 0 at the middle of its mesh."""
        u0 = self.crown.profile.pitch_parameter()
        r, n = self.crown.points(np.array([u0]), np.array([self.crown.mean_cone_distance]),
                                 self.flank, 0)  # fmt: skip
        return float(envelope(r, n, self.external)[2][0])

    def poses(self, phi: float) -> tuple[GearPose, GearPose]:
        ez = np.array([0.0, 0.0, 1.0])
        mis = self.misalignment
        out = []
        phi_c = self.phase + phi * math.sin(self.external.cone_angle)
        for g, axial in ((self.external, mis.axial_a), (self.internal, mis.axial_b)):
            Bt = axis_frame(g.cone_angle).T
            R = Bt @ rot_z(phi_c / math.sin(g.cone_angle))
            axis = Bt @ ez
            out.append(GearPose(R, axial * axis, axis))
        a, b = out
        if not mis.none:
            # gear B: shaft angle about x0 (normal of the plane of the axes), offset along x0
            Rm = rot_x(mis.shaft_angle)
            t = b.origin @ Rm.T + np.array([mis.offset, 0.0, 0.0])
            b = GearPose(Rm @ b.rotation, t, Rm @ b.axis)
        return a, b


@dataclass(frozen=True)
class Separation:
    """Unloaded separation of a grid of points of flank A from flank B (fixed frame).

    Attributes
    ----------
    points, normals : ndarray (n, 3)
        Points of A (m) and A's outward unit normals.
    distance : ndarray (n,)
        ``t``: distance along A's normal to B's flank (m); ``inf`` where B's flank is
        not found along the normal within the tooth (no potential contact).
    lever : ndarray (n,)
        ``lam = -dt/dpsi`` (m/rad) for a rotation ``psi`` of B about its axis.
    uv_b : ndarray (n, 2)
        B's flank parameters of the mating points.
    """

    points: Array
    normals: Array
    distance: Array
    lever: Array
    uv_b: Array


def _solve3(J: Array, b: Array) -> Array:
    """Solve the 3x3 systems ``J x = b`` (batched) by Cramer's rule; singular -> nan."""
    c0, c1, c2 = J[..., 0], J[..., 1], J[..., 2]
    det = np.einsum("ij,ij->i", c0, np.cross(c1, c2))
    with np.errstate(all="ignore"):
        x = np.stack([
            np.einsum("ij,ij->i", b, np.cross(c1, c2)),
            np.einsum("ij,ij->i", c0, np.cross(b, c2)),
            np.einsum("ij,ij->i", c0, np.cross(c1, b)),
        ], axis=1) / det[:, None]  # fmt: skip
    return x


def _turn(points: Array, normals: Array, pose: GearPose, angle: float) -> tuple[Array, Array]:
    """Tooth points turned by ``angle`` about the gear axis, then placed (fixed frame)."""
    R = pose.rotation @ rot_z(angle)
    return points @ R.T + pose.origin, normals @ R.T


def _eval_b(flank: Flank, pose: GearPose, angle: float, u: Array, v: Array):
    P, N = flank.evaluate(u, v)
    Pf, Nf = _turn(P, N, pose, angle)
    return Pf, Nf, P


def separations(
    pair: MeshPair,
    phi: float,
    tooth: int,
    u: ArrayLike,
    v: ArrayLike,
    *,
    seed_grid: tuple[int, int] = (25, 25),
    tol: float = 1e-11,
    max_iter: int = 12,
) -> Separation:
    """Distances from points ``(u, v)`` of tooth ``tooth`` of gear A to gear B's flank.

    Parameters
    ----------
    pair : MeshPair
    phi : float
        Mesh position: gear A's rotation (rad).
    tooth : int
        Tooth pair index ``k`` (tooth ``k`` of A against tooth ``k`` of B).
    u, v : array_like, shape (n,)
        Parameters of the points on A's flank.
    seed_grid : (int, int)
        Grid of B's flank used to start Newton's method at the nearest point.
    tol : float
        Newton stops when the largest residual is below ``tol`` (m).
    """
    A, B = pair.flank_a, pair.flank_b
    pa, pb = pair.poses(phi)
    ang_a, ang_b = pair.tooth_angles(tooth)
    uu, vv = np.asarray(u, float).ravel(), np.asarray(v, float).ravel()
    PA_gear, NA_gear = A.evaluate(uu, vv)
    ok = A.inside(PA_gear)
    P, N = _turn(PA_gear, NA_gear, pa, ang_a)
    # Newton start: nearest point of a seed grid of B
    lo, hi = B.u_range
    su, sv = np.meshgrid(np.linspace(lo, hi, seed_grid[0]), np.linspace(0, 1, seed_grid[1]))
    su, sv = su.ravel(), sv.ravel()
    Sq, _, _ = _eval_b(B, pb, ang_b, su, sv)
    _, j = cKDTree(Sq).query(P)
    x = np.stack([su[j], sv[j], np.einsum("ij,ij->i", Sq[j] - P, N)], axis=1)
    h = 1e-6
    res = np.full(len(P), np.inf)
    act = np.arange(len(P))  # points still iterating (a converged point stays put)
    for _ in range(max_iter):
        xa, Pa, Na = x[act], P[act], N[act]
        Q, _, _ = _eval_b(B, pb, ang_b, xa[:, 0], xa[:, 1])
        r = Q - Pa - xa[:, 2:3] * Na
        res[act] = np.linalg.norm(r, axis=1)
        going = ok[act] & ~(res[act] < tol)
        if not np.any(going):
            break
        act, xa, Q, r, Pa, Na = act[going], xa[going], Q[going], r[going], Pa[going], Na[going]
        Qu, _, _ = _eval_b(B, pb, ang_b, xa[:, 0] + h, xa[:, 1])
        Qv, _, _ = _eval_b(B, pb, ang_b, xa[:, 0], xa[:, 1] + h)
        J = np.stack([(Qu - Q) / h, (Qv - Q) / h, -Na], axis=2)
        dx = _solve3(J, -r)
        dx = np.where(np.isfinite(dx), dx, 0.0)
        dx[:, :2] = np.clip(dx[:, :2], -0.2, 0.2)
        xa = xa + dx
        xa[:, 0] = np.clip(xa[:, 0], lo - 0.05, hi + 0.05)
        xa[:, 1] = np.clip(xa[:, 1], -0.05, 1.05)
        x[act] = xa
    else:  # the residual after the last step
        Q, _, _ = _eval_b(B, pb, ang_b, x[act, 0], x[act, 1])
        res[act] = np.linalg.norm(Q - P[act] - x[act, 2:3] * N[act], axis=1)
    Q, NB, QB_gear = _eval_b(B, pb, ang_b, x[:, 0], x[:, 1])
    inb = (x[:, 0] >= lo - 1e-12) & (x[:, 0] <= hi + 1e-12) & (x[:, 1] >= -1e-12)
    inb &= x[:, 1] <= 1 + 1e-12
    found = ok & inb & (res < 1e3 * tol) & B.inside(QB_gear)
    # lever: rigid rotation psi of B about its axis moves Q by psi a x (Q - o)
    dQ = np.cross(pb.axis, Q - pb.origin)
    with np.errstate(all="ignore"):
        lam = -np.einsum("ij,ij->i", dQ, NB) / np.einsum("ij,ij->i", N, NB)
    t = np.where(found, x[:, 2], np.inf)
    return Separation(P, N, t, np.where(found, lam, 0.0), x[:, :2])
