"""The sensitivity and energy maps and the kinematics figure as the report shows them
(issue 32): the parameters the sensitivities cover, the rows and columns the maps keep,
readable text and no touching tick labels."""

from __future__ import annotations

import numpy as np
import pytest

from reducerlab.analysis.modal import frequency_sensitivity, modal
from reducerlab.drives import build_model, load_design
from reducerlab.examples import example_dir
from reducerlab.model.inspect import parameter_paths


def _model(name: str):
    return build_model(load_design(example_dir() / f"{name}.toml"))


@pytest.fixture(scope="module")
def khv():
    model = _model("khv")
    return model, modal(model)


@pytest.fixture(scope="module")
def cycloid():
    model = _model("cycloid_ball")
    res = modal(model)
    return model, res, frequency_sensitivity(model, [p for p, _ in parameter_paths(model)], res)


def test_a_piecewise_mesh_law_is_a_parameter_by_its_mean(khv):
    # the KHV mesh stiffness is a piecewise polynomial (single/double tooth): its mean
    # is derived, and was left out of the parameters; it is the mean mesh stiffness
    model, res = khv
    paths = dict(parameter_paths(model))
    assert "mesh.stiffness" in paths
    k = model.parameter("mesh.stiffness")
    assert paths["mesh.stiffness"] == pytest.approx(k)
    s = frequency_sensitivity(model, ["mesh.stiffness"], res).data["dfdp"].values[:, 0]
    h = 1e-4 * k
    up = modal(model.with_parameter("mesh.stiffness", k + h)).frequencies
    down = modal(model.with_parameter("mesh.stiffness", k - h)).frequencies
    fd = (up - down) / (2 * h)
    elastic = ~res.data["rigid"].values.astype(bool)
    np.testing.assert_allclose(s[elastic], fd[elastic], rtol=1e-3)
    # the law is scaled to the mean, its shape held
    law = model.with_parameter("mesh.stiffness", 2 * k).elements
    law = next(e for e in law if e.name == "mesh").stiffness
    old = next(e for e in model.elements if e.name == "mesh").stiffness
    t = np.linspace(0.0, 2 * old.period, 50)
    np.testing.assert_allclose(law(t), 2 * old(t))
