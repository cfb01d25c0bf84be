"""The datasheet page of the report (issue 31): the torsion test's catalogue numbers
computed on the report's design (the API's numbers, to the bit), a given torsion-test
or efficiency result, no section for designs without bench ends, and the datasheet in
the report of ``reducerlab run`` keyed on the model design alone."""

from __future__ import annotations

from html.parser import HTMLParser

import numpy as np
import pytest

from reducerlab.analysis.efficiency import efficiency
from reducerlab.analysis.torsion_test import torsion_test
from reducerlab.analysis.transmission_accuracy import transmission_accuracy
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.pipeline import run
from reducerlab.reporting import report
from reducerlab.reporting.sections.datasheet import efficiency_row

#: Table rows (in order) and the catalogue keys they show.
ROWS = [
    "backlash_arcmin", "lost_motion_3pct_arcmin", "lost_motion_4pct_arcmin",
    "hysteresis_loss_arcmin", "loop_area_J", "T1_N_m", "T2_N_m", "K1_N_m_per_arcmin",
    "K2_N_m_per_arcmin", "K3_N_m_per_arcmin", "theta1_arcmin", "theta2_arcmin",
    "torsional_rigidity_rv_N_m_per_arcmin", "tangent_stiffness_at_rated_N_m_per_arcmin",
]  # fmt: skip


class _Tables(HTMLParser):
    """The numbers (``data-value``) of every table of a page, by ``data-table``."""

    def __init__(self, html: str) -> None:
        super().__init__(convert_charrefs=True)
        self.tables: dict[str, list[list[float]]] = {}
        self._table: str | None = None
        self.feed(html)
        self.close()

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "table":
            self._table = a.get("data-table", "")
            self.tables.setdefault(self._table, [])
        elif tag == "tr" and self._table is not None:
            self.tables[self._table].append([])
        elif tag == "td" and self._table is not None and "data-value" in a:
            self.tables[self._table][-1].append(float(a["data-value"]))

    def handle_endtag(self, tag):
        if tag == "table":
            self._table = None


def _shown(html: str) -> list[float]:
    """The datasheet table's values (data-value), one per row."""
    return [row[0] for row in _Tables(html).tables["datasheet"] if row]


@pytest.mark.parametrize(("name", "rated"), [("gear_pair", 144.0), ("khv", 50.0)])
def test_the_datasheet_is_the_torsion_tests(name, rated):
    path = example_dir() / f"{name}.toml"
    rep = report(path, only=["datasheet"])
    sec = rep.section("datasheet")
    assert sec is not None and sec.error is None
    want = torsion_test(load_design(path))
    assert sec.values["numbers"] == want.numbers.attrs()
    cat = want.numbers.catalogue()
    shown = _shown(rep.html)
    n = len(ROWS) + 1
    assert shown[:n] == [float(want.data.attrs["rated_torque"]), *(cat[k] for k in ROWS)]
    te = transmission_accuracy(load_design(path)).peak_to_peak  # the rigid TE, computed
    assert shown[n:] == [te] and sec.values["te_peak_to_peak_arcsec"] == te
    assert sec.values["rated_torque"] == pytest.approx(rated, rel=1e-12)
    assert sec.values["source"] == "computed for this report"
    assert sec.values["efficiency_percent"] is None
    assert '<img alt="hysteresis loop' in rep.html  # the result's own figure
    assert "Not computed here" in rep.html and "give an efficiency result" in rep.html
    assert "tolerances" in rep.html
    if te:  # the error's figure
        assert "transmission error: output angle error" in rep.html
    else:  # no error given: a note, no empty figure (issue 32)
        assert "Transmission error: no manufacturing or assembly error is given" in rep.html
        assert "transmission error: output angle error" not in rep.html


def test_the_khv_numbers_are_its_backlash_and_stiffness():
    sec = report(example_dir() / "khv.toml", only=["datasheet"]).section("datasheet")
    cat = sec.values["catalogue"]
    assert cat["backlash_arcmin"] == pytest.approx(0.279, abs=1e-3)  # docs/datasheet.md
    # 41.46 frictionless; Coulomb mu = 0.05 on the sliding flanks stiffens the loading
    # mesh on the loading branch by 1 + mu tan(alpha_w), in series with the shafts
    assert cat["K1_N_m_per_arcmin"] == pytest.approx(41.72, abs=1e-2)


def test_a_given_torsion_test_is_shown_instead(tmp_path):
    path = example_dir() / "gear_pair.toml"
    d = load_design(path)
    given = torsion_test(d, rated=100.0, steps=12, t1=0.25, t2=0.8)
    f = given.save(tmp_path / "sheet.nc")
    sec = report(path, only=["datasheet"], results=[f]).section("datasheet")
    assert sec.error is None
    assert sec.values["numbers"] == given.numbers.attrs()
    assert sec.values["rated_torque"] == 100.0
    assert sec.values["source"] == "a given torsion-test result (report --with)"
    other = torsion_test(load_design(example_dir() / "khv.toml")).save(tmp_path / "khv.nc")
    with pytest.raises(ReducerlabError, match=r"was computed for .*not for this design"):
        report(path, only=["datasheet"], results=[other])


def test_a_given_efficiency_enters_the_table():
    path = example_dir() / "gear_pair.toml"
    d = load_design(path)  # 60 N m on the pinion: between the two torques
    eff = efficiency(d, rigid=True, positions=3, torques=[40.0, 80.0], cell=3e-4)
    rep = report(path, only=["datasheet"], results=[eff])
    sec = rep.section("datasheet")
    want = 100.0 * float(np.interp(60.0, [40.0, 80.0], eff.efficiency))
    assert sec.values["efficiency_percent"] == want
    assert _shown(rep.html)[len(ROWS) + 1] == want  # after the torsion test's rows
    assert "efficiency (give" not in rep.html
    label, value, unit = efficiency_row(eff)
    assert "design load" in label and unit == "%" and value == want
    high = efficiency(d, rigid=True, positions=3, torques=[80.0], cell=3e-4)
    label, value, _ = efficiency_row(high)  # the design load outside: the nearest torque
    assert "outside" in label and value == 100.0 * float(high.efficiency[0])


@pytest.mark.parametrize("name", ["torsional_chain", "spinning_disc", "khv_kinematics"])
def test_designs_without_bench_ends_have_no_datasheet(name):
    rep = report(example_dir() / f"{name}.toml", only=["datasheet"])
    assert rep.section("datasheet") is None
    assert not rep.failed


def test_a_design_without_load_gets_a_note_not_an_error():
    rep = report(example_dir() / "gear_pair.toml", overrides=["operating.torque=0"],
                 only=["datasheet"])  # fmt: skip
    sec = rep.section("datasheet")
    assert sec is not None and sec.error is None
    assert "no output torque" in rep.html and "datasheet" not in _Tables(rep.html).tables


def test_the_runs_report_has_the_datasheet_of_its_model_design(tmp_path):
    path = example_dir() / "khv.toml"  # ISO stiffness: no contact, one response stage
    res = run(path, tmp_path / "out", response={"periods": 60, "keep": 20})
    sec = res.built.section("datasheet")
    assert sec is not None and sec.error is None and not sec.reused
    assert sec.values["numbers"] == torsion_test(res.model_design).numbers.attrs()
    assert 'id="datasheet"' in (tmp_path / "out" / "report.html").read_text()
    # other response settings: a new verdict, the same model design: the datasheet is
    # read from the stage cache, the sections that read the verdict are built again
    again = run(path, tmp_path / "out", response={"periods": 80, "keep": 20})
    assert again.built.section("datasheet").reused
    assert not again.built.section("response").reused
    assert again.built.section("datasheet").values == sec.values
    # a changed design (its mesh backlash): built again, with its own numbers
    third = run(path, tmp_path / "out", overrides=["mesh.half_backlash=4 um"],
                response={"periods": 60, "keep": 20})  # fmt: skip
    got = third.built.section("datasheet")
    assert not got.reused
    assert got.values["numbers"] == torsion_test(third.model_design).numbers.attrs()
    assert got.values["numbers"]["backlash"] == pytest.approx(
        2.0 * sec.values["numbers"]["backlash"], rel=1e-9
    )


def test_cli_report_takes_the_datasheet_file(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.cli import app

    path = str(example_dir() / "gear_pair.toml")
    cli = CliRunner()
    got = cli.invoke(app, ["datasheet", path, "--rated", "120 N*m", "--no-efficiency",
                           "--unloaded", "-o", str(tmp_path / "s")])  # fmt: skip
    assert got.exit_code == 0, got.output
    page = tmp_path / "r.html"
    got = cli.invoke(app, ["report", path, "-s", "datasheet", "--with",
                           str(tmp_path / "s" / "datasheet.nc"), "-o", str(page)])  # fmt: skip
    assert got.exit_code == 0, got.output
    assert _shown(page.read_text(encoding="utf-8"))[0] == 120.0  # the file's rated torque


def test_a_given_contact_puts_its_stiffness_into_the_datasheet(tmp_path):
    """The report's design is the one with the contact's k(t) in its mesh (as the run's
    model design): the datasheet is that design's torsion test, not the ISO one's."""
    from reducerlab.analysis.contact import contact_analysis, design_with_contact

    path = example_dir() / "nutation_surface.toml"
    d = load_design(path)
    res = contact_analysis(d, 1, torque=19.1, positions=5, order=2, rigid=True)
    sec = report(path, results=[res.save(tmp_path / "c.nc")], only=["datasheet"]).section(
        "datasheet"
    )
    want = torsion_test(design_with_contact(d, [res])).numbers.attrs()
    assert sec.values["numbers"] == want
    assert want["K1"] != torsion_test(d).numbers.K1
