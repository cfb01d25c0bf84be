"""Mode-type names of gear bodies (paper 000 §4, Table 4): reducerlab.fe.modetypes.

Synthetic displacement fields whose type is known by construction on a point cloud of a
thick annulus, then real free-free FE modes of an annular plate and a short ring meshed
by gmsh, checked against plate and ring theory.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.errors import ReducerlabError
from reducerlab.fe.modetypes import (
    MODE_NAMES,
    ModeType,
    classify_mode,
    classify_modes,
    mode_families,
    node_shapes,
    vertex_shapes,
)

A, B, H = 0.03, 0.1, 0.02  # annulus radii and height (m)
N = 3000


@pytest.fixture(scope="module")
def cloud() -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Random points of the thick annulus: (points, r, theta, z)."""
    rng = np.random.default_rng(20240614)
    r = np.sqrt(rng.uniform(A * A, B * B, N))  # uniform over the area
    theta = rng.uniform(0.0, 2 * math.pi, N)
    z = rng.uniform(0.0, H, N)
    return np.c_[r * np.cos(theta), r * np.sin(theta), z], r, theta, z


def cartesian(theta: np.ndarray, ur=0.0, ut=0.0, uz=0.0) -> np.ndarray:
    """Cartesian displacements from cylindrical components (broadcast to the nodes)."""
    ur, ut, uz = (np.broadcast_to(np.asarray(c, dtype=float), theta.shape) for c in (ur, ut, uz))
    c, s = np.cos(theta), np.sin(theta)
    return np.c_[ur * c - ut * s, ur * s + ut * c, uz]


def fields(r, theta, z, shift=0.0) -> dict[str, tuple[np.ndarray, str, int, int | None]]:
    """Known fields: name -> (u, type, nodal diameters, nodal circles or None).

    ``shift`` turns the pattern about the axis (theta -> theta + shift).
    """
    t = theta + shift
    # an n = 1 axial field with the rigid tilt (u_z ~ r cos theta) projected out
    g = r**2 - (np.sum(r**3) / np.sum(r**2)) * r
    zc = z - H / 2
    return {
        "bending n=2": (cartesian(theta, uz=np.cos(2 * t)), "bending", 2, 0),
        "bending n=3 two circles": (
            cartesian(theta, uz=(r - 0.05) * (r - 0.08) * np.cos(3 * t)),
            "bending",
            3,
            2,
        ),
        "umbrella": (cartesian(theta, uz=(r / B) ** 2), "umbrella", 0, 0),
        "umbrella one circle": (cartesian(theta, uz=r - 0.065), "umbrella", 0, 1),
        "circumferential": (cartesian(theta, ut=r), "circumferential", 0, 0),
        "breathing": (cartesian(theta, ur=r), "radial", 0, 0),
        "radial n=2": (
            cartesian(theta, ur=np.cos(2 * t), ut=-np.sin(2 * t) / 2),  # inextensional
            "radial",
            2,
            0,
        ),
        "folding n=2": (
            cartesian(theta, ur=zc * np.cos(2 * t), ut=-zc * np.sin(2 * t) / 2),
            "folding",
            2,
            0,
        ),
        "torsional": (cartesian(theta, uz=g * np.cos(t)), "torsional", 1, None),
    }


CASES = list(fields(np.ones(1), np.zeros(1), np.zeros(1)))


@pytest.mark.parametrize("case", CASES)
def test_known_fields(cloud, case):
    p, r, theta, z = cloud
    u, name, n, circles = fields(r, theta, z)[case]
    m = classify_mode(p, u)
    assert isinstance(m, ModeType) and m.family is None
    assert m.name == name and m.name in MODE_NAMES
    assert m.nodal_diameters == n
    if circles is not None:
        assert m.nodal_circles == circles
    assert m.purity > 0.95
    assert sum(m.shares.values()) == pytest.approx(1.0)
    assert set(m.shares) == {"radial", "tangential", "axial"}


def test_shares_and_axial_reversal(cloud):
    p, r, theta, z = cloud
    f = fields(r, theta, z)
    radial = classify_mode(p, f["radial n=2"][0])
    # u_r = cos 2t, u_t = -sin 2t / 2: mean squares 1/2 and 1/8
    assert radial.shares["radial"] == pytest.approx(0.8, abs=0.02)
    assert radial.shares["tangential"] == pytest.approx(0.2, abs=0.02)
    assert radial.shares["axial"] == 0.0
    assert radial.axial_reversal == pytest.approx(-1.0, abs=0.05)  # ends in phase
    assert classify_mode(p, f["folding n=2"][0]).axial_reversal > 0.9  # ends in anti-phase
    assert math.isnan(classify_mode(p, f["bending n=2"][0]).axial_reversal)  # no in-plane


@pytest.mark.parametrize("case", CASES)
def test_robust_to_noise_scale_and_turning(cloud, case):
    p, r, theta, z = cloud
    u, name, n, circles = fields(r, theta, z)[case]
    rng = np.random.default_rng(7)
    noisy = u + 0.1 * np.abs(u).max() * rng.standard_normal(u.shape)
    m = classify_mode(p, 1e-6 * noisy)
    assert (m.name, m.nodal_diameters) == (name, n)
    if circles is not None:
        assert m.nodal_circles == circles
    # the pattern turned about the axis (a pair's other member for n >= 1)
    shift = math.pi / (2 * max(n, 1))
    turned = classify_mode(p, fields(r, theta, z, shift)[case][0])
    assert (turned.name, turned.nodal_diameters) == (name, n)


def test_frame_turned_about_axis(cloud):
    """The type does not depend on where theta = 0 is."""
    p, r, theta, z = cloud
    u = fields(r, theta, z)["folding n=2"][0]
    c, s = math.cos(0.7), math.sin(0.7)
    R = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    assert classify_mode(p @ R.T, u @ R.T).name == "folding"


def test_weights(cloud):
    p, r, theta, z = cloud
    u = fields(r, theta, z)["bending n=2"][0].copy()
    junk = np.arange(N) % 5 == 0
    u[junk] = [3.0, -2.0, 5.0]  # large junk on nodes of zero mass
    w = np.where(junk, 0.0, 1.0)
    m = classify_mode(p, u, weights=w)
    assert (m.name, m.nodal_diameters) == ("bending", 2)
    assert m.purity > 0.99
    unweighted = classify_mode(p, u)  # the junk (a translation of 20 % of the nodes) wins
    assert (unweighted.name, unweighted.nodal_diameters) == ("umbrella", 0)
    assert unweighted.purity < 0.5


def test_points_on_the_axis_are_ignored(cloud):
    p, r, theta, z = cloud
    u = fields(r, theta, z)["radial n=2"][0]
    axis = np.c_[np.zeros(20), np.zeros(20), np.linspace(0, H, 20)]
    m = classify_mode(np.r_[p, axis], np.r_[u, np.zeros((20, 3))])
    assert (m.name, m.nodal_diameters) == ("radial", 2)


def test_pair_members_named_alike(cloud):
    """Any orthogonal combination of a pair (a mode solver's choice) is named alike."""
    p, r, theta, z = cloud
    out = []
    for case in ("bending n=2", "radial n=2", "folding n=2", "torsional"):
        n = fields(r, theta, z)[case][2]
        u1 = fields(r, theta, z)[case][0]
        u2 = fields(r, theta, z, math.pi / (2 * n))[case][0]
        a = 0.4
        out += [math.cos(a) * u1 + math.sin(a) * u2, -math.sin(a) * u1 + math.cos(a) * u2]
    shapes = np.stack(out, axis=2)
    freqs = np.array([100.0, 100.3, 250.0, 250.0, 400.0, 401.0, 90.0, 90.5])
    modes = classify_modes(p, shapes, freqs)
    names = [m.name for m in modes]
    assert names == ["bending"] * 2 + ["radial"] * 2 + ["folding"] * 2 + ["torsional"] * 2
    assert [m.family for m in modes] == [1, 1, 2, 2, 3, 3, 0, 0]  # families by frequency
    for first, second in zip(modes[::2], modes[1::2], strict=True):
        assert first.nodal_diameters == second.nodal_diameters
        assert first.nodal_circles == second.nodal_circles
        assert first.shares == second.shares and first.purity == second.purity


def test_mode_families():
    f = [100.0, 300.0, 100.5, 101.0, 200.0, 200.0, 0.0, 0.0]
    n = [2, 3, 2, 2, 0, 0, 1, 1]
    assert mode_families(f, n) == [(6, 7), (0, 2), (3,), (4,), (5,), (1,)]
    assert mode_families([100.0, 103.0], [2, 2]) == [(0,), (1,)]
    assert mode_families([100.0, 103.0], [2, 2], tol=0.05) == [(0, 1)]
    assert mode_families([100.0, 100.0], [2, 3]) == [(0,), (1,)]
    assert mode_families([], []) == []


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda p, u: classify_mode(p[:, :2], u), "points must have shape"),
        (lambda p, u: classify_mode(p, u[:-1]), "displacement must have shape"),
        (lambda p, u: classify_mode(p, np.where(u > 0.5, np.nan, u)), "displacement must be"),
        (lambda p, u: classify_mode(p, 0 * u), "displacement must not be zero"),
        (lambda p, u: classify_mode(p * [0, 0, 1], u), "points must not all lie on the axis"),
        (lambda p, u: classify_mode(p, u, weights=-np.ones(len(p))), "weights must be >= 0"),
        (lambda p, u: classify_mode(p, u, weights=np.ones(3)), "weights must have shape"),
        (lambda p, u: classify_mode(p, u, kmax=0), "kmax must be an integer"),
        (lambda p, u: classify_mode(p[:3], u[:3]), "points must hold at least 5"),
        (lambda p, u: classify_modes(p, u, [1.0]), r"shapes must have shape \(n, 3, modes\)"),
        (lambda p, u: classify_modes(p, u[:, :, None], [1.0, 2.0]), "frequencies must have"),
        (lambda p, u: classify_modes(p, u[:, :, None], [-1.0]), "frequencies must be >= 0"),
        (lambda p, u: classify_modes(p, u[:, :, None], [1.0], pair_tol=-1), "pair_tol"),
        (
            lambda p, u: classify_modes(p, np.stack([u, 0 * u], 2), [1.0, 2.0]),
            r"mode\(s\) \[1\] are zero",
        ),
        (lambda p, u: mode_families([1.0, 2.0], [1]), "nodal_diameters must be integers"),
    ],
)
def test_bad_input(cloud, call, match):
    p, r, theta, z = cloud
    u = fields(r, theta, z)["bending n=2"][0]
    with pytest.raises(ReducerlabError, match=match):
        call(p, u)


# -- real FE modes -----------------------------------------------------------------------


def annulus_modes(a: float, b: float, h: float, size: float, count: int):
    """Free-free modes of the annulus ``a <= r <= b``, ``0 <= z <= h`` (m), P2 tets."""
    gmsh = pytest.importorskip("gmsh")
    skfem = pytest.importorskip("skfem")
    from reducerlab.fe import assemble, body_modes

    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        occ = gmsh.model.occ
        outer = occ.addCylinder(0, 0, 0, 0, 0, h, b)
        inner = occ.addCylinder(0, 0, 0, 0, 0, h, a)
        occ.cut([(3, outer)], [(3, inner)])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, _, nodes = gmsh.model.mesh.getElements(3, -1)
    finally:
        gmsh.finalize()
    index = np.full(int(tags.max()) + 1, -1)
    index[tags] = np.arange(len(tags))
    tets = index[nodes[0].reshape(-1, 4)]
    used = np.unique(tets)
    local = np.full(len(tags), -1)
    local[used] = np.arange(len(used))
    points = coords.reshape(-1, 3)[used]
    mesh = skfem.MeshTet(np.ascontiguousarray(points.T), np.ascontiguousarray(local[tets].T))
    K, M, basis = assemble(mesh)
    modes = body_modes(K, M, count=count)
    p, shapes = vertex_shapes(basis, modes.shapes)
    return p, shapes, modes.frequencies


def test_free_annular_plate():
    """Thin free annular plate (b/a = 3.3, h/2b = 0.04): Leissa's order of the lowest
    modes is (n, s) = (2, 0) pair, (0, 1), (3, 0) pair, (1, 1) pair: out-of-plane."""
    p, shapes, f = annulus_modes(0.03, 0.1, 0.008, 0.016, 7)
    assert shapes.shape == (len(p), 3, 7)
    modes = classify_modes(p, shapes, f)
    got = [(m.name, m.nodal_diameters, m.nodal_circles) for m in modes]
    assert got == [
        ("bending", 2, 0),
        ("bending", 2, 0),
        ("umbrella", 0, 1),
        ("bending", 3, 0),
        ("bending", 3, 0),
        ("torsional", 1, 1),
        ("torsional", 1, 1),
    ]
    assert [m.family for m in modes] == [0, 0, 1, 2, 2, 3, 3]
    assert all(m.shares["axial"] > 0.9 and m.purity > 0.95 for m in modes)
    # Kirchhoff plate: f = lambda^2 / (2 pi b^2) sqrt(D / (rho h)); the (2, 0) mode of a
    # free annular plate of a/b = 0.3 has lambda^2 close to the full disc's 5.25
    E, nu, rho, h, b = 206e9, 0.29, 7850.0, 0.008, 0.1
    D = E * h**3 / (12 * (1 - nu**2))
    lam2 = f[0] * 2 * math.pi * b**2 / math.sqrt(D / (rho * h))
    assert 4.5 < lam2 < 5.5


def test_free_short_ring():
    """Short thin ring: the lowest pair is the in-plane inextensional n = 2 mode (an
    elliptical end face, no axial motion: "radial"), at the thin-ring frequency
    omega = n (n^2 - 1) / sqrt(n^2 + 1) sqrt(E I / (rho A R^4))."""
    a, b, h = 0.08, 0.09, 0.04
    p, shapes, f = annulus_modes(a, b, h, 0.02, 2)
    modes = classify_modes(p, shapes, f)
    assert [(m.name, m.nodal_diameters, m.family) for m in modes] == [("radial", 2, 0)] * 2
    assert modes[0].shares["axial"] < 0.01
    R, t = (a + b) / 2, b - a
    omega = 6 / math.sqrt(5) * math.sqrt(206e9 / 7850.0 * t**2 / 12) / R**2
    assert f[0] == pytest.approx(omega / (2 * math.pi), rel=0.05)


def graded_ring(a: float, b: float, h: float, sectors: int, layers: int):
    """A polygonal ring (``sectors`` sides, ``a <= r <= b``, ``0 <= z <= h``) of P2 tets
    whose layers crowd towards ``z = 0`` (``z_k = h (k / layers)^3``): 3/4 of its nodes
    lie in the lower half. Returns the skfem mesh."""
    skfem = pytest.importorskip("skfem")
    s = np.linspace(0.0, 1.0, layers + 1)
    m = skfem.MeshTet.init_tensor(
        np.array([a, b]), np.arange(sectors + 1) * (2 * math.pi / sectors), h * s**3
    )
    r, t, z = m.p
    # close the ring: the nodes at t = 2 pi are those at t = 0
    seam = np.isclose(t, 2 * math.pi)
    start = np.flatnonzero(np.isclose(t, 0.0))
    key = {(round(r[i] / h, 9), round(z[i] / h, 9)): i for i in start}
    target = np.arange(m.p.shape[1])
    target[seam] = [key[(round(r[i] / h, 9), round(z[i] / h, 9))] for i in np.flatnonzero(seam)]
    tets = target[m.t]
    keep = np.unique(tets)
    new = np.full(m.p.shape[1], -1)
    new[keep] = np.arange(len(keep))
    p = np.array([r * np.cos(t), r * np.sin(t), z])[:, keep]
    return skfem.MeshTet(np.ascontiguousarray(p), np.ascontiguousarray(new[tets]))


def test_shares_are_mass_weighted_on_a_graded_mesh():
    """Issue 26 (8a): the shares are shares of the body's kinetic energy, not of its
    nodes. On a prism ``0 <= z <= h`` any field ``f(x, y) g(z)`` integrates as
    ``int f dA int g dz``, so ``u_r = cos 2t``, ``u_z = B (z / h) cos 2t`` has the axial
    share ``(B^2 / 3) / (1 + B^2 / 3)`` exactly, whatever the cross-section: 0.6 for
    ``B^2 = 4.5`` ("bending", the paper's n = 2 pair mostly axial). The mesh crowds its
    nodes where ``u_z`` is small, so counting nodes gives ~0.43 ("radial"); the HRZ
    masses of :func:`node_shapes` give the integral."""
    from reducerlab.fe import assemble

    h = 0.02
    mesh = graded_ring(0.03, 0.05, h, 24, 8)
    _, M, basis = assemble(mesh)
    p, _, w = node_shapes(basis, np.zeros(basis.N), M)
    assert np.mean(p[:, 2] < h / 2) > 0.7  # the nodes crowd at the bottom
    # the weights: positive, summing to the prism's mass (rho area h)
    area = 0.5 * 24 * math.sin(2 * math.pi / 24) * (0.05**2 - 0.03**2)
    assert np.all(w > 0) and w.sum() == pytest.approx(7850.0 * area * h, rel=1e-12)
    t, z = np.arctan2(p[:, 1], p[:, 0]), p[:, 2]
    ur, uz = np.cos(2 * t), math.sqrt(4.5) * z / h * np.cos(2 * t)
    u = np.c_[ur * np.cos(t), ur * np.sin(t), uz]
    weighted = classify_mode(p, u, w)
    assert (weighted.name, weighted.nodal_diameters) == ("bending", 2)
    assert weighted.shares["axial"] == pytest.approx(0.6, abs=0.005)
    by_nodes = classify_mode(p, u)  # the old equal weights: a share of the nodes
    assert (by_nodes.name, by_nodes.nodal_diameters) == ("radial", 2)
    assert by_nodes.shares["axial"] < 0.45
    # node_shapes hands back the shapes at the same nodes, vertices then mid-edge nodes
    phi = np.zeros(basis.N)
    phi[basis.nodal_dofs[2]] = 1.0
    phi[basis.edge_dofs[2]] = 1.0
    _, d, _ = node_shapes(basis, phi, M)
    assert d.shape == (len(p), 3, 1) and np.all(d[:, 2, 0] == 1.0) and not np.any(d[:, :2])


def test_node_shapes_bad_input():
    from reducerlab.fe import assemble

    mesh = graded_ring(0.03, 0.05, 0.02, 8, 1)
    _, M, basis = assemble(mesh, order=1)
    with pytest.raises(ReducerlabError, match="shapes must have"):
        node_shapes(basis, np.zeros(basis.N + 1), M)
    with pytest.raises(ReducerlabError, match="mass must be"):
        node_shapes(basis, np.zeros(basis.N), M[:-1])
    with pytest.raises(ReducerlabError, match="diagonal entry"):
        node_shapes(basis, np.zeros(basis.N), -M)


def test_ring_fit_is_the_least_squares_solution():
    """A ring's fit (one pseudo-inverse for all modes) gives ``numpy.linalg.lstsq``'s
    weighted least-squares harmonics."""
    from reducerlab.fe.modetypes import _fit, _fourier

    rng = np.random.default_rng(3)
    theta = np.sort(rng.uniform(-np.pi, np.pi, 60))
    w = rng.uniform(0.5, 2.0, 60)
    values = rng.standard_normal((60, 3, 2))
    k = 5
    got = _fourier(_fit(theta, w, k), values, k)
    cols = [np.ones_like(theta)]
    for j in range(1, k + 1):
        cols += [np.cos(j * theta), np.sin(j * theta)]
    sw = np.sqrt(w)[:, None]
    x = np.linalg.lstsq(np.stack(cols, 1) * sw, values.reshape(60, -1) * sw, rcond=None)[0]
    x = x.reshape(2 * k + 1, 3, 2)
    np.testing.assert_allclose(got[0].real, x[0], atol=1e-12)
    np.testing.assert_allclose(got[1:], x[1::2] - 1j * x[2::2], atol=1e-12)
