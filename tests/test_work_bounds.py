"""Work and memory are bounded before the work starts (issue 26, items 2 and 4): the
contact grid, the finite-element meshes of gear bodies and tooth compliance, the load of
a contact analysis and the body geometry are estimated or checked from the inputs, and a
job beyond its bound is refused with the estimate, the limit and the setting, before
any allocation, meshing or solving."""

from __future__ import annotations

import time

import pytest
from typer.testing import CliRunner

from reducerlab.analysis.body_modal import body_estimate, body_modal, gear_blank
from reducerlab.analysis.contact import check_load, contact_analysis, contact_pair
from reducerlab.analysis.gear_bodies import gear_body_modes
from reducerlab.budget import MEMORY_ENV
from reducerlab.cli import app
from reducerlab.cli.output import count_text
from reducerlab.contact import compliance as compliance_module
from reducerlab.contact.ltca import (
    MAX_CANDIDATES,
    MAX_GRID_CELLS,
    ContactGrid,
    candidate_estimate,
    grid_estimate,
)
from reducerlab.drives import load_design
from reducerlab.errors import BudgetError, DesignError, ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.fe import gear_mesh
from reducerlab.fe.gear_mesh import MAX_DOFS, MeshError, MeshSizes

EXAMPLE = example_dir() / "nutation_surface.toml"
DESIGN = load_design(EXAMPLE)
runner = CliRunner()


@pytest.fixture
def no_work(monkeypatch):
    """Meshing and the finite-element compliance fail the test if they start."""

    def started(*args, **kwargs):
        raise AssertionError("the work started before the refusal")

    monkeypatch.setattr(gear_mesh, "_mesh_gear", started)
    monkeypatch.setattr(compliance_module, "flank_influence", started)
    monkeypatch.delenv(MEMORY_ENV, raising=False)


@pytest.fixture(scope="module")
def pair():
    return contact_pair(DESIGN, 1)


# ------------------------------------------------------------------ gear-body meshes


def test_tiny_tooth_size_is_refused_before_meshing(no_work, tmp_path):
    t0 = time.perf_counter()
    r = runner.invoke(app, ["body-modal", str(EXAMPLE), "--tooth-size", "0.01 mm",
                            "-o", str(tmp_path / "o")])  # fmt: skip
    assert r.exit_code == 2, r.output
    msg = " ".join(r.output.split())
    assert "Traceback" not in msg
    assert "DOFs exceeds the limit of 3e+06 DOFs" in msg and "--tooth-size" in msg
    assert "quadratic tetrahedra (0.01 mm in the teeth" in msg
    assert time.perf_counter() - t0 < 60  # design loading and tooth generation only


def test_body_memory_beyond_the_limit_names_estimate_limit_and_sizes(no_work, monkeypatch):
    monkeypatch.setenv(MEMORY_ENV, "100M")
    with pytest.raises(BudgetError) as info:
        body_modal(DESIGN, 2, count=2)
    msg = str(info.value)
    # the default solution is by cyclic symmetry (hundreds of MiB for this gear), the
    # whole mesh's needs GiB
    assert "MiB of memory" in msg and "100 MiB" in msg and MEMORY_ENV in msg
    assert "--tooth-size" in msg and "gear2.blank.rim" in msg and "DOFs" in msg
    assert "cyclic symmetry" in msg
    with pytest.raises(BudgetError, match="GiB of memory"):
        body_modal(DESIGN, 2, count=2, method="full")


def test_every_body_is_estimated_before_the_first_is_meshed(no_work, monkeypatch):
    monkeypatch.setenv(MEMORY_ENV, "100M")
    with pytest.raises(BudgetError, match="gear 1 body"):
        gear_body_modes(DESIGN)


def test_thick_rim_counts_in_the_estimate():
    thin = body_estimate(DESIGN, 1)
    thick = body_estimate(DESIGN.with_values({"gear1.blank": {"rim": 0.1}}), 1)
    assert thick.work > 3 * thin.work and thick.memory > 3 * thin.memory
    assert thin.work < MAX_DOFS


# ------------------------------------------------------------------ the body geometry


def test_rim_past_the_axis_of_an_external_gear_names_the_field(no_work):
    d = DESIGN.with_values({"gear2.blank": {"rim": 0.1}})
    with pytest.raises(DesignError) as info:
        gear_blank(d, 2)
    msg = str(info.value)
    assert msg.startswith("gear2.blank.rim = '100 mm': ")
    assert "reaches past the axis" in msg and "at most" in msg
    with pytest.raises(DesignError, match=r"surface\.rim = '100 mm'"):
        gear_blank(DESIGN.with_values({"surface.rim": 0.1}), 2)
    # the internal gear's rim grows outward: no axis to reach
    assert gear_blank(DESIGN.with_values({"gear1.blank": {"rim": 0.1}}), 1)[0] == 0.1


def test_rim_past_the_axis_on_the_command_line(no_work, tmp_path):
    r = runner.invoke(app, ["body-modal", str(EXAMPLE), "-g", "2", "--set",
                            "gear2.blank.rim=100 mm", "-o", str(tmp_path / "o")])  # fmt: skip
    assert r.exit_code == 2, r.output
    msg = " ".join(r.output.split())
    assert "Traceback" not in msg and "Could not revolve" not in msg
    assert "gear2.blank.rim = '100 mm'" in msg and "past the axis" in msg


def test_any_gmsh_failure_names_the_gear_and_its_body_fields(monkeypatch):
    """A failure gmsh raises where no stage catches it (here forced in the revolve of
    the ring) is a ReducerlabError naming the gear and its body fields."""
    import gmsh

    def fail(*args, **kwargs):
        raise Exception("Could not revolve")

    monkeypatch.setattr(gmsh.model.occ, "revolve", fail)
    # an earlier test in this process may have built this sector solid: its cache
    # (fe.gear_mesh) would skip the revolve; start from an empty one
    from reducerlab.fe import gear_mesh

    monkeypatch.setattr(gear_mesh._SOLIDS, "items", {})
    coarse = MeshSizes(0.85 * 2e-3, 2.5 * 2e-3)
    with pytest.raises(MeshError) as info:
        body_modal(DESIGN, 2, count=2, sizes=coarse, convergence=False)
    msg = str(info.value)
    assert "gear 2 body (rim = 4 mm" in msg and "gear2.blank" in msg
    assert "gmsh failed (Could not revolve)" in msg
    assert not gmsh.isInitialized()


# ------------------------------------------------------------------ contact analysis


def test_tiny_cell_is_refused_before_any_work(no_work, tmp_path):
    t0 = time.perf_counter()
    r = runner.invoke(app, ["contact", str(EXAMPLE), "--power", "3 kW", "--cell", "1e-4 mm",
                            "-o", str(tmp_path / "o")])  # fmt: skip
    assert r.exit_code == 2, r.output
    msg = " ".join(r.output.split())
    assert "Traceback" not in msg
    assert "fine cells exceeds the limit of 1e+06 fine cells" in msg and "--cell" in msg
    assert time.perf_counter() - t0 < 60


def test_contact_grid_memory_names_estimate_limit_and_cell(no_work, monkeypatch, pair):
    monkeypatch.setenv(MEMORY_ENV, "10M")
    est = grid_estimate(pair, ContactGrid(0.01e-3))
    assert 4e5 < est.work < MAX_GRID_CELLS  # 4.35 mm x 11.2 mm at 0.01 mm
    with pytest.raises(BudgetError) as info:
        contact_analysis(DESIGN, 1, torque=19.1, cell=0.01e-3, rigid=True)
    msg = str(info.value)
    assert "MiB of memory" in msg and "10 MiB" in msg and "--cell" in msg


def test_fe_tooth_compliance_is_estimated_before_meshing(no_work):
    with pytest.raises(BudgetError) as info:
        contact_analysis(DESIGN, 1, torque=19.1, tooth_size=0.01e-3)
    msg = str(info.value)
    assert "tooth compliance" in msg and "DOFs exceeds" in msg and "--tooth-size" in msg


def test_candidate_cells_are_bounded_before_the_dense_matrix(monkeypatch):
    monkeypatch.setenv(MEMORY_ENV, "1G")
    candidate_estimate(2000, 0.0).check()  # 32 MB
    with pytest.raises(BudgetError, match=r"would need about .* GiB.*--cell.*--power"):
        candidate_estimate(30_000, 0.0).check()
    monkeypatch.delenv(MEMORY_ENV)
    with pytest.raises(BudgetError, match="candidate cells exceeds the limit"):
        candidate_estimate(MAX_CANDIDATES + 1, 0.0).check()


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"power": 1e10}, r"power: 1e\+10 W at 1500 rpm .* at most 7\.\d+e\+05 W"),
        ({"torque": 1e6}, r"torque: 1e\+06 N m on the external gear .* at most 4\d{3} N m"),
    ],
)
def test_a_load_no_elastic_contact_carries_is_refused_before_work(no_work, kwargs, message):
    t0 = time.perf_counter()
    with pytest.raises(ReducerlabError, match=message):
        contact_analysis(DESIGN, 1, **kwargs)
    assert time.perf_counter() - t0 < 20


def test_the_load_bound_leaves_ordinary_loads_alone(pair):
    # paper 001's 3 kW at 1500 rpm: 19.1 N m, 250 times below the bound
    check_load(pair, 19.1, 0.0286878, 112.5e9, 157.08, True)
    check_load(pair, 19.1 * 200, 0.0286878, 112.5e9, 157.08, True)
    with pytest.raises(ReducerlabError, match="yield everywhere"):
        check_load(pair, 19.1 * 300, 0.0286878, 112.5e9, 157.08, True)


# ------------------------------------------------------------------ progress display


def test_a_progress_bar_without_total_shows_no_counter():
    assert count_text(0, None) == ""
    assert count_text(3, 24) == "3/24"


def test_whole_gear_surface_mesh_is_estimated_before_patterning(monkeypatch):
    from reducerlab.geometry.solid import build_gear_solid, section_counts

    crown, bevel = DESIGN.tooth_generation(2)
    solid = build_gear_solid(crown, bevel, **section_counts(5), rim=DESIGN.surface.rim)
    est = solid.gear_mesh_estimate()
    monkeypatch.setenv(MEMORY_ENV, "10K")
    with pytest.raises(BudgetError) as info:
        solid.gear_mesh()
    msg = str(info.value)
    assert "whole gear's triangle mesh (26 teeth)" in msg and "--points or --tooth" in msg
    assert f"{est.work:.3g} vertices" in msg and "10 KiB" in msg
    monkeypatch.delenv(MEMORY_ENV)
    assert len(solid.gear_mesh().vertices) == est.work  # the estimate is exact


def test_check_bodies_refuses_before_meshing_any_gear(no_work, monkeypatch, tmp_path):
    monkeypatch.setenv(MEMORY_ENV, "100M")
    r = runner.invoke(app, ["check", str(EXAMPLE), "--bodies"])
    assert r.exit_code == 2, r.output
    msg = " ".join(r.output.split())
    assert "gear 1 body" in msg and "100 MiB" in msg and "--tooth-size" in msg
    assert "Traceback" not in msg
