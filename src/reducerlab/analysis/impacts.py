"""Tooth separation and impacts along a mesh line: how gear-rattle results are reported.

A mesh line with half backlash ``b`` is in one of three states at each instant, read
from its deflection ``delta = G q - e`` (m):

* drive-side contact, ``delta > b`` (the loaded flanks touch);
* separated, ``|delta| <= b`` (inside the backlash: no elastic force);
* back-side contact, ``delta < -b`` (the opposite flanks touch);

with ``delta`` taken positive on the loaded side (``side``).

Over the sampled steady motion this module counts the time share of each state, the
contact losses (drive-side contact -> separated) and the back-side impacts (entries
into back-side contact) per forcing period, and names the impact class of the
gear-rattle literature (Kahraman and Singh, J. Sound Vib. 142, 1990, 49-75): *no
impact* (the teeth never separate), *single-sided impact* (they separate and re-engage
on the drive side only) and *double-sided impact* (they also strike the back side).
A line without backlash (``b = 0``) cannot separate: its model force stays linear.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError

__all__ = ["IMPACT_CLASSES", "ContactStates", "contact_states"]

#: The impact classes, in order of severity.
IMPACT_CLASSES = ("no impact", "single-sided impact", "double-sided impact")


@dataclass(frozen=True)
class ContactStates:
    """Contact states of a mesh line over a steady motion.

    Attributes
    ----------
    separation_fraction : float
        Share of the time with the teeth apart, ``|delta| <= b`` (0..1).
    back_contact_fraction : float
        Share of the time in back-side contact, ``delta < -b`` (0..1).
    contact_losses : float
        Drive-side contact losses per forcing period.
    back_impacts : float
        Entries into back-side contact per forcing period.
    impact_class : str
        One of :data:`IMPACT_CLASSES`.
    """

    separation_fraction: float
    back_contact_fraction: float
    contact_losses: float
    back_impacts: float
    impact_class: str


def _share_above(d0: NDArray, d1: NDArray, h: float) -> NDArray:
    """Share of each interval on which the straight line from ``d0`` to ``d1`` lies
    above ``h``."""
    lo, hi = np.minimum(d0, d1), np.maximum(d0, d1)
    with np.errstate(divide="ignore", invalid="ignore"):
        part = np.clip((hi - h) / (hi - lo), 0.0, 1.0)
    return np.where(lo > h, 1.0, np.where(hi <= h, 0.0, part))


def contact_states(
    delta: NDArray[np.float64],
    half_backlash: float,
    periods: float,
    side: float = 1.0,
    times: NDArray[np.float64] | None = None,
) -> ContactStates:
    """Contact states of a sampled mesh deflection.

    The time shares take the deflection as linear between samples (the crossing of a
    backlash boundary is placed inside its interval, not at a sample: error O(h^2) in
    the sampling interval h instead of O(h)); the counts of contact losses and back-side
    impacts are changes of state between samples.

    Parameters
    ----------
    delta : ndarray
        Mesh deflection ``G q - e`` (m) at samples of the steady motion, in time order
        (for example every integration step of the last periods).
    half_backlash : float
        ``b`` (m), >= 0.
    periods : float
        Forcing periods the samples span (> 0), for the per-period counts.
    side : {1, -1}
        Sign of the deflection on the drive (loaded) side: -1 when the mean load presses
        the flanks of negative deflection together (``response`` takes the sign of the
        mean elastic force).
    times : ndarray, optional
        Sample times (s), increasing; equally spaced samples when omitted.

    Returns
    -------
    ContactStates
    """
    d = np.asarray(delta, dtype=float)
    if d.ndim != 1 or d.size == 0 or not np.all(np.isfinite(d)):
        raise ReducerlabError("delta: must be a non-empty 1-D array of finite deflections (m)")
    if not (np.isfinite(half_backlash) and half_backlash >= 0):
        raise ReducerlabError(f"half_backlash: must be >= 0 m, got {half_backlash!r}")
    if not (np.isfinite(periods) and periods > 0):
        raise ReducerlabError(f"periods: must be > 0, got {periods!r}")
    if side not in (1, -1, 1.0, -1.0):
        raise ReducerlabError(f"side: must be 1 or -1, got {side!r}")
    if half_backlash == 0.0:
        return ContactStates(0.0, 0.0, 0.0, 0.0, IMPACT_CLASSES[0])
    d = d * side
    state = np.where(d > half_backlash, 1, np.where(d < -half_backlash, -1, 0))
    before, after = state[:-1], state[1:]
    losses = int(np.count_nonzero((before == 1) & (after != 1)))
    back = int(np.count_nonzero((before != -1) & (after == -1)))
    if d.size == 1:
        apart, behind = float(state[0] == 0), float(state[0] == -1)
    else:
        if times is None:
            w = np.ones(d.size - 1)
        else:
            t = np.asarray(times, dtype=float)
            if t.shape != d.shape or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
                raise ReducerlabError("times: must be increasing finite times (s), one per sample")
            w = np.diff(t)
        above = _share_above(d[:-1], d[1:], half_backlash)
        below = _share_above(-d[:-1], -d[1:], half_backlash)
        total = float(w.sum())
        behind = float(w @ below) / total
        apart = max(0.0, 1.0 - float(w @ above) / total - behind)
    if np.any(state == -1):
        cls = IMPACT_CLASSES[2]
    elif np.any(state == 0):
        cls = IMPACT_CLASSES[1]
    else:
        cls = IMPACT_CLASSES[0]
    return ContactStates(apart, behind, losses / periods, back / periods, cls)


def mesh_mode(s, line: int) -> tuple[float, float]:
    """The natural frequency (Hz) of the mode that strains mesh line ``line`` most, and
    that mode's share of its strain energy in the line (0..1).

    Modes of the mean system ``(K_mean, M)`` (teeth in contact, mean stiffness); the share
    is ``k_m (G_m phi)^2 / (phi^T K_mean phi)``. For a single mesh on one relative
    coordinate this is ``sqrt(k_m / m_e) / 2 pi``, the ``omega_n`` of the gear-dynamics
    literature (paper 004: ``sqrt(k_m / M_VH)``); the forcing frequency over it is the
    ``omega-bar`` of dimensionless studies.
    """
    import scipy.linalg

    from ..model.laws import flat_mean

    K = s.mean_stiffness
    lam, V = scipy.linalg.eigh(K, s.M)
    k_line = abs(flat_mean(int(s.k_kind[line]), s.k_params[line]))
    strain = k_line * (s.G[line] @ V) ** 2
    total = np.einsum("ij,ik,kj->j", V, K, V)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(total > 0, strain / total, 0.0)
    i = int(np.argmax(share))
    return float(np.sqrt(max(lam[i], 0.0)) / (2 * np.pi)), float(share[i])
