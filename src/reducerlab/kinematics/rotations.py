"""Rotation matrices, ZXZ Euler angles and named homogeneous transforms.

Conventions (``docs/conventions.md``): right-handed frames, active rotations,
``R @ v`` maps the coordinates of a vector in the rotated (body) frame to the
reference frame. A :class:`Transform` ``M_21`` maps coordinates in frame ``S1`` to
coordinates in frame ``S2`` (paper 002's notation); composing ``M_32 @ M_21`` checks
that the inner frame names agree and yields ``M_31``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError

__all__ = ["Transform", "euler_zxz", "rot_x", "rot_y", "rot_z", "skew", "unskew"]


def _axis_rotation(angle: ArrayLike, i: int, j: int) -> NDArray[np.float64]:
    a = np.asarray(angle, dtype=float)
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((*a.shape, 3, 3))
    k = 3 - i - j
    out[..., k, k] = 1.0
    out[..., i, i] = c
    out[..., j, j] = c
    out[..., i, j] = -s
    out[..., j, i] = s
    return out


def rot_x(angle: ArrayLike) -> NDArray[np.float64]:
    """Rotation by ``angle`` (rad) about x; broadcasts over arrays, shape (..., 3, 3)."""
    return _axis_rotation(angle, 1, 2)


def rot_y(angle: ArrayLike) -> NDArray[np.float64]:
    """Rotation by ``angle`` (rad) about y; shape (..., 3, 3)."""
    return _axis_rotation(angle, 2, 0)


def rot_z(angle: ArrayLike) -> NDArray[np.float64]:
    """Rotation by ``angle`` (rad) about z; shape (..., 3, 3)."""
    return _axis_rotation(angle, 0, 1)


def euler_zxz(phi: ArrayLike, theta: ArrayLike, psi: ArrayLike) -> NDArray[np.float64]:
    """Orientation from ZXZ Euler angles: ``R = Rz(phi) Rx(theta) Rz(psi)``.

    Parameters
    ----------
    phi : array_like
        Precession about the fixed zeta axis (rad).
    theta : array_like
        Nutation about the line of nodes (rad).
    psi : array_like
        Spin about the body axis z (rad).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Maps body-frame coordinates to fixed-frame coordinates (paper 002).
    """
    return rot_z(phi) @ rot_x(theta) @ rot_z(psi)


def skew(w: ArrayLike) -> NDArray[np.float64]:
    """Skew-symmetric matrix ``W`` with ``W @ r = w x r`` (paper 002); shape (..., 3, 3)."""
    w = np.asarray(w, dtype=float)
    out = np.zeros((*w.shape[:-1], 3, 3))
    out[..., 0, 1], out[..., 0, 2] = -w[..., 2], w[..., 1]
    out[..., 1, 0], out[..., 1, 2] = w[..., 2], -w[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -w[..., 1], w[..., 0]
    return out


def unskew(W: ArrayLike) -> NDArray[np.float64]:
    """Vector of a skew-symmetric matrix (its antisymmetric part); shape (..., 3)."""
    W = np.asarray(W, dtype=float)
    A = 0.5 * (W - np.swapaxes(W, -1, -2))
    return np.stack([A[..., 2, 1], A[..., 0, 2], A[..., 1, 0]], axis=-1)


@dataclass(frozen=True)
class Transform:
    """A 4x4 homogeneous transform ``M_{to,frm}`` between two named frames.

    ``M @ [x, y, z, 1]`` maps coordinates of a point in frame ``frm`` to frame ``to``.

    Parameters
    ----------
    matrix : ndarray, shape (..., 4, 4)
    to, frm : str
        Frame names, e.g. ``Transform(M, to="S2", frm="S1")`` is paper 002's ``M_21``.
    """

    matrix: NDArray[np.float64]
    to: str
    frm: str

    @classmethod
    def from_rotation(
        cls, R: ArrayLike, to: str, frm: str, translation: ArrayLike | None = None
    ) -> Transform:
        """Build from a rotation (..., 3, 3) and an optional translation (..., 3) in m."""
        R = np.asarray(R, dtype=float)
        M = np.zeros((*R.shape[:-2], 4, 4))
        M[..., :3, :3] = R
        if translation is not None:
            M[..., :3, 3] = np.asarray(translation, dtype=float)
        M[..., 3, 3] = 1.0
        return cls(M, to, frm)

    @property
    def rotation(self) -> NDArray[np.float64]:
        """The 3x3 rotation block."""
        return self.matrix[..., :3, :3]

    @property
    def translation(self) -> NDArray[np.float64]:
        """The translation column (m)."""
        return self.matrix[..., :3, 3]

    def __matmul__(self, other: Transform) -> Transform:
        if not isinstance(other, Transform):
            return NotImplemented
        if self.frm != other.to:
            raise ReducerlabError(
                f"cannot compose M_{self.to}{self.frm} @ M_{other.to}{other.frm}: "
                f"frame {self.frm!r} does not match {other.to!r}"
            )
        return Transform(self.matrix @ other.matrix, self.to, other.frm)

    def inverse(self) -> Transform:
        """``M_{frm,to}``: rotation transposed, translation ``-R^T t``."""
        R = self.rotation
        Rt = np.swapaxes(R, -1, -2)
        t = -(Rt @ self.translation[..., None])[..., 0]
        return Transform.from_rotation(Rt, to=self.frm, frm=self.to, translation=t)

    def apply(self, points: ArrayLike) -> NDArray[np.float64]:
        """Map points (..., 3) given in ``frm`` to ``to`` coordinates."""
        p = np.asarray(points, dtype=float)
        return (self.rotation @ p[..., None])[..., 0] + self.translation

    def apply_vector(self, vectors: ArrayLike) -> NDArray[np.float64]:
        """Map free vectors (velocities, axes): rotation only."""
        v = np.asarray(vectors, dtype=float)
        return (self.rotation @ v[..., None])[..., 0]
