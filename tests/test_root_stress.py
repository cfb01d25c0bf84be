"""Root-stress machinery: stress recovery of quadratic tetrahedra (``fe.stress``), the
solve of many loads by one factor (``fe.elasticity.pardiso_gram_solve``) and the linear
map from flank forces to fillet stresses (``contact.rootstress``).

The FE tooth model itself is checked against ISO 6336-3 in
``tests/published/test_iso6336_root_stress.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.sparse as sp

from reducerlab.contact.compliance import ToothCompliance
from reducerlab.contact.rootstress import (
    FilletInfluence,
    bump_amplitudes,
    line_load_root_stress,
    tooth_root_stress,
    von_mises,
)
from reducerlab.errors import ReducerlabError
from reducerlab.fe.elasticity import STEEL, assemble, pardiso_gram_solve
from reducerlab.fe.stress import principal_stresses, surface_stress_operator


def _box(nx=6, ny=3, nz=3, L=0.1, h=0.02, w=0.01):
    import skfem

    return skfem.MeshTet.init_tensor(
        np.linspace(0, L, nx), np.linspace(0, h, ny), np.linspace(0, w, nz)
    )


def test_recovered_stress_is_exact_for_a_quadratic_displacement():
    """A quadratic displacement field lies in the P2 space: its interpolant's stress is
    the field's own (Hooke's law of its linear strain), exact to rounding at every
    surface node whatever element the average takes it from."""
    mesh = _box()
    _, _, basis = assemble(mesh, STEEL, order=2, mass=False)
    X, Y, Z = basis.doflocs
    a, b, c, d, e = 1e-3, 2e-3, 3e-3, -1e-3, 5e-4
    comp = np.arange(basis.N) % 3
    U = np.where(
        comp == 0, a * X * Y + c * Z**2, np.where(comp == 1, b * X**2 + d * Y**2, e * X * Z)
    )
    ss = surface_stress_operator(basis, STEEL, mesh.boundary_facets())
    sigma = (ss.operator @ U).reshape(-1, 6)
    x, y, z = ss.points.T
    exx, eyy, ezz = a * y, 2 * d * y, e * x
    exy, exz = 0.5 * (a * x + 2 * b * x), 0.5 * (2 * c * z + e * z)
    lam, mu = STEEL.lame
    tr = exx + eyy + ezz
    ref = np.stack([lam * tr + 2 * mu * exx, lam * tr + 2 * mu * eyy, lam * tr + 2 * mu * ezz,
                    0 * x, 2 * mu * exz, 2 * mu * exy], axis=1)  # fmt: skip
    assert np.max(np.abs(sigma - ref)) < 1e-10 * np.max(np.abs(ref))
    # outward normals of the box faces
    on_top = np.isclose(ss.points[:, 1], 0.02) & (ss.points[:, 0] > 0.01) & (ss.points[:, 0] < 0.09)
    on_top &= (ss.points[:, 2] > 1e-3) & (ss.points[:, 2] < 9e-3)
    assert on_top.any() and np.allclose(ss.normals[on_top], [0.0, 1.0, 0.0])
    with pytest.raises(ReducerlabError, match="no facets"):
        surface_stress_operator(basis, STEEL, np.array([], dtype=int))


def test_cantilever_bending_stress_against_beam_theory():
    """A cantilever (L = 100 mm, h = 20 mm, w = 10 mm) clamped at x = 0 under an end
    shear F: the axial stress at the top and bottom fibres at mid-span is ``-+ M c / I``
    with ``M = F (L - x)`` (Euler-Bernoulli; Saint-Venant: exact away from the ends
    for the linear bending stress of a tip shear, Timoshenko & Goodier §21). 2 %:
    five quadratic elements over the depth, the averaged nodal stress; measured +0.4 %."""
    from skfem import FacetBasis, LinearForm, asm

    L, h, w, F = 0.1, 0.02, 0.01, 1000.0
    mesh = _box(21, 5, 3, L, h, w)
    K, _, basis = assemble(mesh, STEEL, order=2, mass=False)
    end = mesh.facets_satisfying(lambda x: np.isclose(x[0], L))
    fb = FacetBasis(mesh, basis.elem, facets=end)

    @LinearForm
    def shear(v, _):
        return -F / (h * w) * v[1]  # traction -y over the end face

    f = asm(shear, fb)
    fixed = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    free = np.setdiff1d(np.arange(basis.N), fixed)
    u = np.zeros(basis.N)
    u[free] = sp.linalg.spsolve(K[free][:, free].tocsc(), f[free])
    ss = surface_stress_operator(basis, STEEL, mesh.boundary_facets())
    sxx = (ss.operator @ u).reshape(-1, 6)[:, 0]
    mid = np.isclose(ss.points[:, 0], L / 2) & np.isclose(ss.points[:, 2], w / 2)
    top = mid & np.isclose(ss.points[:, 1], h)
    bottom = mid & np.isclose(ss.points[:, 1], 0.0)
    beam = F * (L / 2) * (h / 2) / (w * h**3 / 12)  # M c / I (Pa)
    assert sxx[top][0] == pytest.approx(beam, rel=0.02)  # tension on top (load -y)
    assert sxx[bottom][0] == pytest.approx(-beam, rel=0.02)


def test_gram_and_solution_by_one_factor():
    rng = np.random.default_rng(0)
    n = 400
    A = sp.random(n, n, density=0.01, random_state=1)
    A = (A @ A.T + 5 * sp.eye(n)).tocsr()
    Bm = rng.standard_normal((n, 5))
    out = pardiso_gram_solve(A, Bm)
    if out is None:
        pytest.skip("pypardiso not installed")
    G, X = out
    ref = np.linalg.solve(A.toarray(), Bm)
    assert np.max(np.abs(X - ref)) < 1e-10 * np.max(np.abs(ref))
    assert np.max(np.abs(G - Bm.T @ ref)) < 1e-10 * np.max(np.abs(G))


def test_principal_and_von_mises_closed_forms():
    # uniaxial 100 MPa; pure shear 50 MPa (principal +-50, von Mises sqrt(3) 50)
    s = np.array([[100e6, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 50e6]])
    p = principal_stresses(s)
    assert np.allclose(p[0], [0, 0, 100e6]) and np.allclose(p[1], [-50e6, 0, 50e6])
    assert np.allclose(von_mises(s), [100e6, math.sqrt(3) * 50e6])
    with pytest.raises(ReducerlabError, match="6 Voigt"):
        principal_stresses(np.zeros((2, 5)))


def _synthetic(with_fillet=True):
    """A compliance of 3 teeth x 2 x 3 load points and a fillet of 4 nodes per tooth
    (2 each side) whose stress is a random linear map of the bumps."""
    rng = np.random.default_rng(3)
    u_nodes, v_nodes, teeth = np.array([0.2, 0.8]), np.array([0.1, 0.5, 0.9]), (-1, 0, 1)
    TL = 3 * 6
    n = 12
    tooth = np.repeat(np.array(teeth), 4)
    side = np.tile([1, 1, -1, -1], 3)
    S = 1e6 * rng.standard_normal((n, 6, TL))
    inf = FilletInfluence(rng.standard_normal((n, 3)), np.tile([0.0, 0.0, 1.0], (n, 1)),
                          tooth, side, np.linspace(1.0, 2.0, n), np.linspace(-1, 1, n),
                          np.linspace(0.1, 1.4, n), S)  # fmt: skip
    return ToothCompliance(u_nodes, v_nodes, teeth, np.eye(TL), 100, 1e-3,
                           inf if with_fillet else None)  # fmt: skip


def test_forces_reach_the_bumps_through_the_compliance_stencil():
    c = _synthetic()
    tooth = np.array([0, 0, 1, -1])
    u = np.array([0.2, 0.5, 0.7, 1.0])  # 1.0: extrapolated beyond the last node
    v = np.array([0.1, 0.3, 0.6, 0.9])
    f = np.array([10.0, 20.0, 5.0, 1.0])
    a = bump_amplitudes(c, tooth, u, v, f)
    # the bilinear weights sum to one: the bumps carry the total force of each tooth
    L = 6
    for k, t in enumerate(c.teeth):
        assert a[k * L : (k + 1) * L].sum() == pytest.approx(f[tooth == t].sum(), rel=1e-12)
    # a force at a load point lands on that bump alone
    a0 = bump_amplitudes(c, [0], [0.2], [0.1], [7.0])
    assert a0[L] == pytest.approx(7.0) and np.count_nonzero(np.abs(a0) > 1e-12) == 1
    # the root stress is the fillet's linear map of the amplitudes
    r = tooth_root_stress(c, tooth, u, v, f)
    p = principal_stresses(c.fillet.stress(a))
    for i, k in enumerate(c.teeth):
        on = (c.fillet.tooth == k) & (c.fillet.side == 1)
        assert r.tensile[i] == pytest.approx(p[on, 2].max())
        off = (c.fillet.tooth == k) & (c.fillet.side == -1)
        assert r.compressive[i] == pytest.approx(p[off, 0].min())
        j = np.flatnonzero(on)[np.argmax(p[on, 2])]
        assert r.tensile_radius[i] == c.fillet.radius[j] and r.tensile_angle[i] == c.fillet.angle[j]
    # a line load of n equal parts is their sum
    line = line_load_root_stress(c, 0, 0.5, 30.0, points=3)
    direct = tooth_root_stress(c, [0, 0, 0], [0.5] * 3, (np.arange(3) + 0.5) / 3, [10.0] * 3)
    assert np.allclose(line.tensile, direct.tensile)


def test_reversed_teeth_and_bad_input():
    c = _synthetic()
    rev = c.fillet.reversed_teeth(c.teeth, 6)
    assert np.array_equal(rev.tooth, -c.fillet.tooth)
    assert np.array_equal(rev.matrix[:, :, 0:6], c.fillet.matrix[:, :, 12:18])
    with pytest.raises(ReducerlabError, match="root_stress=True"):
        tooth_root_stress(_synthetic(False), [0], [0.5], [0.5], [1.0])
    with pytest.raises(ReducerlabError, match="force"):
        bump_amplitudes(c, [0], [0.5], [0.5], [np.nan])
    with pytest.raises(ReducerlabError, match="one force per point"):
        bump_amplitudes(c, [0, 0], [0.5, 0.5], [0.5, 0.5], [1.0])
    with pytest.raises(ReducerlabError, match="tooth pairs"):
        bump_amplitudes(c, [2], [0.5], [0.5], [1.0])
    with pytest.raises(ReducerlabError, match="force"):
        line_load_root_stress(c, 0, 0.5, -1.0)
    with pytest.raises(ReducerlabError, match="points"):
        line_load_root_stress(c, 0, 0.5, 1.0, points=1)
    with pytest.raises(ReducerlabError, match="amplitudes"):
        c.fillet.stress(np.zeros(5))


def test_contact_analysis_refuses_root_stress_it_cannot_give():
    import xarray as xr

    from reducerlab.analysis.contact_rootstress import check_root_compliance, root_stress_lines

    with pytest.raises(ReducerlabError, match="rigid"):
        check_root_compliance(None, rigid=True)
    with pytest.raises(ReducerlabError, match="without the root-stress"):
        check_root_compliance((_synthetic(), _synthetic(False)), rigid=False)
    check_root_compliance((_synthetic(), _synthetic()), rigid=False)  # accepted
    assert root_stress_lines(xr.Dataset()) == []


def test_a_fillet_outside_the_model_is_nan_not_an_error():
    c = _synthetic()
    f = c.fillet
    keep = ~((f.tooth == 1) & (f.side == -1))  # as if cut away by the sector's end wall
    cut = FilletInfluence(*(getattr(f, n)[keep] for n in (
        "points", "normals", "tooth", "side", "radius", "face", "angle", "matrix")))  # fmt: skip
    c2 = ToothCompliance(c.u_nodes, c.v_nodes, c.teeth, c.matrix, c.dofs, c.radius, cut)
    r = tooth_root_stress(c2, [0], [0.5], [0.5], [1.0])
    assert np.isnan(r.compressive[2]) and np.isnan(r.compressive_radius[2])
    assert np.all(np.isfinite(r.tensile)) and np.all(np.isfinite(r.compressive[:2]))


def test_contact_command_offers_root_stress():
    from typer.testing import CliRunner

    from reducerlab.cli import app

    out = " ".join(
        CliRunner().invoke(app, ["contact", "--help"], terminal_width=200).output.split()
    )
    assert "--root-stress" in out and "tooth-root stress" in out


def test_bevel_tooth_model_root_stress_is_the_same_on_each_modelled_tooth():
    """The external gear of pair 1 of ``examples/nutation_surface.toml`` on a coarse
    tooth model (elements of 0.4 m_n): the three modelled teeth are whole teeth of the
    same gear, so the same line load on each gives its own root stress alike (the rim
    and the neighbours differ a little near the sector's ends: 10 %), both fillets of
    every tooth are found, in tension on the loaded side and compression on the other,
    between the root cone and the active flank's edge."""
    from reducerlab.analysis.contact import contact_pair
    from reducerlab.contact.compliance import fe_tooth_compliance
    from reducerlab.drives import load_design
    from reducerlab.geometry.solid import cone_coordinates

    mp = contact_pair(load_design("examples/nutation_surface.toml"), 1)
    flank = mp.flank_a
    m_n = flank.crown.profile.module
    # fillet_size = the tooth size: no root-band refinement (the cheap model of CI)
    c = fe_tooth_compliance(flank, tooth_size=0.4 * m_n, root_stress=True, fillet_size=0.4 * m_n)
    f = c.fillet
    for k in c.teeth:
        for side in (1, -1):
            assert np.count_nonzero((f.tooth == k) & (f.side == side)) > 20
    _, h, _ = cone_coordinates(f.points, flank.gear.cone_angle)
    bl = flank.blank
    assert h.min() > bl.root - 0.05 * m_n and h.max() < bl.root + 0.6 * m_n
    own = []
    for i, k in enumerate(c.teeth):
        r = line_load_root_stress(c, k, 0.7, 1000.0)
        assert r.tensile[i] > 0 > r.compressive[i]
        others = [j for j in range(3) if j != i]
        assert np.all(r.tensile[others] < 0.7 * r.tensile[i])
        own.append(r.tensile[i])
    assert max(own) / min(own) < 1.1


def test_root_stress_memory_is_estimated_and_bounded(monkeypatch):
    from reducerlab.budget import MEMORY_ENV
    from reducerlab.contact.compliance import root_stress_estimate
    from reducerlab.errors import BudgetError

    monkeypatch.setenv(MEMORY_ENV, "1G")
    est = root_stress_estimate(100_000, 162, 2000)  # the spur model: 3 x 130 MB + 16 MB
    assert est.memory == pytest.approx(3 * 8.0 * 100_000 * 162 + 6 * 8.0 * 2000 * 162)
    est.check()
    with pytest.raises(BudgetError, match="root-stress influence"):
        root_stress_estimate(1_000_000, 162, 2000).check()  # 3.9 GB


def test_fillet_nodes_near_the_face_ends_are_reported_apart():
    """Nodes within ``end_margin`` of an end face leave the tensile, compressive and von
    Mises results and give ``end_tensile`` alone (not converged there:
    ``contact.rootstress`` module docstring)."""
    import dataclasses

    from reducerlab.fe.stress import principal_stresses

    c = _synthetic()
    f = c.fillet
    n = f.points.shape[0]
    args = ([0, 0, 1], [0.2, 0.5, 0.8], [0.3, 0.5, 0.7], [10.0, 20.0, 5.0])
    whole = tooth_root_stress(c, *args)
    assert np.all(np.isnan(whole.end_tensile))  # no end distances: every node inside
    # tooth 0's first loaded-fillet node 0.5 bump radii from an end face, the rest far
    ends = np.full(n, 1.0)
    j = np.flatnonzero((f.tooth == 0) & (f.side == 1))
    ends[j[0]] = 0.5e-3
    fillet = dataclasses.replace(f, end_distance=ends, end_margin=1e-3)
    c2 = dataclasses.replace(c, fillet=fillet)
    r = tooth_root_stress(c2, *args)
    p = principal_stresses(f.stress(bump_amplitudes(c, *args)))[:, 2]
    i = r.teeth.index(0)
    assert r.end_tensile[i] == pytest.approx(p[j[0]])
    assert r.tensile[i] == pytest.approx(p[j[1:]].max())
    others = [k for k in range(3) if k != i]
    assert np.all(np.isnan(r.end_tensile[others]))
    assert np.array_equal(r.tensile[others], whole.tensile[others])


def test_root_stress_lines_report_the_face_ends_apart():
    import xarray as xr

    from reducerlab.analysis.contact_rootstress import root_stress_lines

    dims = ("gear", "position", "tooth_pair")
    full = np.full((2, 1, 3), 100e6)
    ds = xr.Dataset(
        {
            "root_stress": (dims, full),
            "root_compressive": (dims, -full),
            "root_von_mises": (dims, full),
            "root_stress_face_ends": (dims, np.full((2, 1, 3), np.nan)),
        },
        attrs=dict(root_stress_peak=100e6, root_stress_peak_gear="external",
                   root_stress_peak_position=0, root_stress_peak_tooth=0,
                   root_stress_peak_radius=0.05, root_stress_peak_face=0.0,
                   root_stress_peak_angle=40.0),
    )  # fmt: skip
    lines = root_stress_lines(ds)
    # stresses by the numformat rule (issue 32): 4 significant digits, no trailing zeros
    assert len(lines) == 3 and "stress: 100 MPa" in lines[0]
    ds["root_stress_face_ends"][1, 0, 2] = 150e6
    lines = root_stress_lines(ds)
    assert len(lines) == 4 and "face ends: up to 150 MPa" in lines[3]
    assert "not converged" in lines[3]


def test_khv_contact_analysis_gives_both_gears_root_stress():
    """The KHV internal pair through ``contact_analysis(root_stress=True)`` (coarse FE,
    tooth elements 0.35 m): planet and ring, every position, tension on the loaded
    fillets; the ring's own check against ISO 6336-3 is
    ``tests/published/test_iso6336_internal_root_stress.py``."""
    from reducerlab.analysis.contact import contact_analysis
    from reducerlab.analysis.contact_rootstress import root_stress_lines
    from reducerlab.drives import load_design
    from reducerlab.examples import example_dir

    design = load_design(example_dir() / "khv.toml")
    res = contact_analysis(design, torque=50.0, positions=6, order=2, root_stress=True,
                           tooth_size=0.35 * 3.5e-3)  # fmt: skip
    ds = res.data
    rs = ds["root_stress"].values  # (gear, position, tooth pair)
    assert rs.shape == (2, 6, 3)
    assert np.all(np.isfinite(rs))
    # the most loaded tooth of each gear at each position is in tension, its opposite
    # fillet in compression; measured 37.6 MPa (planet) and 24.8 MPa (ring) at 50 N m
    assert np.all(rs.max(axis=2) > 0) and np.all(ds["root_compressive"].values.min(axis=2) < 0)
    assert 10e6 < rs[0].max() < 100e6 and 5e6 < rs[1].max() < 100e6
    assert ds.attrs["root_stress_peak"] == pytest.approx(float(rs.max()))
    assert any("peak tooth-root stress" in line for line in root_stress_lines(ds))
