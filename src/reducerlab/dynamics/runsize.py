"""Work and memory of an integration, estimated before it starts
(:class:`reducerlab.budget.Estimate`): RK4 steps x trajectories, and the bytes of the
Poincaré points and histories it returns."""

from __future__ import annotations

from ..budget import Estimate

__all__ = ["AUTO_STEPS_FLOOR", "MAX_WORK", "run_estimate"]

#: Most RK4 steps (summed over the trajectories) one command may plan. The compiled
#: kernel does about 1e6 to 5e6 steps per second and core on the bundled examples
#: (benchmarks/RESULTS.md), so this is a day or more of one core: anything larger is a
#: typing error (a period or value count with extra zeros), refused before it starts.
MAX_WORK = 1e11

#: Fewest steps per period the automatic step rule ever picks (the stability count is at
#: least 32, :func:`reducerlab.dynamics.steps.steps_for`): the lower bound used where a
#: command estimates its work before the model's step count is known.
AUTO_STEPS_FLOOR = 32

#: Temporaries beside the returned arrays (mesh deflections, times, force laws) and the
#: working copies of the kernel: a factor on the returned bytes, on the high side.
_TEMPORARIES = 3.0


def run_estimate(
    what: str,
    members: int,
    periods: int,
    steps: int,
    n: int,
    lines: int = 1,
    keep: int = 1,
    history: int = 0,
    exponents: bool = False,
    *,
    at_least: bool = False,
    control: str = "--periods, --steps or the number of values",
) -> Estimate:
    """The work and memory of integrating ``members`` trajectories for ``periods``
    forcing periods of ``steps`` RK4 steps.

    Parameters
    ----------
    what : str
        The job, as the user knows it (``"bifurcation"``).
    members : int
        Trajectories (values x seeds x sweep directions).
    periods, steps : int
        Forcing periods per trajectory and RK4 steps per period.
    n, lines : int
        DOFs of the (reduced) system and mesh lines.
    keep, history : int
        Poincaré points kept and periods whose every step is returned.
    exponents : bool
        Each trajectory runs beside a perturbed copy (twice the work).
    at_least : bool
        ``steps`` is a lower bound (the step rule has not run yet); the message says so.
    control : str
        The settings a user changes to shrink the job.

    Returns
    -------
    Estimate
        Work in RK4 steps (bounded by :data:`MAX_WORK`), memory in bytes.
    """
    copies = 2 if exponents else 1
    work = float(members) * float(periods) * float(steps) * copies
    state = 2 * n
    per_member = (keep + 1) * (state + 2 * lines) + history * steps * (state + 3 * lines + 2)
    memory = 8.0 * _TEMPORARIES * copies * float(members) * per_member
    return Estimate(what, memory, work, "RK4 steps", MAX_WORK, control, at_least)
