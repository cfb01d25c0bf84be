"""Validated designs: pydantic base classes, quantity fields with units, TOML loading.

A design is one drive's parameters. Every drive defines a subclass of :class:`Design`
whose fields use the quantity types below; a design file gives each quantity either as
a plain number in SI or as a string with units (see :mod:`reducerlab.units`). Values are
converted to SI once, here, at load time.

Errors are collected into one :class:`~reducerlab.errors.DesignError` whose message has a
line per problem: ``FILE: field.path = VALUE: rule``.
"""

from __future__ import annotations

import math
import stat
import tomllib
import typing
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Self, TypeVar

from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    PrivateAttr,
    ValidationError,
)
from pydantic_core import PydanticCustomError

from .errors import DesignError
from .io import digest
from .units import QUANTITIES, parse_quantity, shown

if TYPE_CHECKING:
    from .kinematics import DriveKinematics

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
    "Real",
    "Spec",
    "SpeedRange",
    "Stiffness",
    "Torque",
    "angle_between",
    "apply_overrides",
    "field_kind",
    "field_rules",
    "operating_range_of",
    "quantity",
    "read_toml",
    "set_path",
    "validate_design",
]


def _si(kind: str) -> BeforeValidator:
    def convert(value: Any) -> float:
        try:
            return parse_quantity(value, kind)
        except ValueError as exc:
            raise PydanticCustomError("quantity", str(exc)) from None

    convert.quantity_kind = kind  # type: ignore[attr-defined]  # read by field_kind
    return BeforeValidator(convert)


def field_kind(design: BaseModel, path: str) -> str | None:
    """The quantity kind (a key of :data:`reducerlab.units.QUANTITIES`) of the design
    field at dotted ``path`` (``"input_speed"`` -> ``"angular velocity"``), ``None`` for
    a plain number or a path that is not a quantity field."""
    node: Any = design
    info = None
    for key in path.split("."):
        if isinstance(node, list | tuple):
            if not key.isdigit() or int(key) >= len(node):
                return None
            node = node[int(key)]
            continue
        fields = getattr(type(node), "model_fields", None)
        if fields is None or key not in fields:
            return None
        info = fields[key]
        node = getattr(node, key)
    if info is None:
        return None
    for meta in info.metadata:
        kind = getattr(getattr(meta, "func", None), "quantity_kind", None)
        if kind is not None:
            return kind
    for arg in typing.get_args(info.annotation):  # Optional[quantity]
        for meta in getattr(arg, "__metadata__", ()):
            kind = getattr(getattr(meta, "func", None), "quantity_kind", None)
            if kind is not None:
                return kind
    return None


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
#: Speeds are bounded by the kind's range, 1e7 rad/s (about 95 million rpm), so that
#: squares stay finite.
AngularVelocity = quantity("angular velocity")
Angle = quantity("angle")
#: Counts (teeth, lobes, balls, bearings): a positive integer, at most 100000 so that the
#: geometry built from it stays finite.
PositiveInt = Annotated[int, Field(strict=True, gt=0, le=100_000)]


def _representable(value: float) -> float:
    kind = QUANTITIES["dimensionless"]
    if value != 0 and not kind.lo <= abs(value) <= kind.hi:
        raise PydanticCustomError(
            "number_range",
            "outside the representable range: 0 or a magnitude within [{lo}, {hi}]",
            {"lo": f"{kind.lo:g}", "hi": f"{kind.hi:g}"},
        )
    return value


#: A plain number that is not a physical quantity (a ratio, a projection coefficient):
#: finite, strictly a number (not a boolean or a string), and 0 or of a magnitude within
#: the range of the "dimensionless" kind of :data:`reducerlab.units.QUANTITIES`.
Real = Annotated[float, Field(strict=True, allow_inf_nan=False), AfterValidator(_representable)]


def _check_range(r: list[float]) -> list[float]:
    if len(r) != 2 or not 0 <= r[0] <= r[1]:
        raise PydanticCustomError(
            "speed_range", "must be [min, max] with 0 <= min <= max (e.g. ['1000 rpm', '2000 rpm'])"
        )
    return r


#: An operating speed range ``[min, max]`` (rad/s).
SpeedRange = Annotated[list[AngularVelocity], AfterValidator(_check_range)]  # type: ignore[valid-type]


class Spec(BaseModel):
    """Base of every design section: unknown fields are errors, instances are frozen.

    Validation is strict: a boolean field takes only ``true``/``false`` (not 1, "yes",
    "on"), a number field takes only a number (not ``true`` or a string), a list only a
    list; numbers must be finite. Quantity fields still read strings with units, since
    their converter runs before the strict float check. Plain numbers that are not
    quantities use :data:`Real` (or an explicitly bounded float).
    """

    model_config = ConfigDict(
        extra="forbid", frozen=True, validate_default=True, strict=True, allow_inf_nan=False
    )


class BifurcationRequest(Spec):
    """A bifurcation diagram the report computes (``[report.bifurcation]``): ``parameter``
    a design field or model parameter path, ``values`` a value specification
    (``"lin:300 rpm:3000 rpm:40"``, as ``reducerlab bifurcation -v``)."""

    parameter: Annotated[str, Field(min_length=1)]
    values: Annotated[str, Field(min_length=1)]
    periods: Annotated[int, Field(strict=True, ge=20, le=100_000)] = 600
    keep: Annotated[int, Field(strict=True, ge=1, le=10_000)] = 100


class RegimeMapRequest(Spec):
    """A regime map the report computes (``[report.regime_map]``): ``x`` and ``y`` are
    ``PATH=VALUES`` (as ``reducerlab regime-map -x/-y``)."""

    x: Annotated[str, Field(min_length=3)]
    y: Annotated[str, Field(min_length=3)]
    periods: Annotated[int, Field(strict=True, ge=20, le=100_000)] = 600
    keep: Annotated[int, Field(strict=True, ge=1, le=10_000)] = 64


class ReportSpec(Spec):
    """What the design report computes beyond the standard sections (``[report]``)."""

    bifurcation: BifurcationRequest | None = None
    regime_map: RegimeMapRequest | None = None


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
    report: ReportSpec | None = None
    _source: str = PrivateAttr(default="<design>")

    @property
    def source(self) -> str:
        """Where the design came from (its file for ``load_design``), quoted in front
        of every error that the builders raise about it."""
        return self._source

    @property
    def hash(self) -> str:
        """SHA-256 of the design's SI content (hex, 16 characters); the ``[report]``
        table (what the report draws, not what is analysed) is left out."""
        return digest(self.model_dump_json(exclude={"report"}))

    @property
    def provenance(self) -> dict[str, str]:
        """``{"design": SI JSON, "design_hash": hash, "source": file}``: the metadata that
        models and results built from this design carry (one JSON dump serves both; the
        source, when known, lets an analysis's error name the file)."""
        text = self.model_dump_json(exclude={"report"})
        out = {"design": text, "design_hash": digest(text)}
        if self._source != "<design>":
            out["source"] = self._source
        return out

    # -- the drive contract: what analyses and the report ask of every design --------

    @property
    def drive_name(self) -> str:
        """The drive this design describes (its ``type``; a kinematics-only design names
        its ``drive``), for titles and for choosing the papers' assumptions."""
        return self.type

    @property
    def operating_speed(self) -> float:
        """The operating speed of the input member (rad/s); 0 for a design at rest."""
        return 0.0

    def operating_range(self) -> tuple[float, float]:
        """The operating speed range ``(min, max)`` of the input member (rad/s): the
        design's ``speed_range`` where it gives one, else the operating speed twice."""
        s = float(self.operating_speed)
        return s, s

    def kinematics(self) -> DriveKinematics | None:
        """The drive's kinematics (ratio, member speeds, mesh frequencies), or None for
        a design that defines none (a lumped model)."""
        return None

    @property
    def has_tooth_surfaces(self) -> bool:
        """Whether the design describes tooth surfaces that can be generated (paper 001)."""
        return False

    def with_values(self, changes: Mapping[str, Any], source: str | None = None) -> Self:
        """A validated copy with fields changed: ``{"gears.x1": 0.5, "gears.x2": None}``.

        Paths are dotted into the design's SI dump (list items by index); values are SI
        numbers or what a design file may hold there. The copy is validated again, so
        a value that breaks a rule raises :class:`~reducerlab.errors.DesignError`
        naming ``source`` (default: this design's source with the changes), the field
        and the rule.
        """
        data = self.model_dump(mode="json")
        for path, value in changes.items():
            set_path(data, path, value, "with_values")
        label = source or f"{self.source} with " + ", ".join(
            f"{k} = {shown(v)}" for k, v in changes.items()
        )
        out = validate_design(type(self), data, label)
        out._source = label
        return out


def operating_range_of(speed: float, speed_range: list[float] | None) -> tuple[float, float]:
    """``speed_range`` as ``(min, max)`` when given, else ``(speed, speed)`` (rad/s)."""
    if speed_range:
        return float(speed_range[0]), float(speed_range[1])
    return float(speed), float(speed)


D = TypeVar("D", bound=BaseModel)

#: Largest design file read, in bytes (a real design is a few kB).
MAX_DESIGN_BYTES = 10 * 1024 * 1024


def read_toml(path: str | Path) -> dict[str, Any]:
    """Read a TOML file, turning every failure into a :class:`DesignError`.

    A UTF-8 byte-order mark at the start is skipped; syntax errors, text that is not
    UTF-8, unreadable files, directories and other files that are not regular files
    (devices, pipes), files larger than :data:`MAX_DESIGN_BYTES` and nesting too deep
    for the parser name the file.
    """
    p = Path(path)
    try:
        st = p.stat()
    except FileNotFoundError:
        raise DesignError(f"{p}: no such design file") from None
    except OSError as exc:
        raise DesignError(f"{p}: cannot read the design file ({exc.strerror})") from None
    if stat.S_ISDIR(st.st_mode):
        raise DesignError(f"{p}: is a directory, not a design file")
    if not stat.S_ISREG(st.st_mode):
        raise DesignError(f"{p}: is not a regular file (a design file is a TOML text file)")
    too_big = DesignError(
        f"{p}: larger than {MAX_DESIGN_BYTES // 2**20} MB; a design file is a few kB of TOML"
    )
    if st.st_size > MAX_DESIGN_BYTES:
        raise too_big
    try:
        with p.open("rb") as f:  # bounded read: the file may grow after stat()
            raw = f.read(MAX_DESIGN_BYTES + 1)
        if len(raw) > MAX_DESIGN_BYTES:
            raise too_big
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise DesignError(f"{p}: not a text file in UTF-8 (TOML must be UTF-8)") from None
    except OSError as exc:
        raise DesignError(f"{p}: cannot read the design file ({exc.strerror})") from None
    # a byte-order mark, as some Windows editors write, is not part of the TOML text
    text = text.removeprefix("\ufeff")
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise DesignError(f"{p}: not valid TOML: {exc}") from None
    except RecursionError:
        raise DesignError(
            f"{p}: not a usable design: arrays or inline tables nested too deeply"
        ) from None


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
    "bool_type": "must be true or false",
    "float_type": "must be a number",
    "finite_number": "must be a finite number",
    "string_type": "must be a string",
    "list_type": "must be a list (an array)",
    "dict_type": "must be a table",
    "model_type": "must be a table",
    "model_attributes_type": "must be a table",
}


def _raw_value(data: Any, loc: tuple[Any, ...]) -> Any:
    for key in loc:
        try:
            data = data[key]
        except (KeyError, IndexError, TypeError):
            return None
    return data


def _user_loc(data: Any, loc: tuple[Any, ...]) -> tuple[Any, ...]:
    """``loc`` without the tags pydantic inserts for a tagged union (``elements.0.mesh``
    becomes ``elements.0``): the path as the user wrote it."""
    out = []
    for key in loc:
        if isinstance(data, Mapping) and key not in data and data.get("type") == key:
            continue
        out.append(key)
        try:
            data = data[key]
        except (KeyError, IndexError, TypeError):
            data = None
    return tuple(out)


def field_rules(*problems: tuple[str, str]) -> PydanticCustomError:
    """The error a model validator raises for rules between fields, naming each field.

    Parameters
    ----------
    *problems : (str, str)
        ``(field path relative to the model, rule)`` pairs, e.g.
        ``("operating.speed", "must be > 0 to set the mesh frequency")``.

    Returns
    -------
    PydanticCustomError
        To ``raise``; :func:`validate_design` reports one line per problem as
        ``FILE: model.path.field = VALUE: rule``.
    """
    message = "; ".join(f"{path}: {rule}" for path, rule in problems)
    return PydanticCustomError("field_rules", message, {"problems": [list(p) for p in problems]})


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
        loc = _user_loc(data, tuple(err["loc"]))
        kind = err["type"]
        if kind == "field_rules":  # rules between fields: one line per named field
            for sub, rule in err["ctx"]["problems"]:
                lines.append(_line(source, data, (*loc, *_split(sub)), rule))
            continue
        rule = _RULES.get(kind)
        if rule is not None:
            try:
                rule = rule.format(**err.get("ctx", {}))
            except (KeyError, IndexError):
                rule = err["msg"]
        else:
            rule = err["msg"].removeprefix("Value error, ")
        if kind == "extra_forbidden":
            allowed = _fields_at(model, tuple(err["loc"])[:-1])
            if allowed:
                rule += f" (allowed: {', '.join(allowed)})"
        lines.append(_line(source, data, loc, rule, show=kind != "missing"))
    return lines


def _split(path: str) -> tuple[Any, ...]:
    return tuple(int(k) if k.isdigit() else k for k in path.split(".") if k)


def _line(
    source: str, data: Mapping[str, Any], loc: tuple[Any, ...], rule: str, show: bool = True
) -> str:
    """``FILE: field.path = VALUE: rule`` (the value when the file gives a scalar, cut to
    :data:`reducerlab.units.SHOW_CHARS` characters)."""
    path = ".".join(str(k) for k in loc) or "(design)"
    value = _raw_value(data, loc)
    text = (
        "" if not show or value is None or isinstance(value, dict | list) else f" = {shown(value)}"
    )
    return f"{source}: {path}{text}: {rule}"


def _override_value(text: str) -> Any:
    """The value of a ``PATH=VALUE`` override: a TOML literal (``670``, ``true``,
    ``"involute"``, ``[1, 2]``) where it reads as one, else the text itself (``670 rpm``,
    ``involute``), which a quantity or text field parses."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text.strip()


def apply_overrides(
    data: Mapping[str, Any], overrides: typing.Sequence[str], option: str = "--set"
) -> dict[str, Any]:
    """A copy of raw design data with ``PATH=VALUE`` overrides applied, before validation.

    ``PATH`` is a dotted path into the design (``input_speed``, ``gears.x1``,
    ``elements.4.stiffness``); ``VALUE`` is what the design file would hold there, with
    units where the field is a quantity (``670 rpm``, ``2.5e8 N/m``). A field the file
    leaves at its default may be set too (its table is created); the design's schema
    then checks the value and names the field and the rule when it is wrong.

    Raises
    ------
    DesignError
        For an override that is not ``PATH=VALUE``, or whose path runs through a value
        that is not a table or list, or past the end of a list.
    """
    import copy

    out: dict[str, Any] = copy.deepcopy(dict(data))
    for item in overrides:
        if not isinstance(item, str) or "=" not in item:
            raise DesignError(f"{option} {item!r}: write PATH=VALUE, e.g. input_speed=670rpm")
        path, _, text = item.partition("=")
        path = path.strip()
        if not path or any(not k.strip() for k in path.split(".")):
            raise DesignError(f"{option} {item!r}: the path before '=' names no field")
        if not text.strip():
            raise DesignError(f"{option} {item!r}: no value after '='")
        set_path(out, path, _override_value(text), f"{option} {item!r}")
    return out


def set_path(data: dict[str, Any], path: str, value: Any, what: str) -> None:
    """Set ``value`` at the dotted ``path`` of raw design data (list items by index;
    missing tables are created), in place.

    Raises
    ------
    DesignError
        Naming ``what`` when the path runs through a value that is not a table or list,
        or past the end of a list.
    """
    keys = path.split(".")
    node: Any = data
    for depth, key in enumerate(keys):
        last = depth == len(keys) - 1
        where = ".".join(keys[:depth]) or "the design"
        if isinstance(node, list):
            if not key.isdigit() or int(key) >= len(node):
                raise DesignError(
                    f"{what}: {where} is a list of {len(node)}; {key!r} is not an index in it"
                )
            if last:
                node[int(key)] = value
            else:
                node = node[int(key)]
        elif isinstance(node, dict):
            if last:
                node[key] = value
            else:
                node = node.setdefault(key, {})
        else:
            raise DesignError(f"{what}: {where} = {shown(node)} is a value, not a table")


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
