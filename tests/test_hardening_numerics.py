"""Issue 13, numerics: no silently wrong or NaN results from divergent, extreme or
degenerate models; errors name physical DOFs, times and parameter values."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import scipy.linalg

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.campbell import campbell
from reducerlab.analysis.modal import modal
from reducerlab.analysis.response import response
from reducerlab.analysis.sweep import Axis, sweep
from reducerlab.drives import build_model, design_from_dict, load_design
from reducerlab.dynamics.coordinates import to_system
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.guards import BOUND_FACTOR, check_stability, state_bounds
from reducerlab.errors import DivergenceError, ModelError, ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.model import (
    Centripetal,
    Coupling,
    CubicSpring,
    Dof,
    Fourier,
    Inertia,
    Load,
    Mesh,
    Model,
    Support,
)


def centrifuged(ratio: float = 15.0) -> Model:
    """Two bodies on bearings and a mesh; the centripetal term of the wheel exceeds its
    support and mesh stiffness (ratio 15 at 3000 rpm): a divergent mode of wheel.x."""
    return Model(
        [Dof("pinion", "x"), Dof("wheel", "x")],
        [
            Inertia("pinion.x", 1.0),
            Inertia("wheel.x", 4.0),
            Support("pinion.x", 1e8, 200.0),
            Support("wheel.x", 1e7, 200.0),
            Centripetal("wheel.x", 4.0, ratio),
            Mesh({"pinion.x": 1.0, "wheel.x": -1.0}, Fourier(2e8, (3e7,), 16 * 100 * math.pi),
                 damping=400.0),
            Load("pinion.x", 1000.0),
        ],
        speed=100 * math.pi,
        name="centrifuged",
    )  # fmt: skip


def test_divergent_linear_part_stops_response_and_bifurcation_naming_the_dof():
    m = centrifuged()
    assert modal(m).data["unstable"].values.any()  # modal flags it too
    with pytest.raises(DivergenceError, match=r"divergent mode.*wheel\.x"):
        response(m, periods=10, keep=2, history=2)
    ax = Axis("support:wheel.x.stiffness", [1e6, 2e6, 3e6])
    with pytest.raises(DivergenceError, match=r"support:wheel\.x\.stiffness = 1e\+06.*wheel\.x"):
        bifurcation(m, ax, periods=10, keep=2)
    # a stable member is untouched by the check: same model at a low frame speed
    response(centrifuged(ratio=1.0), periods=10, keep=2, history=2)


def test_stability_check_spares_rigid_modes_and_the_duffing_double_well():
    # a free pair: its rigid mode has eigenvalue ~0 of either sign
    free = Model(
        [Dof("a", "x"), Dof("b", "x")],
        [Inertia("a.x", 1.0), Inertia("b.x", 1e-3), Coupling({"a.x": 1, "b.x": -1}, 1e9),
         Mesh({"a.x": 1.0, "b.x": -1.0}, Fourier(1e6, (1e5,), 50.0))],
    ).nonlinear()  # fmt: skip
    check_stability([free])
    # negative linear stiffness held by a hardening cubic spring: bounded, allowed
    duffing = Model(
        [Dof("a", "x")],
        [Inertia("a.x", 1.0), Support("a.x", 0.0, 0.3), CubicSpring({"a.x": 1.0}, -1.0, 1.0)],
    ).nonlinear()
    check_stability([duffing])
    softening = Model(
        [Dof("a", "x")],
        [Inertia("a.x", 1.0), CubicSpring({"a.x": 1.0}, -1.0, -1.0)],
    ).nonlinear()
    with pytest.raises(DivergenceError, match=r"a\.x"):
        check_stability([softening], ["case 3"])


def mathieu(amplitude: float) -> Model:
    """A free pair whose mesh stiffness pumps at twice its natural frequency."""
    return Model(
        [Dof("pinion", "x"), Dof("wheel", "x")],
        [Inertia("pinion.x", 1.0), Inertia("wheel.x", 1.0),
         Mesh({"pinion.x": 1.0, "wheel.x": -1.0}, Fourier(2.0, (amplitude,), 4.0)),
         Load("pinion.x", 0.1), Load("wheel.x", -0.1)],
        name="mathieu",
    )  # fmt: skip


def test_parametric_instability_stops_at_the_state_bound_with_time_and_physical_dofs():
    # linear part stable (mean stiffness > 0), but the pumped stiffness makes the motion
    # grow exponentially: the default bound stops it long before overflow
    with pytest.raises(DivergenceError) as exc:
        response(mathieu(0.8), periods=200, keep=5, history=2)
    text = str(exc.value)
    assert "'mathieu' at t = " in text and "pinion.x" in text and "wheel.x" in text
    assert "elastic_" not in text  # relative coordinates mapped back to the DOFs
    t = float(text.split("at t = ")[1].split(" s")[0])
    assert 0 < t < 200 * math.pi / 2
    ok = response(mathieu(0.0), periods=40, keep=2, history=2)
    assert ok.data.attrs["dynamic_load_factor"] == pytest.approx(1.0)


def test_default_state_bound_rule():
    s = Model(
        [Dof("a", "x")],
        [Inertia("a.x", 4.0), Support("a.x", 1e4), Load("a.x", Fourier(60.0, (40.0,), 10.0))],
    ).nonlinear()
    b = state_bounds([s], np.zeros((1, 2)), np.array([2 * math.pi / 10.0]))
    d = 100.0 / 1e4  # static deflection under the peak load 60 + 40
    assert b[0, 0] == pytest.approx(BOUND_FACTOR * d)
    assert b[0, 1] == pytest.approx(BOUND_FACTOR * d * 50.0)  # sqrt(1e4 / 4) > 10 rad/s
    with pytest.raises(DivergenceError, match=r"case 2 at t = .*a\.x.*left its bound"):
        ensemble([s], periods=5, keep=1, y0=np.array([2e6 * d, 0.0]), labels=["case 2"],
                 limit=1e4 * d)  # fmt: skip


def test_a_very_light_pinion_keeps_its_elastic_modes():
    data = load_design(example_dir() / "gear_pair.toml").model_dump(mode="python")
    data["pinion"]["mass"] = 1e-9  # 1e-6 g
    model = build_model(design_from_dict(data))
    res = modal(model)
    mats = model.matrices()
    lam = scipy.linalg.eigh(mats.K, mats.M, eigvals_only=True)
    rigid = res.data["rigid"].values.astype(bool)
    assert rigid.sum() == 1  # the free rotation of the pair only
    elastic = np.sqrt(lam[1:]) / (2 * math.pi)
    np.testing.assert_allclose(res.frequencies[1:], elastic, rtol=1e-6)
    assert res.frequencies[1] == pytest.approx(1388.35, rel=1e-4)
    assert campbell(model, [0.0, 10.0]).data["frequency"].values[0, 1] == pytest.approx(
        res.frequencies[1], rel=1e-9
    )
    # the sweep decides rigidity by the same kind of test (strain, not the largest
    # eigenvalue): the batched path keeps the elastic mode too
    sw = sweep(model, Axis("mesh.stiffness", (3.8e8, 3.9e8, 4.0e8)), workers=1, track=False)
    np.testing.assert_allclose(sw.data["frequency"].values[0, 1:], elastic, rtol=1e-6)
    assert sw.data["frequency"].values[0, 0] == 0.0


RIGID = {
    "cycloid_ball": 1, "gear_pair": 1, "khv": 1, "nutation_double_sided": 1,
    "nutation_surface": 1, "torsional_chain": 1,
}  # fmt: skip


@pytest.mark.parametrize("name", sorted(RIGID))
def test_true_rigid_modes_of_every_example(name):
    res = modal(build_model(load_design(example_dir() / f"{name}.toml")))
    rigid = res.data["rigid"].values.astype(bool)
    assert rigid.sum() == RIGID[name]
    assert np.all(res.frequencies[rigid] == 0.0)
    assert np.all(np.abs(res.frequencies[~rigid]) > 1.0)


def chain(inertia: float = 6e-2, torque: float = 2.0, shaft: float = 2.5e3) -> Model:
    return Model(
        [Dof("motor", "rz"), Dof("pinion", "rz"), Dof("load", "rz")],
        [Inertia("motor.rz", 4e-4), Inertia("pinion.rz", inertia), Inertia("load.rz", 8e-3),
         Coupling({"motor.rz": 1, "pinion.rz": -1}, shaft, 0.05),
         Mesh({"pinion.rz": 0.012, "load.rz": -0.03}, Fourier(2.4e8, (3e7,), 1000.0),
              damping=400.0),
         Load("motor.rz", torque)],
        name="chain",
    )  # fmt: skip


def test_huge_torque_gives_finite_results():
    # f**3 with a zero cubic coefficient once gave inf * 0 = NaN
    res = response(chain(torque=1e150), periods=20, keep=2, history=2)
    for var in res.data.data_vars.values():
        assert np.all(np.isfinite(var.values))
    s = to_system(chain(torque=1e150))
    assert np.all(np.isfinite(s.mesh_forces(0.0, np.full(s.n, 1e140), np.zeros(s.n))))


@pytest.mark.parametrize(
    ("kw", "dof"),
    [({"inertia": 1e-300}, "pinion.rz"), ({"shaft": 1.7e308}, "motor.rz")],
)
def test_extreme_values_give_model_errors_naming_the_dof(kw, dof):
    m = chain(**kw)
    for run in (
        lambda: modal(m),
        lambda: campbell(m, [0.0, 100.0]),
        lambda: response(m, periods=10, keep=2, history=2),
    ):
        with pytest.raises(ModelError, match=rf"'{dof}'"):
            run()


def test_overflowing_assembly_names_dof_and_elements():
    m = Model(
        [Dof("a", "x")],
        [Inertia("a.x", 1.0), Support("a.x", 1.7e308, name="s1"),
         Support("a.x", 1.7e308, name="s2")],
    )  # fmt: skip
    with pytest.raises(ModelError, match=r"stiffness at DOF 'a\.x' is not finite.*'s1'"):
        m.matrices()


def test_flat_system_refuses_non_finite_arrays():
    s = chain().nonlinear()
    K = s.K.copy()
    K[1, 1] = np.nan
    with pytest.raises(ReducerlabError, match=r"stiffness matrix is not finite at 'pinion\.rz'"):
        dataclasses.replace(s, K=K)


def test_response_without_a_mesh_says_so():
    free = Model([Dof("a", "x")], [Inertia("a.x", 1.0), Load("a.x", 1.0)])
    with pytest.raises(ReducerlabError, match="no mesh line: a nonlinear response needs"):
        response(free, period=0.1)


def test_reduction_error_names_dofs_and_elements():
    s = Model(
        [Dof("a", "x"), Dof("b", "x")],
        [Inertia("a.x", 1.0), Inertia("b.x", 1.0), Support("a.x", 10.0),
         Mesh({"a.x": 1.0, "b.x": -1.0}, 100.0)],
    ).nonlinear()  # fmt: skip
    # a single relative coordinate leaves the common motion free, held by the support
    with pytest.raises(ReducerlabError) as exc:
        s.reduced(np.array([[1.0, -1.0]]), ["stretch"])
    text = str(exc.value)
    assert "'a.x'" in text and "rows of T" not in text and "stretch" in text


def test_speed_terms_do_not_turn_rigid_motion_into_divergence():
    """The cycloid ball example runs at 1000 rpm: its centripetal terms, linearised in
    the rotating frame, give the rigid rotation a small negative 'stiffness' (modal
    reports it as a rigid mode with drift). The nonlinear runs remove the rigid motion
    of the model at rest, as modal does, instead of integrating (or refusing) an
    exponentially drifting rigid coordinate."""
    design = load_design(example_dir() / "cycloid_ball.toml", ["output_torque=0"])
    m = modal(build_model(design))
    assert not m.data["unstable"].values.any()
    res = response(design, period=1e-3, periods=40, keep=5, history=2)
    # unloaded (the example's rated load taken off), constant stiffness: the model
    # rests, so there is no mean force to compare with and the load factor is
    # undefined (NaN), not inf
    assert math.isnan(res.data.attrs["dynamic_load_factor"])
    assert np.all(np.isfinite(res.data["delta"].values))
    axis = Axis("input_speed", (900 * math.pi / 30, 1000 * math.pi / 30))
    bif = bifurcation(design, axis, periods=20, keep=4, period=1e-3)
    assert np.all(np.isfinite(bif.data["poincare"].values))
    assert bif.data.attrs["forcing_hz"] == pytest.approx(1e3)


@pytest.mark.parametrize("name", sorted(RIGID))
def test_sweep_and_modal_agree_on_rigid_and_elastic_modes(name):
    """A sweep decides rigid modes as modal does (element strain, at rest when the model
    runs at a speed): at the design value it gives modal's frequencies, 0 Hz included
    (the cycloid example's speed terms used to turn its rigid mode into -3.5 Hz)."""
    from reducerlab.model.inspect import parameter_paths

    model = build_model(load_design(example_dir() / f"{name}.toml"))
    res = modal(model)
    path, value = parameter_paths(model)[0]
    for values in ((value, 1.01 * value, 1.02 * value), (value,)):  # batched and per point
        sw = sweep(model, Axis(path, values), workers=1, track=False)
        f = sw.data["frequency"].values[0]
        assert np.sum(f == 0.0) == RIGID[name]
        np.testing.assert_allclose(f, res.frequencies, rtol=1e-9, atol=1e-9)


def _gear_pair(**changes: dict) -> object:
    data = load_design(example_dir() / "gear_pair.toml").model_dump(mode="python")
    for section, fields in changes.items():
        node = data
        for key in section.split("."):
            node = node[key]
        node.update(fields)
    return design_from_dict(data, "variant.toml")


def test_frequencies_below_the_eigen_solver_resolution_are_refused():
    """A 1e-12 kg m^2 pinion on a 1e18 N/m mesh (both within the design ranges) puts
    the highest frequency at 5.6e12 Hz: every other mode is below what double precision
    resolves (the absolute eigenvalue error is ~eps x the largest). modal used to print
    round-off as '-174 Hz divergent' and '1.27 Hz torsional'; a 1e-6 N/m bearing gave a
    2.5e-6 Hz 'mode'. Both are refused, naming the DOF that sets the top frequency."""
    stiff = _gear_pair(pinion={"moment_of_inertia": 1e-12}, mesh={"stiffness": 1e18})
    with pytest.raises(ModelError, match=r"pinion\.rz.*no frequency below .* can be computed"):
        modal(build_model(stiff))
    with pytest.raises(ModelError, match=r"pinion\.rz.*no frequency below .* can be computed"):
        campbell(build_model(stiff), [0.0, 10.0])
    with pytest.raises(ModelError, match=r"pinion\.rz.*no frequency below .* can be computed"):
        response(stiff, periods=4, keep=1, history=1)
    soft = _gear_pair(**{"pinion.bearing": {"stiffness_x": 1e-6}})
    with pytest.raises(ModelError, match=r"no frequency below .* can be computed"):
        modal(build_model(soft))


def test_stiff_runs_are_refused_before_they_start():
    """A near-rigid part (highest frequency 1e8 Hz against a 625 Hz mesh) would need
    millions of RK4 steps per period: the run used to start and grow to gigabytes; it is
    refused at once, naming the frequency and the DOF, unless the steps are given."""
    light = _gear_pair(pinion={"moment_of_inertia": 1e-12})
    assert modal(build_model(light)).frequencies[1] == pytest.approx(1495.0, rel=1e-3)
    with pytest.raises(ReducerlabError, match=r"1\.093e\+08 Hz.*pinion\.rz.*--steps"):
        response(light, periods=4, keep=1, history=1)
    rigid_mesh = _gear_pair(mesh={"stiffness": 1e18})
    with pytest.raises(ReducerlabError, match=r"steps per forcing period \(at most 100000\)"):
        response(rigid_mesh, periods=4, keep=1, history=1)


def test_short_runs_from_the_command_line_need_no_keep_or_history(tmp_path):
    """`response --periods 10` used to fail on the defaults of options the user never
    gave ('--keep 100: must be at most --periods (10)'); the defaults now shrink."""
    from typer.testing import CliRunner

    from reducerlab.cli import app

    design = str(example_dir() / "gear_pair.toml")
    r = CliRunner().invoke(app, ["response", design, "--periods", "10", "-o", str(tmp_path)])
    assert r.exit_code == 0, r.output
    assert (tmp_path / "response.nc").exists()
    r = CliRunner().invoke(app, ["response", design, "--periods", "10", "--keep", "11"])
    assert r.exit_code == 2 and "--keep 11: must be at most --periods (10)" in r.output


def test_a_sweep_into_unresolvable_values_stops_instead_of_reporting_round_off():
    model = build_model(_gear_pair(pinion={"moment_of_inertia": 1e-12}))
    ok = sweep(model, Axis("mesh.stiffness", (3.8e8, 4.0e8)), workers=1, track=False)
    assert ok.data["frequency"].values[0, 1] == pytest.approx(1495.0, rel=1e-3)
    with pytest.raises(ModelError, match=r"sweep: .*no frequency below .* can be computed"):
        sweep(model, Axis("mesh.stiffness", (3.8e8, 1e18)), workers=1, track=False)


def test_campbell_solves_each_speed_as_modal_does():
    """The cycloid example's rigid mode drifted to -6.8 Hz at 200 rad/s in the Campbell
    diagram (speed terms on the rigid rotation) while modal reports it at 0 Hz; each
    speed is now solved as modal solves the model at that speed."""
    design = load_design(example_dir() / "cycloid_ball.toml")
    speeds = [0.0, 100.0, 200.0]
    f = campbell(design, speeds).data["frequency"].values
    assert np.all(f[:, 0] == 0.0)
    for w, row in zip(speeds, f, strict=True):
        at = modal(build_model(design).with_speed(w)).frequencies
        np.testing.assert_allclose(row, at, rtol=1e-9, atol=1e-9)


def test_round_off_of_an_unloaded_model_is_not_a_load_factor_or_a_spectrum():
    """The double-sided nutation example without its load: its mesh force is round-off
    (~1e-15 N) and the 'dynamic load factor' was reported as 2.77 with spectral peaks at
    '15x, 13.5x'; a force below the line stiffness x 1 pm is no load, a deflection
    varying by less than 1 pm no spectrum."""
    sets = ["output_torque=0", "mesh1.harmonics=[]", "mesh2.harmonics=[]"]
    design = load_design(example_dir() / "nutation_double_sided.toml", sets)
    res = response(design, periods=20, keep=5, history=2)
    assert math.isnan(res.data.attrs["dynamic_load_factor"])
    assert res.peaks(5) == []
    loaded = response(load_design(example_dir() / "gear_pair.toml"), periods=20, keep=5,
                      history=2)  # fmt: skip
    assert loaded.data.attrs["dynamic_load_factor"] > 1.0 and loaded.peaks(3)


def damped_mathieu(damping: float) -> Model:
    """x'' + c x' + (1 + 0.6 cos 2t) x = 1: principal parametric resonance."""
    from reducerlab.model import Backlash, Fourier, Mesh

    return Model(
        [Dof("a", "x")],
        [
            Inertia("a.x", 1.0),
            Mesh({"a.x": 1.0}, Fourier(1.0, (0.6,), 2.0), damping, name="mesh",
                 backlash=Backlash.half(0.0)),
            Load("a.x", 1.0),
        ],
        name="mathieu",
    )  # fmt: skip


def test_a_diverging_value_is_marked_without_aborting_the_bifurcation():
    # issue 16: the Mathieu oscillator's mean system is stable, so the check before the
    # run passes, but with little damping (0.002, below the tongue's threshold of about
    # 0.6 / 2) the motion grows without bound. That value is marked "diverged" (NaN
    # points), the damped values on either side keep their results; ensemble's default
    # (on_divergence="raise") still stops a run naming it.
    from reducerlab.dynamics.coordinates import to_system
    from reducerlab.dynamics.ensemble import ensemble

    res = bifurcation(damped_mathieu(0.02), Axis("mesh.damping", [0.5, 0.002, 0.4]), periods=200,
                      keep=5, exponents=True)  # fmt: skip
    assert res.diverged.tolist() == [False, True, False]
    assert res.labels() == ["period-1", "diverged", "period-1"]
    assert np.isnan(res.data["exponent"].values[1])
    assert np.all(np.isfinite(res.data["poincare"].values[[0, 2]]))
    assert res.periodicity().tolist() == [1, 0, 1]
    assert len(res.plot().axes) == 3
    assert res.impacts() == ["no impact", "diverged", "no impact"]
    with pytest.raises(DivergenceError, match="diverged"):
        ensemble([to_system(damped_mathieu(0.002))], periods=200, keep=5, y0=np.array([1.0, 0.0]))
