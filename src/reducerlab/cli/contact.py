"""``reducerlab contact``: loaded tooth contact analysis of a gear pair (papers 001,
000 §2.3)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from ..io import atomic_path, prepare_output_file
from ..numformat import fmt
from .options import ProfileChoice, SetOption, quantity_option, signed_quantity
from .output import (
    add_result,
    output_set,
    position_callbacks,
    progress_bar,
    savefig,
    user_errors,
    write_file,
    write_json,
)


def contact(
    design: Annotated[
        Path,
        typer.Argument(
            help="Nutation design file (TOML) with [surface], a gear_pair design with "
            "mesh.face_width, or a khv design (its internal pair)"
        ),
    ],
    pair: Annotated[
        int, typer.Option("--pair", help="Gear pair: 1 (gears 1-2) or 2 (gears 3-4).", min=1)
    ] = 1,
    power: Annotated[
        str | None,
        typer.Option(
            help="Power through the pair at the design's input speed on the "
            "external gear, e.g. '3 kW'. Without --power and --torque: the torque flow's "
            "torque on the external gear at the design's load (output_torque/output_power)."
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
    workers: Annotated[
        int | None,
        typer.Option(
            help="Processes: the two gears' tooth models at once and the positions in "
            "chunks (default 2 on two cores or more, 1 with --rigid; 1: one process).",
            min=1,
            max=64,
        ),
    ] = None,
    write_design: Annotated[
        Path | None,
        typer.Option(
            help="Also write a copy of the design whose [meshN] table (a khv design's "
            "[mesh]) holds the fitted k_m, harmonics and phases (paper 000 Eq. 8)."
        ),
    ] = None,
    root_stress: Annotated[
        bool,
        typer.Option(
            "--root-stress",
            help="Also the tooth-root stress of both gears at every position (from the "
            "finite-element tooth models); prints the peak and where it is.",
        ),
    ] = False,
    sweep: Annotated[
        int | None,
        typer.Option(
            "--sweep",
            help="Loaded TE against torque: this many torques from 0 to --top times the "
            "load (one tooth-compliance build; te_sweep.nc/.json/.txt/.png).",
            min=2,
            max=41,
        ),
    ] = None,
    top: Annotated[
        float, typer.Option(help="--sweep: largest torque over the load.", min=0.01, max=3.0)
    ] = 1.5,
    harmonics: Annotated[
        int, typer.Option(help="--sweep: mesh orders of the TE reported.", min=1, max=20)
    ] = 3,
    layout: Annotated[
        bool,
        typer.Option(
            "--layout",
            help="Propose lead crowning and tip relief at the load: least TE peak-to-peak "
            "with the peak pressure at most --pressure-limit and no edge contact "
            "(layout.nc/.json/.txt/.png; one tooth-compliance build; 17 candidates of "
            "--positions each: 12 positions take half the time of the default 24).",
        ),
    ] = False,
    pressure_limit: Annotated[
        str, typer.Option(help="--layout: largest contact pressure, e.g. '1500 MPa'.")
    ] = "1500 MPa",
    sets: SetOption = None,
) -> None:
    """Loaded tooth contact analysis of a gear pair over one mesh cycle (papers 001, 000
    §2.3): contact pattern and pressure, transmission error, contact force, subsurface
    stress, mesh stiffness k(t) and its Fourier series; netCDF, JSON, table, figures."""
    from ..analysis.contact import contact_analysis, design_with_mesh
    from ..analysis.contact_rootstress import root_stress_lines
    from ..contact.flanks import Misalignment
    from ..drives import load_design

    with user_errors():
        files = output_set(output)
        d = load_design(design, sets or ())
        if sweep is not None or layout:
            what = "--sweep" if sweep is not None else "--layout"
            clash = ((rigid, "--rigid"), (write_design, "--write-design"), (workers, "--workers"),
                     (layout and sweep, "--layout"), (root_stress, "--root-stress"))  # fmt: skip
            for given, option in clash:
                if given:
                    raise ReducerlabError(f"{option}: not with {what} (one process, elastic)")
        P = quantity_option(power, "--power", "power")
        T = quantity_option(torque, "--torque", "torque")
        if P is not None and T is not None:
            raise ReducerlabError("--power/--torque: give exactly one of them")
        if P is None and T is None:
            T = _design_torque(d, pair)
        h = quantity_option(cell, "--cell", "length")
        ts = quantity_option(tooth_size, "--tooth-size", "length")
        mis = {}
        for text, option, kind, name in (
            (axial_external, "--axial-external", "length", "axial_a"),
            (axial_internal, "--axial-internal", "length", "axial_b"),
            (offset, "--offset", "length", "offset"),
            (shaft_angle, "--shaft-angle", "angle", "shaft_angle"),
        ):
            if text is not None:
                mis[name] = signed_quantity(text, option, kind)
        if write_design is not None and write_design.resolve() == design.resolve():
            raise ReducerlabError("--write-design: must not overwrite the design file itself")
        if write_design is not None:  # before the analysis, not after it
            prepare_output_file(write_design, "--write-design", (".toml",))
        misalignment = Misalignment(**mis) if mis else None
        if layout:
            if mis or profile is not None:
                raise ReducerlabError("--layout: the design's own profile, no misalignment")
            p_lim = quantity_option(pressure_limit, "--pressure-limit", "pressure")
            _layout(d, pair, T if P is None else None, P, positions, h, ts, p_lim, files)
            return
        if sweep is not None:
            opts = dict(loads=sweep, top=top, harmonics=harmonics, positions=positions,
                        cell=h, tooth_size=ts, misalignment=misalignment,
                        profile=None if profile is None else profile.value)  # fmt: skip
            _te_sweep(d, pair, P, T, opts, files)
            return
        with progress_bar() as progress:
            task = progress.add_task("contact analysis", total=None)
            res = contact_analysis(
                d, pair, power=P, torque=T, positions=positions, order=order, cell=h,
                profile=None if profile is None else profile.value,
                misalignment=misalignment, tooth_size=ts,
                rigid=rigid, workers=workers, root_stress=root_stress,
                stage=lambda text: progress.update(task, description=text),
                progress=lambda done, total: progress.update(
                    task, completed=done, total=total,
                    description=f"loaded contact, position {done}/{total}",
                ),
            )  # fmt: skip
            progress.update(task, description="writing results")
            with files:
                res.save(files.path("contact.nc"))
                write_json(res, files.path("contact.json"))
                lines = root_stress_lines(res.data)
                files.path("contact.txt").write_text("\n".join([res.table(), *lines]) + "\n")
                savefig(res.figure(), files.path("contact.png"), res.data.attrs)
                from ..plot.contact import plot_pressure_map
                from ..plot.contact_pattern import plot_bearing_pattern

                savefig(plot_pressure_map(res), files.path("pressure.png"), res.data.attrs)
                savefig(plot_bearing_pattern(res), files.path("pattern.png"), res.data.attrs)
        if write_design is not None:
            text = design_with_mesh(design, res)
            write_file(write_design, lambda tmp: tmp.write_text(text))
    typer.echo(res.table())
    for line in root_stress_lines(res.data):
        typer.echo(line)


def _te_sweep(d, pair: int, P, T, opts: dict, files) -> None:
    """``--sweep``: loaded TE against torque (``analysis.te_sweep``); the positions done
    so far are written to ``te_sweep.partial.txt`` as they come (about every eighth of
    the positions), removed when the results are in place."""
    from ..analysis.te_sweep import te_sweep

    partial = files.directory / "te_sweep.partial.txt"

    def write_partial(res) -> None:
        files.directory.mkdir(parents=True, exist_ok=True)
        done = res.data.attrs["positions_done"]
        text = f"# partial: {done} of {res.data.sizes['position']} positions\n" + res.table()
        with atomic_path(partial) as tmp:  # quietly: rewritten after each chunk
            tmp.write_text(text + "\n")

    with progress_bar() as progress:
        task = progress.add_task("te sweep", total=None)
        res = te_sweep(
            d, pair, power=P, torque=T, **opts, partial=write_partial,
            **position_callbacks(
                progress, task, "loaded contact, position {done}/{total} (all torques)"
            ),
        )  # fmt: skip
        progress.update(task, description="writing results")
        with files:
            add_result(res, files, "te_sweep")
    partial.unlink(missing_ok=True)
    typer.echo(res.table())


def _layout(d, pair: int, T, P, positions: int, h, ts, p_lim, files) -> None:
    """``--layout``: the flank modification layout (``analysis.layout``)."""
    from ..analysis.layout import modification_layout

    with progress_bar() as progress:
        task = progress.add_task("layout", total=None)
        res = modification_layout(
            d, pair, torque=T, power=P, positions=positions, cell=h,
            tooth_size=ts, pressure_limit=p_lim,
            stage=lambda text: progress.update(task, description=text),
            progress=lambda done, total: progress.update(
                task, completed=done, total=total, description=f"candidate {done}/{total}"
            ),
        )  # fmt: skip
        progress.update(task, description="writing results")
        with files:
            add_result(res, files, "layout")
    typer.echo(res.table())


def _design_torque(design, pair: int) -> float:
    """The torque flow's torque on pair ``pair``'s external gear at the design's load
    (a gear_pair: its ``[operating]`` torque or power, on the pinion)."""
    from ..analysis.te_sweep import design_load
    from ..analysis.torque_flow import torque_flow
    from ..drives.gear_pair import GearPairDesign

    if isinstance(design, GearPairDesign) or getattr(design, "type", None) == "khv":
        torque = design_load(design, pair)
        gear = "pinion" if isinstance(design, GearPairDesign) else "planet"
        typer.echo(f"torque on the {gear} from the design's load: {fmt(torque, 'torque')} N m")
        return torque

    flow = torque_flow(design)
    mesh = flow.meshes.get(f"mesh{pair}")
    if mesh is None:
        raise ReducerlabError(f"pair: must be 1..{len(flow.meshes)}; got {pair}")
    if not flow.output_torque or mesh.external_torque is None:
        raise ReducerlabError(
            "--power/--torque: give exactly one of them, or a load in the design "
            "(output_torque or output_power) for the torque flow to load the pair"
        )
    typer.echo(
        f"torque on {mesh.external} (pair {pair}) from the torque flow at "
        f"{fmt(flow.output_torque, 'torque')} N m output torque: "
        f"{fmt(mesh.external_torque, 'torque')} N m"
    )
    return mesh.external_torque


def register(app: typer.Typer) -> None:
    """Add ``contact`` to the command line."""
    app.command()(contact)
