"""Paper 000 (Lin, Yao, Xie 2020): double-sided nutation drive, geometry, the 12-DOF
model, Table 3 (not reproducible from the stated model: the argument is tested),
Fig. 5-6 trends and the resonance verdict. Tolerances justified inline."""

from __future__ import annotations

import importlib.util
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.modal import modal
from reducerlab.cli import app
from reducerlab.drives import build_model, design_from_dict, load_design
from reducerlab.drives.nutation_mesh import contact_normal
from reducerlab.errors import DesignError
from reducerlab.examples import example_dir

EXAMPLE = example_dir() / "nutation_double_sided.toml"
TABLE3_HZ = np.array([0, 6600, 7870, 7880, 7880, 16160, 16330, 29630, 35970, 70210, 107120, 285490])
# our computed table for Tables 1-2 (regression pin; see docs/assumptions.md)
OURS_HZ = np.array(
    [0.0, 2238.9665, 2565.7824, 2565.9945, 3450.8935, 4068.1901, 4696.7453, 4696.7453,
     5611.0590, 5611.0590, 7779.2438, 9594.3375]
)  # fmt: skip


@pytest.fixture(scope="module")
def design():
    return load_design(EXAMPLE)


@pytest.fixture(scope="module")
def result(design):
    return modal(build_model(design))


def test_geometry_from_the_mean_radii(design):
    # The four mean cone distances r_m / sin(delta) agree at one nutation angle: 5.00 deg
    # with a cone distance of 50.00 mm (Table 1's radii are given to 0.1 um, so the
    # angle is determined to ~1e-3 deg).
    assert math.degrees(design.theta) == pytest.approx(5.0, abs=2e-3)
    d = design.cone_distances(design.theta)
    np.testing.assert_allclose(d, 50.0e-3, rtol=1e-4)
    assert design.kinematics().ratio == 105.0


def test_projection_vectors_are_unit_and_k_symmetric(design):
    b, an = design.helix_angle, design.normal_pressure_angle
    for delta in (0.3, 0.9, 1.2):
        for rot in (0.0, design.theta, 0.4):
            assert np.linalg.norm(contact_normal(delta, b, an, rot)) == pytest.approx(1.0, 1e-15)
    K = build_model(design).matrices().K
    np.testing.assert_array_equal(K, K.T)


def test_one_rigid_body_motion(result):
    # gear 2 has no torsional support in Eq. 7 (paper 000's Table 3 has one 0 Hz mode):
    # the only free motion turns gears 2, 1+3 and 4 together through both meshes
    assert int(result.data["rigid"].sum()) == 1
    phi = result.shapes[:, 0]
    names = result.dof_names
    moving = {n for n, v in zip(names, phi, strict=True) if abs(v) > 1e-9 * np.abs(phi).max()}
    assert moving == {"g2.rz", "g13.rz", "g4.rz"}


def test_support_only_modes_explain_why_table_3_is_not_reproducible(design, result):
    # With equal supports in x, y and z, each external gear translates perpendicular to
    # its (single) mesh normal without straining the mesh: a pure support mode at
    # sqrt(k/m), a double root, whatever the nutation geometry and mesh stiffness.
    m2, m4 = design.gear2.mass, design.gear4.mass
    f2 = math.sqrt(design.support2.k_x / m2) / (2 * math.pi)
    f4 = math.sqrt(design.support4.k_x / m4) / (2 * math.pi)
    f = result.frequencies
    for target in (f2, f4):
        assert np.sum(np.abs(f - target) < 1e-6 * target) == 2
    # independent of mesh stiffness and of the tooth geometry (helix, pressure angle)
    for change in ({"mesh1": {"stiffness": 5e9}}, {"helix_angle": 0.1},
                   {"normal_pressure_angle": 0.5}):  # fmt: skip
        data = design.model_dump()
        for k, v in change.items():
            if isinstance(v, dict):
                data[k].update(v)
            else:
                data[k] = v
        g = modal(build_model(design_from_dict(data))).frequencies
        for target in (f2, f4):
            assert np.sum(np.abs(g - target) < 1e-6 * target) == 2
    # Table 3 has none of these values: its nearest entry, 6600 Hz, is 18 % above
    # 5611 Hz and 41 % above 4697 Hz
    for target in (f2, f4):
        assert np.min(np.abs(TABLE3_HZ - target)) / target > 0.15


def test_pinned_computed_table(result):
    # regression pin of our table (pinned to 1e-4 Hz: rtol 1e-7 covers the rounding)
    np.testing.assert_allclose(result.frequencies, OURS_HZ, rtol=1e-7, atol=1e-6)


def test_fig_5_and_6_trends(tmp_path):
    spec = importlib.util.spec_from_file_location("p000", example_dir() / "paper_000_figures.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    res = mod.run(tmp_path)
    f5 = res["fig5_mesh_stiffness"].data["frequency"].values
    f6 = res["fig6_nutating_support_stiffness"].data["frequency"].values
    with np.errstate(invalid="ignore", divide="ignore"):  # mode 1 is 0 Hz
        rise5 = f5[-1] / f5[0] - 1
        rise6 = f6[-1] / f6[0] - 1
    # Fig. 5: the mesh stiffness mainly moves the highest orders (11, 12 here: +47..49 %);
    # orders 2-10 move by < 7 % (the paper: 10-12 strongly, 5 and 7 slightly)
    assert np.all(rise5[10:] > 0.4) and np.all(rise5[1:10] < 0.07)
    # Fig. 6: the nutating supports leave the highest orders unchanged (< 0.5 %), as the
    # paper says; here they lift orders 2-4 (support modes of the nutating body) and 6
    # most, where the paper names the 6th and 7th (its Table 3 orders differ from ours)
    assert np.all(rise6[10:] < 0.005)
    assert np.all(rise6[1:4] > 0.35)
    assert all((tmp_path / f"{n}.png").exists() for n in res)


def test_single_sided_torsional_closed_form():
    # single-sided drive with rigid supports: the one elastic torsional mode has
    # omega^2 = k (a_ny^2 r_n^2 / J_13 + a_cy^2 r_c^2 / J_2), a_y = cos(beta) cos(alpha_n)
    data = {
        "type": "nutation", "sides": "single", "input_speed": "1500 rpm", "module": "2 mm",
        "helix_angle": "25 deg", "normal_pressure_angle": "24 deg", "nutation_angle": "5 deg",
        "nutating_bearings": 1,
        "gear1": {"teeth": 28, "mass": "642 g", "J_x": "541970 g*mm^2",
                  "J_y": "542353 g*mm^2", "J_z": "986900 g*mm^2", "mean_radius": "39.5024 mm"},
        "gear2": {"teeth": 26, "mass": "177 g", "J_x": "67684 g*mm^2",
                  "J_y": "67684 g*mm^2", "J_z": "133241 g*mm^2", "mean_radius": "36.6806 mm"},
        "support2": {"k_x": 1e16, "k_y": 1e16, "k_z": 1e16},
        "support13": {"k_x": 1e16, "k_y": 1e16, "k_z": 1e16},
        "mesh1": {"stiffness": "2.1168e8 N/m"},
    }  # fmt: skip
    d = design_from_dict(data)
    res = modal(build_model(d), rigid_tol=1e-16)
    ay = math.cos(math.radians(25)) * math.cos(math.radians(24))
    w2 = 2.1168e8 * ay**2 * (39.5024e-3**2 / 986900e-9 + 36.6806e-3**2 / 133241e-9)
    # supports 1e16 vs mesh 2e8: the translations perturb the torsional mode by ~1e-8
    assert res.frequencies[1] == pytest.approx(math.sqrt(w2) / (2 * math.pi), rel=1e-6)
    assert res.frequencies[0] == 0.0


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"gear3": {"mean_radius": "45 mm"}}, "mean cone distances r_m / sin(delta) disagree"),
        ({"gear1": {"teeth": 25}}, "needs more teeth than its mate"),
        ({"sides": "single"}, "a single-sided drive has no"),
        ({"mesh2": None}, "a double-sided drive needs ['mesh2']"),
        ({"helix_angle": "70 deg"}, "out of range"),
        ({"mesh1": {"stiffness": "-1 N/m"}}, "must be greater than 0"),
    ],
)
def test_bad_designs(design, change, message):
    data = design.model_dump()
    for k, v in change.items():
        if isinstance(v, dict):
            data[k].update(v)
        elif v is None:
            data.pop(k)
        else:
            data[k] = v
    with pytest.raises(DesignError) as exc:
        design_from_dict(data, "n.toml")
    assert message in str(exc.value)


def test_resonance_verdict_cli():
    r = CliRunner().invoke(app, ["check", str(EXAMPLE)])
    # our frequencies meet 3x the mesh frequencies inside 1000-2000 rpm: exit 1
    assert r.exit_code == 1 and "RESONANCE RISK" in r.output
    assert "mesh 1 (gears 1-2)" in r.output
