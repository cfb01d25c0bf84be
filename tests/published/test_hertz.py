"""Hertz contact (reducerlab.contact.hertz) against its published closed forms, and the
discretised half-space contact (reducerlab.contact.halfspace) against Hertz.

(a) Closed forms: Johnson, *Contact Mechanics* (1985), ch. 3-4 (sphere on plane, line
contact, stresses on the axis); the table of Hertz coefficients in Timoshenko & Goodier;
the Hamrock & Brewe (1983) curve fits; and two independent proofs of the exact elliptic
solution (the load integral and the displacement of its pressure computed from
Boussinesq's point-force solution). (b) A small frictionless contact solver on a plane
grid of square cells (in this file only) reproduces the Hertz semi-axes, peak pressure,
approach and the maximum subsurface von Mises stress within 2 %. Tolerances are
justified inline.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import dblquad, quad
from scipy.linalg import cho_factor, cho_solve

from reducerlab.contact.halfspace import (
    combined_modulus,
    influence_matrix,
    max_subsurface_von_mises,
    subsurface_stress,
)
from reducerlab.contact.hertz import (
    HertzContact,
    axis_stresses,
    hertz_crossed_cylinders,
    hertz_elliptic,
    hertz_line,
    hertz_sphere_plane,
    max_axis_von_mises,
)
from reducerlab.errors import ReducerlabError

E_STAR = combined_modulus(210e9, 0.3, 210e9, 0.3)  # steel on steel, 115.38 GPa
NU = 0.3


# ------------------------------------------------------------------ (a) closed forms
def test_sphere_on_plane_textbook_formulas():
    # Johnson (1985) §4.2: a = (3FR/4E*)^(1/3), p0 = 3F/(2 pi a^2), delta = a^2/R. Our
    # solution goes through the general elliptic equations with A = B = 1/(2R) (Carlson
    # integrals at k = 1): round-off only, 1e-13.
    F, R = 100.0, 0.01
    c = hertz_sphere_plane(F, R, E_STAR)
    a = (3 * F * R / (4 * E_STAR)) ** (1 / 3)
    assert c.a == pytest.approx(a, rel=1e-13)
    assert c.b == c.a
    assert c.p0 == pytest.approx(3 * F / (2 * math.pi * a * a), rel=1e-13)
    assert c.delta == pytest.approx(a * a / R, rel=1e-13)
    assert c.mean_pressure == pytest.approx(2 * c.p0 / 3, rel=1e-13)
    # the numbers of this steel example: a = 0.1866 mm, p0 = 1.371 GPa, delta = 3.483 um
    assert (round(c.a * 1e3, 4), round(c.p0 / 1e9, 3), round(c.delta * 1e6, 3)) == (
        0.1866,
        1.371,
        3.483,
    )


def test_circle_axis_stresses_johnson():
    # Johnson (1985) §3.4 (Eq. 3.45 and the discussion of Fig. 3.9), nu = 0.3: at the
    # surface centre sigma_r = -(1 + 2nu)/2 p0, sigma_z = -p0; the largest shear on the
    # axis tau1 = 0.31 p0 at z = 0.48 a, hence von Mises 2 tau1 = 0.62 p0 (sigma_r =
    # sigma_theta). Checked to the printed digits.
    c = hertz_sphere_plane(100.0, 0.01, E_STAR)
    sx, sy, sz = axis_stresses(c, np.array([0.0]), NU)
    assert sx[0] == pytest.approx(-(1 + 2 * NU) / 2 * c.p0, rel=1e-14)
    assert sy[0] == sx[0]
    assert sz[0] == pytest.approx(-c.p0, rel=1e-14)
    vm, z = max_axis_von_mises(c, NU)
    assert (round(vm / c.p0, 2), round(z / c.a, 2)) == (0.62, 0.48)
    zz = np.linspace(0, 2 * c.a, 20001)
    sx, _, sz = axis_stresses(c, zz, NU)
    tau = (sx - sz) / 2
    k = int(np.argmax(tau))
    assert (round(tau[k] / c.p0, 2), round(zz[k] / c.a, 2)) == (0.31, 0.48)


def test_line_contact_johnson():
    # Johnson (1985) §4.3: b = sqrt(4 w R/(pi E*)), p0 = 2w/(pi b) (so int p = w); on the
    # axis (McEwen 1949) tau1 = 0.30 p0 at z = 0.78 b; von Mises 0.56 p0 at 0.70 b
    # (nu = 0.3). Formulas to round-off; maxima to the printed digits (Johnson's 0.78 b
    # is the exact 0.786 b cut to two digits, so that depth gets +-0.01).
    w, R = 2.0e5, 0.015
    c = hertz_line(w, R, E_STAR)
    assert c.b == pytest.approx(math.sqrt(4 * w * R / (math.pi * E_STAR)), rel=1e-14)
    assert c.p0 == pytest.approx(2 * w / (math.pi * c.b), rel=1e-14)
    load, _ = quad(c.pressure, -c.b, c.b, epsabs=0, epsrel=1e-12)
    assert load == pytest.approx(w, rel=1e-10)  # quad of a sqrt endpoint: 1e-10
    vm, z = max_axis_von_mises(c, NU)
    assert (round(vm / c.p0, 2), round(z / c.b, 2)) == (0.56, 0.70)
    zz = np.linspace(0, 2 * c.b, 20001)
    sx, sy, sz = axis_stresses(c, zz, NU)
    tau = (np.max([sx, sy, sz], axis=0) - np.min([sx, sy, sz], axis=0)) / 2
    k = int(np.argmax(tau))
    assert round(tau[k] / c.p0, 2) == 0.30
    assert zz[k] / c.b == pytest.approx(0.78, abs=0.01)


def test_elliptic_reduces_to_the_circle_continuously():
    # A = B is the circle exactly; a relative difference of 1e-9 between A and B moves
    # a, b, p0, delta by O(1e-9) (the Carlson form of the eccentricity equation has no
    # cancellation as e -> 0): tolerance 1e-8. The axis stresses of the general
    # (elliptic) formula then agree with Johnson's circle formula (Eq. 3.45) to 1e-8 p0.
    F, R = 10.0, 0.004
    circle = hertz_sphere_plane(F, R, E_STAR)
    same = hertz_elliptic(F, 0.5 / R, 0.5 / R, E_STAR)
    assert same == circle
    near = hertz_elliptic(F, 0.5 / R, 0.5 / R * (1 + 1e-9), E_STAR)
    for name in ("a", "b", "p0", "delta"):
        assert getattr(near, name) == pytest.approx(getattr(circle, name), rel=1e-8)
    z = np.linspace(0, 3, 13) * circle.a
    for s_near, s_circle in zip(
        axis_stresses(near, z, NU), axis_stresses(circle, z, NU), strict=True
    ):
        np.testing.assert_allclose(s_near, s_circle, rtol=0, atol=1e-8 * circle.p0)


# Timoshenko & Goodier, Theory of Elasticity (3rd ed. 1970), §140, table of the Hertz
# coefficients: a = m (3 F/(4 E* (A + B)))^(1/3), b = n (...)^(1/3), cos(theta) =
# (B - A)/(A + B). The table was computed by hand (Hertz's own tables carry errors in the
# third decimal, Cooper 1968); we allow 2.5e-3 absolute.
TG_TABLE = [
    (30, 2.731, 0.493),
    (35, 2.397, 0.530),
    (40, 2.136, 0.567),
    (45, 1.926, 0.604),
    (50, 1.754, 0.641),
    (55, 1.611, 0.678),
    (60, 1.486, 0.717),
    (65, 1.378, 0.759),
    (70, 1.284, 0.802),
    (75, 1.202, 0.846),
    (80, 1.128, 0.893),
    (85, 1.061, 0.944),
    (90, 1.000, 1.000),
]


@pytest.mark.parametrize(("theta", "m", "n"), TG_TABLE)
def test_timoshenko_goodier_hertz_coefficients(theta, m, n):
    A = 1.0
    ct = math.cos(math.radians(theta))
    B = A * (1 + ct) / (1 - ct)
    c = hertz_elliptic(1.0, A, B, 1.0)
    scale = (3.0 / (4.0 * (A + B))) ** (1 / 3)
    assert c.a / scale == pytest.approx(m, abs=2.5e-3)
    assert c.b / scale == pytest.approx(n, abs=2.5e-3)


# crossed cylinders, R2/R1 = 4: A = 1/(2 R1) = 4 B
F_X, R1, R2 = 50.0, 0.005, 0.02


@pytest.fixture(scope="module")
def crossed() -> HertzContact:
    return hertz_crossed_cylinders(F_X, R1, R2, E_STAR)


def test_crossed_cylinders_hamrock_brewe(crossed):
    # Hamrock & Brewe (1983), J. Lubr. Technol. 105, 171-177: curve fits for Ry/Rx in
    # [1, 100], k = 1.0339 (Ry/Rx)^0.6360, E_ = 1.0003 + 0.5968 Rx/Ry, F_ = 1.5277 +
    # 0.6023 ln(Ry/Rx); Dy = 2 (6 k^2 E_ w R/(pi E'))^(1/3), Dx = 2 (6 E_ w R/(pi k E'))^(1/3),
    # delta = F_ [9/(2 E_ R) (w/(pi k E'))^2]^(1/3), 1/R = 1/Rx + 1/Ry, E' = 2 E*. The fits
    # are good to a few per cent (3.4 % in k at Ry/Rx = 1): we allow 3 %.
    c = crossed
    Rx, Ry = R1, R2  # the larger curvature is along x: the ellipse is long in y
    al = Ry / Rx
    k = 1.0339 * al**0.6360
    Eb = 1.0003 + 0.5968 / al
    Fb = 1.5277 + 0.6023 * math.log(al)
    R = 1 / (1 / Rx + 1 / Ry)
    Ep = 2 * E_STAR
    Dy = 2 * (6 * k * k * Eb * F_X * R / (math.pi * Ep)) ** (1 / 3)
    Dx = 2 * (6 * Eb * F_X * R / (math.pi * k * Ep)) ** (1 / 3)
    delta = Fb * (9 / (2 * Eb * R) * (F_X / (math.pi * k * Ep)) ** 2) ** (1 / 3)
    assert c.b > c.a
    assert c.a == pytest.approx(Dx / 2, rel=0.03)
    assert c.b == pytest.approx(Dy / 2, rel=0.03)
    assert c.delta == pytest.approx(delta, rel=0.03)
    assert c.p0 == pytest.approx(6 * F_X / (math.pi * Dx * Dy), rel=0.03)


def test_crossed_cylinders_load_integral(crossed):
    # The pressure integrates to the force: a numerical double integral (QUADPACK to
    # 1e-12) of p0 sqrt(1 - x^2/a^2 - y^2/b^2) over the ellipse equals F to 1e-9.
    c = crossed

    def half_chord(x):
        return c.b * math.sqrt(max(0.0, 1 - (x / c.a) ** 2))

    load, _ = dblquad(
        lambda y, x: float(c.pressure(x, y)), -c.a, c.a,
        lambda x: -half_chord(x), half_chord, epsabs=0, epsrel=1e-12,
    )  # fmt: skip
    assert load == pytest.approx(F_X, rel=1e-9)


def _displacement(c: HertzContact, x: float, y: float, tol: float = 1e-12) -> float:
    """Normal approach at surface point (x, y) caused by the Hertz pressure of ``c``:
    ``u = 1/(pi E*) int int p / r`` (Boussinesq, Johnson 1985 §3.2), in polar coordinates
    about (x, y) so that the Jacobian cancels 1/r: ``u = 1/(pi E*) int_0^2pi int p dr dth``.
    Along a ray, ``1 - x^2/a^2 - y^2/b^2 = alpha (r1 - r)(r - r0)`` with ``r0 < r1`` the
    crossings of the ellipse, and the inner integral of the square root over the part of
    ``[r0, r1]`` with r >= 0 is elementary (circular-segment area); the outer one is done
    by adaptive quadrature to ``tol`` (smooth and periodic for a point inside the
    ellipse; outside, the rays tangent to the ellipse make square-root kinks)."""
    a, b, p0 = c.a, c.b, c.p0

    def seg(t, R):  # primitive of sqrt(R^2 - t^2)
        t = min(max(t, -R), R)
        return 0.5 * (t * math.sqrt(max(R * R - t * t, 0.0)) + R * R * math.asin(t / R))

    def inner(th):
        ct, st = math.cos(th), math.sin(th)
        al = ct * ct / a**2 + st * st / b**2
        be = x * ct / a**2 + y * st / b**2
        ga = x * x / a**2 + y * y / b**2 - 1
        disc = be * be - al * ga
        if disc <= 0:
            return 0.0
        r0, r1 = (-be - math.sqrt(disc)) / al, (-be + math.sqrt(disc)) / al
        if r1 <= 0:
            return 0.0
        mid, R = 0.5 * (r0 + r1), 0.5 * (r1 - r0)
        return p0 * math.sqrt(al) * (seg(R, R) - seg(max(r0, 0.0) - mid, R))

    val, _ = quad(inner, 0, 2 * math.pi, epsabs=0, epsrel=tol, limit=400)
    return val / (math.pi * c.E_star)


def test_crossed_cylinders_displacement_proves_the_solution(crossed):
    # Independent proof of the exact solution: the displacement of its pressure (point
    # force integrated numerically, see _displacement) equals delta - A x^2 - B y^2 inside
    # the ellipse (the bodies conform there) and exceeds it outside (the gap stays open).
    # The quadrature is good to ~1e-12 inside (smooth integrand): tolerance 1e-9 (found
    # 2e-15). Outside, 1e-8 quadrature suffices for the inequality (the displacement
    # exceeds delta - h by 40 to 130 % at these points).
    c = crossed
    for fx, fy in ((0.0, 0.0), (0.3, 0.2), (-0.6, 0.5), (0.1, -0.9), (-0.7, -0.7)):
        x, y = fx * c.a, fy * c.b
        rigid = c.delta - c.A * x * x - c.B * y * y
        assert _displacement(c, x, y) == pytest.approx(rigid, rel=1e-9)
    for fx, fy in ((1.3, 0.0), (0.0, 1.2), (0.9, 0.9)):
        x, y = fx * c.a, fy * c.b
        assert _displacement(c, x, y, tol=1e-8) > c.delta - c.A * x * x - c.B * y * y


def _axis_stress_by_quadrature(c: HertzContact, z: float, nu: float) -> list[float]:
    """(sigma_x, sigma_y, sigma_z) at (0, 0, z) by integrating Johnson's (1985, §3.2,
    Eq. 3.3) point-force stresses over the Hertz pressure in polar coordinates (nested
    adaptive quadrature, 1e-11)."""

    def kernel(r, th, comp):
        rho = math.hypot(r, z)
        sr = ((1 - 2 * nu) / r**2 * (1 - z / rho) - 3 * z * r * r / rho**5) / (2 * math.pi)
        st = -(1 - 2 * nu) * (1 / r**2 * (1 - z / rho) - z / rho**3) / (2 * math.pi)
        c2, s2 = math.cos(th) ** 2, math.sin(th) ** 2
        if comp == 0:
            return sr * c2 + st * s2
        if comp == 1:
            return sr * s2 + st * c2
        return -3 * z**3 / (2 * math.pi * rho**5)

    out = []
    for comp in range(3):

        def inner(th, comp=comp):
            rm = 1 / math.sqrt(math.cos(th) ** 2 / c.a**2 + math.sin(th) ** 2 / c.b**2)
            f = lambda r: c.p0 * math.sqrt(max(0.0, 1 - (r / rm) ** 2)) * kernel(r, th, comp) * r  # noqa: E731
            return quad(f, 0, rm, epsabs=0, epsrel=1e-11, limit=200)[0]

        out.append(4 * quad(inner, 0, math.pi / 2, epsabs=0, epsrel=1e-11, limit=200)[0])
    return out


def test_elliptic_axis_stresses_match_boussinesq_integration(crossed):
    # Oracle: the Boussinesq point-force stresses (Johnson 1985 Eq. 3.3) integrated over
    # the Hertz pressure by nested quadrature to 1e-11; our closed form (Love's
    # potentials in Carlson integrals) agrees to round-off, we allow 1e-8 p0.
    c = crossed
    for fz in (0.1, 0.5, 1.0, 3.0):
        z = fz * c.a
        ref = _axis_stress_by_quadrature(c, z, NU)
        got = [float(s) for s in axis_stresses(c, z, NU)]
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-8 * c.p0)
    # surface centre (Johnson 1985 §3.7): sigma_x = -p0 [2nu + (1 - 2nu) b/(a + b)],
    # and continuity of the z > 0 branch into it (1e-6 p0 at z = 1e-9 a)
    sx0, sy0, sz0 = (float(s) for s in axis_stresses(c, 0.0, NU))
    assert sx0 == pytest.approx(-c.p0 * (2 * NU + (1 - 2 * NU) * c.b / (c.a + c.b)), rel=1e-14)
    assert sy0 == pytest.approx(-c.p0 * (2 * NU + (1 - 2 * NU) * c.a / (c.a + c.b)), rel=1e-14)
    assert sz0 == pytest.approx(-c.p0, rel=1e-15)
    eps = [float(s) for s in axis_stresses(c, 1e-9 * c.a, NU)]
    np.testing.assert_allclose(eps, [sx0, sy0, sz0], rtol=0, atol=1e-6 * c.p0)


def test_long_ellipse_tends_to_the_line_contact():
    # B/A = 1e8 gives b/a ~ 3e-5: the axis stresses per p0 at depths in units of b
    # approach McEwen's line contact (Johnson 1985 §4.3) with an error O(b/a): 1e-4.
    e = hertz_elliptic(1.0, 1e-8, 1.0, 1.0)
    line = hertz_line(1.0, 1.0, 1.0)
    s = np.linspace(0, 3, 13)
    got = np.array(axis_stresses(e, s * e.b, NU)) / e.p0
    ref = np.array(axis_stresses(line, s * line.b, NU)) / line.p0
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-4)


def test_hertz_errors_name_the_argument(crossed):
    with pytest.raises(ReducerlabError, match="force"):
        hertz_elliptic(-1.0, 1.0, 1.0, 1.0)
    with pytest.raises(ReducerlabError, match="B"):
        hertz_elliptic(1.0, 1.0, float("nan"), 1.0)
    with pytest.raises(ReducerlabError, match="radius"):
        hertz_sphere_plane(1.0, 0.0, 1.0)
    with pytest.raises(ReducerlabError, match="R2"):
        hertz_crossed_cylinders(1.0, 1.0, -2.0, 1.0)
    with pytest.raises(ReducerlabError, match="E_star"):
        hertz_line(1.0, 1.0, 0.0)
    with pytest.raises(ReducerlabError, match="z"):
        axis_stresses(crossed, [-1e-3], NU)
    with pytest.raises(ReducerlabError, match="nu"):
        max_axis_von_mises(crossed, 0.6)
    with pytest.raises(ReducerlabError, match="contact"):
        axis_stresses("circle", [0.1], NU)  # type: ignore[arg-type]


# ------------------------------------------------------------------ (b) discretised
def _solve_contact(C: np.ndarray, gap: np.ndarray, force: float) -> tuple[np.ndarray, float]:
    """Frictionless normal contact of two half-spaces on a cell grid (test-only solver).

    Unknowns: cell forces P >= 0 (N) and the rigid approach delta (m). Complementarity:
    on the contact set S, C P = delta - gap and P >= 0; outside, P = 0 and the loaded gap
    C P - delta + gap >= 0; sum P = force. Active-set iteration (Kalker, *Three-
    Dimensional Elastic Bodies in Rolling Contact*, 1990, ch. 2): solve the equality
    problem on S (Cholesky of C_SS, delta from the load), drop cells with P < 0, else
    add the penetrating cells, until neither happens.
    """
    S = gap <= np.quantile(gap, 0.1)
    for _ in range(100):
        idx = np.flatnonzero(S)
        fac = cho_factor(C[np.ix_(idx, idx)])
        u = cho_solve(fac, np.column_stack([gap[idx], np.ones(idx.size)]))
        delta = (force + u[:, 0].sum()) / u[:, 1].sum()
        P = np.zeros(gap.size)
        P[idx] = delta * u[:, 1] - u[:, 0]
        if (P[idx] < 0).any():
            S[idx[P[idx] < 0]] = False
            continue
        pen = ~S & (C @ P + gap - delta < 0)
        if not pen.any():
            return P, delta
        S |= pen
    raise AssertionError("the active-set iteration did not converge")


def _discretised(c: HertzContact, cells_per_minor: int, *, stress: bool = True) -> dict:
    """Solve the Hertz problem of ``c`` on a plane grid of square cells (side h = minor
    semi-axis / cells_per_minor, an odd number of cells so that one sits on the axis,
    covering 1.25 times each semi-axis) and measure the Hertz quantities."""
    h = min(c.a, c.b) / cells_per_minor
    nx = 2 * math.ceil(1.25 * c.a / h) + 1
    ny = 2 * math.ceil(1.25 * c.b / h) + 1
    x = (np.arange(nx) - (nx - 1) / 2) * h
    y = (np.arange(ny) - (ny - 1) / 2) * h
    X, Y = (g.ravel() for g in np.meshgrid(x, y, indexing="ij"))
    n = X.size
    half = np.full(n, h / 2)
    pts = np.column_stack([X, Y, np.zeros(n)])
    C = influence_matrix(
        pts, np.tile([1.0, 0, 0], (n, 1)), np.tile([0, 1.0, 0], (n, 1)), half, half, c.E_star
    )
    P, delta = _solve_contact(C, c.A * X**2 + c.B * Y**2, c.force)
    p = P / (h * h)
    on = p > 0
    # semi-axes and peak from a least-squares fit of the Hertz form
    # p^2 = p0^2 (1 - x^2/a^2 - y^2/b^2) to the loaded cells
    M = np.column_stack([np.ones(on.sum()), -(X[on] ** 2), -(Y[on] ** 2)])
    k0, kx, ky = np.linalg.lstsq(M, p[on] ** 2, rcond=None)[0]
    out = dict(
        a=math.sqrt(k0 / kx), b=math.sqrt(k0 / ky), p0=float(p.max()), delta=delta,
        load=float(P.sum()), cells=n,
    )  # fmt: skip
    if stress:
        out["vm"], out["depth"], out["at"] = max_subsurface_von_mises(pts[:, :2], half, half, p, NU)
        z = np.array([0.25, 0.5, 1.0]) * min(c.a, c.b)
        s = subsurface_stress(pts[:, :2], half, half, p, np.column_stack([0 * z, 0 * z, z]), NU)
        out["axis"] = (s[:, 0, 0], s[:, 1, 1], s[:, 2, 2], z)
    return out


@pytest.fixture(scope="module")
def sphere_solution():
    c = hertz_sphere_plane(100.0, 0.01, E_STAR)
    return c, _discretised(c, 8)


@pytest.fixture(scope="module")
def crossed_solution(crossed):
    return crossed, _discretised(crossed, 6)


@pytest.mark.parametrize("case", ["sphere_solution", "crossed_solution"])
def test_discretised_contact_matches_hertz(case, request):
    # Piecewise-uniform pressure on square cells (8 per radius for the sphere, 6 per
    # minor semi-axis for the crossed cylinders R2/R1 = 4), Love's influence matrix,
    # frictionless complementarity: the Hertz semi-axes (fitted), peak pressure (the
    # central cell's mean), approach, and the largest subsurface von Mises stress and its
    # depth agree with the closed forms within 2 % (the brief's bound; found: < 0.6 %).
    c, d = request.getfixturevalue(case)
    assert d["load"] == pytest.approx(c.force, rel=1e-12)  # the load constraint holds
    assert d["a"] == pytest.approx(c.a, rel=0.02)
    assert d["b"] == pytest.approx(c.b, rel=0.02)
    assert d["p0"] == pytest.approx(c.p0, rel=0.02)
    assert d["delta"] == pytest.approx(c.delta, rel=0.02)
    vm, depth = max_axis_von_mises(c, NU)
    assert d["vm"] == pytest.approx(vm, rel=0.02)
    assert d["depth"] == pytest.approx(depth, rel=0.02)
    assert d["at"] == (0.0, 0.0)  # on the axis, under the central cell
    # the three principal stresses on the axis, from 0.25 to 1 minor semi-axis deep
    # (the shallowest is 1.5 to 2 cells deep, where the Gauss rule is good to 1e-3):
    # within 2 % of the largest (|sigma_z|, i.e. ~p0 to 0.5 p0 there)
    sx, sy, sz, z = d["axis"]
    for got, ref in zip((sx, sy, sz), axis_stresses(c, z, NU), strict=True):
        np.testing.assert_allclose(got, ref, rtol=0, atol=0.02 * np.abs(sz).max())


def test_discretised_error_falls_under_grid_refinement():
    # Sphere on plane on three grids (4, 6 and 10 cells per contact radius): the error of
    # the peak pressure against Hertz (Johnson 1985 §4.2) falls monotonically, about as
    # h^2 (found 0.60 %, 0.18 %, 0.064 %; h^2 alone would divide it by 6.25 from 4 to 10
    # cells, we require more than 4). (The fitted semi-axis and the approach are already
    # within 0.3 % and 0.07 % on these grids and wander in sign at that level.)
    c = hertz_sphere_plane(100.0, 0.01, E_STAR)
    e_p0 = [abs(_discretised(c, k, stress=False)["p0"] / c.p0 - 1) for k in (4, 6, 10)]
    assert e_p0[0] > e_p0[1] > e_p0[2]
    assert e_p0[0] > 4 * e_p0[2]
    assert e_p0[2] < 1e-3
