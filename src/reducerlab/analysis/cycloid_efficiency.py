"""Friction loss and efficiency of the cycloid-ball drive's ball track (issue 31).

Each loaded contact line of a ball (``contact.ball_track``: the ball squeezed along its
normal line between the centre disc's groove wall and the planetary disc's, at the
contact angle ``beta`` out of the disc plane) is two Hertz contacts at the two ends of a
diameter. Their relative motion follows from the kinematics (``docs/efficiency.md``,
"Cycloid-ball drive: spin of the rolling balls"), in the frame of the eccentric, where
the centre disc turns at ``W_2 = omega_c - omega_in`` about its axis ``O``, the
planetary disc at ``W_3 = omega_p - omega_in`` about ``(0, e)``, and the ball set at
``d psi / dt = (z_c / Z) W_2`` (``= (z_p / Z) W_3``):

* **spin**: the ball's angular velocity along its contact line is free; by symmetry of
  the two (nearly equal) contacts it settles half way, so each contact spins at
  ``omega_s = Omega_rel . n / 2 = (omega_c - omega_p) sin(beta) / 2``;
* **differential sliding** along the groove: pure rolling at both ends of the diameter
  needs the ball centre to move at the mean of the two walls' speeds at the contact
  points. The grooves place the ball (it follows the tangency of the two trochoids),
  and the residual ``S = u_2 + u_3 + sigma r_b cos(beta) (omega_c - omega_p)`` (``u_k``:
  the ball centre's speed along the common tangent relative to disc ``k``, ``sigma =
  +1`` for line ``+``, ``-1`` for line ``-``) is not zero: ``u_2 : u_3 = -z_p : z_c``
  while ``2 r_b cos(beta)`` is the offset of the two contact points. Each contact
  slides by ``S / 2`` along the groove (the symmetric split of the two equal
  contacts).

A contact in full slip loses ``integral mu p |v| dA`` (``contact.spin_friction``:
sliding and spin together; ``(3 pi / 16) mu F a omega_s`` in pure spin of a circle,
``mu F |S| / 2`` in pure sliding). The drive loss ``P_V`` is the sum over the loaded
lines (forces from ``ball_loads``) averaged over the ball-set phases of one ball
pitch; ``eta = 1 - P_V / P_0``, ``P_0 = T_out |omega_out|`` (``analysis.efficiency``).
The result is an :class:`~reducerlab.analysis.efficiency.EfficiencyResult` with one
"pair" (the ball track).

Out of scope: the cross-ball equal-speed mechanism, the eccentric and support bearings,
rolling (hysteresis, EHL film) resistance, churning.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..results import provenance
from .efficiency import DEFAULT_MU, EfficiencyResult, load_grid

__all__ = ["ball_track_motion", "cycloid_efficiency", "cycloid_friction_coefficient"]

Array = NDArray[np.float64]


def cycloid_friction_coefficient(design: Any, mu: float | None) -> float:
    """``mu`` if given, else ``cycloid_pair.friction_coefficient``, else
    :data:`~reducerlab.analysis.efficiency.DEFAULT_MU` (the Coulomb coefficient of the
    spinning and sliding ball contacts), checked."""
    from ..contact.friction import check_friction_coefficient

    if mu is not None:
        return check_friction_coefficient(mu)
    value = getattr(design.cycloid_pair, "friction_coefficient", None)
    if value is None:
        return DEFAULT_MU
    return check_friction_coefficient(value, "cycloid_pair.friction_coefficient")


def ball_track_motion(design: Any, phase: float, omega_in: float) -> tuple[Array, float]:
    """Sliding along the groove and spin of each ball's contacts (module docstring).

    Parameters
    ----------
    design : CycloidBallDesign
    phase : float
        Ball-set phase ``psi_0`` (rad).
    omega_in : float
        Input (eccentric) speed (rad/s).

    Returns
    -------
    slip : ndarray
        ``S`` (m/s) of lines ``+`` and ``-`` of each ball, shape ``(Z, 2)``: the sum of
        the two contacts' sliding speeds along the groove,
        ``u_2 + u_3 + sigma r_b cos(beta) (omega_c - omega_p)``.
    relative_spin : float
        ``(omega_c - omega_p) sin(beta)`` (rad/s), the two discs' relative angular
        velocity along a contact line (each contact spins at half of it).
    """
    track = design.ball_track()
    s = design.kinematics().speeds(omega_in)
    wc, wp = s["centre disc"], s["planetary disc"]
    w2, w3 = wc - omega_in, wp - omega_in
    e, rb, beta = track.eccentricity, track.ball_radius, track.contact_angle
    Z, Rb = track.balls, track.ball_circle_radius
    psi = float(phase) + 2 * math.pi * np.arange(Z) / Z
    cx, cy = Rb * np.sin(psi), e / 2 - Rb * np.cos(psi)  # ball centres about O
    dpsi = track.centre_lobes / Z * w2
    vx, vy = Rb * np.cos(psi) * dpsi, Rb * np.sin(psi) * dpsi
    mx, my = cx, cy + track.pitch_radius  # from the pitch point P = (0, -r_2)
    norm = np.hypot(mx, my)
    tx, ty = -my / norm, mx / norm  # common tangent z x m
    u2 = (vx + w2 * cy) * tx + (vy - w2 * cx) * ty
    u3 = (vx + w3 * (cy - e)) * tx + (vy - w3 * cx) * ty
    rel = wc - wp
    roll = rb * math.cos(beta) * rel
    return np.stack([u2 + u3 + roll, u2 + u3 - roll], axis=1), rel * math.sin(beta)


def _unit_contacts(track: Any, phase: float) -> Array:
    """``(a, b, p0)`` of every contact at unit force (m, m, Pa; they scale with
    ``F^(1/3)``), shape ``(Z, 2, 2, 3)``: ball, line, wall; NaN where undercut."""
    from ..contact.hertz import hertz_elliptic

    ab = track.contact_curvatures(phase)
    out = np.full((*ab.shape[:3], 3), np.nan)
    for idx in np.ndindex(*ab.shape[:3]):
        A, B = ab[idx]
        if np.isfinite(A):
            h = hertz_elliptic(1.0, A, B, track.contact_modulus)
            out[idx] = (h.a, h.b, h.p0)
    return out


def _phase_loss(
    force: Array, unit: Array, slip: Array, spin: float, mu: float
) -> tuple[float, float, float]:
    """Full-slip friction power (W) of the loaded lines at one phase; with the pure-spin
    ``sum 2 M |spin| / 2`` and pure-sliding ``sum mu F |S|`` parts for comparison."""
    from ..contact.spin_friction import full_slip_power, spin_moment

    on = force > 0
    if not np.any(on):
        return 0.0, 0.0, 0.0
    F = force[on]
    c = unit[on]  # (n, wall, 3)
    scale = np.cbrt(F)[:, None]
    a, b, p0 = c[..., 0] * scale, c[..., 1] * scale, c[..., 2] * scale
    half = np.zeros((*a.shape, 2))
    half[..., 0] = 0.5 * slip[on][:, None]  # along the groove: the contact's x (A) axis
    total = float(full_slip_power(a, b, p0, half, 0.5 * spin, mu).sum())
    spin_only = float(spin_moment(a, b, p0, mu).sum()) * 0.5 * abs(spin)
    slide_only = float(mu * np.sum(F * np.abs(slip[on])))
    return total, spin_only, slide_only


def cycloid_efficiency(
    design: Any,
    *,
    mu: float | None = None,
    torques: Sequence[float] | None = None,
    loads: int = 4,
    top: float = 1.5,
    speeds: Sequence[float] | None = None,
    phases: int = 8,
) -> EfficiencyResult:
    """Ball-track friction loss and efficiency of a cycloid-ball drive against torque.

    Parameters
    ----------
    design : CycloidBallDesign
        With the ball-track fields of ``[cycloid_pair]`` and a load.
    mu : float, optional
        Coulomb coefficient of the ball contacts in ``[0, 0.3]``; default
        ``cycloid_pair.friction_coefficient``, else 0.05.
    torques : sequence of float, optional
        Torques on the centre disc (N m, > 0); default ``loads`` torques from ``top /
        loads`` to ``top`` times the design's.
    loads, top : int, float
        As above (``loads`` in 1..41, ``top`` in (0, 3]).
    speeds : sequence of float, optional
        Input speeds (rad/s) of ``loss_at_speed``; default the design's.
    phases : int
        Ball-set phases over one ball pitch (1..360).

    Returns
    -------
    EfficiencyResult
        One pair (the ball track); ``position`` is the ball-set phase; extra variables
        ``spin_loss`` and ``slide_loss`` (torque; W): the pure-spin and pure-sliding
        parts taken alone.

    Raises
    ------
    ReducerlabError
        Not a cycloid-ball design, a bad coefficient, torque, speed or phase count, a
        design without load, speed or ball-track fields.
    """
    from ..contact.ball_track import ball_loads
    from ..drives.cycloid_ball import centre_disc_torque

    t0 = time.perf_counter()
    if getattr(design, "type", None) != "cycloid_ball":
        raise ReducerlabError(
            f"design: the ball-track efficiency needs a cycloid_ball design; got type = "
            f"{getattr(design, 'type', None)!r}"
        )
    mu = cycloid_friction_coefficient(design, mu)
    if isinstance(phases, bool) or not isinstance(phases, int) or not 1 <= phases <= 360:
        raise ReducerlabError(f"phases: must be an integer in 1..360; got {phases!r}")
    point = design.operating_point()
    speed0 = float(design.operating_speed or 0.0)
    if not speed0:
        raise ReducerlabError("input_speed: the design has no input speed for the losses")
    if not point.output_torque:
        raise ReducerlabError("output_torque: the design gives no load (output torque or power)")
    track = design.ball_track()
    ref = centre_disc_torque(design)
    T, W = load_grid(ref, torques, loads, top, speeds, speed0)
    scale = T / ref
    ph = 2 * math.pi / track.balls * np.arange(phases) / phases
    loss = np.zeros((T.size, phases))
    spin_loss, slide_loss = np.zeros_like(loss), np.zeros_like(loss)
    vmax = np.zeros(phases)
    for j, p in enumerate(ph):
        slip, spin = ball_track_motion(design, float(p), speed0)
        unit = _unit_contacts(track, float(p))
        for i, t in enumerate(T):
            force = ball_loads(track, float(t), float(p)).force
            loss[i, j], spin_loss[i, j], slide_loss[i, j] = _phase_loss(force, unit, slip, spin, mu)
            if i == T.size - 1 and np.any(force > 0):
                vmax[j] = 0.5 * float(np.abs(slip[force > 0]).max())
    mesh_loss = loss.mean(axis=1)
    s = design.kinematics().speeds(speed0)
    rolling = T * abs(s["centre disc"] - speed0)  # the centre disc's power in the eccentric frame
    p_out = point.power * scale
    ds = xr.Dataset(
        {
            "loss": (("pair", "torque", "position"), loss[None], {"units": "W"}),
            "mesh_loss": (("pair", "torque"), mesh_loss[None], {"units": "W"}),
            "rolling_power": (("pair", "torque"), rolling[None], {"units": "W"}),
            "mesh_efficiency": (("pair", "torque"), (1.0 - mesh_loss / rolling)[None]),
            "output_power": ("torque", p_out, {"units": "W"}),
            "output_torque": ("torque", abs(point.output_torque) * scale, {"units": "N m"}),
            "efficiency": ("torque", 1.0 - mesh_loss / p_out),
            "loss_at_speed": (("torque", "speed"), mesh_loss[:, None] * W[None, :] / speed0,
                              {"units": "W"}),
            "sliding_speed": (("pair", "position"), vmax[None], {"units": "m/s"}),
            "pair_torque": (("pair", "torque"), T[None], {"units": "N m"}),
            "spin_loss": ("torque", spin_loss.mean(axis=1), {"units": "W"}),
            "slide_loss": ("torque", slide_loss.mean(axis=1), {"units": "W"}),
        },
        coords={
            "pair": [1],
            "torque": ("torque", T, {"units": "N m"}),
            "position": np.arange(phases),
            "speed": ("speed", W, {"units": "rad/s"}),
        },
        attrs={"title": "Ball-track friction loss and efficiency",
               **provenance(design.provenance)},
    )  # fmt: skip
    ds.attrs.update(mu=mu, input_speed_rad_s=speed0, design_torque=float(ref),
                    ratio=abs(float(design.kinematics().ratio)), rigid=0,
                    model="ball track: spin and differential sliding, full slip",
                    seconds=time.perf_counter() - t0)  # fmt: skip
    return EfficiencyResult(ds)
