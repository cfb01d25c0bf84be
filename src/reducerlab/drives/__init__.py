"""Drive builders: each turns a validated Design into a generic Model.

:func:`load_design` reads a TOML design file and validates it against the Design class
its ``type`` field names; :func:`build_model` dispatches to that drive's builder.
A design's kinematics (ratio, member speeds, mesh frequencies) are built by its kinematic
train in :data:`reducerlab.kinematics.TRAINS`, which a kinematics-only design
(``type = "kinematics"``) names in its ``drive`` field.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, NamedTuple

from ..design import Design
from ..design_files import apply_overrides, read_toml, validate_design
from ..errors import DesignError, ReducerlabError, names_source
from ..kinematics import DriveKinematics
from ..model import Model
from . import cycloid_ball, gear_pair, khv, kinematic, lumped, nutation
from .places import (
    DriveLayout,
    Place,
    complete,
    cycloid_ball_places,
    gear_pair_places,
    khv_places,
    nutation_places,
)

__all__ = [
    "DRIVES",
    "DriveType",
    "build_model",
    "design_and_model",
    "design_from_dict",
    "drive_layout",
    "has_model",
    "kinematics_of",
    "load_design",
]


class DriveType(NamedTuple):
    """A registered design type: its Design class, its model builder (None for a
    kinematics-only design), a one-line summary and where its model's bodies sit
    (``places``: design → :class:`~reducerlab.drives.places.Place` list; None: on
    one axis, :func:`~reducerlab.drives.places.complete`)."""

    design: type[Design]
    build: Callable[[Any], Model] | None
    summary: str
    places: Callable[[Any], list[Place]] | None = None


DRIVES: dict[str, DriveType] = {
    "gear_pair": DriveType(
        gear_pair.GearPairDesign,
        gear_pair.build_model,
        "spur gear pair on bearings, bending-torsional",
        gear_pair_places,
    ),
    "cycloid_ball": DriveType(
        cycloid_ball.CycloidBallDesign,
        cycloid_ball.build_model,
        "cycloid ball transmission, 7-DOF translational-torsional (paper 003)",
        cycloid_ball_places,
    ),
    "khv": DriveType(
        khv.KHVDesign,
        khv.build_model,
        "KHV planetary drive with a small tooth difference, 4-DOF torsional (paper 004)",
        khv_places,
    ),
    "nutation": DriveType(
        nutation.NutationDesign,
        nutation.build_model,
        "nutation drive, single- or double-sided, bending-torsional-axial (paper 000)",
        nutation_places,
    ),
    "kinematics": DriveType(
        kinematic.KinematicsDesign,
        None,
        "kinematics only: ratio, member speeds, mesh frequencies, cone angles",
    ),
    "lumped": DriveType(
        lumped.LumpedDesign,
        lumped.build_model,
        "any lumped model written out DOF by DOF and element by element",
    ),
}


def design_from_dict(data: Mapping[str, Any], source: str = "<design>") -> Design:
    """Validate a raw design mapping (as read from TOML) against its drive's schema."""
    if not isinstance(data, Mapping):
        raise DesignError(
            f"{source}: a design must be a table of fields, got {type(data).__name__}"
        )
    kind = data.get("type")
    if kind is None:
        raise DesignError(
            f"{source}: type: required field is missing (one of: {', '.join(DRIVES)})"
        )
    if not isinstance(kind, str) or kind not in DRIVES:
        raise DesignError(
            f"{source}: type = {kind!r}: unknown drive type (one of: {', '.join(DRIVES)})"
        )
    design = validate_design(DRIVES[kind].design, data, source)
    design._source = source
    return design


def load_design(path: str | Path, overrides: Sequence[str] = ()) -> Design:
    """Read and validate a TOML design file; quantities are converted to SI.

    Parameters
    ----------
    path : str or Path
    overrides : sequence of str
        ``PATH=VALUE`` settings applied to the file's fields before validation
        (``"input_speed=670 rpm"``, ``"gears.x1=0.5"``), as the command line's ``--set``;
        see :func:`reducerlab.design_files.apply_overrides`.

    Raises
    ------
    DesignError
        Naming the file, the field path, the value and the rule for every problem.
    """
    data = read_toml(path)
    if not overrides:
        return design_from_dict(data, str(path))
    return design_from_dict(apply_overrides(data, overrides), f"{path} (with --set)")


def _entry(design: Design) -> DriveType:
    for drive in DRIVES.values():
        if type(design) is drive.design:
            return drive
    raise DesignError(f"unregistered design class {type(design).__name__}")


def has_model(design: Design) -> bool:
    """Whether the design's type has a dynamic model (a builder)."""
    return _entry(design).build is not None


@names_source
def build_model(design: Design) -> Model:
    """Turn a validated design into its generic :class:`~reducerlab.model.Model`.

    Raises
    ------
    ReducerlabError
        When the builder finds a rule broken between fields; the message starts with
        the design's source (its file, for :func:`load_design`).
    """
    build = _entry(design).build
    if build is None:
        raise DesignError(
            f"{design.source}: design type {design.type!r} describes kinematics only and "
            "has no dynamic model; use 'reducerlab kinematics'"
        )
    return build(design)


@names_source
def kinematics_of(design: Design) -> tuple[DriveKinematics, float]:
    """The drive kinematics of a design and its input speed (rad/s).

    Raises
    ------
    DesignError
        Naming the design's source when it has no kinematics or its ``input_speed`` is
        zero (a model may run at rest; speeds and mesh frequencies need a speed).
    """
    drive = design.kinematics()
    if drive is None:
        raise DesignError(
            f"{design.source}: design type {design.type!r} defines no drive kinematics"
        )
    speed = float(design.operating_speed)
    if speed == 0.0:
        field = design.speed_fields[0] or "input_speed"
        raise DesignError(
            f"{design.source}: {field} = 0: member speeds and mesh frequencies need a "
            f"non-zero input speed (e.g. {field} = '1500 rpm')"
        )
    return drive, speed


def drive_layout(target: Design | Model, model: Model | None = None) -> DriveLayout:
    """Where the bodies of a design's model (or of a bare model: on one axis) sit in the
    drive, for the mode-shape figures (:mod:`reducerlab.drives.places`).

    Parameters
    ----------
    target : Design or Model
    model : Model, optional
        The design's model, when already built.
    """
    design, built = design_and_model(target, "drive_layout") if model is None else (target, model)
    places: list[Place] = []
    if isinstance(design, Design):
        hook = _entry(design).places
        places = hook(design) if hook is not None else []
    return complete(places, built, built.name)


def design_and_model(target: Design | Model, what: str) -> tuple[Design | None, Model]:
    """The design (None when a model is given) and the model of an analysis's target.

    Parameters
    ----------
    target : Design or Model
    what : str
        The analysis, named in the error for any other target.
    """
    if isinstance(target, Design):
        return target, build_model(target)
    if isinstance(target, Model):
        return None, target
    raise ReducerlabError(
        f"{what}: target must be a Design or a Model, got {type(target).__name__}"
    )
