"""``reducerlab sweep`` and ``campbell``: natural frequencies over a parameter, a grid
of two, or the input speed."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from .options import (
    MAX_SWEEP_POINTS,
    MAX_WORKERS,
    DesignArgument,
    Format,
    FormatOption,
    ResultsOption,
    SchedulerOption,
    SetOption,
    axis,
    parse_speeds,
    path_values,
    scheduler_client,
)
from .output import (
    busy,
    keeps_run,
    note,
    output_set,
    outputs,
    save_with_figure,
    savefig,
    user_errors,
)


def sweep(
    design: DesignArgument,
    param: Annotated[str, typer.Option("--param", "-p", help="Parameter path to sweep.")],
    values: Annotated[
        str,
        typer.Option(
            "--values",
            "-v",
            help="'1e8,2e8', '2e8 N/m,3e8 N/m', 'lin:START:STOP:N', 'log:START:STOP:N', "
            "'rel:1.5,2,2.5' or '150%,200%'.",
        ),
    ],
    grid: Annotated[
        str | None,
        typer.Option("--grid", help="Second parameter for a grid: 'PATH=VALUES'."),
    ] = None,
    output: Annotated[Path, typer.Option("--output", "-o", help="Run folder (resumable).")] = Path(
        "sweep-output"
    ),
    chunk_size: Annotated[
        int, typer.Option(help="Points per chunk.", min=1, max=MAX_SWEEP_POINTS)
    ] = 2000,
    workers: Annotated[
        int | None,
        typer.Option(help="Worker processes (default: all cores).", min=1, max=MAX_WORKERS),
    ] = None,
    scheduler: SchedulerOption = None,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Natural frequencies over a parameter (tracked modes, veerings) or a grid of two.

    At most 1000000 points in all; the run folder is resumable (sweep.json, chunks/)."""
    from ..analysis.sweep import sweep as run_sweep
    from ..drives import load_design

    with user_errors():
        files = output_set(output)
        d = load_design(design, sets or ())
        axes = [axis("sweep --values", param, values, MAX_SWEEP_POINTS)]
        if grid is not None:
            example = "mesh.damping=lin:0:1e3:11"
            axes.append(path_values("sweep --grid", grid, MAX_SWEEP_POINTS, example))
        n_points = math.prod(len(a.values) for a in axes)
        if n_points > MAX_SWEEP_POINTS:
            raise ReducerlabError(
                f"--values x --grid: {n_points} points; at most {MAX_SWEEP_POINTS} are allowed"
            )
        nc_existed = (output / "sweep.nc").exists()
        keeps_run(output)
        with scheduler_client(scheduler) as client, busy("sweep chunks") as report:
            result = run_sweep(
                d,
                axes,
                output=output,
                chunk_size=chunk_size,
                workers=workers,
                scheduler=client,
                progress=report,
            )
        note(f"{'replaced' if nc_existed else 'wrote'} {output / 'sweep.nc'}")
        with files:
            savefig(result.plot(), files.path("sweep.png"), result.data.attrs)
    if fmt is Format.json:
        ds = result.data
        typer.echo(
            json.dumps(
                {
                    "parameters": result.parameters,
                    "values": [ds[f"p{i}"].values.tolist() for i in range(len(axes))],
                    "frequencies_hz": ds["frequency"].values.tolist(),
                    "events": result.events(),
                    "vectorised": bool(ds.attrs["vectorised"]),
                }
            )
        )
    else:
        typer.echo(result.table())


def campbell(
    design: DesignArgument,
    speeds: Annotated[
        str | None, typer.Option(help="Input speeds in rpm: 'lin:0:3000:301' or a list.")
    ] = None,
    output: ResultsOption = None,
    fmt: FormatOption = Format.table,
    complex_: Annotated[
        bool,
        typer.Option(
            "--complex",
            help="Complex modes: damped frequencies, forward/backward whirl, stability.",
        ),
    ] = False,
    sets: SetOption = None,
) -> None:
    """Campbell diagram: natural frequencies and excitation lines against input speed
    (at most 100000 speeds)."""
    from ..analysis.campbell import campbell as run_campbell
    from ..analysis.complex_modal import complex_campbell
    from ..drives import load_design

    with user_errors():
        files = outputs(output)
        d = load_design(design, sets or ())
        omegas = parse_speeds(speeds)
        with busy("campbell"):
            res = complex_campbell(d, omegas) if complex_ else run_campbell(d, omegas)
        if files is not None:
            save_with_figure(res, files, "complex_campbell" if complex_ else "campbell")
    if complex_:
        typer.echo(json.dumps(res.to_dict()) if fmt is Format.json else res.table())
        return
    typer.echo(json.dumps({"crossings": res.crossings()}) if fmt is Format.json else res.table())


def register(app: typer.Typer) -> None:
    """Add ``sweep`` and ``campbell`` to the command line."""
    app.command()(sweep)
    app.command()(campbell)
