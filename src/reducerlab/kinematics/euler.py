"""Angular velocity, acceleration and gyroscopic moment from ZXZ Euler angles.

For ``R = Rz(phi) Rx(theta) Rz(psi)`` (paper 002) the angular velocity is
``omega = phi' e_zeta + theta' n + psi' k`` with ``n`` the line of nodes and ``k`` the
body axis. Projected on the body axes (paper 002, "Euler kinematic equations"):

``w_x = phi' sin(theta) sin(psi) + theta' cos(psi)``
``w_y = phi' sin(theta) cos(psi) - theta' sin(psi)``
``w_z = phi' cos(theta) + psi'``

and on the fixed axes:

``w_xi   = theta' cos(phi) + psi' sin(theta) sin(phi)``
``w_eta  = theta' sin(phi) - psi' sin(theta) cos(phi)``
``w_zeta = phi' + psi' cos(theta)``

Both are checked in the tests against finite differences of ``R``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError
from .rotations import euler_zxz

__all__ = [
    "angular_acceleration_body",
    "angular_acceleration_fixed",
    "angular_velocity_body",
    "angular_velocity_fixed",
    "gyroscopic_moment",
]


def angular_velocity_body(
    theta: ArrayLike, psi: ArrayLike, dphi: ArrayLike, dtheta: ArrayLike, dpsi: ArrayLike
) -> NDArray[np.float64]:
    """Angular velocity (rad/s) in body axes, shape (..., 3)."""
    th, ps = np.asarray(theta, float), np.asarray(psi, float)
    dphi, dth, dps = (np.asarray(x, float) for x in (dphi, dtheta, dpsi))
    wx = dphi * np.sin(th) * np.sin(ps) + dth * np.cos(ps)
    wy = dphi * np.sin(th) * np.cos(ps) - dth * np.sin(ps)
    wz = dphi * np.cos(th) + dps
    return np.stack(np.broadcast_arrays(wx, wy, wz), axis=-1)


def angular_velocity_fixed(
    phi: ArrayLike, theta: ArrayLike, dphi: ArrayLike, dtheta: ArrayLike, dpsi: ArrayLike
) -> NDArray[np.float64]:
    """Angular velocity (rad/s) in fixed axes (xi, eta, zeta), shape (..., 3)."""
    ph, th = np.asarray(phi, float), np.asarray(theta, float)
    dph, dth, dps = (np.asarray(x, float) for x in (dphi, dtheta, dpsi))
    wxi = dth * np.cos(ph) + dps * np.sin(th) * np.sin(ph)
    weta = dth * np.sin(ph) - dps * np.sin(th) * np.cos(ph)
    wzeta = dph + dps * np.cos(th)
    return np.stack(np.broadcast_arrays(wxi, weta, wzeta), axis=-1)


def angular_acceleration_body(
    theta: ArrayLike,
    psi: ArrayLike,
    dphi: ArrayLike,
    dtheta: ArrayLike,
    dpsi: ArrayLike,
    ddphi: ArrayLike = 0.0,
    ddtheta: ArrayLike = 0.0,
    ddpsi: ArrayLike = 0.0,
) -> NDArray[np.float64]:
    """Time derivative of :func:`angular_velocity_body` (rad/s^2), shape (..., 3).

    The derivative of body-frame components equals the body-frame components of the
    absolute angular acceleration (``omega x omega = 0``).
    """
    th, ps = np.asarray(theta, float), np.asarray(psi, float)
    a, b, c = (np.asarray(x, float) for x in (dphi, dtheta, dpsi))
    aa, bb, cc = (np.asarray(x, float) for x in (ddphi, ddtheta, ddpsi))
    s_t, c_t, s_p, c_p = np.sin(th), np.cos(th), np.sin(ps), np.cos(ps)
    ax = aa * s_t * s_p + a * b * c_t * s_p + a * c * s_t * c_p + bb * c_p - b * c * s_p
    ay = aa * s_t * c_p + a * b * c_t * c_p - a * c * s_t * s_p - bb * s_p - b * c * c_p
    az = aa * c_t - a * b * s_t + cc
    return np.stack(np.broadcast_arrays(ax, ay, az), axis=-1)


def angular_acceleration_fixed(
    phi: ArrayLike,
    theta: ArrayLike,
    psi: ArrayLike,
    dphi: ArrayLike,
    dtheta: ArrayLike,
    dpsi: ArrayLike,
    ddphi: ArrayLike = 0.0,
    ddtheta: ArrayLike = 0.0,
    ddpsi: ArrayLike = 0.0,
) -> NDArray[np.float64]:
    """Time derivative of :func:`angular_velocity_fixed` (rad/s^2), shape (..., 3).

    ``d(w_fixed)/dt = R d(w_body)/dt`` because ``R' w_body = W R w_body = w x w = 0``.
    """
    a = angular_acceleration_body(theta, psi, dphi, dtheta, dpsi, ddphi, ddtheta, ddpsi)
    return _body_to_fixed(phi, theta, psi, a)


def _body_to_fixed(
    phi: ArrayLike, theta: ArrayLike, psi: ArrayLike, v: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Fixed-frame components of body-frame vectors ``v`` (..., 3): ``R v``."""
    return (euler_zxz(phi, theta, psi) @ v[..., None])[..., 0]


def gyroscopic_moment(
    inertia: ArrayLike,
    phi: ArrayLike,
    theta: ArrayLike,
    psi: ArrayLike,
    dphi: ArrayLike,
    dtheta: ArrayLike,
    dpsi: ArrayLike,
    ddphi: ArrayLike = 0.0,
    ddtheta: ArrayLike = 0.0,
    ddpsi: ArrayLike = 0.0,
    *,
    frame: str = "body",
) -> NDArray[np.float64]:
    """Moment (N m) that makes a rigid body follow the given Euler-angle motion.

    ``M = dH/dt = J w' + w x (J w)`` in body axes (Euler's equations), with ``J`` the
    inertia tensor about the fixed point in body axes (kg m^2). This is the gyroscopic
    moment of a nutating gear (paper 000 Eq. 7, ``L_1``, ``L_3``); the moment the gear
    exerts on its supports is its negative.

    Parameters
    ----------
    inertia : array_like, shape (3, 3) or (3,)
        Inertia tensor in body axes, or its principal values ``(J_x, J_y, J_z)``.
    phi, theta, psi, dphi, dtheta, dpsi, ddphi, ddtheta, ddpsi : array_like
        Euler angles (rad) and their first and second time derivatives.
    frame : {"body", "fixed"}
        Axes in which the moment is returned.

    Returns
    -------
    ndarray, shape (..., 3)
    """
    J = np.asarray(inertia, dtype=float)
    if J.shape == (3,):
        J = np.diag(J)
    if J.shape != (3, 3) or not np.allclose(J, J.T):
        raise ReducerlabError("inertia must be a symmetric 3x3 tensor or 3 principal values")
    w = angular_velocity_body(theta, psi, dphi, dtheta, dpsi)
    dw = angular_acceleration_body(theta, psi, dphi, dtheta, dpsi, ddphi, ddtheta, ddpsi)
    Jw = w @ J.T
    M = dw @ J.T + np.cross(w, Jw)
    if frame == "body":
        return M
    if frame == "fixed":
        return _body_to_fixed(phi, theta, psi, M)
    raise ReducerlabError(f"frame must be 'body' or 'fixed', got {frame!r}")
