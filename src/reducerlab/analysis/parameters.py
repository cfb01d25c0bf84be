"""Parameters of the analyses that vary one (sweep, bifurcation, frequency response) or two
(sweep grid, regime map): their paths, their values, and the model at a parameter point.

A parameter path is a dotted path into the design's SI fields (``"mesh.stiffness"``,
``"pinion.bearing.stiffness_x"``, ``"elements.4.stiffness"``) or a model parameter
(``"support:gear.x.stiffness"``, ``"speed"``, see :meth:`reducerlab.model.Model.parameter`);
``design:`` or ``model:`` in front chooses when both exist, otherwise the design wins.
:class:`Axis` holds a path and its values, :func:`parse_values` and
:func:`parse_path_values` read them as the command line and the design's ``[report]``
table write them, :func:`resolve` finds a path's :class:`Target` and :func:`axis_targets`
the targets and SI values of an axis. :class:`Evaluator` builds the model at a point: the
design with the swept fields changed is validated again and rebuilt
(:meth:`reducerlab.design.Design.with_values`), then the model parameters are set
(:meth:`reducerlab.model.Model.with_parameter`).
"""

from __future__ import annotations

import dataclasses
import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..design import Design
from ..design_files import path_keys, walk
from ..errors import DesignError, ReducerlabError
from ..model import Model

__all__ = [
    "Axis",
    "Evaluator",
    "Target",
    "axis_targets",
    "design_keys",
    "parameter_kind",
    "parse_path_values",
    "parse_values",
    "resolve",
]


# ----------------------------------------------------------------------------- axes
@dataclass(frozen=True)
class Axis:
    """One swept parameter.

    Parameters
    ----------
    path : str
        A dotted path into the design (``"mesh.stiffness"``,
        ``"pinion.bearing.stiffness_x"``, ``"elements.4.stiffness"``), or a model
        parameter (``"support:gear.x.stiffness"``, ``"speed"``). Prefix ``design:`` or
        ``model:`` to choose when both exist; otherwise the design wins. Several paths
        joined by ``+`` are tied: they take the same value (relative sweeps scale each
        from its own design value); the coordinate shows the first one.
    values : sequence
        The values: numbers in SI, or strings with units for design fields. When
        ``relative`` they are factors of the design value (1.5 = 150 %).
    relative : bool
    scale : {"linear", "log"}
        How to space axes in figures.
    """

    path: str
    values: tuple[Any, ...]
    relative: bool = False
    scale: str = "linear"

    def __post_init__(self) -> None:
        if not isinstance(self.path, str) or not self.path.strip():
            raise ReducerlabError("axis: the parameter path must be a non-empty string")
        vals = tuple(self.values)
        if not vals:
            raise ReducerlabError(f"axis {self.path!r}: no values (empty range)")
        for v in vals:
            if isinstance(v, bool) or not isinstance(v, int | float | str | np.number):
                raise ReducerlabError(
                    f"axis {self.path!r}: value {v!r} is not a number or a quantity string"
                )
            if isinstance(v, int | float | np.number) and not math.isfinite(float(v)):
                raise ReducerlabError(f"axis {self.path!r}: value {v!r} is not finite")
        if self.relative and any(isinstance(v, str) for v in vals):
            raise ReducerlabError(f"axis {self.path!r}: relative values must be plain factors")
        object.__setattr__(self, "values", vals)

    @classmethod
    def linspace(cls, path: str, start: float, stop: float, num: int) -> Axis:
        """``num`` evenly spaced values from ``start`` to ``stop`` (SI)."""
        _check_range(path, start, stop, num)
        return cls(path, tuple(np.linspace(start, stop, num).tolist()))

    @classmethod
    def logspace(cls, path: str, start: float, stop: float, num: int) -> Axis:
        """``num`` log-spaced values from ``start`` to ``stop`` (both > 0, SI)."""
        _check_range(path, start, stop, num)
        if not (start > 0 and stop > 0):
            raise ReducerlabError(f"axis {path!r}: a log range needs start, stop > 0")
        return cls(path, tuple(np.geomspace(start, stop, num).tolist()), scale="log")

    @classmethod
    def relative_to_design(cls, path: str, factors: Iterable[float]) -> Axis:
        """Factors of the design value, e.g. ``[1.5, 2.0, 2.5]`` for 150-250 %."""
        return cls(path, tuple(factors), relative=True)


def _check_range(path: str, start: Any, stop: Any, num: Any) -> None:
    for name, v in (("start", start), ("stop", stop)):
        if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
            raise ReducerlabError(f"axis {path!r}: {name} must be a finite number, got {v!r}")
    if isinstance(num, bool) or not isinstance(num, int) or num < 1:
        raise ReducerlabError(f"axis {path!r}: the number of points must be >= 1, got {num!r}")


_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def _range_quantities(label: str, spec: str, kind: str, a: str, b: str) -> tuple:
    """START and STOP of a range written with units (``lin:1300 rpm:1700 rpm:41``): their
    magnitudes in START's unit, and that unit."""
    from ..units import registry

    ureg = registry()
    rule = (
        f"{label}: {spec!r}: write {kind}:START:STOP:N with SI numbers, or both ends "
        "as quantities with units such as 1300 rpm"
    )
    number = re.compile(r"\s*[-+]?(\d|\.\d)")
    if not (number.match(a) and number.match(b)):
        raise ReducerlabError(rule)
    try:
        qa, qb = ureg.Quantity(a.strip()), ureg.Quantity(b.strip())
    except Exception:
        raise ReducerlabError(rule) from None
    if not (hasattr(qa, "units") and hasattr(qb, "units")) or qa.dimensionless:
        raise ReducerlabError(rule)
    if qa.dimensionality != qb.dimensionality:
        raise ReducerlabError(
            f"{label}: {spec!r}: START and STOP have different dimensions "
            f"({qa.units} and {qb.units})"
        )
    return float(qa.magnitude), float(qb.to(qa.units).magnitude), str(qa.units)


def parse_values(
    path: str, spec: str, *, limit: int | None = None, option: str | None = None
) -> Axis:
    """Parse a command-line value specification into an axis.

    Parameters
    ----------
    path : str
        The parameter path (see :class:`Axis`).
    spec : str
        ``"1e8,2e8,3e8"`` (a list; items may carry units: ``"2e8 N/m, 3e8 N/m"``),
        ``"lin:START:STOP:N"``, ``"log:START:STOP:N"`` (SI numbers, or both ends with
        units: ``"lin:1300 rpm:1700 rpm:41"``), or ``"rel:1.5,2,2.5"`` /
        ``"150%,200%,250%"`` (factors of the design value).
    limit : int, optional
        More than ``limit`` values are refused, a range before any is made.
    option : str, optional
        The command and option (``"regime-map -x"``) or the design field that gave
        ``spec``, named in the message of a refusal (default ``"values"``).

    Returns
    -------
    Axis

    Raises
    ------
    ReducerlabError
        For a specification that is not one of the forms above, or too many values.
    """
    axis = _parse_values(path, spec, limit, option)
    if limit is not None and len(axis.values) > limit:
        raise ReducerlabError(
            f"{option or _label(path, option)}: {len(axis.values)} values; at most {limit} are "
            "allowed"
        )
    return axis


def parse_path_values(
    text: str, *, limit: int | None = None, option: str = "PATH=VALUES",
    example: str = "input_speed=lin:300 rpm:2000 rpm:41",
) -> Axis:  # fmt: skip
    """``"PATH=VALUES"`` (``sweep --grid``, ``regime-map -x/-y``, a design's
    ``[report.regime_map]``) as an axis: :func:`parse_values` of the part after ``=``.

    Parameters
    ----------
    text : str
        ``PATH=VALUES``, e.g. ``"gears.x1=0.5,0.6"``.
    limit : int, optional
        At most this many values (see :func:`parse_values`).
    option : str
        The option or field that gave ``text``, named in messages.
    example : str
        An example shown when ``text`` has no ``=``.

    Returns
    -------
    Axis
    """
    if not isinstance(text, str) or "=" not in text:
        raise ReducerlabError(f"{option} must be 'PATH=VALUES', e.g. '{example}'")
    path, values = text.split("=", 1)
    if not path.strip():
        raise ReducerlabError(f"{option} {text!r}: no parameter path before '='")
    return parse_values(path.strip(), values.strip(), limit=limit, option=option)


def _label(path: str, option: str | None) -> str:
    """How a value specification's messages start: ``regime-map -x 'mesh.stiffness'``."""
    return f"{option or 'values'} {path!r}"


def _parse_values(path: str, spec: str, limit: int | None, option: str | None) -> Axis:
    label = _label(path, option)
    if not isinstance(spec, str) or not spec.strip():
        raise ReducerlabError(f"{label}: empty value specification")
    s = spec.strip()
    m = re.fullmatch(r"(lin|log):([^:]+):([^:]+):([^:]+)", s)
    if m:
        kind, a, b, n = m.groups()
        unit = None
        try:
            a_, b_ = float(a), float(b)
        except ValueError:
            a_, b_, unit = _range_quantities(label, spec, kind, a, b)
        try:
            n_ = int(n)
        except ValueError:
            raise ReducerlabError(
                f"{label}: {spec!r}: N = {n.strip()!r} must be a whole number of points, e.g. 101"
            ) from None
        if limit is not None and n_ > limit:
            raise ReducerlabError(
                f"{option or label}: {spec!r} asks for {n_} values; at most {limit} are allowed"
            )
        ax = Axis.linspace(path, a_, b_, n_) if kind == "lin" else Axis.logspace(path, a_, b_, n_)
        if unit is None:
            return ax
        # the design field converts each value from its unit (as for a list with units)
        return Axis(path, [f"{float(v)!r} {unit}" for v in ax.values])
    if s.startswith(("lin:", "log:")):
        raise ReducerlabError(f"{label}: {spec!r}: write lin:START:STOP:N or log:...")
    relative = s.startswith("rel:")
    items = [x.strip() for x in (s[4:] if relative else s).split(",") if x.strip()]
    if not items:
        raise ReducerlabError(f"{label}: no values in {spec!r}")
    percent = all(x.endswith("%") for x in items)
    if percent:
        relative = True
        items = [x[:-1].strip() for x in items]
    values: list[Any] = []
    for x in items:
        if re.fullmatch(_NUM, x):
            values.append(float(x) / 100.0 if percent else float(x))
        elif relative:
            raise ReducerlabError(f"{label}: relative value {x!r} is not a number")
        elif re.match(_NUM, x):
            values.append(x)  # a quantity with units, parsed by the design
        else:
            raise ReducerlabError(f"{label}: value {x!r} is not a number")
    return Axis(path, tuple(values), relative=relative)


# ----------------------------------------------------------------------------- paths
def design_keys(data: dict[str, Any], path: str) -> tuple[Any, ...] | None:
    """The keys of a numeric field at dotted ``path`` of a design's ``model_dump()``, None
    where the path is not there or holds no number (a table, a string, a boolean)."""
    keys = path_keys(data, path)
    if keys is None:
        return None
    value = walk(data, keys)
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return keys


# ----------------------------------------------------------------------------- targets
@dataclass(frozen=True)
class Target:
    """One parameter an axis drives.

    Attributes
    ----------
    where : {"design", "model"}
        A design field (set in the design, which is validated again and rebuilt) or a
        model parameter (:meth:`reducerlab.model.Model.with_parameter`).
    path : str
        The path without its ``design:``/``model:`` prefix.
    keys : tuple
        The keys of a design field in the design's ``model_dump()`` (empty for a model
        parameter).
    base : float
        The design or model value (SI).
    integer : bool
        An integer design field (values are rounded to whole numbers).
    axis : int
        Which axis of the analysis drives it.
    scale : float
        The parameter's value is the axis value times ``scale`` (tied relative paths).
    """

    where: str
    path: str
    keys: tuple[Any, ...]
    base: float
    integer: bool = False
    axis: int = 0
    scale: float = 1.0


def resolve(design: Design | None, model: Model, path: str, what: str = "sweep") -> Target:
    """The design field or model parameter that ``path`` names.

    Parameters
    ----------
    design : Design or None
        The design (None when the analysis was given a model).
    model : Model
        The design's model, or the model given.
    path : str
        One parameter path (see :class:`Axis`; not a tied ``a+b``).
    what : str
        The analysis, named in messages (``"regime-map: unknown parameter path ..."``).

    Returns
    -------
    Target
        Driven by axis 0 at scale 1.

    Raises
    ------
    ReducerlabError
        For a path that is neither a numeric design field nor a model parameter.
    """
    where = None
    raw = path
    if path.startswith(("design:", "model:")):
        where, path = path.split(":", 1)
    if where in (None, "design") and design is not None:
        data = design.model_dump(mode="python")
        keys = design_keys(data, path)
        if keys is not None:
            value = walk(data, keys)
            return Target("design", path, keys, float(value), isinstance(value, int))
        if where == "design":
            raise ReducerlabError(f"{what}: {raw!r} is not a numeric field of the design")
    if where == "design":
        raise ReducerlabError(f"{what}: {raw!r}: no design field to vary (a model was given)")
    try:
        value = model.parameter(path)
    except ReducerlabError as exc:
        hint = " or a numeric design field" if design is not None else ""
        raise ReducerlabError(f"{what}: unknown parameter path {raw!r}{hint} ({exc})") from None
    return Target("model", path, (), float(value))


#: DOF kinds that are rotations (rad); the others (x, y, z, u) are lengths (m).
_ROTATIONS = frozenset({"rx", "ry", "rz"})


def parameter_kind(design: Design | None, model: Model | None, path: str) -> str | None:
    """The quantity kind of a parameter path (a key of
    :data:`reducerlab.units.QUANTITIES`: ``"stiffness"`` for N/m, ``"moment of
    inertia"`` for kg m^2, ...), as :func:`resolve` would find the path; the first of a
    tied ``a+b`` path. None for a plain number, an unknown path, or a model parameter
    whose unit its element does not fix (a coupling over both lengths and angles).

    A design field's kind is its declared quantity; a model parameter's follows from its
    element and the kinds of its DOFs: an inertia's value is a mass on a translation
    and a moment of inertia on a rotation, a support's or coupling's stiffness and
    damping are torsional on rotations, a mesh or cubic spring acts along a line (m),
    a load is a force or a torque, and ``speed`` an angular velocity.
    """
    from ..design import field_kind

    path = path.split("+")[0].strip()
    where = None
    if path.startswith(("design:", "model:")):
        where, path = path.split(":", 1)
    if (
        where in (None, "design")
        and design is not None
        and design_keys(design.model_dump(mode="python"), path) is not None
    ):
        return field_kind(design, path)
    if where == "design" or model is None:
        return None
    return _model_kind(model, path)


def _model_kind(model: Model, path: str) -> str | None:
    """:func:`parameter_kind` of a model parameter."""
    from ..model import Coupling, CubicSpring, Inertia, Load, Mesh, Support

    if path == "speed":
        return "angular velocity"
    owners = [e for e in model.elements if path.startswith(e.name + ".")]
    if not owners:
        return None
    elem = max(owners, key=lambda e: len(e.name))
    field = path[len(elem.name) + 1 :].split(".")[0]
    kinds = {d.rsplit(".", 1)[-1] in _ROTATIONS for d in elem.dofs}
    rot = kinds.pop() if len(kinds) == 1 else None
    if isinstance(elem, Mesh | CubicSpring):  # along a line of action (m)
        named = {"stiffness": "stiffness", "damping": "damping", "backlash": "length",
                 "error": "length", "reference_deflection": "length"}  # fmt: skip
        return named.get(field)
    if rot is None:
        return None
    if isinstance(elem, Inertia) and field == "value":
        return "moment of inertia" if rot else "mass"
    if isinstance(elem, Load) and field == "value":
        return "torque" if rot else "force"
    if isinstance(elem, Support | Coupling) and field in ("stiffness", "damping"):
        return f"torsional {field}" if rot else field
    return None


def axis_targets(
    design: Design | None, model: Model, a: Axis, index: int = 0, what: str = "sweep"
) -> tuple[list[Target], NDArray]:
    """The parameters an axis drives and its values in SI units.

    A path ``a+b`` ties parameters (same value; relative values scale each by its own
    base value); values may be quantities with units (``"500 rpm"``) for design fields,
    converted by the field's unit; integer fields take whole numbers.

    Parameters
    ----------
    design : Design or None
        The design (None when the analysis was given a model).
    model : Model
        The design's model, or the model given.
    a : Axis
    index : int
        The axis's position in the analysis (``Target.axis``).
    what : str
        The analysis, named in messages.

    Returns
    -------
    targets : list of Target
        One per tied path, the first one's value is the axis value.
    values : ndarray
        The axis values in SI units (n_values,).
    """
    members = [resolve(design, model, p.strip(), what) for p in a.path.split("+")]
    if len({(t.where, t.path) for t in members}) != len(members):
        raise ReducerlabError(f"{what} {a.path!r}: a tied path lists a parameter twice")
    first = members[0].base
    group = [
        dataclasses.replace(
            t, axis=index, scale=(t.base / first if (a.relative and first) else 1.0)
        )
        for t in members
    ]
    t = group[0]
    vals = list(a.values)
    if a.relative:
        vals = [float(v) * t.base for v in vals]
    if any(isinstance(v, str) for v in vals):
        if design is None or any(m.where != "design" for m in group):
            raise ReducerlabError(
                f"{what} {a.path!r}: a model parameter takes SI numbers, not {vals[0]!r}"
            )
        vals = [_si_of(design, t, v, what) for v in vals]
    col = np.asarray(vals, dtype=float)
    if any(m.integer for m in group) and not np.all(col == np.round(col)):
        raise ReducerlabError(f"{what} {a.path!r}: an integer field takes whole numbers")
    return group, col


def _si_of(design: Design, t: Target, value: str, what: str = "sweep") -> float:
    """A design field's value written with units, in SI (as the design converts it)."""
    try:
        new = design.with_values({t.path: value}, source=f"{what} value")
    except DesignError as exc:
        raise ReducerlabError(f"{what} {t.path!r}: value {value!r} rejected:\n{exc}") from None
    return float(walk(new.model_dump(mode="python"), t.keys))


# ----------------------------------------------------------------------------- points
@dataclass
class Evaluator:
    """The model at parameter points; picklable for worker processes.

    Parameters
    ----------
    design : Design or None
        The design whose fields are swept (None when only model parameters are).
    model : Model
        The model at the design values.
    targets : tuple of Target
        What the points set (:func:`axis_targets` of every axis).
    what : str
        The analysis (``"sweep"``, ``"regime-map"``...), named in messages.
    """

    design: Design | None
    model: Model
    targets: tuple[Target, ...]
    #: The analysis, named in messages.
    what: str = "sweep"

    def model_at(self, values: Sequence[Any]) -> Model:
        """The model at one point.

        Parameters
        ----------
        values : sequence of float
            One value per axis (SI); a target takes its axis's value times its scale.

        Returns
        -------
        Model
            Rebuilt from the design with its fields set (integer fields rounded) when
            design fields are swept, with the model parameters set.

        Raises
        ------
        ReducerlabError
            When the design at the point is not valid, or its model has other DOFs.
        """
        from ..drives import build_model

        model = self.model
        per = [float(values[t.axis]) * t.scale for t in self.targets]
        changes = {
            t.path: round(v) if t.integer else v
            for t, v in zip(self.targets, per, strict=True)
            if t.where == "design"
        }
        if changes:
            if self.design is None:
                raise ReducerlabError(f"{self.what}: design fields vary but no design is given")
            try:
                model = build_model(self.design.with_values(changes, source=f"{self.what} point"))
            except DesignError as exc:
                point = dict(zip([t.path for t in self.targets], per, strict=True))
                raise ReducerlabError(
                    f"{self.what} point {point} is not a valid design:\n{exc}"
                ) from None
            if model.dof_names != self.model.dof_names:
                raise ReducerlabError(f"{self.what}: the varied field changes the model's DOFs")
        for t, v in zip(self.targets, per, strict=True):
            if t.where == "model":
                model = model.with_parameter(t.path, v)
        return model
