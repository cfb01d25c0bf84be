"""Quadratic tetrahedral meshes of spur gear tooth sectors (reducerlab.fe.spur_mesh)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.errors import ReducerlabError
from reducerlab.fe.gear_mesh import MeshError, MeshSizes
from reducerlab.fe.spur_mesh import default_spur_sizes, mesh_spur_sector
from reducerlab.geometry.spur import SpurGear

GEAR = SpurGear(20, 1e-3, 4e-3)


@pytest.fixture(scope="module")
def mesh():
    return mesh_spur_sector(GEAR)  # 3 teeth, rim 3.5 m, sizes 0.25 m / 0.8 m


def test_volume_is_the_exact_sector_area_times_face_width(mesh):
    assert mesh.tooth_ids == (-1, 0, 1)
    assert mesh.inner_radius == pytest.approx(GEAR.root_radius - 3.5e-3)
    assert mesh.sizes == default_spur_sizes(1e-3)
    exact = GEAR.sector_area(3, mesh.inner_radius) * GEAR.face_width
    assert mesh.exact_volume == pytest.approx(exact)
    # straight-sided tetrahedra: chord errors on the curved surfaces, well inside 0.5 %
    assert abs(mesh.volume / exact - 1) < 5e-3
    # the quadratic (curved) elements follow the CAD surfaces: 1e-6-level agreement
    assert abs(mesh.curved_volume() / exact - 1) < 2e-5


def test_elements_are_quadratic_positive_and_finer_on_the_teeth(mesh):
    P, T = mesh.points, mesh.tets
    assert T.shape[1] == 10
    p = P[T[:, :4]]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    assert np.all(vol > 0)
    # VTK order: node 4 is the middle of edge 0-1, node 9 of edge 2-3 (on straight
    # edges exactly, on curved ones close to it)
    for mid, (i, j) in ((4, (0, 1)), (9, (2, 3)), (7, (0, 3))):
        gap = np.linalg.norm(P[T[:, mid]] - 0.5 * (P[T[:, i]] + P[T[:, j]]), axis=1)
        assert np.median(gap) < 1e-12 and gap.max() < 0.05e-3
    # edge length in the teeth ~ tooth size, in the rim ~ body size
    e = np.linalg.norm(P[T[:, 1]] - P[T[:, 0]], axis=1)
    r = np.hypot(*P[T[:, :4]].mean(axis=1)[:, :2].T)
    assert np.median(e[r > GEAR.root_radius]) < 0.4e-3
    assert np.median(e[r < mesh.inner_radius + 0.5e-3]) > 0.5e-3
    sk = mesh.skfem()
    assert sk.p.shape[1] >= len(mesh.corners)


def test_fixed_and_flank_nodes(mesh):
    P = mesh.points
    bore = mesh.bore_nodes()
    np.testing.assert_allclose(np.hypot(P[bore, 0], P[bore, 1]), mesh.inner_radius, rtol=1e-9)
    cut = mesh.cut_nodes()
    ang = np.arctan2(P[cut, 1], P[cut, 0])
    lo, hi = mesh.cut_angles
    assert lo == pytest.approx(-1.5 * GEAR.pitch) and hi == pytest.approx(1.5 * GEAR.pitch)
    assert np.all(np.isclose(ang, lo, atol=1e-9) | np.isclose(ang, hi, atol=1e-9))
    assert np.all(np.hypot(P[cut, 0], P[cut, 1]) <= GEAR.root_radius * (1 + 1e-9))
    fixed = mesh.fixed_nodes()
    assert len(fixed) == len(np.union1d(bore, cut)) and len(bore) > 50 and len(cut) > 100
    # the face z = +-b/2 appears among them
    assert np.isclose(P[fixed, 2].min(), -2e-3) and np.isclose(P[fixed, 2].max(), 2e-3)
    for tooth in mesh.tooth_ids:
        for flank in (1, -1):
            idx, u, v = mesh.flank_nodes(flank, tooth)
            d, _, _ = GEAR.flank_distance(P[idx], flank, tooth)
            assert len(idx) > 100 and np.abs(d).max() < 1e-9
            assert u.min() < 0.02 and u.max() > 0.98 and v.min() == 0 and v.max() == 1
            # the nodes are where flank_points puts them
            q, _ = GEAR.flank_points(u, v, flank, tooth)
            assert np.abs(q - P[idx]).max() < 1e-9


def test_bore_variant_and_bad_input():
    m = mesh_spur_sector(GEAR, teeth=1, bore=12e-3, sizes=MeshSizes(0.4e-3, 1.0e-3))
    assert m.tooth_ids == (0,) and m.inner_radius == pytest.approx(6e-3)
    assert abs(m.volume / m.exact_volume - 1) < 5e-3
    assert min(np.hypot(m.points[:, 0], m.points[:, 1])) == pytest.approx(6e-3, rel=1e-9)
    with pytest.raises(MeshError, match=r"^rim, bore"):
        mesh_spur_sector(GEAR, rim=2e-3, bore=10e-3)
    with pytest.raises(MeshError, match=r"^rim"):
        mesh_spur_sector(GEAR, rim=-1.0)
    with pytest.raises(MeshError, match=r"^rim/bore"):
        mesh_spur_sector(GEAR, bore=2 * GEAR.root_radius)
    with pytest.raises(MeshError, match=r"^sizes.tooth"):
        mesh_spur_sector(GEAR, sizes=MeshSizes(2e-3, 2e-3))
    with pytest.raises(MeshError, match=r"^sizes.body"):
        mesh_spur_sector(GEAR, sizes=MeshSizes(0.3e-3, 0.2e-3))
    with pytest.raises(ReducerlabError, match=r"^teeth"):
        mesh_spur_sector(GEAR, teeth=0)
    with pytest.raises(ReducerlabError, match=r"^tooth"):
        m.flank_nodes(1, tooth=1)
    assert math.isclose(default_spur_sizes(2e-3).body, 1.6e-3)
