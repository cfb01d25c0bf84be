"""Closed solids of generated nutation spiral bevel gears (paper 001), export and figures."""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest

from reducerlab.geometry import CrownGear, DoubleCircularArcProfile, InvoluteProfile
from reducerlab.geometry.bevel_surface import nutation_bevel_pair
from reducerlab.geometry.export import export_mesh, export_point_cloud, export_step, load_mesh
from reducerlab.geometry.solid import (
    SolidError,
    build_gear_solid,
    cone_coordinates,
    default_blank,
    independent_volume_estimate,
    require_trimesh,
)

trimesh = pytest.importorskip("trimesh")

M = 2e-3
BETA = math.radians(25)
EXT, INT = nutation_bevel_pair(26, 28, math.radians(5))
PROFILES = {"involute": InvoluteProfile(M), "double_arc": DoubleCircularArcProfile(M)}
GEARS = {"external": EXT, "internal": INT}
COARSE = dict(n_profile=9, n_face=5, n_land=2, n_space=5)


def crown_for(profile):
    return CrownGear.for_gear(profile, EXT.teeth, EXT.cone_angle, BETA, 10e-3)


_cache: dict = {}


def solid(name, kind):
    if (name, kind) not in _cache:
        _cache[name, kind] = build_gear_solid(crown_for(PROFILES[name]), GEARS[kind], **COARSE)
    return _cache[name, kind]


@pytest.mark.parametrize("kind", ["external", "internal"])
@pytest.mark.parametrize("name", ["involute", "double_arc"])
def test_tooth_and_gear_solids_are_watertight(name, kind):
    S = solid(name, kind)
    tooth, gear = S.tooth_mesh(), S.gear_mesh()
    for mesh in (tooth, gear):
        tm = mesh.to_trimesh()
        assert tm.is_watertight and tm.is_winding_consistent
        assert mesh.open_edges() == 0  # our own edge count, without trimesh
        assert mesh.volume > 0
        # trimesh's volume and ours (divergence theorem) are the same sum
        assert tm.volume == pytest.approx(mesh.volume, rel=1e-12)
    # z sectors make the gear: the side walls of the sector cancel exactly
    assert GEARS[kind].teeth * tooth.volume == pytest.approx(gear.volume, rel=1e-10)
    assert S.max_residual <= 1e-9


@pytest.mark.parametrize("kind", ["external", "internal"])
@pytest.mark.parametrize("name", ["involute", "double_arc"])
def test_sections_lie_on_the_blank_cones(name, kind):
    """Every section lies on its front/back-parallel cone L = const (1e-12 relative: the
    rho iteration stops at 1e-13 R_m), top lands on the face cone (the bisection on the
    profile parameter resolves h to ~1e-15 m), body points on the body cone."""
    S = solid(name, kind)
    d = S.gear.cone_angle
    L, h, _ = cone_coordinates(S.loop, d)
    np.testing.assert_allclose(L, S.L[:, None] * np.ones_like(L), rtol=1e-12)
    assert L[0, 0] == pytest.approx(S.blank.front) and L[-1, 0] == pytest.approx(S.blank.back)
    np.testing.assert_allclose(h[:, S.parts["land"]], S.blank.face, atol=1e-12)
    _, hb, _ = cone_coordinates(S.body, d)
    np.testing.assert_allclose(hb, S.blank.body, atol=1e-15)
    # teeth stay between the face cone and the body cone
    lo, hi = sorted((S.blank.face, S.blank.body))
    assert np.all((h >= lo - 1e-12) & (h <= hi + 1e-12))


@pytest.mark.parametrize("kind", ["external", "internal"])
@pytest.mark.parametrize("name", ["involute", "double_arc"])
def test_volume_against_blank_and_basic_tooth_estimate(name, kind):
    """Mesh volume vs an estimate without the mesh: the conical ring between the body
    and root cones (analytic, Pappus) plus z teeth, each the basic tooth's normal section
    swept along the log-spiral tooth line (length b / cos(beta)) with the first-order
    cone correction r / r_pitch = 1 + h / (L tan(delta)).

    Tolerance 1.5 % of the gear volume: the estimate neglects the difference between the
    generated (conjugate) tooth and the basic tooth (generated root fillet, flank heights
    h != x, a few % of the tooth volume, which is 30-40 % of the gear) and, for the
    internal gear, the parts of the spaces cut deeper than the nominal root cone. The
    measured errors are 0.2-0.9 %. The mesh itself converges to 0.05 % (checked below),
    so a missing tooth (4 % of the teeth), a flipped end face or a wrong rim fails."""
    S = solid(name, kind)
    V = S.gear_mesh().volume
    est = independent_volume_estimate(S)
    assert abs(V / est["total"] - 1) <= 0.015
    # and the mesh, refined twice, moves by less than 0.1 %
    fine = build_gear_solid(S.crown, S.gear, n_profile=17, n_face=9, n_land=4, n_space=9)
    assert fine.gear_mesh().volume == pytest.approx(V, rel=1e-3)
    # a thicker rim adds the analytic ring between the two body cones, up to the sag of
    # the flat triangles of the body cones: a triangle spanning the azimuth dpsi lies
    # r dpsi^2 / 8 inside the cone, so the ring between two such cones is short by at
    # most dpsi^2 / 8 of itself (dpsi: the widest diagonal of a body quad, which the
    # spiral twists from section to section)
    thick = build_gear_solid(S.crown, S.gear, rim=3 * M, **COARSE)
    ring = S.blank.ring_volume(S.gear.cone_angle, S.blank.body, thick.blank.body)
    _, _, psi = cone_coordinates(thick.body, S.gear.cone_angle)
    psi = np.unwrap(psi, axis=1)
    span = np.abs(psi[1:, 1:] - psi[:-1, :-1]).max()
    added = thick.gear_mesh().volume - V
    assert 0 < 1 - added / ring <= span**2 / 8


def test_exported_stl_and_ply_round_trip(tmp_path):
    """Binary STL stores float32 coordinates (in mm, ~40 mm: 4e-6 mm resolution, a
    relative volume error ~1e-6); PLY keeps float64."""
    from stl import mesh as numpy_stl

    gear = solid("double_arc", "internal").gear_mesh()
    stl = export_mesh(gear, tmp_path / "gear.stl")
    back = load_mesh(stl)
    assert len(back.faces) == len(gear.faces)
    assert back.volume == pytest.approx(gear.volume, rel=1e-5)
    assert back.to_trimesh().is_watertight
    raw = numpy_stl.Mesh.from_file(str(stl))
    assert len(raw.vectors) == len(gear.faces)
    assert raw.get_mass_properties()[0] * 1e-9 == pytest.approx(gear.volume, rel=1e-5)
    ply = load_mesh(export_mesh(gear, tmp_path / "gear.ply"))
    assert len(ply.faces) == len(gear.faces)
    assert ply.volume == pytest.approx(gear.volume, rel=1e-12)
    with pytest.raises(SolidError, match="unknown file type"):
        export_mesh(gear, tmp_path / "gear.obj")


def test_point_clouds_per_flank(tmp_path):
    S = solid("involute", "external")
    clouds = S.flank_points()
    n_rows = S.parts["A"].stop - S.parts["A"].start
    for key in ("A", "B"):
        P, N = clouds[key]
        assert P.shape == (S.loop.shape[0] * n_rows, 3)
        np.testing.assert_allclose(np.linalg.norm(N, axis=1), 1.0, atol=1e-12)
    pa, na = clouds["A"]
    path = export_point_cloud(pa, na, tmp_path / "flank_a.ply")
    pc = trimesh.load(path)
    np.testing.assert_allclose(np.asarray(pc.vertices), pa * 1e3, rtol=1e-15)
    # the flank normals point away from the other flank of the tooth
    pb, _ = clouds["B"]
    assert np.all(np.einsum("ij,ij->i", na, pa - pb) > 0)


def test_step_export_of_a_tooth(tmp_path):
    """A faceted STEP solid through OpenCASCADE has the mesh's volume (1e-9: the same
    planar facets, integrated by OCC)."""
    pytest.importorskip("OCP")
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    from OCP.STEPControl import STEPControl_Reader

    tiny = dict(n_profile=5, n_face=3, n_land=1, n_space=3)
    tooth = build_gear_solid(crown_for(PROFILES["involute"]), INT, **tiny).tooth_mesh()
    path = export_step(tooth, tmp_path / "tooth.step")
    reader = STEPControl_Reader()
    reader.ReadFile(str(path))
    reader.TransferRoots()
    props = GProp_GProps()
    BRepGProp.VolumeProperties_s(reader.OneShape(), props)
    assert props.Mass() * 1e-9 == pytest.approx(tooth.volume, rel=1e-9)


def test_bad_solids_are_rejected():
    crown = crown_for(PROFILES["involute"])
    with pytest.raises(SolidError, match="n_face >= 2"):
        build_gear_solid(crown, EXT, n_face=1)
    with pytest.raises(SolidError, match=r"blank\.rim"):
        build_gear_solid(crown, INT, rim=0.02 * M, **COARSE)  # the spaces reach 1.15 m_n
    with pytest.raises(SolidError, match=r"blank\.addendum"):
        default_blank(crown, EXT, addendum=1.1 * M)
    # a thin basic tooth with a tall addendum meets below the face cone
    thin = InvoluteProfile(M, math.radians(25), addendum=1.2, dedendum=1.45, thickness=1.2 * M)
    with pytest.raises(SolidError, match="pointed tooth"):
        build_gear_solid(crown_for(thin), EXT, **COARSE)


def test_missing_trimesh_names_the_cad_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "trimesh", None)
    with pytest.raises(SolidError, match="'cad' extra"):
        require_trimesh()


def test_rendered_tooth_and_pair(tmp_path):
    from reducerlab.plot.surface import gear_to_mesh_frame, plot_gear_pair, plot_tooth

    ext, int_ = solid("double_arc", "external"), solid("double_arc", "internal")
    for fig, name in ((plot_tooth(ext), "tooth.png"), (plot_gear_pair(ext, int_), "pair.png")):
        assert fig.axes[0].collections, "nothing drawn"
        fig.savefig(tmp_path / name, dpi=60)
        assert (tmp_path / name).stat().st_size > 5000
    # in mesh: the two gear axes (z_i mapped to S0) are the nutation angle apart
    a1 = gear_to_mesh_frame(ext) @ [0, 0, 1]
    a2 = gear_to_mesh_frame(int_) @ [0, 0, 1]
    assert math.degrees(math.acos(a1 @ a2)) == pytest.approx(5.0, abs=1e-12)
    from reducerlab.errors import ReducerlabError

    with pytest.raises(ReducerlabError, match="external gear's solid first"):
        plot_gear_pair(int_, ext)


def test_solid_rejects_a_foreign_crown_and_non_integer_grids():
    """Regression: a crown gear of another gear built a solid whose patterned teeth do
    not fit the circle; a float grid size was accepted."""
    from reducerlab.geometry import BevelGear, ProfileError

    crown = crown_for(PROFILES["involute"])
    with pytest.raises(ProfileError, match=r"crown\.teeth"):
        build_gear_solid(crown, BevelGear(10, 0.3), **COARSE)
    with pytest.raises(SolidError, match="integers"):
        build_gear_solid(crown, EXT, n_profile=5.5)


@pytest.mark.parametrize("name", ["involute", "double_arc"])
def test_internal_gear_root_is_a_fillet_not_a_corner(name):
    """The internal gear's space is the basic tooth, whose tip line meets the flanks in
    a corner; the solid rounds it with a root fillet tangent to the flank ends (a
    re-entrant corner there made the FE root stress grow with every mesh refinement,
    like r^-0.40 for the involute's 65 deg turn: docs/contact.md)."""
    from reducerlab.geometry.solid import _rot_z

    S = build_gear_solid(crown_for(PROFILES[name]), INT, n_profile=41, n_face=5, n_land=3,
                         n_space=41)  # fmt: skip
    prof = PROFILES[name]
    x_root, x_tip = prof.x_range()
    A, B, sp = S.parts["A"], S.parts["B"], S.parts["space"]
    for j in range(S.loop.shape[0]):
        path = np.concatenate([S.loop[j, B], S.loop[j, sp], _rot_z(S.loop[j, A], -S.pitch_angle)])
        d = np.diff(path, axis=0)
        seg = np.linalg.norm(d, axis=1)
        t = d / seg[:, None]
        turn = np.degrees(np.arccos(np.clip((t[1:] * t[:-1]).sum(1), -1, 1)))
        nb, ns = B.stop - B.start, sp.stop - sp.start
        for k in (nb - 2, nb + ns - 1):  # the turns at the two flank/fillet joints
            # tangent joint: no larger than its neighbours' (a corner turns at once)
            assert turn[k] <= max(turn[k - 1], turn[k + 1]) + 0.5, (j, k, turn[k - 2 : k + 3])
        assert turn[nb - 2 : nb + ns].max() < 5.0
        # radius of curvature of the fillet-bottom path (section): >= 0.3 m_n
        kappa = np.radians(turn[nb : nb + ns - 2]) / seg[nb : nb + ns - 2]
        assert 1 / kappa.max() > 0.3 * M
        # the bottom lies beyond the flank ends by at most the clearance h_f - h_a
        _, h, _ = cone_coordinates(S.loop[j], INT.cone_angle)
        depth = h[sp].max() - max(h[B][-1], h[A][0])
        assert 0.05 * M < depth <= (-x_root - x_tip) * (1 + 1e-9)
