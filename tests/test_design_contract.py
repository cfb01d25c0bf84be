"""The Design contract (issue 25): what every analysis and the report ask of a design,
answered by every bundled example from its own fields, and ``with_values`` as the one
way to change a design."""

from __future__ import annotations

import math

import pytest

from reducerlab.design import Design
from reducerlab.drives import DRIVES, design_and_model, load_design
from reducerlab.errors import DesignError, ReducerlabError
from reducerlab.examples import example_files
from reducerlab.kinematics import TRAINS, DriveKinematics
from reducerlab.model import Model

EXAMPLES = {p.name: p for p in example_files()}


def _raw_speed(raw: dict) -> tuple[float | None, list | None]:
    """Operating speed and range as a design file's reader would find them by hand."""
    if "operating" in raw:
        return raw["operating"].get("speed"), raw["operating"].get("speed_range")
    return raw.get("input_speed", raw.get("speed")), raw.get("speed_range")


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_every_design_answers_the_contract(name):
    d = load_design(EXAMPLES[name])
    assert isinstance(d, Design)
    dumped = d.model_dump()
    speed, rng = _raw_speed(dumped)
    assert d.operating_speed == pytest.approx(float(speed or 0.0), rel=0, abs=0)
    lo, hi = d.operating_range()
    if rng:
        assert (lo, hi) == (rng[0], rng[1])
    else:
        assert lo == hi == d.operating_speed
    kin = d.kinematics()
    assert kin is None or isinstance(kin, DriveKinematics)
    # a lumped model has no kinematics; every other drive kind is a registered train
    assert (kin is None) == (d.type == "lumped")
    if kin is not None:
        assert d.drive_name in TRAINS
        assert math.isfinite(kin.ratio)
    assert d.has_tooth_surfaces == (d.type == "nutation" and dumped.get("surface") is not None)
    assert d.type in DRIVES


def test_drive_name_of_a_kinematics_only_design_is_its_drive():
    d = load_design(EXAMPLES["nutation_double.toml"])
    assert (d.type, d.drive_name) == ("kinematics", "double_nutation")


def test_with_values_is_a_validated_copy():
    d = load_design(EXAMPLES["khv.toml"])
    e = d.with_values({"gears.x1": 0.5, "gears.x2": None})
    assert e.gears.x1 == 0.5 and d.gears.x1 != 0.5  # the original is untouched
    assert type(e) is type(d) and e.hash != d.hash
    with pytest.raises(DesignError, match=r"gears\.x1 = 'abc'"):
        d.with_values({"gears.x1": "abc"})
    with pytest.raises(DesignError, match="is a value, not a table"):
        d.with_values({"input_speed.x": 1.0})


def test_design_and_model_names_the_analysis_for_a_wrong_target():
    d = load_design(EXAMPLES["gear_pair.toml"])
    design, model = design_and_model(d, "x")
    assert design is d and isinstance(model, Model)
    assert design_and_model(model, "x") == (None, model)
    with pytest.raises(ReducerlabError, match="campbell: target must be a Design or a Model"):
        design_and_model(3, "campbell")
