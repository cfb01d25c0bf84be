"""The flat layout of a law of time: one kind code and one float row per law.

A :class:`~reducerlab.model.laws.TimeLaw` exports itself as ``(kind, params)``
(:meth:`~reducerlab.model.laws.TimeLaw.flat`) so that the compiled integrators evaluate
it without Python objects. This module is the one place that knows where each quantity
sits in the row; everyone else (the law classes, the reference evaluators of
:mod:`reducerlab.model.laws`, the compiled kernel of :mod:`reducerlab.dynamics`, the
rescaling to dimensionless form, the contact maps) reads and writes rows through it.

``LAW_CONSTANT``: ``[value]``

``LAW_FOURIER``: ``[mean, omega, n, amplitudes (n), phases (n)]``: ``mean + sum_r
a_r cos(r omega t + phi_r)`` (paper 000 Eq. 8)

``LAW_PIECEWISE``: ``[period, t0, n, m, breaks (n), coefficients (n * m)]``: ``n``
pieces starting at the phases ``breaks`` of ``s = ((t - t0) / period) mod 1``, each a
polynomial of ``m`` ascending coefficients in ``s`` (paper 004 Eq. 9), row by row.

Rows of several laws are zero-padded to a common width (:func:`pack_laws`); the
accessors read only the part their header announces. The accessors return views, so
that an in-place update (``amplitudes(p)[:] *= 2``) edits the row.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "CONSTANT_VALUE",
    "FOURIER_COUNT",
    "FOURIER_HEAD",
    "FOURIER_MEAN",
    "FOURIER_OMEGA",
    "LAW_CONSTANT",
    "LAW_FOURIER",
    "LAW_PIECEWISE",
    "PIECE_COUNT",
    "PIECE_HEAD",
    "PIECE_PERIOD",
    "PIECE_T0",
    "PIECE_WIDTH",
    "Flat",
    "amplitudes",
    "breaks",
    "coefficients",
    "constant_terms",
    "encode_constant",
    "encode_fourier",
    "encode_piecewise",
    "fourier_count",
    "pack_laws",
    "phases",
    "piece_shape",
]

#: Kind codes of the flat laws.
LAW_CONSTANT, LAW_FOURIER, LAW_PIECEWISE = 0, 1, 2

#: Constant row: index of the value.
CONSTANT_VALUE = 0

#: Fourier row: index of the mean, of the fundamental (rad/s), of the harmonic count
#: ``n``, and where the ``n`` amplitudes start (the ``n`` phases follow them).
FOURIER_MEAN, FOURIER_OMEGA, FOURIER_COUNT, FOURIER_HEAD = 0, 1, 2, 3

#: Piecewise row: index of the period (s), of the phase origin ``t0`` (s), of the piece
#: count ``n``, of the coefficients per piece ``m``, and where the ``n`` breaks start
#: (the ``n * m`` coefficients follow them).
PIECE_PERIOD, PIECE_T0, PIECE_COUNT, PIECE_WIDTH, PIECE_HEAD = 0, 1, 2, 3, 4


def encode_constant(value: float) -> NDArray[np.float64]:
    """Row of a constant law."""
    return np.array([value], dtype=float)


def encode_fourier(
    mean: float, omega: float, amps: Sequence[float], phis: Sequence[float]
) -> NDArray[np.float64]:
    """Row of a Fourier series: mean, fundamental ``omega`` (rad/s), the harmonic
    amplitudes and phases (rad), r = 1..n."""
    return np.array([mean, omega, len(amps), *amps, *phis], dtype=float)


def encode_piecewise(
    period: float, t0: float, starts: Sequence[float], coef: ArrayLike
) -> NDArray[np.float64]:
    """Row of a periodic piecewise polynomial: period (s), phase origin ``t0`` (s), the
    start phases of the pieces and their ascending coefficients ``(n, m)``."""
    c = np.asarray(coef, dtype=float)
    n, m = c.shape
    return np.array([period, t0, n, m, *starts, *c.ravel()], dtype=float)


def fourier_count(p: NDArray[np.float64]) -> int:
    """Harmonic count ``n`` of a Fourier row."""
    return int(p[FOURIER_COUNT])


def amplitudes(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The harmonic amplitudes of a Fourier row (a view)."""
    n = fourier_count(p)
    return p[FOURIER_HEAD : FOURIER_HEAD + n]


def phases(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The harmonic phases (rad) of a Fourier row (a view)."""
    n = fourier_count(p)
    return p[FOURIER_HEAD + n : FOURIER_HEAD + 2 * n]


def piece_shape(p: NDArray[np.float64]) -> tuple[int, int]:
    """``(n, m)`` of a piecewise row: pieces and coefficients per piece."""
    return int(p[PIECE_COUNT]), int(p[PIECE_WIDTH])


def breaks(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The start phases of the pieces of a piecewise row (a view)."""
    n, _ = piece_shape(p)
    return p[PIECE_HEAD : PIECE_HEAD + n]


def coefficients(p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The coefficients ``(n, m)`` of a piecewise row (a view), piece by piece."""
    n, m = piece_shape(p)
    return p[PIECE_HEAD + n : PIECE_HEAD + n + n * m].reshape(n, m)


def constant_terms(kind: int, p: NDArray[np.float64]) -> NDArray[np.float64]:
    """The terms a constant offset adds to (a view): the value of a constant, the mean
    of a Fourier series, the constant coefficient of every piece of a piecewise law."""
    if kind == LAW_PIECEWISE:
        n, m = piece_shape(p)
        return p[PIECE_HEAD + n : PIECE_HEAD + n + n * m : m]
    return p[0:1]


class Flat(Protocol):
    """What :func:`pack_laws` needs of a law: its flat export (a
    :class:`~reducerlab.model.laws.TimeLaw`)."""

    def flat(self) -> tuple[int, NDArray[np.float64]]:
        """``(kind, params)`` in this module's layout."""
        ...


def pack_laws(laws: Sequence[Flat]) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Kind codes ``(n,)`` and zero-padded parameter rows ``(n, p_max)`` of ``laws``."""
    flats = [law.flat() for law in laws]
    width = max((p.size for _, p in flats), default=1)
    kinds = np.array([k for k, _ in flats], dtype=np.int64)
    params = np.zeros((len(flats), width))
    for i, (_, p) in enumerate(flats):
        params[i, : p.size] = p
    return kinds, params
