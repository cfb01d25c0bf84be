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


def test_the_plan_names_the_optional_stages_of_each_pair():
    d = load_design(example_dir() / "nutation_double_sided.toml")
    names = [name for _, name in run_plan(d, te_sweep=True, layout=True)]
    assert names[:10] == ["compliance gear 2", "compliance gear 1", "contact pair 1",
                          "te sweep pair 1", "layout pair 1",
                          "compliance gear 4", "compliance gear 3", "contact pair 2",
                          "te sweep pair 2", "layout pair 2"]  # fmt: skip
    assert "te sweep pair 1" not in [name for _, name in run_plan(d)]


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"te_sweep": 1}, r"te_sweep\.loads: must be an integer in 2\.\.41; got 1"),
        ({"te_sweep": True}, r"te_sweep: must be a number of torques"),
        ({"te_sweep": 4.0}, r"te_sweep: must be a number of torques"),
        ({"layout": "yes"}, r"layout: must be true, false or a LayoutSettings"),
    ],
)
def test_bad_optional_stages_are_refused_naming_the_argument(tmp_path, kw, match):
    with pytest.raises(ReducerlabError, match=match):
        run(example_dir() / "nutation_surface.toml", tmp_path / "out", **kw)
    assert not (tmp_path / "out").exists()  # refused before any work


def test_bad_settings_of_the_optional_stages_are_refused():
    from reducerlab.pipeline import ContactSettings, LayoutSettings, SweepSettings

    with pytest.raises(ReducerlabError, match=r"te_sweep\.top: must be a number in \(0, 3\]"):
        SweepSettings(top=4.0)
    with pytest.raises(ReducerlabError, match=r"te_sweep\.positions: must be an integer in 7\."):
        SweepSettings(harmonics=3, positions=6)  # 3 mesh orders need 7 positions
    with pytest.raises(ReducerlabError, match=r"layout\.grid: must be an integer in 2\.\.7"):
        LayoutSettings(grid=9)
    with pytest.raises(ReducerlabError, match=r"layout\.pressure_limit: must be a number > 0"):
        LayoutSettings(pressure_limit=-1.0)
    with pytest.raises(ReducerlabError, match=r"root_stress: must be true or false"):
        ContactSettings(root_stress="yes")  # type: ignore[arg-type]


def test_optional_stages_need_gear_pairs_and_fit_their_work_bound(tmp_path):
    from reducerlab.pipeline import SweepSettings

    with pytest.raises(ReducerlabError, match=r"te_sweep: needs a design with tooth surfaces"):
        run(example_dir() / "khv.toml", tmp_path / "a", te_sweep=4)
    with pytest.raises(ReducerlabError, match=r"layout: needs a design with tooth surfaces"):
        run(example_dir() / "khv.toml", tmp_path / "b", layout=True)
    # 41 torques x 200 positions = 8200 solves > MAX_SOLVES (4000): refused by the
    # estimate before the FE models are built
    with pytest.raises(ReducerlabError, match=r"te sweep: 200 positions x 41 torques"):
        run(example_dir() / "nutation_surface.toml", tmp_path / "c",
            te_sweep=SweepSettings(loads=41, positions=200))  # fmt: skip
    assert not (tmp_path / "c").exists()


def test_the_cli_refuses_optional_stages_on_a_drive_without_pairs(tmp_path):
    from typer.testing import CliRunner

    from reducerlab.cli import app

    args = ["run", str(example_dir() / "khv.toml"), "-o", str(tmp_path / "o"), "--te-sweep", "4"]
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 2
    assert "te_sweep: needs a design with tooth surfaces" in r.output
    r = CliRunner().invoke(app, [*args[:4], "--te-sweep", "1"])
    assert r.exit_code == 2 and "--te-sweep" in r.output


@pytest.mark.parametrize("value", ["5 kg", "-1 MPa", "nan"])
def test_the_cli_refuses_a_bad_layout_pressure_limit(tmp_path, value):
    from typer.testing import CliRunner

    from reducerlab.cli import app

    args = ["run", str(example_dir() / "nutation_surface.toml"), "-o", str(tmp_path / "o"),
            "--layout", "--pressure-limit", value]  # fmt: skip
    r = CliRunner().invoke(app, args)
    assert r.exit_code == 2, r.output
    assert "--pressure-limit" in r.output or "layout.pressure_limit" in r.output
    assert not list((tmp_path / "o").glob("*.nc"))  # refused before any stage


def test_root_stress_reasons_judge_the_static_peak_against_sigma_fp():
    """ISO 6336-3:2019 Eq. 3-5: sigma_F = sigma_F0 K_A K_v K_Fbeta K_Falpha <= sigma_FP,
    every factor >= 1: a static FE peak above sigma_FP is a risk, below it a note (never
    ok); the threshold is the smaller sigma_FP of the pair's gears."""
    import numpy as np
    import xarray as xr

    from reducerlab.analysis.contact_rootstress import root_stress_reasons

    class Contact:
        def __init__(self, peak):
            self.data = xr.Dataset(
                {"root_stress": (("gear",), np.array([peak, 0.5 * peak]))},
                attrs={"root_stress_peak": peak, "root_stress_peak_gear": "external",
                       "root_stress_peak_tooth": 0},
            )  # fmt: skip

    class Rating:
        def pairs(self):
            return {"pair 1": {}}

        def value(self, symbol, gear, pair):
            assert symbol == "sigma_FP" and pair == "pair 1"
            return {"1": 500e6, "2": 400e6}[gear]

    (low,) = root_stress_reasons({1: Contact(399e6)}, Rating())
    (high,) = root_stress_reasons({1: Contact(401e6)}, Rating())
    assert (low["status"], high["status"]) == ("note", "risk")
    assert low["threshold"] == high["threshold"] == 400e6
    (bare,) = root_stress_reasons({1: Contact(401e6)}, None)
    assert bare["status"] == "note" and bare["threshold"] is None
    plain = Contact(1.0)
    plain.data = plain.data.drop_vars("root_stress")
    assert root_stress_reasons({1: plain}, Rating()) == []  # no root stress: no reason
