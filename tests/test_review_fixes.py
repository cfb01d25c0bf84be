"""Regression tests for defects found in review: signs, units, speed-following laws,
and bad input that used to escape as raw Python errors."""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.cli import app
from reducerlab.drives import build_model, design_from_dict, load_design
from reducerlab.errors import DesignError, ModelError, ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.kinematics import NutationDrive
from reducerlab.model import (
    Centripetal,
    Constant,
    Dof,
    Fourier,
    Inertia,
    Mesh,
    Model,
    PiecewisePolynomial,
    Support,
)
from reducerlab.units import parse_quantity

runner = CliRunner()


def test_mesh_frequency_follows_the_model_speed():
    model = build_model(load_design(example_dir() / "torsional_chain.toml"))
    w0 = model.speed
    omega0 = model.nonlinear().k_params[0, 1]
    assert omega0 == pytest.approx(16 * w0)
    fast = model.with_speed(2 * w0).nonlinear()
    assert fast.k_params[0, 1] == pytest.approx(2 * omega0)
    rest = model.with_speed(0.0).nonlinear()
    assert rest.k_kind[0] == 0 and rest.k_params[0, 0] == pytest.approx(2.4e8)  # mean
    # a law with a fixed frequency is left alone
    law = Fourier(1.0, (0.1,), 5.0)
    assert law.at_speed(123.0) is law


@pytest.mark.parametrize("text", ["1500 rpm", "100 rad/s", "3 rev/s"])
def test_frequency_refuses_angle_based_units(text):
    with pytest.raises(ValueError, match="a frequency is in Hz"):
        parse_quantity(text, "frequency")


def test_phases_have_a_range():
    data = load_design(example_dir() / "gear_pair.toml").model_dump()
    data["mesh"]["stiffness_phases"] = [0.0, 30.0]  # degrees written without a unit
    with pytest.raises(DesignError, match=r"stiffness_phases\.1 = 30\.0: angle 1718\.87°"):
        design_from_dict(data, "g.toml")


def test_cli_output_is_a_file_and_non_utf8_design(tmp_path):
    f = tmp_path / "afile"
    f.write_text("x")
    r = runner.invoke(app, ["modal", str(example_dir() / "gear_pair.toml"), "-o", str(f)])
    assert r.exit_code == 2 and "Traceback" not in r.output and "error" in r.output
    bad = tmp_path / "latin1.toml"
    bad.write_bytes('name = "Zahnrad \xe4"\n'.encode("latin-1"))
    r = runner.invoke(app, ["modal", str(bad)])
    assert r.exit_code == 2 and "not a text file in UTF-8" in r.output


def test_huge_speed_is_a_design_error():
    with pytest.raises(DesignError, match=r"input_speed = 1e\+200: .*outside the range of an ang"):
        design_from_dict(
            {"type": "kinematics", "drive": "khv", "input_speed": 1e200,
             "teeth": {"planet": 30, "ring": 33}}
        )  # fmt: skip


def test_lumped_empty_coefficients_and_nan_ratio():
    base = {
        "type": "lumped",
        "dofs": [{"body": "a", "kind": "x"}],
        "elements": [
            {"type": "inertia", "dof": "a.x", "mass": 1.0},
            {"type": "coupling", "coefficients": {}, "stiffness": 1.0},
        ],
    }
    with pytest.raises(DesignError, match=r"elements\.1\.coefficients"):
        design_from_dict(base)
    base["elements"][1] = {"type": "centripetal", "dof": "a.x", "mass": 1.0, "ratio": math.nan}
    with pytest.raises(DesignError, match="ratio"):
        design_from_dict(base)


def test_kinematics_contact_only_for_nutation_drives():
    with pytest.raises(DesignError, match="has no bevel contact type"):
        design_from_dict(
            {"type": "kinematics", "drive": "khv", "input_speed": 1.0, "contact": "external",
             "teeth": {"planet": 30, "ring": 33}}
        )  # fmt: skip


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: Mesh({"a.x": math.nan}, stiffness=1.0), "coefficient of 'a.x' must be a finite"),
        (lambda: Mesh({"a.x": "1"}, stiffness=1.0), "must be a finite number"),
        (lambda: PiecewisePolynomial(1.0, (), ((1.0,),)), "at least one piece"),
        (lambda: PiecewisePolynomial(1.0, (0.0,), ((1.0,), (1.0, 2.0))), "numbers"),
        (lambda: PiecewisePolynomial(1.0, (0.0, math.nan), ((1,), (2,))), "finite"),
        (lambda: Inertia("a.x", "heavy"), "value must be a finite number > 0"),
        (lambda: Support("a.x", "stiff"), "finite number >= 0"),
        (lambda: Constant(None), "finite numbers"),
        (lambda: Dof("a", "u", radius=math.inf), "needs a radius > 0"),
        (lambda: Dof("a", "u", radius="x"), "needs a radius > 0"),
        (lambda: Fourier(1.0, (0.1,), "fast"), "must be numbers"),
    ],
)
def test_api_bad_input_is_a_model_error(build, match):
    with pytest.raises(ModelError, match=match):
        build()


def test_fourier_accepts_numpy_phases_and_centripetal_needs_a_translation():
    law = Fourier(1.0, np.array([0.1, 0.2]), 3.0, np.array([0.0, 0.5]))
    assert law.phases == (0.0, 0.5)
    m = Model([Dof("a", "rz")], [Inertia("a.rz", 1.0), Centripetal("a.rz", 1.0)], speed=10.0)
    with pytest.raises(ModelError, match="centripetal terms act on translations"):
        m.matrices()
    with pytest.raises(ReducerlabError, match="nutation angle must be a number"):
        NutationDrive(59, 60, "5")


@pytest.mark.parametrize(
    ("example", "where"),
    [("gear_pair.toml", ("operating",)), ("nutation_double_sided.toml", ()),
     ("khv.toml", ()), ("cycloid_ball.toml", ()), ("torsional_chain.toml", ())],
)  # fmt: skip
def test_every_speed_range_is_checked(example, where):
    data = load_design(example_dir() / example).model_dump()
    node = data
    for key in where:
        node = node[key]
    node["speed_range"] = [300.0, 100.0]
    with pytest.raises(DesignError, match="speed_range: must be \\[min, max\\]"):
        design_from_dict(data, example)
