"""Step policy of the fixed-step integrators: limits on the RK4 steps per forcing
period, the stability-based step count, and :class:`Steps`, the policy as a small
validated object (a fixed count, or the count that meets an accuracy: see
:mod:`.accuracy`), in the manner of diffrax's step-size controllers."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..model import NonlinearSystem
from ..model.system import describe_dofs
from .limits import MAX_STEPS, MIN_STEPS

__all__ = [
    "MAX_STEPS",
    "MIN_STEPS",
    "Steps",
    "stable_steps",
    "steps_for",
    "too_many_steps",
]


def too_many_steps(systems: Sequence[NonlinearSystem], T: NDArray, N: int) -> str:
    """Message for a run whose highest natural frequency needs more than MAX_STEPS."""
    s = systems[0]
    lam, V = scipy.linalg.eigh(s.mean_stiffness, s.M)
    top = describe_dofs(s.dominant_dofs(V[:, -1]))
    f_top = math.sqrt(max(float(lam[-1]), 0.0)) / (2 * math.pi)
    return (
        f"the highest natural frequency, {f_top:.4g} Hz (a mode of {top}), is "
        f"{f_top * float(T[0]):.3g} times the forcing frequency {1 / float(T[0]):.4g} Hz: an "
        f"accurate explicit integration needs {N} steps per forcing period (at most "
        f"{MAX_STEPS}). Such a frequency comes from a near-zero inertia or a near-rigid "
        "stiffness on those DOFs: check their values (a rigid joint is better modelled by "
        "merging the DOFs), or give steps_per_period (--steps) explicitly"
    )


def stable_steps(
    systems: Sequence[NonlinearSystem],
    T: NDArray,
    accuracy: float = 0.25,
    lam_max: NDArray[np.float64] | None = None,
) -> int:
    """:func:`steps_for` of every member at once (batched eigenvalues), the largest;
    ``lam_max``: the members' largest eigenvalues when already known
    (:func:`~reducerlab.dynamics.guards.check_stability` returns them)."""
    lam = lam_max
    if lam is None:
        K = np.stack([s.mean_stiffness for s in systems])
        Lc = np.linalg.cholesky(np.stack([s.M for s in systems]))
        A = np.linalg.solve(Lc, np.swapaxes(np.linalg.solve(Lc, K), 1, 2))
        lam = np.linalg.eigvalsh(0.5 * (A + np.swapaxes(A, 1, 2))).max(axis=1)
    w = np.sqrt(np.maximum(lam, 0.0))
    return max(32, int(np.ceil(np.max(np.asarray(T) * w) / accuracy)))


def steps_for(s: NonlinearSystem, T: float, accuracy: float = 0.25) -> int:
    """Steps per forcing period: ``omega_max h <= accuracy`` for the highest natural
    frequency of the mean system (RK4 is stable to 2.8; 0.25 keeps its per-step
    relative phase error near 1e-6), at least 32."""
    return stable_steps([s], np.array([T]), accuracy)


@dataclass(frozen=True)
class Steps:
    """The step policy of a fixed-step run, as a small validated object (in the manner
    of diffrax's step-size controllers): a fixed count of RK4 steps per forcing period
    (:meth:`fixed`), or the smallest count that meets a target error of the Poincaré
    points relative to the motion's scale (:meth:`accuracy`, the rule of
    :func:`reducerlab.dynamics.accuracy.accurate_steps`).

    The runs keep their ``steps_per_period=`` / ``accuracy=`` keyword arguments and check
    them through :meth:`fixed` and :meth:`accuracy` (:func:`~.prepare.prepare`,
    :func:`~.accuracy.accurate_steps`), so every entry point gives the same messages.

    Examples
    --------
    >>> Steps.fixed(2000).count
    2000
    >>> Steps.accuracy(1e-6).tolerance
    1e-06
    """

    #: RK4 steps per forcing period, or None to follow :attr:`tolerance`.
    count: int | None = None
    #: Target error of the Poincaré points (relative to the motion's scale), or None.
    tolerance: float | None = None

    @classmethod
    def fixed(cls, count: int) -> Steps:
        """``count`` RK4 steps per forcing period (an integer >= :data:`MIN_STEPS`).

        Raises
        ------
        ReducerlabError
            For anything else.
        """
        if not (isinstance(count, int) and count >= MIN_STEPS):
            raise ReducerlabError(
                f"steps_per_period must be an integer >= {MIN_STEPS}, got {count!r}"
            )
        return cls(count=count)

    @classmethod
    def accuracy(cls, tolerance: float) -> Steps:
        """The smallest step count whose Poincaré points meet ``tolerance`` (in (0, 1))
        relative to the motion's scale.

        Raises
        ------
        ReducerlabError
            For anything else.
        """
        if not (isinstance(tolerance, int | float) and 0 < tolerance < 1):
            raise ReducerlabError(f"accuracy must be a number in (0, 1), got {tolerance!r}")
        return cls(tolerance=float(tolerance))
