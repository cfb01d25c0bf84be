"""Work and memory estimates, checked before a command allocates, meshes or integrates.

Every command that can be made arbitrarily large by its inputs (a contact cell size, an
FE element size, a number of speeds, periods or trajectories) estimates the memory its
largest arrays will need and the work it will do *before* it starts, and refuses with
the estimate, the limit and the setting to change when either exceeds its bound
(:class:`~reducerlab.errors.BudgetError`). A refused run costs milliseconds instead of a
kernel kill after minutes.

Memory is bounded by :data:`MEMORY_SHARE` of the memory the operating system reports as
available (``MemAvailable`` of ``/proc/meminfo``; on other systems the physical memory),
or by the environment variable ``REDUCERLAB_MEMORY_LIMIT`` (bytes, or a number with
``K``/``M``/``G``/``T``, e.g. ``"4G"``) when it is set and smaller. Work is bounded by a
documented limit of each command (cells, DOFs, steps x trajectories).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

from .errors import BudgetError

__all__ = [
    "MEMORY_ENV",
    "MEMORY_SHARE",
    "Estimate",
    "check",
    "format_bytes",
    "memory_limit",
]

#: Share of the available memory one command may plan to use (the rest is left to the
#: interpreter, libraries' temporaries and the rest of the machine).
MEMORY_SHARE = 0.8

#: Environment variable that lowers the memory limit (bytes, or ``"4G"`` etc.).
MEMORY_ENV = "REDUCERLAB_MEMORY_LIMIT"

_SUFFIX = {"": 1, "K": 2**10, "M": 2**20, "G": 2**30, "T": 2**40}


def format_bytes(n: float) -> str:
    """``n`` bytes as a short human-readable string (``"53.6 GiB"``)."""
    if not math.isfinite(n):
        return "an unbounded amount of memory"
    for unit, size in (("TiB", 2**40), ("GiB", 2**30), ("MiB", 2**20), ("KiB", 2**10)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n:.0f} B"


def _available() -> float:
    """Bytes of memory available to a new allocation (``MemAvailable``), or the physical
    memory where ``/proc/meminfo`` is missing, or infinity where neither is known."""
    try:
        with open("/proc/meminfo", encoding="ascii") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (AttributeError, OSError, ValueError):
        return math.inf


def _env_limit() -> float:
    text = os.environ.get(MEMORY_ENV, "").strip().upper().removesuffix("B").removesuffix("I")
    if not text:
        return math.inf
    suffix = text[-1] if text[-1] in _SUFFIX and not text[-1].isdigit() else ""
    number = text[: len(text) - len(suffix)].strip()
    try:
        value = float(number) * _SUFFIX[suffix]
    except ValueError:
        raise BudgetError(
            f"{MEMORY_ENV} = {os.environ[MEMORY_ENV]!r}: must be a number of bytes, "
            "optionally with K, M, G or T (e.g. '4G')"
        ) from None
    if not (math.isfinite(value) and value > 0):
        raise BudgetError(f"{MEMORY_ENV} = {os.environ[MEMORY_ENV]!r}: must be positive")
    return value


def memory_limit() -> float:
    """Bytes one command may plan to allocate: :data:`MEMORY_SHARE` of the available
    memory, or ``REDUCERLAB_MEMORY_LIMIT`` when that is smaller."""
    return min(MEMORY_SHARE * _available(), _env_limit())


@dataclass(frozen=True)
class Estimate:
    """What a command is about to do, estimated before it does it.

    Parameters
    ----------
    what : str
        The job, as the user knows it (``"contact: the cell grid"``).
    memory : float
        Peak bytes of the job's largest arrays (an estimate, deliberately on the high
        side).
    work : float, optional
        Size of the job in ``unit`` (cells, DOFs, steps x trajectories).
    unit : str, optional
        What ``work`` counts.
    work_limit : float, optional
        The documented bound on ``work`` (infinite: none).
    control : str, optional
        The setting(s) a user changes to shrink the job (``"--cell"``), named in the
        refusal.
    lower_bound : bool, optional
        ``work`` and ``memory`` are lower bounds (some size is not known yet); the
        refusal says "at least".
    """

    what: str
    memory: float
    work: float = 0.0
    unit: str = ""
    work_limit: float = math.inf
    control: str = ""
    lower_bound: bool = False

    def check(self) -> Estimate:
        """Refuse (:class:`~reducerlab.errors.BudgetError`) when the memory exceeds
        :func:`memory_limit` or the work exceeds ``work_limit``; return ``self``."""
        return check(self)


def check(estimate: Estimate) -> Estimate:
    """Refuse ``estimate`` when it exceeds the memory limit or its work limit.

    Raises
    ------
    BudgetError
        The message gives the job, the estimate, the limit and the setting to change.
    """
    hint = f"; change {estimate.control}" if estimate.control else ""
    least = "at least " if estimate.lower_bound else ""
    work = f"{least}{estimate.work:.3g} {estimate.unit}".strip() if estimate.unit else ""
    if not (estimate.work <= estimate.work_limit):
        raise BudgetError(
            f"{estimate.what}: {work} exceeds the limit of {estimate.work_limit:.3g}"
            f" {estimate.unit}{hint}"
        )
    limit = memory_limit()
    if not (estimate.memory <= limit):
        size = f" ({work})" if work else ""
        need = f"{least or 'about '}{format_bytes(estimate.memory)}"
        raise BudgetError(
            f"{estimate.what}{size} would need {need} of "
            f"memory, more than the {format_bytes(limit)} this command may use "
            f"({MEMORY_SHARE:.0%} of the available memory, or {MEMORY_ENV}){hint}"
        )
    return estimate
