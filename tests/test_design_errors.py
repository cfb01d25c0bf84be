"""Error messages of the design loader, one test per schema rule.

Every test writes a variant of ``examples/gear_pair.toml`` into ``tmp_path`` and checks
that the :class:`DesignError` names the file, the dotted field path, the value as written
and the rule that was broken.
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from reducerlab.drives import design_from_dict, load_design
from reducerlab.drives.gear_pair import GearPairDesign
from reducerlab.errors import DesignError

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "gear_pair.toml"
BASE = EXAMPLE.read_text()

OPERATING = """[operating]
speed = "1500 rpm"                 # pinion
torque = "60 N*m"                  # transmitted by the pinion
speed_range = ["1200 rpm", "1800 rpm"]   # operating range for `reducerlab check`
"""


def edited(*edits: tuple[str, str]) -> str:
    """The example design with each ``(old, new)`` replacement applied exactly once."""
    text = BASE
    for old, new in edits:
        assert text.count(old) == 1, f"{old!r} is not unique in the example"
        text = text.replace(old, new)
    return text


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "design.toml"
    path.write_text(text)
    return path


def load_error(tmp_path: Path, *edits: tuple[str, str]) -> tuple[DesignError, Path]:
    """Load the edited example and return the DesignError it must raise."""
    path = write(tmp_path, edited(*edits))
    with pytest.raises(DesignError) as exc:
        load_design(path)
    return exc.value, path


def only_problem(err: DesignError, path: Path) -> str:
    """The single problem of ``err``; it must also appear in the message."""
    assert len(err.problems) == 1, err.problems
    problem = err.problems[0]
    assert problem.startswith(f"{path}: "), problem
    assert problem in str(err)
    return problem


def assert_names(problem: str, path: Path, field: str, value: object, *rule: str) -> None:
    """``problem`` names file, field path, value as written (repr) and the rule words."""
    assert problem.startswith(f"{path}: {field} = {value!r}: "), problem
    for words in rule:
        assert words in problem, (words, problem)


# --- a valid design ----------------------------------------------------------------------


def test_valid_design_loads_with_si_values():
    design = load_design(EXAMPLE)
    assert isinstance(design, GearPairDesign)
    assert design.type == "gear_pair"
    assert design.pinion.teeth == 25
    assert design.pinion.mass == 1.25
    assert design.pinion.moment_of_inertia == pytest.approx(1.10e-3, rel=1e-12)
    assert design.gear.moment_of_inertia == pytest.approx(3.9e-2, rel=1e-12)
    assert design.pinion.bearing.damping_x == 900.0
    assert design.mesh.module == pytest.approx(3e-3, rel=1e-12)
    assert design.mesh.pressure_angle == pytest.approx(math.radians(20), rel=1e-12)
    assert design.mesh.backlash == pytest.approx(80e-6, rel=1e-12)
    assert design.mesh.stiffness_harmonics == pytest.approx([5.2e7, 1.1e7], rel=1e-12)
    assert design.mesh.stiffness_phases == pytest.approx([0.0, math.radians(30)], rel=1e-12)
    assert design.operating.speed == pytest.approx(1500 * 2 * math.pi / 60, rel=1e-12)
    assert design.operating.torque == 60.0


def test_valid_design_loads_from_a_str_path(tmp_path):
    path = write(tmp_path, BASE)
    assert load_design(str(path)) == load_design(path)


# --- rules on single fields --------------------------------------------------------------


def test_negative_mass(tmp_path):
    err, path = load_error(tmp_path, ('mass = "1.25 kg"', 'mass = "-642 g"'))
    problem = only_problem(err, path)
    assert_names(problem, path, "pinion.mass", "-642 g", "must be greater than 0")


@pytest.mark.parametrize("value", [0, "0 kg*m^2"], ids=["plain", "with-unit"])
def test_zero_moment_of_inertia(tmp_path, value):
    written = f'"{value}"' if isinstance(value, str) else str(value)
    err, path = load_error(
        tmp_path,
        ('moment_of_inertia = "3.9e7 g*mm^2"', f"moment_of_inertia = {written}"),
    )
    problem = only_problem(err, path)
    assert_names(problem, path, "gear.moment_of_inertia", value, "must be greater than 0")


def test_non_integer_tooth_number(tmp_path):
    err, path = load_error(tmp_path, ("teeth = 25", "teeth = 25.5"))
    problem = only_problem(err, path)
    assert_names(problem, path, "pinion.teeth", 25.5, "must be an integer")


def test_tooth_number_given_as_a_string(tmp_path):
    err, path = load_error(tmp_path, ("teeth = 60", 'teeth = "60"'))
    problem = only_problem(err, path)
    assert_names(problem, path, "gear.teeth", "60", "must be an integer")


def test_zero_tooth_number(tmp_path):
    err, path = load_error(tmp_path, ("teeth = 25", "teeth = 0"))
    problem = only_problem(err, path)
    assert_names(problem, path, "pinion.teeth", 0, "must be greater than 0")


def test_pressure_angle_out_of_range(tmp_path):
    err, path = load_error(tmp_path, ('pressure_angle = "20 deg"', 'pressure_angle = "60 deg"'))
    problem = only_problem(err, path)
    assert_names(problem, path, "mesh.pressure_angle", "60 deg", "out of range", "(0°, 45°)")


def test_pressure_angle_plain_number_is_read_as_radians(tmp_path):
    err, path = load_error(tmp_path, ('pressure_angle = "20 deg"', "pressure_angle = 20"))
    problem = only_problem(err, path)
    assert_names(
        problem,
        path,
        "mesh.pressure_angle",
        20,
        "out of range",
        "(0°, 45°)",
        "a plain number is read as radians",
        "'25 deg'",
    )


@pytest.mark.parametrize(
    ("written", "shown"),
    [('"60 deg"', "angle 60°"), ("20", "angle 1145.92°")],
    ids=["60-deg", "20-rad"],
)
def test_pressure_angle_message_shows_the_angle_in_degrees(tmp_path, written, shown):
    err, path = load_error(tmp_path, ('pressure_angle = "20 deg"', f"pressure_angle = {written}"))
    problem = only_problem(err, path)
    assert "{deg" not in problem
    assert shown in problem


@pytest.mark.parametrize(
    ("anchor", "field", "allowed"),
    [
        (
            "[pinion]\n",
            "pinion.mas",
            "bearing, errors, mass, modifications, moment_of_inertia, shift, teeth",
        ),
        (
            "[pinion.bearing]\n",
            "pinion.bearing.mas",
            "damping_x, damping_y, stiffness_x, stiffness_y",
        ),
        (
            'type = "gear_pair"\n',
            "mas",
            "check, description, gear, material, mesh, name, operating, pinion, report, type",
        ),
    ],
    ids=["pinion", "bearing", "top-level"],
)
def test_unknown_field(tmp_path, anchor, field, allowed):
    err, path = load_error(tmp_path, (anchor, f'{anchor}mas = "1 kg"\n'))
    problem = only_problem(err, path)
    assert_names(problem, path, field, "1 kg", "unknown field", f"(allowed: {allowed})")


def test_wrong_dimension(tmp_path):
    err, path = load_error(tmp_path, ('stiffness = "3.8e8 N/m"', 'stiffness = "5 kg"'))
    problem = only_problem(err, path)
    assert_names(
        problem,
        path,
        "mesh.stiffness",
        "5 kg",
        "wrong dimension",
        "expected a stiffness",
        "'2.2e8 N/m'",
    )


def test_wrong_dimension_inside_a_list(tmp_path):
    err, path = load_error(
        tmp_path,
        ('["5.2e7 N/m", "1.1e7 N/m"]', '["5.2e7 N/m", "1.1e7 kg"]'),
    )
    problem = only_problem(err, path)
    assert_names(
        problem, path, "mesh.stiffness_harmonics.1", "1.1e7 kg", "wrong dimension", "stiffness"
    )


def test_unparsable_unit(tmp_path):
    err, path = load_error(tmp_path, ('module = "3 mm"', 'module = "3 mmm"'))
    problem = only_problem(err, path)
    assert_names(
        problem,
        path,
        "mesh.module",
        "3 mmm",
        "cannot read '3 mmm' as a length",
        "'mmm' is not defined",
        "'39.5 mm'",
    )


def test_hz_for_a_speed(tmp_path):
    err, path = load_error(tmp_path, ('speed = "1500 rpm"', 'speed = "25 Hz"'))
    problem = only_problem(err, path)
    assert_names(problem, path, "operating.speed", "25 Hz", "Hz is ambiguous", "rpm")


def test_boolean_quantity(tmp_path):
    err, path = load_error(tmp_path, ('mass = "6.8 kg"', "mass = true"))
    problem = only_problem(err, path)
    assert_names(problem, path, "gear.mass", True, "not a boolean")


def test_missing_required_field(tmp_path):
    err, path = load_error(tmp_path, ('mass = "1.25 kg"\n', ""))
    problem = only_problem(err, path)
    assert problem == f"{path}: pinion.mass: required field is missing"


def test_missing_required_section(tmp_path):
    section = BASE[BASE.index("[mesh]") : BASE.index("[operating]")]
    err, path = load_error(tmp_path, (section, ""))
    problem = only_problem(err, path)
    assert problem == f"{path}: mesh: required field is missing"


# --- the drive type ----------------------------------------------------------------------


def test_unknown_drive_type(tmp_path):
    err, path = load_error(tmp_path, ('type = "gear_pair"', 'type = "planetary"'))
    problem = only_problem(err, path)
    assert_names(problem, path, "type", "planetary", "unknown drive type", "one of: gear_pair")


def test_missing_drive_type(tmp_path):
    err, path = load_error(tmp_path, ('type = "gear_pair"\n', ""))
    problem = only_problem(err, path)
    assert problem.startswith(f"{path}: type: required field is missing")
    assert "one of: gear_pair" in problem


@pytest.mark.parametrize("written", ['["gear_pair"]', "{ name = 1 }"], ids=["list", "table"])
def test_drive_type_that_is_not_a_string(tmp_path, written):
    err, path = load_error(tmp_path, ('type = "gear_pair"', f"type = {written}"))
    problem = only_problem(err, path)
    assert "type" in problem
    assert "gear_pair" in problem


# --- the file itself ---------------------------------------------------------------------


def test_invalid_toml_syntax(tmp_path):
    err, path = load_error(tmp_path, ("teeth = 25", "teeth = = 25"))
    problem = only_problem(err, path)
    assert "not valid TOML" in problem
    assert "line 8" in problem


def test_nonexistent_file(tmp_path):
    path = tmp_path / "no_such_design.toml"
    with pytest.raises(DesignError) as exc:
        load_design(path)
    problem = only_problem(exc.value, path)
    assert problem == f"{path}: no such design file"


# --- cross-field rules of gear_pair.py ---------------------------------------------------


def test_stiffness_phases_count_mismatch(tmp_path):
    err, path = load_error(tmp_path, ('["0 deg", "30 deg"]', '["0 deg"]'))
    problem = only_problem(err, path)
    assert problem.startswith(f"{path}: mesh.stiffness_phases: "), problem
    assert "has 1 entries but stiffness_harmonics has 2" in problem
    assert "one phase per harmonic or none" in problem


def test_no_phases_is_allowed(tmp_path):
    path = write(tmp_path, edited(('["0 deg", "30 deg"]', "[]")))
    design = load_design(path)
    assert design.mesh.stiffness_phases == []
    assert len(design.mesh.stiffness_harmonics) == 2


@pytest.mark.parametrize(
    "edit",
    [('speed = "1500 rpm"', "speed = 0"), ('speed = "1500 rpm"', 'speed = "-100 rpm"')],
    ids=["zero", "negative"],
)
def test_harmonics_need_a_positive_speed(tmp_path, edit):
    err, path = load_error(tmp_path, edit)
    problem = only_problem(err, path)
    assert "mesh.stiffness_harmonics need operating.speed > 0" in problem


def test_harmonics_need_a_speed_when_operating_is_omitted(tmp_path):
    err, path = load_error(tmp_path, (OPERATING, ""))
    problem = only_problem(err, path)
    assert "mesh.stiffness_harmonics need operating.speed > 0" in problem


def test_no_harmonics_need_no_speed(tmp_path):
    path = write(
        tmp_path,
        edited(
            ('stiffness_harmonics = ["5.2e7 N/m", "1.1e7 N/m"]\n', ""),
            ('stiffness_phases = ["0 deg", "30 deg"]\n', ""),
            (OPERATING, ""),
        ),
    )
    design = load_design(path)
    assert design.operating.speed == 0.0
    assert design.mesh.stiffness_harmonics == []


def test_harmonics_summing_above_the_mean(tmp_path):
    err, path = load_error(tmp_path, ('["5.2e7 N/m", "1.1e7 N/m"]', '["3e8 N/m", "1e8 N/m"]'))
    problem = only_problem(err, path)
    assert problem.startswith(f"{path}: mesh.stiffness_harmonics: "), problem
    assert "add up to 4e+08 N/m" in problem
    assert "more than the mean stiffness 3.8e+08 N/m" in problem


def test_harmonics_equal_to_the_mean_are_allowed(tmp_path):
    # k(t) then touches zero once per period but never becomes negative
    path = write(tmp_path, edited(('["5.2e7 N/m", "1.1e7 N/m"]', '["3.8e8 N/m", "0 N/m"]')))
    assert sum(load_design(path).mesh.stiffness_harmonics) == pytest.approx(3.8e8)


# --- several problems at once ------------------------------------------------------------


def test_several_problems_are_reported_in_one_error(tmp_path):
    edits = [
        ('mass = "1.25 kg"', 'mass = "-642 g"'),
        ("teeth = 60", "teeth = 60.5"),
        ('stiffness = "3.8e8 N/m"', 'stiffness = "5 kg"'),
        ('module = "3 mm"', 'module = "3 mmm"'),
        ("[operating]\n", "[operating]\nrpm = 1500\n"),
        ('moment_of_inertia = "1.10e6 g*mm^2"\n', ""),
    ]
    err, path = load_error(tmp_path, *edits)
    expected = [
        ("pinion.mass = '-642 g': ", "must be greater than 0"),
        ("pinion.moment_of_inertia: ", "required field is missing"),
        ("gear.teeth = 60.5: ", "must be an integer"),
        ("mesh.stiffness = '5 kg': ", "wrong dimension"),
        ("mesh.module = '3 mmm': ", "cannot read"),
        ("operating.rpm = 1500: ", "unknown field"),
    ]
    assert len(err.problems) == len(expected), err.problems
    for head, rule in expected:
        matches = [p for p in err.problems if p.startswith(f"{path}: {head}")]
        assert len(matches) == 1, (head, err.problems)
        assert rule in matches[0]
    message = str(err)
    for problem in err.problems:
        assert problem in message


def test_field_and_cross_field_problems_are_reported_together(tmp_path):
    err, path = load_error(
        tmp_path,
        ('mass = "1.25 kg"', 'mass = "-642 g"'),
        ('["0 deg", "30 deg"]', '["0 deg"]'),
    )
    assert len(err.problems) == 2, err.problems
    assert err.problems[0].startswith(f"{path}: pinion.mass = '-642 g': ")
    assert err.problems[1].startswith(f"{path}: mesh.stiffness_phases: has 1 entries")


# --- design_from_dict --------------------------------------------------------------------


@pytest.mark.parametrize("data", [["gear_pair"], "gear_pair", None, 3], ids=repr)
def test_design_from_dict_rejects_a_non_mapping(data):
    with pytest.raises(DesignError) as exc:
        design_from_dict(data, "src.toml")
    assert str(exc.value) == (
        f"src.toml: a design must be a table of fields, got {type(data).__name__}"
    )


def test_design_from_dict_names_the_default_source():
    with pytest.raises(DesignError) as exc:
        design_from_dict({"type": "gear_pair"})
    assert len(exc.value.problems) == 3, exc.value.problems
    for field in ("pinion", "gear", "mesh"):
        assert f"<design>: {field}: required field is missing" in exc.value.problems
