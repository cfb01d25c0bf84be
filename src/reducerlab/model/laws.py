"""Scalar laws of time (mesh stiffness, transmission error, loads) and the backlash.

Each law evaluates vectorised over ``t`` and exports itself as a kind code plus a flat
float array (:meth:`TimeLaw.flat`, in the layout that :mod:`reducerlab.model.layout`
owns) that :func:`evaluate_flat` — and the compiled
integrators built on it — evaluate without Python objects.
"""

from __future__ import annotations

import copy
import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field, replace
from functools import cached_property
from itertools import pairwise

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ModelError
from . import layout
from .layout import LAW_CONSTANT, LAW_FOURIER, LAW_PIECEWISE

__all__ = [
    "Backlash",
    "Constant",
    "Fourier",
    "PiecewisePolynomial",
    "TimeLaw",
    "dead_zone",
    "evaluate_flat",
    "flat_mean",
    "flat_peak",
    "flat_period",
]


class TimeLaw(ABC):
    """A scalar function of time ``k(t)`` (unit of the quantity it describes)."""

    @abstractmethod
    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        """Value at times ``t`` (s)."""

    @abstractmethod
    def derivative(self, t: ArrayLike) -> NDArray[np.float64]:
        """Time derivative at ``t`` (unit per s)."""

    #: Time average over one period (the value modal analysis uses). A dataclass field
    #: of the laws that store it, a property of those that derive it.
    mean: float
    #: Period (s); ``inf`` for a constant.
    period: float

    def breakpoints(self, t0: float, t1: float) -> NDArray[np.float64]:
        """Times in ``[t0, t1]`` where the law or its derivative jumps (s)."""
        return np.empty(0)

    def lower_bound(self) -> float | None:
        """A value the law never goes below (its unit), or None where unknown.

        Exact for a constant and a piecewise polynomial, ``mean - sum |k_r|`` for a
        Fourier series. Elements whose law must stay non-negative (a mesh stiffness)
        check it, so that a law built in Python obeys the rule a design file obeys.
        """
        return None

    def at_speed(self, speed: float) -> TimeLaw:
        """The law at model speed ``speed`` (rad/s).

        Laws built with a reference speed (``ref_speed``, e.g. a mesh frequency that is
        a multiple of the input speed) scale their time axis by ``speed / ref_speed``;
        at zero speed they become their mean (a gear pair at rest). Other laws are
        returned unchanged.
        """
        return self

    def with_mean(self, value: float) -> TimeLaw:
        """The law with its mean set to ``value`` (what a parameter path ending on the
        law changes): the other parameters held; a law that derives its mean
        (:class:`PiecewisePolynomial`) is scaled, its shape held."""
        return replace(self, mean=value)  # type: ignore[type-var]

    @abstractmethod
    def flat(self) -> tuple[int, NDArray[np.float64]]:
        """``(kind, params)`` for :func:`evaluate_flat`."""


def _check_finite(name: str, *values: float) -> None:
    for v in values:
        if isinstance(v, float | int) and not isinstance(v, bool):
            if math.isfinite(v):
                continue
            raise ModelError(f"{name}: parameters must be finite numbers, got {v!r}")
        try:
            ok = np.all(np.isfinite(np.real(np.asarray(v, dtype=complex))))
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ModelError(f"{name}: parameters must be finite numbers, got {v!r}")


@dataclass(frozen=True)
class Constant(TimeLaw):
    """``k(t) = mean``."""

    mean: float

    def __post_init__(self) -> None:
        _check_finite("Constant", self.mean)

    @property
    def period(self) -> float:  # type: ignore[override]
        return math.inf

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        return np.full(np.shape(t), self.mean) if np.ndim(t) else np.asarray(self.mean)

    def lower_bound(self) -> float:
        return float(np.real(self.mean))

    def derivative(self, t: ArrayLike) -> NDArray[np.float64]:
        return np.zeros(np.shape(t))

    def flat(self) -> tuple[int, NDArray[np.float64]]:
        return LAW_CONSTANT, layout.encode_constant(self.mean)


@dataclass(frozen=True)
class Fourier(TimeLaw):
    """Truncated Fourier series, paper 000 Eq. 8.

    ``k(t) = mean + sum_r amplitudes[r-1] * cos(r * omega * t + phases[r-1])``

    Parameters
    ----------
    mean : float
        Average value (e.g. N/m for a mesh stiffness).
    amplitudes : array_like
        Harmonic amplitudes ``k_r``, r = 1..l (same unit as ``mean``).
    phases : array_like
        Harmonic phases ``phi_r`` (rad); zeros if omitted.
    omega : float
        Fundamental angular frequency (rad/s), e.g. the mesh frequency.
    ref_speed : float, optional
        Model speed (rad/s) at which ``omega`` holds; at another speed ``omega`` scales
        with it (:meth:`at_speed`).
    speed_power : int
        With ``ref_speed``, the amplitudes scale as ``(speed / ref_speed)**speed_power``
        too: 2 for a force that grows with the square of the speed, such as the inertial
        excitation ``-m e''(t)`` of a transmission error
        (:func:`reducerlab.model.forcing.inertial_error`); 0 (default) keeps them.
    """

    mean: float
    amplitudes: tuple[float, ...]
    omega: float
    phases: tuple[float, ...] = field(default=())
    ref_speed: float | None = None
    speed_power: int = 0

    def __post_init__(self) -> None:
        try:
            amps = tuple(np.atleast_1d(np.asarray(self.amplitudes, dtype=complex)).tolist())
            phases = (0.0,) * len(amps) if len(np.atleast_1d(self.phases)) == 0 else self.phases
            phases = tuple(np.atleast_1d(np.asarray(phases, dtype=float)).tolist())
            float(np.real(self.omega))
        except (TypeError, ValueError):
            raise ModelError(
                f"Fourier: amplitudes, phases and omega must be numbers, got {self.amplitudes!r}, "
                f"{self.phases!r}, {self.omega!r}"
            ) from None
        amps = tuple(a.real if a.imag == 0 else a for a in amps)
        if len(phases) != len(amps):
            raise ModelError(
                f"Fourier: {len(amps)} amplitudes but {len(phases)} phases; give one per harmonic"
            )
        if not np.real(self.omega) > 0:
            raise ModelError(f"Fourier: omega must be > 0 rad/s, got {self.omega!r}")
        _check_finite("Fourier", self.mean, self.omega, *amps, *phases)
        if self.ref_speed is not None and not (
            isinstance(self.ref_speed, int | float) and math.isfinite(self.ref_speed)
            and self.ref_speed > 0
        ):  # fmt: skip
            raise ModelError(f"Fourier: ref_speed must be > 0 rad/s, got {self.ref_speed!r}")
        if (
            isinstance(self.speed_power, bool)
            or not isinstance(self.speed_power, int)
            or not (0 <= self.speed_power <= 4)
        ):
            raise ModelError(
                f"Fourier: speed_power must be an integer in 0..4, got {self.speed_power!r}"
            )
        if self.speed_power and self.ref_speed is None:
            raise ModelError("Fourier: speed_power needs ref_speed (the speed of the amplitudes)")
        object.__setattr__(self, "amplitudes", amps)
        object.__setattr__(self, "phases", phases)

    def at_speed(self, speed: float) -> TimeLaw:
        if self.ref_speed is None:
            return self
        if speed == 0:
            return Constant(self.mean)
        ratio = speed / self.ref_speed
        amps = self.amplitudes
        if self.speed_power:
            amps = tuple(a * ratio**self.speed_power for a in amps)
        return Fourier(self.mean, amps, self.omega * ratio, self.phases)

    def lower_bound(self) -> float:
        # attained when the phases line up (always for one harmonic)
        return float(np.real(self.mean) - np.sum(np.abs(np.real(self.amplitudes))))

    def _arg(self, t: ArrayLike) -> NDArray[np.float64]:
        r = np.arange(1, len(self.amplitudes) + 1)
        return np.multiply.outer(np.asarray(t, dtype=float), r * self.omega) + np.asarray(
            self.phases
        )

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        return self.mean + np.cos(self._arg(t)) @ np.asarray(self.amplitudes)

    def derivative(self, t: ArrayLike) -> NDArray[np.float64]:
        r = np.arange(1, len(self.amplitudes) + 1)
        return -np.sin(self._arg(t)) @ (np.asarray(self.amplitudes) * r * self.omega)

    @property
    def period(self) -> float:  # type: ignore[override]
        return 2 * math.pi / float(np.real(self.omega))

    def flat(self) -> tuple[int, NDArray[np.float64]]:
        return LAW_FOURIER, layout.encode_fourier(
            self.mean, self.omega, self.amplitudes, self.phases
        )


@dataclass(frozen=True)
class PiecewisePolynomial(TimeLaw):
    """Periodic piecewise polynomial in the phase ``s = ((t - t0) / period) mod 1``.

    Paper 004 Eq. 9 writes the single/double-tooth mesh stiffness this way.

    Parameters
    ----------
    period : float
        Period (s), e.g. one mesh period.
    breaks : array_like
        Start phases of the pieces, ``0 = s_0 < s_1 < ... < s_{n-1} < 1``.
    coefficients : array_like, shape (n_pieces, degree + 1)
        Ascending-power coefficients in ``s`` of each piece:
        ``value = c0 + c1 s + c2 s^2 + ...`` (unit of the quantity).
    t0 : float
        Time (s) at which the phase is zero.
    """

    period: float
    breaks: tuple[float, ...]
    coefficients: tuple[tuple[float, ...], ...]
    t0: float = 0.0
    ref_speed: float | None = None

    def __post_init__(self) -> None:
        try:
            breaks = np.atleast_1d(np.asarray(self.breaks, dtype=float))
            coef = np.atleast_2d(np.asarray(self.coefficients, dtype=float))
            float(self.period)
        except (TypeError, ValueError):
            raise ModelError(
                "PiecewisePolynomial: breaks and coefficients must be numbers, with one row "
                "of equal length per piece"
            ) from None
        if breaks.size == 0 or coef.ndim != 2:
            raise ModelError("PiecewisePolynomial: needs at least one piece (breaks = [0])")
        _check_finite("PiecewisePolynomial", *breaks)
        if self.ref_speed is not None and not (
            isinstance(self.ref_speed, int | float) and math.isfinite(self.ref_speed)
            and self.ref_speed > 0
        ):  # fmt: skip
            raise ModelError(
                f"PiecewisePolynomial: ref_speed must be > 0 rad/s, got {self.ref_speed!r}"
            )
        if not np.real(self.period) > 0:
            raise ModelError(f"PiecewisePolynomial: period must be > 0 s, got {self.period!r}")
        if breaks[0] != 0.0 or np.any(np.diff(breaks) <= 0) or breaks[-1] >= 1.0:
            raise ModelError(
                "PiecewisePolynomial: breaks must start at 0, increase strictly and stay < 1; "
                f"got {breaks.tolist()}"
            )
        if coef.shape[0] != breaks.size:
            raise ModelError(
                f"PiecewisePolynomial: {breaks.size} breaks but {coef.shape[0]} coefficient rows"
            )
        _check_finite("PiecewisePolynomial", self.period, self.t0, *coef.ravel())
        object.__setattr__(self, "breaks", tuple(breaks.tolist()))
        object.__setattr__(self, "coefficients", tuple(tuple(row) for row in coef.tolist()))

    def at_speed(self, speed: float) -> TimeLaw:
        if self.ref_speed is None:
            return self
        if speed == 0:
            return Constant(self.mean)
        f = speed / self.ref_speed
        # the same validated law on a scaled time axis (no re-validation: period and t0
        # stay positive and finite; the mean does not change)
        out = copy.copy(self)
        object.__setattr__(out, "period", self.period / abs(f))
        object.__setattr__(out, "t0", self.t0 / abs(f))
        object.__setattr__(out, "ref_speed", None)
        return out

    def lower_bound(self) -> float:
        # exact: each piece's minimum is at an end of its interval or where c'(s) = 0
        edges = np.append(np.asarray(self.breaks), 1.0)
        out = math.inf
        for (a, b), c in zip(pairwise(edges), self.coefficients, strict=True):
            poly = np.polynomial.Polynomial(c)
            crit = poly.deriv().roots() if len(c) > 2 else np.empty(0)
            crit = np.real(crit[(np.abs(np.imag(crit)) < 1e-12)])
            s = np.concatenate(([a, b], crit[(crit > a) & (crit < b)]))
            out = min(out, float(np.min(poly(s))))
        return out

    def _piece(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
        s = np.mod((np.asarray(t, dtype=float) - self.t0) / self.period, 1.0)
        i = np.searchsorted(np.asarray(self.breaks), s, side="right") - 1
        return s, i

    def __call__(self, t: ArrayLike) -> NDArray[np.float64]:
        s, i = self._piece(t)
        c = np.asarray(self.coefficients)[i]  # (..., deg+1)
        powers = s[..., None] ** np.arange(c.shape[-1])
        return np.sum(c * powers, axis=-1)

    def derivative(self, t: ArrayLike) -> NDArray[np.float64]:
        s, i = self._piece(t)
        c = np.asarray(self.coefficients)[i]
        p = np.arange(1, c.shape[-1])
        powers = s[..., None] ** (p - 1)
        return np.sum(c[..., 1:] * p * powers, axis=-1) / self.period

    @cached_property
    def mean(self) -> float:  # type: ignore[override]
        c = np.asarray(self.coefficients)
        edges = np.append(np.asarray(self.breaks), 1.0)
        p = np.arange(1, c.shape[1] + 1)
        upper = (edges[1:, None] ** p) / p
        lower = (edges[:-1, None] ** p) / p
        return float(np.sum(c * (upper - lower)))

    def with_mean(self, value: float) -> TimeLaw:
        """The law scaled to the mean ``value`` (the single/double-tooth shape held)."""
        mean = self.mean
        if mean == 0:
            raise ModelError("PiecewisePolynomial: a law of mean 0 cannot be scaled to a mean")
        f = value / mean
        rows = tuple(tuple(f * c for c in row) for row in self.coefficients)
        return replace(self, coefficients=rows)

    def breakpoints(self, t0: float, t1: float) -> NDArray[np.float64]:
        n0 = math.floor((t0 - self.t0) / self.period)
        n1 = math.ceil((t1 - self.t0) / self.period)
        k = np.arange(n0, n1 + 1)
        times = self.t0 + (k[:, None] + np.asarray(self.breaks)) * self.period
        times = times.ravel()
        return times[(times >= t0) & (times <= t1)]

    def flat(self) -> tuple[int, NDArray[np.float64]]:
        return LAW_PIECEWISE, layout.encode_piecewise(
            self.period, self.t0, self.breaks, self.coefficients
        )


def evaluate_flat(kind: int, params: NDArray[np.float64], t: float) -> tuple[float, float]:
    """Value and time derivative of a law from its flat export at one time ``t`` (s).

    This is the reference for the compiled kernels: it uses scalar arithmetic only.
    """
    if kind == LAW_CONSTANT:
        return float(params[layout.CONSTANT_VALUE]), 0.0
    if kind == LAW_FOURIER:
        mean, omega = params[layout.FOURIER_MEAN], params[layout.FOURIER_OMEGA]
        n = layout.fourier_count(params)
        amps, phis = layout.amplitudes(params), layout.phases(params)
        val, der = mean, 0.0
        for r in range(1, n + 1):
            arg = r * omega * t + phis[r - 1]
            val += amps[r - 1] * math.cos(arg)
            der -= amps[r - 1] * r * omega * math.sin(arg)
        return float(val), float(der)
    if kind == LAW_PIECEWISE:
        period, t0 = params[layout.PIECE_PERIOD], params[layout.PIECE_T0]
        n, m = layout.piece_shape(params)
        starts, coef = layout.breaks(params), layout.coefficients(params)
        s = ((t - t0) / period) % 1.0
        i = 0
        while i + 1 < n and starts[i + 1] <= s:
            i += 1
        val, der = 0.0, 0.0
        for p in range(m - 1, -1, -1):  # Horner in s
            der = der * s + val if p < m - 1 else 0.0
            val = val * s + coef[i, p]
        return float(val), float(der / period)
    raise ModelError(f"unknown law kind {kind}")


def flat_period(kind: int, params: NDArray[np.float64]) -> float:
    """Period (s) of a flat law; ``inf`` for a constant (or a zero-frequency series)."""
    if kind == LAW_FOURIER and params[layout.FOURIER_OMEGA] > 0:
        return 2 * math.pi / float(params[layout.FOURIER_OMEGA])
    if kind == LAW_PIECEWISE:
        return float(params[layout.PIECE_PERIOD])
    return math.inf


def flat_mean(kind: int, params: NDArray[np.float64]) -> float:
    """Time average of a flat law over one period (exact integral for piecewise laws)."""
    if kind == LAW_PIECEWISE:
        edges = np.append(layout.breaks(params), 1.0)
        c = layout.coefficients(params)
        q = np.arange(1, c.shape[1] + 1)
        return float(np.sum(c * (edges[1:, None] ** q - edges[:-1, None] ** q) / q))
    if kind == LAW_FOURIER:
        return float(params[layout.FOURIER_MEAN])
    return float(params[layout.CONSTANT_VALUE])


def flat_peak(kind: int, params: NDArray[np.float64]) -> float:
    """An upper bound of ``|law(t)|`` over all times of a flat law (its unit): the mean
    plus the harmonic amplitudes of a Fourier law, the largest sum of coefficient
    magnitudes of a piecewise polynomial (``|c(s)| <= sum |c_q|`` for ``s`` in [0, 1])."""
    if kind == LAW_FOURIER:
        return float(abs(params[layout.FOURIER_MEAN]) + np.abs(layout.amplitudes(params)).sum())
    if kind == LAW_PIECEWISE:
        return float(np.abs(layout.coefficients(params)).sum(axis=1).max())
    return float(abs(params[layout.CONSTANT_VALUE]))


def dead_zone(delta: ArrayLike, half_width: float) -> NDArray[np.float64]:
    """Backlash (clearance) function with a dead zone ``|delta| <= half_width``.

    ``f = delta - h`` for ``delta > h``, ``0`` for ``|delta| <= h``,
    ``delta + h`` for ``delta < -h``, with ``h = half_width`` (m). This is paper 004
    Eq. 11 with ``h = b`` (its b is half the backlash) and paper 000 Eq. 6 with
    ``h = b/2`` (its b is the full backlash). See ``docs/conventions.md``.
    """
    d = np.asarray(delta, dtype=float)
    return d - np.clip(d, -half_width, half_width)


@dataclass(frozen=True)
class Backlash:
    """Clearance of a mesh along its line of action, stored as the half width (m).

    Build it with the convention of the source you copy from:
    ``Backlash.full(b)`` when ``b`` is the whole clearance between the flanks
    (paper 000 Eq. 6), ``Backlash.half(b)`` when ``b`` is half of it (paper 004 Eq. 11).
    """

    half_width: float

    def __post_init__(self) -> None:
        try:
            h = float(np.real(self.half_width))
        except (TypeError, ValueError):
            h = math.nan
        if not (math.isfinite(h) and h >= 0):
            raise ModelError(f"Backlash: half width must be >= 0 m, got {self.half_width!r}")

    @classmethod
    def full(cls, b: float) -> Backlash:
        """From the full backlash ``b`` (m): dead zone ``|delta| <= b/2``."""
        return cls(b / 2.0)

    @classmethod
    def half(cls, b: float) -> Backlash:
        """From the half backlash ``b`` (m): dead zone ``|delta| <= b``."""
        return cls(b)

    @property
    def full_width(self) -> float:
        """Whole clearance (m)."""
        return 2.0 * self.half_width

    def __call__(self, delta: ArrayLike) -> NDArray[np.float64]:
        return dead_zone(delta, self.half_width)
