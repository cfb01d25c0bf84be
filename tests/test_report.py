"""The HTML design report (issue 18): it parses, every section each bundled example
supports is there, its numbers are the API's, a failing section does not take the
report down, nothing is fetched when it opens, and its entry points refuse bad input."""

from __future__ import annotations

import math
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import reducerlab as rl
from reducerlab.analysis.body_modal import BodyModalResult
from reducerlab.analysis.modal import modal
from reducerlab.analysis.resonance import resonance_check
from reducerlab.analysis.response import response
from reducerlab.cli import app
from reducerlab.errors import DesignError, ReducerlabError
from reducerlab.examples import example_dir, example_files
from reducerlab.reporting import report, sections, write_index

#: Sections each bundled example must show (summary and provenance: always).
EXPECTED = {
    "cycloid_ball": {"design", "kinematics", "modal", "sensitivity", "campbell", "response",
                     "ball-track", "datasheet"},
    "cycloid_ball_kinematics": {"design", "kinematics"},
    "gear_pair": {"design", "kinematics", "modal", "sensitivity", "campbell", "response",
                  "capacity", "datasheet"},
    "gear_pair_crowned": {"design", "kinematics", "modal", "sensitivity", "campbell",
                          "response", "capacity", "datasheet"},
    "khv": {"design", "kinematics", "modal", "sensitivity", "campbell", "response",
            "closed-graph", "capacity", "datasheet"},
    "khv_kinematics": {"design", "kinematics"},
    "khv_rattle": {"design", "kinematics", "modal", "sensitivity", "campbell", "response",
                   "bifurcation", "closed-graph", "capacity", "datasheet"},
    "nutation_double": {"design", "kinematics"},
    "nutation_double_sided": {"design", "kinematics", "modal", "sensitivity", "campbell",
                              "response", "surfaces", "capacity", "datasheet"},
    "nutation_surface": {"design", "kinematics", "modal", "sensitivity", "campbell",
                         "response", "surfaces", "capacity", "datasheet"},
    "spinning_disc": {"design", "modal", "sensitivity", "campbell"},
    "torsional_chain": {"design", "modal", "sensitivity", "campbell", "response"},
}  # fmt: skip

VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source",
        "track", "wbr"}  # fmt: skip


class Page(HTMLParser):
    """Checks that every element is closed in order and collects the sections, the
    table cells' full values and every external reference."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.errors: list[str] = []
        self.sections: dict[str, str] = {}
        self.tables: dict[str, list[list[float]]] = {}
        self.external: list[str] = []
        self._table: str | None = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("src", "href"):
            v = a.get(key) or ""
            if v.startswith(("http:", "https:", "//")):
                self.external.append(v)
        if tag == "script" and a.get("src"):
            self.external.append(a["src"])
        if tag == "section":
            self.sections[a["id"]] = a.get("data-status", "")
        if tag == "table":
            self._table = a.get("data-table", "")
            self.tables.setdefault(self._table, [])
        if tag == "tr" and self._table is not None:
            self.tables[self._table].append([])
        if tag == "td" and self._table is not None and "data-value" in a:
            self.tables[self._table][-1].append(float(a["data-value"]))
        if tag not in VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if tag in VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes <{self.stack[-1] if self.stack else None}>")
            return
        self.stack.pop()
        if tag == "table":
            self._table = None


def parse(html: str) -> Page:
    p = Page()
    p.feed(html)
    p.close()
    assert not p.errors, p.errors[:5]
    assert not p.stack, p.stack
    return p


@pytest.fixture(scope="module")
def reports():
    return {path.stem: report(path) for path in example_files()}


def test_every_example_is_covered():
    assert {p.stem for p in example_files()} == set(EXPECTED)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_report_parses_and_has_its_sections(reports, name):
    r = reports[name]
    page = parse(r.html)
    want = EXPECTED[name] | {"summary", "provenance"}
    assert set(page.sections) == want
    assert all(status == "ok" for status in page.sections.values()), page.sections
    assert not page.external  # self-contained: opens offline
    assert r.html.count("<!DOCTYPE html>") == 1
    # plotly.js embedded once, when (and only when) an interactive figure is there
    interactive = 'class="interactive"' in r.html
    assert ("Plotly" in r.html) == interactive
    assert interactive == bool(want & {"modal", "bifurcation"})


def _column(page: Page, table: str, j: int) -> list[float]:
    return [row[j] for row in page.tables[table] if len(row) > j]


def test_numbers_are_the_apis(reports):
    # exact: the report keeps each number's repr in data-value
    d = rl.load_design(example_dir() / "gear_pair.toml")
    page = parse(reports["gear_pair"].html)
    want = modal(rl.build_model(d)).frequencies
    got = _column(page, "modes", 1)
    assert np.array_equal(got, want)
    check = resonance_check(d)
    assert reports["gear_pair"].section("campbell").values["crossings"] == check["crossings"]
    dlf = response(rl.build_model(d)).data.attrs["dynamic_load_factor"]
    assert reports["gear_pair"].section("response").values["dynamic_load_factor"] == dlf
    rows = {r[0]: r for r in page.tables["response"] if r}
    assert dlf in [v for r in page.tables["response"] for v in r]
    assert rows  # the table has numeric rows
    k = reports["nutation_double_sided"]
    from reducerlab.analysis.kinematics import kinematics
    from reducerlab.drives import kinematics_of

    dn = rl.load_design(example_dir() / "nutation_double_sided.toml")
    ratio = kinematics(*kinematics_of(dn)).data.attrs["ratio"]
    assert parse(k.html).tables["ratio"][1][0] == ratio == 105.0


def test_bifurcation_asked_by_the_design_is_the_apis(reports):
    from reducerlab.analysis.bifurcation import bifurcation
    from reducerlab.analysis.parameters import parse_values

    d = rl.load_design(example_dir() / "khv_rattle.toml")
    req = d.report.bifurcation
    res = bifurcation(d, parse_values(req.parameter, req.values), periods=req.periods,
                      keep=req.keep)  # fmt: skip
    assert reports["khv_rattle"].section("bifurcation").values["periods"] == [
        res.periodicity().tolist()
    ]
    # the diagram is not trivial: quasi-periodic, a period-3 window and period-1 (the
    # example's comment, docs/paper_004_regimes.md)
    assert {0, 1, 3} <= set(res.periodicity().tolist())


def test_an_unexcited_drive_reports_no_response_instead_of_round_off(reports):
    # the bundled drive carries its rated load and k(t) (issue 27): a load factor
    s = reports["nutation_double_sided"].section("response")
    assert s.values["dynamic_load_factor"] > 1.0
    # without them nothing excites it: no load factor from round-off
    sets = ["output_torque=0", "mesh1.harmonics=[]", "mesh2.harmonics=[]"]
    path = example_dir() / "nutation_double_sided.toml"
    s = report(path, overrides=sets, only=["response"]).section("response")
    assert math.isnan(s.values["dynamic_load_factor"])
    assert "not excited" in s.blocks[0].html


def test_a_failing_section_shows_its_error_and_the_rest_renders(monkeypatch):
    def broken(ctx):
        raise RuntimeError("synthetic failure")

    table = [(sid, t, broken if sid == "sensitivity" else b) for sid, t, b in sections.SECTIONS]
    monkeypatch.setattr(sections, "SECTIONS", table)
    import reducerlab.reporting as rep

    monkeypatch.setattr(rep, "SECTIONS", table)
    r = report(example_dir() / "gear_pair.toml")
    page = parse(r.html)
    assert page.sections["sensitivity"] == "error"
    assert page.sections["modal"] == page.sections["campbell"] == "ok"
    assert "synthetic failure" in r.html and "FAILED" in r.section("summary").blocks[-1].html
    assert [s.id for s in r.failed] == ["sensitivity"]


def _body_result(design) -> BodyModalResult:
    """A gear-body result as body_modal writes it (values chosen for the test)."""
    freq = np.array([5000.0, 5000.0, 9000.0])
    ds = xr.Dataset(
        {"frequency": ("mode", freq, {"units": "Hz"}),
         "type": ("mode", np.array(["2 nodal diameters", "2 nodal diameters", "umbrella"]))},
        coords={"mode": [1, 2, 3]},
        attrs={"title": "gear 2 body", "design_hash": design.hash, "gear": 2},
    )  # fmt: skip
    return BodyModalResult(ds)


def test_given_body_modes_enter_the_report_and_the_verdict():
    path = example_dir() / "nutation_double_sided.toml"
    d = rl.load_design(path)
    body = _body_result(d)
    r = report(path, results=[body], only=["campbell", "bodies"])
    page = parse(r.html)
    assert {"campbell", "bodies"} <= set(page.sections)
    assert _column(page, "body-modes", 1) == [5000.0, 5000.0, 9000.0]
    from reducerlab.analysis.components import ComponentModes

    check = resonance_check(d, components=[ComponentModes.from_body_modal(body)])
    assert r.section("campbell").values["ok"] == check["ok"]
    assert "BODY" in r.html


def test_report_refuses_bad_input(tmp_path):
    path = example_dir() / "gear_pair.toml"
    with pytest.raises(ReducerlabError, match="unknown section"):
        report(path, only=["nope"])
    with pytest.raises(ReducerlabError, match="no such result file"):
        report(path, results=[tmp_path / "missing.nc"])
    with pytest.raises(ReducerlabError, match="target must be"):
        report(42)  # type: ignore[arg-type]
    bad = tmp_path / "bad.toml"
    bad.write_text((example_dir() / "khv_rattle.toml").read_text().replace(
        'values = "lin:0.416:0.835:43"', 'values = "lin:a:b:c"'))  # fmt: skip
    r = report(bad, only=["bifurcation"])
    assert r.section("bifurcation").error.startswith("ReducerlabError: report.bifurcation.values")
    with pytest.raises(DesignError, match=r"report\.bifurcation\.periods"):
        rl.load_design(example_dir() / "khv_rattle.toml", ["report.bifurcation.periods=5"])


def test_cli_report_and_demo_index(tmp_path, monkeypatch):
    runner = CliRunner()
    out = tmp_path / "gear.html"
    res = runner.invoke(app, ["report", str(example_dir() / "gear_pair.toml"), "-o", str(out),
                              "-s", "modal"])  # fmt: skip
    assert res.exit_code == 0, res.output
    assert set(parse(out.read_text()).sections) == {"summary", "modal", "provenance"}
    res = runner.invoke(app, ["report", str(example_dir() / "gear_pair.toml"), "-o",
                              str(tmp_path / "x.pdf")])  # fmt: skip
    assert res.exit_code == 2 and "-o" in res.output and ".html" in res.output
    # demo: one report per example and an index linking them (two examples here)
    import reducerlab.examples as ex

    two = [example_dir() / "gear_pair.toml", example_dir() / "nutation_double.toml"]
    monkeypatch.setattr(ex, "example_files", lambda: two)
    res = runner.invoke(app, ["demo", "-o", str(tmp_path / "demo")])
    assert res.exit_code == 0, res.output
    index = (tmp_path / "demo" / "index.html").read_text()
    assert 'href="gear_pair.html"' in index and 'href="nutation_double.html"' in index
    assert "index.html" in res.output.replace("\n", "")  # a long path wraps on the terminal


def test_demo_writes_a_report_per_example(reports, tmp_path, monkeypatch):
    """The flagship example goes through the whole chain (``run``, into its own folder),
    every other example gets its report, and the index has a row for each (the reports
    are the module's, handed in through stand-ins to keep the test fast)."""
    from types import SimpleNamespace

    import reducerlab.pipeline as pipe
    import reducerlab.reporting as rep
    from reducerlab.cli.report import FLAGSHIP

    def run(path, out, progress=None):
        out.mkdir(parents=True)
        r = reports[Path(path).stem]
        file = r.write(out / "report.html")
        return SimpleNamespace(report=file, built=r, ok=False, seconds=1.0,
                               verdict=SimpleNamespace(risks=[{}]))  # fmt: skip

    monkeypatch.setattr(rep, "report", lambda path: reports[Path(path).stem])
    monkeypatch.setattr(pipe, "run", run)
    res = CliRunner().invoke(app, ["demo", "-o", str(tmp_path)])
    assert res.exit_code == 0, res.output
    assert f"{FLAGSHIP}: the whole chain" in res.output and "RISK" in res.output
    index = (tmp_path / "index.html").read_text()
    for path in example_files():
        file = f"{path.stem}/report.html" if path.name == FLAGSHIP else f"{path.stem}.html"
        r = reports[path.stem]
        shared = f'<script src="{rep.PLOTLY_FILE}"></script>'
        inline = f'<script type="text/javascript">{r.plotly_js}</script>'
        written = (tmp_path / file).read_text()
        if path.name != FLAGSHIP:  # the demo's reports share plotly.js in their folder
            written = written.replace(shared, inline, 1)
        assert written == r.html
        assert f'href="{file}"' in index


def test_cli_report_into_a_folder_writes_report_html(tmp_path):
    """-o DIR, the convention of every command (issue 26): report.html inside."""
    res = CliRunner().invoke(app, ["report", str(example_dir() / "gear_pair.toml"), "-o",
                                   str(tmp_path), "-s", "modal"])  # fmt: skip
    assert res.exit_code == 0 and (tmp_path / "report.html").is_file(), res.output


def test_write_index_links_reports(reports, tmp_path):
    pairs = [(tmp_path / f"{k}.html", reports[k]) for k in ("gear_pair", "khv")]
    text = write_index(pairs, tmp_path / "index.html").read_text()
    parse(text)
    assert text.count("<tr>") == 3  # header + two reports
    assert Path(pairs[0][0]).name in text


def test_design_inputs_carry_units_and_the_assumptions_in_force(reports):
    # the papers' choices recorded in docs/assumptions.md, by drive family
    assert "Paper 000" in reports["nutation_double_sided"].section("design").blocks[-1].html
    assert "Paper 004" in reports["khv_kinematics"].section("design").blocks[-1].html
    assert "Paper 003" in reports["cycloid_ball"].section("design").blocks[-1].html
    assert "Paper 00" not in reports["gear_pair"].html.split('id="design"')[1].split(
        "</section>")[0]  # fmt: skip
    blocks = reports["nutation_double_sided"].section("design").blocks
    html = next(b.html for b in blocks if 'data-table="inputs"' in b.html)
    row = html.split("<td>input_speed</td>")[1].split("</tr>")[0]
    assert "1500 rpm" in row and "rad/s" in row and "157.0796" in row


def test_given_contact_result_is_reported_with_its_numbers(tmp_path):
    """A small real LTCA (rigid teeth, 5 positions, as tests/test_contact_plot.py) saved
    to a file and handed to the report: the table's numbers are its summary's."""
    from reducerlab.analysis.contact import contact_analysis

    path = example_dir() / "nutation_surface.toml"
    res = contact_analysis(rl.load_design(path), 1, torque=19.1, positions=5, order=2,
                           rigid=True)  # fmt: skip
    nc = res.save(tmp_path / "contact.nc")
    r = report(path, results=[nc], only=["contact"])
    page = parse(r.html)
    assert page.sections["contact"] == "ok"
    summ = res.summary()
    got = [row[0] for row in page.tables["contact"] if row]
    assert got[0] == summ["k_mean"]
    assert got[1] == summ["te_peak_to_peak"] * 1e6
    assert "another design" not in r.html  # same design: no warning
    with pytest.raises(ReducerlabError, match="the report takes"):
        report(path, results=[modal(rl.build_model(rl.load_design(path)))])


def test_given_gear_pair_contact_fills_its_mesh_and_refuses_another_design(tmp_path):
    """A gear_pair's contact result handed to the report (it failed with "mesh1: unknown
    field": the k(t) went to a nutation drive's [meshN] table): the contact section is
    built, the report's dynamics take the contact's k(t) in [mesh]'s
    stiffness_harmonics; a result of other teeth is refused naming the field, while a
    field of the lumped model only (the mesh damping) is not one the contact depends on."""
    from reducerlab.analysis.contact import contact_analysis, design_with_mesh

    path = example_dir() / "gear_pair.toml"
    res = contact_analysis(rl.load_design(path), 1, torque=60.0, positions=5, order=2,
                           rigid=True)  # fmt: skip
    nc = res.save(tmp_path / "contact.nc")
    r = report(path, results=[nc], only=["contact"])
    assert parse(r.html).sections["contact"] == "ok", r.section("contact").error
    amp, phase = res.harmonics()
    assert r.design.mesh.stiffness == pytest.approx(res.mean_stiffness)
    assert r.design.mesh.stiffness_harmonics == pytest.approx(amp)
    assert r.design.mesh.stiffness_phases == pytest.approx(phase)
    assert report(path, overrides=["mesh.damping=700 N*s/m"], results=[nc],
                  only=["contact"]).design.mesh.damping == 700.0  # fmt: skip
    refused = r"contact\.nc was computed for .*pinion\.teeth 25 ≠ 26"
    with pytest.raises(ReducerlabError, match=refused):
        report(path, overrides=["pinion.teeth=26"], results=[nc], only=["contact"])
    # contact --write-design: the same table and field names, a valid design file
    out = tmp_path / "filled.toml"
    out.write_text(design_with_mesh(path, res))
    assert rl.load_design(out).mesh.stiffness_harmonics == pytest.approx(amp, rel=1e-5)


def test_regime_map_asked_by_the_design(tmp_path):
    """[report.regime_map] on the KHV drive, a 3 x 2 grid of short runs: the report's
    classes are those of the API's regime map."""
    from reducerlab.analysis.parameters import parse_values
    from reducerlab.analysis.regime_map import regime_map

    text = (example_dir() / "khv_rattle.toml").read_text().split("[report.bifurcation]")[0]
    text += ('\n[report.regime_map]\nx = "gears.x1=0.5,0.65,0.8"\n'
             'y = "input_speed=1100 rpm,1300 rpm"\nperiods = 60\nkeep = 16\n')  # fmt: skip
    path = tmp_path / "rm.toml"
    path.write_text(text)
    r = report(path, only=["regime-map"])
    page = parse(r.html)
    assert page.sections["regime-map"] == "ok", r.section("regime-map").error
    d = rl.load_design(path)
    x = parse_values("gears.x1", "0.5,0.65,0.8")
    y = parse_values("input_speed", "1100 rpm,1300 rpm")
    api = regime_map(d, x, y, periods=60, keep=16)
    assert r.section("regime-map").values["classes"] == [
        sorted(set(np.asarray(api.labels()).ravel().tolist()))
    ]


def test_every_report_is_under_1_5_mb_beside_its_shared_plotly(reports, tmp_path):
    """Issue 32: a drive's report under 1.5 MB (plotly.js shared in the folder, the
    figures as palette PNGs: tests/test_report_size.py), every bundled example's."""
    from reducerlab.reporting import PLOTLY_FILE

    for name, r in reports.items():
        page = r.write(tmp_path / f"{name}.html", plotly=tmp_path / PLOTLY_FILE)
        assert page.stat().st_size < 1.5e6, (name, page.stat().st_size)
