"""Transmission accuracy of the nutation drive under load (issue 31):
``transmission_accuracy(design, load=...)`` of a nutation design and
``analysis.loaded_accuracy_nutation``.

Oracles:

* the sign of each mesh's TE against the drive model (``drives.nutation.build_model``):
  its static mesh forces under the model's own output load and reaction (the rotation
  DOFs carry no support, so ``L_d = k lambda g_d`` on them) give the sign of the model's
  mesh deflection ``lambda_j``; the model's output rotation that ``lambda_j`` makes
  (its mesh constraints closed for the rotations, as in
  ``tests/test_transmission_accuracy_drives.py``) must lag the output (against its
  turning sense ``sgn(i)``) and equal the mapping of the TE ``|lambda_j| / a_y``;
* identity through the two-stage law: with zero manufacturing errors and half-space
  teeth at the design load, the output error at the output angles where mesh ``j``'s
  phase meets the contact's positions is the law applied here to an independent
  ``te_sweep`` of pair ``j`` at ``analysis.te_sweep.design_load`` (gear B's equivalent
  rotation ``epsilon_B = -s_j TE / r_mB``, ``s_j`` the model's sign,
  ``d theta_4 = (r_m3 / r_m4)(-epsilon_1)`` or ``(r_m3 / r_m4) epsilon_3``, single-sided
  ``d theta_13 = -epsilon_1``, the output's error ``sgn(i)`` times it);
* the spectrum: mesh ``j``'s line at output order ``n_j`` (364; 2730 and 3120) carries
  the contact's first mesh harmonic through the law times the linear interpolation's
  response, and only the multiples of the ``n_j`` carry anything;
* first-order superposition with gear eccentricities, sample by sample.

The teeth are rigid beyond the contact half-space, 5 positions and a 0.3 mm contact
cell keep the file fast (the mapping does not depend on the teeth's model).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis import te_sweep as te_module
from reducerlab.analysis.loaded_accuracy_nutation import (
    mesh_gains,
    mesh_orders,
    nutation_loaded_error,
    pair_torques,
)
from reducerlab.analysis.te_sweep import design_load, mesh_harmonics, te_sweep
from reducerlab.analysis.transmission_accuracy import ARCSEC, transmission_accuracy
from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.results import Result

SINGLE = example_dir() / "nutation_surface.toml"
DOUBLE = example_dir() / "nutation_double_sided.toml"
#: positions over one mesh cycle; contact cell (m)
N = 5
CELL = 3e-4


def _sweeps(d):
    """Each pair's loaded TE at the design load (``design_load``), half-space teeth."""
    out = []
    for j in range(1, d.gear_count // 2 + 1):
        t = design_load(d, j)
        out.append(te_sweep(d, j, torques=[t], torque=t, positions=N, harmonics=2,
                            compliance=(None, None), cell=CELL))  # fmt: skip
    return out


@pytest.fixture(scope="module")
def double():
    d = load_design(DOUBLE)
    sweeps = _sweeps(d)
    return d, sweeps, transmission_accuracy(d, load="design", mesh_te=sweeps)


@pytest.fixture(scope="module")
def single():
    d = load_design(SINGLE)
    sweeps = _sweeps(d)
    return d, sweeps, transmission_accuracy(d, load="design", mesh_te=sweeps)


def _model_signs(d):
    """The model's mesh deflection signs ``s_j`` under its load, its output rotation per
    unit ``lambda_j`` (model's rz sense) and ``a_y``."""
    from reducerlab.drives import build_model
    from reducerlab.model import Load, Mesh

    model = build_model(d)
    g = {e.name: e.coefficients for e in model.elements if isinstance(e, Mesh)}
    load = {e.dof: e.value.mean for e in model.elements if isinstance(e, Load)}
    # statics of the rotations: L_d = k_j lambda_j g_j,d (k_j > 0)
    if d.sides == "double":
        lam = [load["g2.rz"] / g["mesh1"]["g2.rz"], load["g4.rz"] / g["mesh2"]["g4.rz"]]
        # the model's closure: g13 d13 = lambda_1; g13 d13 + g4 d4 = lambda_2
        per = [-g["mesh2"]["g13.rz"] / g["mesh1"]["g13.rz"] / g["mesh2"]["g4.rz"],
               1.0 / g["mesh2"]["g4.rz"]]  # fmt: skip
    else:
        lam = [load["g13.rz"] / g["mesh1"]["g13.rz"]]
        per = [1.0 / g["mesh1"]["g13.rz"]]
    a_y = math.cos(d.helix_angle) * math.cos(d.normal_pressure_angle)
    return [int(math.copysign(1, v)) for v in lam], per, a_y


@pytest.mark.parametrize("path", [SINGLE, DOUBLE])
def test_te_sign_against_the_drive_models_statics(path):
    d = load_design(path)
    signs, per, a_y = _model_signs(d)
    sense = math.copysign(1.0, d.kinematics().ratio)
    for gain, s, p in zip(mesh_gains(d), signs, per, strict=True):
        assert gain.flank == s
        lam = s * 1e-6  # a compression of 1 um on the loaded flank
        model_out = sense * p * lam
        assert model_out < 0  # the output lags under the load
        te = abs(lam) / a_y  # the contact's TE of that compression (at r_mB)
        assert gain.output_error(np.array([te]), sense)[0] == pytest.approx(model_out, rel=1e-9)


def _law(d, j, te, signs):
    """Output error (rad, output sense) of pair ``j``'s TE ``te`` (m at r_mB) by the
    law's formula, radii from the design."""
    r = [getattr(d, f"gear{k}").mean_radius for k in range(1, 2 * (d.gear_count // 2) + 1)]
    sense = math.copysign(1.0, d.kinematics().ratio)
    eps = -signs[j - 1] * te / r[2 * j - 2]  # gear B: 1 or 3
    if d.sides == "single":
        return sense * (-eps)
    return sense * r[2] / r[3] * (-eps if j == 1 else eps)


def _at_positions(res, source, order):
    """The contribution of ``source`` (rad) where the mesh phase meets the positions."""
    step = res.data.sizes["output_angle"] // (order * N)
    assert step * order * N == res.data.sizes["output_angle"]
    c = res.data["contribution"].sel(source=source).values
    return np.asarray(c, float)[::step].reshape(order, N)


@pytest.mark.parametrize("which", ["single", "double"])
def test_identity_through_the_two_stages(which, request):
    d, sweeps, res = request.getfixturevalue(which)
    signs = _model_signs(d)[0]
    orders = mesh_orders(d)
    assert orders == ([364] if which == "single" else [2730, 3120])
    total = 0.0
    for j, (s, n) in enumerate(zip(sweeps, orders, strict=True), start=1):
        te = s.data["te"].values[0]
        want = _law(d, j, te - te.mean(), signs)
        got = _at_positions(res, f"mesh {j} under load", n)
        np.testing.assert_allclose(got, np.broadcast_to(want, got.shape), rtol=0, atol=1e-15)
        assert np.ptp(want) > 0.1 * ARCSEC  # a real variation
        wind = -_law(d, j, te.mean(), signs)
        assert wind > 0  # the output lags
        assert res.data.attrs[f"mesh{j}_wind_up_arcsec"] == pytest.approx(wind / ARCSEC, rel=1e-12)
        total += wind
    assert res.data.attrs["wind_up_arcsec"] == pytest.approx(total / ARCSEC, rel=1e-12)
    # no manufacturing errors: the error is the loaded variations alone
    total_trace = res.data["contribution"].sum("source").values
    np.testing.assert_allclose(res.data["error"].values, total_trace, rtol=0, atol=1e-18)
    names = [f"mesh {j} under load" for j in range(1, len(orders) + 1)]
    assert list(res.data["source"].values) == names


def test_torques_on_gear_a_follow_the_torque_flow():
    for path, t_out in ((SINGLE, 60.0), (DOUBLE, 120.0)):
        d = load_design(path)
        got = pair_torques(d, t_out)
        assert got == pytest.approx([design_load(d, j) for j in range(1, len(got) + 1)])
        assert pair_torques(d, 2 * t_out) == pytest.approx([2 * t for t in got])
    d = load_design(DOUBLE)  # T_out (1 - 1/i) on the fixed gear 2, T_out on gear 4
    assert pair_torques(d, 120.0) == pytest.approx([120.0 * (1 - 1 / 105), 120.0])


def test_spectrum_lines_at_each_mesh_order(double):
    d, sweeps, res = double
    samples = res.data.sizes["output_angle"]
    signs = _model_signs(d)[0]
    amp = np.asarray(res.data["amplitude"].values, float)
    orders = mesh_orders(d)
    for j, (s, n) in enumerate(zip(sweeps, orders, strict=True), start=1):
        m = samples // (n * N)
        h1 = mesh_harmonics(s.data["te"].values[0], 1)[0]
        response = (np.sin(np.pi / N) / (m * np.sin(np.pi / (N * m)))) ** 2
        want = abs(_law(d, j, h1, signs)) * response / ARCSEC
        assert amp[n] == pytest.approx(want, rel=1e-6)
    # nothing between the multiples of the mesh orders
    k = np.arange(amp.size)
    other = (k % orders[0] != 0) & (k % orders[1] != 0)
    assert amp[other].max() < 1e-9 * amp.max()
    assert {o for o, _ in res.largest_orders(2)} == set(orders)


def test_superposition_with_eccentricities(double):
    d, sweeps, loaded = double
    errs = {"gear1.errors": {"eccentricity": 4e-6, "eccentricity_phase": 0.4},
            "gear4.errors": {"eccentricity": 6e-6, "eccentricity_phase": 1.1}}  # fmt: skip
    e = d.with_values(errs)
    samples = loaded.data.sizes["output_angle"]
    both = transmission_accuracy(e, load="design", mesh_te=sweeps)
    rigid = transmission_accuracy(e, samples=samples)
    assert both.data.sizes["output_angle"] == samples
    np.testing.assert_allclose(both.data["error"].values,
                               rigid.data["error"].values + loaded.data["error"].values,
                               rtol=0, atol=1e-15)  # fmt: skip
    assert both.peak_to_peak > rigid.peak_to_peak


def test_computed_contact_equals_the_given_one(single):
    """The module's own contact runs (pair torques, te_sweep per pair) give the result of
    the independent sweeps given as a cache."""
    d, sweeps, res = single
    u = res.data["output_angle"].values
    own = nutation_loaded_error(d, "design", u, positions=N, rigid=True, cell=CELL)
    assert not own.reused and own.rigid
    np.testing.assert_allclose(own.variations[0],
                               res.data["contribution"].sel(source="mesh 1 under load").values,
                               rtol=0, atol=1e-15)  # fmt: skip
    # a mapping by pair number, and a lone result for the single-sided drive
    again = transmission_accuracy(d, load="60 N*m", mesh_te={1: sweeps[0]})
    np.testing.assert_array_equal(again.data["error"].values, res.data["error"].values)
    lone = transmission_accuracy(d, load=60.0, mesh_te=sweeps[0])
    np.testing.assert_array_equal(lone.data["error"].values, res.data["error"].values)
    assert res.data.attrs["contact_reused"] == 1
    assert "mean wind-up of the meshes" in res.table()


def test_round_trip(double, tmp_path):
    _, _, res = double
    res.save(tmp_path / "a.nc")
    back = Result.load(tmp_path / "a.nc")
    assert back.to_dict()["mesh2_order"] == 3120
    assert "tooth-mesh orders 2730, 3120" in back.table()
    fig = back.figure()  # the third panel: three cycles of order 2730, both meshes
    labels = [t.get_text() for t in fig.axes[2].get_legend().get_texts()]
    assert labels == ["mesh 1 under load", "mesh 2 under load", "total"]
    assert "order 2730" in fig.axes[2].get_title()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"samples": 4096}, "samples: the loaded TE repeats 3120 times"),
        ({"positions": 2}, "positions: must be an integer in 3..400"),
        ({"rigid": "yes"}, "rigid: must be true or false"),
        ({"load": "-5 N*m"}, "load: must be a torque > 0"),
        ({"mesh_te": "one"}, "mesh_te"),
    ],
)
def test_bad_input_is_named(double, kwargs, match):
    d, sweeps, _ = double
    kw = {"load": "design", "mesh_te": sweeps, **kwargs}
    with pytest.raises(ReducerlabError, match=match):
        transmission_accuracy(d, **kw)


def test_bad_sweeps_are_named(double, single, no_surface_design):
    d, sweeps, _ = double
    with pytest.raises(ReducerlabError, match=r"mesh_te: one loaded TE .* 2 for a double"):
        transmission_accuracy(d, load="design", mesh_te=sweeps[:1])
    with pytest.raises(ReducerlabError, match=r"mesh_te\[1\]: must be pair 1's"):
        transmission_accuracy(d, load="design", mesh_te=sweeps[::-1])
    with pytest.raises(ReducerlabError, match=r"mesh_te\[1\]: must be the loaded TE at the one"):
        transmission_accuracy(d, load="100 N*m", mesh_te=sweeps)
    with pytest.raises(ReducerlabError, match=r"mesh_te: a mapping must have the pairs 1\.\.2"):
        transmission_accuracy(d, load="design", mesh_te={1: sweeps[0]})
    # the single-sided drive's pair 1 (same teeth 26/28, another load) as pair 1
    with pytest.raises(ReducerlabError, match=r"mesh_te\[1\]: must be the loaded TE at the one"):
        transmission_accuracy(d, load="design", mesh_te=[single[1][0], sweeps[1]])
    with pytest.raises(ReducerlabError, match=r"mesh_te\[2\]: must be pair 2's"):
        transmission_accuracy(d, load="design", mesh_te=[sweeps[0], single[1][0]])
    plain = load_design(no_surface_design)
    with pytest.raises(ReducerlabError, match="surface: the design has no"):
        transmission_accuracy(plain, load="10 N*m", rigid=True, positions=N)
    ball = load_design(example_dir() / "cycloid_ball.toml")  # its load path has no contact
    with pytest.raises(ReducerlabError, match=r"rigid"):
        transmission_accuracy(ball, load="10 N*m", rigid=True)


def test_work_is_checked_before_the_contact(monkeypatch):
    from reducerlab.errors import BudgetError

    def never(*_a, **_k):
        raise AssertionError("the contact ran before its estimate was refused")

    monkeypatch.setattr(te_module, "te_sweep", never)
    monkeypatch.setenv("REDUCERLAB_MEMORY_LIMIT", "1M")
    with pytest.raises(BudgetError, match="tooth compliance"):
        transmission_accuracy(load_design(SINGLE), load="design", positions=N)


def test_every_pair_is_checked_before_the_first_contact(monkeypatch):
    """Pair 2's tooth models over the memory: refused before pair 1's contact runs."""
    from reducerlab.analysis import contact_setup
    from reducerlab.budget import Estimate
    from reducerlab.errors import BudgetError

    own = contact_setup.PairSetup.compliance_estimate

    def estimate(self, *a, **k):
        if self.gears == ("gear4", "gear3"):
            return Estimate("tooth compliance of pair 2 (test)", 1e18, control="--tooth-size")
        return own(self, *a, **k)

    def never(*_a, **_k):
        raise AssertionError("pair 1's contact ran before pair 2's estimate was refused")

    monkeypatch.setattr(contact_setup.PairSetup, "compliance_estimate", estimate)
    monkeypatch.setattr(te_module, "te_sweep", never)
    with pytest.raises(BudgetError, match="pair 2"):
        transmission_accuracy(load_design(DOUBLE), load="design", positions=N)


def test_cli_load_rigid_and_cache(tmp_path, monkeypatch, single):
    _, sweeps, res = single
    args = ["accuracy", str(SINGLE), "--load", "design", "--rigid", "--positions", str(N),
            "--cache", str(tmp_path / "cache")]  # fmt: skip
    # fill the cache with the fixture's sweep (its 0.3 mm cell) through te_sweep itself
    monkeypatch.setattr(te_module, "te_sweep", lambda *_a, **_k: sweeps[0])
    r = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "a")])
    assert r.exit_code == 0, r.output
    assert "wind-up of the meshes" in r.output
    first = Result.load(tmp_path / "a" / "accuracy.nc")
    np.testing.assert_array_equal(first.data["error"].values, res.data["error"].values)

    def never(*_a, **_k):
        raise AssertionError("the cached contact was recomputed")

    monkeypatch.setattr(te_module, "te_sweep", never)
    r = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "b")])
    assert r.exit_code == 0, r.output
    again = Result.load(tmp_path / "b" / "accuracy.nc")
    assert again.data.attrs["contact_reused"] == 1
    np.testing.assert_array_equal(again.data["error"].values, first.data["error"].values)
