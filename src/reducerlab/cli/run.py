"""``reducerlab run``: a design at its operating point through the whole chain, to one
verdict and one report (:func:`reducerlab.pipeline.run`)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from .options import (
    DesignArgument,
    SchedulerOption,
    SetOption,
    quantity_option,
    scheduler_client,
)
from .output import keeps_cache, note, run_progress, user_errors


def run_cmd(
    design: DesignArgument,
    output: Annotated[
        Path,
        typer.Option(
            "--output",
            "-o",
            help="Output folder: report.html, verdict.json, "
            "run.json and every stage's result (netCDF).",
        ),
    ] = Path("run-output"),
    cache: Annotated[
        Path | None,
        typer.Option(
            help="Stage cache folder (default OUTPUT/cache); shared between runs "
            "of designs that share stages."
        ),
    ] = None,
    bodies: Annotated[
        bool, typer.Option("--bodies/--no-bodies", help="Compute the gear bodies' FE modes.")
    ] = True,
    positions: Annotated[
        int,
        typer.Option(
            min=15,
            max=1000,
            help="Loaded-contact positions per mesh cycle "
            "(at least 15 for the 7 harmonics of paper 000's Eq. 8).",
        ),
    ] = 24,
    cell: Annotated[
        str | None, typer.Option(help="Contact cell, e.g. '0.1 mm' (default: automatic).")
    ] = None,
    tooth_size: Annotated[
        str | None,
        typer.Option(help="Element size of the FE tooth-compliance models (default 0.3 m_n)."),
    ] = None,
    body_tooth_size: Annotated[
        str | None,
        typer.Option(help="Element size in the teeth of the gear-body meshes (default 0.6 m_n)."),
    ] = None,
    body_size: Annotated[
        str | None,
        typer.Option(help="Element size in the blanks of the gear-body meshes (default 1.5 m_n)."),
    ] = None,
    periods: Annotated[
        int, typer.Option(min=10, max=100000, help="Forcing periods of each nonlinear response.")
    ] = 600,
    root_stress: Annotated[
        bool,
        typer.Option(
            "--root-stress/--no-root-stress",
            help="FE tooth-root stress of both gears at every contact position (into the "
            "verdict and the report's load capacity; 15-30 % more tooth-model and "
            "contact time, docs/run.md).",
        ),
    ] = True,
    te_sweep: Annotated[
        int | None,
        typer.Option(
            "--te-sweep",
            min=2,
            max=41,
            help="Also the loaded TE of each pair at N torques from 0 to 1.5x its "
            "operating torque (te_sweep-pairN.nc/.txt; about a single-load contact's "
            "time more).",
        ),
    ] = None,
    layout: Annotated[
        bool,
        typer.Option(
            "--layout/--no-layout",
            help="Also the flank modification layout (lead crowning, tip relief) of each "
            "pair at its operating torque (layout-pairN.nc/.txt; 18 candidates of 12 "
            "positions: several contacts' time).",
        ),
    ] = False,
    sharing: Annotated[
        int | None,
        typer.Option(
            "--sharing",
            min=2,
            max=41,
            help="Also a KHV drive's load sharing at N torques from 0 to 1.5x the "
            "planet's operating torque: tooth pairs in contact, their shares, k against "
            "torque (sharing-pair1.nc/.txt; on the run's tooth models, built for it "
            "under the ISO stiffness). Other drives refuse it.",
        ),
    ] = None,
    datasheet: Annotated[
        bool,
        typer.Option(
            "--datasheet",
            help="Also the datasheet's efficiency with the starting and back-driving "
            "torque (and a KHV or nutation drive's transmission accuracy under load) on "
            "the run's tooth models: in the report's Datasheet section, efficiency.nc, "
            "accuracy.nc.",
        ),
    ] = False,
    pressure_limit: Annotated[
        str, typer.Option(help="--layout: largest contact pressure, e.g. '1500 MPa'.")
    ] = "1500 MPa",
    scheduler: SchedulerOption = None,
    sets: SetOption = None,
) -> None:
    """The whole chain of a design at its operating point: torque flow, loaded contact per
    pair (with the FE tooth-root stress), optionally each pair's loaded-TE torque sweep
    and flank modification layout (a KHV drive's load sharing), k(t) in the model, modes
    and Campbell diagram, nonlinear response under load, gear-body modes, verdict and
    report. Each stage is cached by what it depends on: a second run reads it. Exit 1
    when the verdict finds a risk."""
    from ..io import prepare_output_dir
    from ..pipeline import ContactSettings, LayoutSettings, run
    from ..pipeline.store import Store

    with user_errors():
        prepare_output_dir(output)
        store = Store(cache if cache is not None else output / "cache")
        length = {
            name: quantity_option(text, f"--{name.replace('_', '-')}", "length")
            for name, text in (
                ("cell", cell),
                ("tooth_size", tooth_size),
                ("body_tooth_size", body_tooth_size),
                ("body_size", body_size),
            )
        }
        settings = ContactSettings(
            positions=positions,
            cell=length["cell"],
            tooth_size=length["tooth_size"],
            root_stress=root_stress,
        )
        p_lim = quantity_option(pressure_limit, "--pressure-limit", "pressure")
        lay = LayoutSettings(pressure_limit=p_lim) if layout else False
        keeps_cache(store.root)
        with scheduler_client(scheduler) as client, run_progress() as show:
            res = run(
                design,
                output,
                overrides=sets or (),
                cache=store.root,
                contact=settings,
                bodies=bodies,
                body_sizes=(length["body_tooth_size"], length["body_size"]),
                response={
                    "periods": periods,
                    "keep": min(100, periods // 2),
                    "history": min(20, periods // 4),
                },
                te_sweep=te_sweep,
                layout=lay,
                sharing=sharing,
                datasheet=datasheet,
                scheduler=client,
                progress=show,
            )
    for f in res.files:
        note(f"wrote {f}")
    for st in res.stages:
        typer.echo(f"  {st.name:<32} {st.status:<9} {st.seconds:8.1f} s")
    typer.echo(res.verdict.table())
    typer.echo(f"report: {res.report}" if res.report else "")
    typer.echo(f"run: {res.seconds:.1f} s")
    if not res.ok:
        raise typer.Exit(1)


def register(app: typer.Typer) -> None:
    """Add ``run`` to the command line."""
    app.command("run")(run_cmd)
