"""``reducerlab body-modal``: finite-element modes of one gear body (paper 000 §4)."""

from __future__ import annotations

from enum import StrEnum
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from .options import GearOption, SetOption, quantity_option
from .output import output_set, progress_bar, savefig, user_errors, write_json


class MethodChoice(StrEnum):
    """Solutions of the whole gear (``--method``)."""

    cyclic = "cyclic"
    full = "full"


class BoundaryChoice(StrEnum):
    """Boundary conditions of a gear body (``--boundary``)."""

    free = "free"
    bore = "bore"
    face = "face"


def body_modal(
    design: Annotated[Path, typer.Argument(help="Nutation design file (TOML), surface table")],
    gear: GearOption = 1,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "body-modal-output"
    ),
    modes: Annotated[
        int, typer.Option("--modes", "-n", help="Elastic modes (paper 000: 10).", min=1, max=50)
    ] = 10,
    boundary: Annotated[
        BoundaryChoice,
        typer.Option(help="free (rigid modes removed), bore fixed, or mounting face fixed."),
    ] = BoundaryChoice.free,
    tooth_size: Annotated[
        str | None,
        typer.Option(help="Element size in the teeth, e.g. '1.2 mm' (default 0.6 m_n)."),
    ] = None,
    body_size: Annotated[
        str | None,
        typer.Option(help="Element size in the blank, e.g. '3 mm' (default 1.5 m_n)."),
    ] = None,
    method: Annotated[
        MethodChoice,
        typer.Option(
            help="cyclic: one tooth sector per harmonic index, expanded to the whole gear "
            "(cyclic symmetry, the default); full: the whole mesh at once. Same modes."
        ),
    ] = MethodChoice.cyclic,
    convergence: Annotated[
        bool,
        typer.Option(help="Also solve a 1.5x coarser mesh and report each mode's change."),
    ] = True,
    renders: Annotated[bool, typer.Option(help="One PNG render per mode.")] = True,
    sets: SetOption = None,
) -> None:
    """Finite-element modes of one gear body (paper 000 §4, Table 4): frequencies, mode
    types, renders, netCDF/JSON and a VTU file of the mesh and mode shapes (ParaView)."""
    from ..analysis.body_modal import body_modal as run_body_modal
    from ..analysis.body_modal import check_bodies
    from ..analysis.gear_bodies import body_mesh_sizes
    from ..drives import load_design
    from ..fe.vtu import write_vtu
    from ..plot.body import plot_body_mode

    with user_errors():
        files = output_set(output)
        d = load_design(design, sets or ())
        try:
            check_bodies(d)
        except ReducerlabError as exc:
            raise ReducerlabError(f"{design}: {exc}") from None
        if gear not in range(1, d.gear_count + 1):
            raise ReducerlabError(
                f"--gear: must be 1..{d.gear_count} for a {d.sides}-sided drive; got {gear}"
            )
        sizes = body_mesh_sizes(
            d,
            gear,
            tooth=quantity_option(tooth_size, "--tooth-size", "length"),
            body=quantity_option(body_size, "--body-size", "length"),
        )
        with progress_bar() as progress:
            task = progress.add_task("gear body", total=None)
            res = run_body_modal(
                d, gear, count=modes, boundary=boundary.value, sizes=sizes,
                convergence=convergence, method=method.value,
                stage=lambda s: progress.update(task, description=s),
            )  # fmt: skip
            progress.update(task, description="writing results")
            with files:
                res.save(files.path("body_modal.nc"))
                write_json(res, files.path("body_modal.json"))
                files.path("body_modal.txt").write_text(res.table() + "\n")
                savefig(res.figure(), files.path("modes.png"), res.data.attrs)
                mesh, shapes = res.mesh, res.shapes
                labels = res.labels
                write_vtu(files.path("body_modes.vtu"), mesh.points, mesh.tets[:, :4], shapes,
                          res.frequencies, labels)  # fmt: skip
                if renders:
                    for k, (f, lab) in enumerate(zip(res.frequencies, labels, strict=True)):
                        title = f"Gear {gear}, mode {k + 1}: {f:.5g} Hz, {lab}"
                        fig = plot_body_mode(mesh.points, mesh.tets[:, :4], shapes[:, :, k], title)
                        savefig(fig, files.path(f"mode_{k + 1:02d}.png"), res.data.attrs)
    typer.echo(res.table())


def register(app: typer.Typer) -> None:
    """Add ``body-modal`` to the command line."""
    app.command("body-modal")(body_modal)
