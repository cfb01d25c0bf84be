"""Command line: ``reducerlab modal``, ``sensitivity``, ``kinematics``, ``sweep``,
``campbell``, ``check``, ``surface``, ``demo``.

Errors caused by the user's input are printed as one clear message (exit code 2),
never as a traceback.
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from enum import StrEnum
from pathlib import Path
from typing import Annotated, NoReturn

import typer
from rich.console import Console
from rich.table import Table

from . import __version__
from .errors import ReducerlabError

app = typer.Typer(
    name="reducerlab",
    help="Design and dynamic analysis of compact high-ratio gear reducers.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
out = Console()
err = Console(stderr=True)


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


def _fail(exc: Exception) -> NoReturn:
    err.print(f"[bold red]error:[/] {exc}", highlight=False, markup=True, soft_wrap=True)
    raise typer.Exit(code=2)


@contextmanager
def _user_errors() -> Iterator[None]:
    """Print an error caused by the user's input (or an unwritable output) as one line
    and exit with code 2, without a traceback."""
    try:
        yield
    except (ReducerlabError, OSError) as exc:
        _fail(exc)


def _save_with_figure(result, outdir: Path, stem: str) -> tuple[Path, Path]:
    """Save ``STEM.nc`` and the result's figure ``STEM.png`` into ``outdir``."""
    outdir.mkdir(parents=True, exist_ok=True)
    nc, png = outdir / f"{stem}.nc", outdir / f"{stem}.png"
    result.save(nc)
    result.plot().savefig(png, dpi=120)
    return nc, png


def _model_from(design_path: Path):
    from .drives import build_model, load_design

    design = load_design(design_path)
    return design, build_model(design)


def _write_modal(result, outdir: Path) -> list[Path]:
    outdir.mkdir(parents=True, exist_ok=True)
    written = [result.save(outdir / "modal.nc")]
    (outdir / "modal.json").write_text(result.to_json())
    (outdir / "modal.txt").write_text(result.table() + "\n")
    written += [outdir / "modal.json", outdir / "modal.txt"]
    for name, fig in (
        ("mode_shapes.png", result.plot_shapes()),
        ("energy.png", result.plot_energy()),
    ):
        fig.savefig(outdir / name, dpi=120)
        written.append(outdir / name)
    return written


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
        float, typer.Option(help="Relative eigenvalue below which a mode is rigid (0 Hz).")
    ] = 1e-10,
) -> None:
    """Natural frequencies, mode shapes and energy classification of a design."""
    from .analysis.modal import modal as run_modal

    with _user_errors():
        _, model = _model_from(design)
        result = run_modal(model, rigid_tol=rigid_tol)
        written = _write_modal(result, output) if output is not None else []
    if fmt is Format.json:
        typer.echo(result.to_json())
    else:
        _print_modal(result)
    for p in written:
        err.print(f"wrote {p}", highlight=False)


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
) -> None:
    """Sensitivity of every natural frequency to model parameters (analytic)."""
    from .analysis.modal import frequency_sensitivity
    from .model.inspect import parameter_paths

    with _user_errors():
        _, model = _model_from(design)
        if list_params:
            for path, value in parameter_paths(model):
                typer.echo(f"{path} = {value:.6g}")
            return
        params = param or [p for p, _ in parameter_paths(model)]
        res = frequency_sensitivity(model, params)
        if output is not None:
            nc, png = _save_with_figure(res, output, "sensitivity")
            err.print(f"wrote {nc}, {png}")
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


def _write_kinematics(result, outdir: Path) -> list[Path]:
    outdir.mkdir(parents=True, exist_ok=True)
    written = [result.save(outdir / "kinematics.nc")]
    (outdir / "kinematics.json").write_text(result.to_json())
    written.append(outdir / "kinematics.json")
    if "omega" in result.data:
        result.plot().savefig(outdir / "angular_velocity.png", dpi=120)
        written.append(outdir / "angular_velocity.png")
    return written


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
) -> None:
    """Transmission ratio, member speeds, mesh frequencies and cone angles of a drive."""
    from .drives import load_design

    with _user_errors():
        result = _run_kinematics(load_design(design))
        written = _write_kinematics(result, output) if output is not None else []
    typer.echo(result.to_json() if fmt is Format.json else result.table())
    for p in written:
        err.print(f"wrote {p}", highlight=False)


def _parse_speeds(spec: str | None) -> list[float] | None:
    """``lin:START:STOP:N`` in rpm, or a comma list in rpm."""
    if spec is None:
        return None
    import numpy as np

    from .analysis.sweep import parse_values

    axis = parse_values("speeds", spec)
    if axis.relative or any(isinstance(v, str) for v in axis.values):
        raise ReducerlabError("--speeds takes plain numbers in rpm, e.g. lin:0:3000:301")
    return (np.asarray(axis.values, dtype=float) * 2 * np.pi / 60).tolist()


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
    chunk_size: Annotated[int, typer.Option(help="Points per chunk.")] = 2000,
    workers: Annotated[
        int | None, typer.Option(help="Worker processes (default: all cores).")
    ] = None,
    scheduler: Annotated[
        str | None, typer.Option(help="Dask scheduler address, e.g. tcp://HOST:8786.")
    ] = None,
    fmt: Annotated[Format, typer.Option("--format", help="Output on stdout.")] = Format.table,
) -> None:
    """Natural frequencies over a parameter (tracked modes, veerings) or a grid of two."""
    from rich.progress import Progress

    from .analysis.sweep import parse_values
    from .analysis.sweep import sweep as run_sweep
    from .drives import load_design

    with _user_errors():
        d = load_design(design)
        axes = [parse_values(param, values)]
        if grid is not None:
            if "=" not in grid:
                raise ReducerlabError(
                    "--grid must be 'PATH=VALUES', e.g. 'mesh.damping=lin:0:1e3:11'"
                )
            p2, v2 = grid.split("=", 1)
            axes.append(parse_values(p2.strip(), v2.strip()))
        with Progress(console=err, transient=True) as progress:
            task = progress.add_task("sweep chunks", total=None)

            def report(done: int, total: int) -> None:
                progress.update(task, completed=done, total=total)

            result = run_sweep(
                d,
                axes,
                output=output,
                chunk_size=chunk_size,
                workers=workers,
                scheduler=scheduler,
                progress=report,
            )
        fig = result.plot()
        fig.savefig(output / "sweep.png", dpi=120)
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
    err.print(f"wrote {output / 'sweep.nc'}, {output / 'sweep.png'}", highlight=False)


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
) -> None:
    """Campbell diagram: natural frequencies and excitation lines against input speed."""
    from .analysis.campbell import campbell as run_campbell
    from .drives import load_design

    with _user_errors():
        res = run_campbell(load_design(design), _parse_speeds(speeds))
        if output is not None:
            nc, png = _save_with_figure(res, output, "campbell")
            err.print(f"wrote {nc}, {png}")
    typer.echo(json.dumps({"crossings": res.crossings()}) if fmt is Format.json else res.table())


@app.command()
def check(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
    margin: Annotated[
        float, typer.Option(help="Relative distance to an excitation that counts (0.10 = 10 %).")
    ] = 0.10,
    speed_range: Annotated[
        str | None, typer.Option(help="Operating range in rpm 'MIN,MAX' (default: design's).")
    ] = None,
    fmt: Annotated[Format, typer.Option("--format", help="Output on stdout.")] = Format.table,
) -> None:
    """Resonance verdict: exits 1 when a natural frequency meets an excitation."""
    from .analysis.campbell import format_check, resonance_check
    from .drives import load_design

    with _user_errors():
        rng = None
        if speed_range is not None:
            parts = _parse_speeds(speed_range)
            if parts is None or len(parts) != 2:
                raise ReducerlabError("--speed-range must be 'MIN,MAX' in rpm")
            rng = (parts[0], parts[1])
        report = resonance_check(load_design(design), margin=margin, speed_range=rng)
    typer.echo(json.dumps(report, indent=2) if fmt is Format.json else format_check(report))
    if not report["ok"]:
        raise typer.Exit(code=1)


@app.command()
def bifurcation(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
    param: Annotated[str, typer.Option("--param", "-p", help="Parameter path.")],
    values: Annotated[
        str, typer.Option("--values", "-v", help="'lin:START:STOP:N', a list, or 'rel:...'.")
    ],
    periods: Annotated[int, typer.Option(help="Mesh periods integrated.")] = 600,
    keep: Annotated[int, typer.Option(help="Last periods kept as Poincaré points.")] = 100,
    steps: Annotated[
        int | None, typer.Option(help="RK4 steps per period (default: from the model).")
    ] = None,
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Output folder (resumable).")
    ] = Path("bifurcation-output"),
    scheduler: Annotated[
        str | None, typer.Option(help="Dask scheduler address, e.g. tcp://HOST:8786.")
    ] = None,
    classify: Annotated[
        bool, typer.Option(help="Lyapunov exponents and motion classes (slower).")
    ] = False,
    workers: Annotated[
        int | None,
        typer.Option(help="Processes building the models (default: one per core).", min=1),
    ] = None,
) -> None:
    """Bifurcation diagram: Poincaré points of the mesh deflection against a parameter."""
    from rich.progress import Progress

    from .analysis.nonlinear import bifurcation as run_bifurcation
    from .analysis.sweep import parse_values
    from .drives import load_design

    with _user_errors():
        d = load_design(design)
        axis = parse_values(param, values)
        with Progress(console=err, transient=True) as progress:
            task = progress.add_task("bifurcation", total=None)
            res = run_bifurcation(
                d, axis, periods=periods, keep=keep, steps_per_period=steps,
                output=output, scheduler=scheduler, exponents=classify, workers=workers,
                progress=lambda done, total: progress.update(task, completed=done, total=total),
            )  # fmt: skip
        nc, png = _save_with_figure(res, output, "bifurcation")
    summary = res.to_dict()
    if classify:
        summary["motion"] = res.labels()
    typer.echo(json.dumps(summary))
    err.print(f"wrote {nc}, {png}", highlight=False)


@app.command()
def response(
    design: Annotated[Path, typer.Argument(help="Design file (TOML).")],
    periods: Annotated[int, typer.Option(help="Forcing periods integrated.")] = 600,
    keep: Annotated[int, typer.Option(help="Poincaré points kept.")] = 100,
    history: Annotated[int, typer.Option(help="Periods of time history kept.")] = 20,
    steps: Annotated[int | None, typer.Option(help="RK4 steps per period.")] = None,
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "response-output"
    ),
) -> None:
    """Steady nonlinear response: phase trajectory, Poincaré map, spectrum, load factor."""
    from .analysis.nonlinear import response as run_response
    from .drives import load_design

    with _user_errors():
        res = run_response(
            load_design(design), periods=periods, keep=keep, history=history,
            steps_per_period=steps,
        )  # fmt: skip
        nc, png = _save_with_figure(res, output, "response")
    peaks = ", ".join(f"{m:.3g}x" for m, _ in res.peaks(5))
    typer.echo(
        f"dynamic load factor {res.data.attrs['dynamic_load_factor']:.4f}, mean mesh force "
        f"{res.data.attrs['mean_mesh_force']:.5g} N; spectral peaks at {peaks} the forcing "
        "frequency"
    )
    err.print(f"wrote {nc}, {png}", highlight=False)


class ProfileChoice(StrEnum):
    involute = "involute"
    double_arc = "double-arc"


@app.command()
def surface(
    design: Annotated[Path, typer.Argument(help="Nutation design file (TOML), surface table")],
    gear: Annotated[
        int,
        typer.Option("--gear", "-g", help="Gear number: 1, 3 nutating (internal); 2, 4 external."),
    ] = 1,
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
) -> None:
    """Generate a gear's tooth surfaces (paper 001), check them, export a closed solid."""
    import numpy as np
    from rich.progress import Progress

    from .drives import load_design
    from .geometry import generate_tooth
    from .geometry.export import MESH_FORMATS, export_mesh, export_point_cloud
    from .geometry.solid import build_gear_solid

    with _user_errors():
        if not 3 <= points <= 401:
            raise ReducerlabError(f"--points: must be an integer in [3, 401]; got {points}")
        if export is not None and export.suffix.lower() not in MESH_FORMATS:
            raise ReducerlabError(
                f"--export: unknown file type {export.suffix or '(none)'!r} in {export}; "
                f"use one of {', '.join(MESH_FORMATS)}"
            )
        if png is not None and png.suffix.lower() != ".png":
            raise ReducerlabError(f"--png: must name a .png file; got {png}")
        if cloud is not None and cloud.suffix.lower() != ".ply":
            raise ReducerlabError(f"--cloud: must name a .ply file; got {cloud}")
        d = load_design(design)
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
        with Progress(console=err, transient=True) as progress:
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
            written = []
            if export is not None:
                progress.update(task, description=f"writing {export.name}", total=None)
                written.append(export_mesh(mesh, export))
            if cloud is not None:
                fl = solid.flank_points()
                pts = [fl["A"][0], fl["B"][0]]
                nrm = [fl["A"][1], fl["B"][1]]
                written.append(export_point_cloud(
                    np.concatenate(pts), np.concatenate(nrm), cloud
                ))  # fmt: skip
            if png is not None:
                from .plot.surface import plot_tooth

                png.parent.mkdir(parents=True, exist_ok=True)
                plot_tooth(solid).savefig(png, dpi=130)
                written.append(png)
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
    for p in written:
        err.print(f"wrote {p}", highlight=False)


khv_app = typer.Typer(help="KHV planetary drive tools (paper 004).", no_args_is_help=True)
app.add_typer(khv_app, name="khv")


@khv_app.command("closed-graph")
def khv_closed_graph(
    design: Annotated[Path, typer.Argument(help="KHV design file (TOML).")],
    output: Annotated[Path, typer.Option("--output", "-o", help="Figure file (PNG).")] = Path(
        "closed-graph.png"
    ),
) -> None:
    """Draw the closed graph (x1 vs x2, limit lines, feasible region) and mark the design."""
    from .design import read_toml, validate_design
    from .drives.khv import Gears
    from .plot.khv import plot_closed_graph

    with _user_errors():
        data = read_toml(design)
        if data.get("type") != "khv":
            raise ReducerlabError(f"{design}: type = {data.get('type')!r}: not a KHV design")
        gears = validate_design(Gears, data.get("gears", {}), f"{design}: gears")
        pair = gears.pair()
        fig = plot_closed_graph(pair, gears.shift_line if gears.x2 is None else None)
        output.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(output, dpi=120)
    for c in pair.conditions():
        flag = "ok  " if c.ok else "FAIL"
        typer.echo(f"{flag} {c.name:<28} margin {c.margin:+.4g}   ({c.rule})")
    typer.echo(f"contact ratio {pair.contact_ratio:.4f}, working pressure angle "
               f"{math.degrees(pair.working_pressure_angle):.3f} deg")  # fmt: skip
    err.print(f"wrote {output}", highlight=False)


@khv_app.command("stiffness")
def khv_stiffness(
    design: Annotated[Path, typer.Argument(help="KHV design file (TOML).")],
    x1: Annotated[
        str, typer.Option(help="Planet shift coefficients to compare, comma separated.")
    ] = "0.416,0.626,0.835",
    output: Annotated[Path, typer.Option("--output", "-o", help="Figure file (PNG).")] = Path(
        "mesh-stiffness.png"
    ),
) -> None:
    """Time-varying mesh stiffness for several x1 on the design's shift line (Fig. 5)."""
    from .drives import design_from_dict, load_design
    from .plot.khv import plot_mesh_stiffness

    with _user_errors():
        d = load_design(design)
        if d.type != "khv":
            raise ReducerlabError(f"{design}: type = {d.type!r}: not a KHV design")
        try:
            values = [float(v) for v in x1.split(",") if v.strip()]
        except ValueError:
            raise ReducerlabError(f"--x1: {x1!r} is not a list of numbers") from None
        if not values:
            raise ReducerlabError("--x1: give at least one value")
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
        output.parent.mkdir(parents=True, exist_ok=True)
        plot_mesh_stiffness(laws).savefig(output, dpi=120)
    err.print(f"wrote {output}", highlight=False)


@app.command()
def demo(
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "demo-output"
    ),
) -> None:
    """Run every bundled example end to end and write its outputs."""
    from rich.progress import Progress

    from .analysis.campbell import campbell as run_campbell
    from .analysis.modal import modal as run_modal
    from .drives import build_model, has_model, load_design
    from .examples import example_files

    files = example_files()
    if not files:
        _fail(ReducerlabError("no bundled examples found"))
    summary = []
    with Progress(console=err, transient=True) as progress:
        task = progress.add_task("examples", total=len(files))
        for path in files:
            progress.update(task, description=f"{path.name}")
            with _user_errors():
                design = load_design(path)
                outdir = output / path.stem
                res_m = res_k = None
                if has_model(design):
                    res_m = run_modal(build_model(design))
                    _write_modal(res_m, outdir)
                    _save_with_figure(run_campbell(design), outdir, "campbell")
                if hasattr(design, "kinematics"):
                    res_k = _run_kinematics(design)
                    _write_kinematics(res_k, outdir)
            summary.append((path, res_m, res_k))
            progress.advance(task)
    for path, res_m, res_k in summary:
        out.print(f"[bold]{path.name}[/]  ->  {output / path.stem}")
        if res_k is not None:
            out.print(res_k.table(), highlight=False)
        if res_m is not None:
            _print_modal(res_m)
    out.print(f"demo outputs in {output.resolve()}")


def main() -> None:
    """Console-script entry point."""
    try:
        app()
    except KeyboardInterrupt:  # pragma: no cover - interactive
        err.print("interrupted")
        sys.exit(130)
