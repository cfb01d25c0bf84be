"""Issue 13, design-file and API input: no silent wrong values, no tracebacks.

Each test fails without its fix: bare units read as 1, 1/time speeds read per radian,
torque units taken for torsional stiffness, byte-order marks and deep nesting, finite
but absurd magnitudes, lax coercions (``true`` as 1.0, ``"yes"`` as true), errors of
rules between fields reported without the field, and negative Fourier stiffness laws
accepted through the Python API.
"""

from __future__ import annotations

import math
import re
import tomllib

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reducerlab.design_files import MAX_DESIGN_BYTES, read_toml
from reducerlab.drives import design_from_dict, load_design
from reducerlab.errors import DesignError, ModelError
from reducerlab.examples import example_files
from reducerlab.model import Constant, Fourier, Mesh, PiecewisePolynomial
from reducerlab.units import QUANTITIES, parse_quantity

EXAMPLES = {p.name: p for p in example_files()}


def _example(name: str) -> dict:
    return tomllib.loads(EXAMPLES[name].read_text())


def _problems(data: dict, source: str = "f.toml") -> list[str]:
    with pytest.raises(DesignError) as exc:
        design_from_dict(data, source)
    return exc.value.problems


# --- 1. a unit without a number ----------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "kind"),
    [("kg", "mass"), ("N/m", "stiffness"), ("rpm", "angular velocity"), ("mm", "length")],
)
def test_a_bare_unit_is_refused_not_read_as_one(text, kind):
    spec = QUANTITIES[kind]
    with pytest.raises(ValueError, match="a number is missing") as exc:
        parse_quantity(text, kind)
    assert spec.name in str(exc.value) and repr(spec.example) in str(exc.value)


def test_a_bare_unit_in_a_design_names_the_field():
    data = _example("gear_pair.toml")
    data["pinion"]["mass"] = "kg"
    (line,) = _problems(data)
    assert line.startswith("f.toml: pinion.mass = 'kg': ") and "a number is missing" in line


# --- 2. angle units: speeds, torsional stiffness, frequencies ------------------------------


@pytest.mark.parametrize("text", ["1500 min^-1", "1500 1/min", "25 1/s", "25 /s", "3 kHz"])
def test_pure_reciprocal_time_is_refused_for_an_angular_velocity(text):
    with pytest.raises(ValueError, match="ambiguous for an angular velocity") as exc:
        parse_quantity(text, "angular velocity")
    assert "'rpm', 'rev/s' or 'rad/s'" in str(exc.value)


@pytest.mark.parametrize(
    ("text", "si"),
    [
        ("1500 rpm", 1500 * 2 * math.pi / 60),
        ("25 rps", 25 * 2 * math.pi),
        ("25 rev/s", 25 * 2 * math.pi),
        ("25 turn/s", 25 * 2 * math.pi),
        ("90 deg/s", math.pi / 2),
        ("10 rad/s", 10.0),
        ("1500 rev/min", 1500 * 2 * math.pi / 60),
    ],
)
def test_speeds_with_an_angle_unit_are_converted(text, si):
    assert parse_quantity(text, "angular velocity") == pytest.approx(si, rel=1e-12)


@pytest.mark.parametrize(
    ("text", "kind", "si"),
    [
        ("1.5e5 N*m/rad", "torsional stiffness", 1.5e5),
        ("1.5e5 N*m/deg", "torsional stiffness", 1.5e5 * 180 / math.pi),
        ("2 N*m*s/rad", "torsional damping", 2.0),
        ("50 N*m", "torque", 50.0),
        ("25 deg", "angle", math.radians(25)),
    ],
)
def test_angle_units_in_the_right_power_are_accepted(text, kind, si):
    assert parse_quantity(text, kind) == pytest.approx(si, rel=1e-12)


@pytest.mark.parametrize(
    ("text", "kind"),
    [("1.5e5 N*m", "torsional stiffness"), ("2 N*m*s", "torsional damping")],
)
def test_a_missing_angle_unit_is_refused(text, kind):
    with pytest.raises(ValueError, match="needs an angle unit") as exc:
        parse_quantity(text, kind)
    assert repr(QUANTITIES[kind].example) in str(exc.value)


@pytest.mark.parametrize(
    ("text", "kind", "found", "expected"),
    [
        ("1.5e5 N*m*rad", "torsional stiffness", 1, -1),
        ("1500 rpm*rad", "angular velocity", 2, 1),
        ("3 rad^2/s", "angular velocity", 2, 1),
        ("2 N*m*s/rad^2", "torsional damping", -2, -1),
        ("25 deg^2", "angle", 2, 1),
    ],
)
def test_an_angle_unit_in_the_wrong_power_says_found_and_expected(text, kind, found, expected):
    with pytest.raises(ValueError) as exc:
        parse_quantity(text, kind)
    msg = str(exc.value)
    assert f"to the power {found}, but" in msg and f"needs it to the power {expected}" in msg
    assert "without an angle unit" not in msg


@pytest.mark.parametrize(
    ("text", "kind"),
    [
        ("60 N*m/rad", "torque"),
        ("60 N*m*rad", "torque"),
        ("1 kg*deg", "mass"),
        ("1.25 kg/rad", "mass"),
        ("3 mm/rad", "length"),
        ("3 mm*deg", "length"),
        ("2e8 N/m/rad", "stiffness"),
        ("2 g*mm^2/rad", "moment of inertia"),
        ("2 g*mm^2*rad^2", "moment of inertia"),
        ("787 N*s/m*rad", "damping"),
        ("100 N*rad", "force"),
        ("2 ms*rad", "time"),
        ("0.5 deg", "dimensionless"),
        ("25 Hz*rad", "frequency"),
    ],
)
def test_an_angle_unit_on_a_quantity_without_angle_is_refused(text, kind):
    assert QUANTITIES[kind].angle_power == 0
    with pytest.raises(ValueError, match=r"has an angle unit|angle-based units") as exc:
        parse_quantity(text, kind)
    assert repr(QUANTITIES[kind].example) in str(exc.value) or kind == "frequency"


def test_every_kind_without_rad_in_its_unit_refuses_angle_units():
    for spec in QUANTITIES.values():
        assert spec.angle_power == spec.si_unit.count("rad") * (-1 if "/rad" in spec.si_unit else 1)


def test_a_torque_per_radian_in_a_design_names_the_field():
    data = _example("gear_pair.toml")
    data["operating"]["torque"] = "60 N*m/rad"
    (line,) = _problems(data)
    assert line.startswith("f.toml: operating.torque = '60 N*m/rad': ")
    assert "has an angle unit" in line


# --- numbers: exactly a plain number, then a unit ------------------------------------------


@pytest.mark.parametrize("text", ["1,25 kg", "1,250 kg", "1,000,000 g", "0,5"])
def test_a_decimal_comma_or_thousands_separator_is_refused(text):
    with pytest.raises(ValueError, match=re.escape("write 1.25, not 1,25")):
        parse_quantity(text, "dimensionless" if " " not in text else "mass")


@pytest.mark.parametrize(
    "text",
    [
        "1_000 kg",
        "1 000 kg",
        "1 000",
        "½ kg",
        "1½ kg",
        "1e3e3 kg",
        "1.5.3 kg",
        "\u0661\u0660 kg",  # Arabic-Indic digits
        "1\u0660 kg",
        "\uff11 kg",  # a full-width digit
        "1 kg 2",
        "1 kg*2",
        "1 kg/2",
        "1 2 kg",
        "+ 1 kg",
    ],
)
def test_text_other_than_a_plain_number_and_a_unit_is_refused(text):
    with pytest.raises(ValueError) as exc:
        parse_quantity(text, "mass")
    assert "642 g" in str(exc.value)


@pytest.mark.parametrize(
    ("text", "kind", "si"),
    [
        ("1.25 kg", "mass", 1.25),
        ("-1.25e-3 N", "force", -1.25e-3),
        (".5 kg", "mass", 0.5),
        ("5. kg", "mass", 5.0),
        ("642g", "mass", 0.642),
        ("1500 1/min", "frequency", 25.0),
        ("25 /s", "frequency", 25.0),
        ("986900 g*mm^2", "moment of inertia", 986900e-9),
        ("1E3 mm", "length", 1.0),
        ("0.5", "dimensionless", 0.5),
        ("+2 N*m", "torque", 2.0),
    ],
)
def test_plain_numbers_with_units_are_still_read(text, kind, si):
    assert parse_quantity(text, kind) == pytest.approx(si, rel=1e-12)


def test_a_decimal_comma_in_a_design_names_the_field():
    data = _example("gear_pair.toml")
    data["pinion"]["mass"] = "1,25 kg"
    (line,) = _problems(data)
    assert line.startswith("f.toml: pinion.mass = '1,25 kg': ") and "not 1,25" in line


# --- values shown in messages are cut -----------------------------------------------------


def test_huge_values_are_not_echoed_in_full():
    huge = "x" * 50_000_000
    data = _example("gear_pair.toml")
    data["pinion"]["colour"] = huge
    data["pinion"]["mass"] = "1 " + huge
    with pytest.raises(DesignError) as exc:
        design_from_dict(data, "f.toml")
    assert len(str(exc.value)) < 2000
    assert all("..." in line for line in exc.value.problems)
    with pytest.raises(ValueError) as exc2:
        parse_quantity("1 " + huge, "mass")
    assert len(str(exc2.value)) < 400


@pytest.mark.parametrize("value", [1.5e5, 0.0])
def test_a_plain_number_is_si_for_a_torsional_stiffness(value):
    assert parse_quantity(value, "torsional stiffness") == value


@pytest.mark.parametrize("text", ["3 rev/s", "60 rpm", "2 cycle/s", "6 rad/s"])
def test_a_frequency_refuses_angle_units(text):
    with pytest.raises(ValueError, match="angle-based units are ambiguous"):
        parse_quantity(text, "frequency")


def test_torque_unit_for_a_torsional_stiffness_in_a_design_names_the_field():
    data = _example("torsional_chain.toml")
    i = next(k for k, e in enumerate(data["elements"]) if "torsional_stiffness" in e)
    data["elements"][i]["torsional_stiffness"] = "1.8e4 N*m"
    (line,) = _problems(data)
    assert line.startswith(f"f.toml: elements.{i}.torsional_stiffness = '1.8e4 N*m': ")


# --- 9. byte-order mark, deep nesting ---------------------------------------------------


def test_a_byte_order_mark_is_skipped(tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + EXAMPLES["gear_pair.toml"].read_bytes())
    assert load_design(path).model_dump() == load_design(EXAMPLES["gear_pair.toml"]).model_dump()


@pytest.mark.parametrize("text", ["a = " + "[" * 5000 + "]" * 5000, "a = " + "{b = " * 5000])
def test_deep_nesting_is_a_design_error_naming_the_file(tmp_path, text):
    path = tmp_path / "deep.toml"
    path.write_text(text)
    with pytest.raises(DesignError, match=re.escape(str(path))):
        read_toml(path)


def test_a_directory_or_a_device_is_not_called_missing(tmp_path):
    with pytest.raises(DesignError, match=re.escape(f"{tmp_path}: is a directory")):
        read_toml(tmp_path)
    with pytest.raises(DesignError, match="/dev/zero: is not a regular file"):
        read_toml("/dev/zero")
    with pytest.raises(DesignError, match="no such design file"):
        read_toml(tmp_path / "missing.toml")


def test_a_huge_design_file_is_refused_without_reading_it(tmp_path):
    path = tmp_path / "huge.toml"
    with path.open("wb") as f:  # sparse: 11 MB without writing them
        f.truncate(MAX_DESIGN_BYTES + 1)
    with pytest.raises(DesignError, match=re.escape(f"{path}: larger than 10 MB")):
        read_toml(path)


# --- 10. representable ranges ------------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "kind"),
    [
        (1.7e308, "stiffness"),
        (1e-300, "length"),
        ("1e-300 mm", "length"),
        (1e150, "torque"),
        (1e-300, "moment of inertia"),
        (-1e20, "force"),
        (1e200, "angular velocity"),
    ],
)
def test_absurd_finite_values_are_refused_with_the_range(value, kind):
    spec = QUANTITIES[kind]
    with pytest.raises(ValueError, match="outside the range") as exc:
        parse_quantity(value, kind)
    assert f"[{spec.lo:g}, {spec.hi:g}]" in str(exc.value)


@pytest.mark.parametrize("kind", sorted(QUANTITIES))
def test_range_ends_and_zero_are_accepted(kind):
    spec = QUANTITIES[kind]
    for v in (0.0, spec.lo, spec.hi, -spec.lo, -spec.hi):
        assert parse_quantity(v, kind) == v


@pytest.mark.parametrize(
    ("example", "path", "value"),
    [
        ("cycloid_ball.toml", ("eccentricity",), 1e-300),
        ("khv.toml", ("gears", "module"), "1e-300 mm"),
        ("gear_pair.toml", ("mesh", "stiffness"), 1.7e308),
        ("nutation_double_sided.toml", ("gear1", "mean_radius"), 1e-300),
        ("gear_pair.toml", ("pinion", "teeth"), 10**30),
    ],
)
def test_absurd_values_in_designs_name_file_field_value_and_range(example, path, value):
    data = _example(example)
    parent = data
    for k in path[:-1]:
        parent = parent[k]
    parent[path[-1]] = value
    (line,) = _problems(data)
    assert line.startswith(f"f.toml: {'.'.join(path)} = {value!r}: "), line


def test_every_bundled_example_still_loads():
    tomls = [p for p in EXAMPLES.values() if p.suffix == ".toml"]
    assert tomls
    for path in tomls:
        design = load_design(path)
        assert design.source == str(path) and len(design.hash) == 16


@pytest.mark.parametrize("value", [math.inf, math.nan, 1e300, -1e300, 1e-300])
def test_plain_numbers_that_are_not_quantities_are_bounded(value):
    data = _example("torsional_chain.toml")
    i = next(k for k, e in enumerate(data["elements"]) if "coefficients" in e)
    dof = next(iter(data["elements"][i]["coefficients"]))
    data["elements"][i]["coefficients"][dof] = value
    (line,) = _problems(data)
    assert line.startswith(f"f.toml: elements.{i}.coefficients.{dof}"), line


# --- 18. strict types ------------------------------------------------------------------


@pytest.mark.parametrize("value", ["yes", "no", "on", 1, 0, "true"])
def test_booleans_take_only_true_or_false(value):
    data = _example("cycloid_ball.toml")
    data["centripetal"] = value
    (line,) = _problems(data)
    assert line == f"f.toml: centripetal = {value!r}: must be true or false"


@pytest.mark.parametrize("value", [True, False, "0.5"])
def test_numbers_refuse_booleans_and_strings(value):
    data = _example("khv.toml")
    data["shafts"]["damping_ratio"] = value
    (line,) = _problems(data)
    assert line == f"f.toml: shafts.damping_ratio = {value!r}: must be a number"


def test_quantities_still_read_strings_under_strict_validation():
    design = load_design(EXAMPLES["khv.toml"])
    assert design.input_speed > 0 and design.gears.module < 0.1


def test_a_negative_fourier_stiffness_is_refused_by_the_python_api():
    law = Fourier(mean=1e8, amplitudes=(6e7, 5e7), omega=100.0)
    assert law.lower_bound() == pytest.approx(-1e7)
    with pytest.raises(ModelError, match="must stay >= 0"):
        Mesh({"a.x": 1.0}, stiffness=law)
    Mesh({"a.x": 1.0}, stiffness=Fourier(mean=1e8, amplitudes=(6e7, -4e7), omega=100.0))


def test_lower_bounds_of_the_laws_are_exact():
    assert Constant(3.0).lower_bound() == 3.0
    law = PiecewisePolynomial(period=1.0, breaks=(0.0, 0.5), coefficients=((1.0, -4.0, 4.0),
                              (2.0, 0.0, 0.0)))  # fmt: skip
    assert law.lower_bound() == pytest.approx(0.0, abs=1e-15)  # 1 - 4s + 4s^2 = 0 at s = 1/2
    with pytest.raises(ModelError, match="must stay >= 0"):
        Mesh({"a.x": 1.0}, stiffness=PiecewisePolynomial(1.0, (0.0,), ((1.0, -1.5),)))


# --- 13. rules between fields name the field ---------------------------------------------


@pytest.mark.parametrize(
    ("example", "change", "field"),
    [
        ("nutation_surface.toml", lambda d: d.pop("sides"), "sides"),
        ("gear_pair.toml", lambda d: d["operating"].update(speed=0), "operating.speed"),
        ("khv.toml", lambda d: d.update(input_speed="-5 rpm"), "input_speed"),
        (
            "cycloid_ball.toml",
            lambda d: d["planetary_disc"].update(lobes=7),
            "planetary_disc.lobes",
        ),
        ("khv_kinematics.toml", lambda d: d["teeth"].pop("ring"), "teeth"),
    ],
)
def test_rules_between_fields_name_a_field(example, change, field):
    data = _example(example)
    change(data)
    lines = _problems(data)
    assert any(line.startswith(f"f.toml: {field}") for line in lines), lines
    assert not any("(design)" in line for line in lines), lines


# --- parse_quantity never raises anything but ValueError ---------------------------------

_UNITS = ["", "kg", "g", "m", "mm", "N/m", "rpm", "1/min", "Hz", "deg", "N*m/rad", "rad/s",
          "s", "%", "abc", "(", "**", "^-1", "/", "kg*kg"]  # fmt: skip
_texts = st.one_of(
    st.text(max_size=20),
    st.builds(
        lambda n, u: f"{n} {u}",
        st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-(10**400), 10**400)),
        st.sampled_from(_UNITS),
    ),
)
_values = st.one_of(
    _texts,
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**400), 10**400),
    st.booleans(),
    st.none(),
    st.lists(st.integers(), max_size=2),
)


@settings(deadline=None, max_examples=400)
@given(value=_values, kind=st.sampled_from(sorted(QUANTITIES)))
def test_parse_quantity_gives_a_value_in_range_or_a_value_error(value, kind):
    spec = QUANTITIES[kind]
    try:
        out = parse_quantity(value, kind)
    except ValueError:
        return
    assert isinstance(out, float) and math.isfinite(out)
    assert out == 0 or spec.lo <= abs(out) <= spec.hi
