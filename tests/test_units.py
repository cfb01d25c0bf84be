"""Tests of :func:`reducerlab.units.parse_quantity`: numbers and strings with units to SI."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from reducerlab.units import QUANTITIES, parse_quantity

# The first call builds pint's registry (~0.5 s), which would trip hypothesis' deadline.
HYPOTHESIS = settings(deadline=None, max_examples=300)

finite_floats = st.floats(allow_nan=False, allow_infinity=False)


def in_range(kind: str, scale: float = 1.0) -> st.SearchStrategy[float]:
    """0 or a magnitude within the representable range of ``kind`` (SI), over ``scale``."""
    lo, hi = QUANTITIES[kind].lo / scale, QUANTITIES[kind].hi / scale
    return st.one_of(
        st.floats(min_value=lo, max_value=hi),
        st.floats(min_value=-hi, max_value=-lo),
        st.just(0.0),
    )


# --- plain numbers are SI --------------------------------------------------------------


@pytest.mark.parametrize(
    ("value", "kind"),
    [
        (642, "mass"),
        (0.642, "mass"),
        (-3.5, "torque"),
        (0, "damping"),
        (2.2e8, "stiffness"),
        (20, "angle"),  # radians, not degrees
        (157.0796, "angular velocity"),
    ],
)
def test_plain_number_is_taken_as_si(value, kind):
    out = parse_quantity(value, kind)
    assert type(out) is float
    assert out == value


@HYPOTHESIS
@given(v=in_range("stiffness"))
def test_plain_float_is_returned_unchanged(v):
    out = parse_quantity(v, "stiffness")
    assert type(out) is float
    assert out == v
    assert math.copysign(1.0, out) == math.copysign(1.0, v)


@HYPOTHESIS
@given(v=st.integers(min_value=-(10**10), max_value=10**10))
def test_plain_int_becomes_the_same_float(v):
    out = parse_quantity(v, "force")
    assert type(out) is float
    assert out == v


# --- strings with units are converted to SI ----------------------------------------------


@pytest.mark.parametrize(
    ("text", "kind", "si"),
    [
        ("642 g", "mass", 0.642),
        ("1.25 kg", "mass", 1.25),
        ("986900 g*mm^2", "moment of inertia", 9.869e-4),
        ("986900 g*mm**2", "moment of inertia", 9.869e-4),
        ("39.5 mm", "length", 0.0395),
        ("80 um", "length", 80e-6),
        ("2.2e8 N/m", "stiffness", 2.2e8),
        ("220 N/um", "stiffness", 2.2e8),
        ("25 deg", "angle", math.radians(25)),
        ("0.5 rad", "angle", 0.5),
        ("1500 rpm", "angular velocity", 1500 * 2 * math.pi / 60),
        ("10 rad/s", "angular velocity", 10.0),
        ("787 N*s/m", "damping", 787.0),
        ("1.5e5 N*m/rad", "torsional stiffness", 1.5e5),
        ("2 N*m*s/rad", "torsional damping", 2.0),
        ("100 N", "force", 100.0),
        ("3 kN", "force", 3000.0),
        ("50 N*m", "torque", 50.0),
        ("7880 Hz", "frequency", 7880.0),
        ("2 ms", "time", 0.002),
        ("0.5", "dimensionless", 0.5),
        ("  642 g  ", "mass", 0.642),
        ("-642 g", "mass", -0.642),  # the sign is a design rule, not a parsing one
    ],
)
def test_string_with_units_is_converted_to_si(text, kind, si):
    out = parse_quantity(text, kind)
    assert type(out) is float
    assert out == pytest.approx(si, rel=1e-12, abs=0)


def test_1500_rpm_is_157_rad_per_s():
    assert parse_quantity("1500 rpm", "angular velocity") == pytest.approx(157.0796, abs=1e-4)


@pytest.mark.parametrize("kind", sorted(QUANTITIES))
def test_every_example_shown_in_messages_parses_as_its_kind(kind):
    spec = QUANTITIES[kind]
    out = parse_quantity(spec.example, kind)
    assert math.isfinite(out)
    assert out > 0


@HYPOTHESIS
@given(v=in_range("mass"))
def test_value_in_kg_round_trips(v):
    out = parse_quantity(f"{v} kg", "mass")
    assert math.isclose(out, v, rel_tol=1e-12, abs_tol=0.0)


@HYPOTHESIS
@given(v=in_range("mass", scale=1e-3))
def test_value_in_grams_is_divided_by_1000(v):
    out = parse_quantity(f"{v} g", "mass")
    assert math.isclose(out, v / 1000, rel_tol=1e-12, abs_tol=0.0)


@HYPOTHESIS
@given(v=in_range("angle", scale=math.pi / 180))
def test_value_in_degrees_is_converted_to_radians(v):
    out = parse_quantity(f"{v} deg", "angle")
    assert math.isclose(out, math.radians(v), rel_tol=1e-12, abs_tol=0.0)


# --- wrong dimension ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "kind", "got"),
    [
        ("5 kg", "stiffness", "[mass]"),
        ("642 g", "length", "[mass]"),
        ("2.2e8 N/m", "damping", "[mass] / [time] ** 2"),
        ("5 kg", "dimensionless", "[mass]"),
        ("25 deg", "mass", "dimensionless"),
        ("5", "mass", "dimensionless"),  # a bare number inside a string has no unit
        ("50 N*m", "force", "[mass] * [length] ** 2 / [time] ** 2"),
    ],
)
def test_wrong_dimension_is_rejected(text, kind, got):
    spec = QUANTITIES[kind]
    with pytest.raises(ValueError, match="wrong dimension") as exc:
        parse_quantity(text, kind)
    msg = str(exc.value)
    assert f"expected a {spec.name}" in msg
    assert repr(spec.example) in msg
    assert f"{text!r} is [{got}]" in msg


def test_wrong_dimension_names_the_expected_dimension():
    with pytest.raises(ValueError) as exc:
        parse_quantity("5 kg", "stiffness")
    assert "wrong dimension: expected a stiffness [[mass] / [time] ** 2]" in str(exc.value)


# --- unreadable text ---------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "culprit"),
    [
        ("1 abc xyz", "'abc' is not defined"),
        ("3 kgg", "'kgg' is not defined"),
        ("3 (((", "TokenError"),
    ],
)
def test_unparsable_text_is_rejected(text, culprit):
    with pytest.raises(ValueError, match="cannot read") as exc:
        parse_quantity(text, "mass")
    msg = str(exc.value)
    assert repr(text) in msg
    assert "mass" in msg
    assert culprit in msg
    assert "'642 g'" in msg


@pytest.mark.parametrize("text", ["", "   "])
def test_empty_string_is_rejected(text):
    with pytest.raises(ValueError, match=r"expected a mass.*empty string"):
        parse_quantity(text, "mass")


@pytest.mark.parametrize("value", [None, [1.0], {"value": 1.0}, b"642 g"])
def test_other_types_are_rejected(value):
    with pytest.raises(ValueError, match="expected a mass as a number") as exc:
        parse_quantity(value, "mass")
    assert type(value).__name__ in str(exc.value)


def test_unknown_kind_is_a_key_error():
    with pytest.raises(KeyError):
        parse_quantity("1 kg", "weight")


# --- Hz for an angular velocity ----------------------------------------------------------


@pytest.mark.parametrize("text", ["25 Hz", "25 hz", "3 kHz", "50 Hz"])
def test_hz_is_rejected_for_an_angular_velocity(text):
    with pytest.raises(ValueError, match="Hz is ambiguous for an angular velocity") as exc:
        parse_quantity(text, "angular velocity")
    assert "rpm" in str(exc.value)


def test_hz_is_accepted_for_a_frequency():
    assert parse_quantity("10 Hz", "frequency") == 10.0


@pytest.mark.parametrize(
    ("text", "si"),
    [
        ("60 rpm", 2 * math.pi),
        ("1 rad/s", 1.0),
        ("1 rev/s", 2 * math.pi),
    ],
)
def test_units_suggested_instead_of_hz_are_accepted(text, si):
    assert parse_quantity(text, "angular velocity") == pytest.approx(si, rel=1e-12)


# --- booleans and non-finite values ------------------------------------------------------


@pytest.mark.parametrize("value", [True, False])
def test_booleans_are_rejected(value):
    with pytest.raises(ValueError, match=r"expected a mass, e\.g\. '642 g', not a boolean"):
        parse_quantity(value, "mass")


@pytest.mark.parametrize(
    "value",
    [math.nan, math.inf, -math.inf, "inf kg", "-inf kg", "nan kg", "1e400 kg"],
)
def test_non_finite_values_are_rejected(value):
    with pytest.raises(ValueError, match="expected a finite mass") as exc:
        parse_quantity(value, "mass")
    assert repr(value) in str(exc.value)


def test_huge_integer_is_rejected_with_a_value_error():
    with pytest.raises(ValueError, match="finite"):
        parse_quantity(10**400, "mass")
