"""``reducerlab khv``: tools of the KHV planetary drive (paper 004): the closed graph of
the shift coefficients and the mesh stiffness along the shift line."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from .options import SetOption
from .output import output_set, savefig, user_errors

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
            typer.echo(f"x1 = {v:g}: k_C = {dv.pitch_stiffness():.4g} N/m, mean {law.mean:.4g} N/m")
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
    typer.echo("pair  min (um)   max (um)   (drive flanks, r_b2 psi over one mesh cycle)")
    for j, k in enumerate(ks):
        col = c[:, j][np.isfinite(c[:, j])]
        if col.size:
            part = "" if col.size == len(rolls) else f"   ({col.size} of {len(rolls)} positions)"
            typer.echo(f"{k:+4d}  {col.min() * 1e6:9.2f}  {col.max() * 1e6:9.2f}{part}")
        else:
            typer.echo(f"{k:+4d}  no drive-flank contact possible")


def register(app: typer.Typer) -> None:
    """Add the ``khv`` command group to the command line."""
    app.add_typer(khv_app, name="khv")
