"""Command line: ``reducerlab modal``, ``sensitivity``, ``kinematics``, ``sweep``,
``campbell``, ``check``, ``bifurcation``, ``frequency-response``, ``regime-map``,
``response``, ``surface``, ``khv``, ``body-modal``, ``contact``, ``demo``. Every command
that reads a design file takes ``--set PATH=VALUE`` to override a field.

Errors caused by the user's input are printed as one clear message (exit code 2),
never as a traceback. Text from the user (paths, values, design fields) is printed
verbatim: the consoles interpret no rich markup, emoji codes or highlighting.

Outputs follow one convention (:mod:`reducerlab.io`): ``-o DIR`` names an output
directory for every command that writes files; it is checked before any computation,
each command's files are written together (staged, then moved into place) and every
file written or replaced is reported on stderr. Options that name one file
(``surface --export/--png/--cloud``) have their suffix checked before any work.

Counts are bounded (checked before any work, the option named in the message): at
most 100000 speeds (``campbell --speeds``), 1000000 sweep points, 100000 bifurcation
values, periods in [1, 10^6], ``--keep`` and ``--history`` at most ``--periods``, RK4
steps per period in [4, 100000], at most 4 ``--workers`` per core.
"""

from __future__ import annotations

import json
import math
import re
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, NoReturn

import typer
from rich.console import Console
from rich.table import Table
from rich.text import Text

from . import __version__
from .analysis.workers import max_workers
from .dynamics.steps import MAX_STEPS, MIN_STEPS
from .errors import ReducerlabError
from .io import OutputSet, atomic_path, png_metadata, prepare_output_dir, prepare_output_file

if TYPE_CHECKING:
    from rich.progress import Progress

app = typer.Typer(
    name="reducerlab",
    help="Design and dynamic analysis of compact high-ratio gear reducers.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
# user text (paths, values, messages) is printed verbatim: no markup, emoji or highlighting
out = Console(markup=False, emoji=False, highlight=False)
err = Console(stderr=True, markup=False, emoji=False, highlight=False)

MAX_SPEEDS = 100_000
"""Most input speeds of ``campbell --speeds``."""
MAX_SWEEP_POINTS = 1_000_000
"""Most points of a ``sweep`` (all axes together)."""
MAX_VALUES = 100_000
"""Most parameter values of a ``bifurcation``."""
MAX_PERIODS = 1_000_000
"""Most forcing periods of ``bifurcation`` and ``response``."""
"""Range of RK4 steps per forcing period (``--steps``)."""
MAX_WORKERS = max_workers()
"""Most worker processes (``--workers``): the API's limit, 4 per core."""
SCHEDULER_TIMEOUT_S = 10.0
"""Seconds allowed to connect to a Dask scheduler (``--scheduler``)."""


SetOption = Annotated[
    list[str] | None,
    typer.Option(
        "--set",
        metavar="PATH=VALUE",
        help="Override a design field, units allowed (repeatable): --set 'input_speed=670 rpm'.",
    ),
]
"""``--set PATH=VALUE``: design fields overridden before validation (every command that
reads a design file takes it; see :func:`reducerlab.design.apply_overrides`)."""


SchedulerOption = Annotated[
    str | None, typer.Option(help="Dask scheduler address, e.g. tcp://HOST:8786.")
]
"""``--scheduler``: run the chunks of a resumable command on a Dask cluster."""


class Format(StrEnum):
    table = "table"
    json = "json"


def _version(value: bool) -> None:
    if value:
        typer.echo(f"reducerlab {__version__}")
        raise typer.Exit()


@app.callback()
def _main(
    version: Annotated[
        bool, typer.Option("--version", callback=_version, is_eager=True, help="Show version.")
    ] = False,
) -> None:
    """reducerlab: from a design file to frequencies, modes, responses and reports."""


def _note(line: str) -> None:
    """One line on stderr, verbatim (``wrote PATH``)."""
    err.print(line, soft_wrap=True)


def _fail(exc: Exception) -> NoReturn:
    """Print ``error: MESSAGE`` (the message verbatim) and exit with code 2."""
    err.print(Text.assemble(("error:", "bold red"), " ", str(exc)), soft_wrap=True)
    raise typer.Exit(code=2)


def _progress() -> Progress:
    """A transient progress bar on stderr; task descriptions are shown verbatim."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    return Progress(
        TextColumn("{task.description}", markup=False),
        BarColumn(),
        TextColumn("{task.completed}/{task.total}", markup=False),
        TimeElapsedColumn(),
        console=err,
        transient=True,
        disable=not err.is_terminal,  # no bar (nor blank line) in logs and pipes
    )


@contextmanager
def _busy(description: str) -> Iterator[Callable[[int, int], None]]:
    """A progress bar for work of unknown length; yields an update(done, total)."""
    with _progress() as progress:
        task = progress.add_task(description, total=None)
        yield lambda done, total: progress.update(task, completed=done, total=total)


def _rigid_tol(value: float) -> float:
    """Typer callback: ``--rigid-tol`` must be a finite number in [0, 1)."""
    if not 0 <= value < 1:  # also false for NaN
        raise typer.BadParameter(f"must be a finite number in [0, 1); got {value!r}")
    return value


def _outputs(output: Path | None) -> OutputSet | None:
    """The output set of ``-o DIR`` (checked now, before any work), or None."""
    return None if output is None else OutputSet(output, "-o", report=_note)


def _write_file(path: Path, write: Callable[[Path], Any]) -> None:
    """Write one file atomically with ``write(temporary_path)`` and report it."""
    replaced = path.exists()
    with atomic_path(path) as tmp:
        write(tmp)
    _note(f"{'replaced' if replaced else 'wrote'} {path}")


@contextmanager
def _user_errors() -> Iterator[None]:
    """Print an error caused by the user's input (or an unwritable output) as one line
    and exit with code 2, without a traceback."""
    try:
        yield
    except (ReducerlabError, OSError) as exc:
        _fail(exc)


def _savefig(fig: Any, path: Path, attrs: dict[str, Any], dpi: int = 120) -> None:
    """Save a figure as PNG stamped with its provenance (version, time, design, hash)."""
    fig.savefig(path, dpi=dpi, format="png", metadata=png_metadata(attrs))


def _add_with_figure(result, files: OutputSet, stem: str) -> None:
    """Add ``STEM.nc`` and the result's figure ``STEM.png`` to an open output set."""
    result.save(files.path(f"{stem}.nc"))
    _savefig(result.plot(), files.path(f"{stem}.png"), result.data.attrs)


def _save_with_figure(result, files: OutputSet, stem: str) -> None:
    """Write ``STEM.nc`` and ``STEM.png`` as one output set."""
    with files:
        _add_with_figure(result, files, stem)


def _write_json(result, path: Path) -> None:
    """The result's JSON summary stamped with its provenance (version, time, design)."""
    path.write_text(json.dumps({**result.to_dict(), **result.provenance}, indent=2) + "\n")


def _model_from(design_path: Path, sets: list[str] | None = None):
    from .drives import build_model, load_design

    design = load_design(design_path, sets or ())
    return design, build_model(design)


def _add_modal(result, files: OutputSet) -> None:
    """Add modal.nc, modal.json, modal.txt and the two figures to an open output set."""
    result.save(files.path("modal.nc"))
    _write_json(result, files.path("modal.json"))
    files.path("modal.txt").write_text(result.table() + "\n")
    _savefig(result.plot_shapes(), files.path("mode_shapes.png"), result.data.attrs)
    _savefig(result.plot_energy(), files.path("energy.png"), result.data.attrs)


def _print_modal(result) -> None:
    table = Table(title=result.data.attrs.get("title", "modal analysis"))
    table.add_column("mode", justify="right")
    table.add_column("frequency (Hz)", justify="right")
    table.add_column("classification")
    for m, f, c in zip(
        result.data["mode"].values, result.frequencies, result.classifications, strict=True
    ):
        table.add_row(str(int(m)), f"{f:.6g}", c)
    out.print(table)


@app.command()
def modal(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write results and figures here.")
    ] = None,
    fmt: Annotated[Format, typer.Option("--format", help="Output on stdout.")] = Format.table,
    rigid_tol: Annotated[
        float,
        typer.Option(
            help="Relative eigenvalue below which a mode is rigid (0 Hz), in [0, 1).",
            callback=_rigid_tol,
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
    """Natural frequencies, mode shapes and energy classification of a design."""
    from .analysis.complex_modal import complex_modes
    from .analysis.modal import modal as run_modal

    with _user_errors():
        files = _outputs(output)
        with _busy("modal analysis"):
            _, model = _model_from(design, sets)
            result = run_modal(model, rigid_tol=rigid_tol)
            cplx = complex_modes(model, rigid_tol=rigid_tol) if complex_ else None
        if files is not None:
            with files:
                _add_modal(result, files)
                if cplx is not None:
                    _add_with_figure(cplx, files, "complex_modes")
                    _write_json(cplx, files.path("complex_modes.json"))
    if cplx is not None:
        typer.echo(json.dumps(cplx.to_dict()) if fmt is Format.json else cplx.table())
        return
    if fmt is Format.json:
        typer.echo(result.to_json())
    else:
        _print_modal(result)
        if result.data.attrs.get("skew_velocity_terms"):
            _note("the model has gyroscopic, Coriolis or circulatory terms, which undamped "
                  "modes leave out: see reducerlab modal --complex")  # fmt: skip


@app.command()
def sensitivity(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
    param: Annotated[
        list[str] | None,
        typer.Option("--param", "-p", help="Parameter path, e.g. mesh.stiffness (repeatable)."),
    ] = None,
    list_params: Annotated[
        bool, typer.Option("--list", help="List the model's parameter paths and exit.")
    ] = False,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write results and figure here.")
    ] = None,
    fmt: Annotated[Format, typer.Option("--format", help="Output on stdout.")] = Format.table,
    sets: SetOption = None,
) -> None:
    """Sensitivity of every natural frequency to model parameters (analytic)."""
    from .analysis.modal import frequency_sensitivity
    from .model.inspect import parameter_paths

    with _user_errors():
        files = None if list_params else _outputs(output)
        _, model = _model_from(design, sets)
        if list_params:
            for path, value in parameter_paths(model):
                typer.echo(f"{path} = {value:.6g}")
            return
        params = param or [p for p, _ in parameter_paths(model)]
        with _busy("sensitivity"):
            res = frequency_sensitivity(model, params)
        if files is not None:
            _save_with_figure(res, files, "sensitivity")
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


def _add_kinematics(result, files: OutputSet) -> None:
    """Add kinematics.nc, kinematics.json (and angular_velocity.png) to an open set."""
    result.save(files.path("kinematics.nc"))
    _write_json(result, files.path("kinematics.json"))
    if "omega" in result.data:
        _savefig(result.plot(), files.path("angular_velocity.png"), result.data.attrs)


def _run_kinematics(design):
    from .analysis.kinematics import kinematics as run_kinematics
    from .drives import kinematics_of

    drive, speed = kinematics_of(design)
    return run_kinematics(
        drive,
        speed,
        title=design.name,
        metadata=design.provenance,
    )


@app.command()
def kinematics(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write results and figure here.")
    ] = None,
    fmt: Annotated[Format, typer.Option("--format", help="Output on stdout.")] = Format.table,
    sets: SetOption = None,
) -> None:
    """Transmission ratio, member speeds, mesh frequencies and cone angles of a drive."""
    from .drives import load_design

    with _user_errors():
        files = _outputs(output)
        result = _run_kinematics(load_design(design, sets or ()))
        if files is not None:
            with files:
                _add_kinematics(result, files)
    typer.echo(result.to_json() if fmt is Format.json else result.table())


def _axis(option: str, path: str, spec: str, limit: int):
    """A value specification (:func:`~reducerlab.analysis.sweep.parse_values`) of at most
    ``limit`` values."""
    from .analysis.sweep import parse_values

    return parse_values(path, spec, limit=limit, option=option)


def _path_values(
    option: str, text: str, limit: int, example: str = "input_speed=lin:300 rpm:2000 rpm:41"
):
    """``PATH=VALUES`` (``sweep --grid``, ``regime-map -x/-y``) as an axis."""
    from .analysis.sweep import parse_path_values

    return parse_path_values(text, limit=limit, option=option, example=example)


def _parse_speeds(spec: str | None, option: str = "--speeds") -> list[float] | None:
    """``lin:START:STOP:N`` in rpm, or a comma list in rpm (at most :data:`MAX_SPEEDS`)."""
    if spec is None:
        return None
    import numpy as np

    from .analysis.campbell import RPM
    from .units import QUANTITIES

    axis = _axis(option, "speeds", spec, MAX_SPEEDS)
    if axis.relative or any(isinstance(v, str) for v in axis.values):
        raise ReducerlabError(f"{option} takes plain numbers in rpm, e.g. lin:0:3000:301")
    rpm = np.asarray(axis.values, dtype=float)
    # the range of the speeds that design files may give (units.QUANTITIES), in rpm
    kind = QUANTITIES["angular velocity"]
    lo, hi = kind.lo * RPM, kind.hi * RPM
    bad = rpm[~((rpm == 0) | ((rpm >= lo) & (rpm <= hi)))]  # also negative, non-finite
    if bad.size:
        raise ReducerlabError(
            f"{option}: {bad[0]:g} rpm is outside the range of speeds: 0 or within "
            f"[{lo:.3g}, {hi:.3g}] rpm"
        )
    return (rpm / RPM).tolist()


_ADDRESS = re.compile(
    r"(?:(?:tcp|tls|ucx|ws|wss)://)?(?:\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):([0-9]{1,5})"
)


@contextmanager
def _scheduler(address: str | None) -> Iterator[Any]:
    """A Dask client for ``--scheduler`` (None without one), closed afterwards.

    The address form is checked before connecting; a failed connection is a
    :class:`ReducerlabError` naming ``--scheduler``.
    """
    if address is None:
        yield None
        return
    m = _ADDRESS.fullmatch(address.strip())
    if not m or not 1 <= int(m.group(1)) <= 65535:
        raise ReducerlabError(
            f"--scheduler: {address!r} is not a scheduler address; write "
            "tcp://HOST:PORT, e.g. tcp://10.0.0.5:8786"
        )
    try:
        from dask.distributed import Client
    except ImportError:  # pragma: no cover - dask is a dependency
        raise ReducerlabError("--scheduler needs dask.distributed installed") from None
    try:
        client = Client(address.strip(), timeout=SCHEDULER_TIMEOUT_S)
    except (OSError, TimeoutError, ValueError) as exc:
        raise ReducerlabError(
            f"--scheduler {address}: cannot connect to a Dask scheduler within "
            f"{SCHEDULER_TIMEOUT_S:g} s ({type(exc).__name__}: {exc})"
        ) from None
    try:
        yield client
    finally:
        client.close()


@app.command()
def sweep(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
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
    fmt: Annotated[Format, typer.Option("--format", help="Output on stdout.")] = Format.table,
    sets: SetOption = None,
) -> None:
    """Natural frequencies over a parameter (tracked modes, veerings) or a grid of two.

    At most 1000000 points in all; the run folder is resumable (sweep.json, chunks/)."""
    from .analysis.sweep import sweep as run_sweep
    from .drives import load_design

    with _user_errors():
        files = OutputSet(output, "-o", report=_note)
        d = load_design(design, sets or ())
        axes = [_axis("--values", param, values, MAX_SWEEP_POINTS)]
        if grid is not None:
            axes.append(_path_values("--grid", grid, MAX_SWEEP_POINTS, "mesh.damping=lin:0:1e3:11"))
        n_points = math.prod(len(a.values) for a in axes)
        if n_points > MAX_SWEEP_POINTS:
            raise ReducerlabError(
                f"--values x --grid: {n_points} points; at most {MAX_SWEEP_POINTS} are allowed"
            )
        nc_existed = (output / "sweep.nc").exists()
        with _scheduler(scheduler) as client, _busy("sweep chunks") as report:
            result = run_sweep(
                d,
                axes,
                output=output,
                chunk_size=chunk_size,
                workers=workers,
                scheduler=client,
                progress=report,
            )
        _note(f"{'replaced' if nc_existed else 'wrote'} {output / 'sweep.nc'}")
        with files:
            _savefig(result.plot(), files.path("sweep.png"), result.data.attrs)
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


@app.command()
def campbell(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
    speeds: Annotated[
        str | None, typer.Option(help="Input speeds in rpm: 'lin:0:3000:301' or a list.")
    ] = None,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write results and figure here.")
    ] = None,
    fmt: Annotated[Format, typer.Option("--format", help="Output on stdout.")] = Format.table,
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
    from .analysis.campbell import campbell as run_campbell
    from .analysis.complex_modal import complex_campbell
    from .drives import load_design

    with _user_errors():
        files = _outputs(output)
        d = load_design(design, sets or ())
        omegas = _parse_speeds(speeds)
        with _busy("campbell"):
            res = complex_campbell(d, omegas) if complex_ else run_campbell(d, omegas)
        if files is not None:
            _save_with_figure(res, files, "complex_campbell" if complex_ else "campbell")
    if complex_:
        typer.echo(json.dumps(res.to_dict()) if fmt is Format.json else res.table())
        return
    typer.echo(json.dumps({"crossings": res.crossings()}) if fmt is Format.json else res.table())


@app.command()
def check(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
    margin: Annotated[
        float,
        typer.Option(
            help="Relative distance to an excitation that counts (0.10 = 10 %), in (0, 1)."
        ),
    ] = 0.10,
    speed_range: Annotated[
        str | None, typer.Option(help="Operating range in rpm 'MIN,MAX' (default: design's).")
    ] = None,
    fmt: Annotated[Format, typer.Option("--format", help="Output on stdout.")] = Format.table,
    body_modes: Annotated[
        list[Path] | None,
        typer.Option(
            "--body-modes",
            help="A gear body's modes (body_modal.nc from 'reducerlab body-modal'); repeat "
            "for each gear.",
        ),
    ] = None,
    bodies: Annotated[
        bool,
        typer.Option(
            "--bodies",
            help="Compute every gear body's modes first (needs a [surface] table; minutes).",
        ),
    ] = False,
    output: Annotated[
        Path | None,
        typer.Option(
            "--output",
            "-o",
            help="Also write check.json, the Table 5-style comparison and the Campbell "
            "diagram with the body lines (PNG) here.",
        ),
    ] = None,
    sets: SetOption = None,
) -> None:
    """Resonance verdict: exits 1 when a natural frequency meets an excitation, or a gear
    body's mode meets an excitation or a system mode (paper 000 Table 5)."""
    from .analysis.body_modal import BodyModalResult
    from .analysis.campbell import ComponentModes, format_check, resonance_check
    from .drives import load_design

    with _user_errors():
        files = _outputs(output)
        components = []
        for path in body_modes or []:
            res_b = BodyModalResult.load(path)
            components.append(ComponentModes.from_body_modal(res_b, source=str(path)))
        rng = None
        if speed_range is not None:
            parts = _parse_speeds(speed_range, "--speed-range")
            if parts is None or len(parts) != 2:
                raise ReducerlabError("--speed-range must be 'MIN,MAX' in rpm")
            rng = (parts[0], parts[1])
        d = load_design(design, sets or ())
        if bodies:
            components += _all_body_modes(d, design, {c.label for c in components})
        with _busy("resonance check"):
            report = resonance_check(d, margin=margin, speed_range=rng, components=components)
        if files is not None:
            _write_check(d, report, components, files)
    typer.echo(json.dumps(report, indent=2) if fmt is Format.json else format_check(report))
    if not report["ok"]:
        raise typer.Exit(code=1)


def _all_body_modes(d, design: Path, have: set[str]) -> list:
    """Body modes of every gear of a nutation design not given already (progress bar)."""
    from .analysis.body_modal import body_modal as run_body_modal
    from .analysis.body_modal import check_bodies
    from .analysis.campbell import ComponentModes

    try:
        check_bodies(d)
    except ReducerlabError as exc:
        raise ReducerlabError(
            f"--bodies: {design}: {exc}; give --body-modes files instead"
        ) from None
    out = []
    gears = [g for g in range(1, d.gear_count + 1) if f"gear {g}" not in have]
    with _progress() as progress:
        task = progress.add_task("gear bodies", total=None)
        for g in gears:
            res = run_body_modal(
                d, g, convergence=False,
                stage=lambda s, g=g: progress.update(task, description=f"gear {g}: {s}"),
            )  # fmt: skip
            out.append(ComponentModes.from_body_modal(res))
    return out


def _write_check(d, report: dict, components: list, files: OutputSet) -> None:
    """check.json, components.png (Table 5-style) and campbell.png with the body lines."""
    import numpy as np

    from .analysis.campbell import campbell as run_campbell
    from .io import stamp
    from .plot.components import plot_component_comparison
    from .plot.sweep import plot_campbell

    hi = report["speed_range_rpm"][1] * 2 * math.pi / 60  # rad/s
    res_c = run_campbell(d, np.linspace(0.0, 1.5 * hi, 151))
    fmax = None
    if components:
        fmax = 1.05 * max(max(c.frequencies) for c in components)
    with files:
        files.path("check.json").write_text(
            json.dumps({**report, **stamp(d.provenance)}, indent=2) + "\n"
        )
        if components:
            _savefig(plot_component_comparison(report), files.path("components.png"),
                     d.provenance)  # fmt: skip
        _savefig(plot_campbell(res_c, components, fmax=fmax), files.path("campbell.png"),
                 d.provenance)  # fmt: skip


#: Target error of the Poincaré points (analysis.response.accurate_steps).
AccuracyOption = Annotated[
    float,
    typer.Option(
        help="Target error of the Poincaré points relative to the motion's scale: the "
        "step count is chosen to meet it (ignored with --steps).",
        min=1e-12,
        max=0.1,
    ),
]


class ContinuationChoice(StrEnum):
    up = "up"
    down = "down"
    both = "both"


@app.command()
def bifurcation(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
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
    accuracy: AccuracyOption = 1e-6,
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Output folder (resumable).")
    ] = Path("bifurcation-output"),
    scheduler: SchedulerOption = None,
    classify: Annotated[
        bool, typer.Option(help="Lyapunov exponents and motion classes (slower).")
    ] = False,
    continuation: Annotated[
        ContinuationChoice | None,
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
    sets: SetOption = None,
) -> None:
    """Bifurcation diagram: Poincaré points of the mesh deflection against a parameter.

    At most 100000 values; the output folder is resumable (bifurcation.json, chunks/)."""
    from .analysis.nonlinear import bifurcation as run_bifurcation
    from .drives import load_design

    with _user_errors():
        keep = min(100, periods) if keep is None else keep
        _check_periods(periods, keep=keep)
        T = _forcing_period(period, frequency)
        files = OutputSet(output, "-o", report=_note)
        d = load_design(design, sets or ())
        axis = _axis("--values", param, values, MAX_VALUES)
        with _scheduler(scheduler) as client, _busy("bifurcation") as report:
            res = run_bifurcation(
                d, axis, periods=periods, keep=keep, steps_per_period=steps, period=T,
                accuracy=accuracy,
                output=output, scheduler=client, exponents=classify, workers=workers,
                continuation=None if continuation is None else continuation.value,
                progress=report, seeds=seeds,
            )  # fmt: skip
        _save_with_figure(res, files, "bifurcation")
    summary = res.to_dict()
    if classify:
        summary["motion"] = res.labels()
    if seeds or continuation is ContinuationChoice.both:
        summary["coexisting"] = res.coexisting().tolist()
    typer.echo(json.dumps(summary))


@app.command("frequency-response")
def frequency_response(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
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
        ContinuationChoice,
        typer.Option(help="Sweep direction(s); each value starts from the previous end state."),
    ] = ContinuationChoice.both,
    accuracy: AccuracyOption = 1e-6,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "frequency-response-output"
    ),
    sets: SetOption = None,
) -> None:
    """Frequency-response curves: RMS dynamic transmission error, dynamic load factor and
    tooth separation against a parameter, swept up and down (jumps, hysteresis)."""
    from .analysis.frequency_response import frequency_response as run_fr
    from .drives import load_design

    with _user_errors():
        _check_periods(periods, history=history)
        files = OutputSet(output, "-o", report=_note)
        d = load_design(design, sets or ())
        axis = _axis("--values", param, values, MAX_VALUES)
        with _busy("frequency-response") as report:
            res = run_fr(d, axis, periods=periods, history=history,
                         continuation=continuation.value, accuracy=accuracy,
                         progress=report)  # fmt: skip
        _save_with_figure(res, files, "frequency-response")
    typer.echo(json.dumps(res.to_dict()))


class RegimeContinuation(StrEnum):
    up = "up"
    down = "down"
    both = "both"
    none = "none"


@app.command("regime-map")
def regime_map(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
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
        RegimeContinuation,
        typer.Option(help="Sweep direction(s) along -x; 'none': every point from rest."),
    ] = RegimeContinuation.up,
    accuracy: AccuracyOption = 1e-6,
    rows_per_chunk: Annotated[
        int, typer.Option(help="Rows (-y values) per chunk of the run folder.", min=1)
    ] = 4,
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Output folder (resumable).")
    ] = Path("regime-map-output"),
    scheduler: SchedulerOption = None,
    fmt: Annotated[Format, typer.Option("--format", help="Output on stdout.")] = Format.table,
    sets: SetOption = None,
) -> None:
    """Regime map: motion class (period-n, quasi-periodic, chaotic) and impact class of
    the steady response over two parameters.

    At most 250000 points; the output folder is resumable (regime_map_run.json, chunks/)."""
    from .analysis.regime_map import MAX_POINTS
    from .analysis.regime_map import regime_map as run_regime_map
    from .drives import load_design

    with _user_errors():
        _check_periods(periods, keep=keep)
        files = OutputSet(output, "-o", report=_note)
        d = load_design(design, sets or ())
        ax = _path_values("-x", x, MAX_POINTS)
        ay = _path_values("-y", y, MAX_POINTS)
        way = None if continuation is RegimeContinuation.none else continuation.value
        with _scheduler(scheduler) as client, _busy("regime map") as report:
            res = run_regime_map(
                d, ax, ay, periods=periods, keep=keep, continuation=way, accuracy=accuracy,
                rows_per_chunk=rows_per_chunk, output=output, scheduler=client,
                progress=report,
            )  # fmt: skip
        with files:
            _add_with_figure(res, files, "regime_map")
            _write_json(res, files.path("regime_map.json"))
            files.path("regime_map.txt").write_text(res.table() + "\n")
    typer.echo(json.dumps(res.to_dict()) if fmt is Format.json else res.table())


def _check_periods(periods: int, **counts: int) -> None:
    """``--keep``/``--history`` must not exceed ``--periods``."""
    for name, value in counts.items():
        if value > periods:
            raise ReducerlabError(f"--{name} {value}: must be at most --periods ({periods})")


def _quantity_option(text: str | None, option: str, kind: str) -> float | None:
    """A positive finite quantity of ``kind`` ("time", "frequency", "length", ...) from
    an option, in SI: a plain number in SI or a quantity string ("2 ms", "1.2 mm")."""
    if text is None:
        return None
    from .units import parse_quantity

    try:
        value = float(text)
    except ValueError:
        try:
            value = parse_quantity(text, kind)
        except ValueError as exc:
            raise ReducerlabError(f"{option}: {exc}") from None
    if not (math.isfinite(value) and value > 0):
        raise ReducerlabError(f"{option}: must be a finite {kind} > 0; got {text!r}")
    return value


def _forcing_period(period: str | None, frequency: str | None) -> float | None:
    """The sampling period (s) given by ``--period`` or ``--frequency``, or None."""
    if period is not None and frequency is not None:
        raise ReducerlabError("--period and --frequency: give one of them, not both")
    f = _quantity_option(frequency, "--frequency", "frequency")
    return 1.0 / f if f is not None else _quantity_option(period, "--period", "time")


PeriodOption = Annotated[
    str | None,
    typer.Option(
        "--period",
        help="Forcing period, e.g. '2 ms' or 0.002 (s), for a design without a periodic "
        "mesh law (default: the design's).",
    ),
]
FrequencyOption = Annotated[
    str | None,
    typer.Option("--frequency", help="Forcing frequency, e.g. '500 Hz' (instead of --period)."),
]


@app.command()
def response(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
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
    accuracy: AccuracyOption = 1e-6,
    period: PeriodOption = None,
    frequency: FrequencyOption = None,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "response-output"
    ),
    sets: SetOption = None,
) -> None:
    """Steady nonlinear response: phase trajectory, Poincaré map, spectrum, load factor."""
    from .analysis.nonlinear import response as run_response
    from .drives import load_design

    with _user_errors():
        # defaults shrink to a short run; values the user gives are checked
        keep = min(100, periods) if keep is None else keep
        history = min(20, periods) if history is None else history
        _check_periods(periods, keep=keep, history=history)
        T = _forcing_period(period, frequency)
        files = OutputSet(output, "-o", report=_note)
        d = load_design(design, sets or ())
        with _busy("response"):
            res = run_response(
                d, periods=periods, keep=keep, history=history, steps_per_period=steps,
                period=T, accuracy=accuracy,
            )  # fmt: skip
        _save_with_figure(res, files, "response")
    attrs = res.data.attrs
    dlf = attrs["dynamic_load_factor"]
    typer.echo(
        f"dynamic load factor {dlf:.4f}, mean mesh force {attrs['mean_mesh_force']:.5g} N"
        if math.isfinite(dlf)
        else "no mean mesh force (no load on the model): the dynamic load factor is undefined"
    )
    typer.echo(f"{attrs['steps_per_period']} RK4 steps per period")
    typer.echo(
        f"mesh mode {attrs['mesh_mode_hz']:.5g} Hz (forcing / mesh mode = "
        f"{attrs['frequency_ratio']:.4g}); {attrs['impact_class']}: teeth apart "
        f"{100 * attrs['separation_fraction']:.1f} % of the time, back-side contact "
        f"{100 * attrs['back_contact_fraction']:.1f} %, "
        f"{attrs['contact_losses_per_period']:.3g} contact losses and "
        f"{attrs['back_impacts_per_period']:.3g} back-side impacts per period"
    )
    peaks = res.peaks(5)
    typer.echo(
        "spectral peaks at " + ", ".join(f"{m:.3g}x" for m, _ in peaks) + " the forcing frequency"
        if peaks
        else "no spectral peaks: the mesh deflection is constant (nothing excites the model)"
    )


class ProfileChoice(StrEnum):
    involute = "involute"
    double_arc = "double-arc"


GearOption = Annotated[
    int,
    typer.Option("--gear", "-g", help="Gear number: 1, 3 nutating (internal); 2, 4 external."),
]


@app.command()
def surface(
    design: Annotated[Path, typer.Argument(help="Nutation design file (TOML), surface table")],
    gear: GearOption = 1,
    profile: Annotated[
        ProfileChoice | None,
        typer.Option("--profile", help="Basic profile (default: the design's surface.profile)."),
    ] = None,
    export: Annotated[
        Path | None,
        typer.Option("--export", "-e", help="Write the solid: .stl, .ply or .step/.stp (mm)."),
    ] = None,
    points: Annotated[
        int,
        typer.Option("--points", "-n", help="Grid points along each flank and across the face."),
    ] = 15,
    tooth: Annotated[
        bool, typer.Option("--tooth", help="Export one tooth sector instead of the whole gear.")
    ] = False,
    cloud: Annotated[
        Path | None, typer.Option("--cloud", help="Write the flank point clouds (PLY, mm).")
    ] = None,
    png: Annotated[Path | None, typer.Option("--png", help="Render the tooth (PNG).")] = None,
    sets: SetOption = None,
) -> None:
    """Generate a gear's tooth surfaces (paper 001), check them, export a closed solid."""
    import numpy as np

    from .drives import load_design
    from .geometry import generate_tooth
    from .geometry.export import MESH_FORMATS, export_mesh, export_point_cloud
    from .geometry.solid import build_gear_solid

    with _user_errors():
        if not 3 <= points <= 401:
            raise ReducerlabError(f"--points: must be an integer in [3, 401]; got {points}")
        for option, path, suffixes in (
            ("--export", export, MESH_FORMATS),
            ("--png", png, (".png",)),
            ("--cloud", cloud, (".ply",)),
        ):
            if path is not None:
                prepare_output_file(path, option, suffixes)
        d = load_design(design, sets or ())
        if not hasattr(d, "tooth_generation"):
            raise ReducerlabError(
                f"{design}: type = {d.type!r}: tooth surfaces need a nutation design"
            )
        try:
            crown, bevel = d.tooth_generation(gear, None if profile is None else profile.value)
        except ValueError as exc:
            if isinstance(exc, ReducerlabError):
                raise
            name = "--gear" if str(exc).startswith("gear must") else str(design)
            raise ReducerlabError(f"{name}: {exc}") from None
        with _progress() as progress:
            task = progress.add_task("tooth surfaces", total=None)
            tooth_surface = generate_tooth(crown, bevel, points, points)
            progress.update(task, description="sections and blank")
            solid = build_gear_solid(
                crown,
                bevel,
                n_profile=points,
                n_face=points,
                n_land=max(1, points // 5),
                n_space=max(3, points // 2) | 1,
                rim=d.surface.rim,
                progress=lambda done, total: progress.update(task, completed=done, total=total),
            )
            if tooth:
                mesh = solid.tooth_mesh()
            else:
                progress.update(task, description="patterning teeth", completed=0)
                mesh = solid.gear_mesh(
                    progress=lambda k, z: progress.update(task, completed=k, total=z)
                )
            if export is not None:
                progress.update(task, description=f"writing {export.name}", total=None)
                _write_file(export, lambda tmp: export_mesh(mesh, tmp))
            if cloud is not None:
                fl = solid.flank_points()
                pts = np.concatenate([fl["A"][0], fl["B"][0]])
                nrm = np.concatenate([fl["A"][1], fl["B"][1]])
                _write_file(cloud, lambda tmp: export_point_cloud(pts, nrm, tmp))
            if png is not None:
                from .plot.surface import plot_tooth

                _write_file(
                    png,
                    lambda tmp: _savefig(plot_tooth(solid), tmp, d.provenance, 130),
                )
        closed = mesh.open_edges() == 0
    typer.echo(
        f"gear {gear}: {bevel.kind}, z = {bevel.teeth}, pitch cone "
        f"{math.degrees(bevel.cone_angle):.4f} deg, {crown.profile.name} profile, normal "
        f"module {crown.profile.module * 1e3:.5g} mm, spiral angle "
        f"{math.degrees(crown.spiral_angle):.4g} deg, face width {crown.face_width * 1e3:.5g} mm"
    )
    typer.echo(tooth_surface.report.summary())
    typer.echo(
        f"{'tooth sector' if tooth else 'gear'} solid: {len(mesh.faces)} triangles, "
        f"{len(mesh.vertices)} vertices, volume {mesh.volume * 1e9:.6g} mm^3, "
        f"{'closed (watertight)' if closed else 'NOT closed'}"
    )
    for note in solid.notes:
        typer.echo(f"note: {note}")


khv_app = typer.Typer(help="KHV planetary drive tools (paper 004).", no_args_is_help=True)
app.add_typer(khv_app, name="khv")


@khv_app.command("closed-graph")
def khv_closed_graph(
    design: Annotated[Path, typer.Argument(help="KHV design file (TOML).")],
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Output folder (writes closed-graph.png).")
    ] = Path("."),
    sets: SetOption = None,
) -> None:
    """Draw the closed graph (x1 vs x2, limit lines, feasible region) and mark the design."""
    from .design import apply_overrides, read_toml, validate_design
    from .drives.khv import Gears
    from .plot.khv import plot_closed_graph

    with _user_errors():
        files = OutputSet(output, "-o", report=_note)
        data = apply_overrides(read_toml(design), sets or ())
        if data.get("type") != "khv":
            raise ReducerlabError(f"{design}: type = {data.get('type')!r}: not a KHV design")
        gears = validate_design(Gears, data.get("gears", {}), f"{design}: gears")
        pair = gears.pair()
        fig = plot_closed_graph(pair, gears.shift_line if gears.x2 is None else None)
        with files:
            _savefig(fig, files.path("closed-graph.png"), {"design": json.dumps(data, default=str)})
    for c in pair.conditions():
        flag = "ok  " if c.ok else "FAIL"
        typer.echo(f"{flag} {c.name:<28} margin {c.margin:+.4g}   ({c.rule})")
    typer.echo(f"contact ratio {pair.contact_ratio:.4f}, working pressure angle "
               f"{math.degrees(pair.working_pressure_angle):.3f} deg")  # fmt: skip


@khv_app.command("stiffness")
def khv_stiffness(
    design: Annotated[Path, typer.Argument(help="KHV design file (TOML).")],
    x1: Annotated[
        str, typer.Option(help="Planet shift coefficients to compare, comma separated.")
    ] = "0.416,0.626,0.835",
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Output folder (writes mesh-stiffness.png).")
    ] = Path("."),
    sets: SetOption = None,
) -> None:
    """Time-varying mesh stiffness for several x1 on the design's shift line (Fig. 5)."""
    from .drives import design_from_dict, load_design
    from .plot.khv import plot_mesh_stiffness

    with _user_errors():
        files = OutputSet(output, "-o", report=_note)
        try:
            values = [float(v) for v in x1.split(",") if v.strip()]
        except ValueError:
            raise ReducerlabError(f"--x1: {x1!r} is not a list of numbers") from None
        if not values:
            raise ReducerlabError("--x1: give at least one value")
        if not all(math.isfinite(v) for v in values):
            raise ReducerlabError(f"--x1: {x1!r}: the values must be finite numbers")
        if len(values) > 20:
            raise ReducerlabError(f"--x1: {len(values)} values; at most 20 are allowed")
        d = load_design(design, sets or ())
        if d.type != "khv":
            raise ReducerlabError(f"{design}: type = {d.type!r}: not a KHV design")
        laws = {}
        for v in values:
            data = d.model_dump()
            data["gears"]["x1"] = v
            data["gears"]["x2"] = None
            dv = design_from_dict(data, f"{design} with x1 = {v:g}")
            law = dv.stiffness_law()
            laws[f"x1 = {v:g}: eps = {dv.gears.pair().contact_ratio:.3f}, "
                 f"mean {law.mean / 1e8:.3f}e8 N/m"] = law  # fmt: skip
            typer.echo(f"x1 = {v:g}: k_C = {dv.pitch_stiffness():.4g} N/m, mean {law.mean:.4g} N/m")
        with files:
            _savefig(plot_mesh_stiffness(laws), files.path("mesh-stiffness.png"), d.provenance)


class BoundaryChoice(StrEnum):
    free = "free"
    bore = "bore"
    face = "face"


@app.command("body-modal")
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
    convergence: Annotated[
        bool,
        typer.Option(help="Also solve a 1.5x coarser mesh and report each mode's change."),
    ] = True,
    renders: Annotated[bool, typer.Option(help="One PNG render per mode.")] = True,
    sets: SetOption = None,
) -> None:
    """Finite-element modes of one gear body (paper 000 §4, Table 4): frequencies, mode
    types, renders, netCDF/JSON and a VTU file of the mesh and mode shapes (ParaView)."""
    from .analysis.body_modal import body_modal as run_body_modal
    from .analysis.body_modal import check_bodies
    from .drives import load_design
    from .fe.gear_mesh import MeshSizes
    from .fe.vtu import write_vtu
    from .plot.body import plot_body_mode

    with _user_errors():
        files = OutputSet(output, "-o", report=_note)
        d = load_design(design, sets or ())
        try:
            check_bodies(d)
        except ReducerlabError as exc:
            raise ReducerlabError(f"{design}: {exc}") from None
        if gear not in range(1, d.gear_count + 1):
            raise ReducerlabError(
                f"--gear: must be 1..{d.gear_count} for a {d.sides}-sided drive; got {gear}"
            )
        sizes = None
        if tooth_size is not None or body_size is not None:
            crown, _ = d.tooth_generation(gear)
            dflt = MeshSizes.default(crown.profile.module)
            t, b = (
                default if text is None else _quantity_option(text, option, "length")
                for text, option, default in (
                    (tooth_size, "--tooth-size", dflt.tooth),
                    (body_size, "--body-size", dflt.body),
                )
            )
            sizes = MeshSizes(t, max(b, t) if body_size is None else b)
        with _progress() as progress:
            task = progress.add_task("gear body", total=None)
            res = run_body_modal(
                d, gear, count=modes, boundary=boundary.value, sizes=sizes,
                convergence=convergence,
                stage=lambda s: progress.update(task, description=s),
            )  # fmt: skip
            progress.update(task, description="writing results")
            with files:
                res.save(files.path("body_modal.nc"))
                _write_json(res, files.path("body_modal.json"))
                files.path("body_modal.txt").write_text(res.table() + "\n")
                _savefig(res.figure(), files.path("modes.png"), res.data.attrs)
                mesh, shapes = res.mesh, res.shapes
                labels = res.labels
                write_vtu(files.path("body_modes.vtu"), mesh.points, mesh.tets[:, :4], shapes,
                          res.frequencies, labels)  # fmt: skip
                if renders:
                    for k, (f, lab) in enumerate(zip(res.frequencies, labels, strict=True)):
                        title = f"Gear {gear}, mode {k + 1}: {f:.5g} Hz, {lab}"
                        fig = plot_body_mode(mesh.points, mesh.tets[:, :4], shapes[:, :, k], title)
                        _savefig(fig, files.path(f"mode_{k + 1:02d}.png"), res.data.attrs)
    typer.echo(res.table())


@app.command()
def contact(
    design: Annotated[Path, typer.Argument(help="Nutation design file (TOML), surface table")],
    pair: Annotated[
        int, typer.Option("--pair", help="Gear pair: 1 (gears 1-2) or 2 (gears 3-4).", min=1)
    ] = 1,
    power: Annotated[
        str | None,
        typer.Option(
            help="Power through the pair at the design's input speed on the "
            "external gear, e.g. '3 kW'."
        ),
    ] = None,
    torque: Annotated[
        str | None, typer.Option(help="Torque on the external gear, e.g. '19.1 N*m'.")
    ] = None,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "contact-output"
    ),
    positions: Annotated[
        int, typer.Option(help="Mesh positions over one mesh cycle.", min=2, max=400)
    ] = 24,
    order: Annotated[
        int, typer.Option(help="Harmonics of the Fourier fit (paper 000 Eq. 8).", min=0)
    ] = 7,
    profile: Annotated[
        ProfileChoice | None, typer.Option(help="Override the design's surface.profile.")
    ] = None,
    cell: Annotated[
        str | None,
        typer.Option(help="Contact cell size, e.g. '0.05 mm' (default: from a pilot run)."),
    ] = None,
    tooth_size: Annotated[
        str | None,
        typer.Option(help="Element size of the finite-element tooth models (default 0.3 m_n)."),
    ] = None,
    axial_external: Annotated[
        str | None, typer.Option(help="Misalignment: external gear moved along its axis.")
    ] = None,
    axial_internal: Annotated[
        str | None, typer.Option(help="Misalignment: internal gear moved along its axis.")
    ] = None,
    offset: Annotated[
        str | None, typer.Option(help="Misalignment: offset of the internal gear's axis.")
    ] = None,
    shaft_angle: Annotated[
        str | None, typer.Option(help="Misalignment: shaft angle error, e.g. '0.05 deg'.")
    ] = None,
    rigid: Annotated[
        bool,
        typer.Option(
            help="Rigid teeth (half-space contact only): a quick contact pattern; "
            "the mesh stiffness is then far too high."
        ),
    ] = False,
    write_design: Annotated[
        Path | None,
        typer.Option(
            help="Also write a copy of the design whose [meshN] table holds the "
            "fitted k_m, harmonics and phases (paper 000 Eq. 8)."
        ),
    ] = None,
    sets: SetOption = None,
) -> None:
    """Loaded tooth contact analysis of a gear pair over one mesh cycle (papers 001, 000
    §2.3): contact pattern and pressure, transmission error, contact force, subsurface
    stress, mesh stiffness k(t) and its Fourier series; netCDF, JSON, table, figures."""
    from .analysis.contact import contact_analysis, design_with_mesh
    from .contact.flanks import Misalignment
    from .drives import load_design

    with _user_errors():
        files = OutputSet(output, "-o", report=_note)
        d = load_design(design, sets or ())
        P = _quantity_option(power, "--power", "power")
        T = _quantity_option(torque, "--torque", "torque")
        if (P is None) == (T is None):
            raise ReducerlabError("--power/--torque: give exactly one of them")
        h = _quantity_option(cell, "--cell", "length")
        ts = _quantity_option(tooth_size, "--tooth-size", "length")
        mis = {}
        for text, option, kind, name in (
            (axial_external, "--axial-external", "length", "axial_a"),
            (axial_internal, "--axial-internal", "length", "axial_b"),
            (offset, "--offset", "length", "offset"),
            (shaft_angle, "--shaft-angle", "angle", "shaft_angle"),
        ):
            if text is not None:
                mis[name] = _signed_quantity(text, option, kind)
        if write_design is not None and write_design.resolve() == design.resolve():
            raise ReducerlabError("--write-design: must not overwrite the design file itself")
        with _progress() as progress:
            task = progress.add_task("contact analysis", total=None)
            res = contact_analysis(
                d, pair, power=P, torque=T, positions=positions, order=order, cell=h,
                profile=None if profile is None else profile.value,
                misalignment=Misalignment(**mis) if mis else None, tooth_size=ts,
                rigid=rigid, stage=lambda text: progress.update(task, description=text),
                progress=lambda done, total: progress.update(
                    task, completed=done, total=total,
                    description=f"loaded contact, position {done}/{total}",
                ),
            )  # fmt: skip
            progress.update(task, description="writing results")
            with files:
                res.save(files.path("contact.nc"))
                _write_json(res, files.path("contact.json"))
                files.path("contact.txt").write_text(res.table() + "\n")
                _savefig(res.figure(), files.path("contact.png"), res.data.attrs)
                from .plot.contact import plot_pressure_map

                _savefig(plot_pressure_map(res), files.path("pressure.png"), res.data.attrs)
        if write_design is not None:
            text = design_with_mesh(design, res)
            _write_file(write_design, lambda tmp: tmp.write_text(text))
    typer.echo(res.table())


def _signed_quantity(text: str, option: str, kind: str) -> float:
    """A finite quantity of ``kind`` that may be negative or zero (SI)."""
    t = text.strip()
    sign = -1.0 if t.startswith("-") else 1.0
    body = t[1:] if t[:1] in "+-" else t
    try:
        value = float(body)
    except ValueError:
        value = _quantity_option(body, option, kind) or 0.0
    if not math.isfinite(value):
        raise ReducerlabError(f"{option}: must be finite; got {text!r}")
    return sign * value


@app.command("report")
def report_cmd(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="Report file (.html); default DESIGN-report.html."),
    ] = None,
    section: Annotated[
        list[str] | None,
        typer.Option("--section", "-s", help="Build only these sections (repeatable)."),
    ] = None,
    given: Annotated[
        list[Path] | None,
        typer.Option(
            "--with",
            help="A result computed before (body_modal.nc, contact.nc, bifurcation.nc, "
            "regime_map.nc) to include (repeatable).",
        ),
    ] = None,
    sets: SetOption = None,
) -> None:
    """One self-contained HTML report of everything reducerlab can say about a design
    (exit 1 when a section failed: its error is shown in its place in the report)."""
    from .reporting import report as build_report

    with _user_errors():
        path = output if output is not None else Path(f"{design.stem}-report.html")
        prepare_output_file(path, "-o", (".html", ".htm"))
        with _progress() as progress:
            task = progress.add_task("report", total=None)

            def step(title: str, done: int, total: int) -> None:
                progress.update(task, description=title, completed=done, total=total)

            rep = build_report(design, overrides=sets or (), results=given or (),
                               only=section, progress=step)  # fmt: skip
        _write_file(path, rep.write)
    for s in rep.sections:
        status = f"FAILED: {s.error}" if s.error else "ok"
        typer.echo(f"  {s.title:<45} {s.seconds:7.2f} s  {status}")
    typer.echo(f"report: {path.resolve()} ({rep.seconds:.1f} s)")
    if rep.failed:
        raise typer.Exit(1)


@app.command()
def demo(
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "demo-output"
    ),
) -> None:
    """Write the design report of every bundled example and an index.html linking them."""
    from .examples import example_files
    from .reporting import report as build_report
    from .reporting import write_index

    with _user_errors():
        prepare_output_dir(output)
    examples = example_files()
    if not examples:
        _fail(ReducerlabError("no bundled examples found"))
    done = []
    with _progress() as progress:
        task = progress.add_task("examples", total=len(examples))
        for path in examples:
            progress.update(task, description=path.name)
            with _user_errors():
                rep = build_report(path)
                file = rep.write(output / f"{path.stem}.html")
            done.append((file, rep))
            progress.advance(task)
    with _user_errors():
        index = write_index(done, output / "index.html")
    for file, rep in done:
        failed = f", {len(rep.failed)} section(s) FAILED" if rep.failed else ""
        out.print(Text.assemble((file.name, "bold"), f"  {len(rep.sections)} sections, "
                                f"{rep.seconds:.1f} s{failed}"))  # fmt: skip
    out.print(f"open {index.resolve()}")


class _Terminated(SystemExit):
    """SIGTERM, raised in the main thread so that every ``finally`` runs: worker pools
    end their processes, staged outputs are discarded, finished chunks stay."""


def _on_sigterm(signum: int, frame: Any) -> None:
    import signal

    signal.signal(signal.SIGTERM, signal.SIG_IGN)  # one clean shutdown, not nested ones
    raise _Terminated(128 + signum)


def _termination(exc: BaseException) -> _Terminated | None:
    """The SIGTERM behind ``exc``, if any: raised inside compiled code (the numba
    kernel), it surfaces as the context of another error (``SystemError``)."""
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, _Terminated):
            return e
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return None


def main() -> None:
    """Console-script entry point.

    SIGTERM ends the command like Ctrl-C does (exit code 143): worker processes are
    stopped, no partial output set is left, and a sweep or bifurcation resumes from its
    finished chunks when run again.
    """
    import signal

    signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        app()
    except KeyboardInterrupt:  # pragma: no cover - interactive
        err.print("interrupted")
        sys.exit(130)
    except BaseException as exc:
        term = _termination(exc)
        if term is None:
            raise
        err.print(
            "terminated (SIGTERM); a sweep or bifurcation resumes from its finished chunks "
            "when run again"
        )
        sys.exit(term.code)
