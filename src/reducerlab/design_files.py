"""Design files: reading TOML, ``PATH=VALUE`` overrides, and validation whose errors name
the file, the field, the value and the rule.

:func:`validate_design` collects every problem into one
:class:`~reducerlab.errors.DesignError` with a line per problem,
``FILE: field.path = VALUE: rule``; model validators report rules between fields with
:func:`field_rules`.
"""

from __future__ import annotations

import copy
import stat
import tomllib
import typing
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, TypeVar

from pydantic import BaseModel, ValidationError
from pydantic_core import PydanticCustomError

from .errors import DesignError
from .units import shown

__all__ = [
    "MAX_DESIGN_BYTES",
    "apply_overrides",
    "field_rules",
    "lookup",
    "path_keys",
    "read_toml",
    "set_path",
    "validate_design",
    "walk",
]


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


def path_keys(data: Any, path: str) -> tuple[Any, ...] | None:
    """The keys of a dotted path in nested tables and lists.

    Parameters
    ----------
    data : dict or list
        Raw design data (a design file's tables, a design's ``model_dump()``).
    path : str
        Dotted, list items by index: ``"elements.4.stiffness"``.

    Returns
    -------
    tuple or None
        The keys (str for tables, int for lists), for :func:`walk`; None where the path
        is not in ``data``.
    """
    keys: list[Any] = []
    node: Any = data
    for part in path.split("."):
        if isinstance(node, dict) and part in node:
            keys.append(part)
            node = node[part]
        elif isinstance(node, list) and part.isdigit() and int(part) < len(node):
            keys.append(int(part))
            node = node[int(part)]
        else:
            return None
    return tuple(keys)


def walk(data: Any, keys: Sequence[Any]) -> Any:
    """The value that ``keys`` (from :func:`path_keys`) lead to in ``data``."""
    for k in keys:
        data = data[k]
    return data


def lookup(data: Any, path: str) -> Any:
    """The value at a dotted ``path`` of nested tables and lists (see :func:`path_keys`),
    None where the path is not there."""
    keys = path_keys(data, path)
    return None if keys is None else walk(data, keys)


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
