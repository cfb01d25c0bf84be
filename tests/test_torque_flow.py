"""The torque flow (issue 27): mesh torques by virtual work through each drive's
kinematics against the closed forms, power and moment balance over tooth numbers, the
operating point in every design and its bad input, and the statics of the loaded
models (no load along a rigid mode; static mesh forces = the flow's tangential forces
over the lever)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from reducerlab.analysis.torque_flow import torque_flow
from reducerlab.drives import build_model, load_design
from reducerlab.errors import DesignError, ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.kinematics import TRAINS
from reducerlab.kinematics.torques import mesh_torques
from reducerlab.model import Mesh
from reducerlab.model.rigid import RIGID_TOL, rigid_and_elastic

EX = example_dir()
RPM = 2 * math.pi / 60
THETA = math.radians(5.0)
HYP = settings(deadline=None, max_examples=200)
teeth = st.integers(min_value=8, max_value=90)


def _train(name, z, output=None, contact=None):
    tr = TRAINS[name]
    return tr.build(z, THETA if tr.nutating else None, contact, output)


# ------------------------------------------------------------------ closed forms


def test_double_nutation_closed_forms():
    z1, z2, z3, z4 = 28, 26, 32, 30
    kin = _train("double_nutation", {"z1": z1, "z2": z2, "z3": z3, "z4": z4})
    T = 150.0
    f = mesh_torques(kin, T, 1500 * RPM)
    m1, m2 = f.meshes["mesh1"], f.meshes["mesh2"]
    assert kin.ratio == pytest.approx(1 / (1 - z2 * z3 / (z1 * z4)), rel=1e-14) == 105.0
    assert m2.torque("gear 4") == pytest.approx(T, rel=1e-14)
    assert m2.torque("gear 3") == pytest.approx(-T * z3 / z4, rel=1e-14)
    assert m1.torque("gear 1") == pytest.approx(T * z3 / z4, rel=1e-14)  # one body: T1 = T3
    assert m1.torque("gear 2") == pytest.approx(-T * z2 * z3 / (z1 * z4), rel=1e-14)
    assert (m2.external, m1.external) == ("gear 4", "gear 2")
    assert f.fixed == "gear 2" and f.reaction_torque == pytest.approx(T * z2 * z3 / (z1 * z4))
    assert f.input_torque == pytest.approx(T / 105.0, rel=1e-14)


def test_single_nutation_closed_forms():
    # gear 2 fixed, output the nutating gear's net rotation through a coupling
    kin = _train("nutation", {"nutating": 28, "central": 26}, output="nutating")
    f = mesh_torques(kin, 60.0, 1500 * RPM)
    m = f.meshes["mesh1"]
    assert kin.ratio == pytest.approx(28 / (28 - 26))
    assert m.torque("nutating gear") == pytest.approx(60.0, rel=1e-14)
    assert m.torque("central gear") == pytest.approx(-60.0 * 26 / 28, rel=1e-14)
    assert (m.external, f.fixed) == ("central gear", "central gear")
    # the other output: the nutating gear held from net rotation, the central gear turns
    kin = _train("nutation", {"nutating": 28, "central": 26}, output="central")
    m = mesh_torques(kin, 60.0, 1500 * RPM).meshes["mesh1"]
    assert abs(m.torque("central gear")) == pytest.approx(60.0)
    assert abs(m.torque("nutating gear")) == pytest.approx(60.0 * 28 / 26)


def test_khv_closed_forms():
    # paper 004: carrier input, ring K fixed, planet V out through the W mechanism
    kin = _train("khv", {"planet": 30, "ring": 33})
    f = mesh_torques(kin, 50.0, 1500 * RPM)
    m = f.meshes["mesh"]
    assert kin.ratio == -10.0
    assert abs(m.torque("planet V")) == pytest.approx(50.0)
    assert abs(m.torque("ring K")) == pytest.approx(50.0 * 33 / 30)
    assert f.input_torque == pytest.approx(5.0)
    assert m.external == "planet V" and f.fixed == "ring K"


def test_gear_pair_closed_forms():
    kin = _train("gear_pair", {"pinion": 25, "gear": 60})
    f = mesh_torques(kin, 144.0, 1500 * RPM)
    m = f.meshes["mesh"]
    assert abs(m.torque("gear")) == pytest.approx(144.0)
    assert abs(m.torque("pinion")) == pytest.approx(144.0 * 25 / 60) == f.input_torque
    # the mesh's torques oppose the pinion's rotation and the gear's: the pinion drives
    assert m.torque("pinion") < 0 and m.torque("gear") * (1500 * RPM / kin.ratio) > 0
    assert f.fixed is None and f.reaction_torque is None and m.external is None


@pytest.mark.parametrize("output", ["centre", "planetary"])
def test_cycloid_ball_total_track_torque(output):
    kin = _train("cycloid_ball", {"centre": 38, "planetary": 40}, output=output)
    f = mesh_torques(kin, 50.0, 1000 * RPM)
    m = f.meshes["cycloid_pairs"]  # the whole ball track, one mesh
    out, held = ("centre disc", "planetary disc")[:: 1 if output == "centre" else -1]
    assert m.gears == (out, held)
    assert abs(m.torque(out)) == pytest.approx(50.0)
    z = {"centre disc": 38, "planetary disc": 40}
    assert abs(m.torque(held)) == pytest.approx(50.0 * z[held] / z[out])


# --------------------------------------------------------- balances, any tooth numbers


def _balances(kin, T=100.0, w_in=157.0, coaxial=True):
    f = mesh_torques(kin, T, w_in)
    w_h, w_out = kin.carrier_speed(w_in), w_in / kin.ratio
    rel = kin.relative_speeds(w_in)
    out = next(iter(f.meshes.values())).gears[0]
    assert rel[out] == pytest.approx(w_out - w_h, rel=1e-12, abs=1e-12)
    # P_in = P_out (lossless)
    assert f.input_torque * w_in == pytest.approx(T * abs(w_out), rel=1e-12)
    # every mesh passes the same carrier-frame power, in at the driven gear and out at
    # the driving one
    p = f.output_torque * (w_out - w_h)
    for m in f.meshes.values():
        assert m.torques[0] * m.relative_speeds[0] == pytest.approx(p, rel=1e-12)
        assert -m.torques[1] * m.relative_speeds[1] == pytest.approx(p, rel=1e-12)
        assert m.carrier_power == pytest.approx(p, rel=1e-12)
    if coaxial:  # moments about the main axis: input = drive torque on output + on fixed
        tau_fixed = -f.reaction_torque
        assert f.input_torque == pytest.approx(f.output_torque + tau_fixed, rel=1e-9, abs=1e-9)
    return f


@HYP
@given(z1=teeth, z2=teeth, z3=teeth, z4=teeth, contact=st.sampled_from(["internal", "external"]))
def test_double_nutation_balances(z1, z2, z3, z4, contact):
    assume(z1 * z4 != z2 * z3 and z1 != z2 and z3 != z4)
    try:
        kin = _train("double_nutation", {"z1": z1, "z2": z2, "z3": z3, "z4": z4},
                     contact=contact)  # fmt: skip
    except ReducerlabError:
        assume(False)
    f = _balances(kin)
    m1, m2 = f.meshes["mesh1"], f.meshes["mesh2"]
    assert m1.torque("gear 1") + m2.torque("gear 3") == pytest.approx(0.0, abs=1e-9)
    assert abs(m1.torque("gear 2")) == pytest.approx(100.0 * z2 * z3 / (z1 * z4), rel=1e-12)
    assert kin.ratio == pytest.approx(1 / (1 - z2 * z3 / (z1 * z4)), rel=1e-12)


@HYP
@given(zn=teeth, zc=teeth, output=st.sampled_from(["central", "nutating"]))
def test_single_nutation_balances(zn, zc, output):
    assume(zn != zc)
    kin = _train("nutation", {"nutating": zn, "central": zc}, output=output)
    f = _balances(kin)
    out, held = ("nutating gear", "central gear")[:: 1 if output == "nutating" else -1]
    z = {"nutating gear": zn, "central gear": zc}
    assert abs(f.meshes["mesh1"].torque(held)) == pytest.approx(100.0 * z[held] / z[out])


@HYP
@given(zv=teeth, dz=st.integers(min_value=1, max_value=8))
def test_khv_balances(zv, dz):
    f = _balances(_train("khv", {"planet": zv, "ring": zv + dz}))
    assert abs(f.meshes["mesh"].torque("ring K")) == pytest.approx(100.0 * (zv + dz) / zv)


@HYP
@given(zc=teeth, output=st.sampled_from(["centre", "planetary"]))
def test_cycloid_ball_balances(zc, output):
    f = _balances(_train("cycloid_ball", {"centre": zc, "planetary": zc + 2}, output=output))
    assert abs(f.output_torque) == pytest.approx(100.0, rel=1e-12)  # the torque asked for


@HYP
@given(zp=teeth, zg=teeth)
def test_gear_pair_balances(zp, zg):
    f = _balances(_train("gear_pair", {"pinion": zp, "gear": zg}), coaxial=False)
    assert abs(f.meshes["mesh"].torque("gear")) / abs(f.meshes["mesh"].torque("pinion")) == (
        pytest.approx(zg / zp, rel=1e-12)
    )


def test_torques_do_not_depend_on_speed_and_rest_gives_the_same():
    kin = _train("double_nutation", {"z1": 28, "z2": 26, "z3": 32, "z4": 30})
    a, b, rest = (mesh_torques(kin, 80.0, w) for w in (10.0, 300.0, 0.0))
    for name in a.meshes:
        assert a.meshes[name].torques == pytest.approx(b.meshes[name].torques, rel=1e-12)
        assert a.meshes[name].torques == pytest.approx(rest.meshes[name].torques, rel=1e-12)
    assert rest.meshes["mesh1"].carrier_power == 0.0
    with pytest.raises(ReducerlabError, match="output_torque: must be a torque >= 0"):
        mesh_torques(kin, -1.0)


# ------------------------------------------------------------------ the examples


def test_double_sided_example_flow():
    d = load_design(EX / "nutation_double_sided.toml")
    f = torque_flow(d)
    z = {k: getattr(d, f"gear{k}").teeth for k in range(1, 5)}
    assert f.ratio == 105.0
    assert f.output_torque == 120.0
    assert f.input_torque == pytest.approx(120.0 / 105.0)
    assert f.power == pytest.approx(120.0 * 1500 * RPM / 105.0)
    t2 = f.meshes["mesh1"].torque("gear 2")
    t4 = f.meshes["mesh2"].torque("gear 4")
    assert -t2 / t4 == pytest.approx(z[2] * z[3] / (z[1] * z[4]), rel=1e-14)
    # what contact_analysis takes: the torque on each pair's external gear
    assert f.meshes["mesh1"].external == "gear 2"
    assert f.meshes["mesh1"].external_torque == pytest.approx(120.0 * 26 * 32 / (28 * 30))
    assert f.meshes["mesh2"].external_torque == pytest.approx(120.0)
    # tangential forces at the external gears' mean radii
    assert f.meshes["mesh1"].tangential_force == pytest.approx(-t2 / d.gear2.mean_radius)
    assert f.meshes["mesh2"].tangential_force == pytest.approx(t4 / d.gear4.mean_radius)
    # the kinematics-only design of the same drive gives the same torques, no forces
    k = torque_flow(load_design(EX / "nutation_double.toml"))
    assert k.meshes["mesh1"].torques == pytest.approx(f.meshes["mesh1"].torques, rel=1e-14)
    assert k.meshes["mesh1"].tangential_force is None
    # the table's rows (issue 32: torques and forces by the numformat rule, 4 digits)
    lines = f.table().splitlines()
    assert lines[lines.index("mesh   gear    torque (N m)  F_t (N)  external") + 3 :] == [
        "mesh1  gear 1           128        —",
        "mesh1  gear 2        -118.9     3240  yes",
    ]


def test_the_3kw_operating_point_of_the_issue():
    # 3 kW at 1500 rpm through the 105:1 drive: the fixed gear reacts about 2 kN m
    d = load_design(EX / "nutation_double_sided.toml", ["output_torque=0", "output_power=3 kW"])
    f = torque_flow(d)
    assert f.output_torque == pytest.approx(3000 * 105 / (1500 * RPM))  # 2005 N m
    assert f.reaction_torque == pytest.approx(1986.0, rel=1e-3)
    assert f.input_torque == pytest.approx(3000 / (1500 * RPM))  # 19.1 N m


@pytest.mark.parametrize(
    "name",
    ["nutation_double_sided", "nutation_surface", "khv", "khv_rattle", "gear_pair",
     "cycloid_ball"],
)  # fmt: skip
def test_flow_meshes_are_the_models_meshes_and_every_drive_example_is_loaded(name):
    d = load_design(EX / f"{name}.toml")
    meshes = {e.name for e in build_model(d).elements if isinstance(e, Mesh)}
    flow = torque_flow(d)
    assert set(flow.meshes) == meshes
    assert flow.output_torque > 0


def test_kinematics_examples_carry_loads():
    for name in ("nutation_double", "khv_kinematics", "cycloid_ball_kinematics"):
        assert torque_flow(load_design(EX / f"{name}.toml")).output_torque > 0


def test_a_lumped_design_has_no_flow():
    d = load_design(EX / "torsional_chain.toml")
    assert d.operating_point().output_torque == 0.0
    with pytest.raises(ReducerlabError, match="no drive kinematics"):
        torque_flow(d)


# ------------------------------------------------------------- the operating point


@pytest.mark.parametrize(
    ("example", "torque", "power", "speed"),
    [
        ("nutation_double_sided.toml", "output_torque", "output_power", "input_speed"),
        ("nutation_surface.toml", "output_torque", "output_power", "input_speed"),
        ("cycloid_ball.toml", "output_torque", "output_power", "input_speed"),
        ("khv.toml", "load_torque", "output_power", "input_speed"),
        ("nutation_double.toml", "output_torque", "output_power", "input_speed"),
        ("gear_pair.toml", "operating.torque", "operating.power", "operating.speed"),
    ],
)
def test_power_gives_the_torque_and_bad_loads_are_refused(example, torque, power, speed):
    d = load_design(EX / example, [f"{torque}=0", f"{power}=2 kW"])
    p = d.operating_point()
    assert p.power == pytest.approx(2000.0, rel=1e-12)
    assert p.output_torque == pytest.approx(2000.0 / abs(p.output_speed), rel=1e-12)
    assert p.input_torque * p.input_speed == pytest.approx(2000.0, rel=1e-12)
    cases = [
        ([f"{torque}=10 N*m", f"{power}=1 kW"], f"{power} = '1 kW': give the load as {torque} "
                                                f"or as {power}, not both"),
        ([f"{torque}=-10 N*m"], f"{torque} = '-10 N*m': must be >= 0 (N m)"),
        ([f"{torque}=0", f"{power}=-1 kW"], f"{power} = '-1 kW': must be >= 0 (W)"),
    ]  # fmt: skip
    for sets, message in cases:
        with pytest.raises(DesignError) as err:
            load_design(EX / example, sets)
        assert message in str(err.value)


def test_power_without_speed_is_refused():
    sets = ["operating.speed=0", "operating.torque=0", "operating.power=1 kW",
            "mesh.stiffness_harmonics=[]", "mesh.stiffness_phases=[]"]  # fmt: skip
    with pytest.raises(DesignError, match=r"operating\.power = '1 kW': a power needs a "
                       r"non-zero operating\.speed"):  # fmt: skip
        load_design(EX / "gear_pair.toml", sets)
    # a torque at rest is a static load: allowed
    sets[2] = "operating.torque=5 N*m"
    point = load_design(EX / "gear_pair.toml", sets).operating_point()
    assert point.output_torque == pytest.approx(12.0) and point.power == 0.0


def test_retired_input_torque_names_its_replacement():
    with pytest.raises(DesignError) as err:
        load_design(EX / "nutation_double_sided.toml", ["input_torque=19.1 N*m"])
    line = str(err.value)
    assert "input_torque = '19.1 N*m': no longer a field" in line
    assert "output_torque or output_power" in line


def test_khv_input_torque_defaults_to_the_flow():
    from reducerlab.drives import design_from_dict

    d = load_design(EX / "khv.toml")
    assert d.input_torque == 50.0 and d.load_torque == 50.0  # paper 004 Table 2, as printed
    data = d.model_dump(mode="json")
    del data["input_torque"]
    free = design_from_dict(data)
    assert free.input_torque is None
    cos, residual, _ = _statics(build_model(free))  # T_D = T_L / |i| = 5 N m
    assert cos.max() < 1e-10 and residual < 1e-9


# ---------------------------------------------------------------- statics of the models


def _statics(model):
    """(cosine of the load with each rigid mode, static displacement, mesh forces)."""
    rest = model.with_speed(0.0)
    mats = rest.matrices()
    F = model.nonlinear().external_forces(0.0)
    _, phi, rigid, _ = rigid_and_elastic(rest, mats.M, mats.K, RIGID_TOL)
    R, V = phi[:, rigid], phi[:, ~rigid]
    cos = np.abs(R.T @ F) / (np.linalg.norm(R, axis=0) * np.linalg.norm(F))
    q = V @ np.linalg.solve(V.T @ mats.K @ V, V.T @ F)
    residual = np.linalg.norm(mats.K @ q - F) / np.linalg.norm(F)
    forces = {}
    for e in model.elements:
        if isinstance(e, Mesh):
            idx = [model.index[d] for d in e.dofs]
            forces[e.name] = float(e.stiffness.mean * (e.g @ q[idx]))
    return cos, residual, forces


@pytest.mark.parametrize("example", ["nutation_double_sided", "nutation_surface"])
def test_loaded_nutation_model_is_in_static_equilibrium(example):
    d = load_design(EX / f"{example}.toml")
    model = build_model(d)
    cos, residual, forces = _statics(model)
    assert cos.size == 1 and cos.max() < 1e-12  # no load along the rigid rotation
    assert residual < 1e-10  # so K q = F has a solution
    # static mesh forces = the flow's tangential forces over the lever a_y (mesh force
    # along the normal n, whose tangential component is a_y = cos(beta) cos(alpha_n))
    a_y = math.cos(d.helix_angle) * math.cos(d.normal_pressure_angle)
    flow = torque_flow(d)
    for name, m in flow.meshes.items():
        assert abs(forces[name]) == pytest.approx(m.tangential_force / a_y, rel=1e-5)


def test_nutation_reaction_follows_the_model_levers_not_the_teeth():
    """The model's rigid rotation turns the gears in the ratio of the levers a_y r_m;
    the kinematics in that of the teeth. They differ by the mean radii's departure from
    r2/r1 = z2/z1 (< 1e-3 by the design's cone-distance rule): 1.9e-6 for the example.
    The builder takes the lever ratio (static equilibrium exists exactly)."""
    d = load_design(EX / "nutation_double_sided.toml")
    loads = {e.name: e.value.mean for e in build_model(d).elements if e.name.endswith("torque")}
    kin = torque_flow(d).reaction_torque
    r = {k: getattr(d, f"gear{k}").mean_radius for k in range(1, 5)}
    lever = 120.0 * r[2] * r[3] / (r[1] * r[4])
    assert loads["output_torque"] == -120.0
    assert loads["reaction_torque"] == pytest.approx(lever, rel=1e-12)
    assert abs(lever / kin - 1) == pytest.approx(1.92e-6, rel=0.05)


def test_grounded_fixed_gear_reacts_through_its_support():
    d = load_design(EX / "nutation_double_sided.toml", ["fixed_gear_torsional_stiffness=1e6"])
    model = build_model(d)
    assert not [e for e in model.elements if e.name == "reaction_torque"]
    cos, residual, forces = _statics(model)
    assert cos.size == 0 and residual < 1e-10
    free = _statics(build_model(load_design(EX / "nutation_double_sided.toml")))[2]
    for name in forces:  # the same mesh forces: the spring carries the reaction
        assert forces[name] == pytest.approx(free[name], rel=1e-6)


@pytest.mark.parametrize(
    ("example", "sets"),
    [
        ("gear_pair.toml", []),
        ("cycloid_ball.toml", []),
        ("khv.toml", ["input_torque=5 N*m"]),
    ],
)  # fmt: skip
def test_other_drives_load_no_rigid_mode(example, sets):
    cos, residual, _ = _statics(build_model(load_design(EX / example, sets)))
    assert cos.size == 1 and cos.max() < 1e-10 and residual < 1e-9


def test_cycloid_planetary_output_loads_the_end_cover():
    # centre disc held, the end cover takes the planetary disc's rotation out; paper 003's
    # model grounds the end cover (k5u > 0), so make it nearly free: the load does no
    # work on the nearly rigid rotation (the lowest mode)
    sets = ["output=planetary", "centre_disc.torsional_stiffness=1e9",
            "end_cover_disc.torsional_stiffness=1e-3"]  # fmt: skip
    model = build_model(load_design(EX / "cycloid_ball.toml", sets))
    loads = {e.dof for e in model.elements if e.name.endswith("torque")}
    assert loads == {"input_shaft.u", "end_cover_disc.u"}
    K = model.with_speed(0.0).matrices().K
    F = model.nonlinear().external_forces(0.0)
    w, V = np.linalg.eigh(K)
    assert w[0] < 1e-9 * w[-1]
    assert abs(V[:, 0] @ F) / np.linalg.norm(F) < 1e-9


def test_paper_004_torques_as_printed_do_not_balance():
    # T_D = T_L = 50 N m with i = -10 (docs/assumptions.md): the rigid motion accelerates
    cos, _, _ = _statics(build_model(load_design(EX / "khv.toml")))
    assert cos.max() == pytest.approx(0.448, abs=0.01)
