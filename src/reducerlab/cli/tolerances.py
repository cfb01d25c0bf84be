"""``reducerlab tolerances``: Monte-Carlo over tolerance fields, the distribution (mean,
std, p5, p95) of the lost motion, backlash and transmission error
(``analysis.tolerances``)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from .options import (
    DesignArgument,
    Format,
    FormatOption,
    SchedulerOption,
    SetOption,
    quantity_option,
    scheduler_client,
)
from .output import add_result, keeps_run, output_set, progress_bar, user_errors

MAX_SAMPLES = 100_000
"""Most samples of ``tolerances --samples`` (the API's limit)."""


def tolerances(
    design: DesignArgument,
    tol: Annotated[
        list[str] | None,
        typer.Option(
            "--tol",
            metavar="PATH=DIST",
            help="A toleranced design field (repeatable): uniform 'LO..HI UNIT' or normal "
            "'MEAN +- SIGMA UNIT', e.g. --tol 'mesh.backlash=60..100 um'; a "
            "pitch_deviations list takes one distribution for every tooth (centred on 0).",
        ),
    ] = None,
    tolerance_file: Annotated[
        Path | None,
        typer.Option(
            "--tolerances",
            help='TOML file with a [tolerances] table of PATH = "DIST" entries.',
        ),
    ] = None,
    samples: Annotated[int, typer.Option(help="Number of samples.", min=2, max=MAX_SAMPLES)] = 1000,
    seed: Annotated[
        int, typer.Option(help="Seed of the draws (same seed, same samples).", min=0, max=2**63 - 1)
    ] = 0,
    steps: Annotated[
        int, typer.Option(help="Torque steps of each torsion test.", min=3, max=10000)
    ] = 4,
    rated: Annotated[
        str | None,
        typer.Option(
            "--rated", help="Rated output torque, e.g. '120 N*m' (default: the design's)."
        ),
    ] = None,
    mu: Annotated[
        float | None,
        typer.Option(
            "--mu",
            help="Coulomb coefficient of the torsion test's sliding contacts (0: none; "
            "default: the design's material.friction_coefficient, else 0.05).",
        ),
    ] = None,
    te_samples: Annotated[
        int,
        typer.Option(help="Steps over one output revolution of each TE.", min=64, max=2**20),
    ] = 4096,
    chunk_size: Annotated[
        int, typer.Option(help="Samples per chunk (written when finished).", min=1, max=MAX_SAMPLES)
    ] = 50,
    output: Annotated[Path, typer.Option("--output", "-o", help="Run folder (resumable).")] = Path(
        "tolerances-output"
    ),
    scheduler: SchedulerOption = None,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Monte-Carlo over tolerances: each sample draws the toleranced fields, runs the
    torsion test (lost motion at +/-3 % rated, backlash) and the rigid transmission
    error, and the run reports mean, std, p5 and p95: tolerances.nc/.json/.txt/.png.
    Finished chunks are kept in the run folder; the same command resumes."""
    from ..analysis.tolerance_specs import read_tolerance_file, tolerance_items
    from ..analysis.tolerances import tolerance_estimate
    from ..analysis.tolerances import tolerances as run
    from ..drives import load_design

    with user_errors():
        files = output_set(output)
        torque = quantity_option(rated, "--rated", "torque")
        given = []
        if tolerance_file is not None:
            label = f"--tolerances {tolerance_file}:"
            given = tolerance_items(read_tolerance_file(tolerance_file), label)
        in_file = {p for p, *_ in given}
        for p, dist, lab in tolerance_items(tol or ()):
            if p in in_file:
                raise ReducerlabError(f"{lab}: {p} is also in --tolerances")
            given.append((p, dist, lab))
        if not given:
            raise ReducerlabError("--tol / --tolerances: give at least one toleranced field")
        d = load_design(design, sets or ())
        work = tolerance_estimate(samples, steps, len(given)).check()
        typer.echo(f"estimate: {work.what}: {work.work:.3g} {work.unit}", err=True)
        keeps_run(output)
        with scheduler_client(scheduler) as client, progress_bar() as bar:
            task = bar.add_task("tolerance samples", total=samples)
            res = run(d, given, samples=samples, seed=seed, steps=steps, rated=torque, mu=mu,
                      te_samples=te_samples, chunk_size=chunk_size, output=output,
                      scheduler=client,
                      progress=lambda done, total: bar.update(task, completed=done,
                                                              total=total))  # fmt: skip
        with files:
            add_result(res, files, "tolerances")
    typer.echo(json.dumps(res.to_dict()["statistics"]) if fmt is Format.json else res.table())


def register(app: typer.Typer) -> None:
    """Add ``tolerances`` to the command line."""
    app.command()(tolerances)
