"""Command line: ``reducerlab run`` (the whole chain), ``modal``, ``sensitivity``,
``kinematics``, ``sweep``, ``campbell``, ``check``, ``bifurcation``,
``frequency-response``, ``regime-map``, ``response``, ``surface``, ``khv``,
``body-modal``, ``contact``, ``efficiency``, ``accuracy``, ``rating``, ``balls``,
``datasheet``, ``tolerances``, ``report``, ``demo``.
Every command that reads a design file takes ``--set PATH=VALUE`` to override a field.

Errors caused by the user's input are printed as one clear message (exit code 2),
never as a traceback. Text from the user (paths, values, design fields) is printed
verbatim: the consoles interpret no rich markup, emoji codes or highlighting.

Outputs follow one convention (:mod:`reducerlab.io`): ``-o DIR`` names an output
directory for every command that writes files; it is checked before any computation,
each command's files are written together (staged, then moved into place) and every
file written or replaced is reported on stderr. Options that name one file
(``surface --export/--png/--cloud``) have their suffix checked before any work.

Counts are bounded (checked before any work, the option named in the message): at
most 100000 speeds (``campbell --speeds``), 1000000 sweep points, 100000 bifurcation
values, periods in [1, 10^6], ``--keep`` and ``--history`` at most ``--periods``, RK4
steps per period in [4, 100000], at most 4 ``--workers`` per core.

The package: :mod:`.options` parses the options the commands share, :mod:`.output`
writes and prints; one module per command group (:mod:`.modal`, :mod:`.kinematics`,
:mod:`.sweep`, :mod:`.check`, :mod:`.nonlinear`, :mod:`.geometry`, :mod:`.body`,
:mod:`.contact`, :mod:`.efficiency`, :mod:`.report`, :mod:`.khv`, :mod:`.balls`,
:mod:`.datasheet`) adds its commands to :data:`app`.
"""

from __future__ import annotations

import sys
from typing import Annotated, Any

import typer

from .. import __version__
from . import (
    accuracy,
    balls,
    body,
    check,
    contact,
    datasheet,
    efficiency,
    geometry,
    khv,
    kinematics,
    modal,
    nonlinear,
    report,
    run,
    sweep,
    tolerances,
)
from . import rating as rating_command
from .output import err, kept, reset_kept

__all__ = ["app", "main"]

app = typer.Typer(
    name="reducerlab",
    help="Design and dynamic analysis of compact high-ratio gear reducers.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # help texts are plain text: with rich markup, "[surface] table" or "[meshN]" lost
    # their brackets (rich took them for style tags)
    rich_markup_mode=None,
)
"""The ``reducerlab`` command line."""


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
    reset_kept()


# the commands, in this order in the help
for _group in (run, modal, kinematics, sweep, check, nonlinear, geometry, body, contact,
               efficiency, accuracy, rating_command, report, khv, balls, datasheet,
               tolerances):  # fmt: skip
    _group.register(app)
del _group


class _Terminated(SystemExit):
    """SIGTERM, raised in the main thread so that every ``finally`` runs: worker pools
    end their processes, staged outputs are discarded, finished chunks stay."""


def _on_sigterm(signum: int, frame: Any) -> None:
    import signal

    signal.signal(signal.SIGTERM, signal.SIG_IGN)  # one clean shutdown, not nested ones
    raise _Terminated(128 + signum)


def _termination(exc: BaseException) -> _Terminated | None:
    """The SIGTERM behind ``exc``, if any: raised inside compiled code (the numba
    kernel), it surfaces as the context of another error (``SystemError``)."""
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, _Terminated):
            return e
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return None


def _interrupted(exc: BaseException) -> bool:
    """Whether ``exc`` is Ctrl-C: a ``KeyboardInterrupt``, or the exit typer makes of
    one."""
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return True
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return False


def main() -> None:
    """Console-script entry point.

    SIGTERM ends the command like Ctrl-C does (exit codes 143 and 130): worker processes
    are stopped, no partial output set is left, and a sweep, bifurcation or regime map
    resumes from its finished chunks when run again. Either prints one line saying what
    was kept (:func:`.output.kept`).
    """
    import signal

    signal.signal(signal.SIGTERM, _on_sigterm)
    try:
        app()
    except BaseException as exc:
        # typer turns Ctrl-C into exit code 130 (a SystemExit caused by the interrupt)
        if _interrupted(exc):
            err.print(f"interrupted: {kept()}", soft_wrap=True)
            sys.exit(130)
        term = _termination(exc)
        if term is None:
            raise
        err.print(f"terminated (SIGTERM): {kept()}", soft_wrap=True)
        sys.exit(term.code)
