"""The whole chain in one call (issue 27): :func:`run` takes a design at its operating
point through every link the drive supports, caching each stage by what it depends on
(:mod:`.store`, :mod:`.stages`), and returns a :class:`RunResult` with one verdict.

This floor sits between the command line and the report: it calls the analyses and
the report, and only the command line imports it."""

from .optional import SharingSettings
from .run import RunResult, run, run_plan
from .stages import ContactSettings, LayoutSettings, Stage, SweepSettings
from .store import Store

__all__ = [
    "ContactSettings",
    "LayoutSettings",
    "RunResult",
    "SharingSettings",
    "Stage",
    "Store",
    "SweepSettings",
    "run",
    "run_plan",
]
