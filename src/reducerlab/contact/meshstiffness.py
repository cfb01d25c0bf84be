"""Mesh stiffness over a mesh cycle and its Fourier series (paper 000, Eq. 8).

``k(t) = k_m + sum_{r=1}^{l} k_r cos(r omega_m t + phi_r)``. On ``n`` samples evenly
spaced over one mesh period the least-squares fit of this series (``2 l + 1 <= n``) is
the truncated discrete Fourier transform, so the fit is exact (no iteration) and its
residual is what the omitted harmonics carry.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError

__all__ = ["FourierFit", "fit_fourier"]

Array = NDArray[np.float64]


@dataclass(frozen=True)
class FourierFit:
    """Paper 000's Eq. 8 fitted to a sampled mesh stiffness.

    Attributes
    ----------
    mean : float
        ``k_m`` (N/m).
    amplitudes : ndarray (l,)
        ``k_r`` (N/m), ``>= 0``.
    phases : ndarray (l,)
        ``phi_r`` (rad), in ``(-pi, pi]``.
    residual : float
        RMS of ``k - fit`` over the samples divided by ``k_m`` (dimensionless).
    """

    mean: float
    amplitudes: Array
    phases: Array
    residual: float

    @property
    def order(self) -> int:
        return len(self.amplitudes)

    def __call__(self, phase: ArrayLike) -> Array:
        """The fitted ``k`` at mesh phases ``omega_m t`` (rad)."""
        x = np.asarray(phase, float)
        r = np.arange(1, self.order + 1)
        return self.mean + np.sum(
            self.amplitudes * np.cos(np.multiply.outer(x, r) + self.phases), axis=-1
        )


def fit_fourier(samples: ArrayLike, order: int = 7) -> FourierFit:
    """Fit Eq. 8 of paper 000 to ``n`` samples at phases ``2 pi j / n``, ``j = 0..n-1``.

    Parameters
    ----------
    samples : array_like (n,)
        Mesh stiffness (N/m) at evenly spaced positions over one mesh period (the first
        at phase 0, the period's end excluded).
    order : int
        Harmonics ``l``; ``2 l + 1 <= n`` (paper 000 uses 7).
    """
    k = np.asarray(samples, float)
    if k.ndim != 1 or not np.all(np.isfinite(k)):
        raise ReducerlabError("stiffness samples: must be a 1-D array of finite values (N/m)")
    if isinstance(order, bool) or not isinstance(order, int) or order < 0:
        raise ReducerlabError(f"order: must be an integer >= 0; got {order!r}")
    n = k.size
    if 2 * order + 1 > n:
        raise ReducerlabError(
            f"order: {order} harmonics need at least {2 * order + 1} positions over the mesh "
            f"cycle; got {n}"
        )
    c = np.fft.rfft(k) / n
    amp = 2.0 * np.abs(c[1 : order + 1])
    if 2 * order == n:  # the Nyquist term is real and counted once
        amp[-1] *= 0.5
    phase = np.angle(c[1 : order + 1])
    fit = FourierFit(float(c[0].real), amp, phase, 0.0)
    x = 2 * math.pi * np.arange(n) / n
    res = float(np.sqrt(np.mean((k - fit(x)) ** 2)) / abs(fit.mean)) if fit.mean else math.inf
    return FourierFit(fit.mean, amp, phase, res)
