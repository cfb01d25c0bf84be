"""What a steady motion is: its period from the Poincaré points, its class (period-n,
quasi-periodic, chaotic, still unsettled), whether two runs hold the same attractor,
the spectral peaks of a signal as multiples of the forcing frequency, and the windowed
spectrum the figures draw."""

from __future__ import annotations

import itertools
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError

__all__ = [
    "COEXIST_TOL",
    "SETTLE",
    "Spectrum",
    "attractor_scale",
    "classify",
    "coinciding_period",
    "different_attractors",
    "period_of",
    "spectrum_peaks",
    "windowed_spectrum",
]


#: Two runs hold different attractors when their motion classes differ or their mean
#: Poincaré deflections differ by more than this share of the largest Poincaré spread
#: (:func:`different_attractors`).
COEXIST_TOL = 0.02


def attractor_scale(points: NDArray) -> float:
    """The size against which mean Poincaré deflections are compared: the largest spread
    of a Poincaré sequence (last axis) in ``points``, at least 1e-3 of the largest mean."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: diverged runs
        if not np.any(np.isfinite(points)):
            return 1e-300
        spread = float(np.nanmax(np.ptp(points, axis=-1)))
        mean = float(np.nanmax(np.abs(np.nanmean(points, axis=-1))))
    spread = spread if np.isfinite(spread) else 0.0
    return max(spread, 1e-3 * mean, 1e-300)


def different_attractors(
    a: NDArray, labels_a: Any, b: NDArray, labels_b: Any, size: float
) -> NDArray[np.bool_]:
    """Rows of Poincaré points ``a``, ``b`` (..., point) with their motion classes that
    belong to different attractors: different classes, or mean deflections apart by more
    than :data:`COEXIST_TOL` ``* size``."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: diverged runs
        apart = np.abs(np.nanmean(a, axis=-1) - np.nanmean(b, axis=-1)) > COEXIST_TOL * size
    return (np.asarray(labels_a, object) != np.asarray(labels_b, object)) | apart


def coinciding_period(
    points: NDArray, sizes: NDArray, tol: float = 1e-4, max_period: int = 12
) -> int:
    """The period n of Poincaré points that coincide every n points to within ``tol`` of
    the orbit's size (a period-n orbit whose spread is round-off or integration error
    against the motion), 0 when they do not: every n-th point (each of the n classes)
    spreads over less than ``tol`` times the size, so that a slow drift whose steps are
    small but whose course is not does not pass.

    Parameters
    ----------
    points : ndarray
        The Poincaré points (n_points, n_coordinates), e.g. deflection and velocity.
    sizes : ndarray
        The orbit's size per coordinate (n_coordinates,), e.g. the peak-to-peak of the
        phase trajectory; a spread below ``tol`` times it is invisible on axes that show
        the orbit.
    tol : float
        The share of the orbit's size below which points coincide.
    max_period : int
        The longest period looked for.

    Returns
    -------
    int
        The smallest such n <= ``max_period``, or 0.
    """
    pts = np.atleast_2d(np.asarray(points, float))
    if pts.shape[0] == 1:
        pts = pts.T
    size = np.maximum(np.asarray(sizes, float), 1e-300)
    if not np.all(np.isfinite(pts)) or pts.shape[0] < 2:
        return 0
    for n in range(1, min(max_period, pts.shape[0] - 1) + 1):
        if all(np.all(np.ptp(pts[k::n], axis=0) <= tol * size) for k in range(n)):
            return n
    return 0


def period_of(row: NDArray, tol: float, max_period: int) -> int:
    span = max(np.ptp(row), np.abs(row).max(), 1e-300)
    for n in range(1, max_period + 1):
        if np.all(np.abs(row[n:] - row[:-n]) <= tol * span):
            return n
    return 0


def classify(
    poincare: NDArray[np.float64],
    exponent: float,
    frequency: float,
    *,
    tol: float = 1e-3,
    max_period: int = 12,
    chaos: float = 0.01,
) -> str:
    """Label a steady motion from its Poincaré points and largest Lyapunov exponent.

    ``"chaotic"`` when the exponent exceeds ``chaos`` x the forcing frequency (1/s per
    Hz: a separation growing by e within ~100 periods), else ``"period-n"`` when the
    Poincaré sequence repeats every n <= ``max_period`` points (to ``tol`` of its
    range), else ``"unsettled"`` when the points still converge (:func:`_converging`:
    their spread, or for some n <= ``max_period`` their n-step differences
    ``|x[k+n] - x[k]|``, shrink from quarter to quarter of the sequence, the last below
    :data:`SETTLE` times the first, and the sequence is a periodic orbit plus decaying
    modes, not a slow drift along a closed curve: a transient of a lightly damped mode
    towards a fixed point or a period-n orbit, not an attractor; run more periods), else
    ``"quasi-periodic"``.
    """
    if exponent > chaos * frequency:
        return "chaotic"
    pts = np.asarray(poincare, float)
    n = period_of(pts, tol, max_period)
    if n:
        return f"period-{n}"
    if pts.size >= 16 and _converging(pts, max_period, tol):
        return "unsettled"
    return "quasi-periodic"


def _converging(pts: NDArray, max_period: int, tol: float = 1e-3) -> bool:
    """Whether a Poincaré sequence still converges.

    Two conditions, both needed:

    1. it shrinks: the spread of its quarters (a transient towards a fixed point), or
       for some n <= ``max_period`` the largest n-step difference ``|x[k+n] - x[k]|`` in
       each quarter (towards a period-n orbit), shrinks from quarter to quarter, the
       last below :data:`SETTLE` times the first;
    2. it is a periodic orbit plus decaying modes: with its decaying part removed
       (:func:`_decaying_part`: the modes ``c z**k`` of a linear-prediction fit with
       ``|z| < SETTLE**(1 / (2 (N - 1)))``) it repeats every n <= ``max_period`` points
       to ``tol`` of its range (the test of period-n in :func:`classify`).

    A transient towards a fixed point or a period-n orbit is that orbit plus modes
    decaying geometrically (roots inside the unit circle); a quasi-periodic sequence
    ``f(theta0 + 2 pi rho k)`` is a sum of undamped modes ``exp(i 2 pi m rho k)`` (roots
    on the unit circle) and stays aperiodic with any decaying modes removed. Near a
    rational rotation number p/n its points drift slowly along the curve and the n-step
    differences can shrink over the window (where the drift nears an extremum of the
    curve, or slows near the ghost of a period-n orbit at the edge of its locking
    tongue): condition 1 alone called such sequences unsettled (issue 26). The root
    bound is looser than what condition 1 can see (a mode losing ``1 - SETTLE`` over
    three quarters of the window has ``|z|`` below it), so a transient condition 1
    detects has all its decay in the decaying part. A drift over a short stretch of a
    curve rich in harmonics can still pass both (more kept points resolve it).
    """
    if not _shrinking(pts, max_period):
        return False
    if not np.all(np.isfinite(pts)):
        return True
    span = max(float(np.ptp(pts)), float(np.abs(pts).max()), 1e-300)
    try:
        rest = pts - _decaying_part(pts)
    except np.linalg.LinAlgError:  # no fit: keep condition 1
        return True
    return any(np.all(np.abs(rest[n:] - rest[:-n]) <= tol * span) for n in range(1, max_period + 1))


def _shrinking(pts: NDArray, max_period: int) -> bool:
    """Condition 1 of :func:`_converging`."""

    def shrinking(q: list[float]) -> bool:
        return q[3] < SETTLE * q[0] and all(a >= b for a, b in itertools.pairwise(q))

    if shrinking([float(np.ptp(part)) for part in np.array_split(pts, 4)]):
        return True
    for n in range(1, max_period + 1):
        diff = np.abs(pts[n:] - pts[:-n])
        if diff.size >= 8 and shrinking([float(part.max()) for part in np.array_split(diff, 4)]):
            return True
    return False


#: Singular values of the Hankel matrix below this share of the largest are noise
#: (:func:`_decaying_part`).
_RANK_TOL = 1e-7


def _decaying_part(pts: NDArray) -> NDArray:
    """The decaying modes of a sequence ``x_k`` (k = 0..N-1): fit ``x_k = sum_i c_i
    z_i**k`` by the matrix-pencil method (Hankel matrix of N/2 + 1 columns, its rank
    from the singular values above :data:`_RANK_TOL` of the largest, the roots ``z_i``
    as the eigenvalues of the shifted signal subspace, the amplitudes ``c_i`` by least
    squares) and return the sum over the modes with ``|z_i| < SETTLE**(1 / (2 (N -
    1)))``, those losing at least ``1 - sqrt(SETTLE)`` (~11 %) over the sequence."""
    x = np.asarray(pts, float)
    size = x.size
    cols = size // 2
    hankel = np.lib.stride_tricks.sliding_window_view(x, cols + 1)
    _, sing, vh = np.linalg.svd(hankel, full_matrices=False)
    rank = int(np.sum(sing > _RANK_TOL * sing[0]))
    if rank == 0:
        return np.zeros_like(x)
    sub = vh[:rank].conj().T
    roots = np.linalg.eigvals(np.linalg.pinv(sub[:-1]) @ sub[1:])
    # z**k, or z**(k - N + 1) where |z| > 1: no column above 1 in modulus
    k = np.arange(size)[:, None]
    with np.errstate(divide="ignore"):
        log = np.log(roots.astype(complex))
    with np.errstate(invalid="ignore", over="ignore"):
        basis = np.nan_to_num(np.exp((k - np.where(log.real > 0, size - 1, 0)) * log))
    amp = np.linalg.lstsq(basis, x.astype(complex), rcond=None)[0]
    decaying = np.abs(roots) < SETTLE ** (1 / (2 * (size - 1)))
    return (basis[:, decaying] @ amp[decaying]).real


#: A Poincaré sequence whose spread (or n-step differences) shrinks from quarter to
#: quarter, the last below this fraction of the first, and which is a periodic orbit plus
#: decaying modes, is still converging (``classify``: "unsettled", :func:`_converging`).
#: A quasi-periodic sequence fills its closed curve in every quarter (no steady
#: shrinking) or drifts along it (aperiodic with decaying modes removed); a transient
#: decaying by a factor 2 over the kept points ends at ~0.6.
SETTLE = 0.8


def spectrum_peaks(
    signal: NDArray[np.float64], dt: float, f_ref: float, count: int = 6
) -> list[tuple[float, float]]:
    """Largest spectral peaks of ``signal`` as ``(multiple of f_ref, amplitude)``, the
    labelling of paper 004 Fig. 8 ("0.48x, 0.57x, ...")."""
    if np.size(signal) < 4 or not (dt > 0 and f_ref > 0):
        raise ReducerlabError("spectrum_peaks: need >= 4 samples, dt > 0 and f_ref > 0")
    x = np.asarray(signal, float) - np.mean(signal)
    amp = 2 * np.abs(np.fft.rfft(x * np.hanning(x.size))) / np.sum(np.hanning(x.size))
    f = np.fft.rfftfreq(x.size, dt)
    peaks = [i for i in range(1, amp.size - 1) if amp[i] >= amp[i - 1] and amp[i] > amp[i + 1]]
    peaks.sort(key=lambda i: -amp[i])
    return [(float(f[i] / f_ref), float(amp[i])) for i in peaks[:count]]


@dataclass(frozen=True)
class Spectrum:
    """A one-sided amplitude spectrum for display (:func:`windowed_spectrum`).

    Attributes
    ----------
    frequency : ndarray
        Frequencies (Hz), on the zero-padded grid (``resolution / pad`` apart).
    amplitude : ndarray
        Amplitude of a sinusoid at that frequency (signal units; exact at a sinusoid's
        own frequency up to the window's scalloping, < 0.1 % with ``pad`` >= 8).
    resolution : float
        The frequency resolution ``1 / record`` (Hz): the bin spacing of the record
        itself; two sinusoids closer than about two bins merge under the window.
    record : float
        The record length ``N dt`` (s).
    window : str
        The window's name (``"Hann"``).
    pad : int
        The zero-padding factor (the displayed grid is ``pad`` times finer than the
        resolution: it interpolates the peaks' shape, it resolves nothing more).
    """

    frequency: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    resolution: float
    record: float
    window: str
    pad: int


def windowed_spectrum(signal: NDArray[np.float64], dt: float, pad: int = 8) -> Spectrum:
    """The Hann-windowed, zero-padded one-sided amplitude spectrum of ``signal`` (its
    windowed mean removed), for display. The Hann window keeps the leakage of a sinusoid
    that does not fall on a bin in sidelobes below -31 dB that fall by 18 dB per octave
    (a rectangular window: -13 dB, 6 dB per octave); the amplitudes are divided by the
    window's sum (coherent gain), so a sinusoid of amplitude A peaks at A.

    Parameters
    ----------
    signal : ndarray
        Samples on a uniform grid (>= 4).
    dt : float
        Sample spacing (s), > 0.
    pad : int
        Zero-padding factor (>= 1): the spectrum is evaluated ``pad`` times finer than
        its resolution ``1 / (N dt)``.

    Returns
    -------
    Spectrum
    """
    x = np.asarray(signal, float)
    if x.size < 4 or not dt > 0 or not (isinstance(pad, int) and pad >= 1):
        raise ReducerlabError("windowed_spectrum: need >= 4 samples, dt > 0 and pad >= 1")
    w = np.hanning(x.size)
    n_fft = pad * x.size
    mean = np.sum(x * w) / np.sum(w)  # the windowed mean: no DC left under the window
    amp = 2.0 * np.abs(np.fft.rfft((x - mean) * w, n=n_fft)) / np.sum(w)
    record = x.size * dt
    return Spectrum(np.fft.rfftfreq(n_fft, dt), amp, 1.0 / record, record, "Hann", pad)
