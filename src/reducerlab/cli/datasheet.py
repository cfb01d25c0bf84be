"""``reducerlab datasheet``: the catalogue numbers of a drive computed from its model
(issue 31). It runs the torsion test with the input held (``analysis.torsion_test``,
Coulomb friction at the sliding contacts) and prints backlash, lost motion, hysteresis
loss, loop area, K1/K2/K3 with T1/T2 and the RV torsional rigidity (N m, arcmin,
N m/arcmin)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from .options import DesignArgument, Format, FormatOption, SetOption, quantity_option
from .output import add_result, output_set, user_errors


def datasheet(
    design: DesignArgument,
    rated: Annotated[
        str | None,
        typer.Option(
            "--rated",
            help="Rated output torque, e.g. '120 N*m' (default: the design's output "
            "torque at its operating point).",
        ),
    ] = None,
    steps: Annotated[
        int, typer.Option(help="Torque steps from 0 to rated on each branch.", min=3, max=10000)
    ] = 20,
    t1: Annotated[float, typer.Option(help="T1 as a fraction of rated (K1/K2 limit).")] = 0.2,
    t2: Annotated[float, typer.Option(help="T2 as a fraction of rated (K2/K3 limit).")] = 0.7,
    mu: Annotated[
        float | None,
        typer.Option(
            "--mu",
            help="Coulomb coefficient at the sliding tooth contacts (0 = no friction; "
            "default: the design's material.friction_coefficient, else 0.05).",
        ),
    ] = None,
    output: Annotated[
        Path | None,
        typer.Option(
            "--output",
            "-o",
            help="Folder for datasheet.nc, datasheet.json, datasheet.txt, datasheet.png.",
        ),
    ] = None,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Torsion test with the input held, output torque 0 -> +rated -> -rated -> 0
    (quasi-static, whole drive model, Coulomb friction at the sliding tooth contacts):
    the hysteresis loop and the catalogue numbers read from it."""
    from ..analysis.torsion_test import torsion_estimate, torsion_test
    from ..drives import build_model, load_design

    with user_errors():
        files = output_set(output) if output is not None else None
        torque = quantity_option(rated, "--rated", "torque")
        if not (0.0 < t1 < t2 < 1.0):
            raise ReducerlabError(f"--t1, --t2: need 0 < t1 < t2 < 1; got {t1}, {t2}")
        d = load_design(design, sets or ())
        model = build_model(d)
        work = torsion_estimate(steps, model.n, len(model.nonlinear().line_names)).check()
        typer.echo(f"estimate: {work.what}: {work.work:.3g} {work.unit}", err=True)
        res = torsion_test(d, rated=torque, steps=steps, t1=t1, t2=t2, model=model, mu=mu)
        if files is not None:
            with files:
                add_result(res, files, "datasheet")
    typer.echo(json.dumps(res.to_dict(), indent=2) if fmt is Format.json else res.table())


def register(app: typer.Typer) -> None:
    """Add ``datasheet`` to the command line."""
    app.command()(datasheet)
