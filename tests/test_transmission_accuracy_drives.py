"""Transmission accuracy of the cycloid-ball drive and the gear drives' assembly errors
(issue 31): the first-order laws against exact rigid computations (the tangency of the
perturbed trochoid grooves, the common tangent of displaced base circles) solved by
Newton's method to round-off."""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.analysis.transmission_accuracy import ARCSEC, transmission_accuracy
from reducerlab.drives import load_design
from reducerlab.errors import DesignError, ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.kinematics.accuracy_assembly import backlash_change
from reducerlab.kinematics.accuracy_cycloid import ball_lead, output_error

CYCLOID = example_dir() / "cycloid_ball.toml"
KHV = example_dir() / "khv.toml"
GEAR = example_dir() / "gear_pair.toml"
UM = 1e-6


def _rot(a, v):
    c, s = math.cos(a), math.sin(a)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


class Trochoids:
    """The exact grooves (ball-centre paths) of a cycloid ball track, built from the
    motion alone: in the frame of the eccentric (line of centres ``+y``, the planetary
    disc's centre at ``e y``) a ball runs on the circle of radius ``R_b = Z e / (2 K)``
    about ``M = (e/2) y``, ``B(psi) = M + R_b (sin psi, -cos psi)``, while the frame
    turns by ``phi = -Z psi / z_p``; the centre disc turns in that frame by
    ``-(z_p / z_c) phi`` and the planetary disc (held) by ``-phi``. Undoing each disc's
    turn gives its groove: ``C_2(u) = R(-Z u / z_c) B(u)`` about ``O``,
    ``C_3(v) = R(-Z v / z_p) (B(v) - e y)`` about the planetary disc's centre. Nothing
    of ``kinematics.accuracy_cycloid`` is used."""

    def __init__(self, zc, e, k):
        self.zc, self.zp, self.z, self.e = zc, zc + 2, zc + 1, e
        self.rb = self.z * e / (2 * k)
        self.k = k

    def ball(self, psi):
        return np.array([self.rb * math.sin(psi), self.e / 2 - self.rb * math.cos(psi)])

    def dball(self, psi):
        return self.rb * np.array([math.cos(psi), math.sin(psi)])

    def c2(self, u):
        return _rot(-self.z * u / self.zc, self.ball(u))

    def c3(self, v):
        return _rot(-self.z * v / self.zp, self.ball(v) - np.array([0.0, self.e]))

    def t2(self, u):
        w = -self.z / self.zc
        p = self.c2(u)
        return _rot(w * u, self.dball(u)) + w * np.array([-p[1], p[0]])

    def t3(self, v):
        w = -self.z / self.zp
        p = self.c3(v)
        return _rot(w * v, self.dball(v)) + w * np.array([-p[1], p[0]])

    def normal(self, psi):
        d = math.sqrt(1 + self.k**2 - 2 * self.k * math.cos(psi))
        return np.array([math.sin(psi) / d, (self.k - math.cos(psi)) / d])

    def closure(self, phi, i, c2, c3, turning="centre"):
        """Exact rotation (rad) of the centre disc (or, ``turning="planetary"``, of the
        planetary disc about its centre) that keeps ball ``i`` in both grooves at input
        angle ``phi``: the grooves stay tangent there. ``c2`` is the centre disc's
        groove offset in its own frame, ``c3`` the planetary disc's groove (and centre)
        offset in the housing. Unknowns: the curve parameters at the touching point and
        the rotation; Newton with a central-difference Jacobian, to round-off."""
        # the input turned by phi; the discs' rotation relative to the eccentric's frame
        # is that of centre output at the input angle s (the centre disc held: the
        # frame turns by phi while the discs turn against each other as by s)
        s_rel = phi if turning == "centre" else self.zc * phi / self.zp
        psi = 2 * math.pi * i / self.z - self.zp * s_rel / self.z
        th2 = phi - self.zp * s_rel / self.zc
        th3 = phi - s_rel
        ball = _rot(phi, self.ball(psi))
        centre = _rot(phi, np.array([0.0, self.e]))

        def pick(curve, n, rot, shift):
            ms = range(n)
            m = min(ms, key=lambda m: np.linalg.norm(rot(curve(psi + 2 * math.pi * m)) + shift
                                                     - ball))  # fmt: skip
            return psi + 2 * math.pi * m

        u0 = pick(self.c2, self.zc, lambda p: _rot(th2, p), 0.0)
        v0 = pick(self.c3, self.zp, lambda p: _rot(th3, p), centre)
        assert np.linalg.norm(_rot(th2, self.c2(u0)) - ball) < 1e-14
        assert np.linalg.norm(_rot(th3, self.c3(v0)) + centre - ball) < 1e-14

        def f(x):
            u, v, d = x
            a2, a3 = (th2 + d, th3) if turning == "centre" else (th2, th3 + d)
            p = _rot(a2, self.c2(u) + c2) - (centre + c3 + _rot(a3, self.c3(v)))
            g2, g3 = _rot(a2, self.t2(u)), _rot(a3, self.t3(v))
            r = self.zc * self.e / 2
            return np.array([p[0] / r, p[1] / r,
                             _cross(g2, g3) / np.linalg.norm(g2) / np.linalg.norm(g3)])  # fmt: skip

        x = np.array([u0, v0, 0.0])
        for _ in range(40):
            jac = np.empty((3, 3))
            for k in range(3):
                h = np.zeros(3)
                h[k] = 1e-7
                jac[:, k] = (f(x + h) - f(x - h)) / 2e-7
            step = np.linalg.solve(jac, -f(x))
            x = x + step
            if np.abs(step).max() < 1e-17:
                break
        assert np.abs(f(x)).max() < 1e-10, np.abs(f(x))
        return x[2]


TRACK = Trochoids(38, 2.5e-3, 0.8)  # the cycloid_ball.toml example
R2, R3 = 38 * 2.5e-3 / 2, 40 * 2.5e-3 / 2


def test_nominal_grooves_touch_at_every_ball():
    # the construction's law of gearing: with no offset the grooves are tangent at each
    # ball and need no rotation (a wrong groove would give an O(1) angle here)
    for i in (0, 7, 20, 33):
        assert abs(TRACK.closure(0.3, i, np.zeros(2), np.zeros(2))) < 1e-13


@pytest.mark.parametrize("offset", [(3 * UM, 0.0), (0.0, 3 * UM), (2 * UM, -2 * UM)])
def test_each_ball_follows_its_first_order_law(offset):
    """Ball i alone: delta_2 = -(c_x sin(theta_i) + c_y cos(theta_i)) / (r_2 sin theta_i),
    with c the centre disc's groove minus the planetary disc's in the frame of the
    eccentric; the exact tangency differs at second order."""
    phi = 0.3
    c = np.array(offset)
    c_housing = _rot(phi, c)  # put on the centre disc's groove (its frame = housing
    c2 = _rot(-(1 - 40 / 38) * phi, c_housing)  # turned back by the disc's rotation)
    worst = []
    for i in range(0, 39, 3):
        psi = 2 * math.pi * i / 39 - 40 * phi / 39
        n = TRACK.normal(psi)
        if abs(n[0]) < 0.4:  # a ball near the line of centres has no lever: ill-posed
            continue
        exact = TRACK.closure(phi, i, c2, np.zeros(2))
        first = float(ball_lead(c, n[0], n[1], R2))
        # second order: (|c| / (r_2 sin^2 theta)) (|c| / (e / 2)) times a constant, e / 2
        # being the trochoids' rolling radius (their curvature radii near the balls are
        # of its order); the largest constant found over the balls and offsets here is
        # 5.3; the rotation itself is ~|c| / r_2 = 6e-5 rad
        size = np.hypot(*c)
        assert abs(exact - first) < 10 * size / (R2 * n[0] ** 2) * size / 1.25e-3
        worst.append(abs(exact - first))
        # the half offset: the residual falls by four (second order), where it stands
        # above the solution's round-off (~1e-11: the tangency is a double root)
        half = TRACK.closure(phi, i, c2 / 2, np.zeros(2))
        assert abs(half - first / 2) == pytest.approx(abs(exact - first) / 4, rel=0.25, abs=1e-11)
    assert len(worst) >= 8 and max(worst) > 0


def test_an_offset_along_the_transmission_direction_turns_every_ball_alike():
    """c along x (normal to the line of centres): one rotation -c_x / r_2 keeps every
    ball in both grooves (exact to second order); the planetary disc's output turns by
    c_x / r_3. c along y would need a different rotation per ball (the clearance
    changes instead)."""
    phi, cx = 0.7, 4 * UM
    c2 = _rot(-(1 - 40 / 38) * phi, _rot(phi, np.array([cx, 0.0])))
    want = float(output_error(cx, "centre", R2, R3))
    bound = 10 * (cx / (R2 * 0.4**2)) * (cx / 1.25e-3)  # as above, |sin theta| > 0.4
    for i in range(0, 39, 4):
        n = TRACK.normal(2 * math.pi * i / 39 - 40 * phi / 39)
        if abs(n[0]) > 0.4:
            assert TRACK.closure(phi, i, c2, np.zeros(2)) == pytest.approx(want, abs=bound)
    # the planetary disc's output (the centre disc held): the planetary groove moved by
    # -c along x does what the centre disc's groove moved by +c does
    want3 = float(output_error(cx, "planetary", R2, R3))
    c3 = _rot(phi, np.array([-cx, 0.0]))
    for i in (1, 6, 30):
        got = TRACK.closure(phi, i, np.zeros(2), c3, turning="planetary")
        assert got == pytest.approx(want3, abs=bound)
    assert want == pytest.approx(-cx / R2) and want3 == pytest.approx(cx / R3)


def _cycloid(values):
    return load_design(CYCLOID).with_values(values)


def test_cycloid_trace_matches_the_exact_closure():
    """The drive's trace with a centre-disc groove eccentricity against the exact
    tangency at a few input angles: each loaded ball's exact rotation, less the part
    that only its own clearance takes up (c_y cot(theta_i) / r_2, first order), is the
    drive's rotation."""
    e2, phase = 5 * UM, 0.4
    d = _cycloid({"centre_disc.track_errors": {"eccentricity": e2, "eccentricity_phase": phase}})
    r = transmission_accuracy(d, samples=1024)
    u = r.data["output_angle"].values
    err = r.data["error"].values
    for j in (0, 37, 300, 777):
        phi = 19 * u[j]  # input, counter-clockwise; the centre disc turns by -phi / 19
        th2 = -phi / 19
        c2 = e2 * np.array([math.cos(math.pi / 2 + phase), math.sin(math.pi / 2 + phase)])
        c_frame = _rot(th2 - phi, c2)  # in the frame of the eccentric
        for i in (2, 11, 25):
            n = TRACK.normal(2 * math.pi * i / 39 - 40 * phi / 39)
            if abs(n[0]) < 0.4:
                continue
            exact = TRACK.closure(phi, i, c2, np.zeros(2))
            common = exact + c_frame[1] * n[1] / (R2 * n[0])
            # the output turns clockwise (i = -19): error = -rotation
            bound = 10 * (e2 / (R2 * n[0] ** 2)) * (e2 / 1.25e-3)  # as above
            assert -common == pytest.approx(err[j], abs=bound)


def test_cycloid_orders_and_amplitudes():
    e = 5 * UM
    both = {
        "centre_disc.track_errors": {"eccentricity": e},
        "planetary_disc.track_errors": {"eccentricity": e, "eccentricity_phase": 1.0},
    }
    r = transmission_accuracy(_cycloid(both), samples=2048)
    amp = r.data["amplitude"].values
    # centre output, i = -19: the centre disc turns 1 + 19 = 20 times in the frame of
    # the eccentric per output turn, the held planetary disc 19 times (input order 1);
    # amplitude e / r_2 each
    assert amp[20] == pytest.approx(e / R2 / ARCSEC, rel=1e-12)
    assert amp[19] == pytest.approx(e / R2 / ARCSEC, rel=1e-12)
    assert np.all(np.delete(amp, [19, 20]) < 1e-9 * amp[19])
    assert r.data["input_order"].values[19] == pytest.approx(1.0)
    parts = [transmission_accuracy(_cycloid({k: v}), samples=2048) for k, v in both.items()]
    total = sum(p.data["error"].values for p in parts)
    assert r.data["error"].values == pytest.approx(total, abs=1e-18)  # superposition
    # planetary output (i = 20, the centre disc fixed): over r_3, orders 20 and 19
    p = transmission_accuracy(_cycloid({**both, "output": "planetary"}), samples=2048)
    amp = p.data["amplitude"].values
    assert amp[20] == pytest.approx(e / R3 / ARCSEC, rel=1e-12)
    assert amp[19] == pytest.approx(e / R3 / ARCSEC, rel=1e-12)


def test_cycloid_crank_errors():
    h = 4 * UM
    crank = {"axis_offset": h, "axis_offset_phase": 0.3, "radius_error": 7 * UM,
             "tangential_offset": 2 * UM}  # fmt: skip
    r = transmission_accuracy(_cycloid({"input_shaft.crank_errors": crank}), samples=1024)
    amp = r.data["amplitude"].values
    # the axis offset moves the planetary disc: once per input turn, h / r_2; the radius
    # error lies on the line of centres (no error); the tangential offset a constant
    assert amp[19] == pytest.approx(h / R2 / ARCSEC, rel=1e-12)
    assert np.all(np.delete(amp, [0, 19]) < 1e-9 * amp[19])
    tangential = r.data["contribution"].sel(source="crank tangential offset").values
    # t along -x moves the planetary groove: c_x = +t, the centre disc turns -t / r_2,
    # the output (clockwise) leads by t / r_2
    assert tangential == pytest.approx(np.full(1024, 2 * UM / R2), rel=1e-12)
    assert r.peak_to_peak == pytest.approx(2 * h / R2 / ARCSEC, rel=1e-4)


def _exact_centres(theta_a, rba, rbb, a, centre_a, centre_b, internal):
    """Exact lead (rad, in B's turning sense) of two involute gears whose base circles
    sit at ``centre_a(theta_a)``, ``centre_b(theta_b)`` in the mesh frame (nominally A
    at the origin, B on +x at ``a``), found as tests/test_transmission_accuracy.py
    finds it: on the crossed common tangent for the external pair (A counter-clockwise,
    B clockwise), on the direct one for the internal pair (both clockwise); the
    unwound lengths from the tangent points add up to the tangent's length. The
    constant is that of the nominal centres. Newton to round-off."""
    nominal_a = lambda ta: np.zeros(2)  # noqa: E731
    nominal_b = lambda tb: np.array([a, 0.0])  # noqa: E731

    def part(ta, tb, ca, cb):
        d_vec = cb(tb) - ca(ta)
        d = math.hypot(*d_vec)
        lam = math.atan2(d_vec[1], d_vec[0])
        if internal:
            at = lam - math.acos((rba - rbb) / d)
            return rba * (ta - at) + rbb * at - math.sqrt(d**2 - (rba - rbb) ** 2) - rbb * tb
        g = math.acos((rba + rbb) / d)
        return (-(rba * (lam - g - ta) + rbb * (lam + math.pi - g))
                - math.sqrt(d**2 - (rba + rbb) ** 2) + rbb * tb)  # fmt: skip

    c0 = part(0.0, 0.0, nominal_a, nominal_b)
    ratio = rba / rbb if internal else -rba / rbb
    slope = -rbb if internal else rbb
    out = []
    for ta in np.atleast_1d(theta_a):
        tb = ratio * ta
        for _ in range(60):
            tb = tb - (part(ta, tb, centre_a, centre_b) - c0) / slope
        assert abs(part(ta, tb, centre_a, centre_b) - c0) < 1e-15
        out.append(-(tb - ratio * ta))
    return np.array(out)


def _khv(values):
    return load_design(KHV).with_values(values)


def test_khv_crank_errors_match_the_exact_common_tangent():
    """The crank's axis off the ring's axis (housing-fixed h), its radius error and
    tangential offset (the planet's axis moved in the carrier frame), with a planet
    eccentricity on top, against the exact direct common tangent of the displaced base
    circles."""
    h, ph, da, dt, ev, pv = 4 * UM, 0.8, 6 * UM, -3 * UM, 3 * UM, -0.5
    crank = {"axis_offset": h, "axis_offset_phase": ph, "radius_error": da,
             "tangential_offset": dt}  # fmt: skip
    d = _khv({"gears.crank_errors": crank,
              "gears.planet_errors": {"eccentricity": ev, "eccentricity_phase": pv}})  # fmt: skip
    r = transmission_accuracy(d, samples=256)
    pair = d.gears.pair()
    rba, rbb, a = pair.base_radius(2), pair.base_radius(1), pair.centre_distance
    u = r.data["output_angle"].values
    ta = -10 * u  # the ring turns once back per carrier turn, 10 carrier turns per output
    hv = h * np.array([math.cos(ph), math.sin(ph)])
    exact = _exact_centres(
        ta, rba, rbb, a,
        lambda t: _rot(t, -hv),  # the ring's axis, carried round in the carrier frame
        lambda t: np.array([a + da, dt]) + ev * np.array([math.cos(t + pv), math.sin(t + pv)]),
        internal=True,
    )  # fmt: skip
    # the planet turns clockwise in the carrier frame and the output clockwise (i = -10):
    # the lead in its turning sense is the output's error
    e = h + math.hypot(da, dt) + ev
    short = (rba - rbb) * math.tan(pair.working_pressure_angle)  # the tangent's length
    # second order, as in tests/test_transmission_accuracy.py: (e / L)(e / r_bV)
    assert r.data["error"].values == pytest.approx(exact, abs=2 * (e / short) * (e / rbb))
    assert np.ptp(exact) > 1.5 * (h + ev) / rbb  # the errors are there, not cancelled
    amp = r.data["amplitude"].values
    assert amp[10] == pytest.approx(h / rbb / ARCSEC, rel=1e-12)  # input order 1
    assert amp[11] == pytest.approx(ev / rbb / ARCSEC, rel=1e-12)
    # radius error and tangential offset: a constant, no peak to peak
    const = r.data["contribution"].sel(source="crank radius and tangential offset").values
    assert np.ptp(const) == 0.0 and abs(const[0]) > 0


def test_centre_distance_gives_no_transmission_error_and_the_backlash_change():
    """A gear pair's centre-distance error: the exact rigid contact on the common
    tangent of the moved base circles keeps the ratio (constant lead); the normal
    backlash grows by 2 r_bSigma (inv alpha_w' - inv alpha_w) ~ 2 sin(alpha_w) delta_a
    (the textbook first-order relation, e.g. ISO/TR 10064-2's j_bn = 2 delta_a sin
    alpha_wt)."""
    da = 30 * UM
    d = load_design(GEAR).with_values({"mesh.centre_distance_error": da})
    r = transmission_accuracy(d, samples=256)
    assert r.peak_to_peak == 0.0
    rbp, rbg = d.base_radius("pinion"), d.base_radius("gear")
    aw = d.mesh.pressure_angle  # zero shifts
    a = (rbp + rbg) / math.cos(aw)
    th = np.linspace(0, 2 * math.pi * rbg / rbp, 41)
    exact = _exact_centres(th, rbp, rbg, a, lambda t: np.zeros(2),
                           lambda t: np.array([a + da, 0.0]), internal=False)  # fmt: skip
    assert np.ptp(exact) < 1e-14  # no transmission error at any order
    dj = r.data.attrs["backlash_change"]
    first = 2 * math.sin(aw) * da
    # second order: the relative residual is of order delta_a / (a tan^2 alpha) ~ 3e-3
    assert dj == pytest.approx(first, rel=10 * da / (a * math.tan(aw) ** 2))
    assert dj != pytest.approx(first, rel=1e-6)  # the exact form, not the linear one
    assert r.data.attrs["backlash_change_arcsec"] == pytest.approx(dj / rbg / ARCSEC)
    # halving delta_a halves the change to within a quarter of the residual
    half = backlash_change(da / 2, rbp + rbg, aw, internal=False)
    assert abs(half - first / 2) == pytest.approx(abs(dj - first) / 4, rel=0.05)
    # the KHV crank's radius error moves the planet into the ring: the backlash falls
    k = _khv({"gears.crank_errors": {"radius_error": 10 * UM}})
    rk = transmission_accuracy(k, samples=128)
    aw_k = k.gears.pair().working_pressure_angle
    assert rk.data.attrs["backlash_change"] == pytest.approx(-2 * math.sin(aw_k) * 10 * UM,
                                                             rel=1e-2)  # fmt: skip
    assert "backlash change" in rk.table()


def test_bad_assembly_and_track_fields_are_named():
    with pytest.raises(DesignError, match=r"gears\.crank_errors\.axis_offset"):
        _khv({"gears.crank_errors": {"axis_offset": -1 * UM}})
    with pytest.raises(DesignError, match=r"input_shaft\.crank_errors\.radius_error"):
        _cycloid({"input_shaft.crank_errors": {"radius_error": 5}})  # 5 m: meant um
    with pytest.raises(DesignError, match=r"centre_disc\.track_errors\.eccentricity"):
        _cycloid({"centre_disc.track_errors": {"eccentricity": -1e-6}})
    with pytest.raises(DesignError, match=r"planetary_disc\.track_errors\.wobble"):
        _cycloid({"planetary_disc.track_errors": {"wobble": 1e-6}})
    with pytest.raises(DesignError, match=r"mesh\.centre_distance_error"):
        load_design(GEAR).with_values({"mesh.centre_distance_error": 0.01})
    with pytest.raises(ReducerlabError, match="output"):
        output_error(1e-6, "cover", R2, R3)
    with pytest.raises(ReducerlabError, match="centre distance error"):
        backlash_change(-0.2, 0.1, 0.35, internal=False)
    with pytest.raises(
        ReducerlabError, match=r"gear_pair, khv, cycloid_ball and nutation designs; got a lumped"
    ):
        transmission_accuracy(load_design(example_dir() / "torsional_chain.toml"))


NUT2 = example_dir() / "nutation_double_sided.toml"
NUT1 = example_dir() / "nutation_surface.toml"


def _nut(path, values):
    return load_design(path).with_values(values)


def _model_closure(design, gear, eps_local):
    """Output rotation (rad, the model's rz sense) that keeps the drive model's mesh
    deflections zero (``drives.nutation.build_model``'s Mesh coefficients: paper 000
    Eq. 2-4 assembled there, with the nutating gear's normal turned by the nutation
    angle into the crank frame) when gear ``gear`` (1..4) is offset by ``eps_local``
    (m, (radial, tangential) in its own frame), gear 2 held: an independent assembly
    of the same constraints the law solves in closed form."""
    from reducerlab.drives import build_model
    from reducerlab.model import Mesh

    model = build_model(design)
    meshes = {e.name: e.coefficients for e in model.elements if isinstance(e, Mesh)}
    th = design.theta
    x, y = eps_local
    if gear in (1, 3):  # the nutating body's frame turned by theta about y
        body, q = "g13", {"x": x * math.cos(th), "y": y, "z": -x * math.sin(th)}
    else:
        body, q = ("g2" if gear == 2 else "g4"), {"x": x, "y": y, "z": 0.0}
    mesh_of = {1: "mesh1", 2: "mesh1", 3: "mesh2", 4: "mesh2"}[gear]
    lam = {m: sum(g.get(f"{body}.{k}", 0.0) * v for k, v in q.items()) if m == mesh_of else 0.0
           for m, g in meshes.items()}  # fmt: skip
    g1 = meshes["mesh1"]
    d13 = -lam["mesh1"] / g1["g13.rz"]
    if "mesh2" not in meshes:
        return d13
    g2 = meshes["mesh2"]
    return -(lam["mesh2"] + g2["g13.rz"] * d13) / g2["g4.rz"]


@pytest.mark.parametrize(("path", "gear"), [(NUT2, 1), (NUT2, 2), (NUT2, 3), (NUT2, 4),
                                            (NUT1, 1), (NUT1, 2)])  # fmt: skip
def test_nutation_law_matches_the_drive_models_constraints(path, gear):
    """Each gear's eccentricity, at every sample, against the drive model's own mesh
    constraints solved for the rotations (the crank and gear 2 exact)."""
    e, phase = 5 * UM, 0.6
    d = _nut(path, {f"gear{gear}.errors": {"eccentricity": e, "eccentricity_phase": phase}})
    r = transmission_accuracy(d, samples=64)
    kin = d.kinematics()
    ratio = kin.ratio
    rel = kin.relative_speeds(1.0)
    rel = rel if d.sides == "double" else {"gear 1": rel["nutating gear"],
                                           "gear 2": rel["central gear"]}  # fmt: skip
    u = r.data["output_angle"].values
    got = r.data["contribution"].sel(source=f"gear {gear} eccentricity").values
    for j in range(0, 64, 5):
        psi = rel[f"gear {gear}"] * abs(ratio) * u[j] + phase
        want = math.copysign(1, ratio) * _model_closure(d, gear, (e * math.cos(psi),
                                                                  e * math.sin(psi)))  # fmt: skip
        # the same linear constraints: equal to round-off
        assert got[j] == pytest.approx(want, rel=1e-9, abs=1e-15)
    assert np.ptp(got) > 1.5 * e / 0.05  # a real error, ~e / r_m


def test_nutation_relative_speeds_keep_the_models_meshes_closed():
    """The law turns each gear by the kinematics' relative speed in the model's rz
    sense: those speeds must keep the model's mesh deflections zero (to the 1e-3 by
    which the design lets the mean radii depart from the tooth numbers)."""
    from reducerlab.drives import build_model
    from reducerlab.model import Mesh

    for path in (NUT2, NUT1):
        d = load_design(path)
        rel = d.kinematics().relative_speeds(1.0)
        rz = {
            "g13": rel.get("gear 1", rel.get("nutating gear")),
            "g2": rel.get("gear 2", rel.get("central gear")),
            "g4": rel.get("gear 4"),
        }
        for e in build_model(d).elements:
            if isinstance(e, Mesh):
                terms = [g * rz[k.split(".")[0]] for k, g in e.coefficients.items()
                         if k.endswith(".rz")]  # fmt: skip
                assert abs(sum(terms)) < 2e-3 * max(abs(t) for t in terms)


def test_nutation_orders_and_superposition():
    """Which rotation carries each gear's error, per output turn of the example
    (i = 105): gear 2 (fixed) turns once back per crank turn: order 105 (input order
    1); gear 4 relative to the crank 105 - 1 = 104; the nutating body 105 z2 / z1 =
    97.5 times (a half order: its line falls between 97 and 98)."""
    e = 5 * UM
    d = load_design(NUT2)
    assert d.kinematics().ratio == 105
    r2 = transmission_accuracy(_nut(NUT2, {"gear2.errors": {"eccentricity": e}}), samples=4096)
    r4 = transmission_accuracy(_nut(NUT2, {"gear4.errors": {"eccentricity": e}}), samples=4096)
    assert [k for k, _ in r2.largest_orders(1)] == [105]
    assert [k for k, _ in r4.largest_orders(1)] == [104]
    # amplitudes: e / r_m sqrt(1 + (a_x / a_y)^2), gear 2's times the levers r_m2 / r_m1 and
    # r_m3 / r_m4 through the body
    from reducerlab.drives.nutation_mesh import contact_normal
    from reducerlab.kinematics.accuracy_nutation import radial_ratio

    (d1, d2), (d3, d4) = d.cones(d.theta)
    b, an = d.helix_angle, d.normal_pressure_angle
    for delta in (d1, d2, d3, d4):
        n = contact_normal(delta, b, an)
        assert radial_ratio(delta, b, an) == pytest.approx(n[0] / n[1], rel=1e-12)
    rm = [getattr(d, f"gear{k}").mean_radius for k in range(1, 5)]
    k4 = math.hypot(1, radial_ratio(d4, b, an))
    assert r4.largest_orders(1)[0][1] == pytest.approx(e / rm[3] * k4 / ARCSEC, rel=1e-9)
    k2 = math.hypot(1, radial_ratio(d2, b, an)) * rm[1] / rm[0] * rm[2] / rm[3]
    assert r2.largest_orders(1)[0][1] == pytest.approx(e / rm[1] * k2 / ARCSEC, rel=1e-9)
    r1 = transmission_accuracy(_nut(NUT2, {"gear1.errors": {"eccentricity": e}}), samples=4096)
    assert {k for k, _ in r1.largest_orders(2)} == {97, 98}
    # superposition: all four at once is the sum of each alone
    every = {f"gear{k}.errors": {"eccentricity": e, "eccentricity_phase": 0.3 * k}
             for k in range(1, 5)}  # fmt: skip
    total = transmission_accuracy(_nut(NUT2, every), samples=512).data["error"].values
    alone = sum(transmission_accuracy(_nut(NUT2, {k: v}), samples=512).data["error"].values
                for k, v in every.items())  # fmt: skip
    assert total == pytest.approx(alone, abs=1e-18)


def test_nutation_pitch_deviations_of_the_output_gear():
    """Gear 4's cumulative pitch F_k of the tooth in mesh, tooth by tooth: a tooth ahead
    in the driven gear's turning sense in the crank frame holds the gear back there by
    F_k / r_m4; gear 4 turns backwards in the crank frame (-0.99 of the input) and
    forwards absolutely (+1/105), so the output leads by F_k / r_m4. Gear 4 turns 104
    times per output turn relative to the crank: its 30 teeth pass 3120 times."""
    d0 = load_design(NUT2)
    z = d0.gear4.teeth
    k = np.arange(z)
    f = np.round(2 * UM * np.sin(2 * math.pi * k / z), 9)  # whole nm; pairs k, z - k cancel
    d = _nut(NUT2, {"gear4.errors": {"pitch_deviations": list(f)}})
    n = 3120 * 8 + 7  # not a multiple of the tooth passing: no sample on a change
    r = transmission_accuracy(d, samples=n)
    u = r.data["output_angle"].values
    angle = d.kinematics().relative_speeds(1.0)["gear 4"] * 105 * u
    tooth = np.mod(np.floor(np.abs(angle) * z / (2 * math.pi) + 0.5).astype(int), z)
    F = np.concatenate([[0.0], np.cumsum(f)[:-1]])
    assert r.data["error"].values == pytest.approx(F[tooth] / d.gear4.mean_radius, abs=1e-18)


def test_nutation_bad_errors_are_named():
    with pytest.raises(DesignError, match=r"gear3\.errors\.pitch_deviations.*32 teeth"):
        _nut(NUT2, {"gear3.errors": {"pitch_deviations": [1e-6, -1e-6]}})
    with pytest.raises(DesignError, match=r"gear2\.errors\.eccentricity"):
        _nut(NUT2, {"gear2.errors": {"eccentricity": -1e-6}})


def test_cli_cycloid_with_a_groove_error(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.analysis.transmission_accuracy import TransmissionAccuracyResult
    from reducerlab.cli import app
    from reducerlab.results import Result

    out = tmp_path / "acc"
    args = ["accuracy", str(CYCLOID), "--samples", "256", "-o", str(out),
            "--set", "centre_disc.track_errors.eccentricity=5 um"]  # fmt: skip
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 0, r.output
    assert "centre disc track eccentricity" in r.output
    res = Result.load(out / "accuracy.nc")
    assert isinstance(res, TransmissionAccuracyResult)
    assert res.data.attrs["output"] == "centre"
    assert res.peak_to_peak == pytest.approx(2 * 5 * UM / R2 / ARCSEC, rel=1e-3)


def test_bevel_law_reduces_to_the_cylindrical_gears():
    """At zero cone angle the bevel gear's normal is a helical gear's: a_x / a_y =
    -tan(alpha_n) / cos(beta) = -tan(alpha_t), and a runout e gives the amplitude
    e sqrt(1 + tan^2 alpha_t) / r = e / r_b, the cylindrical law of
    kinematics.accuracy (checked there against the exact common tangent); at 90 deg
    (a crown gear) a straight tooth's normal has no radial part."""
    from reducerlab.kinematics.accuracy_nutation import eccentricity_rotation, radial_ratio

    an, b, r, e = math.radians(20), math.radians(25), 0.05, 5 * UM
    at = math.atan(math.tan(an) / math.cos(b))
    assert radial_ratio(0.0, b, an) == pytest.approx(-math.tan(at), rel=1e-12)
    th = np.linspace(0, 2 * math.pi, 257)
    eps = eccentricity_rotation(e, 0.3, th, radial_ratio(0.0, b, an), r)
    assert np.abs(eps).max() == pytest.approx(e / (r * math.cos(at)), rel=1e-4)
    assert radial_ratio(math.pi / 2, 0.0, an) == pytest.approx(0.0, abs=1e-15)


def test_cycloid_line_of_centres_offset_is_reported():
    # the crank's radius error lies on the line of centres: no output error, but every
    # ball's clearance changes (up to the offset itself)
    r = transmission_accuracy(_cycloid({"input_shaft.crank_errors": {"radius_error": 7 * UM}}),
                              samples=128)  # fmt: skip
    assert r.peak_to_peak == 0.0
    assert r.data.attrs["line_of_centres_offset_max"] == pytest.approx(7 * UM)
