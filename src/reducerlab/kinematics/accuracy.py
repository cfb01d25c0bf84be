"""Rigid (unloaded) transmission error of one gear mesh from manufacturing errors.

Two gears A (driving) and B (driven) turn about fixed axes in the *mesh frame* (the
housing for a gear pair, the carrier for a planetary mesh) through the angles
``phi_A``, ``phi_B`` (rad, counter-clockwise positive). The line of centres runs from
A's axis to B's axis; the mesh frame's x axis lies along it.

**Eccentricity.** Gear i's base circle is centred ``e_i`` away from its axis, in the
direction ``psi_i = phi_i + phi0_i`` of the mesh frame (``phi0_i``: the direction at
``phi_i = 0``, counter-clockwise from the line of centres). Involute flanks stay in
contact along the common tangent of the two base circles; translating a base circle by
``c`` moves its flank along the line of action by ``c . n``, with ``n`` the unit vector
along which A pushes B. To first order in ``e / r_b`` the driven gear's flank then
leads its nominal position, along the line of action, by

``s = e_A cos(psi_A - tau) - e_B cos(psi_B - tau)``

with ``tau`` the direction angle of ``n`` (:func:`line_angle`: the drive flank's line
of action, along the driven gear's motion at the pitch point). For an external pair
whose driven gear turns clockwise ``tau = pi / 2 - alpha_w`` (``alpha_w``: working
pressure angle), so ``s = e_A sin(psi_A + alpha_w) - e_B sin(psi_B + alpha_w)``: a
sinusoid of
amplitude ``e`` (not ``e cos(alpha)``: the rotating offset projects in full on the
fixed line of action) at once per revolution of the eccentric gear.
``tests/test_transmission_accuracy.py`` checks it, external and internal, against the
exact common tangent of two eccentric base circles (second-order residual).

**Pitch deviations.** ``f_pt,k`` (m, on the reference circle, ISO 1328-1) is the
deviation of the pitch from tooth ``k`` to tooth ``k + 1``; the cumulative deviation
of tooth ``k`` is ``F_k = sum_{j<k} f_pt,j`` (``F_0 = 0``; closed: ``sum f_pt = 0``),
positive when the tooth is ahead in its gear's turning sense. One tooth pair is taken
in contact, the one nearest the pitch point (tooth ``k = round(|phi| z / 2 pi) mod z``,
tooth 0 there at ``phi = 0``): the contact ratio's sharing between pairs is the loaded
analysis's (a later piece). Along the line of action (the base circle) a deviation
counts ``cos(alpha)`` times: ``s += cos(alpha) (F_A,k - F_B,k)``.

The driven gear's angle error in its own turning sense is ``s / r_bB``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError

__all__ = [
    "GearErrors",
    "cumulative_pitch",
    "line_angle",
    "mesh_lead",
    "order_spectrum",
    "tooth_in_mesh",
]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class GearErrors:
    """Manufacturing errors of one gear.

    Attributes
    ----------
    teeth : int
        Number of teeth ``z``.
    eccentricity : float
        ``e`` (m): offset of the base circle's centre from the axis (half the radial
        runout ``F_r`` of a gear whose runout is all eccentricity).
    phase : float
        ``phi0`` (rad): its direction at zero rotation, from the line of centres.
    pitch : tuple of float
        Single pitch deviations ``f_pt,k`` (m), ``z`` of them, or none.
    """

    teeth: int
    eccentricity: float = 0.0
    phase: float = 0.0
    pitch: tuple[float, ...] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        if isinstance(self.teeth, bool) or not isinstance(self.teeth, int) or self.teeth < 1:
            raise ReducerlabError(f"teeth: must be an integer >= 1; got {self.teeth!r}")
        if not (math.isfinite(self.eccentricity) and self.eccentricity >= 0):
            raise ReducerlabError(f"eccentricity: must be >= 0 (m); got {self.eccentricity!r}")
        if not math.isfinite(self.phase):
            raise ReducerlabError(f"phase: must be finite (rad); got {self.phase!r}")
        if self.pitch and len(self.pitch) != self.teeth:
            raise ReducerlabError(
                f"pitch: {len(self.pitch)} single pitch deviations for {self.teeth} teeth; "
                "give one per tooth or none"
            )
        cumulative_pitch(self.pitch)  # checks closure


def cumulative_pitch(single: ArrayLike) -> Array:
    """Cumulative pitch deviations ``F_k = sum_{j<k} f_pt,j`` (m), ``F_0 = 0``.

    Raises
    ------
    ReducerlabError
        Values not finite, or not closed (``|sum f_pt|`` above ``1e-6`` of
        ``sum |f_pt|``): the pitches of a gear add up to its circumference.
    """
    f = np.asarray(single, float).ravel()
    if not np.all(np.isfinite(f)):
        raise ReducerlabError("pitch deviations: must be finite (m)")
    if f.size and abs(f.sum()) > 1e-6 * np.abs(f).sum():
        raise ReducerlabError(
            f"pitch deviations: add up to {f.sum() * 1e6:.4g} um, not 0; the single pitch "
            "deviations of a whole gear close (their sum is zero)"
        )
    return np.concatenate([[0.0], np.cumsum(f)[:-1]]) if f.size else f


def tooth_in_mesh(angle: ArrayLike, teeth: int) -> NDArray[np.int64]:
    """Index of the tooth nearest the pitch point, ``round(|phi| z / 2 pi) mod z``."""
    phi = np.abs(np.asarray(angle, float))
    return np.mod(np.floor(phi * teeth / (2 * math.pi) + 0.5).astype(np.int64), teeth)


def line_angle(turning_b: int, internal: bool, working_pressure_angle: float) -> float:
    """Direction ``tau`` (rad, from the line of centres A -> B) along which A's drive
    flank pushes B: the line of action, tangent to both base circles, in the sense of
    B's motion at the pitch point.

    External pair: ``tau = -sigma_B (pi / 2 - alpha_w)``; internal pair (A the ring,
    B the pinion inside it, the pitch point beyond B): ``tau = sigma_B (pi / 2 +
    alpha_w)``; ``sigma_B = +1`` when B turns counter-clockwise in the mesh frame, -1
    clockwise. (The driven flank faces back along ``n``; its involute's centre of
    curvature, the base circle's tangent point, lies ahead of the contact along ``n``,
    which picks the one of the two tangents.)
    """
    if turning_b not in (1, -1):
        raise ReducerlabError(f"turning_b: must be +1 or -1; got {turning_b!r}")
    if not 0 < working_pressure_angle < math.pi / 2:
        raise ReducerlabError(
            f"working pressure angle: must be in (0, 90) deg; got {working_pressure_angle!r}"
        )
    if internal:
        return turning_b * (math.pi / 2 + working_pressure_angle)
    return -turning_b * (math.pi / 2 - working_pressure_angle)


def _terms(g: GearErrors, angle: Array, tau: float, cos_alpha: float) -> Array:
    out = g.eccentricity * np.cos(angle + g.phase - tau)
    if g.pitch:
        out = out + cos_alpha * cumulative_pitch(g.pitch)[tooth_in_mesh(angle, g.teeth)]
    return out


def mesh_lead(
    angle_a: ArrayLike,
    angle_b: ArrayLike,
    gear_a: GearErrors,
    gear_b: GearErrors,
    line_angle: float,
    pressure_angle: float,
) -> Array:
    """Lead ``s`` (m) of the driven gear B's flank along the line of action.

    ``s = e_A cos(phi_A + phi0_A - tau) - e_B cos(phi_B + phi0_B - tau)
    + cos(alpha) (F_A,kA - F_B,kB)`` (module docstring).

    Parameters
    ----------
    angle_a, angle_b : array_like
        Rotations ``phi_A``, ``phi_B`` (rad) of the gears in the mesh frame.
    gear_a, gear_b : GearErrors
    line_angle : float
        ``tau`` (rad): direction along which A pushes B, from the line of centres.
    pressure_angle : float
        ``alpha`` (rad) of the reference circle, where the pitch is measured.
    """
    a = np.asarray(angle_a, float)
    b = np.asarray(angle_b, float)
    c = math.cos(pressure_angle)
    return _terms(gear_a, a, line_angle, c) - _terms(gear_b, b, line_angle, c)


def order_spectrum(error: ArrayLike) -> tuple[NDArray[np.int64], Array]:
    """One-sided amplitude spectrum of a periodic signal sampled evenly over a period.

    Returns orders ``k = 0 .. N/2`` and amplitudes ``|X_k| / N`` times 2 (1 at ``k = 0``
    and at the Nyquist order of even ``N``), so that ``A cos(k x + p)`` gives ``A``.
    """
    x = np.asarray(error, float)
    n = x.size
    if n < 4:
        raise ReducerlabError(f"spectrum: needs at least 4 samples; got {n}")
    amp = np.abs(np.fft.rfft(x)) / n
    amp[1:] *= 2.0
    if n % 2 == 0:
        amp[-1] /= 2.0
    return np.arange(amp.size), amp
