"""Smaller command-line fixes of issue 26 (item 9), each with its regression test."""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from reducerlab.cli import app
from reducerlab.examples import example_dir

runner = CliRunner()
GEAR = str(example_dir() / "gear_pair.toml")


# ------------------------------------------------- messages name their command
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["regime-map", GEAR, "-x", "nope=1,2", "-y", "mesh.stiffness=1e8,2e8"],
         "regime-map: unknown parameter path 'nope'"),
        (["regime-map", GEAR, "-x", "mesh.stiffness=lin:a:b:c", "-y", "mesh.stiffness=1,2"],
         "regime-map -x 'mesh.stiffness': 'lin:a:b:c': write lin:START:STOP:N"),
        (["regime-map", GEAR, "-x", "mesh.stiffness=1e8", "-y", "mesh.stiffness=rel:a"],
         "regime-map -y 'mesh.stiffness': relative value 'a' is not a number"),
        (["frequency-response", GEAR, "-p", "nope", "-v", "1,2"],
         "frequency-response: unknown parameter path 'nope'"),
        (["frequency-response", GEAR, "-p", "mesh.stiffness", "-v", "abc"],
         "frequency-response --values 'mesh.stiffness': value 'abc' is not a number"),
        (["bifurcation", GEAR, "-p", "nope", "-v", "1,2"],
         "bifurcation: unknown parameter path 'nope'"),
    ],
)  # fmt: skip
def test_parameter_errors_name_the_command_not_sweep(tmp_path, args, message):
    r = runner.invoke(app, [*args, "-o", str(tmp_path / "out")])
    assert r.exit_code == 2, r.output
    text = " ".join(r.output.split())
    assert message in text and "sweep" not in text, text
