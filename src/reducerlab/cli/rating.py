"""``reducerlab rating``: load capacity of a design's gear pairs, pitting and tooth root
safety factors (ISO 6336-2/-3:2019 method B; ISO 10300-1/-2/-3:2023 method B1 for the
bevel pairs, every factor listed with its clause; method A from the loaded tooth contact
analysis, ``analysis.rating_ltca``; issue 29)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated

import typer

from ..errors import ReducerlabError
from .options import DesignArgument, Format, FormatOption, SetOption, quantity_option
from .output import output_set, progress_bar, savefig, user_errors, write_json


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
    method: Annotated[
        str,
        typer.Option(
            help="auto: ISO 6336 method B where the standard covers the pair, method A (the "
            "loaded contact analysis with FE root stresses, minutes per pair) where it does "
            "not (double-arc teeth); B; A; both (judged by the smaller)."
        ),
    ] = "auto",
    positions: Annotated[
        int | None,
        typer.Option(help="Method A: positions over the mesh cycle (8).", min=2, max=48),
    ] = None,
    tooth_size: Annotated[
        str | None,
        typer.Option(
            "--tooth-size",
            help="Method A: element size of the FE tooth models, e.g. '1 mm' (0.3 m_n).",
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
    from ..analysis.rating_ltca import METHODS, MethodA
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
        if method not in METHODS:
            raise ReducerlabError(f"--method: one of {', '.join(METHODS)}; got {method!r}")
        settings = MethodA(
            positions=8 if positions is None else positions,
            tooth_size=quantity_option(tooth_size, "--tooth-size", "length"),
        )
        if method == "B":
            res = load_capacity(d, torque=T, power=P, conditions=cond, method="B")
        else:
            with progress_bar() as bar:
                task = bar.add_task("rating", total=None)
                res = load_capacity(
                    d, torque=T, power=P, conditions=cond, method=method, ltca=settings,
                    stage=lambda text: bar.update(task, description=text),
                    progress=lambda done, total: bar.update(task, completed=done, total=total),
                )  # fmt: skip
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
