"""Tolerance fields of a Monte-Carlo run (:mod:`.tolerances`): a design field path and
the distribution its value is drawn from.

A distribution is written as text, with the unit of the field as a design file would
give it (one unit for both numbers; none for a plain number, which is SI):

* uniform on ``[lo, hi]``: ``"60..100 um"`` (or ``"uniform 60..100 um"``), ``lo <= hi``;
* normal with mean and standard deviation: ``"80 +- 5 um"`` (or ``"normal 80 +- 5 um"``,
  ``±`` for ``+-``), ``sigma >= 0``.

A ``pitch_deviations`` field (``[pinion.errors]``, ``[gears.planet_errors]``, ...;
:mod:`reducerlab.drives.accuracy_specs`) takes one distribution for every tooth: each
tooth's single pitch deviation ``f_pt,k`` is drawn independently and the draws are then
made to close by subtracting their mean, ``f_pt,k - (1/z) sum_j f_pt,j``, as the
deviations of a whole gear do (they add up to zero). The distribution must therefore be
centred on zero (``"0 +- 2 um"``, ``"-3..3 um"``): a mean would be removed by the
closing. The closing lowers each deviation's variance by the factor ``(z - 1) / z``.

Tolerances come from ``--tol PATH=DIST`` (repeatable), from the ``[tolerances]`` table
of a TOML file (``PATH = "DIST"``), or from a mapping given to the API.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..design_files import read_toml
from ..errors import ReducerlabError

__all__ = [
    "Distribution",
    "Tolerance",
    "parse_distribution",
    "read_tolerance_file",
    "tolerance_items",
    "unit_factor",
]

_NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_UNIFORM = re.compile(rf"^(?:uniform\s+)?({_NUM})\s*\.\.\s*({_NUM})\s*(.*)$", re.IGNORECASE)
_NORMAL = re.compile(rf"^(?:normal\s+)?({_NUM})\s*(?:\+/?-|±)\s*({_NUM})\s*(.*)$", re.IGNORECASE)
#: Most characters of a distribution's text.
MAX_CHARS = 200
#: Path ending of a list of single pitch deviations (one distribution per tooth).
PITCH = "pitch_deviations"


@dataclass(frozen=True)
class Distribution:
    """A uniform or normal distribution of one field value, in the unit it was written.

    Parameters
    ----------
    kind : {"uniform", "normal"}
    a, b : float
        ``lo, hi`` (uniform, ``lo <= hi``) or ``mean, sigma`` (normal, ``sigma >= 0``),
        in ``unit``.
    unit : str
        The unit text (``"um"``, ``"deg"``; empty: a plain number, SI).
    text : str
        The text it was read from (for messages and the run key).
    """

    kind: str
    a: float
    b: float
    unit: str = ""
    text: str = ""

    def __post_init__(self) -> None:
        what = self.text or f"{self.kind} {self.a}, {self.b}"
        if self.kind not in ("uniform", "normal"):
            raise ReducerlabError(f"{what!r}: distribution must be uniform or normal")
        if not (math.isfinite(self.a) and math.isfinite(self.b)):
            raise ReducerlabError(f"{what!r}: the numbers must be finite")
        if self.kind == "uniform" and self.a > self.b:
            raise ReducerlabError(f"{what!r}: uniform lo..hi needs lo <= hi; got {self.a:g} > "
                                  f"{self.b:g}")  # fmt: skip
        if self.kind == "normal" and self.b < 0:
            raise ReducerlabError(f"{what!r}: normal mean +- sigma needs sigma >= 0; got "
                                  f"{self.b:g}")  # fmt: skip

    @property
    def centre(self) -> float:
        """The mean of the distribution (in ``unit``)."""
        return 0.5 * (self.a + self.b) if self.kind == "uniform" else self.a

    @property
    def bounds(self) -> tuple[float, float]:
        """Values to check against the field's rules before drawing (in ``unit``):
        ``lo, hi`` of a uniform distribution; the mean of a normal one (twice)."""
        return (self.a, self.b) if self.kind == "uniform" else (self.a, self.a)

    def draw(self, rng: np.random.Generator, size: tuple[int, ...]) -> NDArray[np.float64]:
        """``size`` independent draws (in ``unit``)."""
        if self.kind == "uniform":
            return rng.uniform(self.a, self.b, size)
        return rng.normal(self.a, self.b, size)


def parse_distribution(text: Any, option: str) -> Distribution:
    """A distribution from its text (module docstring).

    Raises
    ------
    ReducerlabError
        Naming ``option`` (``--tol 'PATH=...'``, ``FILE: tolerances.PATH``) and the rule.
    """
    if isinstance(text, bool) or not isinstance(text, str):
        raise ReducerlabError(f"{option}: a distribution is text such as '60..100 um' or "
                              f"'80 +- 5 um'; got {text!r}")  # fmt: skip
    t = text.strip()
    if len(t) > MAX_CHARS:
        raise ReducerlabError(f"{option}: {len(t)} characters is too long for a distribution")
    for kind, pattern in (("uniform", _UNIFORM), ("normal", _NORMAL)):
        m = pattern.match(t)
        if m:
            try:
                return Distribution(kind, float(m[1]), float(m[2]), m[3].strip(), t)
            except ReducerlabError as exc:
                raise ReducerlabError(f"{option}: {exc}") from None
    raise ReducerlabError(
        f"{option}: {t!r} is not a distribution; write 'LO..HI UNIT' (uniform, e.g. "
        "'60..100 um') or 'MEAN +- SIGMA UNIT' (normal, e.g. '80 +- 5 um')"
    )


def unit_factor(unit: str, option: str) -> float:
    """SI value of one ``unit`` (``"um"`` -> 1e-6, ``"deg"`` -> pi/180; ``""`` -> 1).

    The field's own rules check the unit's dimension when the run checks the
    distribution's bounds against the design (:func:`.tolerances.tolerances`)."""
    if not unit:
        return 1.0
    import pint

    from ..units import registry

    try:
        q = registry().Quantity(1.0, unit).to_base_units()
    except (pint.errors.PintError, AttributeError, TypeError, ValueError) as exc:
        raise ReducerlabError(f"{option}: cannot read the unit {unit!r} ({exc})") from None
    value = float(q.magnitude)
    if not (math.isfinite(value) and value > 0):
        raise ReducerlabError(f"{option}: the unit {unit!r} has no positive SI value")
    return value


@dataclass(frozen=True)
class Tolerance:
    """One toleranced field: its path, distribution, the SI value of one unit and, for a
    pitch-deviation list, the gear's number of teeth (one draw per tooth)."""

    path: str
    dist: Distribution
    option: str
    factor: float = 1.0
    teeth: int = 0
    floor: float = 0.0

    @property
    def per_tooth(self) -> bool:
        """Whether the field is a list of single pitch deviations."""
        return self.path.rsplit(".", 1)[-1] == PITCH

    def draw(self, rng: np.random.Generator, n: int) -> NDArray[np.float64]:
        """``n`` draws in SI: (n,) for a scalar field; (n, teeth) for pitch deviations,
        closed (each row's mean subtracted; module docstring). A draw whose magnitude is
        below ``floor`` (the smallest nonzero magnitude the field takes, 1 nm for a
        length: :data:`reducerlab.units.QUANTITIES`) is taken as 0; in a pitch list the
        change goes to the row's largest deviation, so that the row still closes."""
        if not self.per_tooth:
            x = self.factor * self.dist.draw(rng, (n,))
            return np.where(np.abs(x) < self.floor, 0.0, x)
        f = self.dist.draw(rng, (n, self.teeth))
        f = self.factor * (f - f.mean(axis=1, keepdims=True))
        tiny = np.abs(f) < self.floor
        if tiny.any():
            moved = np.where(tiny, f, 0.0).sum(axis=1)
            f = np.where(tiny, 0.0, f)
            big = np.argmax(np.abs(f), axis=1)
            f[np.arange(n), big] += moved
        return f


def teeth_path(path: str) -> str | None:
    """Where the number of teeth of a pitch-deviation list's gear is:
    ``pinion.errors.pitch_deviations`` -> ``pinion.teeth``,
    ``gears.planet_errors.pitch_deviations`` -> ``gears.planet_teeth``; None otherwise."""
    parts = path.split(".")
    if len(parts) < 2 or parts[-1] != PITCH:
        return None
    table = parts[-2]
    if table == "errors":
        return ".".join([*parts[:-2], "teeth"])
    if table.endswith("_errors"):
        return ".".join([*parts[:-2], table.removesuffix("_errors") + "_teeth"])
    return None


def tolerance_items(tols: Any, option: str = "--tol") -> list[tuple[str, Distribution, str]]:
    """``(path, distribution, option label)`` of each tolerance, in the order given.

    Parameters
    ----------
    tols : mapping or sequence
        ``{path: "DIST" or Distribution}``, or a sequence of ``"PATH=DIST"`` (``--tol``)
        and ``(path, DIST, label)`` items (``label`` names the option in messages).
    option : str
        The option or file they came from, for messages.
    """
    items: list[tuple[str, Any, str]] = []
    if isinstance(tols, Mapping):
        items = [(str(p), v, f"{option} {p}") for p, v in tols.items()]
    else:
        for item in tols:
            if isinstance(item, tuple) and len(item) == 3:  # (path, dist, label)
                items.append((str(item[0]), item[1], str(item[2])))
                continue
            if not isinstance(item, str) or "=" not in item:
                raise ReducerlabError(f"{option} {item!r}: write PATH=DIST, e.g. "
                                      "mesh.backlash='60..100 um'")  # fmt: skip
            p, _, v = item.partition("=")
            items.append((p.strip(), v.strip().strip("'\""), f"{option} {item!r}"))
    out, seen = [], set()
    for path, value, label in items:
        if not path or any(not k.strip() for k in path.split(".")):
            raise ReducerlabError(f"{label}: the path names no field")
        if path in seen:
            raise ReducerlabError(f"{label}: {path} is toleranced twice")
        seen.add(path)
        dist = value if isinstance(value, Distribution) else parse_distribution(value, label)
        out.append((path, dist, label))
    return out


def read_tolerance_file(path: str | Path) -> dict[str, str]:
    """The ``[tolerances]`` table of a TOML file (``PATH = "DIST"``; dotted keys and
    nested tables are joined into paths).

    Raises
    ------
    ReducerlabError
        Naming the file: unreadable, no ``[tolerances]`` table, another top-level table,
        or a value that is not a distribution's text.
    """
    data = read_toml(path)
    extra = sorted(set(data) - {"tolerances"})
    if extra:
        raise ReducerlabError(f"{path}: unknown table or key {extra[0]!r}; a tolerance file "
                              "holds one [tolerances] table")  # fmt: skip
    table = data.get("tolerances")
    if not isinstance(table, dict) or not table:
        raise ReducerlabError(f'{path}: no [tolerances] table of PATH = "DIST" entries')
    out: dict[str, str] = {}

    def flat(node: dict[str, Any], prefix: str) -> None:
        for k, v in node.items():
            key = f"{prefix}{k}"
            if isinstance(v, dict):
                flat(v, key + ".")
            elif isinstance(v, str):
                out[key] = v
            else:
                raise ReducerlabError(f"{path}: tolerances.{key} = {v!r}: write the "
                                      "distribution as text, e.g. \"60..100 um\"")  # fmt: skip

    flat(table, "")
    return out
