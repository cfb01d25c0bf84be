"""``type = "lumped"`` designs: any topology from a design file."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from reducerlab.analysis.modal import modal
from reducerlab.drives import build_model, design_from_dict, load_design
from reducerlab.errors import DesignError
from reducerlab.examples import example_dir


def test_torsional_chain_example_against_hand_assembly():
    model = build_model(load_design(example_dir() / "torsional_chain.toml"))
    r = 0.045
    M = np.diag([4.0e-4, 6.0e-5, 2.2e-3 / r**2, 8.0e-3])
    K = np.zeros((4, 4))
    for g, k in (
        (np.array([1.0, -1.0, 0, 0]), 2.5e3),
        (np.array([0, 0.012, 1.0, 0]), 2.4e8),
        (np.array([0, 0, 22.2222222222, -1.0]), 1.8e4),
    ):
        K += k * np.outer(g, g)
    f = np.sqrt(np.clip(scipy.linalg.eigh(K, M, eigvals_only=True), 0, None)) / (2 * math.pi)
    res = modal(model)
    np.testing.assert_allclose(res.frequencies[1:], f[1:], rtol=1e-9)
    assert res.frequencies[0] == 0.0
    law = model.element("mesh").stiffness
    assert law.omega == pytest.approx(16 * 3000 * 2 * math.pi / 60)
    assert model.element("mesh").backlash.half_width == pytest.approx(30e-6)
    np.testing.assert_allclose(model.nonlinear().external_forces(0.0), [2.0, 0, 0, 0])


BASE = {
    "type": "lumped",
    "dofs": [{"body": "a", "kind": "x"}, {"body": "b", "kind": "rz"}],
    "elements": [
        {"type": "inertia", "dof": "a.x", "mass": "2 kg"},
        {"type": "inertia", "dof": "b.rz", "moment_of_inertia": "1e-3 kg*m^2"},
        {"type": "support", "dof": "a.x", "stiffness": "1e6 N/m"},
        {"type": "mesh", "coefficients": {"a.x": 1.0, "b.rz": 0.05}, "stiffness": "1e8 N/m"},
    ],
}


def _with(i, **change):
    els = [dict(e) for e in BASE["elements"]]
    els[i].update(change)
    for k, v in list(els[i].items()):
        if v is None:
            del els[i][k]
    return {**BASE, "elements": els}


def test_valid_lumped_dict():
    model = build_model(design_from_dict(BASE))
    assert model.dof_names == ["a.x", "b.rz"]
    assert modal(model).frequencies.size == 2


@pytest.mark.parametrize(
    ("data", "match"),
    [
        (_with(0, mass=None, moment_of_inertia="1 kg*m^2"), "a.x is a translation: give mass"),
        (_with(1, moment_of_inertia=None, mass="1 kg"), "b.rz is a rotation: give moment_of"),
        (_with(0, moment_of_inertia="1 kg*m^2"), "exactly one of mass or moment_of_inertia"),
        (_with(2, stiffness=None, torsional_stiffness="1 N*m/rad"), "a.x is not a rotation"),
        (_with(2, dof="b.rz"), "b.rz is a rotation: use torsional_stiffness"),
        (_with(2, dof="c.x"), r"unknown DOF \['c.x'\]"),
        (_with(3, harmonics=["1e7 N/m"]), "exactly one of frequency \\(Hz\\) or order"),
        (_with(3, harmonics=["1e7 N/m"], phases=[0, 1], order=3), "phases has 2 entries"),
        (_with(3, stiffness="5 kg"), "wrong dimension"),
        (_with(0, type="spring"), "does not match any of the expected tags"),
        ({**BASE, "dofs": [{"body": "a", "kind": "u"}]}, "needs a radius"),
        ({**BASE, "dofs": [{"body": "a", "kind": "q"}]}, "dofs.0.kind"),
        ({**BASE, "elements": []}, "elements"),
    ],
)
def test_lumped_rules(data, match):
    with pytest.raises(DesignError, match=match):
        build_model(design_from_dict(data, "t.toml"))


def test_model_level_errors_become_design_errors():
    bad = {**BASE, "dofs": [*BASE["dofs"], {"body": "a", "kind": "x"}]}
    with pytest.raises(DesignError, match="duplicate DOF names"):
        build_model(design_from_dict(bad))
