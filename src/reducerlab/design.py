"""Validated designs: pydantic base classes, quantity fields with units, TOML loading.

A design is one drive's parameters. Every drive defines a subclass of :class:`Design`
whose fields use the quantity types below; a design file gives each quantity either as
a plain number in SI or as a string with units (see :mod:`reducerlab.units`). Values are
converted to SI once, here, at load time.

Errors are collected into one :class:`~reducerlab.errors.DesignError` whose message has a
line per problem: ``FILE: field.path = VALUE: rule``.
"""

from __future__ import annotations

import hashlib
import math
import tomllib
import typing
from collections.abc import Mapping
from pathlib import Path
from typing import Annotated, Any, TypeVar

from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    ValidationError,
)
from pydantic_core import PydanticCustomError

from .errors import DesignError
from .units import QUANTITIES, parse_quantity

__all__ = [
    "Angle",
    "AngularVelocity",
    "Damping",
    "Design",
    "Force",
    "Length",
    "Mass",
    "MomentOfInertia",
    "NonNegativeDamping",
    "NonNegativeStiffness",
    "PositiveInt",
    "Spec",
    "SpeedRange",
    "Stiffness",
    "Torque",
    "angle_between",
    "quantity",
    "read_toml",
    "validate_design",
]


def _si(kind: str) -> BeforeValidator:
    def convert(value: Any) -> float:
        try:
            return parse_quantity(value, kind)
        except ValueError as exc:
            raise PydanticCustomError("quantity", str(exc)) from None

    return BeforeValidator(convert)


def quantity(kind: str, **constraints: float) -> Any:
    """Annotated float type for a physical quantity of ``kind`` with bounds in SI.

    Parameters
    ----------
    kind : str
        A key of :data:`reducerlab.units.QUANTITIES`.
    **constraints
        pydantic numeric constraints (``gt``, ``ge``, ``lt``, ``le``) in SI units.
    """
    if kind not in QUANTITIES:
        raise KeyError(kind)
    return Annotated[float, _si(kind), Field(**constraints)]


def angle_between(lo_deg: float, hi_deg: float, *, closed: bool = False) -> Any:
    """Annotated angle type (stored in rad) restricted to ``(lo_deg, hi_deg)`` degrees.

    A plain number is read as radians, as every other SI quantity; the range check then
    catches the common slip of writing degrees without a unit.
    """
    lo, hi = math.radians(lo_deg), math.radians(hi_deg)

    def check(value: float) -> float:
        inside = lo <= value <= hi if closed else lo < value < hi
        if not inside:
            brackets = "[]" if closed else "()"
            raise PydanticCustomError(
                "angle_range",
                "angle {deg}° out of range: must lie in {interval}"
                " (a plain number is read as radians; write e.g. '25 deg')",
                {
                    "deg": f"{math.degrees(value):.6g}",
                    "interval": f"{brackets[0]}{lo_deg:g}°, {hi_deg:g}°{brackets[1]}",
                },
            )
        return value

    return Annotated[float, _si("angle"), AfterValidator(check)]


Mass = quantity("mass", gt=0)
MomentOfInertia = quantity("moment of inertia", gt=0)
Length = quantity("length", gt=0)
Stiffness = quantity("stiffness", gt=0)
NonNegativeStiffness = quantity("stiffness", ge=0)
TorsionalStiffness = quantity("torsional stiffness", ge=0)
Damping = quantity("damping", ge=0)
NonNegativeDamping = Damping
TorsionalDamping = quantity("torsional damping", ge=0)
Force = quantity("force")
Torque = quantity("torque")
#: Speeds are bounded by 1e7 rad/s (about 95 million rpm) so that squares stay finite.
AngularVelocity = quantity("angular velocity", ge=-1e7, le=1e7)
Angle = quantity("angle")
PositiveInt = Annotated[int, Field(strict=True, gt=0)]


def _check_range(r: list[float]) -> list[float]:
    if len(r) != 2 or not 0 <= r[0] <= r[1]:
        raise PydanticCustomError(
            "speed_range", "must be [min, max] with 0 <= min <= max (e.g. ['1000 rpm', '2000 rpm'])"
        )
    return r


#: An operating speed range ``[min, max]`` (rad/s).
SpeedRange = Annotated[list[AngularVelocity], AfterValidator(_check_range)]  # type: ignore[valid-type]


class Spec(BaseModel):
    """Base of every design section: unknown fields are errors, instances are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True, validate_default=True)


class Design(Spec):
    """Base of every drive's design.

    Attributes
    ----------
    type : str
        The drive type; selects the builder (``"gear_pair"``, ...).
    name : str
        A title used in tables, figures and reports.
    """

    type: str
    name: str = ""
    description: str = ""

    @property
    def hash(self) -> str:
        """SHA-256 of the design's SI content (hex, 16 characters)."""
        return _digest(self.model_dump_json())

    @property
    def provenance(self) -> dict[str, str]:
        """``{"design": SI JSON, "design_hash": hash}``: the metadata that models and
        results built from this design carry (one JSON dump serves both)."""
        text = self.model_dump_json()
        return {"design": text, "design_hash": _digest(text)}


def _digest(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:16]


D = TypeVar("D", bound=BaseModel)


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file, turning syntax errors into a :class:`DesignError`."""
    p = Path(path)
    if not p.is_file():
        raise DesignError(f"{p}: no such design file")
    try:
        with p.open("rb") as fh:
            return tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise DesignError(f"{p}: not valid TOML: {exc}") from None
    except UnicodeDecodeError:
        raise DesignError(f"{p}: not a text file in UTF-8 (TOML must be UTF-8)") from None
    except OSError as exc:
        raise DesignError(f"{p}: cannot read the design file ({exc.strerror})") from None


_RULES = {
    "extra_forbidden": "unknown field",
    "missing": "required field is missing",
    "int_type": "must be an integer",
    "int_from_float": "must be an integer",
    "greater_than": "must be greater than {gt}",
    "greater_than_equal": "must be greater than or equal to {ge}",
    "less_than": "must be less than {lt}",
    "less_than_equal": "must be less than or equal to {le}",
    "literal_error": "must be one of {expected}",
}


def _raw_value(data: Any, loc: tuple[Any, ...]) -> Any:
    for key in loc:
        try:
            data = data[key]
        except (KeyError, IndexError, TypeError):
            return None
    return data


def _fields_at(model: type[BaseModel], loc: tuple[Any, ...]) -> list[str] | None:
    """Names of the fields allowed at ``loc`` (for 'unknown field' messages)."""
    cls: Any = model
    for key in loc:
        if isinstance(key, int):
            continue
        fields = getattr(cls, "model_fields", None)
        if fields is None or key not in fields:
            return None
        ann = fields[key].annotation
        cls = None
        for cand in (ann, *typing.get_args(ann)):
            inner = [cand, *typing.get_args(cand)]
            found = [c for c in inner if isinstance(c, type) and issubclass(c, BaseModel)]
            if found:
                cls = found[0]
                break
        if cls is None:
            return None
    fields = getattr(cls, "model_fields", None)
    return sorted(fields) if fields is not None else None


def _format_errors(
    exc: ValidationError, data: Mapping[str, Any], model: type[BaseModel], source: str
) -> list[str]:
    lines = []
    for err in exc.errors(include_url=False):
        loc = tuple(err["loc"])
        # Errors inside a tagged union carry the tag as an extra loc element.
        path = ".".join(str(k) for k in loc) or "(design)"
        kind = err["type"]
        rule = _RULES.get(kind)
        if rule is not None:
            try:
                rule = rule.format(**err.get("ctx", {}))
            except (KeyError, IndexError):
                rule = err["msg"]
        else:
            rule = err["msg"].removeprefix("Value error, ")
        if kind == "extra_forbidden":
            allowed = _fields_at(model, loc[:-1])
            if allowed:
                rule += f" (allowed: {', '.join(allowed)})"
            value = _raw_value(data, loc)
        elif kind == "missing":
            value = None
        else:
            value = _raw_value(data, loc)
        shown = "" if kind == "missing" or isinstance(value, dict | list) else f" = {value!r}"
        lines.append(f"{source}: {path}{shown}: {rule}")
    return lines


def validate_design(model: type[D], data: Mapping[str, Any], source: str = "<design>") -> D:
    """Validate ``data`` against ``model``; raise one :class:`DesignError` on failure.

    Parameters
    ----------
    model : type
        A pydantic model class (a :class:`Design` subclass or any :class:`Spec`).
    data : mapping
        The raw design, as read from TOML.
    source : str
        The file name (or another label) quoted in error messages.
    """
    try:
        return model.model_validate(dict(data))
    except ValidationError as exc:
        lines = _format_errors(exc, data, model, source)
        raise DesignError("invalid design:\n  " + "\n  ".join(lines), lines) from None
