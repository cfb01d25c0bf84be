"""The compiled RK4 ensemble kernel against the event-driven reference, convergence,
energy balance, ensemble independence, divergence errors; bifurcation and spectra."""

from __future__ import annotations

import math
from dataclasses import replace

import numba
import numpy as np
import pytest

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.motion import classify, spectrum_peaks
from reducerlab.analysis.sweep import Axis
from reducerlab.drives import build_model, load_design
from reducerlab.dynamics.coordinates import static_states, to_system
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.lyapunov import lyapunov
from reducerlab.dynamics.reference import simulate_reference
from reducerlab.dynamics.systems import forcing_period
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.model import (
    Backlash,
    Coupling,
    Dof,
    Fourier,
    Inertia,
    Load,
    Mesh,
    Model,
    PiecewisePolynomial,
    Support,
)  # fmt: skip

W = 2 * math.pi * 100.0


def rattle(F=1.0, b=1e-6, k_law=None):
    """Single-DOF gear pair with backlash, time-varying stiffness and error."""
    law = k_law if k_law is not None else Fourier(1e6, (2e5,), W)
    return Model(
        [Dof("a", "x")],
        [
            Inertia("a.x", 1.0),
            Mesh({"a.x": 1.0}, stiffness=law, damping=60.0, backlash=Backlash.half(b),
                 error=Fourier(0.0, (2e-6,), W, (-math.pi / 2,)), name="m"),
            Load("a.x", F),
        ],
    ).nonlinear()  # fmt: skip


def test_kernel_matches_the_event_driven_reference():
    s = rattle()
    T = forcing_period(s)
    ref = simulate_reference(s, np.arange(25, 30) * T)
    fast = ensemble([s], periods=30, keep=5, steps_per_period=2048)
    scale = np.abs(ref[:, 0]).max()
    # the backlash kink limits fixed-step RK4 to low order: 2048 steps per period give
    # ~4e-5 relative (8192 steps: 4e-7, the reference's own level is < 1e-9)
    np.testing.assert_allclose(fast.poincare[0, :5, 0], ref[:, 0], atol=2e-4 * scale)


def test_convergence_with_step_count():
    s = rattle()
    fine = ensemble([s], periods=30, keep=5, steps_per_period=8192).poincare[0, :5, 0]
    errs = []
    for n in (512, 4096):
        x = ensemble([s], periods=30, keep=5, steps_per_period=n).poincare[0, :5, 0]
        errs.append(np.abs(x - fine).max() / np.abs(fine).max())
    # 8x more steps: the backlash kink makes the convergence irregular and of low order
    # (measured 4.6e-5 -> 5.6e-7, x80); ask for at least x20
    assert errs[1] < errs[0] / 20


def test_piecewise_law_steps_are_aligned_with_its_jumps():
    law = PiecewisePolynomial(2 * math.pi / W, (0.0, 0.37), ((1.3e6,), (0.9e6,)))
    s = rattle(k_law=law, b=0.0)
    T = forcing_period(s)
    ref = simulate_reference(s, np.arange(15, 20) * T)
    fast = ensemble([s], periods=20, keep=5, steps_per_period=256)
    # no backlash and steps aligned with the jumps: full 4th order (64 -> 256 steps:
    # 5.2e-5 -> 2.2e-7 relative); 256 steps to 1e-6
    np.testing.assert_allclose(fast.poincare[0, :5, 0], ref[:, 0], rtol=1e-6)


def test_energy_balance_of_an_undamped_linear_run():
    m = Model(
        [Dof("a", "x"), Dof("b", "x")],
        [Inertia("a.x", 2.0), Inertia("b.x", 1.0), Support("a.x", 3e5),
         Coupling({"a.x": 1.0, "b.x": -1.0}, 1e5)],
    ).nonlinear()  # fmt: skip
    y0 = np.array([1e-3, -2e-3, 0.0, 0.0])
    res = ensemble([m], periods=200, keep=200, steps_per_period=64, y0=y0, period=2e-3)
    E = [0.5 * y[2:] @ m.M @ y[2:] + 0.5 * y[:2] @ m.K @ y[:2] for y in res.poincare[0]]
    # RK4 at omega h < 0.15 loses ~1e-7 of the energy per 100 periods
    assert abs(E[-1] / E[0] - 1) < 1e-5


def test_ensemble_results_do_not_depend_on_size_or_threads():
    systems = [rattle(F=f) for f in (0.5, 1.0, 1.5, 2.0, 2.5)]
    all5 = ensemble(systems, periods=20, keep=3, steps_per_period=256).poincare
    alone = ensemble([systems[2]], periods=20, keep=3, steps_per_period=256).poincare
    np.testing.assert_array_equal(all5[2], alone[0])
    n = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = ensemble(systems, periods=20, keep=3, steps_per_period=256).poincare
    finally:
        numba.set_num_threads(n)
    np.testing.assert_array_equal(one, all5)


def test_divergence_names_member_time_and_dof():
    bad = Model([Dof("a", "x")], [Inertia("a.x", 1.0), Support("a.x", 1.0), Load("a.x", 1e3)])
    with pytest.raises(ReducerlabError, match=r"diverged for case 7 at t = .* a\.x"):
        ensemble([bad.nonlinear()], periods=50, keep=1, period=1.0, labels=["case 7"],
                 limit=1e2)  # fmt: skip


def test_spectrum_peaks_as_multiples_of_the_mesh_frequency():
    f = 100.0
    t = np.arange(0, 2.0, 1e-4)
    x = np.sin(2 * math.pi * f * t) + 0.5 * np.sin(2 * math.pi * 0.48 * f * t)
    peaks = spectrum_peaks(x, 1e-4, f, count=2)
    assert [round(p[0], 2) for p in peaks] == [1.0, 0.48]


def test_khv_bifurcation_smoke_and_rigid_motion_removed():
    design = load_design(example_dir() / "khv.toml")
    res = bifurcation(design, Axis.linspace("gears.x1", 0.42, 0.8, 3), periods=40, keep=5)
    assert res.data["poincare"].shape == (3, 5)
    assert np.all(np.isfinite(res.data["poincare"].values))
    from reducerlab.drives import build_model

    assert to_system(build_model(design)).n == 3  # 4 DOFs minus the rigid rotation


def forced_oscillator(second: float | None = None):
    els = [Inertia("a.x", 1.0), Support("a.x", 4e5, 40.0), Load("a.x", Fourier(0.0, (1.0,), W))]
    if second is not None:
        els.append(Load("a.x", Fourier(0.0, (1.0,), second * W), name="second"))
    return Model([Dof("a", "x")], els).nonlinear()


def test_lyapunov_exponent_of_a_damped_linear_oscillator():
    # every perturbation of m x'' + c x' + k x = F(t) decays as exp(-c t / 2m):
    # the largest exponent is -c/(2m) = -20 1/s; 250 periods of renormalisation at
    # 128 steps give it to 0.1 %
    lam = lyapunov([forced_oscillator()], periods=300, transient=50, steps_per_period=128)
    assert lam[0] == pytest.approx(-20.0, rel=5e-3)


def test_motion_classification():
    f = W / (2 * math.pi)
    periodic = ensemble([forced_oscillator()], periods=300, keep=40, steps_per_period=128)
    assert classify(periodic.poincare[0, :40, 0], -20.0, f) == "period-1"
    # a second, incommensurate forcing (golden ratio): the Poincare points fill a curve
    quasi = ensemble([forced_oscillator((1 + 5**0.5) / 2)], periods=300, keep=40,
                     steps_per_period=128, period=2 * math.pi / W)  # fmt: skip
    assert classify(quasi.poincare[0, :40, 0], -20.0, f) == "quasi-periodic"
    assert classify(quasi.poincare[0, :40, 0], 5.0, f) == "chaotic"


def test_a_decaying_transient_is_unsettled_not_quasi_periodic():
    # issue 16: a lightly damped oscillator x'' + 0.004 x' + x = cos(1.3 t) from rest:
    # its free vibration at 1 rad/s decays as exp(-0.002 t), so after 150 periods
    # (720 s) the Poincare points still spiral in (labelled quasi-periodic before);
    # with 10x the damping the same run has settled on period 1
    def osc(c):
        els = [Inertia("a.x", 1.0), Support("a.x", 1.0, c), Load("a.x", Fourier(0.0, (1.0,), 1.3))]
        return Model([Dof("a", "x")], els).nonlinear()

    f = 1.3 / (2 * math.pi)
    slow = ensemble([osc(0.004)], periods=150, keep=60)
    assert classify(slow.poincare[0, :60, 0], -0.002, f) == "unsettled"
    fast = ensemble([osc(0.2)], periods=150, keep=60)
    assert classify(fast.poincare[0, :60, 0], -0.1, f) == "period-1"


def test_a_transient_towards_a_period_3_orbit_is_unsettled():
    # issue 16 (examples/khv_rattle.toml at x1 = 0.72, 600 periods): a sequence still
    # converging towards a period-3 orbit has a large spread in every quarter (the three
    # points), so only its 3-step differences show the transient; they shrink steadily.
    k = np.arange(100)
    orbit = np.array([1.0, -0.4, 0.3])[k % 3]
    f = 1.0
    converging = orbit + 0.05 * np.exp(-0.02 * k) * np.cos(2.1 * k)
    assert classify(converging, -0.5, f) == "unsettled"
    assert classify(orbit + 1e-6 * np.exp(-0.02 * k), -0.5, f) == "period-3"
    # a quasi-periodic sequence (golden-ratio rotation) on top of the same orbit does not
    # shrink: still quasi-periodic
    torus = orbit + 0.05 * np.cos(2 * math.pi * k * (5**0.5 - 1) / 2)
    assert classify(torus, -0.5, f) == "quasi-periodic"


# issue 26 (7): quasi-periodic sequences near a rational rotation number p/n drift slowly
# along their curve; where the drift nears an extremum the n-step differences shrink over
# the 64 kept points, which alone called them unsettled. Each case below shrinks so
# (condition 1 of _converging) yet has no decaying mode.
CURVES = {
    "c2": lambda t: np.cos(t) + 0.3 * np.cos(2 * t),
    "c3": lambda t: np.cos(t) + 0.3 * np.cos(2 * t) + 0.1 * np.sin(3 * t),
}


@pytest.mark.parametrize(
    ("curve", "rho", "theta0"),
    [("c2", 0.3268, 6.0214), ("c2", 0.3305, 4.1888), ("c2", 0.3329, 2.3562),
     ("c2", 0.3361, 2.8798), ("c3", 0.3326, 1.309), ("c3", 0.3398, 0.2618),
     ("c2", 0.2478, 4.7124), ("c3", 0.2521, 1.8326), ("c2", 0.5002, 1.309),
     ("c2", 0.4965, 1.0472), ("c2", 0.4019, 0.0), ("c3", 0.401, 1.309)],
)  # fmt: skip
def test_a_drift_along_a_quasi_periodic_curve_is_not_unsettled(curve, rho, theta0):
    from reducerlab.analysis.motion import _shrinking

    x = CURVES[curve](theta0 + 2 * math.pi * rho * np.arange(64))
    assert _shrinking(x, 12)
    assert classify(x, -1.0, 1.0) == "quasi-periodic"


@pytest.mark.parametrize("orbit", [(0.3,), (1.0, -0.5), (1.0, -0.4, 0.3)])
@pytest.mark.parametrize("factor", [0.5, 0.7])
@pytest.mark.parametrize("omega", [0.0, 1.0, 2.1, math.pi])
def test_decaying_transients_stay_unsettled(orbit, factor, omega):
    # towards a fixed point, a period-2 or a period-3 orbit, by a real (omega 0 or pi)
    # or complex root, the amplitude falling by `factor` over the 64 points; also with
    # white noise of 1e-5 of the range (the decaying part comes from a fit)
    k = np.arange(64)
    x = np.array(orbit)[k % len(orbit)] + 0.3 * factor ** (k / 63) * np.cos(omega * k + 0.7)
    assert classify(x, -1.0, 1.0) == "unsettled"
    noise = np.random.default_rng(7).standard_normal(64)
    assert classify(x + 1e-5 * np.ptp(x) * noise, -1.0, 1.0) == "unsettled"


def test_response_outputs_and_cli(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.analysis.response import ResponseResult, response
    from reducerlab.cli import app

    # linear permanent-contact gear pair forced at W by its error: the response sits at
    # the forcing frequency (peak 1.00x) and the load factor exceeds 1
    res = response(Model(
        [Dof("a", "x")],
        [Inertia("a.x", 1.0),
         Mesh({"a.x": 1.0}, stiffness=1e6, damping=60.0,
              error=Fourier(0.0, (2e-6,), W, (-math.pi / 2,)), name="m"),
         Load("a.x", 10.0)],
    ), periods=200, keep=10, history=20)  # fmt: skip
    assert res.peaks(1)[0][0] == pytest.approx(1.0, abs=0.01)
    assert res.data.attrs["dynamic_load_factor"] > 1.0
    assert res.data.attrs["mean_mesh_force"] == pytest.approx(10.0, rel=1e-3)
    ds = res.data
    # DTE = deflection + static error; the dynamic load averages 1 over whole periods
    np.testing.assert_allclose(ds["dte"], ds["delta"] + ds["static_error"], atol=1e-18)
    assert float(ds["dynamic_load"].mean()) == pytest.approx(1.0, rel=1e-3)
    assert float(ds["dynamic_load"].max()) == pytest.approx(ds.attrs["dynamic_load_factor"])
    assert res.plot().axes
    p = res.save(tmp_path / "r.nc")
    assert ResponseResult.load(p).data["delta"].size == res.data["delta"].size
    khv = str(example_dir() / "khv.toml")
    args = ["response", khv, "--periods", "60", "--keep", "5", "--history", "4"]
    r = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "k")])
    assert r.exit_code == 0, r.output
    assert "dynamic load factor" in r.output and (tmp_path / "k" / "response.png").exists()
    r = CliRunner().invoke(app, ["bifurcation", str(example_dir() / "khv.toml"), "-p",
                                 "gears.x1", "-v", "0.5,0.6", "--periods", "30", "--keep", "3",
                                 "-o", str(tmp_path / "b")])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert (tmp_path / "b" / "bifurcation.png").exists()


def test_bifurcation_resumes_and_runs_on_dask(tmp_path, dask_client):
    design = load_design(example_dir() / "khv.toml")
    axis = Axis.linspace("gears.x1", 0.45, 0.8, 6)
    kw = dict(periods=40, keep=4, chunk_size=2)
    first = bifurcation(design, axis, output=tmp_path / "run", **kw)
    chunks = sorted((tmp_path / "run" / "chunks").glob("chunk_*.npz"))
    assert len(chunks) == 3
    stamps = {p.name: p.stat().st_mtime_ns for p in chunks}
    chunks[1].unlink()  # as if the run had been interrupted
    again = bifurcation(design, axis, output=tmp_path / "run", **kw)
    np.testing.assert_array_equal(again.data["poincare"].values, first.data["poincare"].values)
    for name in (chunks[0].name, chunks[2].name):
        assert (tmp_path / "run" / "chunks" / name).stat().st_mtime_ns == stamps[name]
    with pytest.raises(ReducerlabError, match="different bifurcation run"):
        bifurcation(design, axis, output=tmp_path / "run", periods=41, keep=4, chunk_size=2)
    dask = bifurcation(design, axis, scheduler=dask_client, **kw)
    np.testing.assert_array_equal(dask.data["poincare"].values, first.data["poincare"].values)


def test_bifurcation_worker_processes_and_interpolated_members_change_nothing():
    design = load_design(example_dir() / "khv.toml")
    kw = dict(periods=30, keep=4)
    # per-value builds in two forked processes, overlapped with the integration
    axis = Axis.linspace("gears.x1", 0.45, 0.8, 6)
    alone = bifurcation(design, axis, chunk_size=2, workers=1, **kw)
    forked = bifurcation(design, axis, chunk_size=2, workers=2, **kw)
    np.testing.assert_array_equal(forked.data["poincare"].values, alone.data["poincare"].values)
    with pytest.raises(ReducerlabError, match="workers must be a positive integer"):
        bifurcation(design, axis, workers=0, **kw)
    # the half backlash enters the flat arrays affinely: with more than 8 values the
    # members are interpolated from the ends (after a 4-point affinity check); with 3
    # values they are rebuilt one by one. The same values give the same points.
    many = bifurcation(design, Axis.linspace("mesh.half_backlash", 1e-6, 3e-6, 9), **kw)
    few = bifurcation(design, Axis("mesh.half_backlash", [1e-6, 2e-6, 3e-6]), **kw)
    np.testing.assert_allclose(
        many.data["poincare"].values[[0, 4, 8]], few.data["poincare"].values, rtol=1e-9
    )


def test_dimensionless_form_is_the_same_motion():
    # paper 004 Eq. 13-16: tau = omega_n t, X/b_c; with the same steps per period the
    # RK4 grids map onto each other, so the states agree to round-off
    from reducerlab.dynamics.coordinates import dimensionless

    s = rattle(b=1e-6)
    wn = math.sqrt(1e6 / 1.0)
    d = dimensionless(s, wn, 1e-6, 1.0)
    a = ensemble([s], periods=40, keep=5, steps_per_period=512)
    b = ensemble([d], periods=40, keep=5, steps_per_period=512, limit=1e9)  # units of b_c
    np.testing.assert_allclose(b.poincare[0, :, 0] * 1e-6, a.poincare[0, :, 0], rtol=1e-9)
    np.testing.assert_allclose(b.period[0], a.period[0] * wn, rtol=1e-12)
    assert d.half_backlash[0] == pytest.approx(1.0)
    with pytest.raises(ReducerlabError, match="omega_n must be > 0"):
        dimensionless(s, 0.0, 1e-6, 1.0)


def test_bifurcation_with_exponents_labels_the_motion():
    design = load_design(example_dir() / "khv.toml")
    res = bifurcation(design, Axis.linspace("gears.x1", 0.5, 0.7, 3), periods=200, keep=20,
                      exponents=True)  # fmt: skip
    # one contact loss per mesh period, but a periodic motion (docs/assumptions.md):
    # negative exponents, period-1
    assert np.all(res.data["exponent"].values < 0)
    assert res.labels() == ["period-1"] * 3
    assert len(res.plot().axes) == 3  # diagram, motion band and impact band
    # the teeth leave contact once per mesh period at every value (docs/assumptions.md)
    assert res.impacts() == ["single-sided impact"] * 3
    assert np.all(res.data["contact_losses"].values == 1.0)
    plain = bifurcation(design, Axis.linspace("gears.x1", 0.5, 0.7, 3), periods=50, keep=5)
    with pytest.raises(ReducerlabError, match="no Lyapunov exponents"):
        plain.labels()


def test_bifurcation_exponent_follows_the_trajectory_of_its_points():
    # issue 16: where attractors coexist, an exponent from another start than the points
    # labels the wrong attractor. The exponent is computed inside the kernel beside the
    # points' own trajectory: the points are those of a run without exponents, and the
    # exponent is that of lyapunov() from the same start with the same steps.
    from reducerlab.analysis.members import Members as _Members
    from reducerlab.analysis.members import axis_members

    design = load_design(example_dir() / "khv.toml")
    axis = Axis.linspace("gears.x1", 0.5, 0.7, 2)
    res = bifurcation(design, axis, periods=60, keep=10, exponents=True)
    values, members, _ = axis_members(design, build_model(design), axis, "test")
    assert isinstance(members, _Members)
    systems = members(values)
    y0 = static_states(systems)
    plain = ensemble(systems, periods=60, keep=10, y0=y0)
    both = ensemble(systems, periods=60, keep=10, y0=y0, exponents=True)
    assert both.steps_per_period == plain.steps_per_period
    np.testing.assert_array_equal(both.poincare, plain.poincare)
    lam = lyapunov(systems, periods=60, transient=50, y0=y0,
                   steps_per_period=plain.steps_per_period)  # fmt: skip
    np.testing.assert_allclose(both.exponent, lam, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(res.data["exponent"].values, lam, rtol=1e-12, atol=1e-9)


def test_review_regressions(tmp_path):
    from reducerlab.analysis.response import response

    s = rattle()
    # per-member y0 for lyapunov is repeated per pair (used to overrun the kernel)
    lam = lyapunov([s, s], periods=6, transient=2, steps_per_period=64, y0=np.zeros((2, 2)))
    assert lam.shape == (2,) and np.all(np.isfinite(lam))
    with pytest.raises(ReducerlabError, match="y0 must have shape"):
        lyapunov([s], periods=6, transient=2, y0=np.zeros(3))
    with pytest.raises(ReducerlabError, match="y0 must have shape"):
        ensemble([s], periods=2, keep=1, y0=np.zeros(3))
    with pytest.raises(ReducerlabError, match="labels"):
        ensemble([s, s], periods=2, keep=1, labels=["one"])
    # Poincare deflections subtract e at each sampling time, not e(0): error at W/2
    m = Model([Dof("a", "x")], [
        Inertia("a.x", 1.0),
        Mesh({"a.x": 1.0}, stiffness=Fourier(1e6, (1e5,), W), damping=60.0,
             error=Fourier(0.0, (2e-6,), W / 2), name="m"),
    ]).nonlinear()  # fmt: skip
    r = ensemble([m], periods=41, keep=4, steps_per_period=256, period=4 * math.pi / W)
    T = r.period[0]
    for k in range(4):
        t = (41 - 4 + k) * T
        e = 2e-6 * math.cos(W / 2 * t)
        assert r.delta_poincare[0, k, 0] == pytest.approx(r.poincare[0, k, 0] - e, abs=1e-15)
    # resume folder identifies scale and model
    design = load_design(example_dir() / "khv.toml")
    axis = Axis.linspace("gears.x1", 0.5, 0.6, 2)
    bifurcation(design, axis, periods=20, keep=2, output=tmp_path / "r")
    with pytest.raises(ReducerlabError, match="different bifurcation run"):
        bifurcation(design, axis, periods=20, keep=2, output=tmp_path / "r", scale=1e-3)
    with pytest.raises(ReducerlabError, match="chunk_size"):
        bifurcation(design, axis, periods=20, keep=2, chunk_size=0)
    with pytest.raises(ReducerlabError, match="history must be"):
        response(design, periods=20, keep=2, history=0)
    with pytest.raises(ReducerlabError, match="need >= 4 samples"):
        spectrum_peaks(np.array([]), 1e-3, 1.0)
    # a piecewise law that does not repeat within the sampling period is refused
    law = PiecewisePolynomial(0.0037, (0.0, 0.5), ((1e6,), (2e6,)))
    with pytest.raises(ReducerlabError, match="does not repeat within the sampling period"):
        ensemble([rattle(k_law=law)], periods=2, keep=1, period=0.01)


def test_affinity_probe_is_element_by_element():
    # the stiffness law's row mixes its period (ms, ~ 1/speed) with coefficients of
    # 1e8 N/m: the probe must see the 1/speed dependence, not hide it under the scale
    from reducerlab.analysis.members import Members as _Members
    from reducerlab.analysis.parameters import Evaluator, resolve
    from reducerlab.drives import build_model
    from reducerlab.dynamics.coordinates import rigid_reduction

    design = load_design(example_dir() / "khv.toml")
    model = build_model(design)
    found = {}
    for path, lo, hi in (("mesh.half_backlash", 1e-6, 3e-6), ("input_speed", 100.0, 200.0),
                         ("gears.x1", 0.45, 0.8)):  # fmt: skip
        ev = Evaluator(design, model, (resolve(design, model, path),))
        members = _Members(ev, rigid_reduction(model.nonlinear()))
        members.probe(lo, hi)
        found[path] = None if members.fit is None else members.fit.form
    # the speed is not affine (periods ~ 1/speed) but in the speed form (FORMS);
    # x1 changes the model itself (radii, masses in relative coordinates): rebuilt
    assert found == {"mesh.half_backlash": "affine", "input_speed": "speed",
                     "gears.x1": None}  # fmt: skip


@pytest.mark.parametrize(
    ("example", "path", "lo", "hi", "form"),
    [
        ("khv.toml", "input_speed", 60.0, 400.0, "speed"),
        ("nutation_double_sided.toml", "input_speed", 50.0, 300.0, "speed"),
        ("khv.toml", "mesh.damping_ratio", 0.02, 0.2, "affine"),
    ],
)
def test_fitted_members_equal_rebuilt_models(example, path, lo, hi, form):
    # issue 28: law values that follow the value in a known form are evaluated, not
    # rebuilt; at values between and off the probe points every flat array must equal the
    # rebuilt model's to round-off (1e-12 of each element's size: the forms are exact)
    from reducerlab.analysis.members import FLAT, target_members
    from reducerlab.analysis.parameters import resolve
    from reducerlab.drives import build_model

    design = load_design(example_dir() / example)
    model = build_model(design)
    members, _ = target_members(design, model, [resolve(design, model, path)])
    members.probe(lo, hi)
    assert members.fit is not None and members.fit.form == form
    values = np.array([lo, lo + 0.21 * (hi - lo), lo + 0.5 * (hi - lo), hi])
    for v, got in zip(values, members(values), strict=True):
        want = members.one(float(v))
        for f in FLAT:
            a, b = getattr(got, f), getattr(want, f)
            assert np.all(np.abs(a - b) <= 1e-12 * np.maximum(np.abs(b), np.abs(b).max())), f
        for f in ("k_kind", "e_kind", "f_kind"):
            np.testing.assert_array_equal(getattr(got, f), getattr(want, f))


def test_fit_refuses_a_square_law():
    # a value entering as v^3 (outside the speed form) must be rebuilt, not fitted: the
    # probe checks the form at points that did not fix it
    from reducerlab.analysis.members import _fit

    def system(v):
        return replace(rattle(), line_damping=np.array([v**3]))

    pts = [1.0, 2.0, 1.37, 1.61, 1.13, 1.83, 1.5]
    assert _fit(pts, [system(p) for p in pts], "speed") is None
    assert _fit(pts, [system(p) for p in pts], "affine") is None
    lin = [replace(rattle(), line_damping=np.array([3.0 + 2.0 / p - p * p])) for p in pts]
    assert _fit(pts, lin, "speed") is not None


def test_bifurcation_takes_units_and_tied_paths():
    # issue 16: values with units (the design field's unit) and tied paths, as in sweep
    from reducerlab.analysis.parameters import parse_values

    design = load_design(example_dir() / "khv.toml")
    rpm = bifurcation(design, parse_values("input_speed", "1400 rpm,1500 rpm"), periods=20,
                      keep=2)  # fmt: skip
    np.testing.assert_allclose(rpm.data["p0"].values, [1400 * math.pi / 30, 1500 * math.pi / 30])
    si = bifurcation(design, Axis("input_speed", [1400 * math.pi / 30, 1500 * math.pi / 30]),
                     periods=20, keep=2)  # fmt: skip
    np.testing.assert_allclose(rpm.data["poincare"].values, si.data["poincare"].values)
    tied = bifurcation(design, Axis("inertia.drive+inertia.load", [0.02, 0.04]), periods=20,
                       keep=2)  # fmt: skip
    assert tied.data["poincare"].shape == (2, 2)
    with pytest.raises(ReducerlabError, match="lists a parameter twice"):
        bifurcation(design, Axis("gears.x1+gears.x1", [0.5]), periods=20, keep=2)
