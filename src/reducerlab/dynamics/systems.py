"""The systems the engine integrates: the state at rest, the forcing period, the
structure an ensemble shares, and the law discontinuities the steps align with."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..model import Model, NonlinearSystem, layout
from ..model.laws import flat_period
from ..model.layout import LAW_FOURIER, LAW_PIECEWISE

__all__ = [
    "at_rest",
    "check_commensurate",
    "check_structure",
    "divides",
    "forcing_period",
    "law_breaks",
    "mass_problem",
    "repeats_within",
]


def at_rest(model: Model) -> NonlinearSystem | None:
    """The flat system of ``model`` at zero speed, or None when it runs at zero speed.

    Rigid-body motion is the motion that strains no element: the null space of the
    stiffness *without* speed-dependent terms. The centripetal and gyroscopic terms,
    linearised in a rotating frame, do not respect it (e.g. ``-m Omega^2`` on a
    tangential translation that is a pure phase shift of the rotating assembly), so
    they would turn a rigid mode into a slowly diverging one. As in
    :func:`reducerlab.analysis.modal.modal`, the rigid motion is taken from the model
    at rest and removed; the speed terms act on the elastic coordinates only.
    """
    if model.speed == 0.0:
        return None
    return model.with_speed(0.0).nonlinear()


def mass_problem(s: NonlinearSystem, exc: Exception | None = None) -> str:
    """Message for a mass matrix that the solvers cannot factorise, naming the DOF."""
    names, _, M = s.physical()
    d = np.diag(M)
    if np.any(~(d > 0)):
        bad = [names[i] for i in np.nonzero(~(d > 0))[0]]
        return (
            f"DOF(s) {bad} have no inertia, so the mass matrix is singular; add an "
            "Inertia element on each DOF (or remove the DOF)"
        )
    i, j = int(np.argmin(d)), int(np.argmax(d))
    return (
        f"the mass matrix is not positive definite to working precision ({exc}); the "
        f"inertias span {d[i]:.3g} ({names[i]}) to {d[j]:.3g} ({names[j]}) in SI: check "
        "for an extreme inertia value"
    )


def forcing_period(s: NonlinearSystem) -> float:
    """Period (s) of the first time-varying mesh law (stiffness, then error), or of the
    first periodic load; the stroboscopic sampling period of Poincaré sections."""
    for kinds, params in ((s.k_kind, s.k_params), (s.e_kind, s.e_params), (s.f_kind, s.f_params)):
        for kind, p in zip(kinds, params, strict=True):
            period = flat_period(int(kind), p)
            if math.isfinite(period):
                return period
    raise ReducerlabError(
        "the model has no periodic law (constant mesh stiffness, no periodic error or "
        "load), so there is no forcing period to sample: give one (API: period=...; "
        "command line: --period '2 ms' or --frequency '500 Hz')"
    )


def law_breaks(s: NonlinearSystem, T: float) -> NDArray[np.float64]:
    """Phases in [0, 1) of stiffness-law discontinuities within one forcing period."""
    out = [0.0]
    for kind, p in zip(s.k_kind, s.k_params, strict=True):
        if kind != LAW_PIECEWISE:
            continue
        P, t0 = p[layout.PIECE_PERIOD], p[layout.PIECE_T0]
        j = np.arange(math.floor(-t0 / P) - 1, math.ceil((T - t0) / P) + 1)
        times = (t0 + (j[:, None] + layout.breaks(p)) * P).ravel()
        out += list((times[(times >= 0) & (times < T)] / T).tolist())
    # exact phases (a rounded phase puts the step boundary beside the jump, and with
    # more than ~5000 steps per period the samples just inside a step then read the law
    # on the wrong side of it: a first-order error); phases closer than 1e-12 (the same
    # jump seen from two laws, or 1 - 1e-17 and 0) are one
    ph = np.sort(np.array(out))
    ph = ph[(ph >= 0) & (ph < 1 - 1e-12)]
    keep = np.concatenate([[True], np.diff(ph) > 1e-12])
    return ph[keep]


def check_structure(systems: Sequence[NonlinearSystem]) -> None:
    """Raise unless the ensemble has members, all of one structure: DOF count, lines
    and law kinds (parameter values may differ)."""
    if not systems:
        raise ReducerlabError("ensemble: no systems")
    s0 = systems[0]
    for s in systems[1:]:
        if (
            s.n != s0.n
            or s.G.shape != s0.G.shape
            or not np.array_equal(s.k_kind, s0.k_kind)
            or not np.array_equal(s.e_kind, s0.e_kind)
            or not np.array_equal(s.f_kind, s0.f_kind)
        ):
            raise ReducerlabError("ensemble: all members must have the same structure")


def divides(P: float, T: float) -> bool:
    """A law of period ``P`` repeats within ``T`` (a whole number >= 1 of periods)."""
    ratio = T / P
    return abs(ratio - round(ratio)) <= 1e-9 * max(1.0, ratio) and round(ratio) >= 1


def repeats_within(s: NonlinearSystem, T: float) -> bool:
    """Every law of ``s`` has a period that divides ``T`` (or is constant: a Fourier law
    whose amplitudes are all zero counts as constant)."""
    for kinds, params in ((s.k_kind, s.k_params), (s.e_kind, s.e_params), (s.f_kind, s.f_params)):
        for kind, p in zip(kinds, params, strict=True):
            if int(kind) == LAW_FOURIER and not np.any(layout.amplitudes(p)):
                continue
            P = flat_period(int(kind), p)
            if math.isfinite(P) and not divides(P, T):
                return False
    return True


def check_commensurate(s: NonlinearSystem, T: float) -> None:
    """Every law with jumps (piecewise) must repeat within the sampling period T: the
    kernel aligns its steps with the jumps of one period and reuses that grid. Smooth
    laws (Fourier) may have any frequency."""
    for kinds, params in ((s.k_kind, s.k_params), (s.e_kind, s.e_params), (s.f_kind, s.f_params)):
        for kind, p in zip(kinds, params, strict=True):
            if kind != LAW_PIECEWISE:
                continue
            P = flat_period(int(kind), p)
            if not divides(P, T):
                raise ReducerlabError(
                    f"a law of period {P:.6g} s does not repeat within the sampling period "
                    f"{T:.6g} s; give period= as a common multiple of all law periods"
                )
