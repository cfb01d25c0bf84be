"""Help texts are shown as written (issue 26, item 9): typer's rich markup took
``[surface]`` and ``[meshN]`` in a help text for style tags and dropped them."""

from __future__ import annotations

import re

import typer
from typer.testing import CliRunner

from reducerlab.cli import app

runner = CliRunner()
BRACKETED = re.compile(r"\[[^\]\s]+\]")


def _commands(cmd, path: tuple[str, ...] = ()):
    yield path, cmd
    if hasattr(cmd, "commands"):  # a group (typer's click or its own copy of it)
        for name, sub in cmd.commands.items():
            yield from _commands(sub, (*path, name))


def test_no_help_text_loses_its_bracketed_words():
    root = typer.main.get_command(app)
    checked = 0
    for path, cmd in _commands(root):
        texts = [cmd.help or ""] + [getattr(p, "help", None) or "" for p in cmd.params]
        words = {w for t in texts for w in BRACKETED.findall(t)}
        res = runner.invoke(app, [*path, "--help"], terminal_width=400)
        assert res.exit_code == 0, (path, res.output)
        flat = " ".join(res.output.split())
        for w in words:
            assert w in flat, f"{' '.join(path)} --help lost {w}"
            checked += 1
    assert checked >= 2  # [surface] (check --bodies), [meshN] (contact --write-design)
    out = " ".join(runner.invoke(app, ["contact", "--help"]).output.split())
    assert "[meshN]" in out
    out = " ".join(runner.invoke(app, ["check", "--help"]).output.split())
    assert "[surface] table" in out
