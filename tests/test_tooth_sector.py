"""The five-tooth sector of the bevel tooth-compliance model holds its modelled teeth.

``contact.compliance.fe_tooth_compliance`` meshes five tooth sectors of a gear
(``fe.gear_mesh.mesh_gear``), holds the two end walls (planes through the gear axis)
and loads the flank of the teeth ``-1, 0, 1`` (tooth ``k``: the flank's tooth 0 turned
by ``-2 pi k / z``). A wall through a modelled tooth clamps it at that plane: the
half-tooth is far stiffer than a whole one and its far root fillet is missing.

The rule checked here, on the geometry alone (the sector's walls from the tooth-space
loft, ``fe.gear_mesh.sector_walls``, and the load points of the flank): a tooth's centre
line lies a quarter pitch ``p/4`` into the tooth from its flank (the tooth is about half
a pitch thick at the pitch cone: a standard basic rack, ISO 53 / GB/T 12759, tooth
thickness ``p/2``). At the middle of the face it must lie at least ``3 p/4`` from each
wall: the half tooth plus half a pitch of gear beyond it (its neighbouring tooth space
or the half of the next tooth the wall passes through). The walls are planes through
the axis while the teeth spiral (25 deg here): over the face a tooth's azimuth drifts by
about +-0.3 p, so at every other load point the centre must lie at least ``p/2`` from a
wall (the wall stays a quarter pitch clear of the tooth's side).

Five sectors hold four whole teeth (the walls pass through the middle of teeth): the
middle of the five is a tooth space, so three modelled teeth sit at best at ``-0.5,
0.5, 1.5`` pitches from it, one and two pitches (centre to wall) from the walls; that
layout meets the rule with ``0.89 p`` at mid-face and ``0.63 p`` at the face ends.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.analysis.contact import contact_pair
from reducerlab.contact.compliance import TEETH, load_nodes, tooth_sectors
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.fe.gear_mesh import sector_walls
from reducerlab.kinematics.rotations import rot_z

EXAMPLE = "examples/nutation_surface.toml"
PROFILES = ("involute", "double-arc")
MID_FACE = 0.75  # pitches: half the tooth plus half a pitch beyond it
ANY_POINT = 0.5  # pitches: half the tooth plus a quarter pitch, the spiral's drift aside


@pytest.fixture(scope="module")
def pairs():
    """Pair 1 (internal gear 1, external gear 2) of both profiles, loaded on either
    crown flank, and the walls of each gear's sector (one loft per gear: about a second)."""
    out, walls = [], {}
    for profile in PROFILES:
        design = load_design(EXAMPLE, [f"surface.profile={profile}"])
        for side in (1, -1):
            mp = contact_pair(design, 1, flank=side)
            for flank in (mp.flank_a, mp.flank_b):
                key = (profile, flank.gear.kind, tooth_sectors(flank))
                if key not in walls:
                    walls[key] = sector_walls(flank.crown, flank.gear, key[2])
                out.append((profile, side, flank, walls[key]))
    return out


def tooth_centres(flank, n_u=6, n_v=9):
    """Per modelled tooth, the azimuths (rad) of its centre line at the load points of
    ``fe_tooth_compliance`` (load grid inset by its bump radius ``0.6 m_n``; rows along
    the face), as an array (teeth, n_u, n_v)."""
    m_n = flank.crown.profile.module
    u, v = load_nodes(flank, 0.6 * m_n, n_u, n_v)
    uu, vv = np.meshgrid(u, v, indexing="ij")
    P, N = flank.evaluate(uu.ravel(), vv.ravel())
    pitch = 2 * math.pi / flank.gear.teeth
    out = []
    for k in TEETH:
        R = rot_z(-2 * math.pi * k / flank.gear.teeth)
        Q, M = P @ R.T, N @ R.T
        psi = np.arctan2(Q[:, 1], Q[:, 0])
        e_psi = np.stack([-np.sin(psi), np.cos(psi), np.zeros_like(psi)], axis=1)
        into = -np.sign(np.einsum("ij,ij->i", M, e_psi))  # the normal points out of the tooth
        out.append((psi + into * pitch / 4).reshape(n_u, n_v))
    return np.array(out)


def wall_clearance(flank, walls):
    """Distance (pitches) of each modelled tooth's centre line to the nearer wall at each
    load point (teeth, n_u, n_v); negative outside the sector."""
    lo, hi = walls
    pitch = 2 * math.pi / flank.gear.teeth
    c = tooth_centres(flank)
    up = np.angle(np.exp(1j * (hi - c))) / pitch
    down = np.angle(np.exp(1j * (c - lo))) / pitch
    return np.minimum(up, down)


def test_modelled_teeth_lie_whole_inside_the_sector(pairs):
    """Both gears of pair 1, both profiles, either loaded flank: every modelled tooth's
    centre line at least ``3 p/4`` from each wall at mid-face and ``p/2`` everywhere
    (module docstring). Before the fix the internal gear's tooth -1 under flank +1 lay
    on the wall (0.03 p at mid-face, -0.27 p at a face end)."""
    seen = set()
    for profile, side, flank, walls in pairs:
        d = wall_clearance(flank, walls)
        n_v = d.shape[2]
        name = f"{profile}, flank {side:+d}, {flank.gear.kind} gear"
        for i, k in enumerate(TEETH):
            assert d[i, :, n_v // 2].min() >= MID_FACE, (name, k, d[i].min())
            assert d[i].min() >= ANY_POINT, (name, k, d[i].min())
        seen.add((profile, flank.gear.kind, side))
    assert len(seen) == 8


def test_sector_walls_are_five_pitches_apart_and_checked(pairs):
    """The five sectors span five pitches; a bad sector range is refused by name."""
    _, _, flank, (lo, hi) = pairs[0]
    assert (hi - lo) / (2 * math.pi / flank.gear.teeth) == pytest.approx(5.0, abs=1e-12)
    with pytest.raises(ReducerlabError, match="sectors: must be 1 to"):
        sector_walls(flank.crown, flank.gear, range(0, 2 * flank.gear.teeth))
    with pytest.raises(ReducerlabError, match="sectors: must be 1 to"):
        sector_walls(flank.crown, flank.gear, range(0, 6, 2))


def test_internal_gear_mesh_holds_all_six_root_fillets(pairs):
    """The meshed sector of the internal gear (involute, flank +1, coarse elements of
    0.5 m_n): its end walls are those :func:`sector_walls` gives (1e-9 rad: the mesh's
    extreme azimuths lie on the walls' planes), and the root-fillet finder of the root
    stress (``contact.compliance._bevel_fillet``) finds both fillets of each of the
    three modelled teeth: a tooth cut by a wall loses its far fillet."""
    import skfem

    from reducerlab.contact.compliance import _bevel_fillet
    from reducerlab.fe.gear_mesh import MeshSizes, mesh_gear

    _, _, flank, walls = next(
        p for p in pairs if p[0] == "involute" and p[1] == 1 and p[2].gear.kind == "internal"
    )
    m_n = flank.crown.profile.module
    mesh = mesh_gear(
        flank.crown, flank.gear, sizes=MeshSizes(0.5 * m_n, m_n), sectors=tooth_sectors(flank)
    )
    az = np.arctan2(mesh.points[:, 1], mesh.points[:, 0])
    rel = np.angle(np.exp(1j * (az - walls[0])))
    assert rel.min() == pytest.approx(0.0, abs=1e-9)
    assert rel.max() == pytest.approx(walls[1] - walls[0], abs=1e-9)
    skm = mesh.skfem()
    basis = skfem.Basis(skm, skfem.ElementVector(skfem.ElementTetP2()))
    angles = [-2 * math.pi * k / flank.gear.teeth for k in TEETH]
    _, tooth, side = _bevel_fillet(flank, mesh.blank, angles)(basis)
    for k in TEETH:
        for s in (1, -1):
            # a fillet of a 10 mm face in 0.5 m_n elements: 24 to 27 facets (before the
            # fix, none on the far side of tooth -1)
            assert np.count_nonzero((tooth == k) & (side == s)) > 20, (k, s)
