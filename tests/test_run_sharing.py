"""The KHV load sharing against torque in the ``run`` pipeline and the report (issue 30).

``run(..., sharing=...)`` / ``reducerlab run --sharing N`` runs
``analysis.khv_sharing.load_sharing`` on the compliance stage's tooth models of the
planet and the ring, caches it as a stage, writes ``sharing-pair1.nc``/``.txt`` and
hands it to the report's contact section, as ``report --with sharing.nc`` does.

Kept small as tests/test_khv_contact_stiffness.py: tooth elements 0.35 m, no fillet
influence, a 0.2 mm cell, 15 positions (the contact's, which the sharing takes), three
torques 0, 37.5 and 75 N m (0 to 1.5 times the planet's 50 N m). The oracles: the
stage's result is the API's on the same tooth models (to round-off); a second run and the
CLI read it back; the shares and stiffness obey what tests/test_khv_sharing.py checks
against rigid geometry and ISO 6336, here at the run's grid.
"""

from __future__ import annotations

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.contact_setup import PairSetup
from reducerlab.analysis.khv_sharing import load_sharing
from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.pipeline import ContactSettings, SharingSettings, run, run_plan
from reducerlab.pipeline.store import Store

KHV = example_dir() / "khv.toml"
SETTINGS = ContactSettings(positions=15, order=7, cell=0.2e-3, tooth_size=0.35 * 3.5e-3,
                           root_stress=False)  # fmt: skip
RESPONSE = {"periods": 120, "keep": 60, "history": 20}  # what the CLI's --periods 120 asks
SHARING = SharingSettings(loads=3)  # 0, 37.5, 75 N m at the contact's 15 positions


@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    out = tmp_path_factory.mktemp("khv-sharing") / "out"
    partial: list[str] = []

    def progress(description: str, _fraction: float) -> None:
        f = out / "sharing-pair1.partial.txt"
        if description.startswith("load sharing pair 1") and f.is_file():
            partial.append(f.read_text())

    res = run(KHV, out, contact=SETTINGS, response=RESPONSE, sharing=SHARING, progress=progress)
    return out, res, partial


def test_the_run_gives_the_sharing_on_the_iso_design(ran):
    out, res, partial = ran
    # [mesh] stiffness = "iso": no contact, the pair's tooth models built for the sharing
    assert [(s.name, s.status) for s in res.stages] == [
        ("compliance planet V, ring K", "computed"), ("load sharing pair 1", "computed"),
        ("response line 1", "computed")]  # fmt: skip
    assert [n for _, n in run_plan(res.design, sharing=True)][:2] == [
        "compliance planet V, ring K", "load sharing pair 1"]  # fmt: skip
    assert res.contacts == {} and res.model_design.mesh.stiffness == "iso"
    sh = res.sharing
    assert sh.kind == "khv-sharing"
    np.testing.assert_allclose(sh.torques, [0.0, 37.5, 75.0])  # the planet's 50 N m x 0..1.5
    assert sh.data.sizes["position"] == 15 and sh.data.attrs["cell_m"] == SETTINGS.cell
    # shares sum to one where loaded; one or two pairs at these loads (eps = 1.23, the
    # neighbours +-2 stand > 40 um off: tests/test_khv_sharing.py)
    share = sh.data["share"].values[1:]
    np.testing.assert_allclose(share.sum(axis=2), 1.0, atol=1e-12)
    n = sh.data["pairs"].values[1:]
    assert set(n.ravel().tolist()) == {1.0, 2.0}
    mean = sh.data["mean_stiffness"].values
    assert np.isnan(mean[0]) and mean[2] > mean[1] > 0  # stiffens with the load
    # written as the other optional stages: the result, its table; the partial table
    # while it ran (positions so far), removed once stored
    assert (out / "sharing-pair1.txt").read_text() == sh.table() + "\n"
    assert (out / "sharing-pair1.nc").is_file() and not (out / "sharing-pair1.partial.txt").exists()
    assert partial and all(t.startswith("KHV pair load sharing") for t in partial)


def test_the_report_of_the_run_shows_it(ran):
    _, res, _ = ran
    sec = res.built.section("contact")
    assert sec is not None and sec.error is None
    (rows,) = sec.values["sharing"]
    ds = res.sharing.data
    assert [r[0] for r in rows] == pytest.approx(list(res.sharing.torques))
    assert rows[0][1] == "-" and rows[2][1] == "1-2"
    assert rows[2][2] == pytest.approx(float(ds["mean_stiffness"].values[2]), rel=1e-12)
    assert rows[2][4] == pytest.approx(1e6 * float(ds["peak_to_peak"].values[2]), rel=1e-12)
    assert [b.kind for b in sec.blocks] == ["table", "figure"]
    assert 'data-table="khv-sharing"' in res.built.html


def test_a_second_run_and_the_cli_read_the_stage(ran):
    out, res, _ = ran
    again = run(KHV, out, contact=SETTINGS, response=RESPONSE, sharing=SHARING,
                write_report=False)  # fmt: skip
    assert {s.status for s in again.stages} == {"cached"}
    np.testing.assert_array_equal(again.sharing.data["te"].values, res.sharing.data["te"].values)
    args = ["run", str(KHV), "-o", str(out.parent / "cli"), "--cache", str(out / "cache"),
            "--positions", "15", "--cell", repr(SETTINGS.cell),
            "--tooth-size", repr(SETTINGS.tooth_size), "--no-root-stress", "--periods", "120",
            "--sharing", "3"]  # fmt: skip
    r = CliRunner().invoke(app, args)
    assert r.exit_code == (0 if res.ok else 1), r.output
    assert "load sharing pair 1" in r.output and "computed" not in r.output
    assert (out.parent / "cli" / "sharing-pair1.nc").is_file()


def test_the_stage_reuses_the_tooth_models(ran, monkeypatch):
    """Other sharing settings: the stage runs on the stored tooth models (a second FE
    build would fail here) and gives what the API gives on them; a design on its
    contact's k(t) reads the same stage (the sharing's key holds no [mesh])."""
    out, res, _ = ran

    def no_fe(*_a, **_k):
        raise AssertionError("a finite-element tooth model was built again")

    monkeypatch.setattr(PairSetup, "compliances", no_fe)
    small = SharingSettings(loads=2, top=1.0, positions=4)
    other = out.parent / "small"  # its own files, the run's cache
    got = run(KHV, other, cache=out / "cache", contact=SETTINGS, response=RESPONSE,
              sharing=small, write_report=False)  # fmt: skip
    status = {s.name: s.status for s in got.stages}
    assert status["compliance planet V, ring K"] == "cached"
    assert status["load sharing pair 1"] == "computed"
    key = res.stages[0].key
    comp = Store(out / "cache").get("compliance", key, extra=True)[1]
    api = load_sharing(res.design, loads=2, top=1.0, torque=50.0, positions=4,
                       cell=SETTINGS.cell, compliance=comp)  # fmt: skip
    for name in ("te", "share", "stiffness", "mean_stiffness"):
        # to round-off (1e-16 measured: the solves' summation order), not bit for bit
        np.testing.assert_allclose(got.sharing.data[name].values, api.data[name].values,
                                   rtol=1e-12, atol=0)  # fmt: skip
    contact = run(KHV, other, cache=out / "cache", overrides=["mesh.stiffness=contact"],
                  contact=SETTINGS, response=RESPONSE, sharing=small,
                  write_report=False)  # fmt: skip
    assert [(s.name, s.status) for s in contact.stages][:3] == [
        ("compliance planet V, ring K", "cached"), ("contact pair 1", "computed"),
        ("load sharing pair 1", "cached")]  # fmt: skip


def test_report_with_the_saved_sharing(ran, tmp_path):
    from reducerlab.reporting import report

    out, res, _ = ran
    saved = out / "sharing-pair1.nc"
    rep = report(KHV, results=[saved], only=["contact"])
    sec = rep.section("contact")
    assert sec is not None and sec.error is None
    np.testing.assert_equal(sec.values["sharing"], res.built.section("contact").values["sharing"])
    # a sharing of other teeth is refused, naming the field that differs
    with pytest.raises(ReducerlabError, match=r"sharing-pair1\.nc was computed .*gears\.x1"):
        report(KHV, overrides=["gears.x1=0.7"], results=[saved], only=["contact"])
    html = tmp_path / "r.html"
    r = CliRunner().invoke(app, ["report", str(KHV), "--with", str(saved), "-s", "contact",
                                 "-o", str(html)])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert 'data-table="khv-sharing"' in html.read_text()
    r = CliRunner().invoke(app, ["report", str(KHV), "--with", str(saved), "-s", "contact",
                                 "--set", "gears.module=4 mm", "-o", str(html)])  # fmt: skip
    assert r.exit_code == 2 and "gears.module" in r.output


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"loads": 1}, r"sharing\.loads: must be an integer in 2\.\.41; got 1"),
        ({"loads": True}, r"sharing\.loads"),
        ({"top": 0.0}, r"sharing\.top: must be a number in \(0, 3\]"),
        ({"top": 5}, r"sharing\.top"),
        ({"positions": 2}, r"sharing\.positions: must be an integer in 3\.\.1000"),
    ],
)
def test_bad_sharing_settings_named(kwargs, match):
    with pytest.raises(ReducerlabError, match=match):
        SharingSettings(**kwargs)


def test_bad_requests_refused_before_any_work(tmp_path):
    cache = tmp_path / "cache"
    for design in ("gear_pair.toml", "nutation_surface.toml"):
        with pytest.raises(ReducerlabError, match=r"sharing: .*KHV drive.*type 'gear_pair'|"
                           r"sharing: .*KHV drive.*type 'nutation'"):  # fmt: skip
            run(example_dir() / design, cache=cache, sharing=3, write_report=False)
    for bad, match in (("3", r"sharing: must be a number of torques \(2\.\.41\) or a "),
                       (1, r"sharing\.loads"), (2.5, r"sharing: must be")):  # fmt: skip
        with pytest.raises(ReducerlabError, match=match):
            run(KHV, cache=cache, sharing=bad, write_report=False)
    # beyond the sweep's work bound, named by the stage's own settings
    with pytest.raises(ReducerlabError, match=r"sharing: 1000 positions x 41 torques.*"
                       r"sharing\.loads or sharing\.positions"):  # fmt: skip
        run(KHV, cache=cache, sharing=SharingSettings(loads=41, positions=1000))
    assert not cache.exists() or not any(cache.iterdir())  # nothing computed
    # the API refuses tooth models that are not a pair of compliances, before any work
    with pytest.raises(ReducerlabError, match=r"compliance: must be the planet's and the ring's"):
        load_sharing(load_design(KHV), torques=[0, 50.0], positions=6, compliance=("a", "b"))
    invoke = CliRunner().invoke
    r = invoke(app, ["run", str(example_dir() / "gear_pair.toml"), "-o", str(tmp_path / "o"),
                     "--sharing", "3"])  # fmt: skip
    assert r.exit_code == 2 and "sharing:" in r.output and "KHV" in r.output, r.output
    r = invoke(app, ["run", str(KHV), "-o", str(tmp_path / "o2"), "--sharing", "1"])
    assert r.exit_code == 2 and "--sharing" in r.output, r.output
