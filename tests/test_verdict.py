"""The verdict an engineer can trust (issue 27): crossings weighted by how strongly the
excitation drives the mode, the nonlinear response at the operating point, thresholds
from the design's ``[check]`` table, and one :class:`Verdict` behind the API, ``reducerlab
check`` and the report."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.impacts import mesh_mode
from reducerlab.analysis.resonance import resonance_check
from reducerlab.analysis.verdict import Thresholds, Verdict, verdict
from reducerlab.cli import app
from reducerlab.drives import build_model, load_design
from reducerlab.errors import DesignError, ReducerlabError
from reducerlab.examples import example_dir
from reducerlab.reporting import report
from reducerlab.units import RPM

runner = CliRunner()
EX = example_dir()
GEAR = EX / "gear_pair.toml"
DISC = EX / "spinning_disc.toml"

#: The disc's tilt: diametral and polar moments (kg m^2), tilt stiffness (N m/rad).
J_D, J_P, K_T = 0.04, 0.07, 3e4


def _by(v: Verdict, rule: str, **match) -> list[dict]:
    return [
        r for r in v.reasons if r["rule"] == rule and all(r.get(k) == x for k, x in match.items())
    ]


def _brief(reasons) -> list[tuple]:
    return [(r["rule"], r["status"], r["text"]) for r in reasons]


# -- the nonlinear response at the operating point -----------------------------------


@pytest.fixture(scope="module")
def khv():
    return {name: verdict(load_design(EX / f"{name}.toml")) for name in ("khv", "khv_rattle")}


def test_khv_with_separating_teeth_is_not_green(khv):
    """examples/khv.toml at 1500 rpm: no crossing in its single-speed range, but the
    teeth separate every mesh period (docs/paper_004_regimes.md, reading A: apart 24-35 %
    of the time at 1500 rpm over x1 = 0.416-0.835; the example's x1 = 0.626 lies
    between) and the mesh force peaks at over three times its mean."""
    v = khv["khv"]
    assert not v.ok and v.resonance.ok  # green about resonance, red about the load
    (dlf,) = _by(v, "dynamic-load-factor")
    assert dlf["status"] == "risk" and dlf["value"] > 3.0 and dlf["threshold"] == 1.5
    (sep,) = _by(v, "separation")
    assert sep["status"] == "risk" and 0.24 <= sep["value"] <= 0.35
    assert "teeth apart" in sep["text"] and "%" in sep["text"]
    assert _by(v, "motion")[0]["value"] == "period-1"
    assert {r["rule"] for r in v.risks} == {"dynamic-load-factor", "separation"}


def test_khv_rattle_is_not_green(khv):
    """examples/khv_rattle.toml at 1230 rpm: double-sided impacts (docs/paper_004_regimes.md:
    double-sided impacts between 350 and 1250 rpm) and quasi-periodic motion (the tongue
    at 1160-1280 rpm for x1 below about 0.675)."""
    v = khv["khv_rattle"]
    assert not v.ok
    risks = {r["rule"] for r in v.risks}
    assert risks == {"dynamic-load-factor", "separation", "back-impacts", "motion"}
    (motion,) = _by(v, "motion")
    assert motion["value"] == "quasi-periodic" and "non-periodic" in motion["text"]
    (back,) = _by(v, "back-impacts")
    assert back["value"] > 0 and "double-sided" in back["text"]
    assert _by(v, "dynamic-load-factor")[0]["value"] > 4.0


@pytest.mark.parametrize("name", ["khv", "khv_rattle"])
def test_api_cli_and_report_give_the_same_reasons(khv, name):
    v = khv[name]
    path = EX / f"{name}.toml"
    r = runner.invoke(app, ["check", str(path), "--format", "json"])
    assert r.exit_code == 1, r.output
    got = json.loads(r.stdout)
    assert got["ok"] is False and got["resonance_ok"] is True
    assert _brief(got["reasons"]) == _brief(v.reasons)
    text = runner.invoke(app, ["check", str(path)])
    assert text.exit_code == 1
    for reason in v.risks:
        assert reason["text"] in " ".join(text.output.split())
    assert "verdict: RISK" in text.output
    rep = report(path, only=["campbell", "response"])
    camp = rep.section("campbell")
    assert camp.values["ok"] is False and _brief(camp.values["reasons"]) == _brief(v.reasons)
    banner = rep.section("summary").blocks[0].html
    assert 'class="verdict risk"' in banner and "RISK" in banner
    # the response section shows the response the verdict judged
    dlf = _by(v, "dynamic-load-factor")[0]["value"]
    assert rep.section("response").values["dynamic_load_factor"] == dlf


def test_an_unloaded_drive_says_so():
    """No torque: no mean mesh force, the dynamic load factor is undefined (NaN) and the
    verdict says the load was not judged instead of passing it; the teeth float in the
    backlash (apart all the time), which is a risk."""
    v = verdict(load_design(GEAR, ["operating.torque=0 N*m"]))
    (dlf,) = _by(v, "dynamic-load-factor")
    assert dlf["status"] == "note" and dlf["value"] is None and "no mean load" in dlf["text"]
    assert _by(v, "separation")[0]["status"] == "risk"
    assert _by(v, "motion")[0]["value"] == "not excited"
    json.dumps(v.to_dict(), allow_nan=False)  # JSON-ready: NaN is None


# -- crossings weighted by the mesh strain energy ------------------------------------


@pytest.fixture(scope="module")
def gear():
    return verdict(load_design(GEAR))


def test_a_mode_without_mesh_strain_is_not_mesh_excited(gear):
    """gear_pair's mode 3 (1495 Hz) has no strain energy in the mesh (0 %): the
    transmission error cannot drive it, so its 2x mesh crossing is a note."""
    (c3,) = _by(gear, "resonance-crossing", mode=3)
    assert c3["status"] == "note" and c3["value"] < 1e-9 and "not mesh-excited" in c3["text"]
    assert c3["excitation"] == "2x mesh" and c3["mesh_lines"] == ["mesh"]
    assert c3["speed_rpm"] == pytest.approx(1495.0004 / 50 * 60, rel=1e-6)
    # the mesh-strained modes 2 (3 %) and 4 (14 %) still cross: risks
    risky = {r["mode"]: r for r in _by(gear, "resonance-crossing") if r["status"] == "risk"}
    assert set(risky) == {2, 4}
    assert risky[2]["value"] == pytest.approx(0.0305, abs=5e-4)
    assert risky[4]["value"] == pytest.approx(0.145, abs=5e-4)
    assert not gear.ok
    out = runner.invoke(app, ["check", str(GEAR)])
    assert out.exit_code == 1 and "not mesh-excited" in out.output


def test_the_mesh_strain_share_is_the_sensitivity_to_the_mesh_stiffness(gear):
    """Oracle: the share k (g . phi)^2 / (phi^T K phi) is (k / lambda) d lambda / d k
    (Lin and Parker 1999), twice the relative frequency sensitivity to the mean mesh
    stiffness that frequency_sensitivity computes by complex step."""
    from reducerlab.analysis.modal import frequency_sensitivity

    rel = frequency_sensitivity(build_model(load_design(GEAR)), ["mesh.stiffness"])
    twice = 2 * rel.data["relative"].values[:, 0]
    rows = [r for r in gear.reasons if r["rule"].startswith("resonance-")]
    assert {r["mode"] for r in rows} == {2, 3, 4}
    for r in rows:
        assert r["value"] == pytest.approx(twice[r["mode"] - 1], abs=1e-9)


def test_a_strongly_mesh_strained_crossing_is_a_risk():
    """An operating range around 4038 rpm, where 3x mesh (75 x the input) meets mode 6
    (5047 Hz), the mode that strains the mesh most (82 %, analysis.impacts.mesh_mode's
    measure): a risk, at the exact speed 2 pi f6 / 75."""
    d = load_design(GEAR)
    rng = (3900 / RPM, 4100 / RPM)
    v = verdict(d, speed_range=rng, run_response=False)
    (c6,) = _by(v, "resonance-crossing", mode=6)
    f6, share = mesh_mode(build_model(d).nonlinear(), 0)
    assert c6["status"] == "risk" and c6["value"] == pytest.approx(share, rel=1e-9)
    assert share > 0.8
    assert c6["speed_rpm"] == pytest.approx(f6 / 75 * 60, rel=1e-6)
    assert _by(v, "response")[0]["status"] == "note"  # not computed: said so
    # a share threshold above it turns it into a note
    v = verdict(d, speed_range=rng, run_response=False, thresholds={"mesh_strain_share": 0.9})
    assert _by(v, "resonance-crossing", mode=6)[0]["status"] == "note" and v.ok


# -- 1x crossings by whirl direction -------------------------------------------------


@pytest.fixture(scope="module")
def disc():
    return verdict(load_design(DISC))


def test_backward_whirl_of_an_isotropic_rotor_is_not_excited_by_unbalance(disc):
    """The isotropic disc's backward tilt whirl meets 1x at Omega = sqrt(k / (J_d + J_p))
    (Friswell et al. 2010, Ch. 3: J_d w^2 + J_p Omega w - k = 0 at w = Omega): a note,
    its forward share 0. Its translation pair (64.97 Hz, isotropic: a forward circular
    whirl lies in its eigenspace) meets 1x at 3898 rpm: a risk."""
    (back,) = _by(disc, "resonance-crossing", whirl="backward")
    assert back["status"] == "note" and back["value"] == 0.0
    assert "not excited by unbalance" in back["text"]
    assert back["speed_rpm"] == pytest.approx(math.sqrt(K_T / (J_D + J_P)) * RPM, rel=1e-3)
    trans = [r for r in _by(disc, "resonance-crossing") if r["status"] == "risk"]
    assert {r["mode"] for r in trans} == {1, 2}
    assert all(r["value"] == pytest.approx(1.0) for r in trans)
    assert _by(disc, "response")[0]["status"] == "note"  # no mesh line


def test_forward_whirl_crossing_is_a_risk():
    """A drum (J_p < J_d): its forward tilt whirl meets 1x at Omega = sqrt(k / (J_d -
    J_p)) (11 695 rpm for J_p = 0.02 kg m^2): a risk, its forward share 1."""
    jp = 0.02
    d = load_design(DISC, [f"elements.8.polar_moment={jp} kg*m^2"])
    d = d.with_values({"speed_range": [0.0, 13000 / RPM]})
    v = verdict(d, run_response=False)
    (fwd,) = _by(v, "resonance-crossing", whirl="forward")
    assert fwd["status"] == "risk" and fwd["value"] == pytest.approx(1.0, abs=1e-6)
    assert fwd["speed_rpm"] == pytest.approx(math.sqrt(K_T / (J_D - jp)) * RPM, rel=1e-3)


def test_backward_whirl_of_an_anisotropic_rotor_is_excited(disc):
    """Unequal supports in x and y make the whirls elliptical: the backward tilt whirl
    gains a forward component (2.4 % here), so unbalance excites it: a risk at the
    default 1 %, a note with a [check] forward_whirl_share of 5 %."""
    sets = ["elements.5.stiffness=3e6 N/m", "elements.7.torsional_stiffness=4.5e4 N*m/rad"]
    d = load_design(DISC, sets)
    v = verdict(d, run_response=False)
    (back,) = _by(v, "resonance-crossing", whirl="backward")
    assert back["status"] == "risk" and 0.01 < back["value"] < 0.05
    # the isotropic disc's backward whirl has none: it comes from the anisotropy
    assert _by(disc, "resonance-crossing", whirl="backward")[0]["value"] == 0.0
    lax = verdict(load_design(DISC, [*sets, "check.forward_whirl_share=0.05"]),
                  run_response=False)  # fmt: skip
    assert _by(lax, "resonance-crossing", whirl="backward")[0]["status"] == "note"


# -- thresholds ----------------------------------------------------------------------


def test_check_thresholds_change_the_outcome(khv):
    d = load_design(EX / "khv.toml", ["check.dynamic_load_factor=4", "check.separation=0.5"])
    v = verdict(d, responses=khv["khv"].responses)  # the same response, other limits
    assert v.ok, v.table()
    assert v.thresholds == Thresholds(dynamic_load_factor=4, separation=0.5)
    assert d.hash == load_design(EX / "khv.toml").hash  # [check] is not analysed
    r = runner.invoke(app, ["check", str(EX / "khv.toml"), "--set", "check.dynamic_load_factor=4",
                            "--set", "check.separation=0.5"])  # fmt: skip
    assert r.exit_code == 0, r.output
    assert "verdict: OK" in r.output
    rattle = khv["khv_rattle"]
    lax = verdict(load_design(EX / "khv_rattle.toml"), resonance=rattle.resonance,
                  responses=rattle.responses,
                  thresholds={"back_impacts_risk": False, "non_periodic_risk": False})  # fmt: skip
    assert {r["rule"] for r in lax.risks} == {"dynamic-load-factor", "separation"}
    assert _by(lax, "back-impacts")[0]["status"] == "note"
    assert _by(lax, "motion")[0]["status"] == "note"


def test_the_margin_comes_from_the_design_and_the_command_line_overrides_it():
    d = load_design(GEAR, ["check.margin=0.05"])
    v = verdict(d, run_response=False)
    assert v.resonance["margin"] == 0.05
    assert not any(r["excitation"] == "3x mesh" and r["mode"] == 2
                   for r in _by(v, "resonance-near"))  # the 7.84 % approach is gone  # fmt: skip
    assert resonance_check(d)["margin"] == 0.05  # the API reads the table too
    r = runner.invoke(app, ["check", str(GEAR), "--set", "check.margin=0.05", "--margin", "0.2",
                            "--format", "json", "--no-response"])  # fmt: skip
    got = json.loads(r.stdout)
    assert got["margin"] == 0.2 and got["thresholds"]["margin"] == 0.2
    assert got["responses"] == [] and any(x["rule"] == "response" for x in got["reasons"])


def test_a_given_resonance_check_is_judged_with_the_thresholds(gear):
    d = load_design(GEAR)
    res = gear.resonance
    strict = verdict(d, resonance=res, responses=gear.responses,
                     thresholds={"mesh_strain_share": 0.2})  # fmt: skip
    assert {r["mode"] for r in strict.risks if r["rule"].startswith("resonance")} == set()
    assert res["crossings"][0]["excited"]  # the given check is not changed
    with pytest.raises(ReducerlabError, match=r"margin 0\.1, less than the thresholds' 0\.2"):
        verdict(d, resonance=res, responses=[], thresholds={"margin": 0.2})


@pytest.mark.parametrize(
    ("setting", "message"),
    [
        ("check.margin=2", "check.margin = 2: must be less than 1"),
        ("check.margin=0", "check.margin = 0: must be greater than 0"),
        ("check.mesh_strain_share=1.5", "check.mesh_strain_share = 1.5: must be less than or"),
        ("check.dynamic_load_factor=0.8", "check.dynamic_load_factor = 0.8: must be greater"),
        ("check.separation=1", "check.separation = 1: must be less than 1"),
        ("check.back_impacts_risk=1", "check.back_impacts_risk = 1: must be true or false"),
        ("check.marginn=0.1", "check.marginn = 0.1: unknown field"),
    ],
)
def test_bad_check_values_are_refused(setting, message):
    with pytest.raises(DesignError) as exc:
        load_design(GEAR, [setting])
    assert message in str(exc.value)
    r = runner.invoke(app, ["check", str(GEAR), "--set", setting])
    assert r.exit_code == 2 and message in " ".join(r.output.split())


def test_bad_thresholds_and_reasons_from_the_api_are_refused():
    d = load_design(GEAR)
    for given, message in [
        ({"margin": 0}, "thresholds: margin must be a fraction in (0, 1), got 0"),
        ({"dynamic_load_factor": math.nan}, "dynamic_load_factor must be a number >= 1"),
        ({"nope": 1}, "thresholds: unknown field(s) nope"),
        (5, "thresholds: must be a Thresholds or a mapping"),
    ]:
        with pytest.raises(ReducerlabError, match=message.replace("(", r"\(").replace(")", r"\)")):
            verdict(d, thresholds=given, run_response=False)
    good = {"rule": "consistency", "status": "ok", "text": "x", "value": 1, "threshold": 2}
    for bad, message in [
        ({**good, "status": "fine"}, r"extra_reasons\[0\] \(consistency\): status must be one"),
        ({k: v for k, v in good.items() if k != "value"}, "missing key"),
        ({**good, "text": "two\nlines"}, "text must be one non-empty line"),
        ("text", "must be a dict"),
    ]:
        with pytest.raises(ReducerlabError, match=message):
            verdict(d, extra_reasons=[bad], run_response=False)


# -- the verdict object ---------------------------------------------------------------


def test_extra_reasons_join_the_verdict(gear):
    d = load_design(GEAR)
    extra = {"rule": "consistency", "status": "risk", "text": "the run's modes are stale",
             "value": 0.2, "threshold": 0.01}  # fmt: skip
    v = verdict(d, resonance=gear.resonance, responses=gear.responses, extra_reasons=[extra])
    assert extra in v.risks and v.reasons[0]["status"] == "risk"
    assert "RISK  consistency: the run's modes are stale" in v.table()


def test_the_verdict_is_one_json_ready_object(gear):
    d = gear.to_dict()
    assert json.loads(json.dumps(d, allow_nan=False)) == d
    assert d["ok"] is False and d["resonance_ok"] is False
    assert d["crossings"] == gear.resonance["crossings"]  # the resonance check's keys
    assert [r["status"] for r in gear.reasons] == sorted(
        (r["status"] for r in gear.reasons), key=["risk", "note", "ok"].index
    )
    for r in gear.reasons:
        assert {"rule", "status", "text", "value", "threshold"} <= set(r)
        assert r["status"] in ("risk", "note", "ok") and "\n" not in r["text"]
    (resp,) = d["responses"]
    assert resp["line"] == "mesh" and resp["motion"] == "period-1"
    assert resp["dynamic_load_factor"] == pytest.approx(1.01, abs=0.01)
    assert gear.plot().axes  # the Campbell diagram it judged
    # 5 passed: the response and resonance rules; 4 more: S_H, S_F of pinion and gear
    assert "verdict: RISK (3 risk(s), 2 note(s), 9 passed)" in gear.table()


def test_a_model_target_uses_the_default_thresholds():
    m = build_model(load_design(GEAR))
    v = verdict(m, run_response=False)
    assert v.thresholds == Thresholds()
    assert v.resonance["speed_range_rpm"] == [pytest.approx(1500.0)] * 2
    assert np.isclose(v.speed_rpm, 1500.0)


def test_body_modes_are_ranked_by_margin_and_unstable_modes_are_risks():
    """Gear-body modes: a crossing (margin 0) before a near miss, each a risk; a mode
    with negative damping: a risk naming its growth rate."""
    from dataclasses import dataclass

    from reducerlab.analysis.components import ComponentModes
    from reducerlab.model import Contribution, Dof, Element, Inertia, Model, Support

    d = load_design(GEAR)
    f_cross = 25 * 1500 / 60  # 1x mesh at 1500 rpm (Hz)
    f_near = 75 * 1800 / 60 * 1.02  # 2 % above 3x mesh at the top of the range
    body = ComponentModes("gear 1", [f_cross, f_near], ["torsional", "2 nodal diameters"])
    v = verdict(d, components=[body], run_response=False)
    ranked = [r for r in v.reasons if r["rule"].startswith("body-")]
    assert ranked[0]["rule"] == "body-crossing" and ranked[0]["value"] == 0.0
    assert ranked[0]["speed_rpm"] == pytest.approx(1500.0)
    assert [r["value"] for r in ranked] == sorted(r["value"] for r in ranked)
    near = next(r for r in ranked if r["rule"] == "body-near" and r["mode"] == 2)
    assert near["value"] == pytest.approx(0.02, rel=1e-9) and near["status"] == "risk"

    @dataclass(frozen=True)
    class NegativeDamper(Element):
        name: str = "negative damper"

        @property
        def dofs(self) -> tuple[str, ...]:
            return ("a.x",)

        def contribution(self, dofs, speed) -> Contribution:
            return Contribution(damping=np.array([[-4.0]]))

    bad = Model([Dof("a", "x")], [Inertia("a.x", 1.0), Support("a.x", 1e4, 0.0),
                                  NegativeDamper()], speed=100.0)  # fmt: skip
    v = verdict(bad, speed_range=(50.0, 100.0), run_response=False)
    (u,) = _by(v, "unstable")
    assert u["status"] == "risk" and u["value"] == pytest.approx(2.0) and "grows" in u["text"]


def test_a_repeated_body_root_is_named_once():
    """The two modes of a degenerate pair (an axisymmetric body's bending pair, split by
    its mesh by 1e-5) that cross one excitation and come near one system mode are one
    reason each, naming both modes; a distinct mode 0.5 % away stays apart."""
    from reducerlab.analysis.components import ComponentModes

    d = load_design(GEAR)
    f = 25 * 1500 / 60  # 1x mesh at 1500 rpm (Hz)
    body = ComponentModes("gear 1", [f, f * (1 + 1e-5), f * 1.005], ["bending"] * 3)
    v = verdict(d, components=[body], run_response=False)
    cross = [r for r in v.reasons if r["rule"] == "body-crossing" and r["excitation"] == "1x mesh"]
    assert [r["modes"] for r in cross] == [[1, 2], [3]]
    assert "gear 1 modes 1, 2 (bending)" in cross[0]["text"] and cross[0]["mode"] == 1
    keys = [(r["rule"], tuple(r["modes"]), r.get("excitation"), r.get("system_mode"))
            for r in v.reasons if r["rule"].startswith("body-")]  # fmt: skip
    assert len(keys) == len(set(keys))  # no reason twice
    for r in v.reasons:
        if r["rule"] == "body-coincidence":
            assert r["system_mode"] == r["system_modes"][0]
