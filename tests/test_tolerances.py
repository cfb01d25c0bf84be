"""Monte-Carlo over tolerances (issue 31): distributions of lost motion and transmission
error from toleranced design fields.

Oracles: the rigid transmission error of a gear pair whose gear alone is eccentric is a
once-per-revolution sine, peak to peak ``2 e / r_bg`` (the closed form of
``tests/test_transmission_accuracy.py``), so with ``e ~ U(0, e_max)`` every sample's TE
equals ``2 e / r_bg`` and the TE is uniform on ``[0, 2 e_max / r_bg]``: mean
``e_max / r_bg``, 95th percentile ``0.95 * 2 e_max / r_bg``. A mesh linear beyond its
backlash ``b`` gives, with the input held, the twist ``sgn(T) b / (2 r) + T / K``
(``tests/test_torsion_test.py``): backlash ``b / r`` and lost motion at +/-3 % of rated
``b / r + 0.06 T_r / K``, ``K`` the output stiffness (static condensation of
``K + G^T k G``, written here apart from the solver).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.tolerance_specs import (
    Distribution,
    parse_distribution,
    read_tolerance_file,
)
from reducerlab.analysis.tolerances import ARCSEC, TolerancesResult, tolerances
from reducerlab.cli import app
from reducerlab.drives import build_model, load_design
from reducerlab.errors import BudgetError, ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.model import Mesh
from reducerlab.results import Result

GEAR = example_dir() / "gear_pair.toml"
KHV = example_dir() / "khv.toml"
UM = 1e-6


@pytest.fixture(scope="module")
def gear_pair():
    return load_design(GEAR)


@pytest.fixture(scope="module")
def eccentric(gear_pair):
    """200 samples of the gear pair with the gear's eccentricity U(0, 10 um)."""
    return tolerances(gear_pair, {"gear.errors.eccentricity": "0..10 um"}, samples=200,
                      seed=7, steps=3, te_samples=1024)  # fmt: skip


def test_eccentric_gear_te_is_the_closed_form_per_sample(gear_pair, eccentric):
    """TE p-p = 2 e / r_bg for every sample; the phase is drawn (uniform 0..360 deg)."""
    rb = gear_pair.base_radius("gear")
    fields = list(eccentric.data["field"].values)
    assert fields == ["gear.errors.eccentricity", "gear.errors.eccentricity_phase"]
    e = eccentric.data["value"].sel(field="gear.errors.eccentricity").values
    phase = eccentric.data["value"].sel(field="gear.errors.eccentricity_phase").values
    assert e.min() >= 0 and e.max() <= 10 * UM and np.ptp(e) > 9 * UM
    assert phase.min() >= 0 and phase.max() < 2 * math.pi and np.ptp(phase) > 6
    te = eccentric.values("te_peak_to_peak")
    # 1024 steps over the revolution: the sampled peak lies within half a step of the
    # sine's, p-p in [2 e cos(pi/1024) / r_bg, 2 e / r_bg] (relative 4.7e-6)
    np.testing.assert_allclose(te, 2 * e / rb, rtol=5e-6, atol=1e-12 * 2e-5 / rb)


def test_eccentric_gear_statistics_converge_to_the_uniform_law(gear_pair, eccentric):
    """The TE is U(0, 2 e_max / r_bg): mean e_max / r_bg, p95 0.95 * 2 e_max / r_bg,
    std (2 e_max / r_bg) / sqrt(12); checked within 4 standard errors of each estimate
    for n = 200 (the seed fixes the draw; 4 sigma would fail with probability 6e-5 for a
    random seed): the mean's s.e. sqrt(1/12/n) and the p95's sqrt(p(1-p)/n) of the
    range (the density of a uniform law is 1/range)."""
    width = 2 * 10 * UM / gear_pair.base_radius("gear")
    a, n = eccentric.data.attrs, 200
    assert a["te_peak_to_peak_mean"] == pytest.approx(width / 2, abs=4 * width / math.sqrt(12 * n))
    se95 = width * math.sqrt(0.95 * 0.05 / n)
    assert a["te_peak_to_peak_p95"] == pytest.approx(0.95 * width, abs=4 * se95)
    # std of a sample std of a uniform law: ~ width sqrt(1/180/n) (4th moment 1/80)
    se_std = width / math.sqrt(180 * n)
    assert a["te_peak_to_peak_std"] == pytest.approx(width / math.sqrt(12), abs=4 * se_std)
    te = eccentric.values("te_peak_to_peak")
    assert a["te_peak_to_peak_p95"] == np.percentile(te, 95)
    assert a["te_peak_to_peak_std"] == pytest.approx(np.std(te, ddof=1), rel=1e-12)
    assert a["te_peak_to_peak_sem"] == pytest.approx(np.std(te, ddof=1) / math.sqrt(n))
    # the eccentricity does not touch the torsion test: lost motion constant
    assert np.ptp(eccentric.values("lost_motion")) <= 1e-9 * eccentric.values("lost_motion")[0]


def _output_stiffness(design) -> float:
    """N m/rad at the gear with the pinion held: Schur complement of ``K + G^T k G``
    (the mesh's mean stiffness) on the gear's rotation."""
    model = build_model(design)
    s = model.nonlinear()
    names = list(s.dof_names)
    k = np.array([e.stiffness.mean for e in model.elements if isinstance(e, Mesh)])
    Kt = s.K + s.G.T @ (s.G * k[:, None])
    o, held = names.index("gear.rz"), names.index("pinion.rz")
    rest = [i for i in range(len(names)) if i not in (o, held)]
    return float(Kt[o, o] - Kt[o, rest] @ np.linalg.solve(Kt[np.ix_(rest, rest)], Kt[rest, o]))


def test_backlash_gives_the_closed_form_lost_motion(gear_pair):
    """b ~ U(60, 100) um: backlash b / r_bg and lost motion b / r_bg + 0.06 T_r / K per
    sample; compared at 1e-8 (the torsion test's closed forms hold to its Newton
    residual, 1e-10 of the load)."""
    res = tolerances(gear_pair, ["mesh.backlash=60..100 um"], samples=12, steps=3,
                     chunk_size=5, mu=0.0)  # fmt: skip  # frictionless closed form
    b = res.data["value"].sel(field="mesh.backlash").values
    assert b.min() >= 60 * UM and b.max() <= 100 * UM
    rb = gear_pair.base_radius("gear")
    Tr = res.data.attrs["rated_torque"]
    assert Tr == pytest.approx(gear_pair.operating_point().output_torque)
    K = _output_stiffness(gear_pair)
    np.testing.assert_allclose(res.values("backlash"), b / rb, rtol=1e-8)
    np.testing.assert_allclose(res.values("lost_motion"), b / rb + 0.06 * Tr / K, rtol=1e-8)
    # no eccentricity or pitch error: no transmission error
    assert np.all(res.values("te_peak_to_peak") == 0.0)


def test_same_seed_same_samples_and_fields_draw_independently(gear_pair):
    """Reproducible with the seed, whatever the chunking; another seed draws others;
    adding a field leaves the other fields' draws unchanged (one stream per path)."""
    tol = {"mesh.backlash": "80 +- 5 um"}
    a = tolerances(gear_pair, tol, samples=6, seed=3, steps=3, chunk_size=6)
    b = tolerances(gear_pair, tol, samples=6, seed=3, steps=3, chunk_size=4)
    c = tolerances(gear_pair, tol, samples=6, seed=4, steps=3)
    both = tolerances(gear_pair, {**tol, "gear.errors.eccentricity": "0..3 um"}, samples=6,
                      seed=3, steps=3, te_samples=64)  # fmt: skip
    for name in ("value", "lost_motion", "backlash", "te_peak_to_peak"):
        assert np.array_equal(a.data[name].values, b.data[name].values)
    assert not np.array_equal(a.data["value"].values, c.data["value"].values)
    assert np.array_equal(both.data["value"].sel(field="mesh.backlash").values,
                          a.data["value"].sel(field="mesh.backlash").values)  # fmt: skip


def test_pitch_deviations_per_tooth_close_and_have_the_closed_variance():
    """``"0 +- 2 um"`` on the ring's pitch list: one draw per tooth (33), each row
    closed (sum zero); the closing leaves variance sigma^2 (z - 1) / z per tooth: the
    pooled std of 33 x 40 draws within 5 % (its relative s.e. is 1/sqrt(2 N) = 2 %)."""
    d = load_design(KHV)
    res = tolerances(d, {"gears.ring_errors.pitch_deviations": "0 +- 2 um"}, samples=40,
                     steps=3, te_samples=256)  # fmt: skip
    f = res.data["pitch_deviation"].sel(pitch_field="gears.ring_errors.pitch_deviations").values
    z = d.gears.ring_teeth
    assert f.shape == (40, z)
    assert np.abs(f.sum(axis=1)).max() <= 1e-12 * np.abs(f).sum(axis=1).min()
    assert np.std(f) == pytest.approx(2 * UM * math.sqrt((z - 1) / z), rel=0.05)
    assert np.all(res.values("te_peak_to_peak") > 0)


def test_chunks_resume_after_an_interruption(gear_pair, tmp_path):
    """Chunks are written as they finish; a run stopped after its first chunk resumes
    from it and gives the same numbers as an uninterrupted run."""
    tol = {"mesh.backlash": "60..100 um"}
    kw = {"samples": 9, "seed": 1, "steps": 3, "chunk_size": 3}

    class Stop(Exception):
        pass

    def stop(done, total):
        if done >= 3:
            raise Stop

    with pytest.raises(Stop):
        tolerances(gear_pair, tol, output=tmp_path, progress=stop, **kw)
    assert sorted(p.name for p in (tmp_path / "chunks").iterdir()) == ["chunk_00000.npz"]
    seen = []
    res = tolerances(gear_pair, tol, output=tmp_path, progress=lambda d, t: seen.append(d), **kw)
    assert seen == [3, 6, 9]  # the first chunk was not recomputed
    fresh = tolerances(gear_pair, tol, **kw)
    assert np.array_equal(res.values("lost_motion"), fresh.values("lost_motion"))
    with pytest.raises(ReducerlabError, match="holds a different Monte-Carlo run"):
        tolerances(gear_pair, tol, output=tmp_path, **{**kw, "seed": 2})


def test_dask_gives_the_local_numbers(gear_pair):
    """The same samples on an in-process Dask cluster (other chunks) as locally."""
    distributed = pytest.importorskip("dask.distributed")
    tol = {"mesh.backlash": "60..100 um", "pinion.errors.eccentricity": "1..4 um"}
    kw = {"samples": 8, "seed": 5, "steps": 3, "te_samples": 128}
    local = tolerances(gear_pair, tol, chunk_size=8, **kw)
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1,
                            dashboard_address=None) as client:  # fmt: skip
        remote = tolerances(gear_pair, tol, chunk_size=3, scheduler=client, **kw)
    for name in ("value", "lost_motion", "te_peak_to_peak"):
        assert np.array_equal(local.data[name].values, remote.data[name].values)


def test_drive_without_transmission_accuracy_gives_lost_motion(monkeypatch):
    """A drive type without a transmission accuracy (every bundled type has one now:
    simulated by refusing it) still gives the torsion test's numbers, and says so."""
    import reducerlab.analysis.transmission_accuracy as ta
    from reducerlab.errors import ReducerlabError

    def refuse(design, *a, **k):
        raise ReducerlabError(f"transmission accuracy: not written for {design.type}")

    monkeypatch.setattr(ta, "transmission_accuracy", refuse)
    d = load_design(example_dir() / "cycloid_ball.toml")
    res = tolerances(d, {"cycloid_pair.ball_stiffness": "2.5e7..3.2e7 N/m"}, samples=3,
                     steps=3)  # fmt: skip
    assert "te_peak_to_peak" not in res.data
    assert "not computed" in res.data.attrs["transmission_accuracy"]
    assert "transmission error: not computed" in res.table()
    assert np.all(res.values("lost_motion") > 0)
    assert np.ptp(res.values("lost_motion")) > 0  # the stiffness moves it


def test_cycloid_ball_track_eccentricity_is_linear():
    """The cycloid-ball drive's groove eccentricity: its first-order law
    (kinematics/accuracy_cycloid.py) makes each sample's TE proportional to its
    eccentricity (one line of amplitude c_x / r_2), so TE / e is the same in every
    sample (to round-off) and the nominal 5 um gives it times 5 um."""
    d = load_design(example_dir() / "cycloid_ball.toml")
    res = tolerances(d, {"centre_disc.track_errors.eccentricity": "1..5 um"}, samples=4,
                     steps=3)  # fmt: skip
    e = res.data["value"].sel(field="centre_disc.track_errors.eccentricity").values
    ratio = res.values("te_peak_to_peak") / e
    # the drawn phase moves the sine's peaks between the 4096 samples of the turn: a
    # sampled order-20 sine's p-p lies within 1 - cos(pi 20 / 4096) = 1.2e-5 of 2A
    sampling = 1 - math.cos(math.pi * 20 / 4096)
    assert np.ptp(ratio) <= sampling * ratio.max()
    five = load_design(example_dir() / "cycloid_ball.toml",
                       ("centre_disc.track_errors.eccentricity=5 um",))  # fmt: skip
    from reducerlab.analysis.transmission_accuracy import transmission_accuracy

    want = transmission_accuracy(five).peak_to_peak * math.pi / (180 * 3600)
    assert ratio[0] * 5 * UM == pytest.approx(want, rel=sampling)


def test_distribution_text():
    assert parse_distribution("60..100 um", "x") == Distribution("uniform", 60, 100, "um",
                                                                 "60..100 um")  # fmt: skip
    d = parse_distribution("normal 80 +- 5 um", "x")
    assert (d.kind, d.a, d.b, d.unit) == ("normal", 80.0, 5.0, "um")
    assert parse_distribution("1e-5 ± 2e-6", "x").unit == ""
    assert parse_distribution("uniform -3 .. 3 deg", "x").bounds == (-3.0, 3.0)
    for text, rule in (("100..60 um", "lo <= hi"), ("80 +- -5 um", "sigma >= 0"),
                       ("about 80 um", "not a distribution"), ("", "not a distribution"),
                       ("nan..1", "not a distribution")):  # fmt: skip
        with pytest.raises(ReducerlabError, match=rule) as exc:
            parse_distribution(text, "--tol 'mesh.backlash=...'")
        assert "--tol 'mesh.backlash=...'" in str(exc.value)


def test_bad_input_is_named(gear_pair):
    cases = [
        (
            {"mesh.backlsh": "1..2 um"},
            {},
            r"mesh.backlsh = .*: unknown field \(allowed: .*backlash",
        ),
        ({"mesh.backlash": "1..2 rpm"}, {}, "mesh.backlash"),
        ({"mesh.backlash": "-5..2 um"}, {}, "mesh.backlash"),
        ({"mesh.backlash": "1..2 parsecs_per_fortnight"}, {}, "cannot read the unit"),
        ({"gear.errors.pitch_deviations": "1 +- 2 um"}, {}, "centred on 0"),
        ({"gear.errors.pitch_deviations": "0 +- 2 km"}, {}, "pitch_deviations"),
        ({"mesh.backlash": "1..2 um"}, {"samples": 1}, "samples must be an integer in 2"),
        ({"mesh.backlash": "1..2 um"}, {"samples": 10**9}, "samples must be an integer"),
        ({"mesh.backlash": "1..2 um"}, {"seed": -1}, "seed must be"),
        ({"mesh.backlash": "1..2 um"}, {"rated": -3.0}, "rated torque must be > 0"),
        ({}, {}, "at least one toleranced field"),
    ]
    for tol, kw, match in cases:
        with pytest.raises(ReducerlabError, match=match):
            tolerances(gear_pair, tol, **kw)
    with pytest.raises(ReducerlabError, match="write PATH=DIST"):
        tolerances(gear_pair, ["mesh.backlash 1..2 um"])
    with pytest.raises(ReducerlabError, match="toleranced twice"):
        tolerances(gear_pair, ["mesh.backlash=1..2 um", "mesh.backlash=3..4 um"])
    # a normal draw that breaks a field's rule fails naming the sample and the field
    with pytest.raises(
        ReducerlabError, match=r"(?s)sample \d+ .*mesh.backlash = -.*greater than or equal to 0"
    ):
        tolerances(gear_pair, {"mesh.backlash": "1 +- 5 um"}, samples=40, steps=3)
    with pytest.raises(BudgetError, match="static solves exceeds the limit"):
        tolerances(gear_pair, {"mesh.backlash": "1..2 um"}, samples=100_000, steps=200)


def test_tolerance_file(tmp_path):
    p = tmp_path / "tol.toml"
    p.write_text('[tolerances]\n"mesh.backlash" = "60..100 um"\n'
                 '[tolerances.gear.errors]\neccentricity = "0 +- 3 um"\n')  # fmt: skip
    assert read_tolerance_file(p) == {"mesh.backlash": "60..100 um",
                                      "gear.errors.eccentricity": "0 +- 3 um"}  # fmt: skip
    for text, match in (('[tolerances]\nx = 5\n', "write the distribution as text"),
                        ('[other]\nx = "1..2"\n', "unknown table"),
                        ('x = 1\n[tolerances]\n', "unknown table")):  # fmt: skip
        p.write_text(text)
        with pytest.raises(ReducerlabError, match=match):
            read_tolerance_file(p)


def test_cli_writes_result_and_names_bad_options(tmp_path):
    out = tmp_path / "mc"
    tol = tmp_path / "tol.toml"
    tol.write_text('[tolerances]\n"mesh.backlash" = "60..100 um"\n')
    args = ["tolerances", str(GEAR), "--tolerances", str(tol), "--tol",
            "gear.errors.eccentricity=0..5 um", "--samples", "6", "--steps", "3",
            "--te-samples", "256", "-o", str(out)]  # fmt: skip
    run = CliRunner().invoke(app, args)
    assert run.exit_code == 0, run.output
    assert "lost motion at +/-3 % rated" in run.output and "p95" in run.output
    written = {p.name for p in out.iterdir()}
    assert written >= {"tolerances.nc", "tolerances.json", "tolerances.txt", "tolerances.png"}
    assert (out / "chunks" / "chunk_00000.npz").exists() and (out / "tolerances-run.json").exists()
    res = Result.load(out / "tolerances.nc")
    assert isinstance(res, TolerancesResult)
    assert res.data.sizes["sample"] == 6
    assert res.statistics()["te_peak_to_peak_arcsec"]["p95"] == pytest.approx(
        res.data.attrs["te_peak_to_peak_p95"] / ARCSEC
    )
    res.figure()
    for args, name in ((["--tol", "mesh.backlash=9..1 um"], "--tol"),
                       (["--tol", "mesh.backlash=1..2 um", "--samples", "1"], "--samples"),
                       (["--tol", "mesh.backlash=1..2 um", "--scheduler", "nowhere"],
                        "--scheduler"),
                       (["--tolerances", str(tmp_path / "none.toml")], "none.toml"),
                       ([], "--tol")):  # fmt: skip
        bad = CliRunner().invoke(app, ["tolerances", str(GEAR), *args, "-o", str(tmp_path / "b")])
        assert bad.exit_code == 2 and name in bad.output, (args, bad.output)
    typo = tmp_path / "typo.toml"
    typo.write_text('[tolerances]\nmesh.backlsh = "1..2 um"\n')
    bad = CliRunner().invoke(app, ["tolerances", str(GEAR), "--tolerances", str(typo)])
    assert bad.exit_code == 2 and f"--tolerances {typo}: mesh.backlsh" in bad.output
    assert "unknown field" in bad.output, bad.output
    taken = tmp_path / "taken"
    taken.write_text("keep")
    r = CliRunner().invoke(app, ["tolerances", str(tmp_path / "missing.toml"), "--tol",
                                 "mesh.backlash=1..2 um", "-o", str(taken)])  # fmt: skip
    assert r.exit_code == 2 and "-o" in r.output and "existing file" in r.output, r.output
