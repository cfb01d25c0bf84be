"""``reducerlab accuracy``: output angle error over one output revolution from the
gears' eccentricities and pitch deviations (``analysis.transmission_accuracy``)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from .options import SetOption
from .output import add_result, output_set, user_errors


def accuracy(
    design: Annotated[
        Path,
        typer.Argument(
            help="A gear_pair, khv, cycloid_ball or nutation design; the errors tables "
            "([pinion.errors], [gears.planet_errors], [gears.crank_errors], "
            "[centre_disc.track_errors], [gear2.errors], ...) give eccentricity, pitch "
            "deviations and assembly errors"
        ),
    ],
    samples: Annotated[
        int, typer.Option(help="Even steps over one output revolution.", min=64, max=2**20)
    ] = 4096,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "accuracy-output"
    ),
    sets: SetOption = None,
) -> None:
    """Transmission accuracy, rigid kinematics: the output angle error (arcsec) over one
    output revolution without reversing, its peak to peak and its spectrum in orders:
    accuracy.nc/.json/.txt/.png."""
    from ..analysis.transmission_accuracy import transmission_accuracy
    from ..drives import load_design

    with user_errors():
        files = output_set(output)
        d = load_design(design, sets or ())
        res = transmission_accuracy(d, samples=samples)
        with files:
            add_result(res, files, "accuracy")
    typer.echo(res.table())


def register(app: typer.Typer) -> None:
    """Add ``accuracy`` to the command line."""
    app.command()(accuracy)
