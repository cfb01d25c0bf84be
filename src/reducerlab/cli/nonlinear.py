"""``reducerlab response``, ``bifurcation``, ``frequency-response`` and ``regime-map``:
the steady nonlinear response of a design and how it changes over parameters."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated, Any

import typer

from ..analysis.policies import Continuation
from ..dynamics.limits import ACCURACY, MAX_STEPS, MIN_STEPS
from ..numformat import Value, fmt, quantity_table
from .options import (
    MAX_PERIODS,
    MAX_VALUES,
    MAX_WORKERS,
    AccuracyOption,
    DesignArgument,
    Direction,
    Format,
    FormatOption,
    FrequencyOption,
    PeriodOption,
    SchedulerOption,
    SetOption,
    axis,
    check_periods,
    forcing_period,
    path_values,
    scheduler_client,
)
from .output import (
    add_with_figure,
    busy,
    keeps_run,
    output_set,
    save_with_figure,
    user_errors,
    write_json,
)


def bifurcation(
    design: DesignArgument,
    param: Annotated[str, typer.Option("--param", "-p", help="Parameter path.")],
    values: Annotated[
        str, typer.Option("--values", "-v", help="'lin:START:STOP:N', a list, or 'rel:...'.")
    ],
    periods: Annotated[
        int, typer.Option(help="Mesh periods integrated.", min=1, max=MAX_PERIODS)
    ] = 600,
    keep: Annotated[
        int | None,
        typer.Option(
            help="Last periods kept as Poincaré points (<= --periods; default 100, at most "
            "--periods).",
            min=1,
        ),
    ] = None,
    steps: Annotated[
        int | None,
        typer.Option(
            help="RK4 steps per period (default: from the model).", min=MIN_STEPS, max=MAX_STEPS
        ),
    ] = None,
    accuracy: AccuracyOption = ACCURACY,
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Output folder (resumable).")
    ] = Path("bifurcation-output"),
    scheduler: SchedulerOption = None,
    classify: Annotated[
        bool, typer.Option(help="Lyapunov exponents and motion classes (slower).")
    ] = False,
    continuation: Annotated[
        Direction | None,
        typer.Option(
            help="Sweep the values in order, each from the previous end state (up, down or "
            "both: shows jumps and coexisting attractors; sequential, not resumable)."
        ),
    ] = None,
    workers: Annotated[
        int | None,
        typer.Option(
            help="Processes building the models (default: one per core).", min=1, max=MAX_WORKERS
        ),
    ] = None,
    period: PeriodOption = None,
    frequency: FrequencyOption = None,
    seeds: Annotated[
        int,
        typer.Option(
            help="Further runs per value from random starts (coexisting attractors).",
            min=0,
            max=1000,
        ),
    ] = 0,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Bifurcation diagram: Poincaré points of the mesh deflection against a parameter.

    At most 100000 values; the output folder is resumable (bifurcation.json, chunks/)."""
    from ..analysis.bifurcation import bifurcation as run_bifurcation
    from ..drives import load_design

    with user_errors():
        keep = min(100, periods) if keep is None else keep
        check_periods(periods, keep=keep)
        T = forcing_period(period, frequency)
        files = output_set(output)
        d = load_design(design, sets or ())
        values_axis = axis("bifurcation --values", param, values, MAX_VALUES)
        keeps_run(output)
        with scheduler_client(scheduler) as client, busy("bifurcation") as report:
            res = run_bifurcation(
                d, values_axis, periods=periods, keep=keep, steps_per_period=steps, period=T,
                accuracy=accuracy,
                output=output, scheduler=client, exponents=classify, workers=workers,
                continuation=continuation,
                progress=report, seeds=seeds,
            )  # fmt: skip
        save_with_figure(res, files, "bifurcation")
    both = bool(seeds) or continuation == Continuation.BOTH
    if fmt is Format.table:
        typer.echo(res.table(motion=classify, coexisting=both))
        return
    summary = res.to_dict()
    if classify:
        summary["motion"] = res.labels()
    if both:
        summary["coexisting"] = res.coexisting().tolist()
    typer.echo(json.dumps(summary))


def frequency_response(
    design: DesignArgument,
    param: Annotated[str, typer.Option("--param", "-p", help="Parameter path, e.g. input_speed.")],
    values: Annotated[
        str,
        typer.Option(
            "--values", "-v", help="'lin:START:STOP:N', a list (units allowed: '1000 rpm,...')."
        ),
    ],
    periods: Annotated[
        int, typer.Option(help="Forcing periods integrated per value.", min=2, max=MAX_PERIODS)
    ] = 300,
    history: Annotated[int, typer.Option(help="Last periods measured (<= --periods).", min=1)] = 10,
    continuation: Annotated[
        Direction,
        typer.Option(help="Sweep direction(s); each value starts from the previous end state."),
    ] = Direction.BOTH,
    accuracy: AccuracyOption = ACCURACY,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "frequency-response-output"
    ),
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Frequency-response curves: RMS dynamic transmission error, dynamic load factor and
    tooth separation against a parameter, swept up and down (jumps, hysteresis)."""
    from ..analysis.frequency_response import frequency_response as run_fr
    from ..drives import load_design

    with user_errors():
        check_periods(periods, history=history)
        files = output_set(output)
        d = load_design(design, sets or ())
        values_axis = axis("frequency-response --values", param, values, MAX_VALUES)
        with busy("frequency-response") as report:
            res = run_fr(d, values_axis, periods=periods, history=history,
                         continuation=continuation, accuracy=accuracy,
                         progress=report)  # fmt: skip
        save_with_figure(res, files, "frequency-response")
    typer.echo(json.dumps(res.to_dict()) if fmt is Format.json else res.table())


def regime_map(
    design: DesignArgument,
    x: Annotated[
        str,
        typer.Option(
            "-x", help="Swept parameter (continuation): 'input_speed=lin:300 rpm:2000 rpm:41'."
        ),
    ],
    y: Annotated[
        str, typer.Option("-y", help="Second parameter (rows): 'gears.x1=lin:0.42:0.83:21'.")
    ],
    periods: Annotated[
        int, typer.Option(help="Forcing periods integrated per point.", min=1, max=MAX_PERIODS)
    ] = 600,
    keep: Annotated[
        int, typer.Option(help="Poincaré points kept per point (<= --periods).", min=1)
    ] = 64,
    continuation: Annotated[
        Continuation,
        typer.Option(
            help="Sweep direction(s) along -x; 'none': every point from its static equilibrium."
        ),
    ] = Continuation.UP,
    accuracy: AccuracyOption = ACCURACY,
    rows_per_chunk: Annotated[
        int, typer.Option(help="Rows (-y values) per chunk of the run folder.", min=1)
    ] = 4,
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Output folder (resumable).")
    ] = Path("regime-map-output"),
    scheduler: SchedulerOption = None,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Regime map: motion class (period-n, quasi-periodic, chaotic) and impact class of
    the steady response over two parameters.

    At most 250000 points; the output folder is resumable (regime_map_run.json, chunks/)."""
    from ..analysis.regime_map import MAX_POINTS
    from ..analysis.regime_map import regime_map as run_regime_map
    from ..drives import load_design

    with user_errors():
        check_periods(periods, keep=keep)
        files = output_set(output)
        d = load_design(design, sets or ())
        ax = path_values("regime-map -x", x, MAX_POINTS)
        ay = path_values("regime-map -y", y, MAX_POINTS)
        keeps_run(output)
        with scheduler_client(scheduler) as client, busy("regime map") as report:
            res = run_regime_map(
                d, ax, ay, periods=periods, keep=keep, continuation=continuation, accuracy=accuracy,
                rows_per_chunk=rows_per_chunk, output=output, scheduler=client,
                progress=report,
            )  # fmt: skip
        with files:
            add_with_figure(res, files, "regime_map")
            write_json(res, files.path("regime_map.json"))
            files.path("regime_map.txt").write_text(res.table() + "\n")
    typer.echo(json.dumps(res.to_dict()) if fmt is Format.json else res.table())


def response(
    design: DesignArgument,
    periods: Annotated[
        int, typer.Option(help="Forcing periods integrated.", min=1, max=MAX_PERIODS)
    ] = 600,
    keep: Annotated[
        int | None,
        typer.Option(help="Poincaré points kept (<= --periods; default 100).", min=1),
    ] = None,
    history: Annotated[
        int | None,
        typer.Option(help="Periods of time history kept (<= --periods; default 20).", min=1),
    ] = None,
    steps: Annotated[
        int | None, typer.Option(help="RK4 steps per period.", min=MIN_STEPS, max=MAX_STEPS)
    ] = None,
    accuracy: AccuracyOption = ACCURACY,
    period: PeriodOption = None,
    frequency: FrequencyOption = None,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "response-output"
    ),
    sets: SetOption = None,
) -> None:
    """Steady nonlinear response: phase trajectory, Poincaré map, spectrum, load factor."""
    from ..analysis.response import response as run_response
    from ..drives import load_design

    with user_errors():
        # defaults shrink to a short run; values the user gives are checked
        keep = min(100, periods) if keep is None else keep
        history = min(20, periods) if history is None else history
        check_periods(periods, keep=keep, history=history)
        T = forcing_period(period, frequency)
        files = output_set(output)
        d = load_design(design, sets or ())
        with busy("response"):
            res = run_response(
                d, periods=periods, keep=keep, history=history, steps_per_period=steps,
                period=T, accuracy=accuracy,
            )  # fmt: skip
        save_with_figure(res, files, "response")
    typer.echo(response_summary(res))


def response_summary(res: Any) -> str:
    """The response's numbers as a table (quantity, value, unit), one rule for every
    number (:mod:`reducerlab.numformat`), then its spectral peaks or why it has none."""
    a = res.data.attrs
    dlf = a["dynamic_load_factor"]
    rows: list[tuple[str, Any, str]] = []
    if math.isfinite(dlf):
        rows += [("dynamic load factor max|F| / mean F", dlf, ""),
                 ("mean mesh force", a["mean_mesh_force"], "N")]  # fmt: skip
    rows += [
        ("RK4 steps per period", Value(a["steps_per_period"], "count"), ""),
        ("mesh mode", a["mesh_mode_hz"], "Hz"),
        ("forcing / mesh mode", a["frequency_ratio"], ""),
        ("teeth apart (share of the time)", 100 * a["separation_fraction"], "%"),
        ("back-side contact (share of the time)", 100 * a["back_contact_fraction"], "%"),
        ("contact losses per period", a["contact_losses_per_period"], ""),
        ("back-side impacts per period", a["back_impacts_per_period"], ""),
    ]
    lines = [quantity_table(rows, title=f"response: {a['impact_class']}").text()]
    if not math.isfinite(dlf):
        lines.append("no mean mesh force (no load on the model): the dynamic load factor is "
                     "undefined")  # fmt: skip
    peaks = res.peaks(5)
    lines.append(
        "spectral peaks at " + ", ".join(f"{fmt(m)}x" for m, _ in peaks) + " the forcing frequency"
        if peaks
        else "no spectral peaks: the mesh deflection is constant (nothing excites the model)"
    )
    return "\n".join(lines)


def register(app: typer.Typer) -> None:
    """Add ``bifurcation``, ``frequency-response``, ``regime-map`` and ``response``."""
    app.command()(bifurcation)
    app.command("frequency-response")(frequency_response)
    app.command("regime-map")(regime_map)
    app.command()(response)
