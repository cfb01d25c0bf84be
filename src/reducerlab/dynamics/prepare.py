"""Preparation of an ensemble for the compiled kernel: the checks (structure, linear
stability, commensurate laws), the step grid aligned with the law discontinuities,
and the member-first stacked arrays (:class:`Prepared`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..model import NonlinearSystem
from .guards import check_stability
from .steps import MAX_STEPS, Steps, stable_steps, too_many_steps
from .systems import (
    check_commensurate,
    check_structure,
    forcing_period,
    law_breaks,
    repeats_within,
)

__all__ = ["KernelArrays", "Prepared", "grid", "linear_lines", "prepare", "subset", "with_steps"]


class KernelArrays(NamedTuple):
    """The system arrays of an ensemble in the order :func:`.kernel.rk4_ensemble` takes
    them (``*arrays``), member axis first; the law kinds are shared (1-D)."""

    Minv: NDArray[np.float64]  # (E, n, n) inverse mass matrices
    C: NDArray[np.float64]  # (E, n, n) linear damping
    K: NDArray[np.float64]  # (E, n, n) linear stiffness
    G: NDArray[np.float64]  # (E, L, n) line projections
    k_kind: NDArray[np.int64]  # (L,) stiffness law kinds
    k_par: NDArray[np.float64]  # (E, L, width) stiffness law rows (model.layout)
    cm: NDArray[np.float64]  # (E, L) line damping
    hb: NDArray[np.float64]  # (E, L) half backlash
    kl: NDArray[np.float64]  # (E, L, 3) cubic line stiffness, load exponent, reference
    e_kind: NDArray[np.int64]  # (L,) error law kinds
    e_par: NDArray[np.float64]  # (E, L, width) error law rows
    B: NDArray[np.float64]  # (E, n, loads) load matrices
    f_kind: NDArray[np.int64]  # (loads,) load law kinds
    f_par: NDArray[np.float64]  # (E, loads, width) load law rows


@dataclass(frozen=True)
class Prepared:
    """Stacked kernel inputs of an ensemble (see :func:`.kernel.rk4_ensemble`)."""

    arrays: KernelArrays
    period: NDArray[np.float64]  # (E,) s
    offs: NDArray[np.float64]  # (E, N) s, step starts from the period start
    dts: NDArray[np.float64]  # (E, N) s, step lengths
    periodic: bool  # every law repeats within the period
    steps: int


def prepare(
    systems: Sequence[NonlinearSystem],
    steps_per_period: int | None,
    period: float | None,
    labels: Sequence[str] | None = None,
) -> Prepared:
    """Check an ensemble (structure, linear stability: :func:`check_stability`) and
    stack its arrays for the kernel (member axis first)."""
    check_structure(systems)
    lam_max = check_stability(systems, labels)
    if period is not None and not (isinstance(period, int | float) and period > 0):
        raise ReducerlabError(f"period must be > 0 s, got {period!r}")
    E = len(systems)
    T = np.array([period if period is not None else forcing_period(s) for s in systems])
    Minv = np.linalg.inv(np.stack([s.M for s in systems]))  # M is positive definite (above)
    N = steps_per_period or stable_steps(systems, T, lam_max=lam_max)
    Steps.fixed(N)  # an integer >= MIN_STEPS
    if steps_per_period is None and N > MAX_STEPS:
        raise ReducerlabError(too_many_steps(systems, T, N))
    for s, t in zip(systems, T, strict=True):
        check_commensurate(s, t)
    offs, dts, N = grid(systems, T, N)
    widths = {
        name: max(getattr(s, name).shape[1] if getattr(s, name).ndim == 2 else 1 for s in systems)
        for name in ("k_params", "e_params", "f_params")
    }

    def params(name: str) -> NDArray:
        out = np.zeros((E, getattr(systems[0], name).shape[0], widths[name]))
        for e, s in enumerate(systems):
            a = getattr(s, name)
            out[e, :, : a.shape[1]] = a
        return out

    s0 = systems[0]
    pad = np.stack
    arrays = KernelArrays(
        Minv, pad([s.C for s in systems]),
        pad([s.K for s in systems]), pad([s.G for s in systems]), s0.k_kind,
        params("k_params"), pad([s.line_damping for s in systems]),
        pad([s.half_backlash for s in systems]),
        pad([np.column_stack([s.line_cubic, s.line_power]) for s in systems]),
        s0.e_kind, params("e_params"), pad([s.load_matrix for s in systems]), s0.f_kind,
        params("f_params"),
    )  # fmt: skip
    periodic = all(repeats_within(s, t) for s, t in zip(systems, T, strict=True))
    return Prepared(arrays, T, offs, dts, periodic, N)


def linear_lines(arrays: KernelArrays) -> bool:
    """Whether every line of every member is piecewise linear: no cubic term and a load
    exponent of 1 (the condition of the one-period maps, :mod:`.maps`)."""
    return not np.any(arrays.kl[..., 0]) and bool(np.all(arrays.kl[..., 1] == 1.0))


def grid(systems: Sequence[NonlinearSystem], T: NDArray, N: int) -> tuple[NDArray, NDArray, int]:
    """Step starts and lengths (E, N) (s, from each period's start), at least one step
    per law segment and aligned with the law jumps, and the step count."""
    from .kernel_laws import step_grid

    brk = [law_breaks(s, t) for s, t in zip(systems, T, strict=True)]
    N = max(N, max(len(b) for b in brk))
    edges = np.ones((len(systems), max(len(b) for b in brk) + 1))
    counts = np.empty(len(systems), np.int64)
    for e, b in enumerate(brk):
        edges[e, : len(b)] = b
        counts[e] = len(b) + 1
    offs, dts = step_grid(edges, counts, N)
    return offs * T[:, None], dts * T[:, None], N


def subset(prep: Prepared, idx: NDArray[np.intp]) -> Prepared:
    """The prepared kernel arrays of members ``idx``."""
    arrays = KernelArrays(*(a if a.ndim == 1 else a[idx] for a in prep.arrays))
    return replace(prep, arrays=arrays, period=prep.period[idx], offs=prep.offs[idx],
                   dts=prep.dts[idx])  # fmt: skip


def with_steps(prep: Prepared, systems: Sequence[NonlinearSystem], N: int) -> Prepared:
    """``prep`` with ``N`` steps per period (its checks and stacked arrays kept)."""
    if prep.steps == N:
        return prep
    offs, dts, N = grid(systems, prep.period, N)
    return replace(prep, offs=offs, dts=dts, steps=N)
