"""Issue 16: ``--set PATH=VALUE`` overrides a design field (with units) on every command
that reads a design file, checked by the design's own schema."""

from __future__ import annotations

import inspect
import json

import pytest
from typer.testing import CliRunner

from reducerlab.cli import app
from reducerlab.design_files import apply_overrides, read_toml
from reducerlab.drives import load_design
from reducerlab.errors import DesignError
from reducerlab.examples import example_dir

runner = CliRunner()
KHV = example_dir() / "khv.toml"
GEAR = example_dir() / "gear_pair.toml"


def test_an_override_with_units_is_converted_by_the_field():
    d = load_design(KHV, ["input_speed=670 rpm", "gears.x1=0.5"])
    assert d.input_speed == pytest.approx(670 * 2 * 3.141592653589793 / 60, rel=1e-12)
    assert d.gears.x1 == 0.5
    # the file itself is untouched, and so is its data
    assert load_design(KHV).gears.x1 == 0.626


def test_overrides_take_toml_literals_and_bare_text():
    data = {"a": {"b": 1}, "l": [1, 2]}
    out = apply_overrides(data, ["a.b=2.5", "a.c=true", "l.1=7", "a.d=involute", 'a.e="x y"'])
    assert out == {"a": {"b": 2.5, "c": True, "d": "involute", "e": "x y"}, "l": [1, 7]}
    assert data == {"a": {"b": 1}, "l": [1, 2]}  # a copy
    # a field left at its default in the file may be set (its table is created)
    assert apply_overrides({}, ["mesh.half_backlash=3 um"]) == {"mesh": {"half_backlash": "3 um"}}


@pytest.mark.parametrize(
    ("item", "message"),
    [
        ("input_speed", "write PATH=VALUE"),
        ("=3", "names no field"),
        ("a..b=3", "names no field"),
        ("input_speed=", "no value after '='"),
        ("gears.x1.deep=1", "gears.x1 = 0.626 is a value, not a table"),
    ],
)
def test_malformed_overrides_are_named(item, message):
    with pytest.raises(DesignError, match="--set") as exc:
        apply_overrides(read_toml(KHV), [item])
    assert message in str(exc.value)


def test_a_list_index_out_of_range_is_named():
    with pytest.raises(DesignError, match="is a list of 2; '5' is not an index"):
        apply_overrides({"l": [1, 2]}, ["l.5=3"])


def test_a_wrong_value_is_refused_by_the_schema_naming_the_field():
    with pytest.raises(DesignError) as exc:
        load_design(KHV, ["input_speed=3 kg"])
    text = str(exc.value)
    assert "khv.toml (with --set): input_speed = '3 kg'" in text
    with pytest.raises(DesignError, match="nope = 1: unknown field"):
        load_design(KHV, ["nope=1"])


def _design_commands():
    """Every CLI command whose first argument is a design file."""
    found = []
    for group in [app, *[g.typer_instance for g in app.registered_groups]]:
        for c in group.registered_commands:
            params = inspect.signature(c.callback).parameters
            if "design" in params:
                found.append(c.callback)
    return found


def test_every_command_that_reads_a_design_takes_set():
    commands = _design_commands()
    assert len(commands) >= 14
    for callback in commands:
        assert "sets" in inspect.signature(callback).parameters, callback.__name__


def test_set_changes_the_result_on_the_command_line():
    base = runner.invoke(app, ["modal", str(GEAR), "--format", "json"])
    stiffer = runner.invoke(
        app, ["modal", str(GEAR), "--format", "json", "--set", "mesh.stiffness=8e8 N/m"]
    )
    assert base.exit_code == 0 and stiffer.exit_code == 0, stiffer.output
    f0 = json.loads(base.output)["frequencies_hz"]
    f1 = json.loads(stiffer.output)["frequencies_hz"]
    assert max(f1) > max(f0)


def test_set_errors_on_the_command_line_name_the_field():
    r = runner.invoke(app, ["kinematics", str(KHV), "--set", "input_speed=fast"])
    assert r.exit_code == 2
    assert "input_speed = 'fast'" in r.output and "Traceback" not in r.output
    r = runner.invoke(app, ["khv", "closed-graph", str(KHV), "--set", "gears.x1"])
    assert r.exit_code == 2 and "write PATH=VALUE" in r.output


def test_set_is_in_the_help_of_a_command():
    r = runner.invoke(app, ["bifurcation", "--help"], env={"COLUMNS": "200"})
    assert r.exit_code == 0 and "--set" in r.output and "PATH=VALUE" in r.output
