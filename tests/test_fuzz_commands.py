"""Fuzz the newer commands (issue 26): every hostile option of ``body-modal``,
``contact``, ``check`` and ``report`` (``tests/fuzz_commands.py``) is refused with exit
code 2 and one message naming the option or the design field, before any meshing or
contact solving, and never with a traceback.

Meshing (gmsh) and the contact solver are replaced by a trap here: a case that reaches
them was not refused up front, which fails the test at once instead of running for
minutes. ``benchmarks/fuzz_commands.py`` runs the same cases, and random pairs of them,
for real in separate processes under a memory cap (counts in ``docs/reliability.md``).
"""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from fuzz_commands import cases
from reducerlab.budget import MEMORY_ENV
from reducerlab.cli import app


class ReachedWork(Exception):
    """Raised by the trap: the command started meshing or solving."""


def _trap(*args, **kwargs):
    raise ReachedWork


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("fuzz")
    (tmp / "folder").mkdir()
    (tmp / "note.txt").write_text("not a result\n")
    return tmp


@pytest.fixture
def trapped(monkeypatch, scratch):
    gmsh = pytest.importorskip("gmsh")
    monkeypatch.setattr(gmsh.model.mesh, "generate", _trap)
    import reducerlab.contact.ltca as ltca

    monkeypatch.setattr(ltca, "loaded_contact", _trap)
    monkeypatch.setenv(MEMORY_ENV, "2G")
    monkeypatch.chdir(scratch)
    return scratch


ALL = cases("{tmp}")


@pytest.mark.parametrize(
    "case", ALL, ids=[c.label.split(" ", 1)[0] + " " + " ".join(c.args[-2:]) for c in ALL]
)
def test_a_hostile_option_is_refused_up_front(case, trapped):
    args = [a.replace("{tmp}", str(trapped)) for a in case.args]
    r = CliRunner().invoke(app, args)
    assert not isinstance(r.exception, ReachedWork), f"started work: {case.label}"
    assert r.exit_code == 2, (case.label, r.output, r.exception)
    assert "Traceback" not in r.output
    assert any(n in r.output for n in case.names), (case.names, r.output)
    assert r.output.count("error") <= 3, r.output  # one message, not a cascade
