"""``reducerlab accuracy``: output angle error over one output revolution from the
gears' eccentricities and pitch deviations (``analysis.transmission_accuracy``), and
under ``--load`` the meshes' loaded transmission error (``analysis.loaded_accuracy``;
a nutation drive's meshes: ``analysis.loaded_accuracy_nutation``; a cycloid_ball
design's ball track, ``analysis.loaded_accuracy_cycloid``)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from .options import SetOption, quantity_option
from .output import add_result, output_set, position_callbacks, progress_bar, user_errors


def _cached_mesh_te(cache: Path, design: Any, load: Any, kw: dict[str, Any]) -> Any:
    """The loaded TE at ``load`` from the stage cache ``cache``, computed and stored when
    absent (``pipeline.datasheet.loaded_sweeps``, the datasheet's entries); a nutation
    design's, one per pair (a list)."""
    from ..analysis.loaded_accuracy import output_load
    from ..pipeline.datasheet import loaded_sweeps
    from ..pipeline.store import Store
    from .output import keeps_cache

    store = Store(cache)
    keeps_cache(store.root)
    out, _, _ = loaded_sweeps(store, design, output_load(design, load), **kw)
    return out if getattr(design, "type", None) == "nutation" else out[0]


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
        int | None,
        typer.Option(
            help="Even steps over one output revolution; default 4096, under --load the "
            "least multiple of the tooth-mesh order times --positions from 4096 (a "
            "cycloid_ball design: the ball-pattern order times --phases).",
            min=64,
            max=2**20,
        ),
    ] = None,
    load: Annotated[
        str | None,
        typer.Option(
            help="Output torque, e.g. '60 N*m', or 'design' (the design's operating output "
            "torque): adds the mesh's loaded transmission error (contact analysis)."
        ),
    ] = None,
    rigid: Annotated[
        bool,
        typer.Option(
            "--rigid",
            help="Under --load: teeth rigid beyond the contact half-space (no "
            "finite-element build): fast.",
        ),
    ] = False,
    positions: Annotated[
        int, typer.Option(help="Under --load: positions over one mesh cycle.", min=3, max=400)
    ] = 24,
    tooth_size: Annotated[
        str | None,
        typer.Option(help="Under --load: finite-element tooth elements, e.g. '0.9 mm'."),
    ] = None,
    phases: Annotated[
        int | None,
        typer.Option(
            help="Under --load, a cycloid_ball design: ball-set positions over one ball "
            "pitch, each a static solve of the ball track (default 256).",
            min=8,
            max=4096,
        ),
    ] = None,
    cache: Annotated[
        Path | None,
        typer.Option(
            help="Under --load: a cache folder for the loaded contact (a repeated call "
            "with the same teeth, load and settings reads it; a nutation drive's: each pair)."
        ),
    ] = None,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "accuracy-output"
    ),
    sets: SetOption = None,
) -> None:
    """Transmission accuracy: the output angle error (arcsec) over one output revolution
    without reversing, its peak to peak and its spectrum in orders, from rigid kinematics
    and, with --load, the mesh's loaded transmission error (its mean, the wind-up,
    reported apart): accuracy.nc/.json/.txt/.png."""
    from ..analysis.transmission_accuracy import transmission_accuracy
    from ..drives import load_design
    from ..errors import ReducerlabError

    with user_errors():
        files = output_set(output)
        d = load_design(design, sets or ())
        if load is None and (rigid or cache is not None or tooth_size is not None):
            raise ReducerlabError("--rigid, --tooth-size, --cache: apply with --load only")
        if getattr(d, "type", None) == "cycloid_ball" and (
            rigid or cache is not None or tooth_size is not None or positions != 24
        ):
            raise ReducerlabError(
                "--rigid, --tooth-size, --cache, --positions: options of the gear contact; a "
                "cycloid_ball design under --load solves its ball track (--phases)"
            )
        if phases is not None and (load is None or getattr(d, "type", None) != "cycloid_ball"):
            raise ReducerlabError("--phases: applies to a cycloid_ball design with --load only")
        target = None
        if load is not None and load.strip().lower() != "design":
            target = quantity_option(load, "--load", "torque")
        elif load is not None:
            target = "design"
        ts = quantity_option(tooth_size, "--tooth-size", "length")
        with progress_bar() as progress:
            task = progress.add_task("transmission accuracy", total=None)
            kw = {"positions": positions, "rigid": rigid, "tooth_size": ts,
                  **position_callbacks(progress, task, "loaded contact, position "
                                       "{done}/{total}")}  # fmt: skip
            mesh_te = None
            if target is not None and cache is not None:
                mesh_te = _cached_mesh_te(cache, d, target, kw)
            contact = {} if target is None else kw
            if getattr(d, "type", None) == "cycloid_ball":  # the ball track under load
                bar = position_callbacks(progress, task, "ball track, phase {done}/{total}")
                contact = {} if target is None else {"phases": phases, "progress": bar["progress"]}
            res = transmission_accuracy(d, samples=samples, load=target, mesh_te=mesh_te,
                                        **contact)  # fmt: skip
            progress.update(task, description="writing results")
            with files:
                add_result(res, files, "accuracy")
    typer.echo(res.table())


def register(app: typer.Typer) -> None:
    """Add ``accuracy`` to the command line."""
    app.command()(accuracy)
