"""Bad input to the Python API of the model layer: clear errors, not numpy tracebacks."""

from __future__ import annotations

import pytest

from conftest import torsional_pair
from reducerlab.analysis.modal import frequency_sensitivity, mac, modal
from reducerlab.errors import ModelError, ReducerlabError
from reducerlab.model import Coupling, Dof, Inertia, Mesh, Model, Support


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: Dof("a.b", "x"), "must be a name"),
        (lambda: Dof("a", "q"), "kind must be one of"),
        (lambda: Dof("a", "u"), "needs a radius"),
        (lambda: Dof("a", "x", radius=0.1), "only kind 'u' takes a radius"),
        (lambda: Inertia("a.x", -1.0), "value must be a finite number > 0"),
        (lambda: Support("a.x", -5.0), "stiffness must be a finite number >= 0"),
        (lambda: Coupling({}, 1.0), "at least one coefficient"),
        (lambda: Mesh({"a.x": 1.0}, stiffness=0.0), "mean stiffness must be > 0"),
        (lambda: Mesh({"a.x": 1.0}, stiffness="stiff"), "must be a number or a TimeLaw"),
        (lambda: Model([], []), "at least one DOF"),
        (lambda: Model([Dof("a", "x"), Dof("a", "x")], []), "duplicate DOF names"),
        (lambda: Model([Dof("a", "x")], [Support("b.x", 1.0)]), "unknown DOF"),
        (
            lambda: Model([Dof("a", "x")], [Inertia("a.x", 1.0), Inertia("a.x", 2.0)]),
            "duplicate element names",
        ),
        (lambda: Model([Dof("a", "x")], [], speed="fast"), "speed must be a number"),
        (lambda: Model([Dof("a", "x")], ["spring"]), "must be Element objects"),
    ],
)
def test_model_construction_errors(build, match):
    with pytest.raises(ModelError, match=match):
        build()


def test_parameter_path_errors():
    model = torsional_pair()
    with pytest.raises(ModelError, match="elements are"):
        model.parameter("nomesh.stiffness")
    with pytest.raises(ModelError, match=r"has no parameter 'stifness' \(parameters: .*stiffness"):
        model.parameter("mesh.stifness")
    with pytest.raises(ModelError, match="not a scalar parameter"):
        frequency_sensitivity(model, ["mesh.coefficients"])
    with pytest.raises(ReducerlabError, match="at least one parameter"):
        frequency_sensitivity(model, [])
    assert model.with_parameter("mesh.stiffness", 1e8).parameter("mesh.stiffness") == 1e8
    with pytest.raises(ModelError, match="mean stiffness must be > 0"):
        model.with_parameter("mesh.stiffness", -1.0)


def test_modal_argument_errors():
    with pytest.raises(ReducerlabError, match="rigid_tol"):
        modal(torsional_pair(), rigid_tol=-1)
    with pytest.raises(ReducerlabError, match="2-D"):
        mac([1.0, 2.0], [1.0, 2.0])
