"""``reducerlab surface``: a gear's generated tooth surfaces (paper 001), checked and
exported as a closed solid."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from ..io import prepare_output_file
from .options import GearOption, ProfileChoice, SetOption
from .output import progress_bar, savefig, user_errors, write_file


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

    from ..drives import load_design
    from ..geometry import generate_tooth
    from ..geometry.export import MESH_FORMATS, export_mesh, export_point_cloud
    from ..geometry.solid import build_gear_solid, section_counts

    with user_errors():
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
        # a nutation design without a [surface] table is refused by tooth_generation
        if not d.has_tooth_surfaces and d.type != "nutation":
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
        with progress_bar() as progress:
            task = progress.add_task("tooth surfaces", total=None)
            tooth_surface = generate_tooth(crown, bevel, points, points)
            progress.update(task, description="sections and blank")
            solid = build_gear_solid(
                crown,
                bevel,
                **section_counts(points),
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
                write_file(export, lambda tmp: export_mesh(mesh, tmp))
            if cloud is not None:
                pts, nrm = solid.flank_cloud()
                write_file(cloud, lambda tmp: export_point_cloud(pts, nrm, tmp))
            if png is not None:
                from ..plot.surface import plot_tooth

                write_file(
                    png,
                    lambda tmp: savefig(plot_tooth(solid), tmp, d.provenance, 130),
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


def register(app: typer.Typer) -> None:
    """Add ``surface`` to the command line."""
    app.command()(surface)
