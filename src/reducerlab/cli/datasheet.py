"""``reducerlab datasheet``: a reducer's catalogue page computed from its design
(issue 31, ``pipeline.datasheet``): the torsion test with the input held (Coulomb
friction at the sliding contacts: backlash, lost motion, hysteresis loss, loop area,
K1/K2/K3 with T1/T2, RV torsional rigidity), the transmission accuracy (under the
rated load for the gear pair and KHV drive), the efficiency with the starting and
back-driving torque, and the page itself (HTML)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from .options import DesignArgument, Format, FormatOption, SetOption, quantity_option
from .output import add_result, keeps_cache, output_set, progress_bar, user_errors


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
    efficiency: Annotated[
        bool,
        typer.Option(
            "--efficiency/--no-efficiency",
            help="Efficiency, starting and back-driving torque (a loaded contact analysis "
            "of every gear pair).",
        ),
    ] = True,
    loaded: Annotated[
        bool,
        typer.Option(
            "--loaded/--unloaded",
            help="Transmission accuracy under the rated torque (gear pair, KHV: the "
            "mesh's loaded TE added), else rigid kinematics alone.",
        ),
    ] = True,
    rigid: Annotated[
        bool,
        typer.Option(
            "--rigid", help="Teeth rigid beyond the contact half-space (fast, for checks)."
        ),
    ] = False,
    positions: Annotated[
        int, typer.Option(help="Mesh positions a cycle in the efficiency.", min=3, max=720)
    ] = 12,
    cache: Annotated[
        Path | None,
        typer.Option(
            "--cache",
            help="Stage cache (reducerlab run's OUTPUT/cache): tooth models and contact "
            "results read from it, stored in it (default OUTPUT/cache with -o).",
        ),
    ] = None,
    output: Annotated[
        Path | None,
        typer.Option(
            "--output",
            "-o",
            help="Folder for datasheet.html (the page), datasheet.nc/.json/.txt/.png (the "
            "torsion test), accuracy.* and efficiency.*.",
        ),
    ] = None,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """The catalogue datasheet: torsion test with the input held, output torque
    0 -> +rated -> -rated -> 0 (quasi-static, whole drive model, Coulomb friction at
    the sliding tooth contacts), transmission accuracy, efficiency with the starting
    and back-driving torque; the page as HTML."""
    from ..analysis.torsion_test import torsion_estimate
    from ..drives import build_model, load_design
    from ..pipeline.datasheet import datasheet as compute
    from ..reporting import PLOTLY_FILE, report

    with user_errors():
        files = output_set(output) if output is not None else None
        torque = quantity_option(rated, "--rated", "torque")
        if not (0.0 < t1 < t2 < 1.0):
            raise ReducerlabError(f"--t1, --t2: need 0 < t1 < t2 < 1; got {t1}, {t2}")
        d = load_design(design, sets or ())
        model = build_model(d)
        work = torsion_estimate(steps, model.n, len(model.nonlinear().line_names)).check()
        typer.echo(f"estimate: {work.what}: {work.work:.3g} {work.unit}", err=True)
        if cache is None and output is not None:
            cache = output / "cache"
        if cache is not None:
            keeps_cache(cache)
        with progress_bar() as bar:
            task = bar.add_task("datasheet", total=1.0)

            def progress(text: str, fraction: float) -> None:
                bar.update(task, description=text, completed=fraction)

            sheet = compute(d, rated=torque, steps=steps, t1=t1, t2=t2, mu=mu,
                            efficiency=efficiency, loaded=loaded, rigid=rigid,
                            positions=positions, cache=cache, progress=progress)  # fmt: skip
        for st in sheet.stages:
            typer.echo(f"{st.name}: {st.status}", err=True)
        if files is not None:
            with files:
                add_result(sheet.torsion, files, "datasheet")
                for res, stem in ((sheet.accuracy, "accuracy"), (sheet.efficiency, "efficiency")):
                    if res is not None:
                        add_result(res, files, stem)
                page = report(d, results=sheet.results, only=["datasheet"])
                shared = files.path(PLOTLY_FILE) if page.plotly_js else None
                page.write(files.path("datasheet.html"), plotly=shared)
    if fmt is Format.json:
        out = sheet.torsion.to_dict()
        out["starting"] = sheet.starting()
        out["accuracy"] = None if sheet.accuracy is None else sheet.accuracy.to_dict()
        out["notes"] = sheet.notes
        typer.echo(json.dumps(out, indent=2))
    else:
        typer.echo(sheet.table())


def register(app: typer.Typer) -> None:
    """Add ``datasheet`` to the command line."""
    app.command()(datasheet)
