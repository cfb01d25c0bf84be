"""``reducerlab khv``: tools of the KHV planetary drive (paper 004): the closed graph of
the shift coefficients, the mesh stiffness along the shift line, the tooth pairs'
clearances and the load sharing against torque (issue 30)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from ..numformat import Column, Table, fmt
from .options import SetOption, quantity_option
from .output import (
    add_result,
    output_set,
    position_callbacks,
    progress_bar,
    savefig,
    user_errors,
)

khv_app = typer.Typer(
    help="KHV planetary drive tools (paper 004).", no_args_is_help=True, rich_markup_mode=None
)
"""The ``khv`` command group."""


@khv_app.command("closed-graph")
def khv_closed_graph(
    design: Annotated[Path, typer.Argument(help="KHV design file (TOML).")],
    output: Annotated[
        Path, typer.Option("--output", "-o", help="Output folder (writes closed-graph.png).")
    ] = Path("."),
    sets: SetOption = None,
) -> None:
    """Draw the closed graph (x1 vs x2, limit lines, feasible region) and mark the design."""
    from ..design_files import apply_overrides, read_toml, validate_design
    from ..drives.khv import Gears
    from ..plot.khv import plot_closed_graph

    with user_errors():
        files = output_set(output)
        data = apply_overrides(read_toml(design), sets or ())
        if data.get("type") != "khv":
            raise ReducerlabError(f"{design}: type = {data.get('type')!r}: not a KHV design")
        gears = validate_design(Gears, data.get("gears", {}), f"{design}: gears")
        pair = gears.pair()
        fig = plot_closed_graph(pair, gears.shift_line if gears.x2 is None else None)
        with files:
            savefig(fig, files.path("closed-graph.png"), {"design": json.dumps(data, default=str)})
    t = Table([Column("", kind="text"), Column("condition", kind="text"), Column("margin"),
               Column("rule", kind="text")])  # fmt: skip
    for c in pair.conditions():
        t.add("ok" if c.ok else "FAIL", c.name, c.margin, c.rule)
    typer.echo(t.text())
    typer.echo(f"contact ratio {fmt(pair.contact_ratio)}, working pressure angle "
               f"{fmt(math.degrees(pair.working_pressure_angle), 'angle')} deg")  # fmt: skip


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
    from ..drives import load_design
    from ..plot.khv import plot_mesh_stiffness

    with user_errors():
        files = output_set(output)
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
            dv = d.with_shift(v, f"{design} with x1 = {v:g}")
            law = dv.stiffness_law()
            laws[f"x1 = {v:g}: eps = {dv.gears.pair().contact_ratio:.3f}, "
                 f"mean {law.mean / 1e8:.3f}e8 N/m"] = law  # fmt: skip
            typer.echo(f"x1 = {v:g}: k_C = {fmt(dv.pitch_stiffness(), 'stiffness')} N/m, mean "
                       f"{fmt(law.mean, 'stiffness')} N/m")  # fmt: skip
        with files:
            savefig(plot_mesh_stiffness(laws), files.path("mesh-stiffness.png"), d.provenance)


@khv_app.command("clearances")
def khv_clearances(
    design: Annotated[Path, typer.Argument(help="KHV design file (TOML).")],
    teeth: Annotated[
        str, typer.Option(help="Tooth pairs, a range 'first:last' or a comma list.")
    ] = "-4:8",
    positions: Annotated[
        int, typer.Option(help="Mesh positions over one mesh cycle.", min=1, max=720)
    ] = 24,
    output: Annotated[
        Path | None,
        typer.Option("--output", "-o", help="Output folder (clearances.png, clearances.json)."),
    ] = None,
    sets: SetOption = None,
) -> None:
    """Unloaded drive-flank clearance of every tooth pair over one mesh cycle (rigid
    teeth, the design's flank modifications): which pairs a load can close."""
    import numpy as np

    from ..analysis.flank_modifications import khv_mesh_pair
    from ..contact.internal_pair import tooth_pair_clearances
    from ..drives import load_design
    from ..io import base_stamp, stamp
    from ..plot.khv import plot_clearances

    with user_errors():
        files = output_set(output) if output is not None else None
        try:
            if ":" in teeth:
                lo, hi = (int(t) for t in teeth.split(":"))
                ks = list(range(lo, hi + 1))
            else:
                ks = [int(t) for t in teeth.split(",") if t.strip()]
        except ValueError:
            raise ReducerlabError(
                f"--teeth: a range 'first:last' or a comma list of integers; got {teeth!r}"
            ) from None
        if not ks or len(ks) > 60:
            raise ReducerlabError(f"--teeth: 1 to 60 tooth pairs; got {len(ks)}")
        d = load_design(design, sets or ())
        mp = khv_mesh_pair(d)
        rolls, c = tooth_pair_clearances(mp, ks, positions=positions)
        if files is not None:
            with files:
                savefig(plot_clearances(rolls, ks, c), files.path("clearances.png"),
                        d.provenance)  # fmt: skip
                data = {"teeth": ks, "rolls_mm": (rolls * 1e3).tolist(),
                        "clearance_um": [[None if not np.isfinite(x) else x * 1e6 for x in row]
                                         for row in c]}  # fmt: skip
                stamped = stamp({**base_stamp(), **d.provenance})
                files.path("clearances.json").write_text(
                    json.dumps({**data, **stamped}, indent=2) + "\n"
                )
    t = Table([Column("pair", kind="text"), Column("min", "um", "length"),
               Column("max", "um", "length"), Column("note", kind="text")],
              title="drive-flank clearance, r_b2 psi over one mesh cycle")  # fmt: skip
    for j, k in enumerate(ks):
        col = c[:, j][np.isfinite(c[:, j])]
        if col.size:
            part = "" if col.size == len(rolls) else f"{col.size} of {len(rolls)} positions"
            t.add(f"{k:+d}", col.min() * 1e6, col.max() * 1e6, part)
        else:
            t.add(f"{k:+d}", None, None, "no drive-flank contact possible")
    typer.echo(t.text())


def _torque_list(text: str) -> list[float]:
    """``--torques``: comma-separated torques on the planet (N m, or quantities such as
    ``'50 N*m'``), each >= 0, one of them > 0."""
    out = []
    for part in (t.strip() for t in text.split(",")):
        if not part:
            continue
        try:
            v = float(part)
        except ValueError:
            v = quantity_option(part, "--torques", "torque")
        if v is None or not math.isfinite(v) or v < 0:
            raise ReducerlabError(f"--torques: each must be a torque >= 0 (N m); got {part!r}")
        out.append(float(v))
    if not out or max(out) <= 0:
        raise ReducerlabError(f"--torques: give torques >= 0 (N m), one of them > 0; got {text!r}")
    return out


@khv_app.command("sharing")
def khv_sharing(
    design: Annotated[Path, typer.Argument(help="KHV design file (TOML).")],
    torques: Annotated[
        str | None,
        typer.Option(
            help="Torques on the planet, comma separated (N m); default --loads "
            "from 0 to --top times the design's load."
        ),
    ] = None,
    loads: Annotated[
        int | None,
        typer.Option(help="Torques from 0 to --top times the load (default 6).", min=2, max=41),
    ] = None,
    top: Annotated[
        float | None,
        typer.Option(
            help="Largest torque over the design's load (default 1.5).", min=0.01, max=3.0
        ),
    ] = None,
    positions: Annotated[
        int, typer.Option(help="Mesh positions over one mesh cycle.", min=3, max=400)
    ] = 24,
    cell: Annotated[
        str | None, typer.Option(help="Contact cell, e.g. '0.2 mm' (default: from a pilot).")
    ] = None,
    tooth_size: Annotated[
        str | None, typer.Option(help="Finite-element tooth element size, e.g. '1 mm'.")
    ] = None,
    output: Annotated[
        Path,
        typer.Option("--output", "-o", help="Output folder (sharing.nc/.json/.txt/.png)."),
    ] = Path("."),
    sets: SetOption = None,
) -> None:
    """Load sharing of the planet-ring pair against torque (loaded tooth contact
    analysis, issue 30): tooth pairs in contact, each pair's load share over one mesh
    cycle, mesh stiffness k(t) and its mean against torque, loaded TE."""
    from ..analysis.contact_setup import pair_setup
    from ..analysis.khv_sharing import load_sharing
    from ..analysis.te_sweep import sweep_estimate
    from ..budget import format_bytes
    from ..drives import load_design

    with user_errors():
        files = output_set(output)
        if torques is not None and (loads is not None or top is not None):
            raise ReducerlabError("--torques: not with --loads or --top (give one or the other)")
        T = None if torques is None else _torque_list(torques)
        loads = 6 if loads is None else loads
        top = 1.5 if top is None else top
        h = quantity_option(cell, "--cell", "length")
        ts = quantity_option(tooth_size, "--tooth-size", "length")
        d = load_design(design, sets or ())
        if d.type != "khv":
            raise ReducerlabError(f"{design}: type = {d.type!r}: not a KHV design")
        n_t = loads if T is None else len(T)
        # told before the work; refused by load_sharing beyond the bounds (after the
        # clearances, which may refuse the torques first)
        fe = pair_setup(d).compliance_estimate(ts)
        work = sweep_estimate(positions, n_t)
        typer.echo(f"estimate: {fe.what}: {fe.work:.3g} {fe.unit}, about "
                   f"{format_bytes(fe.memory)}; then {work.work:.3g} {work.unit}")  # fmt: skip
        with progress_bar() as progress:
            task = progress.add_task("load sharing", total=None)
            res = load_sharing(
                d, torques=T, loads=loads, top=top, positions=positions, cell=h,
                tooth_size=ts, **position_callbacks(
                    progress, task, "loaded contact, position {done}/{total} (all torques)"
                ),
            )  # fmt: skip
            progress.update(task, description="writing results")
            with files:
                add_result(res, files, "sharing")
    typer.echo(res.table())


def register(app: typer.Typer) -> None:
    """Add the ``khv`` command group to the command line."""
    app.add_typer(khv_app, name="khv")
