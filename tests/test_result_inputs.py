"""Another design's results are never used silently (issue 26, item 3): every result
records the design inputs it depends on (``inputs``, :mod:`reducerlab.inputs`), and
``check --body-modes`` and ``report --with`` refuse a result whose inputs differ from
the design's, naming the fields."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import reducerlab as rl
from reducerlab.analysis.body_modal import BodyModalResult
from reducerlab.cli import app
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.inputs import check_inputs, differences, inputs_of
from reducerlab.reporting import report
from reducerlab.results import Result, provenance

runner = CliRunner()
SURFACE = example_dir() / "nutation_surface.toml"
DOUBLE = example_dir() / "nutation_double_sided.toml"
GEAR_PAIR = example_dir() / "gear_pair.toml"


def body_file(path, design, gear: int, freqs=(40000.0, 41000.0)):
    """A body-modal result of ``design``'s gear ``gear`` as body_modal stamps it (no FE
    run: the frequencies are the test's)."""
    n = len(freqs)
    ds = xr.Dataset(
        {
            "frequency": ("mode", np.asarray(freqs, float)),
            "type": ("mode", np.array(["bending"] * n, dtype=object)),
            "nodal_diameters": ("mode", np.full(n, 2)),
            "nodal_circles": ("mode", np.zeros(n, int)),
            "family": ("mode", np.arange(n)),
            "change": ("mode", np.full(n, np.nan)),
        },
        coords={"mode": np.arange(1, n + 1)},
        attrs={**provenance(design.provenance), "gear": gear, "boundary": "free"},
    )
    return BodyModalResult(ds).save(path)


def edited(tmp_path, source, old: str, new: str, name: str = "edited.toml"):
    text = source.read_text()
    assert old in text
    p = tmp_path / name
    p.write_text(text.replace(old, new, 1))
    return p


def test_saved_results_carry_their_inputs(tmp_path):
    d = rl.load_design(SURFACE)
    r = Result.load(body_file(tmp_path / "b.nc", d, 2))
    rec = json.loads(r.attrs["inputs"])
    assert rec["type"] == "nutation" and rec["gear2.teeth"] == d.gear2.teeth
    assert "surface.face_width" in rec and "material.density" in rec
    assert "input_speed" not in rec and "name" not in rec  # a gear body needs neither
    assert r.attrs["inputs_digest"]
    # a result of a whole model records the whole design (its title aside)
    m = rl.modal(rl.build_model(rl.load_design(GEAR_PAIR)))
    rec = json.loads(Result.load(m.save(tmp_path / "m.nc")).attrs["inputs"])
    assert any(k.startswith("pinion.") for k in rec) and "name" not in rec


def test_matching_body_modes_are_accepted(tmp_path):
    d = rl.load_design(SURFACE)
    nc = body_file(tmp_path / "body_modal.nc", d, 2)
    r = runner.invoke(app, ["check", str(SURFACE), "--body-modes", str(nc)])
    assert r.exit_code == 0, r.output
    assert "BODY" in r.output and "gear 2" in r.output
    # a field the gear body does not depend on (the operating speed) may differ
    other = edited(tmp_path, SURFACE, "input_speed", "input_speed = '1400 rpm'\n#")
    r = runner.invoke(app, ["check", str(other), "--body-modes", str(nc)])
    assert r.exit_code in (0, 1) and "computed for" not in r.output, r.output


def test_another_designs_body_modes_are_refused_by_check(tmp_path):
    """The issue's case: nutation_surface's gear 2 given to gear_pair.toml said
    "BODY gear 2 ..." and judged with it."""
    nc = body_file(tmp_path / "body_modal.nc", rl.load_design(SURFACE), 2)
    r = runner.invoke(app, ["check", str(GEAR_PAIR), "--body-modes", str(nc)])
    assert r.exit_code == 2, r.output
    assert "body_modal.nc was computed for gear 2 of" in r.output
    assert "nutation_surface.toml (type nutation)" in r.output
    assert "type 'nutation' ≠ 'gear_pair'" in r.output
    assert "BODY" not in r.output and "Traceback" not in r.output


def test_an_edited_design_is_refused_naming_the_field(tmp_path):
    d = rl.load_design(SURFACE)
    nc = body_file(tmp_path / "body_modal.nc", d, 2)
    # the same file name, the face width changed (as a user edits a design)
    p = edited(tmp_path, SURFACE, 'face_width = "10 mm"', 'face_width = "12 mm"',
               "nutation_surface.toml")  # fmt: skip
    r = runner.invoke(app, ["check", str(p), "--body-modes", str(nc)])
    assert r.exit_code == 2, r.output
    assert "surface.face_width 0.01 ≠ 0.012" in r.output
    # gear 2's teeth (with its mean radius, the mate's and the angle kept consistent)
    more = d.with_values(
        {
            "gear2.teeth": 27,
            "gear2.mean_radius": 28.6878e-3 * 27 / 26,
            "gear1.teeth": 29,
            "gear1.mean_radius": 30.8946e-3 * 29 / 28,
        }
    )
    with pytest.raises(ReducerlabError, match=r"gear1\.mean_radius .*gear1\.teeth 28 ≠ 29"):
        check_inputs(Result.load(nc), more, "b.nc")
    # the material of the bodies
    with pytest.raises(ReducerlabError, match=r"material\.density 7850 ≠ 7800"):
        check_inputs(Result.load(nc), d.with_values({"material.density": 7800.0}), "b.nc")


def test_another_gears_inputs(tmp_path):
    """A gear's modes depend on its own blank and its pair, not on another gear's blank:
    gear 1's file stays valid when gear 3's blank changes, gear 4's does not when gear
    4's bore changes; and a double-sided design's gear 3 does not exist in a
    single-sided one."""
    d = rl.load_design(DOUBLE)
    g1 = Result.load(body_file(tmp_path / "g1.nc", d, 1))
    g4 = Result.load(body_file(tmp_path / "g4.nc", d, 4))
    g3 = Result.load(body_file(tmp_path / "g3.nc", d, 3))
    changed = d.with_values({"gear3.blank": {"bore": 0.03}})
    check_inputs(g1, changed, "g1.nc")  # accepted
    # the example's gear 3 sits on a 52 mm bore (its blank fitted to paper 000 Table 1)
    with pytest.raises(ReducerlabError, match=r"gear 3 of .*gear3\.blank\.bore 0\.052 ≠ 0\.03"):
        check_inputs(g3, changed, "g3.nc")
    with pytest.raises(ReducerlabError, match=r"g4\.nc was computed for gear 4.*gear4\.blank"):
        check_inputs(g4, d.with_values({"gear4.blank": {"bore": 0.02}}), "g4.nc")
    # gear 1's cone angle follows from every gear's mean radius (no nutation_angle)
    with pytest.raises(ReducerlabError, match=r"gear4\.mean_radius"):
        check_inputs(g1, d.with_values({"gear4.mean_radius": 0.0452}), "g1.nc")
    single = rl.load_design(SURFACE)
    with pytest.raises(ReducerlabError, match=r"g3\.nc was computed for gear 3"):
        check_inputs(g3, single, "g3.nc")


def test_report_refuses_what_check_refuses(tmp_path):
    nc = body_file(tmp_path / "body_modal.nc", rl.load_design(SURFACE), 2)
    with pytest.raises(ReducerlabError, match=r"type 'nutation' ≠ 'gear_pair'"):
        report(GEAR_PAIR, results=[nc], only=["bodies"])
    r = runner.invoke(
        app, ["report", str(GEAR_PAIR), "--with", str(nc), "-o", str(tmp_path / "r.html")]
    )
    assert r.exit_code == 2 and "computed for gear 2" in r.output, r.output
    assert not (tmp_path / "r.html").exists()
    # the matching file is taken
    rep = report(SURFACE, results=[nc], only=["bodies"])
    assert not rep.failed and "40000" in rep.section("bodies").blocks[-1].html


def test_results_without_a_record_and_edited_records(tmp_path):
    d = rl.load_design(SURFACE)
    nc = body_file(tmp_path / "b.nc", d, 2)
    # a file written before the record: checked through the design it recorded
    with xr.open_dataset(nc) as ds:
        old = ds.load()
    del old.attrs["inputs"], old.attrs["inputs_digest"]
    old.to_netcdf(tmp_path / "old.nc")
    check_inputs(Result.load(tmp_path / "old.nc"), d, "old.nc")
    with pytest.raises(ReducerlabError, match="gear_pair"):
        check_inputs(Result.load(tmp_path / "old.nc"), rl.load_design(GEAR_PAIR), "old.nc")
    # no design recorded at all: refused, never taken on trust
    for k in ("design", "design_hash", "source"):
        old.attrs.pop(k, None)
    old.to_netcdf(tmp_path / "bare.nc")
    r = runner.invoke(app, ["check", str(SURFACE), "--body-modes", str(tmp_path / "bare.nc")])
    assert r.exit_code == 2 and "carries no record of the design" in r.output, r.output
    # a record edited by hand
    with xr.open_dataset(nc) as ds:
        ed = ds.load()
    rec = json.loads(ed.attrs["inputs"])
    rec["gear2.teeth"] += 1
    ed.attrs["inputs"] = json.dumps(rec, sort_keys=True)
    ed.attrs["design_hash"] = "0"
    ed.to_netcdf(tmp_path / "ed.nc")
    with pytest.raises(ReducerlabError, match="does not match its digest"):
        check_inputs(Result.load(tmp_path / "ed.nc"), d, "ed.nc")


def test_differences_put_the_type_first():
    diff = differences({"a": 1, "type": "x", "b": 2}, {"a": 1, "type": "y", "c": 3})
    assert [k for k, _, _ in diff] == ["type", "b", "c"]
    d = json.loads(rl.load_design(GEAR_PAIR).provenance["design"])
    assert inputs_of("bifurcation", d, {}) == inputs_of("modal", d, {})
