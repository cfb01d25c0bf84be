"""The elastic half-space layer (reducerlab.contact.halfspace): Love's rectangle formula
against numerical integration of Boussinesq's point-force solution, the compliance
matrix of a cell grid, the subsurface stresses and the input errors. Every oracle is
cited and every tolerance justified inline."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy.integrate import dblquad

from reducerlab.contact.halfspace import (
    FAR_FIELD,
    combined_modulus,
    influence_matrix,
    max_subsurface_von_mises,
    rectangle_influence,
    subsurface_stress,
    von_mises,
)
from reducerlab.errors import ReducerlabError


def _integral_inv_r(dx: float, dy: float, a: float, b: float) -> float:
    """``int int dxi deta / sqrt((dx - xi)^2 + (dy - eta)^2)`` over ``|xi| <= a, |eta| <= b``
    by adaptive quadrature (QUADPACK via scipy's dblquad), split at the field point so
    that the integrable ``1/r`` singularity sits at a corner of each piece."""
    xs = sorted({-a, a, *([dx] if -a < dx < a else [])})
    ys = sorted({-b, b, *([dy] if -b < dy < b else [])})
    total = 0.0
    for x0, x1 in itertools.pairwise(xs):
        for y0, y1 in itertools.pairwise(ys):
            val, _ = dblquad(
                lambda eta, xi: 1.0 / math.hypot(dx - xi, dy - eta),
                x0, x1, y0, y1, epsabs=0.0, epsrel=1e-11,
            )  # fmt: skip
            total += val
    return total


def _plane_grid(nx: int, ny: int, h: float, rot: np.ndarray | None = None):
    """Centres and axes of an ``nx x ny`` grid of square cells of side ``h`` (m)."""
    x = (np.arange(nx) - (nx - 1) / 2) * h
    y = (np.arange(ny) - (ny - 1) / 2) * h
    X, Y = np.meshgrid(x, y, indexing="ij")
    n = X.size
    pts = np.column_stack([X.ravel(), Y.ravel(), np.zeros(n)])
    U = np.tile([1.0, 0.0, 0.0], (n, 1))
    V = np.tile([0.0, 1.0, 0.0], (n, 1))
    if rot is not None:
        pts, U, V = pts @ rot.T, U @ rot.T, V @ rot.T
    half = np.full(n, h / 2)
    return pts, U, V, half, half


# ------------------------------------------------------------------ rectangle formula
@pytest.mark.parametrize(
    ("dx", "dy", "a", "b"),
    [
        (0.0, 0.0, 1.0, 1.0),  # self term of a square
        (0.0, 0.0, 0.5, 2.0),  # self term of an oblong cell
        (0.3, -0.7, 0.5, 2.0),  # inside, off centre
        (2.0, 0.0, 1.0, 1.0),  # neighbour on a square grid
        (1.0, 3.0, 1.0, 1.0),  # on the extension of an edge (x - a = 0)
        (-2.0, 4.0, 1.0, 1.5),  # a diagonal neighbour
        (8.0, 5.0, 0.5, 0.8),  # just inside the closed-form zone (r < 12 max(a, b))
    ],
)
def test_rectangle_formula_matches_quadrature_of_point_force(dx, dy, a, b):
    # Oracle: Boussinesq's surface displacement u = P/(pi E* r) (Johnson 1985 §3.2)
    # integrated numerically over the rectangle to 1e-11; Love's closed form has only
    # round-off, so 1e-9 relative leaves margin for the quadrature alone.
    f = rectangle_influence(dx, dy, a, b)
    assert f == pytest.approx(_integral_inv_r(dx, dy, a, b), rel=1e-9)


def test_square_self_term_closed_form():
    # Centre of a square of side 2a: 8 a ln(1 + sqrt 2) (corner integral of 1/r over a
    # square of side a is 2 a asinh(1); Love 1929). Round-off only: 1e-14.
    for a in (1e-4, 1.0, 3.0):
        assert rectangle_influence(0.0, 0.0, a, a) == pytest.approx(
            8 * a * math.log(1 + math.sqrt(2)), rel=1e-14
        )


@pytest.mark.parametrize(("a", "b"), [(1.0, 1.0), (0.5, 1.5), (2.0, 0.3)])
def test_far_field_multipole_matches_quadrature(a, b):
    # Beyond 12 max(a, b) the 4th-order multipole expansion is used; its truncation is
    # of order (max(a, b)/r)^6 ~ 3e-7 at the switch, and below 6e-8 in practice. Against
    # the 1e-11 quadrature of the point-force solution we allow 1e-6 (the brief's bound).
    r = 1.05 * FAR_FIELD * max(a, b)
    for th in (0.0, 0.4, 1.1, 2.5):
        dx, dy = r * math.cos(th), r * math.sin(th)
        assert rectangle_influence(dx, dy, a, b) == pytest.approx(
            _integral_inv_r(dx, dy, a, b), rel=1e-6
        )


def test_multipole_switch_is_continuous_and_tends_to_point_force():
    # Across the switch radius the two forms differ by the truncation error only (< 1e-7
    # relative, see above); far away f -> 4ab/r (the point force 1/(pi E* r) per unit
    # force, Johnson 1985 §3.2) with the quadrupole correction O((a/r)^2) < 1e-5 at
    # r = 1000 a.
    a, b = 0.7, 1.3
    th = np.linspace(0, 2 * np.pi, 73)
    r0 = FAR_FIELD * max(a, b)
    inner = rectangle_influence((r0 - 1e-9) * np.cos(th), (r0 - 1e-9) * np.sin(th), a, b)
    outer = rectangle_influence((r0 + 1e-9) * np.cos(th), (r0 + 1e-9) * np.sin(th), a, b)
    assert np.max(np.abs(outer / inner - 1)) < 1e-7
    r = 1000.0 * max(a, b)
    far = rectangle_influence(r * np.cos(th), r * np.sin(th), a, b)
    assert np.max(np.abs(far * r / (4 * a * b) - 1)) < 1e-5


def test_rectangle_formula_broadcasts_and_is_even():
    # f depends on |dx|, |dy| only (the rectangle is symmetric): exact equality.
    dx = np.linspace(-5, 5, 11)[:, None]
    dy = np.linspace(-3, 3, 7)[None, :]
    f = rectangle_influence(dx, dy, 1.0, 0.5)
    assert f.shape == (11, 7)
    np.testing.assert_array_equal(f, f[::-1, :])
    np.testing.assert_array_equal(f, f[:, ::-1])
    assert np.all(f > 0)


# ------------------------------------------------------------------ influence matrix
E_STAR = 1.1538e11  # steel on steel, E = 210 GPa, nu = 0.3


def test_combined_modulus():
    # Johnson 1985 §4.2: 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2; two equal steels give
    # E/(2 (1 - nu^2)) = 115.38 GPa. Round-off only.
    assert combined_modulus(210e9, 0.3, 210e9, 0.3) == pytest.approx(
        210e9 / (2 * (1 - 0.09)), rel=1e-14
    )
    assert combined_modulus(210e9, 0.3, 70e9, 0.33) == pytest.approx(
        1 / (0.91 / 210e9 + (1 - 0.33**2) / 70e9), rel=1e-14
    )


def test_plane_grid_matrix_is_the_rectangle_formula():
    # On a plane grid of equal cells C_ij = f(x_i - x_j, y_i - y_j)/(pi E* 4ab) exactly
    # (Love 1929 / Johnson 1985 §3.3): each entry per unit force on the cell area; the
    # matrix is then symmetric without the symmetrisation. Round-off: 1e-13.
    h = 2e-4
    pts, U, V, hu, hv = _plane_grid(9, 7, h)
    C = influence_matrix(pts, U, V, hu, hv, E_STAR)
    dx = pts[:, None, 0] - pts[None, :, 0]
    dy = pts[:, None, 1] - pts[None, :, 1]
    ref = rectangle_influence(dx, dy, h / 2, h / 2) / (math.pi * E_STAR * h * h)
    np.testing.assert_allclose(C, ref, rtol=1e-13, atol=0)
    assert np.all(C > 0)
    # the self term is the largest entry of its row (the closest cell)
    assert np.all(np.argmax(C, axis=1) == np.arange(C.shape[0]))


def test_rotated_plane_gives_the_same_matrix():
    # The projection on the cell axes makes the matrix frame-invariant: a rigid rotation
    # of the whole grid changes only round-off (1e-12 relative of the largest entry).
    rng = np.random.default_rng(7)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    h = 1e-4
    C0 = influence_matrix(*_plane_grid(6, 5, h), E_STAR)
    pts, U, V, hu, hv = _plane_grid(6, 5, h, rot=Q)
    C1 = influence_matrix(pts + np.array([0.05, -0.02, 0.1]), U, V, hu, hv, E_STAR)
    np.testing.assert_allclose(C1, C0, rtol=0, atol=1e-12 * C0.max())


def test_curved_strip_matrix_symmetric_positive_and_far_field():
    # 3000 cells of unequal sides on a cylinder of radius 20 mm (a curved flank strip):
    # symmetric by construction (exactly), all entries positive, and far apart each entry
    # is the point-force compliance 1/(pi E* r) (Johnson 1985 §3.2) at the chord r, up to
    # the quadrupole term, at most max(a, b)^2/(3 r^2) < 3e-4 for the pairs below (27
    # cells apart along the straight direction; 90 cells, i.e. 1.1 rad, along the arc).
    nu_, nv_ = 30, 100
    hu0, hv0 = 0.8e-4, 1.2e-4
    u = (np.arange(nu_) - nu_ / 2) * 2 * hu0
    v = (np.arange(nv_) - nv_ / 2) * 2 * hv0
    Uu, Vv = np.meshgrid(u, v, indexing="ij")
    Uu, Vv = Uu.ravel(), Vv.ravel()
    R = 0.02
    pts = np.column_stack([Uu, R * np.sin(Vv / R), R * (1 - np.cos(Vv / R))])
    au = np.tile([1.0, 0.0, 0.0], (Uu.size, 1))
    av = np.column_stack([0 * Uu, np.cos(Vv / R), np.sin(Vv / R)])
    rng = np.random.default_rng(3)
    hu = hu0 * rng.uniform(0.8, 1.0, Uu.size)  # unequal cells: C needs symmetrising
    hv = hv0 * rng.uniform(0.8, 1.0, Uu.size)
    C = influence_matrix(pts, au, av, hu, hv, E_STAR)
    assert C.shape == (3000, 3000)
    np.testing.assert_array_equal(C, C.T)
    assert np.all(C > 0)
    for i, j in ((15, 27 * nv_ + 15), (15 * nv_ + 5, 15 * nv_ + 95)):
        r = np.linalg.norm(pts[i] - pts[j])
        assert C[i, j] * math.pi * E_STAR * r == pytest.approx(1.0, rel=3e-4)


def test_offset_along_the_normal_counts_as_distance():
    # Two parallel cells 1 mm apart along their common normal (a surface folding back):
    # the in-plane projection of their offset is zero, but they are 1 mm apart; the
    # entry is the point-force compliance at that chord, 1/(pi E* r) (Johnson 1985
    # §3.2), up to the quadrupole term (0.05/1)^2/3 < 1e-3 -- not the self term.
    pts = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 1e-3]])
    U = np.tile([1.0, 0.0, 0.0], (2, 1))
    V = np.tile([0.0, 1.0, 0.0], (2, 1))
    half = np.full(2, 5e-5)
    C = influence_matrix(pts, U, V, half, half, E_STAR)
    assert C[0, 1] * math.pi * E_STAR * 1e-3 == pytest.approx(1.0, rel=1e-3)
    assert C[0, 1] < 0.1 * C[0, 0]


def test_cells_on_different_bodies_do_not_interact():
    # Cells on different teeth do not share a half-space: those entries are exactly 0,
    # the rest equal the single-body matrix.
    pts, U, V, hu, hv = _plane_grid(4, 3, 1e-4)
    labels = np.array([0] * 6 + [1] * 6)
    C = influence_matrix(pts, U, V, hu, hv, E_STAR, same_body=labels)
    C_all = influence_matrix(pts, U, V, hu, hv, E_STAR)
    other = labels[:, None] != labels[None, :]
    assert np.all(C[other] == 0)
    np.testing.assert_array_equal(C[~other], C_all[~other])


# ------------------------------------------------------------------ subsurface stress
def _boussinesq_cylindrical(P, r, z, nu):
    """Johnson (1985) §3.2, Eq. 3.3: (sigma_r, sigma_theta, sigma_z, tau_rz) of a normal
    force P (compressive) at the origin, at radius r and depth z."""
    rho = math.hypot(r, z)
    sr = P / (2 * math.pi) * ((1 - 2 * nu) / r**2 * (1 - z / rho) - 3 * z * r**2 / rho**5)
    st = -P / (2 * math.pi) * (1 - 2 * nu) * (1 / r**2 * (1 - z / rho) - z / rho**3)
    sz = -3 * P / (2 * math.pi) * z**3 / rho**5
    trz = -3 * P / (2 * math.pi) * r * z**2 / rho**5
    return sr, st, sz, trz


def test_point_force_stress_is_johnson_eq_3_3_rotated():
    # A one-point rule on a tiny cell is an exact point force P = 4ab p at its centre.
    # Its Cartesian stresses must be Johnson's cylindrical ones rotated by the azimuth
    # (sigma_x = sigma_r cos^2 + sigma_theta sin^2, ...): round-off, 1e-12 relative.
    nu, P = 0.3, 2.0
    pts = np.array([[1.0, 0.0, 0.7], [-0.3, 0.8, 0.2], [0.5, -1.2, 2.0], [-2.0, -0.1, 0.05]])
    S = subsurface_stress([[0.0, 0.0]], [0.5], [0.25], [P / 0.5], pts, nu, quad=1)
    for (x, y, z), s in zip(pts, S, strict=True):
        r = math.hypot(x, y)
        c, sn = x / r, y / r
        sr, st, sz, trz = _boussinesq_cylindrical(P, r, z, nu)
        ref = np.array(
            [
                [sr * c * c + st * sn * sn, (sr - st) * c * sn, trz * c],
                [(sr - st) * c * sn, sr * sn * sn + st * c * c, trz * sn],
                [trz * c, trz * sn, sz],
            ]
        )
        np.testing.assert_allclose(s, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    # directly under the force (r = 0): sigma_x = sigma_y = (1 - 2nu) P/(4 pi z^2), the
    # limit of Eq. 3.3; sigma_z = -3P/(2 pi z^2)
    s = subsurface_stress([[0.0, 0.0]], [0.5], [0.25], [P / 0.5], [[0.0, 0.0, 0.5]], nu, quad=1)
    assert s[0, 0, 0] == pytest.approx((1 - 2 * nu) * P / (4 * math.pi * 0.25), rel=1e-13)
    assert s[0, 2, 2] == pytest.approx(-3 * P / (2 * math.pi * 0.25), rel=1e-13)


def _sigma_z_under_rectangle_centre(a, b, z, p=1.0):
    """Vertical stress under the centre of a uniformly loaded rectangle 2a x 2b: four
    times the corner solution (Love 1929; Holl 1940, reproduced in Poulos & Davis,
    *Elastic Solutions for Soil and Rock Mechanics*, 1974, ch. 3)
    ``sigma_z = -(p/2 pi)[atan(ab/(z R3)) + a b z/R3 (1/R1^2 + 1/R2^2)]`` per corner,
    ``R1 = sqrt(a^2 + z^2)``, ``R2 = sqrt(b^2 + z^2)``, ``R3 = sqrt(a^2 + b^2 + z^2)``."""
    R1, R2, R3 = math.hypot(a, z), math.hypot(b, z), math.sqrt(a * a + b * b + z * z)
    return -(2 * p / math.pi) * (math.atan(a * b / (z * R3)) + a * b * z / R3 * (R1**-2 + R2**-2))


@pytest.mark.parametrize(("depth_in_cells", "tol"), [(1.0, 2e-3), (2.0, 1e-5)])
def test_gauss_rule_accuracy_against_uniform_rectangle(depth_in_cells, tol):
    # A 21 x 21 grid of uniformly loaded square cells is one uniformly loaded square: the
    # closed form of Holl (1940) is the oracle. The 3x3 Gauss rule's error measured here
    # is the one stated in the docstring of subsurface_stress: 1.3e-3 at one cell size
    # deep, 4e-6 at two (tolerances 2e-3 and 1e-5).
    h, n = 1e-4, 21
    pts, *_ = _plane_grid(n, n, h)
    half = np.full(n * n, h / 2)
    z = depth_in_cells * h
    s = subsurface_stress(pts[:, :2], half, half, np.full(n * n, 1e9), [[0, 0, z]], 0.3)
    ref = _sigma_z_under_rectangle_centre(n * h / 2, n * h / 2, z, 1e9)
    assert s[0, 2, 2] == pytest.approx(ref, rel=tol)
    # symmetry of the square load: no shear on its axis, sigma_x = sigma_y (round-off)
    assert abs(s[0, 0, 1]) + abs(s[0, 0, 2]) + abs(s[0, 1, 2]) < 1e-9 * abs(ref)
    assert s[0, 0, 0] == pytest.approx(s[0, 1, 1], rel=1e-10)


def test_vertical_equilibrium_of_a_deep_plane():
    # The vertical stresses on any plane z = const carry the applied force (equilibrium
    # of the slab above it): int int sigma_z dx dy = -F. Midpoint rule on a +-40 z
    # square with spacing z/8; the field decays like rho^-5, the truncated tail is
    # < 1e-3 of F and the rule's error of the smooth field ~1e-4: tolerance 2e-3.
    rng = np.random.default_rng(5)
    xy = rng.uniform(-1e-4, 1e-4, (5, 2))
    half = np.full(5, 2e-5)
    p = rng.uniform(1e8, 2e8, 5)
    F = float(np.sum(p * 4 * half * half))
    z = 5e-4
    g = (np.arange(-320, 321)) * z / 8
    X, Y = np.meshgrid(g, g, indexing="ij")
    pts = np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, z)])
    s = subsurface_stress(xy, half, half, p, pts, 0.3, quad=2)
    total = s[:, 2, 2].sum() * (z / 8) ** 2
    assert total == pytest.approx(-F, rel=2e-3)


def test_von_mises_basic_states():
    # Definitions: uniaxial stress s -> |s|; pure shear t -> sqrt(3) t; hydrostatic -> 0.
    S = np.zeros((3, 3, 3))
    S[0, 0, 0] = -5.0
    S[1, 0, 1] = S[1, 1, 0] = 2.0
    S[2] = -7.0 * np.eye(3)
    np.testing.assert_allclose(von_mises(S), [5.0, 2.0 * math.sqrt(3), 0.0], atol=1e-14)


def test_max_subsurface_search_is_consistent():
    # Sanity of the search on a load whose maximum is known only numerically: the
    # returned value equals a direct evaluation at the returned point (the refinement
    # does not lose it) and no grid point exceeds it.
    pts, *_ = _plane_grid(11, 11, 1e-4)
    half = np.full(121, 5e-5)
    p = 1e9 * (1.0 - (pts[:, 0] ** 2 + pts[:, 1] ** 2) / (6e-4) ** 2)
    val, depth, (x0, y0) = max_subsurface_von_mises(pts[:, :2], half, half, p, 0.3)
    direct = von_mises(subsurface_stress(pts[:, :2], half, half, p, [[x0, y0, depth]], 0.3))
    assert val == pytest.approx(float(direct[0]), rel=1e-12)
    z = np.linspace(1e-4, 8e-4, 15)
    grid = von_mises(
        subsurface_stress(pts[:, :2], half, half, p, np.column_stack([0 * z, 0 * z, z]), 0.3)
    )
    assert val >= grid.max() * (1 - 1e-12)


# ------------------------------------------------------------------ errors
def _good():
    pts, U, V, hu, hv = _plane_grid(2, 2, 1e-4)
    return dict(points=pts, axes_u=U, axes_v=V, half_u=hu, half_v=hv, E_star=E_STAR)


@pytest.mark.parametrize(
    ("change", "name"),
    [
        ({"points": np.zeros((4, 2))}, "points"),
        ({"axes_u": np.zeros((3, 3))}, "axes_u"),
        ({"axes_v": np.tile([0.0, 2.0, 0.0], (4, 1))}, "axes_v"),
        ({"axes_v": np.tile([1.0, 0.0, 0.0], (4, 1))}, "orthogonal"),
        ({"half_u": np.array([1e-4, 0.0, 1e-4, 1e-4])}, "half_u"),
        ({"half_v": np.array([1e-4, -1e-4, 1e-4, 1e-4])}, "half_v"),
        ({"half_v": np.full(3, 1e-4)}, "half_v"),
        ({"points": np.full((4, 3), np.nan)}, "points"),
        ({"half_u": np.array([1e-4, np.nan, 1e-4, 1e-4])}, "half_u"),
        ({"E_star": 0.0}, "E_star"),
        ({"E_star": float("nan")}, "E_star"),
        ({"same_body": np.zeros(3, dtype=int)}, "same_body"),
        ({"same_body": np.zeros(4)}, "same_body"),
        ({"points": "abc"}, "points"),
    ],
)
def test_influence_matrix_errors_name_the_argument(change, name):
    kwargs = _good() | change
    with pytest.raises(ReducerlabError, match=name):
        influence_matrix(**kwargs)


def test_other_errors_name_the_argument():
    ok = dict(points_xy=[[0.0, 0.0]], half_u=[1e-4], half_v=[1e-4], pressure=[1e9])
    with pytest.raises(ReducerlabError, match="a must be > 0"):
        rectangle_influence(0.0, 0.0, 0.0, 1.0)
    with pytest.raises(ReducerlabError, match="dx"):
        rectangle_influence(np.nan, 0.0, 1.0, 1.0)
    with pytest.raises(ReducerlabError, match="broadcastable"):
        rectangle_influence(np.zeros(3), np.zeros(4), 1.0, 1.0)
    with pytest.raises(ReducerlabError, match="eval_xyz"):
        subsurface_stress(**ok, eval_xyz=[[0.0, 0.0, 0.0]], nu=0.3)
    with pytest.raises(ReducerlabError, match="eval_xyz"):
        subsurface_stress(**ok, eval_xyz=[[0.0, 0.0]], nu=0.3)
    with pytest.raises(ReducerlabError, match="nu"):
        subsurface_stress(**ok, eval_xyz=[[0.0, 0.0, 1e-4]], nu=0.7)
    with pytest.raises(ReducerlabError, match="quad"):
        subsurface_stress(**ok, eval_xyz=[[0.0, 0.0, 1e-4]], nu=0.3, quad=0)
    with pytest.raises(ReducerlabError, match="pressure"):
        subsurface_stress(**(ok | {"pressure": [1.0, 2.0]}), eval_xyz=[[0, 0, 1e-4]], nu=0.3)
    with pytest.raises(ReducerlabError, match="points_xy"):
        subsurface_stress(**(ok | {"points_xy": [0.0, 0.0]}), eval_xyz=[[0, 0, 1e-4]], nu=0.3)
    with pytest.raises(ReducerlabError, match="pressure"):
        max_subsurface_von_mises(**(ok | {"pressure": [0.0]}), nu=0.3)
    with pytest.raises(ReducerlabError, match="depths"):
        max_subsurface_von_mises(**ok, nu=0.3, depths=[2e-4, 1e-4])
    with pytest.raises(ReducerlabError, match="stress"):
        von_mises(np.zeros((4, 3)))
    with pytest.raises(ReducerlabError, match="E2"):
        combined_modulus(210e9, 0.3, -1.0, 0.3)
    with pytest.raises(ReducerlabError, match="nu1"):
        combined_modulus(210e9, 0.6, 210e9, 0.3)
