"""``reducerlab efficiency``: mesh friction loss and efficiency against torque and speed
(``analysis.efficiency``)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from .options import SetOption, quantity_option
from .output import add_result, output_set, position_callbacks, progress_bar, user_errors


def efficiency(
    design: Annotated[
        Path,
        typer.Argument(
            help="A gear_pair design with mesh.face_width, a khv design, a nutation "
            "design with [surface] (every pair), or a cycloid_ball design (the spin and "
            "sliding of its balls)"
        ),
    ],
    mu: Annotated[
        float | None,
        typer.Option(
            help="Coulomb friction coefficient in [0, 0.3]; default the design's "
            "material.friction_coefficient, else 0.05."
        ),
    ] = None,
    torques: Annotated[
        list[str] | None,
        typer.Option(
            "--torques",
            help="Torque on gear A of pair 1 (repeat), e.g. --torques '30 N*m' --torques "
            "'60 N*m'; default --loads torques up to --top times the design load.",
        ),
    ] = None,
    loads: Annotated[int, typer.Option(help="Torques without --torques.", min=1, max=41)] = 4,
    top: Annotated[
        float, typer.Option(help="Largest torque over the design load.", min=0.01, max=3.0)
    ] = 1.5,
    speeds: Annotated[
        list[str] | None,
        typer.Option("--speeds", help="Input speeds of the loss table (repeat), e.g. '1000 rpm'."),
    ] = None,
    positions: Annotated[
        int,
        typer.Option(
            help="Mesh positions over one mesh cycle (cycloid_ball: ball-set phases over "
            "one ball pitch, at most 360).",
            min=3,
            max=400,
        ),
    ] = 24,
    cell: Annotated[str | None, typer.Option(help="Contact cell, e.g. '0.1 mm'.")] = None,
    tooth_size: Annotated[
        str | None, typer.Option(help="Finite-element tooth elements, e.g. '0.5 mm'.")
    ] = None,
    rigid: Annotated[
        bool,
        typer.Option(
            "--rigid",
            help="Teeth rigid beyond the contact half-space (no finite-element build): fast.",
        ),
    ] = False,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "efficiency-output"
    ),
    sets: SetOption = None,
) -> None:
    """Mesh power loss and efficiency from Coulomb friction at the loaded tooth contacts
    (sliding velocities from the kinematics, forces from the loaded contact analysis;
    no rolling, bearing or churning loss); for a cycloid_ball design the spin and
    sliding of its balls: efficiency.nc/.json/.txt/.png."""
    from ..analysis.efficiency import efficiency as run_efficiency
    from ..drives import load_design

    with user_errors():
        files = output_set(output)
        d = load_design(design, sets or ())
        T = None if not torques else [quantity_option(t, "--torques", "torque") for t in torques]
        W = None if not speeds else [quantity_option(w, "--speeds", "angular velocity")
                                     for w in speeds]  # fmt: skip
        h = quantity_option(cell, "--cell", "length")
        ts = quantity_option(tooth_size, "--tooth-size", "length")
        with progress_bar() as progress:
            task = progress.add_task("efficiency", total=None)
            if getattr(d, "type", None) == "cycloid_ball":  # the balls' spin and sliding
                from ..analysis.cycloid_efficiency import cycloid_efficiency

                res = cycloid_efficiency(d, mu=mu, torques=T, loads=loads, top=top,
                                         speeds=W, phases=positions)  # fmt: skip
            else:
                res = run_efficiency(
                    d, mu=mu, torques=T, loads=loads, top=top, speeds=W,
                    positions=positions, cell=h, tooth_size=ts, rigid=rigid,
                    **position_callbacks(progress, task,
                                         "loaded contact, position {done}/{total}"),
                )  # fmt: skip
            progress.update(task, description="writing results")
            with files:
                add_result(res, files, "efficiency")
    typer.echo(res.table())


def register(app: typer.Typer) -> None:
    """Add ``efficiency`` to the command line."""
    app.command()(efficiency)
