"""Shared fixtures: small models with closed-form answers."""

from __future__ import annotations

import matplotlib
import pytest

matplotlib.use("Agg")

from reducerlab.model import Dof, Inertia, Mesh, Model, Support


@pytest.fixture
def dask_client():
    """A Dask client on an in-process cluster of one worker (skipped without dask)."""
    distributed = pytest.importorskip("dask.distributed")
    with (
        distributed.LocalCluster(
            n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        yield client


def torsional_pair(J1=2.0e-3, J2=5.0e-2, r1=0.03, r2=0.09, k=3.0e8) -> Model:
    """Two gears coupled only through a mesh on their rotations."""
    return Model(
        [Dof("pinion", "rz"), Dof("gear", "rz")],
        [
            Inertia("pinion.rz", J1),
            Inertia("gear.rz", J2),
            Mesh({"pinion.rz": r1, "gear.rz": r2}, stiffness=k, name="mesh"),
        ],
        name="torsional pair",
    )


def chain(masses, springs, *, grounded=False) -> Model:
    """Spring-mass chain along x; ``springs[i]`` couples mass i and i+1."""
    dofs = [Dof(f"m{i}", "x") for i in range(len(masses))]
    from reducerlab.model import Coupling

    els = [Inertia(f"m{i}.x", m) for i, m in enumerate(masses)]
    els += [
        Coupling({f"m{i}.x": 1.0, f"m{i + 1}.x": -1.0}, k, name=f"k{i}")
        for i, k in enumerate(springs)
    ]
    if grounded:
        els.append(Support("m0.x", springs[0], name="ground"))
    return Model(dofs, els, name="chain")


@pytest.fixture
def pair() -> Model:
    return torsional_pair()


@pytest.fixture
def no_surface_design(tmp_path):
    """The double-sided nutation example with its [surface] table taken out (a design
    whose gear solids cannot be generated)."""
    from reducerlab.examples import example_dir

    text = (example_dir() / "nutation_double_sided.toml").read_text()
    start, end = text.index("[surface]"), text.index("[material]")
    path = tmp_path / "no_surface.toml"
    path.write_text(text[:start] + text[end:])
    return path
