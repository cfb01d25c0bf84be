"""Tetrahedral meshes of generated gears (issue 14): closed, conforming, periodic, the
right volume; clear errors for meshes too coarse and blanks that do not fit."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial import cKDTree

from reducerlab.analysis.body_modal import gear_blank
from reducerlab.drives import load_design
from reducerlab.examples import example_dir
from reducerlab.fe.gear_mesh import BlankFeatures, MeshError, MeshSizes, mesh_gear
from reducerlab.geometry.solid import build_gear_solid

DESIGN = load_design(example_dir() / "nutation_double_sided.toml")


def coarse(gear: int) -> MeshSizes:
    """Coarse but valid sizes (the tooth size just under half the tooth depth)."""
    m_n = DESIGN.tooth_generation(gear)[0].profile.module
    return MeshSizes(0.85 * m_n, 2.5 * m_n)


@pytest.fixture(scope="module")
def ring_mesh():
    crown, bevel = DESIGN.tooth_generation(1)
    rim, _ = gear_blank(DESIGN, 1)  # the rim ring alone (the example's gear 1 is a cup)
    return mesh_gear(crown, bevel, rim=rim, sizes=coarse(1))


@pytest.fixture(scope="module")
def web_mesh():
    crown, bevel = DESIGN.tooth_generation(2)
    rim, features = gear_blank(DESIGN, 2)
    return mesh_gear(crown, bevel, rim=rim, features=features, sizes=coarse(2))


def faces_of(tets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    f = np.concatenate([tets[:, [0, 1, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 3]],
                        tets[:, [1, 2, 3]]])  # fmt: skip
    _, counts = np.unique(np.sort(f, axis=1), axis=0, return_counts=True)
    return f, counts


@pytest.mark.parametrize("name", ["ring_mesh", "web_mesh"])
def test_mesh_is_conforming_and_closed(name, request):
    mesh = request.getfixturevalue(name)
    _, counts = faces_of(mesh.tets[:, :4])
    # conforming: every face is shared by one tet (boundary) or two (interior), never more
    assert set(np.unique(counts)) <= {1, 2}
    # every point is used and every tet has positive volume
    assert np.array_equal(np.unique(mesh.tets), np.arange(len(mesh.points)))
    p = mesh.points[mesh.tets[:, :4]]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    assert np.all(vol > 0)


@pytest.mark.parametrize("name", ["ring_mesh", "web_mesh"])
def test_mesh_is_cyclic(name, request):
    """The mesh maps onto itself turned by one angular pitch (every tooth meshed alike)."""
    mesh = request.getfixturevalue(name)
    a = 2 * math.pi / mesh.gear.teeth
    c, s = math.cos(a), math.sin(a)
    q = mesh.points @ np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])
    dist, _ = cKDTree(mesh.points).query(q)
    assert dist.max() < 1e-9


def test_ring_volume_matches_the_independent_solid(ring_mesh):
    """The tet mesh (CAD loft and cut, gmsh) against the structured triangulated solid of
    geometry.solid (an independent construction of the same gear). Straight-sided tets
    of ~2.8 mm on curved cones (R ~ 40 mm) differ by the chord sagitta, ~0.5 %; the
    structured solid's own sampling by ~0.3 %: 1.5 % is a bound on both."""
    crown, bevel = DESIGN.tooth_generation(1)
    rim, _ = gear_blank(DESIGN, 1)
    solid = build_gear_solid(crown, bevel, n_profile=21, n_face=21, n_land=3, n_space=9, rim=rim)
    ref = solid.gear_mesh().volume
    assert ring_mesh.volume == pytest.approx(ref, rel=0.015)


def test_web_adds_the_revolved_volume(web_mesh):
    """Web and hub add their revolved meridional areas (Pappus) less the overlap with the
    rim: the body with a bore weighs more than the ring alone but less than ring + web
    plate + hub counted fully."""
    crown, bevel = DESIGN.tooth_generation(2)
    rim, f = gear_blank(DESIGN, 2)
    ring = mesh_gear(crown, bevel, rim=rim, sizes=coarse(2)).volume
    hub = math.pi / 4 * (f.hub**2 - f.bore**2) * f.hub_length
    r_out = web_mesh.blank.back * math.sin(bevel.cone_angle)
    web = math.pi * (r_out**2 - (f.hub / 2) ** 2) * f.web
    assert ring < web_mesh.volume < ring + hub + web
    assert web_mesh.bore_radius == pytest.approx(f.bore / 2)
    r = np.hypot(web_mesh.points[:, 0], web_mesh.points[:, 1])
    assert r.min() == pytest.approx(f.bore / 2, rel=1e-6)


def test_default_sizes_refine_the_teeth():
    s = MeshSizes.default(2e-3)
    assert s.tooth < s.body
    assert MeshSizes.default(2e-3, level=1).tooth == pytest.approx(s.tooth / 2)


def test_too_coarse_mesh_is_refused():
    crown, bevel = DESIGN.tooth_generation(2)
    with pytest.raises(MeshError, match="does not resolve a tooth"):
        mesh_gear(crown, bevel, sizes=MeshSizes(5e-3, 8e-3))
    with pytest.raises(MeshError, match="body size"):
        mesh_gear(crown, bevel, sizes=MeshSizes(1e-3, 0.5e-3))
    with pytest.raises(MeshError, match="tooth: must be a length > 0"):
        MeshSizes(-1.0, 1.0)


def test_blank_features_that_do_not_fit_are_refused():
    crown, bevel = DESIGN.tooth_generation(2)
    with pytest.raises(MeshError, match=r"blank\.hub"):
        mesh_gear(crown, bevel, features=BlankFeatures(0.03, 0.005, 0.07, 0.02),
                  sizes=coarse(2))  # fmt: skip
    with pytest.raises(MeshError, match=r"blank\.hub: the hub diameter"):
        BlankFeatures(0.03, 0.005, 0.02, 0.02)
    with pytest.raises(MeshError, match=r"blank\.hub_length"):
        BlankFeatures(0.03, 0.005, 0.04, 0.001)
    with pytest.raises(MeshError, match=r"blank\.web"):
        BlankFeatures(0.03, float("nan"), 0.04, 0.02)


def test_involute_internal_gear_meshes_too():
    """Paper 001's involute teeth (single-sided example), the internal gear: a closed,
    conforming, cyclic mesh whose volume matches the structured solid (same 1.5 %)."""
    d = load_design(example_dir() / "nutation_surface.toml")
    crown, bevel = d.tooth_generation(1)
    rim, features = gear_blank(d, 1)
    m_n = crown.profile.module
    mesh = mesh_gear(
        crown, bevel, rim=rim, features=features, sizes=MeshSizes(0.8 * m_n, 2.5 * m_n)
    )
    _, counts = faces_of(mesh.tets[:, :4])
    assert set(np.unique(counts)) <= {1, 2}
    solid = build_gear_solid(crown, bevel, n_profile=21, n_face=21, n_land=3, n_space=9, rim=rim)
    assert mesh.volume == pytest.approx(solid.gear_mesh().volume, rel=0.015)


def test_section_corners_and_switchbacks():
    """A profile corner leaves a step that turns back on itself: it is dropped, and the
    splines break at the real corners, at the same points on every section."""
    from reducerlab.fe.gear_mesh import _corners_of

    x = np.linspace(0.0, 1.0, 11)
    leg1 = np.stack([x, np.zeros_like(x), np.zeros_like(x)], 1)
    leg2 = np.stack([np.ones(10), np.linspace(0.1, 1.0, 10), np.zeros(10)], 1)
    back = np.array([[0.995, 0.0005, 0.0]])  # a short step back past the corner
    path = np.concatenate([leg1, back, leg2])
    p, ends = _corners_of(np.stack([path, path + np.array([0.0, 0.0, 1.0])]))
    assert p.shape == (2, 21, 3)  # the switchback point is gone on both sections
    assert ends == [0, 10, 20]  # one break, at the 90 deg corner


def test_the_same_mesh_every_time(ring_mesh):
    """A gear meshed again (its sector solid read back from the process's store) is the
    same mesh, node for node: the sector is meshed on one thread (issue 28; HXT on two
    gave 17 584 or 18 088 nodes for one solid from run to run), and a stored solid is
    meshed as a new one is (read back from its BREP text either way)."""
    from reducerlab.fe import gear_mesh

    crown, bevel = DESIGN.tooth_generation(1)
    rim, _ = gear_blank(DESIGN, 1)
    stored = dict(gear_mesh._SOLIDS.items)
    again = mesh_gear(crown, bevel, rim=rim, sizes=coarse(1))
    assert gear_mesh._SOLIDS.items.keys() == stored.keys()  # read back, not built again
    np.testing.assert_array_equal(again.points, ring_mesh.points)
    np.testing.assert_array_equal(again.tets, ring_mesh.tets)
