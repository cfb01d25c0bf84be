"""``reducerlab balls``: load sharing of a cycloid ball drive's ball track against torque
(``analysis.ball_track``, issue 30): loaded balls, ball forces and the track's torsional
and translational stiffness."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from .options import DesignArgument, Format, FormatOption, SetOption, quantity_option
from .output import output_set, progress_bar, savefig, user_errors, write_json


def balls(
    design: DesignArgument,
    torque_max: Annotated[
        str | None,
        typer.Option(
            "--torque-max",
            help="Largest torque on the centre disc, e.g. '75 N*m' (default 1.5 x the "
            "design's load on it).",
        ),
    ] = None,
    points: Annotated[
        int, typer.Option(help="Torques from 0 to the largest.", min=2, max=1000)
    ] = 13,
    phases: Annotated[
        int, typer.Option(help="Ball-set positions over one ball pitch.", min=1, max=360)
    ] = 8,
    y: Annotated[
        str, typer.Option(help="Planetary disc along the line of centres: free or held.")
    ] = "free",
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="Folder for balls.nc, balls.json, balls.png."),
    ] = None,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Ball forces and track stiffness against torque (cycloid_ball designs with the
    ball and groove fields of [cycloid_pair])."""
    import numpy as np

    from ..analysis.ball_track import ball_track_analysis
    from ..drives import load_design

    with user_errors():
        files = output_set(output) if output is not None else None
        d = load_design(design, sets or ())
        if d.type != "cycloid_ball":
            raise ReducerlabError(f"{design}: type = {d.type!r}: not a cycloid_ball design")
        if y not in ("free", "held"):
            raise ReducerlabError(f"--y: free or held; got {y!r}")
        top = quantity_option(torque_max, "--torque-max", "torque")
        if top is not None and not top > 0:
            raise ReducerlabError(f"--torque-max: must be > 0; got {torque_max!r}")
        torques = None if top is None else np.linspace(0.0, top, points)
        with progress_bar() as bar:
            task = bar.add_task("ball track", total=points)
            res = ball_track_analysis(
                d, torques=torques, points=points, phases=phases, y=y,
                progress=lambda done, total: bar.update(task, completed=done, total=total),
            )  # fmt: skip
        if files is not None:
            with files:
                res.save(files.path("balls.nc"))
                write_json(res, files.path("balls.json"))
                savefig(res.plot(), files.path("balls.png"), res.data.attrs)
    typer.echo(json.dumps(res.to_dict(), indent=2) if fmt is Format.json else res.table())


def register(app: typer.Typer) -> None:
    """Add ``balls`` to the command line."""
    app.command()(balls)
