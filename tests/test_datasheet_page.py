"""The datasheet as one page (issue 31): ``pipeline.datasheet`` gathers the torsion test,
the transmission accuracy (under the rated load for a gear pair and KHV drive) and the
efficiency with the starting and back-driving torque; the report's datasheet section
shows them; ``reducerlab datasheet`` writes the page and reuses its stage cache.

The efficiency itself is checked against Ohlendorf's tooth loss factor in
tests/test_friction.py and the loaded transmission error against the contact's own TE
in tests/test_loaded_accuracy.py; here: that the page's numbers are those results'
numbers, through the relations of docs/datasheet.md, and that nothing is recomputed
when the cache has it. Teeth rigid beyond the half-space and few positions keep it fast.
"""

from __future__ import annotations

import pytest
from typer.testing import CliRunner

from reducerlab.analysis.datasheet import starting_torques
from reducerlab.analysis.torsion_test import torsion_test
from reducerlab.analysis.transmission_accuracy import transmission_accuracy
from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.examples import example_dir
from reducerlab.pipeline.datasheet import EFFICIENCY_LOADS, datasheet
from reducerlab.reporting import report


@pytest.fixture(scope="module")
def khv_sheet(tmp_path_factory):
    d = load_design(example_dir() / "khv.toml")
    cache = tmp_path_factory.mktemp("cache")
    return d, cache, datasheet(d, rigid=True, positions=4, cache=cache)


def test_the_sheet_gathers_its_results(khv_sheet):
    """Torsion test as the API's; efficiency at 1/4, 1/2 and 1 times rated, the
    starting torque ``T_r / (|i| eta)`` and the back-driving torque ``T_r / eta`` at
    rated (the efficiency computed at rated exactly, no interpolation); the accuracy
    under the rated load with its wind-up."""
    d, _, sheet = khv_sheet
    assert sheet.torsion.numbers == torsion_test(d, steps=20).numbers
    rated = d.operating_point().output_torque
    eff = sheet.efficiency
    assert list(eff.data["output_torque"].values) == pytest.approx(
        [f * rated for f in EFFICIENCY_LOADS], rel=1e-12
    )
    st = sheet.starting()
    eta = float(eff.efficiency[-1])
    ratio = abs(d.kinematics().ratio)
    assert st["efficiency"] == eta
    assert st["starting_torque"] == pytest.approx(rated / (ratio * eta), rel=1e-14)
    assert st["backdriving_torque"] == pytest.approx(rated / eta, rel=1e-14)
    assert 0.98 < eta < 1.0  # docs/efficiency.md: the KHV example runs at 0.994
    a = sheet.accuracy.data.attrs
    assert a["load_N_m"] == pytest.approx(rated) and a["wind_up_arcsec"] > 0
    with pytest.raises(Exception, match="not around the rated"):
        starting_torques(eff, 3 * rated)


def test_a_second_sheet_reads_every_stage_from_the_cache(khv_sheet):
    d, cache, first = khv_sheet
    again = datasheet(d, rigid=True, positions=4, cache=cache)
    assert {s.status for s in again.stages} == {"cached"}
    assert again.starting() == first.starting()
    assert again.accuracy.peak_to_peak == first.accuracy.peak_to_peak


def test_what_a_drive_lacks_is_said():
    """The cycloid-ball drive: no tooth surfaces, its efficiency from the balls' spin and
    sliding (its accuracy named as missing or given, whichever the drive type has)."""
    sheet = datasheet(load_design(example_dir() / "cycloid_ball.toml"))
    assert sheet.efficiency is not None and "efficiency" not in sheet.notes
    st = sheet.starting()
    assert 0.9 < st["efficiency"] < 1 and st["starting_torque"] > 0
    assert "back-driving torque" in sheet.table()
    assert (sheet.accuracy is None) == ("accuracy" in sheet.notes)
    off = datasheet(load_design(example_dir() / "gear_pair.toml"), efficiency=False,
                    loaded=False)  # fmt: skip
    assert off.efficiency is None and "not asked" in off.notes["efficiency"]
    assert off.accuracy.peak_to_peak == transmission_accuracy(
        load_design(example_dir() / "gear_pair.toml")).peak_to_peak  # fmt: skip
    assert "starting torque" not in off.table()


def test_the_report_section_shows_the_given_results(khv_sheet):
    d, _, sheet = khv_sheet
    rep = report(d, results=sheet.results, only=["datasheet"])
    sec = rep.section("datasheet")
    assert sec.error is None
    assert sec.values["te_peak_to_peak_arcsec"] == sheet.accuracy.peak_to_peak
    st = sheet.starting()
    assert sec.values["efficiency_percent"] == pytest.approx(100 * st["efficiency"])
    html = rep.html
    assert "starting torque at rated output" in html and "back-driving torque" in html
    assert "mean wind-up" in html and "transmission error: output angle error" in html
    assert "loop area (friction work per cycle)" in html
    plain = report(d, only=["datasheet"]).section("datasheet")  # computes the rigid TE
    assert plain.values["te_peak_to_peak_arcsec"] == transmission_accuracy(d).peak_to_peak
    assert plain.values["efficiency_percent"] is None


def test_cli_writes_the_page_and_reuses_its_cache(tmp_path):
    example = str(example_dir() / "gear_pair.toml")
    args = ["datasheet", example, "--rigid", "--positions", "4", "--steps", "5",
            "-o", str(tmp_path / "out")]  # fmt: skip
    first = CliRunner().invoke(app, args)
    assert first.exit_code == 0, first.output
    names = {p.name for p in (tmp_path / "out").iterdir()}
    assert {"datasheet.html", "datasheet.nc", "accuracy.nc", "efficiency.nc", "cache"} <= names
    assert "efficiency: computed" in first.output
    second = CliRunner().invoke(app, args)
    assert second.exit_code == 0, second.output
    assert "efficiency: cached" in second.output and "transmission error: cached" in second.output
    bad = CliRunner().invoke(app, ["datasheet", example, "--positions", "2"])
    assert bad.exit_code == 2 and "--positions" in bad.output
    bad = CliRunner().invoke(app, ["datasheet", example, "--mu", "0.9", "--no-efficiency"])
    assert bad.exit_code != 0 and "friction coefficient" in bad.output


def test_the_run_computes_the_datasheet_on_its_tooth_models(tmp_path):
    """``run(datasheet=True)`` on the KHV example (ISO mesh stiffness: no contact in the
    run, so the datasheet builds the pair's tooth models in the compliance stage): the
    efficiency and the loaded accuracy enter the run's report and files, and
    ``datasheet(..., cache=RUN/cache)`` with the run's contact settings then reads
    every stage. Coarse teeth (0.35 m elements, no fillet stress, 0.2 mm cell) as
    tests/test_run_sharing.py, to stay fast."""
    from reducerlab.pipeline import ContactSettings, run

    settings = ContactSettings(positions=15, order=7, cell=0.2e-3, tooth_size=0.35 * 3.5e-3,
                               root_stress=False)  # fmt: skip
    khv = example_dir() / "khv.toml"
    out = tmp_path / "out"
    res = run(khv, out, contact=settings, response={"periods": 60, "keep": 30, "history": 5},
              datasheet=True)  # fmt: skip
    names = [s.name for s in res.stages]
    assert names[:3] == ["compliance planet V, ring K", "efficiency", "loaded transmission error"]
    kinds = sorted(r.kind for r in res.datasheet)
    assert kinds == ["efficiency", "transmission-accuracy"]
    assert (out / "efficiency.nc").is_file() and (out / "accuracy.nc").is_file()
    sec = res.built.section("datasheet")
    assert sec.error is None and sec.values["efficiency_percent"] is not None
    acc = next(r for r in res.datasheet if r.kind == "transmission-accuracy")
    assert sec.values["te_peak_to_peak_arcsec"] == acc.peak_to_peak
    sheet = datasheet(load_design(khv), cache=out / "cache", contact=settings)
    assert {s.status for s in sheet.stages} == {"cached"}
    eff = next(r for r in res.datasheet if r.kind == "efficiency")
    assert sheet.efficiency.efficiency.tolist() == eff.efficiency.tolist()


def test_a_nutation_sheet_loads_its_meshes(tmp_path):
    """The single-sided nutation drive: its accuracy under the rated torque carries the
    mesh's loaded TE (tests/test_loaded_accuracy_nutation.py checks the mapping), and
    a second sheet reads the loaded TE and the efficiency from the cache."""
    d = load_design(example_dir() / "nutation_surface.toml")
    first = datasheet(d, rigid=True, positions=4, cache=tmp_path)
    acc = first.accuracy.data
    assert "mesh 1 under load" in list(acc["source"].values)
    assert acc.attrs["load_N_m"] == pytest.approx(d.operating_point().output_torque)
    again = datasheet(d, rigid=True, positions=4, cache=tmp_path)
    assert {s.status for s in again.stages} == {"cached"}
    assert again.accuracy.peak_to_peak == first.accuracy.peak_to_peak
