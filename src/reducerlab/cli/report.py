"""``reducerlab report`` and ``demo``: the HTML report of a design, and of every
bundled example."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Annotated

import typer
from rich.text import Text

from ..errors import ReducerlabError
from ..io import prepare_output_dir, prepare_output_file
from .options import DesignArgument, SetOption
from .output import fail, out, progress_bar, run_progress, user_errors, write_file


def report_cmd(
    design: DesignArgument,
    output: Annotated[
        str | None,
        typer.Option(
            "--output",
            "-o",
            metavar="PATH",
            help="Report file (.html), or a folder (an existing one, a path ending in '/' "
            "or without a suffix) to write report.html in; default DESIGN-report.html.",
        ),
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
            "regime_map.nc, te_sweep.nc, layout.nc, a KHV drive's sharing.nc, "
            "datasheet.nc, efficiency.nc) to include (repeatable).",
        ),
    ] = None,
    sets: SetOption = None,
) -> None:
    """One HTML report of everything reducerlab can say about a design, its plotly.js
    beside it (shared by the reports of the folder; opens offline); exit 1 when a
    section failed: its error is shown in its place in the report."""
    from ..reporting import PLOTLY_FILE
    from ..reporting import report as build_report

    with user_errors():
        path = _report_path(output, design)
        prepare_output_file(path, "-o", (".html", ".htm"))
        with progress_bar() as progress:
            task = progress.add_task("report", total=None)

            def step(title: str, done: int, total: int) -> None:
                progress.update(task, description=title, completed=done, total=total)

            rep = build_report(design, overrides=sets or (), results=given or (),
                               only=section, progress=step)  # fmt: skip
        write_file(path, lambda tmp: rep.write(tmp, plotly=path.parent / PLOTLY_FILE))
    for s in rep.sections:
        status = f"FAILED: {s.error}" if s.error else "ok"
        typer.echo(f"  {s.title:<45} {s.seconds:7.2f} s  {status}")
    typer.echo(f"report: {path.resolve()} ({rep.seconds:.1f} s)")
    if rep.failed:
        raise typer.Exit(1)


def _report_path(output: str | None, design: Path) -> Path:
    """The report file: ``-o FILE.html``, or ``report.html`` in ``-o DIR`` (an existing
    folder, a path ending in a separator, or one without a suffix: the ``-o DIR``
    convention of the other commands)."""
    if output is None:
        return Path(f"{design.stem}-report.html")
    p = Path(output)
    folder = p.is_dir() or output.endswith(("/", os.sep)) or (not p.suffix and not p.exists())
    return p / "report.html" if folder else p


#: The example ``demo`` takes through the whole chain (``run``).
FLAGSHIP = "nutation_double_sided.toml"


def demo(
    output: Annotated[Path, typer.Option("--output", "-o", help="Output folder.")] = Path(
        "demo-output"
    ),
) -> None:
    """The whole chain (``run``) of the flagship example, the double-sided nutation drive
    at its operating point, into OUTPUT/nutation_double_sided/; the design report of every
    other bundled example; an index.html linking them."""
    from ..examples import example_files
    from ..pipeline import run
    from ..reporting import PLOTLY_FILE, write_index
    from ..reporting import report as build_report

    with user_errors():
        prepare_output_dir(output)
    examples = example_files()
    if not examples:
        fail(ReducerlabError("no bundled examples found"))
    done = []
    flagship = [p for p in examples if p.name == FLAGSHIP]
    for path in flagship:
        with user_errors(), run_progress() as show:
            res = run(path, output / path.stem, progress=show)
        done.append((res.report, res.built))
        verdict = "no risk" if res.ok else f"RISK ({len(res.verdict.risks)} reason(s))"
        out.print(f"{path.name}: the whole chain in {res.seconds:.1f} s, verdict {verdict}")
    examples = [p for p in examples if p.name != FLAGSHIP]
    with progress_bar() as progress:
        task = progress.add_task("examples", total=len(examples))
        for path in examples:
            progress.update(task, description=path.name)
            with user_errors():
                rep = build_report(path)
                file = rep.write(output / f"{path.stem}.html", plotly=output / PLOTLY_FILE)
            done.append((file, rep))
            progress.advance(task)
    with user_errors():
        index = write_index(done, output / "index.html")
    for file, rep in done:
        failed = f", {len(rep.failed)} section(s) FAILED" if rep.failed else ""
        out.print(Text.assemble((file.name, "bold"), f"  {len(rep.sections)} sections, "
                                f"{rep.seconds:.1f} s{failed}"))  # fmt: skip
    out.print(f"open {index.resolve()}")


def register(app: typer.Typer) -> None:
    """Add ``report`` and ``demo`` to the command line."""
    app.command("report")(report_cmd)
    app.command()(demo)
