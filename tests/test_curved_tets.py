"""Folded curved tetrahedra (``fe.quality``) and the double-arc root-stress defect.

gmsh puts the mid-edge nodes of boundary edges on the curved CAD surfaces; at the heel
end of a bevel tooth's root a mid-edge node could move so far that the quadratic map of
one element folded (Jacobian ratio -1e-5 on the double-arc external gear of
``examples/nutation_surface.toml`` at 0.4 m_n = 0.8 mm elements, -0.57 on the involute
one at 0.8 m_n). The averaged nodal stress recovered there was 9.6e5 MPa under a 1 kN
line load (docs/assumptions.md, "Folded curved elements"). The mesher now straightens
such elements (``mend_curved_tets``) and refuses what it cannot mend.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.errors import ReducerlabError
from reducerlab.fe.quality import (
    MIN_JACOBIAN_RATIO,
    TET10_EDGES,
    jacobian_ratio,
    mend_curved_tets,
)


def _tet10(corners):
    """Points and the element of a straight-sided 10-node tetrahedron."""
    c = np.asarray(corners, dtype=float)
    mids = [0.5 * (c[a] + c[b]) for a, b in TET10_EDGES]
    return np.vstack([c, mids]), np.arange(10)[None, :]


CORNERS = [[0, 0, 0], [2.0, 0, 0], [0, 1.5, 0], [0.2, 0.3, 1.0]]


@pytest.mark.parametrize("t", [0.5, 0.4, 0.3, 0.25, 0.2, 0.7])
def test_jacobian_ratio_of_a_shifted_mid_edge_node(t):
    """Closed form: with the mid-edge node of edge 0-1 at ``x0 + t (x1 - x0)`` (straight
    edge, other nodes at mid-edges) the map along the edge is
    ``x(s) = x0 + (x1 - x0) (s (2 s - 1) + 4 t s (1 - s))``, so ``det J / det J_0 =
    dx/ds / |x1 - x0| = 4 s - 1 + 4 t (1 - 2 s)``, linear in ``s``: ``4 t - 1`` at
    corner 0 and ``3 - 4 t`` at corner 1 (``t = 1/4``: zero, the map folds). The
    lattice holds both corners, so the ratio is exact (round-off only)."""
    P, T = _tet10(CORNERS)
    P[4] = P[0] + t * (P[1] - P[0])
    assert jacobian_ratio(P, T)[0] == pytest.approx(min(4 * t - 1, 3 - 4 * t), abs=1e-12)


def test_mending_straightens_folded_elements_only():
    # two elements sharing face 1-2-3: the first folded, the second curved but valid
    c = np.array(CORNERS, dtype=float)
    c4 = np.array([1.0, 1.0, 1.2])
    P, _ = _tet10(c)
    P = np.vstack([P, c4])
    n4 = len(P) - 1
    T2c = [1, 2, 3, n4]  # beyond face 1-2-3 from corner 0: positively oriented
    # mid-edge nodes of element 2: reuse element 1's where the edge is shared
    shared = {frozenset(e): 4 + k for k, e in enumerate(TET10_EDGES)}
    mids = []
    for a, b in TET10_EDGES:
        key = frozenset((T2c[a], T2c[b]))
        if key in shared:
            mids.append(shared[key])
        else:
            P = np.vstack([P, 0.5 * (P[T2c[a]] + P[T2c[b]])])
            mids.append(len(P) - 1)
    T = np.array([list(range(10)), T2c + mids])
    r0 = jacobian_ratio(P, T)
    assert r0 == pytest.approx([1.0, 1.0])
    # element 2's own (unshared) mid-edge node bowed a little: still valid
    own = T[1, 4 + TET10_EDGES.index((2, 3))]
    P[own] += 0.05 * np.array([0.0, 0.0, 1.0])
    # element 1's unshared edge 0-1 folded (t = 0.2)
    P[4] = P[0] + 0.2 * (P[1] - P[0])
    r = jacobian_ratio(P, T)
    assert r[0] < 0 and r[1] > MIN_JACOBIAN_RATIO
    Q, mended = mend_curved_tets(P, T, "test body")
    assert mended == 1
    assert jacobian_ratio(Q, T)[0] == pytest.approx(1.0)
    assert np.array_equal(Q[own], P[own])  # the valid element keeps its curved edge
    assert not np.shares_memory(Q, P) and P[4][0] == pytest.approx(0.4)


def test_a_flat_element_is_refused_by_name():
    P, T = _tet10([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])  # zero volume
    with pytest.raises(ReducerlabError, match=r"ring body: 1 tetrahedra .* zero or negative"):
        mend_curved_tets(P, T, "ring body")
    P, T = _tet10([CORNERS[1], CORNERS[0], CORNERS[2], CORNERS[3]])  # inverted
    with pytest.raises(ReducerlabError, match=r"ring body: .*inverted"):
        mend_curved_tets(P, T, "ring body")


def _double_arc_pair():
    from reducerlab.analysis.contact import contact_pair
    from reducerlab.drives import load_design
    from reducerlab.examples import example_dir

    design = load_design(example_dir() / "nutation_surface.toml", ["surface.profile=double-arc"])
    return contact_pair(design, 1)


def test_double_arc_tooth_sector_has_no_folded_element():
    """One tooth sector of the double-arc external gear at 0.4 m_n (0.8 mm), the size
    where gmsh's curved mesh folded at the heel end of the root: every element now
    passes the Jacobian check."""
    from reducerlab.fe.gear_mesh import MeshSizes, mesh_gear

    flank = _double_arc_pair().flank_a
    m = flank.crown.profile.module
    mesh = mesh_gear(flank.crown, flank.gear, sizes=MeshSizes(0.4 * m, m), sectors=range(0, 1))
    assert jacobian_ratio(mesh.points, mesh.tets).min() >= MIN_JACOBIAN_RATIO


def test_double_arc_root_stress_stays_physical():
    """The double-arc external gear's tooth model at 0.8 mm elements, no root band
    (where 9.6e5 MPa came out at the heel end of the fillet): under a 1 kN line load at
    three profile positions, every reported stress (tensile, face ends, compressive,
    von Mises) stays below 10 times the nominal bending stress ``F / (b m_n) Y_FS``
    with ``Y_FS = 5`` (ISO 6336-3's combined form and notch factor of external teeth
    without undercut lies near 4 to 5): 2500 MPa. The model gives 150 MPa at most; the
    bound is loose on purpose (it only tells a physical stress from a folded element's),
    and the defect exceeded it 400-fold. The fillet nodes lie in the root band, between
    the root cone and 0.6 m_n above it (never at tip height, 2.25 m_n up)."""
    from reducerlab.contact.compliance import fe_tooth_compliance
    from reducerlab.contact.rootstress import line_load_root_stress
    from reducerlab.geometry.solid import cone_coordinates

    flank = _double_arc_pair().flank_a
    m = flank.crown.profile.module
    c = fe_tooth_compliance(flank, tooth_size=0.4 * m, root_stress=True, fillet_size=0.4 * m)
    bl = flank.blank
    _, h, _ = cone_coordinates(c.fillet.points, flank.gear.cone_angle)
    assert h.min() > bl.root - 0.05 * m and h.max() < bl.root + 0.6 * m
    b = bl.back - bl.front
    force = 1000.0
    bound = 10 * force / (b * m) * 5.0
    assert bound == pytest.approx(2.5e9)
    for u in (0.2, 0.5, 0.8):
        r = line_load_root_stress(c, 0, u, force)
        values = np.concatenate([r.tensile, r.end_tensile, -r.compressive, r.von_mises])
        assert np.all(np.abs(values[np.isfinite(values)]) < bound)
        assert math.isfinite(r.end_tensile[r.teeth.index(0)])


def test_mended_wall_nodes_keep_the_sectors_conforming():
    """The involute external gear of ``examples/nutation_surface.toml`` at 1.0 m_n
    teeth (a coarse body-modal size): 10 folded elements per sector (worst -1.14) are
    straightened, and three sectors still join node to node (``_pattern`` refuses walls
    that do not match) and every element of the joined mesh passes. (One of those
    elements has an edge on a periodic wall, but that edge was straight already: the
    partner-moving branch of ``gear_mesh._mend_sector`` moves it by round-off only.)"""
    from reducerlab.analysis.contact import contact_pair
    from reducerlab.drives import load_design
    from reducerlab.examples import example_dir
    from reducerlab.fe.gear_mesh import MeshSizes, mesh_gear

    flank = contact_pair(load_design(example_dir() / "nutation_surface.toml"), 1).flank_a
    m = flank.crown.profile.module
    mesh = mesh_gear(flank.crown, flank.gear, sizes=MeshSizes(m, 3 * m), sectors=range(0, 3))
    assert jacobian_ratio(mesh.points, mesh.tets).min() >= MIN_JACOBIAN_RATIO
    # conforming: the boundary's faces on planes through the axis are the two outer
    # walls only (a wall left unmatched between two sectors would be boundary too)
    skm = mesh.skfem()
    P = skm.p[:, skm.facets[:, skm.boundary_facets()]]  # (3, 3 corners, facets)
    nrm = np.cross((P[:, 1] - P[:, 0]).T, (P[:, 2] - P[:, 0]).T)
    nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
    c = P.mean(axis=1).T
    through_axis = (np.abs(np.einsum("ij,ij->i", nrm, c)) < 1e-9) & (np.abs(nrm[:, 2]) < 1e-9)
    azimuth = np.arctan2(c[through_axis, 1], c[through_axis, 0])
    pitch = 2 * math.pi / flank.gear.teeth
    planes = np.unique(np.round(azimuth / (0.25 * pitch)))
    assert len(planes) == 2 and mesh.tets.shape[0] == 3 * mesh.sector_tets
