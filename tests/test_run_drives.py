"""``reducerlab run`` on drives without tooth surfaces (issue 27): the chain they
support (torque flow, modes, response under load, verdict, report), the same verdict
as ``check``; a design without a load or a model is answered clearly."""

from __future__ import annotations

import json

import pytest

from reducerlab.analysis.verdict import verdict
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.pipeline import run, run_plan


def test_khv_runs_to_the_checks_verdict(tmp_path):
    path = example_dir() / "khv.toml"
    res = run(path, tmp_path / "out")
    assert [(s.name, s.status) for s in res.stages] == [("response line 1", "computed")]
    assert not res.ok  # paper 004's drive at 1500 rpm: teeth apart (docs/paper_004_regimes.md)
    direct = verdict(load_design(path))
    assert [r["text"] for r in res.verdict.reasons] == [r["text"] for r in direct.reasons]
    saved = json.loads((tmp_path / "out" / "verdict.json").read_text())
    assert saved["ok"] is False
    assert (tmp_path / "out" / "report.html").stat().st_size > 0
    again = run(path, tmp_path / "out", write_report=False)
    assert [s.status for s in again.stages] == ["cached"]


def test_the_plan_names_every_stage_of_the_flagship():
    d = load_design(example_dir() / "nutation_double_sided.toml")
    names = [name for _, name in run_plan(d)]
    assert names[:6] == ["compliance gear 2", "compliance gear 1", "contact pair 1",
                         "compliance gear 4", "compliance gear 3", "contact pair 2"]  # fmt: skip
    assert names[-5:] == [f"body modes gear {g}" for g in range(1, 5)] + ["report"]
    assert "response line 2" in names


def test_a_design_with_surfaces_needs_a_load(tmp_path):
    with pytest.raises(ReducerlabError, match=r"no load at its operating point.*output_torque"):
        run(example_dir() / "nutation_surface.toml", tmp_path, overrides=["output_torque=0"])
