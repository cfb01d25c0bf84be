"""analysis.gear_bodies: element sizes of a gear body's mesh from the sizes given."""

from __future__ import annotations

import pytest

from reducerlab.analysis.gear_bodies import body_mesh_sizes
from reducerlab.drives import load_design
from reducerlab.examples import example_dir
from reducerlab.fe.gear_mesh import MeshSizes


@pytest.fixture(scope="module")
def design():
    return load_design(example_dir() / "nutation_surface.toml")


def test_default_mesh_without_sizes(design):
    assert body_mesh_sizes(design, 1) is None


def test_a_size_not_given_is_the_default_and_the_blank_never_finer(design):
    crown, _ = design.tooth_generation(2)
    default = MeshSizes.default(crown.profile.module)
    assert body_mesh_sizes(design, 2, tooth=1e-3) == MeshSizes(1e-3, max(default.body, 1e-3))
    coarse = 2 * default.body
    assert body_mesh_sizes(design, 2, tooth=coarse) == MeshSizes(coarse, coarse)
    assert body_mesh_sizes(design, 2, body=5e-3) == MeshSizes(default.tooth, 5e-3)
    assert body_mesh_sizes(design, 2, tooth=coarse, body=1e-3) == MeshSizes(coarse, 1e-3)
