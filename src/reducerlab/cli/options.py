"""The options the commands share, parsed in one place: the design argument and
``--set``, output folders, ``--format``, ``--workers``/``--scheduler``, the run lengths
(``--periods``, ``--steps``, ``--accuracy``, ``--period``/``--frequency``), the sweep
direction (``--continuation``), and the parsers of values given as text (speeds,
quantities, parameter axes).

Counts are bounded here (checked before any work, the option named in the message).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from contextlib import contextmanager
from enum import StrEnum
from pathlib import Path
from typing import Annotated, Any

import typer

from ..analysis.policies import Continuation
from ..analysis.workers import max_workers
from ..errors import ReducerlabError

MAX_SPEEDS = 100_000
"""Most input speeds of ``campbell --speeds``."""
MAX_SWEEP_POINTS = 1_000_000
"""Most points of a ``sweep`` (all axes together)."""
MAX_VALUES = 100_000
"""Most parameter values of a ``bifurcation``."""
MAX_PERIODS = 1_000_000
"""Most forcing periods of ``bifurcation`` and ``response``."""
MAX_WORKERS = max_workers()
"""Most worker processes (``--workers``): the API's limit, 4 per core."""
SCHEDULER_TIMEOUT_S = 10.0
"""Seconds allowed to connect to a Dask scheduler (``--scheduler``)."""


class Format(StrEnum):
    """What a command prints on stdout (``--format``)."""

    table = "table"
    json = "json"


class ProfileChoice(StrEnum):
    """Basic tooth profiles of the tooth surfaces (``--profile``)."""

    involute = "involute"
    double_arc = "double-arc"


Direction = StrEnum(
    "Direction", [(c.name, c.value) for c in Continuation if c is not Continuation.NONE]
)
"""The sweep directions of :class:`~reducerlab.analysis.policies.Continuation` without
``none`` (``bifurcation``/``frequency-response --continuation``: up, down, both)."""


DesignArgument = Annotated[Path, typer.Argument(help="Design file (TOML).")]
"""The design file every command but ``demo`` reads."""

SetOption = Annotated[
    list[str] | None,
    typer.Option(
        "--set",
        metavar="PATH=VALUE",
        help="Override a design field, units allowed (repeatable): --set 'input_speed=670 rpm'.",
    ),
]
"""``--set PATH=VALUE``: design fields overridden before validation (every command that
reads a design file takes it; see :func:`reducerlab.design_files.apply_overrides`)."""

FormatOption = Annotated[Format, typer.Option("--format", help="Output on stdout.")]
"""``--format table|json``: what is printed on stdout."""

ResultsOption = Annotated[
    Path | None, typer.Option("--output", "-o", help="Write results and figure here.")
]
"""``-o DIR``: an optional output folder for a command's results and figure."""

SchedulerOption = Annotated[
    str | None, typer.Option(help="Dask scheduler address, e.g. tcp://HOST:8786.")
]
"""``--scheduler``: run the chunks of a resumable command on a Dask cluster."""

AccuracyOption = Annotated[
    float,
    typer.Option(
        help="Target error of the Poincaré points relative to the motion's scale: the "
        "step count is chosen to meet it (ignored with --steps).",
        min=1e-12,
        max=0.1,
    ),
]
"""``--accuracy``: target error of the Poincaré points (the step count's rule)."""

PeriodOption = Annotated[
    str | None,
    typer.Option(
        "--period",
        help="Forcing period, e.g. '2 ms' or 0.002 (s), for a design without a periodic "
        "mesh law (default: the design's).",
    ),
]
"""``--period``: the forcing period as a quantity (see :func:`forcing_period`)."""

FrequencyOption = Annotated[
    str | None,
    typer.Option("--frequency", help="Forcing frequency, e.g. '500 Hz' (instead of --period)."),
]
"""``--frequency``: the forcing frequency, instead of ``--period``."""

GearOption = Annotated[
    int,
    typer.Option("--gear", "-g", help="Gear number: 1, 3 nutating (internal); 2, 4 external."),
]
"""``--gear``: a gear of a nutation drive."""


def check_rigid_tol(value: float) -> float:
    """Typer callback: ``--rigid-tol`` must be a finite number in [0, 1)."""
    if not 0 <= value < 1:  # also false for NaN
        raise typer.BadParameter(f"must be a finite number in [0, 1); got {value!r}")
    return value


def model_from(design_path: Path, sets: list[str] | None = None):
    """The design read from ``design_path`` with ``--set`` applied, and its model."""
    from ..drives import build_model, load_design

    design = load_design(design_path, sets or ())
    return design, build_model(design)


def axis(option: str, path: str, spec: str, limit: int):
    """A value specification (:func:`~reducerlab.analysis.parameters.parse_values`) of at most
    ``limit`` values."""
    from ..analysis.parameters import parse_values

    return parse_values(path, spec, limit=limit, option=option)


def path_values(
    option: str, text: str, limit: int, example: str = "input_speed=lin:300 rpm:2000 rpm:41"
):
    """``PATH=VALUES`` (``sweep --grid``, ``regime-map -x/-y``) as an axis."""
    from ..analysis.parameters import parse_path_values

    return parse_path_values(text, limit=limit, option=option, example=example)


def parse_speeds(spec: str | None, option: str = "--speeds") -> list[float] | None:
    """``lin:START:STOP:N`` in rpm, or a comma list in rpm (at most :data:`MAX_SPEEDS`),
    as input speeds in rad/s; None without a specification."""
    if spec is None:
        return None
    import numpy as np

    from ..units import QUANTITIES, RPM

    values = axis(option, "speeds", spec, MAX_SPEEDS)
    if values.relative or any(isinstance(v, str) for v in values.values):
        raise ReducerlabError(f"{option} takes plain numbers in rpm, e.g. lin:0:3000:301")
    rpm = np.asarray(values.values, dtype=float)
    # the range of the speeds that design files may give (units.QUANTITIES), in rpm
    kind = QUANTITIES["angular velocity"]
    lo, hi = kind.lo * RPM, kind.hi * RPM
    bad = rpm[~((rpm == 0) | ((rpm >= lo) & (rpm <= hi)))]  # also negative, non-finite
    if bad.size:
        raise ReducerlabError(
            f"{option}: {bad[0]:g} rpm is outside the range of speeds: 0 or within "
            f"[{lo:.3g}, {hi:.3g}] rpm"
        )
    return (rpm / RPM).tolist()


_ADDRESS = re.compile(
    r"(?:(?:tcp|tls|ucx|ws|wss)://)?(?:\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):([0-9]{1,5})"
)


@contextmanager
def scheduler_client(address: str | None) -> Iterator[Any]:
    """A Dask client for ``--scheduler`` (None without one), closed afterwards.

    The address form is checked before connecting; a failed connection (within
    :data:`SCHEDULER_TIMEOUT_S`) is a :class:`ReducerlabError` naming ``--scheduler``.
    """
    if address is None:
        yield None
        return
    m = _ADDRESS.fullmatch(address.strip())
    if not m or not 1 <= int(m.group(1)) <= 65535:
        raise ReducerlabError(
            f"--scheduler: {address!r} is not a scheduler address; write "
            "tcp://HOST:PORT, e.g. tcp://10.0.0.5:8786"
        )
    try:
        from dask.distributed import Client
    except ImportError:  # pragma: no cover - dask is a dependency
        raise ReducerlabError("--scheduler needs dask.distributed installed") from None
    try:
        client = Client(address.strip(), timeout=SCHEDULER_TIMEOUT_S)
    except (OSError, TimeoutError, ValueError) as exc:
        raise ReducerlabError(
            f"--scheduler {address}: cannot connect to a Dask scheduler within "
            f"{SCHEDULER_TIMEOUT_S:g} s ({type(exc).__name__}: {exc})"
        ) from None
    try:
        yield client
    finally:
        client.close()


def check_periods(periods: int, **counts: int) -> None:
    """``--keep``/``--history`` must not exceed ``--periods``."""
    for name, value in counts.items():
        if value > periods:
            raise ReducerlabError(f"--{name} {value}: must be at most --periods ({periods})")


def quantity_option(text: str | None, option: str, kind: str) -> float | None:
    """A positive finite quantity of ``kind`` ("time", "frequency", "length", ...) from
    an option, in SI: a plain number in SI or a quantity string ("2 ms", "1.2 mm");
    None without one.

    A plain number and a number with a unit pass the same checks
    (:func:`reducerlab.units.parse_quantity`): the kind's representable range, then
    finite and > 0."""
    if text is None:
        return None
    value = _in_range(text, option, kind)
    if not (math.isfinite(value) and value > 0):
        raise ReducerlabError(f"{option}: must be a finite {kind} > 0; got {text!r}")
    return value


def signed_quantity(text: str, option: str, kind: str) -> float:
    """A finite quantity of ``kind`` that may be negative or zero (SI), its magnitude
    checked against the kind's range as :func:`quantity_option` checks it."""
    t = text.strip()
    sign = -1.0 if t.startswith("-") else 1.0
    body = t[1:] if t[:1] in "+-" else t
    value = _in_range(body, option, kind)
    if not math.isfinite(value):
        raise ReducerlabError(f"{option}: must be finite; got {text!r}")
    return sign * value


def _in_range(text: str, option: str, kind: str) -> float:
    """``text`` (a plain number in SI, or a number with a unit) in SI, refused outside
    the representable range of ``kind`` with the option named."""
    from ..units import parse_quantity

    try:
        plain: float | str = float(text)
    except ValueError:
        plain = text
    if isinstance(plain, float) and not math.isfinite(plain):
        return plain  # the caller refuses it in its own words
    try:
        return parse_quantity(plain, kind)
    except ValueError as exc:
        raise ReducerlabError(f"{option}: {exc}") from None


def forcing_period(period: str | None, frequency: str | None) -> float | None:
    """The sampling period (s) given by ``--period`` or ``--frequency``, or None."""
    if period is not None and frequency is not None:
        raise ReducerlabError("--period and --frequency: give one of them, not both")
    f = quantity_option(frequency, "--frequency", "frequency")
    return 1.0 / f if f is not None else quantity_option(period, "--period", "time")
