"""Output of FE bodies and their modes: boundary triangles of a tetrahedral mesh, VTU
files (meshio round trip) and renders of mode shapes (issue 14)."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest
from skfem import MeshTet

from reducerlab.errors import ReducerlabError
from reducerlab.fe.vtu import boundary_faces, mode_field_names, write_vtu
from reducerlab.plot.body import ELEV, plot_body_mode, plot_body_modes_grid, view_elevation

SIDES = (0.02, 0.03, 0.05)  # m


def box():
    """A 20 x 30 x 50 mm box of 162 tetrahedra of both orientations (scikit-fem)."""
    m = MeshTet.init_tensor(*[np.linspace(0.0, s, 4) for s in SIDES])
    return m.p.T.copy(), m.t.T.copy()


def annulus(nr=3, nt=36, nz=3, ri=0.02, ro=0.05, h=0.01):
    """A ring (m): a scikit-fem tensor mesh in (r, theta, z) mapped to x, y, z, the
    points at theta = 2 pi merged with those at 0."""
    m = MeshTet.init_tensor(
        np.linspace(ri, ro, nr), np.linspace(0.0, 2 * np.pi, nt + 1), np.linspace(0.0, h, nz)
    )
    r, th, z = m.p
    th = np.where(np.isclose(th, 2 * np.pi), 0.0, th)
    p = np.c_[r * np.cos(th), r * np.sin(th), z]
    _, first, inverse = np.unique(
        np.round(p / 1e-9).astype(np.int64), axis=0, return_index=True, return_inverse=True
    )
    return p[first], inverse.reshape(-1)[m.t.T]


def wave(p, n=2):
    """An n-diameter bending wave: axial displacement growing with the radius."""
    r, th = np.hypot(p[:, 0], p[:, 1]), np.arctan2(p[:, 1], p[:, 0])
    return np.c_[0 * r, 0 * r, (r / r.max()) ** 2 * np.cos(n * th)]


def areas_normals(p, f):
    a = p[f[:, 0]]
    n = 0.5 * np.cross(p[f[:, 1]] - a, p[f[:, 2]] - a)
    return n, p[f].mean(axis=1)


# -- boundary faces ----------------------------------------------------------------------


def test_boundary_faces_of_a_box_are_its_outward_surface():
    p, t = box()
    f = boundary_faces(t, p)
    assert f.shape == (6 * 9 * 2, 3) and f.dtype == np.int64
    n, c = areas_normals(p, f)
    a, b, h = SIDES
    assert np.linalg.norm(n, axis=1).sum() == pytest.approx(2 * (a * b + b * h + a * h))
    # outward: each normal points away from the box's centre (a convex body) ...
    assert np.all(np.einsum("ij,ij->i", n, c - 0.5 * np.array(SIDES)) > 0)
    # ... and the divergence theorem gives the volume
    assert np.einsum("ij,ij->", c, n) / 3 == pytest.approx(a * b * h, rel=1e-12)
    # every face lies on the box's surface
    on = np.isclose(c, 0.0) | np.isclose(c, np.array(SIDES))
    assert np.all(on.any(axis=1))


def test_boundary_faces_do_not_depend_on_tet_orientation():
    p, t = box()
    flipped = t.copy()
    flipped[::3, [0, 1]] = flipped[::3, [1, 0]]
    f1, f2 = boundary_faces(t, p), boundary_faces(flipped, p)
    key = lambda f: {tuple(np.roll(x, -int(np.argmin(x)))) for x in f}  # noqa: E731
    assert key(f1) == key(f2)  # the same triangles, turned the same way


def test_boundary_faces_without_points_trust_positive_tets():
    p, t = box()
    q = p[t]
    vol = np.einsum("ij,ij->i", np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), q[:, 3] - q[:, 0])
    t[vol < 0] = t[vol < 0][:, [1, 0, 2, 3]]  # all positive now
    assert np.array_equal(boundary_faces(t), boundary_faces(t, p))


def test_boundary_faces_of_a_ring():
    p, t = annulus()
    f = boundary_faces(t, p)
    n, c = areas_normals(p, f)
    volume = np.pi * (0.05**2 - 0.02**2) * 0.01  # the faceted ring holds a little less
    assert np.einsum("ij,ij->", c, n) / 3 == pytest.approx(volume, rel=0.01)
    assert len(f) == 2 * 36 * (2 * 2 + 2 * 2)  # 2 triangles a quad: 36 around, 2 x 2 across
    assert len(np.unique(f)) == len(p) - 36  # all but the 36 points inside the ring


def test_boundary_faces_reject_non_conforming_meshes():
    p, t = box()
    with pytest.raises(ReducerlabError, match="more than two tetrahedra"):
        boundary_faces(np.vstack([t, t[:1]]), p)
    with pytest.raises(ReducerlabError, match="tets: must have shape"):
        boundary_faces(t[:, :3])
    with pytest.raises(ReducerlabError, match="tets: vertex index 64 out of range"):
        boundary_faces(np.vstack([t, [[0, 1, 2, 64]]]), p)


# -- VTU ---------------------------------------------------------------------------------


def test_vtu_round_trip(tmp_path):
    p, t = annulus()
    rng = np.random.default_rng(3)
    shapes = np.stack([wave(p, 2), wave(p, 3), rng.normal(size=p.shape)], axis=-1)
    freqs = [4162.7, 4163.01, 5466.0]
    types = ["bending (n=2)", "bending (n=3)", "folding (n = 2)"]
    quality = rng.uniform(size=len(t))
    out = write_vtu(tmp_path / "ring.vtu", p, t, shapes, freqs, types, {"quality": quality})
    assert out == tmp_path / "ring.vtu" and not list(tmp_path.glob("*.vtu.*"))
    names = ["mode_01_4162.7Hz_bending_n_2", "mode_02_4163.0Hz_bending_n_3",
             "mode_03_5466.0Hz_folding_n_2"]  # fmt: skip
    assert mode_field_names(freqs, types) == names
    m = meshio.read(out)
    np.testing.assert_allclose(m.points, p, rtol=0, atol=0)  # metres, untouched
    assert [c.type for c in m.cells] == ["tetra"]
    np.testing.assert_array_equal(m.cells[0].data, t)
    assert sorted(m.point_data) == sorted(names + [f"{n}_magnitude" for n in names])
    for i, name in enumerate(names):
        np.testing.assert_allclose(m.point_data[name], shapes[:, :, i], rtol=1e-15)
        np.testing.assert_allclose(
            m.point_data[f"{name}_magnitude"], np.linalg.norm(shapes[:, :, i], axis=1)
        )
    np.testing.assert_allclose(m.field_data["frequency_Hz"], freqs, rtol=0)
    np.testing.assert_array_equal(m.field_data["mode"], [1, 2, 3])
    np.testing.assert_allclose(m.cell_data["quality"][0], quality)
    # a well-formed VTK XML file: field data before the piece, the units stated
    root = ET.parse(out).getroot()
    grid = root.find("UnstructuredGrid")
    assert [c.tag for c in grid] == ["FieldData", "Piece"]
    assert "points in metres" in out.read_text()


def test_vtu_mesh_only_and_single_mode(tmp_path):
    p, t = box()
    m = meshio.read(write_vtu(str(tmp_path / "box.vtu"), p, t))
    assert m.point_data == {} and m.field_data == {}
    assert len(m.cells[0].data) == len(t)
    m = meshio.read(write_vtu(tmp_path / "one.vtu", p, t, shapes=np.ones_like(p)))
    assert sorted(m.point_data) == ["mode_01", "mode_01_magnitude"]
    np.testing.assert_allclose(m.point_data["mode_01_magnitude"], math.sqrt(3))
    names = mode_field_names(np.arange(100.0))
    assert names[0] == "mode_001_0.0Hz" and names[-1] == "mode_100_99.0Hz"


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"points": np.zeros((64, 2))}, "points: must have shape"),
        ({"points": "abc"}, "points: must be an array of numbers"),
        ({"points": np.full((64, 3), np.nan)}, "points: must be finite"),
        ({"tets": np.full((4, 4), 1.5)}, "tets: must be an array of integer"),
        ({"tets": [[0, 1, 2, 99]]}, r"tets: vertex index 99 out of range for 64 points"),
        ({"tets": [[0, 1, 2, -1]]}, "tets: vertex indices must be >= 0"),
        ({"tets": [[0, 1, 1, 2]]}, "tets: a tetrahedron repeats a vertex"),
        ({"tets": np.zeros((0, 4), int)}, "tets: need at least one"),
        ({"shapes": np.zeros((63, 3, 2))}, r"shapes: must have shape \(64, 3\)"),
        ({"shapes": np.full((64, 3, 2), np.inf)}, "shapes: must be finite"),
        ({"shapes": np.zeros((64, 3, 2)), "frequencies": [1.0]}, "frequencies: must be 1-D"),
        ({"shapes": np.zeros((64, 3, 2)), "frequencies": [1.0, -2.0]}, "frequencies: must"),
        ({"frequencies": [1.0]}, "frequencies: given without shapes"),
        ({"shapes": np.zeros((64, 3, 2)), "types": ["a"]}, r"types: need one per mode \(2\)"),
        ({"shapes": np.zeros((64, 3, 2)), "types": "ab"}, "types: must be a sequence of str"),
        ({"cell_data": {"q": np.ones(3)}}, r"cell_data\['q'\]: must have shape \(162,\)"),
        ({"cell_data": {"q": [np.nan] * 162}}, r"cell_data\['q'\]: must be finite"),
    ],
)
def test_vtu_bad_input(tmp_path, kwargs, match):
    p, t = box()
    args = {"path": tmp_path / "bad.vtu", "points": p, "tets": t, **kwargs}
    with pytest.raises(ReducerlabError, match=match):
        write_vtu(**args)
    assert not list(tmp_path.iterdir())


def test_vtu_missing_folder(tmp_path):
    p, t = box()
    with pytest.raises(ReducerlabError, match=r"path: folder .* does not exist"):
        write_vtu(tmp_path / "nope" / "x.vtu", p, t)


# -- renders -----------------------------------------------------------------------------


def colorbars(fig):
    return [a for a in fig.axes if getattr(a, "_colorbar", None) is not None]


def test_render_one_mode(tmp_path):
    from matplotlib.figure import Figure

    p, t = annulus()
    title = "Ring, mode 3: 5466 Hz, bending (n = 2)"
    fig = plot_body_mode(p, t, 1e-3 * wave(p), title)
    assert isinstance(fig, Figure)
    assert fig._suptitle.get_text() == title
    (cbar,) = colorbars(fig)
    assert cbar.get_ylabel() == "|u| (normalised)"
    (ax,) = [a for a in fig.axes if a.name == "3d"]
    assert ax.elev == ELEV
    texts = " ".join(t.get_text() for t in fig.texts)
    assert "8 % of the body size" in texts
    out = tmp_path / "mode.png"
    fig.savefig(out, dpi=80)
    assert out.stat().st_size > 10_000


def test_render_faces_and_scale(tmp_path):
    """Boundary faces instead of tetrahedra (also inward ones) and an explicit scale."""
    p, t = annulus()
    f = boundary_faces(t, p)
    for faces in (f, f[:, ::-1]):
        fig = plot_body_mode(p, faces, wave(p), "faces", scale=2e-3, elev=-20.0, azim=10)
        assert "2 % of the body size" in " ".join(x.get_text() for x in fig.texts)
        fig.savefig(tmp_path / "f.png", dpi=50)
    fig = plot_body_mode(p, t, np.zeros_like(p), "at rest")
    assert "no displacement" in fig.texts[-1].get_text()
    fig.savefig(tmp_path / "rest.png", dpi=50)


def test_render_grid(tmp_path):
    p, t = annulus()
    shapes = np.stack([wave(p, n) for n in range(1, 11)], axis=-1)
    types = [f"bending (n = {n})" for n in range(1, 11)]
    fig = plot_body_modes_grid(p, t, shapes, np.linspace(1e3, 1e4, 10), types, "Ring modes")
    assert len([a for a in fig.axes if a.name == "3d"]) == 10
    assert len(colorbars(fig)) == 1
    labels = [x.get_text() for x in fig.texts]
    assert "mode 1: 1000 Hz\nbending (n = 1)" in labels and fig._suptitle.get_text() == "Ring modes"
    out = tmp_path / "grid.png"
    fig.savefig(out, dpi=60)
    assert out.stat().st_size > 20_000
    fig = plot_body_modes_grid(p, t, shapes[:, :, :3], [1.0, 2.0, 3.0], ["a", "b", "c"], "3")
    assert len([a for a in fig.axes if a.name == "3d"]) == 3


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"tets_or_faces": np.zeros((3, 5), int)}, r"tets_or_faces: must have shape \(m, 4\)"),
        ({"tets_or_faces": [[0, 1, 9999]]}, "tets_or_faces: vertex indices must be in"),
        ({"tets_or_faces": [[0.0, 1.0, 2.0]]}, "tets_or_faces: must be an array of integer"),
        ({"displacement": np.zeros((3, 3))}, r"displacement: must have shape \(324, 3\)"),
        ({"displacement": np.full((324, 3), np.nan)}, "displacement: must be finite"),
        ({"scale": -1.0}, "scale: must be finite and >= 0"),
        ({"scale": "big"}, "scale: must be a number"),
        ({"title": None}, "title: must be a str"),
        ({"elev": math.inf}, "elev: must be finite"),
    ],
)
def test_render_bad_input(kwargs, match):
    p, t = annulus()
    args = {"points": p, "tets_or_faces": t, "displacement": wave(p), "title": "x", **kwargs}
    with pytest.raises(ReducerlabError, match=match):
        plot_body_mode(**args)


def test_render_grid_bad_input():
    p, t = annulus()
    s = np.stack([wave(p, 2), wave(p, 3)], axis=-1)
    with pytest.raises(ReducerlabError, match=r"frequencies: need one per mode \(2\)"):
        plot_body_modes_grid(p, t, s, [1.0], ["a", "b"], "x")
    with pytest.raises(ReducerlabError, match=r"types: need one per mode \(2\)"):
        plot_body_modes_grid(p, t, s, [1.0, 2.0], ["a"], "x")
    with pytest.raises(ReducerlabError, match=r"shapes: must have shape \(324, 3, modes\)"):
        plot_body_modes_grid(p, t, s[:5], [1.0, 2.0], ["a", "b"], "x")
    with pytest.raises(ReducerlabError, match="ncols: must be an integer"):
        plot_body_modes_grid(p, t, s, [1.0, 2.0], ["a", "b"], "x", ncols=0)


def test_view_from_the_side_the_teeth_face():
    """Ridges on one face of a ring (sloped flanks about z) are looked at from their side;
    a plain ring is seen from above."""
    p, t = annulus(nt=72)
    f = boundary_faces(t, p)
    assert view_elevation(p, f) == ELEV
    th = np.arctan2(p[:, 1], p[:, 0])
    ridged = p.copy()
    ridged[:, 2] *= 1 + 0.8 * np.abs(np.sin(6 * th))  # 12 teeth on the top face
    assert view_elevation(ridged, f) == ELEV
    mirrored = ridged * [1, 1, -1]
    assert view_elevation(mirrored, boundary_faces(t, mirrored)) == -ELEV


def test_vtu_file_permissions(tmp_path):
    import os

    umask = os.umask(0)
    os.umask(umask)
    p, t = box()
    out = write_vtu(tmp_path / "box.vtu", p, t)
    assert out.stat().st_mode & 0o777 == 0o666 & ~umask


def test_render_tight_bbox_keeps_the_figure(tmp_path):
    """The 3-D axes' squares reach out of the figure; a tight save must not grow it."""
    from PIL import Image

    p, t = annulus()
    fig = plot_body_mode(p, t, wave(p), "tight")
    w, h = fig.get_size_inches() * 50
    fig.savefig(tmp_path / "t.png", dpi=50, bbox_inches="tight", pad_inches=0)
    tw, th = Image.open(tmp_path / "t.png").size
    assert tw <= w + 1 and th <= h + 1
