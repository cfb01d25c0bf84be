"""``reducerlab kinematics``: ratio, member speeds and mesh frequencies of a drive."""

from __future__ import annotations

from typing import Any

import typer

from ..io import OutputSet
from .options import DesignArgument, Format, FormatOption, ResultsOption, SetOption
from .output import outputs, savefig, user_errors, write_json


def add_kinematics(result: Any, files: OutputSet) -> None:
    """Add kinematics.nc, kinematics.json (and angular_velocity.png) to an open set."""
    result.save(files.path("kinematics.nc"))
    write_json(result, files.path("kinematics.json"))
    if "omega" in result.data:
        savefig(result.plot(), files.path("angular_velocity.png"), result.data.attrs)


def run_kinematics(design: Any) -> Any:
    """The kinematics result of a design at its input speed."""
    from ..analysis.kinematics import kinematics as kinematics_result
    from ..drives import kinematics_of

    drive, speed = kinematics_of(design)
    return kinematics_result(
        drive,
        speed,
        title=design.name,
        metadata=design.provenance,
    )


def kinematics(
    design: DesignArgument,
    output: ResultsOption = None,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Transmission ratio, member speeds, mesh frequencies and cone angles of a drive."""
    from ..drives import load_design

    with user_errors():
        files = outputs(output)
        result = run_kinematics(load_design(design, sets or ()))
        if files is not None:
            with files:
                add_kinematics(result, files)
    typer.echo(result.to_json() if fmt is Format.json else result.table())


def register(app: typer.Typer) -> None:
    """Add ``kinematics`` to the command line."""
    app.command()(kinematics)
