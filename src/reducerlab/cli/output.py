"""What the commands write and print: the consoles, progress bars, errors as one line
(exit code 2), and the files of an output set (results, JSON summaries, figures).

User text (paths, values, messages) is printed verbatim: the consoles interpret no rich
markup, emoji codes or highlighting. Every file written or replaced is reported on
stderr (:mod:`reducerlab.io` stages an output set and moves it into place at once).
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import typer
from rich.console import Console
from rich.text import Text

from ..errors import ReducerlabError
from ..io import OutputSet, atomic_path, png_metadata

if TYPE_CHECKING:
    from rich.progress import Progress

# user text (paths, values, messages) is printed verbatim: no markup, emoji or highlighting
out = Console(markup=False, emoji=False, highlight=False)
"""The console on stdout."""
err = Console(stderr=True, markup=False, emoji=False, highlight=False)
"""The console on stderr (notes, errors, progress)."""


#: What the running command has kept so far (files moved into place, the resumable run
#: folder it writes chunks into), for the line an interruption prints (:func:`kept`).
_KEPT: dict[str, list[str]] = {"files": [], "runs": [], "caches": []}


def note(line: str) -> None:
    """One line on stderr, verbatim (``wrote PATH``); a file written is remembered for
    :func:`kept`."""
    for verb in ("wrote ", "replaced "):
        if line.startswith(verb):
            _KEPT["files"].append(line[len(verb) :])
    err.print(line, soft_wrap=True)


def reset_kept() -> None:
    """Forget what an earlier command kept (each command starts with nothing kept)."""
    for v in _KEPT.values():
        v.clear()


def keeps_run(folder: Path) -> None:
    """Record that the command writes its finished chunks into the run folder ``folder``
    (kept when it is interrupted, resumed when it is run again)."""
    _KEPT["runs"].append(str(folder))


def keeps_cache(folder: Path) -> None:
    """Record that the command stores each finished stage in the cache ``folder``
    (``reducerlab run``: kept when interrupted, read when run again)."""
    _KEPT["caches"].append(str(folder))


def kept() -> str:
    """What an interrupted command leaves behind, in one line: the finished chunks of
    its run folder, the files it wrote before, or nothing (an output set is moved into
    place only when all of its files were written)."""
    parts = []
    for folder in _KEPT["runs"]:
        n = len(list((Path(folder) / "chunks").glob("chunk_*.npz")))
        parts.append(
            f"{n} finished chunk(s) kept in {folder}; run the same command again to resume"
            if n
            else f"no chunk had finished in {folder}"
        )
    for folder in _KEPT["caches"]:
        n = len(list(Path(folder).glob("*.json")))
        parts.append(
            f"{n} finished stage(s) kept in {folder}; run the same command again to resume"
            if n
            else f"no stage had finished in {folder}"
        )
    files = _KEPT["files"]
    if files:
        shown = ", ".join(files[:3]) + (f" and {len(files) - 3} more" if len(files) > 3 else "")
        parts.append(f"kept the files written before: {shown}")
    if not parts:
        return "nothing written (a command's files are moved into place only when complete)"
    return "; ".join(parts)


def fail(exc: Exception) -> NoReturn:
    """Print ``error: MESSAGE`` (the message verbatim) and exit with code 2."""
    err.print(Text.assemble(("error:", "bold red"), " ", str(exc)), soft_wrap=True)
    raise typer.Exit(code=2)


@contextmanager
def user_errors() -> Iterator[None]:
    """Print an error caused by the user's input (or an unwritable output) as one line
    and exit with code 2, without a traceback."""
    try:
        yield
    except (ReducerlabError, OSError) as exc:
        fail(exc)


def count_text(completed: float, total: float | None) -> str:
    """The counter of a progress bar: ``"3/24"``, or nothing while the total is unknown
    (the bar then pulses; never ``"0/None"``)."""
    if total is None:
        return ""
    return f"{completed:.0f}/{total:.0f}"


def progress_bar() -> Progress:
    """A transient progress bar on stderr; task descriptions are shown verbatim. A task
    without a total (``total=None``) shows a pulsing bar and no counter."""
    from rich.progress import BarColumn, Progress, ProgressColumn, TextColumn, TimeElapsedColumn

    class CountColumn(ProgressColumn):
        def render(self, task: Any) -> Text:
            return Text(count_text(task.completed, task.total))

    return Progress(
        TextColumn("{task.description}", markup=False),
        BarColumn(),
        CountColumn(),
        TimeElapsedColumn(),
        console=err,
        transient=True,
        disable=not err.is_terminal,  # no bar (nor blank line) in logs and pipes
    )


@contextmanager
def busy(description: str) -> Iterator[Callable[[int, int], None]]:
    """A progress bar for work of unknown length; yields an update(done, total)."""
    with progress_bar() as progress:
        task = progress.add_task(description, total=None)
        yield lambda done, total: progress.update(task, completed=done, total=total)


def outputs(output: Path | None) -> OutputSet | None:
    """The output set of ``-o DIR`` (checked now, before any work), or None."""
    return None if output is None else output_set(output)


def output_set(output: Path) -> OutputSet:
    """The output set of ``-o DIR`` (checked now, before any work)."""
    return OutputSet(output, "-o", report=note)


def write_file(path: Path, write: Callable[[Path], Any]) -> None:
    """Write one file atomically with ``write(temporary_path)`` and report it."""
    replaced = path.exists()
    with atomic_path(path) as tmp:
        write(tmp)
    note(f"{'replaced' if replaced else 'wrote'} {path}")


def savefig(fig: Any, path: Path, attrs: dict[str, Any], dpi: int = 120) -> None:
    """Save a figure as PNG stamped with its provenance (version, time, design, hash)."""
    fig.savefig(path, dpi=dpi, format="png", metadata=png_metadata(attrs))


def add_with_figure(result: Any, files: OutputSet, stem: str) -> None:
    """Add ``STEM.nc`` and the result's figure ``STEM.png`` to an open output set."""
    result.save(files.path(f"{stem}.nc"))
    savefig(result.plot(), files.path(f"{stem}.png"), result.data.attrs)


def add_result(result: Any, files: OutputSet, stem: str) -> None:
    """Add ``STEM.nc``, ``STEM.json`` (:func:`write_json`), ``STEM.txt`` (the table) and
    ``STEM.png`` (the figure) of a result to an open output set."""
    result.save(files.path(f"{stem}.nc"))
    write_json(result, files.path(f"{stem}.json"))
    files.path(f"{stem}.txt").write_text(result.table() + "\n")
    savefig(result.figure(), files.path(f"{stem}.png"), result.data.attrs)


def position_callbacks(progress: Any, task: Any, label: str) -> dict[str, Callable[..., None]]:
    """``stage`` and ``progress`` keyword callbacks of a contact analysis that show on
    the bar ``task``: each stage's text, then ``label`` formatted with ``done`` and
    ``total`` per position."""
    return {
        "stage": lambda text: progress.update(task, description=text),
        "progress": lambda done, total: progress.update(
            task, completed=done, total=total, description=label.format(done=done, total=total)
        ),
    }


def save_with_figure(result: Any, files: OutputSet, stem: str) -> None:
    """Write ``STEM.nc`` and ``STEM.png`` as one output set."""
    with files:
        add_with_figure(result, files, stem)


def write_json(result: Any, path: Path) -> None:
    """The result's JSON summary stamped with its provenance (version, time, design)."""
    path.write_text(json.dumps({**result.to_dict(), **result.provenance}, indent=2) + "\n")


#: Seconds between two progress lines when stderr is not a terminal (a log).
LOG_EVERY_S = 10.0


class _Lines:
    """Progress as log lines on stderr (output not a terminal): the stage, the
    percentage of the whole run and the time left, at most every ``LOG_EVERY_S`` and at
    every new stage."""

    def __init__(self) -> None:
        self.t0 = time.monotonic()
        self.last = -LOG_EVERY_S
        self.stage = ""

    def __call__(self, description: str, fraction: float) -> None:
        now = time.monotonic() - self.t0
        stage = description.split(":")[0]
        if stage == self.stage and now - self.last < LOG_EVERY_S:
            return
        self.stage, self.last = stage, now
        left = ""
        if 0.02 < fraction < 1:
            left = f", about {now * (1 - fraction) / fraction:.0f} s left"
        err.print(f"[{now:7.1f} s] {100 * fraction:3.0f} % {description}{left}", soft_wrap=True)


class run_progress:
    """A progress display: a bar with percentage and ETA on a terminal, log lines
    otherwise. Yields ``show(description, fraction)``."""

    def __enter__(self) -> Any:
        if not sys.stderr.isatty():
            return _Lines()
        from rich import progress as rp

        self.bar = rp.Progress(
            rp.TextColumn("{task.description}", markup=False),
            rp.BarColumn(),
            rp.TaskProgressColumn(),
            rp.TimeElapsedColumn(),
            rp.TimeRemainingColumn(),
            console=err,
            transient=True,
        )
        self.bar.__enter__()
        task = self.bar.add_task("run", total=1.0)
        return lambda d, f: self.bar.update(task, description=d, completed=f)

    def __exit__(self, *exc: Any) -> None:
        if hasattr(self, "bar"):
            self.bar.__exit__(*exc)
