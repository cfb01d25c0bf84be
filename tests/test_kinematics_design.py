"""Kinematics-only design files: loading and every rule of their schema."""

from __future__ import annotations

import math

import pytest

from reducerlab.analysis.kinematics import kinematics
from reducerlab.drives import design_from_dict, kinematics_of
from reducerlab.errors import DesignError, ReducerlabError
from reducerlab.kinematics import NutationDrive

BASE = {
    "type": "kinematics",
    "drive": "nutation",
    "input_speed": "1500 rpm",
    "nutation_angle": "5 deg",
    "teeth": {"nutating": 59, "central": 60},
}


def test_loads_in_si_and_builds_the_drive():
    d = design_from_dict(BASE)
    drive, speed = kinematics_of(d)
    assert speed == pytest.approx(157.07963267948966)
    assert isinstance(drive, NutationDrive) and drive.ratio == 60.0
    assert drive.nutation_angle == pytest.approx(math.radians(5))


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"teeth": {"nutating": 59}}, "missing ['central']"),
        ({"teeth": {"nutating": 59, "central": 60, "ring": 3}}, "unknown ['ring']"),
        ({"teeth": {"nutating": 59.5, "central": 60}}, "teeth.nutating = 59.5: must be an integer"),
        ({"teeth": {"nutating": 0, "central": 60}}, "must be greater than 0"),
        ({"nutation_angle": None}, "needs nutation_angle"),
        ({"nutation_angle": "190 deg"}, "out of range"),
        ({"drive": "khv", "teeth": {"planet": 30, "ring": 33}}, "has no nutation_angle"),
        ({"input_speed": "0 rpm"}, "input_speed must not be zero"),
        ({"input_speed": "25 Hz"}, "Hz is ambiguous"),
        ({"output": "ring"}, "output for drive 'nutation' must be one of"),
        ({"drive": "wobble"}, "drive = 'wobble'"),
        ({"contact": "side"}, "contact = 'side'"),
    ],
)
def test_rules(change, message):
    data = {**BASE, **change}
    data = {k: v for k, v in data.items() if v is not None}
    with pytest.raises(DesignError) as exc:
        design_from_dict(data, "k.toml")
    assert message in str(exc.value)
    assert "k.toml" in str(exc.value)


def test_geometry_errors_are_reported_at_load_time():
    with pytest.raises(DesignError, match=r"k\.toml: .*different tooth numbers"):
        design_from_dict({**BASE, "teeth": {"nutating": 60, "central": 60}}, "k.toml")
    with pytest.raises(DesignError, match="two lobes more"):
        design_from_dict(
            {"type": "kinematics", "drive": "cycloid_ball", "input_speed": 1.0,
             "teeth": {"centre": 38, "planetary": 39}}
        )  # fmt: skip


def test_analysis_argument_errors():
    drive = NutationDrive(59, 60, 0.1)
    with pytest.raises(ReducerlabError, match="non-zero"):
        kinematics(drive, 0.0)
    with pytest.raises(ReducerlabError, match="points"):
        kinematics(drive, 1.0, points=1)
    with pytest.raises(ReducerlabError, match="DriveKinematics"):
        kinematics("drive", 1.0)
    res = kinematics(drive, 100.0)
    assert res.ratio == 60.0 and "omega" in res.data
