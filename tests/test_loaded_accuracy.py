"""Transmission accuracy under load (issue 31): ``transmission_accuracy(design, load=...)``
and ``analysis.loaded_accuracy``.

Oracles:

* identity through the kinematics: with zero manufacturing errors and half-space teeth
  at a load, the output angle error at the output angles where the mesh phase meets the
  contact's positions is ``-(TE_j - mean TE) / r_bB`` of an independent ``te_sweep``
  run of the same pair and torque, to round-off; the gear pair's line at output order
  ``z_gear = 60`` and the KHV's at ``z_K |i| = 33 x 10 = 330`` (input order 33, the ring
  turning ``|i|`` times per output turn in the carrier frame) carry the contact's mesh
  harmonics ``2 |X_r| / N`` divided by ``r_bB`` times the closed-form response of the
  periodic linear interpolation upsampled ``M`` times,
  ``(sin(pi r / N) / (M sin(pi r / (N M))))^2`` (the DFT of a circular convolution
  with the triangle of half-width ``M``), and no order but the multiples of the
  tooth-mesh order carries anything;
* the mean wind-up is the ``te_sweep`` mean over ``r_bB``;
* first-order superposition: loaded with an eccentricity equals the unloaded error of
  the eccentricity plus the loaded variation of the perfect teeth, sample by sample.

The magnitude of the loaded TE itself is ``te_sweep``'s, checked against ISO
6336-1:2019 clause 9's single and mesh stiffness ``c'`` and ``c_gamma_alpha`` in
``tests/test_te_sweep.py`` and ``tests/published/test_iso6336_ltca.py`` (finite-element
teeth); here the teeth are rigid beyond the contact half-space and the positions few,
to keep the file fast (the mapping does not depend on the teeth's model).
"""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis import te_sweep as te_module
from reducerlab.analysis.loaded_accuracy import (
    cycle_to_output,
    mesh_cycles,
    mesh_te,
    mesh_torque,
    output_load,
)
from reducerlab.analysis.te_sweep import mesh_harmonics, te_sweep
from reducerlab.analysis.transmission_accuracy import (
    ARCSEC,
    TransmissionAccuracyResult,
    transmission_accuracy,
)
from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.results import Result

GEAR = example_dir() / "gear_pair.toml"
KHV = example_dir() / "khv.toml"
#: positions over one mesh cycle: the least odd number carrying mesh orders 1..3
N = 7
#: output samples per contact position of the gear pair (the KHV's default: 2)
M_GEAR = 10


def response(r: np.ndarray, m: int) -> np.ndarray:
    """Amplitude response at mesh harmonic ``r`` of the periodic linear interpolation of
    ``N`` samples a cycle, ``m`` output samples a position step."""
    return (np.sin(np.pi * r / N) / (m * np.sin(np.pi * r / (N * m)))) ** 2


@pytest.fixture(scope="module")
def gear():
    """Gear pair at 144 N m on the output (60 N m on the pinion): the result and an
    independent te_sweep of the same pair and torque."""
    d = load_design(GEAR)
    res = transmission_accuracy(d, samples=60 * N * M_GEAR, load="144 N*m", rigid=True,
                                positions=N)  # fmt: skip
    sweep = te_sweep(d, torques=[60.0], torque=60.0, positions=N, harmonics=3,
                     compliance=(None, None))  # fmt: skip
    return d, res, sweep


@pytest.fixture(scope="module")
def khv():
    """KHV at its design load (50 N m output torque = the planet's torque)."""
    d = load_design(KHV)
    res = transmission_accuracy(d, load="design", rigid=True, positions=N)
    sweep = te_sweep(d, torques=[50.0], torque=50.0, positions=N, harmonics=3,
                     compliance=(None, None))  # fmt: skip
    return d, res, sweep


def _at_positions(res: TransmissionAccuracyResult, cycles: int) -> np.ndarray:
    """The error (rad) at the output angles where the mesh phase is at the contact's
    positions: ``samples / (cycles N)`` samples per position step."""
    step = res.data.sizes["output_angle"] // (cycles * N)
    return np.asarray(res.data["error"].values, float)[::step].reshape(cycles, N)


def test_mesh_cycles_per_output_turn():
    # gear pair: the gear is the output, z_gear = 60 cycles; KHV: z_K |i| = 33 * 10
    assert mesh_cycles(load_design(GEAR)) == 60
    assert mesh_cycles(load_design(KHV)) == 330


def test_gear_pair_identity_through_the_kinematics(gear):
    d, res, sweep = gear
    te = sweep.data["te"].values[0]
    rb = d.base_radius("gear")
    expected = -(te - te.mean()) / rb  # output sense: the gear lags by TE / r_bg
    got = _at_positions(res, 60)
    # trigonometric interpolation through the N samples: exact at them to round-off
    np.testing.assert_allclose(got, np.broadcast_to(expected, got.shape),
                               rtol=0, atol=1e-12 * np.abs(expected).max())  # fmt: skip
    assert res.data.attrs["wind_up_arcsec"] == pytest.approx(te.mean() / rb / ARCSEC, rel=1e-12)
    assert res.data.attrs["mesh_torque_N_m"] == pytest.approx(60.0, rel=1e-12)
    # every position is a sample and the trace is linear between them
    assert res.peak_to_peak == pytest.approx(np.ptp(te) / rb / ARCSEC, rel=1e-12)
    np.testing.assert_allclose(res.data["mesh_te"].values, te, rtol=1e-12)


def test_gear_pair_spectrum_at_the_tooth_mesh_orders(gear):
    d, res, sweep = gear
    rb = d.base_radius("gear")
    r = np.arange(1, 4)
    harm = mesh_harmonics(sweep.data["te"].values[0], 3) / rb / ARCSEC * response(r, M_GEAR)
    amp = res.data["amplitude"].values
    np.testing.assert_allclose(amp[60 * r], harm, rtol=1e-9)
    on = np.arange(amp.size) % 60 == 0
    assert amp[~on].max() < 1e-9 * harm.max()  # only tooth-mesh orders: round-off
    assert [k for k, _ in res.largest_orders(3)] == [60, 120, 180]


def test_khv_order_mapping_and_wind_up(khv):
    d, res, sweep = khv
    te = sweep.data["te"].values[0]
    rb = d.gears.pair().base_radius(1)  # the planet's: B of the rigid term
    got = _at_positions(res, 330)
    expected = -(te - te.mean()) / rb
    np.testing.assert_allclose(got, np.broadcast_to(expected, got.shape),
                               rtol=0, atol=1e-12 * np.abs(expected).max())  # fmt: skip
    # default samples: the least multiple of 330 x 7 from 4096, M = 2 a position step
    assert res.data.sizes["output_angle"] == 330 * N * 2
    r = np.arange(1, 4)
    harm = mesh_harmonics(te, 3) / rb / ARCSEC * response(r, 2)
    amp = res.data["amplitude"].values
    np.testing.assert_allclose(amp[330 * r], harm, rtol=1e-9)
    assert amp[np.arange(amp.size) % 330 != 0].max() < 1e-9 * harm.max()
    # input order of the tooth-mesh line: z_K = 33
    assert float(res.data["input_order"].sel(order=330)) == pytest.approx(33.0, rel=1e-12)
    assert res.data.attrs["wind_up_arcsec"] == pytest.approx(te.mean() / rb / ARCSEC, rel=1e-12)
    assert res.data.attrs["wind_up_arcsec"] > 0  # the load makes the output lag
    assert res.data.attrs["load_N_m"] == pytest.approx(50.0)  # load_torque of khv.toml


def test_superposition_with_an_eccentricity(gear):
    _, res0, sweep = gear
    d = load_design(GEAR, ["gear.errors.eccentricity=5 um"])
    n = res0.data.sizes["output_angle"]
    rigid = transmission_accuracy(d, samples=n)
    both = transmission_accuracy(d, samples=n, load="144 N*m", mesh_te=sweep)
    loaded = res0.data["contribution"].sel(source="mesh under load").values
    np.testing.assert_allclose(both.data["error"].values, rigid.data["error"].values + loaded,
                               rtol=0, atol=1e-15)  # fmt: skip
    # the eccentricity's once-per-turn line e / r_bg is still there
    assert both.data["amplitude"].values[1] == pytest.approx(
        5e-6 / d.base_radius("gear") / ARCSEC, rel=1e-6
    )
    assert both.data.attrs["contact_reused"] == 1  # the given contact, not recomputed
    assert both.data.attrs["contact_seconds"] == sweep.data.attrs["seconds"]


def test_cycle_to_output_is_linear_between_positions():
    te = np.array([0.0, 4.0, 1.0, 3.0])  # mean 2
    u = 2 * np.pi * np.array([0.0, 1 / 16, 1 / 8, 7 / 16, 1 / 2 + 1 / 8 + 1 / 16])
    # 2 cycles a turn: phase 2u/(2 pi) of a cycle, 4 positions a cycle
    out = cycle_to_output(te, 2, u)
    np.testing.assert_allclose(out, [0.0 - 2, 2.0 - 2, 4.0 - 2, 1.5 - 2, 2.5 - 2], atol=1e-14)
    # never outside the positions' range, whatever the phase
    many = cycle_to_output(te, 7, 2 * np.pi * np.linspace(0, 1, 1001))
    assert many.min() >= -2 - 1e-14 and many.max() <= 2 + 1e-14


def test_result_round_trip_table_and_figure(khv, tmp_path):
    _, res, _ = khv
    res.save(tmp_path / "a.nc")
    back = Result.load(tmp_path / "a.nc")
    assert isinstance(back, TransmissionAccuracyResult)
    assert back.data.attrs["wind_up_arcsec"] == pytest.approx(res.data.attrs["wind_up_arcsec"])
    text = back.table()
    assert "load: 50 N m" in text and "wind-up" in text and "330" in text
    assert "mesh under load" in back.to_dict()["contribution_peak_to_peak_arcsec"]
    fig = back.figure()
    assert len(fig.axes) == 3


def test_load_conversions():
    d = load_design(GEAR)
    assert output_load(d, "design") == pytest.approx(144.0)  # 60 N m on the pinion, i 2.4
    assert output_load(d, 30) == 30.0
    assert mesh_torque(d, 144.0) == pytest.approx(60.0)
    assert mesh_torque(load_design(KHV), 50.0) == 50.0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"load": "abc"}, "load"),
        ({"load": -5.0}, "load"),
        ({"load": 0.0}, "load: must be a torque > 0"),
        ({"load": True}, "load"),
        ({"load": 60.0, "samples": 64}, "samples: .* more than 120"),
        ({"rigid": True}, "rigid, tooth_size, mesh_te: apply under load only"),
        ({"tooth_size": 1e-3}, "apply under load only"),
        ({"load": 60.0, "rigid": "yes"}, "rigid: must be true or false"),
        ({"load": 60.0, "positions": 2}, "positions: must be an integer in 3..400"),
    ],
)
def test_bad_input_is_named(kwargs, match):
    with pytest.raises(ReducerlabError, match=match):
        transmission_accuracy(load_design(GEAR), **kwargs)


def test_design_load_missing_and_wrong_cached_torque(gear):
    d = load_design(GEAR, ["operating.torque=0 N*m"])
    with pytest.raises(ReducerlabError, match=r"load: .design.*no load"):
        transmission_accuracy(d, load="design")
    with pytest.raises(ReducerlabError, match="mesh_te: must be the loaded TE at the one torque"):
        transmission_accuracy(load_design(GEAR), load="100 N*m", mesh_te=gear[2])


def test_work_is_checked_before_the_contact(monkeypatch):
    from reducerlab.errors import BudgetError

    def never(*_a, **_k):
        raise AssertionError("the contact ran before its estimate was refused")

    monkeypatch.setattr(te_module, "te_sweep", never)
    monkeypatch.setenv("REDUCERLAB_MEMORY_LIMIT", "1M")
    with pytest.raises(BudgetError, match="tooth compliance"):
        mesh_te(load_design(GEAR), 60.0, positions=N)


def test_cli_load_rigid_and_cache(tmp_path, monkeypatch):
    args = ["accuracy", str(GEAR), "--load", "144 N*m", "--rigid", "--positions", "3",
            "--samples", "1024", "--cache", str(tmp_path / "cache")]  # fmt: skip
    r = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "a")])
    assert r.exit_code == 0, r.output
    assert "wind-up" in r.output
    first = Result.load(tmp_path / "a" / "accuracy.nc")
    assert first.data.attrs["load_N_m"] == pytest.approx(144.0)

    def never(*_a, **_k):
        raise AssertionError("the cached contact was recomputed")

    monkeypatch.setattr(te_module, "te_sweep", never)
    r = CliRunner().invoke(app, [*args, "-o", str(tmp_path / "b")])
    assert r.exit_code == 0, r.output
    again = Result.load(tmp_path / "b" / "accuracy.nc")
    np.testing.assert_array_equal(again.data["error"].values, first.data["error"].values)
    bad = CliRunner().invoke(app, ["accuracy", str(GEAR), "--rigid", "-o", str(tmp_path / "c")])
    assert bad.exit_code != 0 and "--load only" in bad.output
    bad = CliRunner().invoke(app, ["accuracy", str(GEAR), "--load", "x", "-o", str(tmp_path / "c")])
    assert bad.exit_code != 0 and "--load" in bad.output
