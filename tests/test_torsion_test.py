"""The torsion test with the input held and the datasheet numbers of its loop (issue 31).

Oracles: closed forms of a single mesh with backlash (twist ``+/-h/r + T/(k r^2)``), of a
chain of torsional springs in series, of a Hertzian power-law mesh
(``f = d (p F / (k d))^(1/p)``) and of a cubic spring, all solved to the solver's
residual (1e-10 of the load): compared at 1e-8 relative, the round-off of a Newton
solve on stiffnesses of 1e8..1e9 N/m. The example drives: the loop's tangent at rated
torque against the stiffness of ``K + G^T k G`` condensed here to the output DOF (Schur
complement) with the input held, at 1e-7 (the lines are linear beyond their backlash:
the two are the same number up to the conditioning of the condensation, about 1e4).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from reducerlab.analysis.datasheet import loop_numbers
from reducerlab.analysis.torsion_test import ARCMIN, TorsionTestResult, torsion_test
from reducerlab.drives import build_model, load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.model import (
    Backlash,
    Coupling,
    CubicSpring,
    Dof,
    Fourier,
    Inertia,
    Mesh,
    Model,
)
from reducerlab.results import Result


def _pair(k=2e8, h=1.5e-5, r1=0.02, r2=0.06, **mesh) -> Model:
    """Two rotations coupled by one mesh line ``delta = r1 th1 + r2 th2``."""
    dofs = [Dof("pinion", "rz"), Dof("gear", "rz")]
    els = [
        Inertia("pinion.rz", 1e-4),
        Inertia("gear.rz", 1e-2),
        Mesh({"pinion.rz": r1, "gear.rz": r2}, stiffness=k, backlash=Backlash.half(h),
             name="mesh", **mesh),
    ]  # fmt: skip
    return Model(dofs, els, name="pair")


def _run(model: Model, rated: float, steps: int = 6, **kw) -> TorsionTestResult:
    return torsion_test(None, model=model, held=("pinion.rz",), output="gear.rz",
                        rated=rated, steps=steps, **kw)  # fmt: skip


def test_single_linear_mesh_with_backlash_closed_form():
    """twist = sgn(T) h/r2 + T/(k r2^2) on every branch; backlash 2h/r2; lost motion
    2h/r2 + 2 (0.03 T_r)/(k r2^2); K1 = K2 = K3 = k r2^2; no area without friction."""
    k, h, r2, Tr = 2e8, 1.5e-5, 0.06, 200.0
    res = _run(_pair(k, h, r2=r2), Tr)
    T, th = res.data["torque"].values, res.data["twist"].values
    br = res.data["branch"].values
    side = np.where(br < 2, 1.0, -1.0)  # the zero-torque points belong to their branch
    expect = side * h / r2 + T / (k * r2**2)
    np.testing.assert_allclose(th, expect, rtol=1e-8, atol=1e-14)
    n = res.numbers
    assert n.backlash == pytest.approx(2 * h / r2, rel=1e-9)
    assert n.hysteresis_loss == pytest.approx(2 * h / r2, rel=1e-9)
    assert n.lost_motion_3 == pytest.approx(2 * h / r2 + 0.06 * Tr / (k * r2**2), rel=1e-9)
    assert n.lost_motion_4 == pytest.approx(2 * h / r2 + 0.08 * Tr / (k * r2**2), rel=1e-9)
    for K in (n.K1, n.K2, n.K3, n.rigidity_rv, n.stiffness_at_rated):
        assert pytest.approx(k * r2**2, rel=1e-8) == K
    assert abs(n.loop_area) <= 1e-9 * Tr * n.backlash
    # the loop runs 0 -> +T -> -T -> 0 and crosses zero by the backlash jump
    assert T[0] == 0 and T[-1] == 0 and T.max() == Tr and T.min() == -Tr
    np.testing.assert_allclose(res.data["line_force"].values[:, 0], T / r2, rtol=1e-8,
                               atol=1e-9 * Tr / r2)  # fmt: skip


def test_two_lines_in_parallel_with_staggered_backlash():
    """Two lines on the same lever with half backlashes h1 < h2: the first alone carries
    until its deflection reaches h2 - h1 (F* = k1 (h2 - h1)), then both:
    delta = (F + k1 h1 + k2 h2) / (k1 + k2). The active set changes inside a branch and
    the zero-torque limit has only the first line touching."""
    k1, k2, h1, h2, r = 1e8, 3e8, 5e-6, 2e-5, 0.05
    dofs = [Dof("pinion", "rz"), Dof("gear", "rz")]
    els = [Inertia("pinion.rz", 1e-4), Inertia("gear.rz", 1e-2)] + [
        Mesh({"pinion.rz": 0.02, "gear.rz": r}, stiffness=k, backlash=Backlash.half(h),
             name=f"line{j}")
        for j, (k, h) in enumerate(((k1, h1), (k2, h2)))
    ]  # fmt: skip
    knee = k1 * (h2 - h1) * r  # N m: where the second line closes
    res = _run(Model(dofs, els), 4 * knee, steps=12)  # steps of knee / 3
    T, th, br = (res.data[v].values for v in ("torque", "twist", "branch"))
    F = np.abs(T) / r
    delta = np.where(k1 * (h2 - h1) >= F, h1 + F / k1, (F + k1 * h1 + k2 * h2) / (k1 + k2))
    side = np.where(br < 2, 1.0, -1.0)
    np.testing.assert_allclose(th, side * delta / r, rtol=1e-8)
    assert res.numbers.backlash == pytest.approx(2 * h1 / r, rel=1e-9)
    assert res.numbers.stiffness_at_rated == pytest.approx((k1 + k2) * r**2, rel=1e-8)
    # the catalogue fit sees the knee: K1 = k1 r^2 below it (T1 = 0.2 T_r < knee)
    assert pytest.approx(k1 * r**2, rel=1e-8) == res.numbers.K1
    assert pytest.approx((k1 + k2) * r**2, rel=1e-8) == res.numbers.K3


def test_torsional_chain_in_series():
    """Three shafts in series, the first end held: twist = T (1/k1 + 1/k2 + 1/k3)."""
    ks = (3e4, 5e4, 2e4)
    names = ("a", "b", "c", "d")
    dofs = [Dof(n, "rz") for n in names]
    els = [Inertia(f"{n}.rz", 1e-3) for n in names] + [
        Coupling({f"{p}.rz": 1.0, f"{q}.rz": -1.0}, k, name=f"shaft_{p}{q}")
        for (p, q), k in zip(itertools.pairwise(names), ks, strict=True)
    ]  # fmt: skip
    res = torsion_test(None, model=Model(dofs, els), held=("a.rz",), output="d.rz",
                       rated=30.0, steps=4)  # fmt: skip
    flex = sum(1.0 / k for k in ks)
    np.testing.assert_allclose(res.data["twist"], res.data["torque"] * flex, rtol=1e-9)
    assert pytest.approx(1.0 / flex, rel=1e-9) == res.numbers.K3
    assert res.numbers.backlash == 0.0


@pytest.mark.parametrize("p", [1.5, 10.0 / 9.0])
def test_hertzian_power_law_mesh(p):
    """F = k (d/p)(f/d)^p beyond the backlash: f = d (p F / (k d))^(1/p), twist
    (h + f)/r2 ~ T^(1/p) (point contact p = 1.5; line contact 10/9); the tangent at
    the reference deflection is k."""
    k, h, d, r2 = 3e8, 1e-5, 4e-6, 0.06
    Tr = k * d / p * r2  # the line carries k d / p at rated: f = d there
    res = _run(_pair(k, h, r2=r2, exponent=p, reference_deflection=d), Tr, steps=8)
    T, th = res.data["torque"].values, res.data["twist"].values
    pos = (res.data["branch"].values == 0) & (T > 0)
    f = d * (p * (T[pos] / r2) / (k * d)) ** (1.0 / p)
    np.testing.assert_allclose(th[pos], (h + f) / r2, rtol=1e-8)
    slope = np.polyfit(np.log(T[pos]), np.log(th[pos] - h / r2), 1)[0]
    assert slope == pytest.approx(1.0 / p, rel=1e-6)
    assert res.numbers.stiffness_at_rated == pytest.approx(k * r2**2, rel=1e-7)
    # softer at low torque: K1 < K2 < K3
    n = res.numbers
    assert n.K1 < n.K2 < n.K3


def test_cubic_line_closed_form():
    """A hardening line ``F = k1 f + k3 f^3`` holding the output at lever r: the twist
    ``f / r`` solves ``k1 f + k3 f^3 = T / r`` (Cardano's real root); the tangent at
    rated is ``(k1 + 3 k3 f^2) r^2``."""
    k1, k3, r, Tr = 1e6, 4e15, 0.05, 20.0
    dofs = [Dof("a", "rz"), Dof("b", "rz")]
    els = [Inertia("a.rz", 1e-3), Inertia("b.rz", 1e-3),
           CubicSpring({"b.rz": r, "a.rz": -r}, k1, k3, name="line")]  # fmt: skip
    res = torsion_test(None, model=Model(dofs, els), held=("a.rz",), output="b.rz",
                       rated=Tr, steps=5)  # fmt: skip
    T, th = res.data["torque"].values, res.data["twist"].values

    def root(F: float) -> float:  # Cardano: f^3 + (k1/k3) f - F/k3 = 0, one real root
        pp, qq = k1 / k3, -F / k3
        disc = math.sqrt(qq * qq / 4 + pp**3 / 27)
        return math.copysign(abs(-qq / 2 + disc) ** (1 / 3), -qq / 2 + disc) + math.copysign(
            abs(-qq / 2 - disc) ** (1 / 3), -qq / 2 - disc
        )

    np.testing.assert_allclose(th, [root(t / r) / r for t in T], rtol=1e-8, atol=1e-15)
    f = root(Tr / r)
    assert res.numbers.stiffness_at_rated == pytest.approx((k1 + 3 * k3 * f * f) * r**2,
                                                           rel=1e-8)  # fmt: skip
    n = res.numbers
    assert n.K1 < n.K2 < n.K3


def test_stated_mesh_position_reads_the_stiffness_law_there():
    """With ``position`` the mesh stiffness is k(t) there (a Fourier law's value
    ``mean + a cos(omega t)``), not its mean."""
    k0, a, w, r2 = 2e8, 5e7, 2 * math.pi * 100.0, 0.06
    law = Fourier(k0, (a,), w)
    t = 1.0 / 600.0  # a sixth of the period: cos = 1/2
    res = _run(_pair_law(law, r2), 100.0, position=t)
    assert pytest.approx((k0 + 0.5 * a) * r2**2, rel=1e-8) == res.numbers.K3
    assert pytest.approx(k0 * r2**2, rel=1e-8) == _run(_pair_law(law, r2), 100.0).numbers.K3


def _pair_law(law, r2):
    dofs = [Dof("pinion", "rz"), Dof("gear", "rz")]
    els = [Inertia("pinion.rz", 1e-4), Inertia("gear.rz", 1e-2),
           Mesh({"pinion.rz": 0.02, "gear.rz": r2}, stiffness=law, name="mesh")]  # fmt: skip
    return Model(dofs, els)


def _condensed(design) -> float:
    """Stiffness (N m/rad) at the output with the input held, from ``K + G^T k G`` of
    the model (mean laws), by static condensation; written here apart from the solver."""
    model = build_model(design)
    s = model.nonlinear()
    names = list(s.dof_names)
    k = np.array([law.mean for law in _mesh_laws(model)])
    Kt = s.K + s.G.T @ (s.G * k[:, None])
    held, out = {
        "nutation": ("g2.rz", "g4.rz"),
        "khv": ("drive.u", "load.u"),
        "cycloid_ball": ("input_shaft.u", "centre_disc.u"),
        "gear_pair": ("pinion.rz", "gear.rz"),
    }[design.type]
    free = [i for i, n in enumerate(names) if n != held]
    o = names.index(out)
    rest = [i for i in free if i != o]
    Koo = Kt[o, o] - Kt[o, rest] @ np.linalg.solve(Kt[np.ix_(rest, rest)], Kt[rest, o])
    r = {d.name: d.radius for d in model.dofs}[out] or 1.0
    return float(Koo * r**2)


def _mesh_laws(model):
    return [e.stiffness for e in model.elements if isinstance(e, Mesh)]


@pytest.mark.parametrize("name", ["nutation_double_sided", "khv", "cycloid_ball", "gear_pair"])
def test_example_drives_loop_and_stiffness_at_rated(name):
    """Each example: a monotone loop (twist rising with the torque on every branch) whose
    tangent and K3 secant at rated torque equal the condensed linear stiffness (their
    lines are linear beyond the backlash); the backlash jump equals the lines' gap seen
    at the output."""
    d = load_design(example_dir() / f"{name}.toml")
    res = torsion_test(d, steps=4, mu=0.0)  # frictionless: friction in test_torsion_friction
    T, th, br = (res.data[v].values for v in ("torque", "twist", "branch"))
    for j in range(4):
        t, x = T[br == j], th[br == j]
        order = np.argsort(t)
        assert np.all(np.diff(x[order]) > 0), (name, j)
    K = _condensed(d)
    assert res.numbers.stiffness_at_rated == pytest.approx(K, rel=1e-7)
    assert pytest.approx(K, rel=1e-7) == res.numbers.K3
    assert res.data.attrs["rated_torque"] == pytest.approx(d.operating_point().output_torque)
    if name == "khv":  # one mesh line on planet.u - carrier.u, output load.u = r_bV theta
        s = build_model(d)
        r = {x.name: x.radius for x in s.dofs}["load.u"]
        h = s.nonlinear().half_backlash[0]
        assert res.numbers.backlash == pytest.approx(2 * h / r, rel=1e-9)


def test_nutation_backlash_through_both_meshes():
    """Double-sided nutation drive with backlash on both meshes: at zero torque every
    force vanishes, so the supported translations stay at zero and both lines just
    touch through the rotations alone: ``G1[g13] th13 = s1 h1`` and
    ``G2[g13] th13 + G2[g4] th4 = s2 h2`` (gear 2 held; ``s1, s2`` the sides the torque
    loads, opposite here). The backlash is twice that
    ``th4`` (the two sides are symmetric); the loop above it keeps the linear
    stiffness (the lines are linear beyond their gaps)."""
    d = load_design(example_dir() / "nutation_double_sided.toml",
                    ("mesh1.backlash=20 um", "mesh2.backlash=30 um"))  # fmt: skip
    s = build_model(d).nonlinear()
    col = {n: i for i, n in enumerate(s.dof_names)}
    h1, h2 = s.half_backlash
    G = s.G
    res = torsion_test(d, steps=4, mu=0.0)
    top = int(np.argmax(res.data["torque"].values))
    s1, s2 = np.sign(res.data["line_force"].values[top])  # the sides +T_r loads
    th13 = s1 * h1 / G[0, col["g13.rz"]]
    th4 = (s2 * h2 - G[1, col["g13.rz"]] * th13) / G[1, col["g4.rz"]]
    assert res.numbers.backlash == pytest.approx(2 * abs(th4), rel=1e-9)
    assert pytest.approx(_condensed(d), rel=1e-7) == res.numbers.K3


def test_result_file_table_figure_and_cli(tmp_path):
    """The result reads back as its kind; the table speaks catalogue units; ``reducerlab
    datasheet`` writes its four files; bad options name themselves."""
    from typer.testing import CliRunner

    from reducerlab.cli import app

    example = example_dir() / "gear_pair.toml"
    res = torsion_test(load_design(example), steps=3)
    back = Result.load(res.save(tmp_path / "t.nc"))
    assert isinstance(back, TorsionTestResult)
    assert back.numbers == res.numbers
    table = res.table()
    assert "N m/arcmin" in table and "arcmin" in table and "Coulomb mu = 0.05" in table
    lm = res.to_dict()["datasheet"]["lost_motion_3pct_arcmin"]
    assert lm == pytest.approx(res.numbers.lost_motion_3 / ARCMIN)
    res.figure()
    run = CliRunner().invoke(app, ["datasheet", str(example), "--steps", "3", "--no-efficiency",
                                   "--unloaded", "-o", str(tmp_path / "out")])  # fmt: skip
    assert run.exit_code == 0, run.output
    assert {p.name for p in (tmp_path / "out").iterdir()} >= {
        "datasheet.nc", "datasheet.json", "datasheet.txt", "datasheet.png"}  # fmt: skip
    for args, field in ((["--rated", "-5 N*m"], "--rated"), (["--t1", "0.8"], "--t1"),
                        (["--steps", "2"], "--steps")):  # fmt: skip
        bad = CliRunner().invoke(app, ["datasheet", str(example), *args])
        assert bad.exit_code == 2 and field in bad.output, bad.output


def test_bad_input():
    """Negative torque, too few steps, a design without an output, bad T1/T2, a held
    output: each refused with a message naming it."""
    d = load_design(example_dir() / "gear_pair.toml")
    with pytest.raises(ReducerlabError, match="rated torque must be > 0"):
        torsion_test(d, rated=-10.0)
    with pytest.raises(ReducerlabError, match="steps must be an integer >= 3"):
        torsion_test(d, steps=2)
    with pytest.raises(ReducerlabError, match="t1 < t2"):
        torsion_test(d, t1=0.5, t2=0.4)
    chain = load_design(example_dir() / "torsional_chain.toml")
    with pytest.raises(ReducerlabError, match="names no input and output"):
        torsion_test(chain, rated=10.0)
    with pytest.raises(ReducerlabError, match="also held"):
        torsion_test(d, held=("gear.rz",), output="gear.rz")
    with pytest.raises(ReducerlabError, match=r"no DOF 'shaft\.rz'"):
        torsion_test(d, held=("pinion.rz",), output="shaft.rz")
    with pytest.raises(ReducerlabError, match="four branches"):
        loop_numbers(np.zeros(3), np.zeros(3), np.zeros(3), 1.0, 0.2, 0.7)
