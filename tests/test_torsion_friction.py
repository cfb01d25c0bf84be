"""Coulomb friction in the torsion test (issue 31): Jenkins elements on the sliding mesh
contacts (``analysis.torsion_friction``).

Oracles: the closed-form loop of one linear line with a Jenkins element (stick and
slip branches, derived below from Coulomb's law and Mindlin's tangential stiffness), the
energy balance (loop area = friction work), the rigid-bearing gear pair whose loading
stiffness is ``k r_b^2 (1 + mu tan(alpha))``, and the geometry of the builders' sliding
coefficients (the conjugate motion rolls without sliding at the pitch point).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from reducerlab.analysis.torsion_friction import mindlin_ratio
from reducerlab.analysis.torsion_test import ARCMIN, torsion_test
from reducerlab.drives import build_model, load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.model import Backlash, Dof, Inertia, Mesh, Model
from reducerlab.model.elements import ModelError


def _pair(k: float, h: float, r2: float, c: float) -> Model:
    """One mesh line ``delta = r1 th1 + r2 th2`` whose flanks slide by ``c`` times the
    rotational motion (``c = tan(alpha)`` at a pitch point)."""
    r1 = 0.02
    dofs = [Dof("pinion", "rz"), Dof("gear", "rz")]
    els = [
        Inertia("pinion.rz", 1e-4),
        Inertia("gear.rz", 1e-2),
        Mesh({"pinion.rz": r1, "gear.rz": r2}, stiffness=k, backlash=Backlash.half(h),
             name="mesh", sliding={"pinion.rz": c * r1, "gear.rz": c * r2}),
    ]  # fmt: skip
    return Model(dofs, els, name="pair")


def test_single_line_stick_slip_loop_closed_form():
    """One line, pinion held, twist ``th`` of the gear beyond the contact ``th_c = h/r``:
    normal force ``F = k r phi`` (``phi = th - th_c``), sliding ``s = c r phi``.
    Loading slips from the start (``k_t c > mu k``): ``tau = mu F`` and
    ``T = A (1 + mu c) phi`` (``A = k r^2``). On unloading the slider sticks,
    ``T = T_r - A (1 + kappa c^2)(phi_m - phi)``, until ``tau = -mu F`` at
    ``phi_s = phi_m (kappa c - mu)/(kappa c + mu)``, then slips back with
    ``T = A (1 - mu c) phi``; the negative side mirrors it. Every solved state lies on
    these lines to round-off (the return mapping is exact on a monotone branch), and the
    friction work per cycle is
    ``mu A ((c - mu/kappa) phi_m^2 + (c + mu/kappa) phi_s^2)`` (the slider's slip is the
    sliding less the tangential spring's stretch)."""
    k, h, r, c, mu, Tr = 2e8, 1.5e-5, 0.06, math.tan(math.radians(20)), 0.05, 200.0
    kappa = mindlin_ratio(0.3)
    res = torsion_test(None, model=_pair(k, h, r, c), held=("pinion.rz",), output="gear.rz",
                       rated=Tr, steps=40, mu=mu)  # fmt: skip
    A = k * r * r
    pm = Tr / (A * (1 + mu * c))
    ps = pm * (kappa * c - mu) / (kappa * c + mu)
    Ts = A * (1 - mu * c) * ps
    T, th, br = (res.data[v].values for v in ("torque", "twist", "branch"))
    for Tj, x, b in zip(T, th, br, strict=True):
        sg = 1.0 if b in (0, 1) else -1.0  # the side the branch loads
        t = abs(Tj)
        if b in (0, 2):
            phi = t / (A * (1 + mu * c))
        elif t >= Ts:
            phi = pm - (Tr - t) / (A * (1 + kappa * c * c))
        else:
            phi = t / (A * (1 - mu * c))
        want = sg * (h / r + phi)
        assert x == pytest.approx(want, rel=1e-9, abs=1e-15), (Tj, b)
    # slip rate dp = ds - dtau/k_t: r (c - mu/kappa) dphi loading, r (c + mu/kappa)
    # |dphi| on the unloading slip; work = oint mu F |dp| over both sides
    work = mu * A * ((c - mu / kappa) * pm**2 + (c + mu / kappa) * ps**2)
    # the reported work integrates |tau| trapezoidally over each step's slip: exact on
    # the slip lines except the one step per half-loop where stick turns into slip, and
    # the loop's area (polygon through the solved states) cuts that corner: both errors
    # fall with the step (10/40/160 steps: 0.55/0.13/0.006 % and 0.47/0.07/0.003 %)
    assert res.data.attrs["friction_work"] == pytest.approx(work, rel=3e-3)
    assert res.numbers.loop_area == pytest.approx(work, rel=3e-3)
    assert res.numbers.backlash == pytest.approx(2 * h / r, rel=1e-9)
    assert pytest.approx(A * (1 + mu * c), rel=1e-9) == res.numbers.K1


@pytest.mark.parametrize("name", ["gear_pair", "khv", "nutation_double_sided", "nutation_surface"])
def test_example_loops_open_and_balance_their_energy(name):
    """With friction the loading branch lies above the unloading one (a positive area),
    and the loop's area equals the work the sliders dissipate (energy balance; at 20
    steps the two trapezoidal sums differ by the stick-slip corners, under 1 %)."""
    d = load_design(example_dir() / f"{name}.toml")
    res = torsion_test(d, steps=20)
    plain = torsion_test(d, steps=20, mu=0.0)
    area, work = res.numbers.loop_area, res.data.attrs["friction_work"]
    assert area > 0 and work > 0
    assert area == pytest.approx(work, rel=1e-2)
    assert plain.numbers.loop_area == pytest.approx(0.0, abs=1e-9 * area)
    assert res.numbers.K1 > plain.numbers.K1
    assert res.numbers.backlash == pytest.approx(plain.numbers.backlash, rel=1e-9, abs=1e-15)
    assert "Coulomb mu = 0.05" in res.data.attrs["friction"]


def test_rigid_bearing_gear_pair_loading_stiffness():
    """Gear pair, pinion held, bearings 1e7 times stiffer than the mesh: the gear's
    flank slides ``r_bg tan(alpha)`` per radian, so Coulomb's law adds
    ``mu tan(alpha) F r_bg`` to the torque on loading: K1 = ``k r_bg^2 (1 + mu tan a)``,
    and the unloading branch ends on ``k r_bg^2 (1 - mu tan a)``."""
    stiff = "1e16 N/m"
    d = load_design(example_dir() / "gear_pair.toml",
                    tuple(f"{g}.bearing.stiffness_{a}={stiff}" for g in ("pinion", "gear")
                          for a in "xy"))  # fmt: skip
    res = torsion_test(d, steps=10, mu=0.08)
    k, alpha, rbg = d.mesh.stiffness, d.mesh.pressure_angle, d.base_radius("gear")
    want = k * rbg**2 * (1 + 0.08 * math.tan(alpha))
    assert pytest.approx(want, rel=1e-6) == res.numbers.K1  # bearing compliance 1e-7
    assert pytest.approx(want, rel=1e-6) == res.numbers.K3


def test_sliding_coefficients_roll_at_the_pitch_point():
    """The builders' sliding rows: the conjugate motion (the line's rotational parts
    cancelling) rolls without sliding; a rotation of one gear slides its flank by
    ``tan(alpha)`` (spur, KHV) or ``w / a_y`` (nutation bevel, ``w = sqrt(1 - a_y^2)``)
    times its normal motion; a translation's sliding is its part along the unit
    tangent, orthogonal to the normal."""
    gp = load_design(example_dir() / "gear_pair.toml")
    m = build_model(gp)
    mesh = next(e for e in m.elements if isinstance(e, Mesh))
    g, s = mesh.coefficients, mesh.sliding
    a = gp.mesh.pressure_angle
    roll = {"pinion.rz": 1.0, "gear.rz": -g["pinion.rz"] / g["gear.rz"]}
    assert sum(g[k] * v for k, v in roll.items()) == pytest.approx(0, abs=1e-15)
    assert sum(s[k] * v for k, v in roll.items()) == pytest.approx(0, abs=1e-15)
    assert s["gear.rz"] / g["gear.rz"] == pytest.approx(math.tan(a), rel=1e-14)
    tx, ty, nx, ny = s["pinion.x"], s["pinion.y"], g["pinion.x"], g["pinion.y"]
    assert tx * nx + ty * ny == pytest.approx(0, abs=1e-15)
    assert math.hypot(tx, ty) == pytest.approx(1, rel=1e-14)
    khv = build_model(load_design(example_dir() / "khv.toml"))
    mk = next(e for e in khv.elements if isinstance(e, Mesh))
    assert sum(mk.sliding.values()) == pytest.approx(0, abs=1e-15)  # planet.u = carrier.u
    nd = build_model(load_design(example_dir() / "nutation_double_sided.toml"))
    for e in (e for e in nd.elements if isinstance(e, Mesh)):
        other = next(n for n in e.coefficients if n.endswith(".rz") and n != "g13.rz")
        roll = {"g13.rz": 1.0, other: -e.coefficients["g13.rz"] / e.coefficients[other]}
        assert sum(e.sliding[k] * v for k, v in roll.items()) == pytest.approx(0, abs=1e-15)
        n = np.array([e.coefficients[f"g13.{q}"] for q in "xyz"])
        t = np.array([e.sliding[f"g13.{q}"] for q in "xyz"])
        assert t @ n == pytest.approx(0, abs=1e-15)
        assert np.linalg.norm(t) == pytest.approx(1, rel=1e-14)
        w = math.sqrt(1 - n[1] ** 2)
        assert e.sliding["g13.rz"] / e.coefficients["g13.rz"] == pytest.approx(w / n[1])


def test_rolling_balls_and_zero_mu_close_the_loop():
    """The cycloid-ball drive's balls roll (no sliding rows): no friction, no area; and
    ``mu = 0`` on a sliding drive gives the frictionless loop to the bit."""
    cb = torsion_test(load_design(example_dir() / "cycloid_ball.toml"), steps=5)
    assert cb.numbers.loop_area == pytest.approx(0, abs=1e-12)
    assert "rolling" in cb.data.attrs["friction"]
    d = load_design(example_dir() / "khv.toml")
    zero = torsion_test(d, steps=5, mu=0.0)
    assert "mu = 0" in zero.data.attrs["friction"] and zero.data.attrs["friction_work"] == 0
    assert pytest.approx(41.46, abs=1e-2) == zero.numbers.K1 * ARCMIN  # docs/datasheet.md


def test_bad_friction_input():
    d = load_design(example_dir() / "gear_pair.toml")
    for bad in (-0.1, 0.5, math.nan, "0.1"):
        with pytest.raises(ReducerlabError, match="friction coefficient"):
            torsion_test(d, steps=3, mu=bad)
    with pytest.raises(ModelError, match="sliding coefficients must be on the line's own"):
        Mesh({"a.rz": 1.0}, stiffness=1e8, sliding={"b.rz": 1.0})
