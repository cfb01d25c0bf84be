"""Coulomb friction at the tooth contacts: sliding velocities and the mesh power loss.

In the frame where both gear axes are fixed (the pair's frame of ``contact.flanks``:
the housing for a fixed-axis pair, the carrier for a planetary or nutation drive), gear
A turns at ``phi_dot`` and gear B at the conjugate rate. The velocity of the material
point of gear ``G`` at ``p`` is ``w_G x (p - o_G)`` (``w_G``: its angular velocity,
``o_G``: a point of its axis), so the relative velocity of A's flank over B's at a
contact cell is

    v = w_A x (p - o_A) - w_B x (p - o_B),

and the sliding velocity ``v_s`` is its part tangent to the flanks,
``v_s = v - (v . n) n`` (``n``: A's unit normal; for a conjugate pair ``v . n = 0`` on
the contact line, off it the normal part is the rate at which the gap closes). The
relative velocity of two bodies at a common point is the same in every frame, rotating
ones included, so the friction power computed in the pair's frame is the power the
drive dissipates.

The angular velocities are read off the pair's own placement
(``MeshPair.poses(phi)``): ``W_G = dR_G/dphi R_G^T`` is the skew matrix of gear G's
angular velocity per unit rate of ``phi`` (central difference of the exact poses), so
every pair (spur, internal, nutation bevel) is handled alike, misalignment included.

Coulomb's law at a cell of normal force ``F`` gives the friction power
``mu F |v_s|`` (W); the mesh power loss at a position is its sum over the cells. Only
sliding friction: the rolling (hydrodynamic, EHL) loss of the lubricant film is out of
scope.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from .flanks import MeshPair
from .ltca import PositionContact

__all__ = [
    "MU_MAX",
    "SlidingField",
    "angular_velocities",
    "check_friction_coefficient",
    "friction_power",
    "sliding_velocities",
]

Array = NDArray[np.float64]

#: largest Coulomb coefficient accepted at a lubricated tooth contact: dry steel on steel
#: is about 0.3 to 0.6; lubricated gear meshes run at 0.02 to 0.1 (Niemann/Winter
#: Vol. II, 1989, Sec. 21.5), so a larger value is taken for a typo
MU_MAX = 0.3

#: step of the central difference of the poses (rad); the rotation matrices are exact to
#: round-off, so the derivative is good to ~1e-10 relative
_STEP = 1e-5


def check_friction_coefficient(mu: object, name: str = "mu") -> float:
    """``mu`` as a float in ``[0, MU_MAX]``.

    Raises
    ------
    ReducerlabError
        ``mu`` not a finite number in ``[0, MU_MAX]``.
    """
    if isinstance(mu, bool) or not isinstance(mu, int | float) or not math.isfinite(mu):
        raise ReducerlabError(f"{name}: the friction coefficient must be a number; got {mu!r}")
    if not 0.0 <= mu <= MU_MAX:
        raise ReducerlabError(
            f"{name}: the Coulomb friction coefficient must lie in [0, {MU_MAX}] "
            f"(lubricated gear teeth run at 0.02 to 0.1); got {mu!r}"
        )
    return float(mu)


def _axial(W: Array) -> Array:
    """The vector ``w`` of the skew part of ``W`` (``W x = w x x``)."""
    S = 0.5 * (W - W.T)
    return np.array([S[2, 1], S[0, 2], S[1, 0]])


def angular_velocities(pair: MeshPair, phi: float) -> tuple[Array, Array]:
    """Angular velocities of gears A and B per unit rate of gear A's rotation ``phi``
    (rad/rad, vectors in the pair's fixed frame): the axial vectors of
    ``dR/dphi R^T`` of each gear's pose, by a central difference."""
    lo, hi = pair.poses(phi - _STEP), pair.poses(phi + _STEP)
    mid = pair.poses(phi)
    out = []
    for g in range(2):
        dR = (hi[g].rotation - lo[g].rotation) / (2 * _STEP)
        out.append(_axial(dR @ mid[g].rotation.T))
    return out[0], out[1]


@dataclass(frozen=True)
class SlidingField:
    """Relative velocities at the cells of one position, per unit rate of ``phi``.

    Attributes
    ----------
    relative : ndarray (n, 3)
        ``v / phi_dot`` (m/rad): velocity of A's material point over B's.
    sliding : ndarray (n, 3)
        Its part tangent to the flank (m/rad).
    normal : ndarray (n,)
        Its normal part ``v . n`` (m/rad).
    """

    relative: Array
    sliding: Array
    normal: Array

    @property
    def speed(self) -> Array:
        """``|v_s| / phi_dot`` (m/rad) at each cell."""
        return np.linalg.norm(self.sliding, axis=1)


def sliding_velocities(pair: MeshPair, phi: float, points: Array, normals: Array) -> SlidingField:
    """Relative and sliding velocities of A over B at ``points`` (fixed frame, m) with
    A's unit normals ``normals``, per unit rate of gear A's rotation, at mesh position
    ``phi`` (rad): ``v = w_A x (p - o_A) - w_B x (p - o_B)``, ``v_s = v - (v.n) n``."""
    p = np.atleast_2d(np.asarray(points, float))
    n = np.atleast_2d(np.asarray(normals, float))
    if p.shape != n.shape or p.shape[-1] != 3:
        raise ReducerlabError("points, normals: must be two (n, 3) arrays of the same shape")
    wa, wb = angular_velocities(pair, phi)
    pa, pb = pair.poses(phi)
    v = np.cross(wa, p - pa.origin) - np.cross(wb, p - pb.origin)
    vn = np.einsum("ij,ij->i", v, n)
    return SlidingField(v, v - vn[:, None] * n, vn)


def friction_power(pair: MeshPair, run: PositionContact, mu: float, phi_dot: float) -> Array:
    """Coulomb friction power of each cell of one loaded position (W):
    ``mu F_i |v_s,i|`` with ``v_s`` at gear A's speed ``phi_dot`` (rad/s, in the pair's
    frame)."""
    mu = check_friction_coefficient(mu)
    field = sliding_velocities(pair, run.phi, run.points, run.normals)
    return mu * run.force * field.speed * abs(float(phi_dot))
