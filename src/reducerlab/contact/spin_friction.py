"""Coulomb friction power of a Hertz contact in full slip: sliding and spin.

A Hertz contact (semi-axes ``a`` along x, ``b`` along y, pressure ``p(x, y) = p0
sqrt(1 - x^2/a^2 - y^2/b^2)``, Johnson 1985 §4.2) whose two surfaces slide by ``s =
(s_x, s_y)`` (m/s) and spin by ``omega`` (rad/s) about the contact normal has the slip
velocity ``v(x, y) = (s_x - omega y, s_y + omega x)`` at each point. In full slip
(Coulomb, every point slipping: K. L. Johnson, *Contact Mechanics*, Cambridge 1985,
§8.3, the twisting of a Hertz contact with complete slip) the traction is ``mu p``
against the local slip, and the friction power is

``P = integral mu p(x, y) |v(x, y)| dA``.

Pure spin (``s = 0``) gives the spin moment ``M = P / omega = integral mu p r dA``,
which for a circle (``a = b``) is ``M = (3 pi / 16) mu F a`` (Johnson §8.3); pure
sliding gives ``P = mu F |s|``. The integral is taken by quadrature in elliptic polar
coordinates ``x = a rho cos phi``, ``y = b rho sin phi``, ``rho = sin u``: ``p dA = p0
a b cos^2(u) sin(u) du dphi``, smooth in ``u`` (Gauss-Legendre on ``[0, pi/2]``) and
periodic in ``phi`` (the trapezoidal rule, spectrally accurate).

Units: SI (m, Pa, N, m/s, rad/s, W, N m).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError

__all__ = ["full_slip_power", "spin_moment"]

Array = NDArray[np.float64]


@lru_cache(maxsize=8)
def _nodes(n: int) -> tuple[Array, Array, Array, Array]:
    """Quadrature nodes and weights: ``u`` (Gauss-Legendre on [0, pi/2]) and ``phi``
    (``2 n`` trapezoidal points on [0, 2 pi))."""
    x, w = np.polynomial.legendre.leggauss(n)
    u = 0.25 * math.pi * (x + 1.0)
    wu = 0.25 * math.pi * w * np.cos(u) ** 2 * np.sin(u)  # p dA / (p0 a b) weight
    phi = 2.0 * math.pi * np.arange(2 * n) / (2 * n)
    wphi = np.full(2 * n, 2.0 * math.pi / (2 * n))
    return np.sin(u), wu, phi, wphi


def full_slip_power(
    a: ArrayLike,
    b: ArrayLike,
    p0: ArrayLike,
    slip: ArrayLike,
    spin: ArrayLike,
    mu: float,
    nodes: int = 48,
) -> Array:
    """Coulomb friction power ``integral mu p |v| dA`` (W) of Hertz contacts in full
    slip (module docstring).

    Parameters
    ----------
    a, b : array_like
        Semi-axes along x and y (m), > 0 (broadcast together with ``p0``, ``spin`` and
        ``slip[..., 0]``).
    p0 : array_like
        Peak pressure (Pa), >= 0.
    slip : array_like
        Sliding velocity ``(s_x, s_y)`` of one surface over the other (m/s), last axis 2.
    spin : array_like
        Relative angular velocity about the contact normal (rad/s).
    mu : float
        Coulomb coefficient, >= 0.
    nodes : int
        Gauss points in ``u`` (``2 nodes`` in ``phi``), >= 4.

    Returns
    -------
    ndarray
        Power (W), the broadcast shape.

    Raises
    ------
    ReducerlabError
        Non-positive semi-axes, a negative pressure or coefficient, a slip without its
        two components, too few nodes.
    """
    if isinstance(nodes, bool) or not isinstance(nodes, int) or nodes < 4:
        raise ReducerlabError(f"nodes: must be an integer >= 4; got {nodes!r}")
    if not (math.isfinite(mu) and mu >= 0):
        raise ReducerlabError(f"mu: must be a finite number >= 0; got {mu!r}")
    a_, b_, p_, w_ = (np.asarray(v, dtype=float) for v in (a, b, p0, spin))
    s = np.asarray(slip, dtype=float)
    if s.ndim == 0 or s.shape[-1] != 2:
        raise ReducerlabError(f"slip: needs (s_x, s_y) on its last axis; got shape {s.shape}")
    if not (np.all(a_ > 0) and np.all(b_ > 0)):
        raise ReducerlabError("a, b: contact semi-axes must be > 0 (m)")
    if not np.all(p_ >= 0):
        raise ReducerlabError("p0: peak pressure must be >= 0 (Pa)")
    a_, b_, p_, w_, sx, sy = np.broadcast_arrays(a_, b_, p_, w_, s[..., 0], s[..., 1])
    rho, wu, phi, wphi = _nodes(nodes)
    x = a_[..., None, None] * rho[:, None] * np.cos(phi)[None, :]
    y = b_[..., None, None] * rho[:, None] * np.sin(phi)[None, :]
    vx = sx[..., None, None] - w_[..., None, None] * y
    vy = sy[..., None, None] + w_[..., None, None] * x
    speed = np.hypot(vx, vy)
    integral = np.einsum("...ij,i,j->...", speed, wu, wphi)
    return mu * p_ * a_ * b_ * integral


def spin_moment(a: ArrayLike, b: ArrayLike, p0: ArrayLike, mu: float, nodes: int = 48) -> Array:
    """Spin friction moment ``M = integral mu p r dA`` (N m) of Hertz contacts in full
    slip: the pure-spin power per unit spin (module docstring); ``(3 pi / 16) mu F a``
    for a circle of radius ``a`` (Johnson 1985 §8.3)."""
    shape = np.broadcast_shapes(np.shape(a), np.shape(b), np.shape(p0))
    return full_slip_power(a, b, p0, np.zeros((*shape, 2)), np.ones(shape), mu, nodes)
