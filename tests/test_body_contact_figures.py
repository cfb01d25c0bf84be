"""Interactive gear-body mode renders and their place in the report (issue 32): the
decimated surface, the plotly ``Mesh3d`` coloured by the displacement magnitude, one
dropdown entry per mode, and a report that stays small."""

from __future__ import annotations

import math
from types import SimpleNamespace

import matplotlib
import numpy as np
import pytest
import xarray as xr

matplotlib.use("Agg")

from reducerlab.analysis.body_modal import BodyModalResult
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.plot.body import DEFORMATION, body_surface
from reducerlab.plot.body_plotly import decimate_surface, plotly_body_modes
from reducerlab.reporting import PLOTLY_FILE, report


def _plate(nx: int = 24, ny: int = 24, nz: int = 3, size=(0.04, 0.04, 0.004)):
    """A plate (m) of nx x ny x nz hexahedra, each split into six tetrahedra."""
    xs = [np.linspace(0.0, s, n + 1) for s, n in zip(size, (nx, ny, nz), strict=True)]
    X, Y, Z = np.meshgrid(*xs, indexing="ij")
    pts = np.c_[X.ravel(), Y.ravel(), Z.ravel()] - 0.5 * np.asarray(size)
    idx = np.arange(pts.shape[0]).reshape(nx + 1, ny + 1, nz + 1)
    c = [idx[i : i + nx, j : j + ny, k : k + nz].ravel()
         for i in (0, 1) for j in (0, 1) for k in (0, 1)]  # fmt: skip
    # corners 0..7 as (i, j, k) bits; Kuhn's six tetrahedra along the diagonal 0-7
    paths = [(4, 6), (4, 5), (2, 6), (2, 3), (1, 5), (1, 3)]
    tets = np.concatenate([np.c_[c[0], c[a], c[b], c[7]] for a, b in paths])
    vol = np.einsum(
        "ij,ij->i",
        np.cross(pts[tets[:, 1]] - pts[tets[:, 0]], pts[tets[:, 2]] - pts[tets[:, 0]]),
        pts[tets[:, 3]] - pts[tets[:, 0]],
    )
    tets[vol < 0] = tets[vol < 0][:, [0, 2, 1, 3]]
    return pts, tets


def _shapes(pts: np.ndarray) -> np.ndarray:
    """Three analytic shapes: bending (u_z ~ x^2 - y^2), twist (u_z ~ x y), in-plane."""
    x, y = pts[:, 0] / 0.02, pts[:, 1] / 0.02
    zero = np.zeros_like(x)
    s1 = np.c_[zero, zero, x**2 - y**2]
    s2 = np.c_[zero, zero, x * y]
    s3 = np.c_[x, -y, zero]
    return np.stack([s1, s2, s3], axis=2)


PLATE = _plate()
FREQ = np.array([1234.4, 2345.6, 9876.0])
TYPES = ["bending (n = 2)", "torsional (n = 1)", "radial (n = 0)"]


def _edges_used(tris: np.ndarray) -> np.ndarray:
    e = np.sort(np.r_[tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]], axis=1)
    return np.unique(e, axis=0, return_counts=True)[1]


def _volume(p: np.ndarray, tris: np.ndarray) -> float:
    a, b, c = p[tris[:, 0]], p[tris[:, 1]], p[tris[:, 2]]
    return float(np.einsum("ij,ij->", a, np.cross(b, c)) / 6.0)


def test_decimation_keeps_a_closed_oriented_surface_of_mesh_points():
    p, faces = body_surface(*PLATE)
    assert len(faces) > 2500
    verts, tris = decimate_surface(p, faces, 400)
    assert 350 <= len(tris) <= 400
    assert set(_edges_used(tris).tolist()) == {2}  # closed, a manifold
    # the same enclosed volume and orientation: the plate is still a plate
    assert _volume(p[verts], tris) == pytest.approx(_volume(p, faces), rel=0.02)
    # every point kept is a mesh point (its mode displacement exact there)
    assert np.unique(verts).size == verts.size and set(verts) <= set(np.unique(faces))
    # a small surface is left alone
    v2, t2 = decimate_surface(p, faces[:10], 600)
    assert len(t2) == 10 and np.array_equal(v2[t2], faces[:10])
    with pytest.raises(ReducerlabError, match="max_faces"):
        decimate_surface(p, faces, 3)


def test_plotly_body_modes_colour_by_displacement_with_one_entry_per_mode():
    pts, tets = PLATE
    shapes = _shapes(pts)
    fig = plotly_body_modes(pts, tets, shapes, FREQ, TYPES, "plate", max_faces=500)
    mesh, edges = fig.data[0], fig.data[1]
    assert mesh.type == "mesh3d" and edges.type == "scatter3d"
    assert len(mesh.i) <= 500
    assert mesh.colorbar.title.text == "|u| (normalised)"
    assert (mesh.cmin, mesh.cmax) == (0.0, 1.0)
    p, faces = body_surface(pts, tets)
    verts, tris = decimate_surface(p, faces, 500)
    np.testing.assert_array_equal(np.c_[mesh.i, mesh.j, mesh.k], tris)
    menu = fig.layout.updatemenus[0]
    assert [b.label for b in menu.buttons] == [
        f"mode {m + 1}: {FREQ[m]:.0f} Hz, {TYPES[m]}" for m in range(3)
    ]
    size = float(np.max(np.ptp(p[np.unique(faces)], axis=0)))
    for m, b in enumerate(menu.buttons):
        data = b.args[0]
        mag = np.linalg.norm(shapes[:, :, m], axis=1)
        want = mag[verts] / mag[np.unique(faces)].max()
        np.testing.assert_allclose(data["intensity"][0], want, atol=5.1e-3)
        # drawn = undeformed + scale u, the largest displacement DEFORMATION of the size
        drawn = np.c_[data["x"][0], data["y"][0], data["z"][0]]
        moved = np.linalg.norm(drawn - 1e3 * p[verts], axis=1)
        # (coordinates written to 4 significant digits: 0.01 mm on a 40 mm plate)
        assert moved.max() == pytest.approx(1e3 * DEFORMATION * size * want.max(), abs=0.01)
        np.testing.assert_allclose(moved, moved.max() * want / want.max(), atol=0.02)
        assert f"{100 * DEFORMATION:.0f} % of the body size" in b.args[1]["title.text"]
    # the initial trace is mode 1
    np.testing.assert_allclose(mesh.intensity, menu.buttons[0].args[0]["intensity"][0])
    with pytest.raises(ReducerlabError, match="frequencies"):
        plotly_body_modes(pts, tets, shapes, FREQ[:2], TYPES, "plate")


def _body_result(design, points, tets, shapes) -> BodyModalResult:
    ds = xr.Dataset(
        {"frequency": ("mode", FREQ, {"units": "Hz"}),
         "type": ("mode", np.array([t.split(" (")[0] for t in TYPES])),
         "nodal_diameters": ("mode", np.array([2, 1, 0]))},
        coords={"mode": [1, 2, 3]},
        attrs={"title": "gear 2 body", "design_hash": design.hash, "gear": 2,
               "boundary": "free"},
    )  # fmt: skip
    return BodyModalResult(ds, SimpleNamespace(points=points, tets=tets), shapes)


def test_report_shows_body_modes_as_an_interactive_render_and_stays_small(tmp_path):
    from reducerlab.drives import load_design

    path = example_dir() / "nutation_double_sided.toml"
    pts, tets = PLATE
    body = _body_result(load_design(path), pts, tets, _shapes(pts))
    r = report(path, results=[body], only=["bodies"])
    sec = r.section("bodies")
    assert sec.error is None
    blocks = [b for b in sec.blocks if b.kind == "interactive"]
    assert len(blocks) == 1
    html = blocks[0].html
    assert 'id="fig-body-modes-2"' in html and '"type":"mesh3d"' in html
    assert "<noscript><img" in html  # the matplotlib grid where scripts do not run
    for m in range(3):
        assert f"mode {m + 1}: {FREQ[m]:.0f} Hz" in html
    page = r.write(tmp_path / "bodies.html", plotly=tmp_path / PLOTLY_FILE)
    assert page.stat().st_size < 1e6
    assert len(html) < 4e5  # the render and its still: a few hundred kB at most


def test_a_body_without_its_mesh_keeps_the_table_only():
    from reducerlab.drives import load_design

    path = example_dir() / "nutation_double_sided.toml"
    pts, tets = PLATE
    body = _body_result(load_design(path), pts, tets, None)
    r = report(path, results=[body], only=["bodies"])
    kinds = [b.kind for b in r.section("bodies").blocks]
    assert "interactive" not in kinds and "table" in kinds
    assert math.isfinite(r.section("bodies").values["frequencies_hz"][0][0])


# ------------------------------------------------------------------ tooth renders


@pytest.fixture(scope="module")
def external_solid():
    from reducerlab.drives import load_design
    from reducerlab.geometry.solid import build_gear_solid

    d = load_design(example_dir() / "nutation_surface.toml")
    crown, bevel = d.tooth_generation(2)
    return build_gear_solid(crown, bevel, n_profile=15, n_face=15, n_land=3, n_space=7,
                            rim=d.surface.rim)  # fmt: skip


def test_tooth_render_has_a_dimensioned_section_from_the_design(external_solid):
    """The section's diameters against the bevel gear's closed forms at the mean cone
    distance: d = z m_n / cos beta_m, d_a = d + 2 h_a cos delta, d_f = d - 2 h_f cos
    delta, and the tooth thickness half the transverse pitch (a symmetric basic rack)."""
    from reducerlab.plot.surface import plot_tooth, tooth_section

    crown, gear = external_solid.crown, external_solid.gear
    prof = crown.profile
    z, m_n, beta = gear.teeth, 1e3 * prof.module, crown.spiral_angle
    d = z * m_n / math.cos(beta)
    cos_d = math.cos(gear.cone_angle)
    sec = tooth_section(external_solid)
    assert sec["d"] == pytest.approx(d, rel=1e-9)
    assert sec["d"] == pytest.approx(2e3 * crown.mean_cone_distance * math.sin(gear.cone_angle))
    assert sec["d_a"] == pytest.approx(d + 2e3 * prof.addendum * cos_d, abs=0.03)
    assert sec["d_f"] == pytest.approx(d - 2e3 * prof.dedendum * cos_d, abs=0.03)
    assert sec["h_a"] == pytest.approx(1e3 * prof.addendum, abs=0.02)
    assert sec["s"] == pytest.approx(math.pi * d / z / 2, abs=0.02)
    fig = plot_tooth(external_solid)
    ax3d, ax = fig.axes[:2]
    texts = [t.get_text() for t in ax.texts]
    for name, sym, value in (("tip", "d_a", sec["d_a"]), ("pitch", "d", d),
                             ("root", "d_f", sec["d_f"])):  # fmt: skip
        assert f"{name}: {sym} = {value:.2f} mm" in texts
    assert f"s = {sec['s']:.2f} mm" in texts
    assert any(f"m_n = {m_n:.4g} mm, alpha_n = 20 deg" in t for t in texts)
    assert ax.get_xlabel().endswith("(mm)") and ax.get_ylabel().endswith("(mm)")
    # the 3-D render: at most five ticks an axis, small labels
    for axis in (ax3d.xaxis, ax3d.yaxis, ax3d.zaxis):
        lo, hi = sorted(axis.get_view_interval())
        ticks = [t for t in axis.get_ticklocs() if lo <= t <= hi]
        assert 2 <= len(ticks) <= 5
