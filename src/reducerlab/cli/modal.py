"""``reducerlab modal`` and ``sensitivity``: the linear modes of a design's model."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import typer

from ..io import OutputSet
from .options import (
    DesignArgument,
    Format,
    FormatOption,
    ResultsOption,
    SetOption,
    check_rigid_tol,
    model_from,
)
from .output import (
    add_with_figure,
    busy,
    note,
    out,
    outputs,
    save_with_figure,
    savefig,
    user_errors,
    write_json,
)


def add_modal(result: Any, files: OutputSet, layout: Any = None) -> None:
    """Add modal.nc, modal.json, modal.txt and the figures to an open output set: the
    mode-shape bars, the energy map and, given the drive's layout
    (:func:`reducerlab.drives.drive_layout`) and an elastic mode, the mode shapes as the
    drive moving (drive_shapes.png)."""
    result.save(files.path("modal.nc"))
    write_json(result, files.path("modal.json"))
    files.path("modal.txt").write_text(result.table() + "\n")
    savefig(result.plot_shapes(), files.path("mode_shapes.png"), result.data.attrs)
    savefig(result.plot_energy(), files.path("energy.png"), result.data.attrs)
    if layout is not None and not result.data["rigid"].values.all():
        savefig(result.plot_drive(layout), files.path("drive_shapes.png"), result.data.attrs)


def print_modal(result: Any) -> None:
    """The table of modes (number, frequency, classification) on stdout."""
    table = result.table_data()
    table.title = result.data.attrs.get("title", "modal analysis")
    out.print(table.rich())


def modal(
    design: DesignArgument,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write results and figures here.")
    ] = None,
    fmt: FormatOption = Format.table,
    rigid_tol: Annotated[
        float,
        typer.Option(
            help="Relative eigenvalue below which a mode is rigid (0 Hz), in [0, 1).",
            callback=check_rigid_tol,
        ),
    ] = 1e-10,
    complex_: Annotated[
        bool,
        typer.Option(
            "--complex",
            help="Complex modes: damping, gyroscopic and Coriolis terms, whirl, stability.",
        ),
    ] = False,
    sets: SetOption = None,
) -> None:
    """Natural frequencies, mode shapes and energy classification of a design; -o also
    draws the mode shapes as the drive moving (drive_shapes.png)."""
    from ..analysis.complex_modal import complex_modes
    from ..analysis.modal import modal as run_modal
    from ..drives import drive_layout

    with user_errors():
        files = outputs(output)
        with busy("modal analysis"):
            spec, model = model_from(design, sets)
            result = run_modal(model, rigid_tol=rigid_tol)
            cplx = complex_modes(model, rigid_tol=rigid_tol) if complex_ else None
        if files is not None:
            with files:
                add_modal(result, files, drive_layout(spec, model))
                if cplx is not None:
                    add_with_figure(cplx, files, "complex_modes")
                    write_json(cplx, files.path("complex_modes.json"))
    if cplx is not None:
        typer.echo(json.dumps(cplx.to_dict()) if fmt is Format.json else cplx.table())
        return
    if fmt is Format.json:
        typer.echo(result.to_json())
    else:
        print_modal(result)
        if result.data.attrs.get("skew_velocity_terms"):
            note("the model has gyroscopic, Coriolis or circulatory terms, which undamped "
                 "modes leave out: see reducerlab modal --complex")  # fmt: skip


def sensitivity(
    design: DesignArgument,
    param: Annotated[
        list[str] | None,
        typer.Option("--param", "-p", help="Parameter path, e.g. mesh.stiffness (repeatable)."),
    ] = None,
    list_params: Annotated[
        bool, typer.Option("--list", help="List the model's parameter paths and exit.")
    ] = False,
    output: ResultsOption = None,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Sensitivity of every natural frequency to model parameters (analytic)."""
    from ..analysis.modal import frequency_sensitivity
    from ..model.inspect import parameter_paths

    with user_errors():
        files = None if list_params else outputs(output)
        _, model = model_from(design, sets)
        if list_params:
            for path, value in parameter_paths(model):
                typer.echo(f"{path} = {value:.6g}")
            return
        params = param or [p for p, _ in parameter_paths(model)]
        with busy("sensitivity"):
            res = frequency_sensitivity(model, params)
        if files is not None:
            save_with_figure(res, files, "sensitivity")
    if fmt is Format.json:
        ds = res.data
        typer.echo(
            json.dumps(
                {
                    "parameters": [str(p) for p in ds["parameter"].values],
                    "frequencies_hz": [float(f) for f in ds["frequency"].values],
                    "dfdp": [
                        [None if v != v else float(v) for v in row] for row in ds["dfdp"].values
                    ],
                    "relative": [
                        [None if v != v else float(v) for v in row] for row in ds["relative"].values
                    ],
                },
                indent=2,
            )
        )
    else:
        typer.echo(res.table())


def register(app: typer.Typer) -> None:
    """Add ``modal`` and ``sensitivity`` to the command line."""
    app.command()(modal)
    app.command()(sensitivity)
