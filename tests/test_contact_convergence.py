"""Defaults are results: the default contact grid of ``contact_analysis`` against the
same analysis on a grid twice as fine (an independent, tighter reference), on the
involute pair of examples/nutation_surface.toml at 3 kW with the default
finite-element tooth models (about a minute: two FE models and four LTCA runs).

docs/contact.md states: mesh stiffness within 1 %, interior peak pressure within 3 %,
maximum subsurface von Mises stress within 10 % of the refinement."""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.analysis.contact import contact_analysis
from reducerlab.drives import load_design


@pytest.fixture(scope="module")
def runs():
    design = load_design("examples/nutation_surface.toml")
    default = contact_analysis(design, 1, power=3000.0, positions=3, order=1)
    fine = contact_analysis(
        design, 1, power=3000.0, positions=3, order=1,
        cell=0.5 * default.data.attrs["cell_m"], face_cell=0.5 * default.data.attrs["face_cell_m"],
        compliance=default.compliance,
    )  # fmt: skip
    return default, fine


def test_default_grid_against_its_refinement(runs):
    default, fine = runs
    a, b = default.data, fine.data
    # k: the elastic approach integrates the whole load distribution (measured 0.5 %)
    assert np.allclose(a["stiffness"], b["stiffness"], rtol=0.01)
    # interior pressure: 10 cells across the patch, a smooth maximum (measured <= 1 %)
    assert np.allclose(a["interior_pressure"], b["interior_pressure"], rtol=0.03)
    # subsurface von Mises: the maximum is sought under the 40 most loaded interior cells,
    # which cover less of the patch on the finer grid (measured 2.9, 3.4 and 7.6 %)
    assert np.allclose(a["von_mises"], b["von_mises"], rtol=0.10)
    # the load balance is exact on any grid
    assert np.allclose(a["normal_force"], b["normal_force"], rtol=0.01)


def test_mesh_stiffness_is_in_the_range_of_gear_practice(runs):
    """An order-of-magnitude oracle: ISO 6336-1's mesh stiffness per face width of solid
    steel spur gears is c_gamma ~ 14-20 N/(mm um); this 10 mm face pair carries about one
    to two tooth pairs, so k along the normal lies within a factor 2 of 14-40 N/um per
    10 mm, i.e. 0.7e8 .. 8e8 N/m."""
    default, _ = runs
    k = float(default.data.attrs["k_mean"])
    assert 0.7e8 < k < 8e8
    assert math.isfinite(float(default.data.attrs["fit_residual"]))
