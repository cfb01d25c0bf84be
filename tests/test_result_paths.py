"""Result files handed to a command (issue 26, item 9): a folder or a device is named as
what it is, not as a missing file (``--body-modes /dev/null`` said "no such result
file")."""

from __future__ import annotations

import os

import pytest
from typer.testing import CliRunner

from reducerlab.cli import app
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.results import Result

runner = CliRunner()


def test_missing_folder_and_device_are_told_apart(tmp_path):
    with pytest.raises(ReducerlabError, match=r"missing\.nc: no such result file"):
        Result.load(tmp_path / "missing.nc")
    with pytest.raises(ReducerlabError, match="a folder, not a result file"):
        Result.load(tmp_path)
    if os.path.exists(os.devnull):
        with pytest.raises(ReducerlabError, match="not a regular file"):
            Result.load(os.devnull)


def test_check_with_a_folder_as_body_modes(tmp_path):
    r = runner.invoke(
        app, ["check", str(example_dir() / "gear_pair.toml"), "--body-modes", str(tmp_path)]
    )
    assert r.exit_code == 2, r.output
    assert "a folder, not a result file" in r.output and "Traceback" not in r.output
