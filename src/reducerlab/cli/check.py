"""``reducerlab check``: the verdict (issue 27): resonance over the operating range
(paper 000 Table 5), weighted by how strongly each excitation drives its mode, with the
gear bodies' modes given as files or computed first, and the nonlinear response at the
operating point, judged against the design's ``[check]`` table."""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from ..errors import ReducerlabError
from ..io import OutputSet
from .options import DesignArgument, Format, FormatOption, SetOption, parse_speeds
from .output import busy, outputs, progress_bar, savefig, user_errors

if TYPE_CHECKING:
    from ..analysis.verdict import Verdict


def check(
    design: DesignArgument,
    margin: Annotated[
        float | None,
        typer.Option(
            help="Relative distance to an excitation that counts (0.10 = 10 %), in (0, 1); "
            "default the design's [check] margin, else 0.10."
        ),
    ] = None,
    speed_range: Annotated[
        str | None, typer.Option(help="Operating range in rpm 'MIN,MAX' (default: design's).")
    ] = None,
    fmt: FormatOption = Format.table,
    body_modes: Annotated[
        list[Path] | None,
        typer.Option(
            "--body-modes",
            help="A gear body's modes (body_modal.nc from 'reducerlab body-modal' of this "
            "design: refused when computed for other values of the gear's fields); repeat "
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
    run_response: Annotated[
        bool,
        typer.Option(
            "--response/--no-response",
            help="Judge the nonlinear response at the operating point (dynamic load "
            "factor, tooth separation, impacts, motion; seconds per mesh line).",
        ),
    ] = True,
    sets: SetOption = None,
) -> None:
    """The verdict: exits 1 on any risk: a natural frequency meets an excitation that
    drives it (mesh strain or forward whirl), a gear body's mode meets an excitation or
    a system mode (paper 000 Table 5), a mode grows, or at the operating point the
    dynamic load factor exceeds its limit, the teeth separate, strike their back flanks
    or move non-periodically. Thresholds: the design's [check] table (docs/assumptions.md)."""
    from ..analysis.body_modal import BodyModalResult
    from ..analysis.components import ComponentModes
    from ..analysis.verdict import verdict
    from ..drives import load_design
    from ..inputs import check_inputs

    with user_errors():
        files = outputs(output)
        given = [(path, BodyModalResult.load(path)) for path in body_modes or []]
        rng = None
        if speed_range is not None:
            parts = parse_speeds(speed_range, "--speed-range")
            if parts is None or len(parts) != 2:
                raise ReducerlabError("--speed-range must be 'MIN,MAX' in rpm")
            if not parts[0] <= parts[1]:
                raise ReducerlabError(
                    f"--speed-range {speed_range!r}: MIN must not exceed MAX ('MIN,MAX' in rpm)"
                )
            rng = (parts[0], parts[1])
        d = load_design(design, sets or ())
        components = []
        for path, res_b in given:
            check_inputs(res_b, d, f"--body-modes {path}")  # never another design's modes
            components.append(ComponentModes.from_body_modal(res_b, source=str(path)))
        if bodies:
            components += _all_body_modes(d, design, {c.label for c in components})
        with busy("verdict"):
            report = verdict(d, speed_range=rng, components=components,
                             thresholds=None if margin is None else {"margin": margin},
                             run_response=run_response)  # fmt: skip
        if files is not None:
            _write_check(d, report, files)
    typer.echo(json.dumps(report.to_dict(), indent=2) if fmt is Format.json else report.table())
    if not report.ok:
        raise typer.Exit(code=1)


def _all_body_modes(d: Any, design: Path, have: set[str]) -> list:
    """Body modes of every gear of a nutation design not given already (progress bar)."""
    from ..analysis.body_modal import check_bodies
    from ..analysis.gear_bodies import gear_body_modes

    try:
        check_bodies(d)
    except ReducerlabError as exc:
        raise ReducerlabError(
            f"--bodies: {design}: {exc}; give --body-modes files instead"
        ) from None
    with progress_bar() as progress:
        task = progress.add_task("gear bodies", total=None)
        return gear_body_modes(d, skip=have, stage=lambda s: progress.update(task, description=s))


def _write_check(d: Any, report: Verdict, files: OutputSet) -> None:
    """check.json (the verdict), components.png (Table 5-style, with body modes) and
    campbell.png: the Campbell diagram the verdict used, with the body lines."""
    from ..io import stamp

    res = report.resonance
    with files:
        files.path("check.json").write_text(
            json.dumps({**report.to_dict(), **stamp(d.provenance)}, indent=2) + "\n"
        )
        if res is not None and res.components:
            savefig(res.plot_components(), files.path("components.png"), d.provenance)
        if res is not None:
            savefig(res.plot(), files.path("campbell.png"), d.provenance)


def register(app: typer.Typer) -> None:
    """Add ``check`` to the command line."""
    app.command()(check)
