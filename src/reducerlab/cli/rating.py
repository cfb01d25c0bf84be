"""``reducerlab rating``: load capacity of a design's gear pairs, pitting and tooth root
safety factors (ISO 6336-2/-3:2019 method B; ISO 10300-1/-2/-3:2023 method B1 for the
bevel pairs, every factor listed with its clause; issue 29)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from .options import DesignArgument, Format, FormatOption, SetOption, quantity_option
from .output import output_set, savefig, user_errors, write_json


def _factor(text: str | None, option: str) -> float | None:
    if text is None:
        return None
    try:
        v = float(text)
    except ValueError:
        raise ReducerlabError(f"{option}: must be a number >= 1; got {text!r}") from None
    if not v >= 1.0:
        raise ReducerlabError(f"{option}: must be a number >= 1; got {text!r}")
    return v


def rating(
    design: DesignArgument,
    power: Annotated[
        str | None,
        typer.Option(help="Power through the drive at the design's speed, e.g. '3 kW'."),
    ] = None,
    torque: Annotated[
        str | None,
        typer.Option(
            help="Torque on the driving gear of the pair (gear_pair: pinion; khv: planet; "
            "nutation: input shaft), e.g. '60 N*m'. Default: the design's load."
        ),
    ] = None,
    ka: Annotated[str | None, typer.Option("--ka", help="Application factor K_A (1.0).")] = None,
    kv: Annotated[str | None, typer.Option("--kv", help="Dynamic factor K_v (1.1).")] = None,
    khbeta: Annotated[
        str | None,
        typer.Option(
            "--khbeta",
            help="Face load factor K_Hbeta (1.15; cylindrical pairs only: a nutation "
            "design's is ISO 10300-1's K_Hbeta-C).",
        ),
    ] = None,
    khalpha: Annotated[
        str | None, typer.Option("--khalpha", help="Transverse load factor K_Halpha (1.0).")
    ] = None,
    hours: Annotated[
        float | None, typer.Option(help="Required life in hours (20000).", min=1e-6, max=1e7)
    ] = None,
    viscosity: Annotated[
        float | None,
        typer.Option(
            help="Lubricant kinematic viscosity at 40 C in mm^2/s (220: ISO VG 220).",
            min=1.0,
            max=1e5,
        ),
    ] = None,
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Output folder (netCDF, JSON, table).")
    ] = None,
    fmt: FormatOption = Format.table,
    sets: SetOption = None,
) -> None:
    """Load capacity: pitting (S_H) and tooth root (S_F) safety factors of every gear pair
    of a gear_pair, khv or nutation design, with every factor, its value and clause."""
    from dataclasses import replace

    from ..analysis.rating import load_capacity
    from ..drives import load_design
    from ..rating.material import RatingConditions

    with user_errors():
        files = output_set(output) if output is not None else None
        d = load_design(design, sets or ())
        P = quantity_option(power, "--power", "power")
        T = quantity_option(torque, "--torque", "torque")
        if P is not None and T is not None:
            raise ReducerlabError("--power/--torque: give at most one of them")
        changes: dict[str, float] = {}
        for text, option, name in (
            (ka, "--ka", "K_A"), (kv, "--kv", "K_v"), (khbeta, "--khbeta", "K_Hbeta"),
            (khalpha, "--khalpha", "K_Halpha"),
        ):  # fmt: skip
            v = _factor(text, option)
            if v is not None:
                changes[name] = v
        if hours is not None:
            changes["hours"] = float(hours)
        if viscosity is not None:
            changes["viscosity_40"] = viscosity * 1e-6
        cond = replace(RatingConditions(), **changes)
        res = load_capacity(d, torque=T, power=P, conditions=cond)
        if files is not None:
            with files:
                res.save(files.path("rating.nc"))
                write_json(res, files.path("rating.json"))
                files.path("rating.txt").write_text(res.table() + "\n")
                savefig(res.figure(), files.path("rating.png"), res.data.attrs)
    typer.echo(json.dumps(res.to_dict(), indent=2) if fmt is Format.json else res.table())


def register(app: typer.Typer) -> None:
    """Add ``rating`` to the command line."""
    app.command()(rating)
