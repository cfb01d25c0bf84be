"""``reducerlab run`` end to end on a CI-sized variant (issue 27): the single-sided
nutation drive of paper 001's tooth surfaces at its operating point, with coarse grids
(contact 15 positions, coarse FE tooth and body meshes, a short response).

Checked: every link ran and handed its output on (the torque flow's torque in the
contact, the contact's k(t) in the model, the bodies' masses in the consistency
reasons, every piece of evidence in one verdict, one report holding every section);
a second run of the unchanged design reads every stage; a changed damping recomputes
the dynamics only; the CLI, the API and verdict.json give the same verdict. Issue 29:
the contact carries the FE tooth-root stress (that of ``contact_analysis(root_stress=
True)``) into the verdict and the report's load capacity; the optional torque sweep and
modification layout run on the contact's tooth models, are cached, and land in the
folder and the report. The full
default-grid chain of the double-sided drive is timed in ``benchmarks/run_chain.py``.
"""

from __future__ import annotations

import json

import pytest
from typer.testing import CliRunner

from reducerlab.analysis.torque_flow import torque_flow
from reducerlab.cli import app
from reducerlab.examples import example_dir
from reducerlab.pipeline import ContactSettings, LayoutSettings, SweepSettings, run

EXAMPLE = example_dir() / "nutation_surface.toml"
M_N = 2e-3  # the example's normal module
# coarse: load bumps of 0.7 mm radius still fit the 4.35 mm flank; bodies at the
# coarsest sizes the mesher accepts for these teeth (a tooth size up to half the depth)
CONTACT = ContactSettings(positions=15, order=7, cell=0.1 * M_N, tooth_size=0.35 * M_N)
BODY = (1.0 * M_N, 3.0 * M_N)
RESPONSE = {"periods": 120, "keep": 60, "history": 20}  # as `run --periods 120`
KW = {"contact": CONTACT, "body_sizes": BODY, "response": RESPONSE}


@pytest.fixture(scope="module")
def first(tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "out"
    return out, run(EXAMPLE, out, **KW)


def test_every_link_ran_once(first):
    out, res = first
    names = [s.name for s in res.stages]
    assert names == ["compliance gear 2", "compliance gear 1", "contact pair 1",
                     "response line 1", "body modes gear 1", "body modes gear 2"]  # fmt: skip
    assert {s.status for s in res.stages} == {"computed"}
    for f in ("report.html", "verdict.json", "run.json", "contact-pair1.nc", "body-gear1.nc",
              "body-gear2.nc", "response-line1.nc"):  # fmt: skip
        assert (out / f).is_file(), f


def test_the_contact_carries_the_operating_torque(first):
    _, res = first
    flow = torque_flow(res.design)
    attrs = res.contacts[1].data.attrs
    assert attrs["torque_external"] == pytest.approx(flow.meshes["mesh1"].external_torque)
    assert attrs["torque_external"] > 0


def test_the_model_uses_the_contact_stiffness(first):
    _, res = first
    c = res.contacts[1]
    mesh = res.model_design.mesh1
    assert mesh.stiffness == pytest.approx(c.mean_stiffness)
    assert mesh.harmonics == pytest.approx(c.harmonics()[0])
    assert res.design.mesh1.stiffness != pytest.approx(c.mean_stiffness)
    note = [r for r in res.verdict.reasons if r["rule"] == "mesh-stiffness"]
    assert len(note) == 1
    # k_m as the text prints it: 4 significant digits (numformat, issue 32), 5e-4 relative
    shown = note[0]["text"].split("k_m = ")[1].split(" ")[0]
    assert float(shown) == pytest.approx(c.mean_stiffness, rel=5e-4)
    # the response was integrated on that model
    assert json.loads(res.responses[0].attrs["design"])["mesh1"]["stiffness"] == pytest.approx(
        c.mean_stiffness
    )


def test_the_bodies_are_checked_against_the_lumped_gears(first):
    _, res = first
    rows = [r for r in res.verdict.reasons if r["rule"] == "body-consistency"]
    assert len(rows) == 2
    for g, r in zip((1, 2), rows, strict=True):
        a = res.bodies[g].data.attrs
        fe = {"mass": (a["mass_kg"], 1e3, "g"), "J_z": (a["J_z_kg_m2"], 1e9, "g mm^2"),
              "J_x": (a["J_x_kg_m2"], 1e9, "g mm^2")}  # fmt: skip
        shown = r["text"].split("lumped ")[1].split(" ")[0]  # the worst quantity when ok
        v, s, u = fe[shown]
        # the FE body's value as printed: 4 significant digits (numformat, issue 32)
        fe_shown = r["text"].split("against the FE body's ")[1].split(" ")[0]
        assert float(fe_shown) == pytest.approx(v * s, rel=5e-4) and u in r["text"]
        gear = getattr(res.design, f"gear{g}")
        worst = max(abs(getattr(gear, q) / fe[q][0] - 1) for q in fe)
        expect = "risk" if worst > 0.10 else "ok"
        assert r["status"] == expect
        # the example's lumped gears are its FE rim rings' (issue 27, rounded values)
        assert expect == "ok" and worst < 0.005


def test_one_verdict_everywhere(first):
    out, res = first
    saved = json.loads((out / "verdict.json").read_text())
    assert saved["ok"] == res.ok
    assert [r["text"] for r in saved["reasons"]] == [r["text"] for r in res.verdict.reasons]
    html = (out / "report.html").read_text()
    for r in res.verdict.reasons:
        if r["status"] == "risk":
            assert r["rule"] in html
    for title in ("Loaded tooth contact", "Gear-body modes", "Nonlinear response"):
        assert title in html


def test_a_second_run_reads_every_stage(first):
    out, res = first
    again = run(EXAMPLE, out, **KW)
    assert {s.status for s in again.stages} == {"cached"}
    assert [s.key for s in again.stages] == [s.key for s in res.stages]
    assert again.ok == res.ok
    assert again.responses[0].attrs["dynamic_load_factor"] == pytest.approx(
        res.responses[0].attrs["dynamic_load_factor"], rel=0, abs=0
    )
    # the verdict and every report section read from the cache (summary and provenance,
    # which carry the run's date, are made again), with the numbers of the first run
    assert [r["text"] for r in again.verdict.reasons] == [r["text"] for r in res.verdict.reasons]
    built = {s.id: s for s in res.built.sections}
    reused = {s.id for s in again.built.sections if s.reused}
    assert reused == set(built) - {"summary", "provenance"}
    for s in again.built.sections:
        if s.reused:
            assert s.values.keys() == built[s.id].values.keys()
    assert 'data-reused="1"' in again.report.read_text(encoding="utf-8")


def test_changed_damping_recomputes_only_the_dynamics(first):
    out, _ = first
    res = run(EXAMPLE, out, overrides=["mesh1.damping=500 N*s/m"], **KW)
    status = {s.name: s.status for s in res.stages}
    assert status.pop("response line 1") == "computed"
    assert set(status.values()) == {"cached"}
    # the report: the gear-body section (its renders: the bodies alone) reused, every
    # section that reads the dynamics built again
    reused = {s.id for s in res.built.sections if s.reused}
    assert "bodies" in reused
    assert not reused & {"modal", "campbell", "response"}


def test_a_mesh_stiffness_from_the_contact(first):
    """``stiffness = "contact"``: the run fills the mesh from the loaded contact; the
    contact's k(t) replaces a written stiffness anyway, so the model, its response and
    its cache keys are those of the design as written, and the note says where k_m came
    from."""
    out, res = first
    sets = ["mesh1.stiffness=contact", "mesh1.harmonics=[]"]
    filled = run(EXAMPLE, out, overrides=sets, **KW)
    assert filled.design.mesh1.stiffness == "contact"
    assert filled.model_design.mesh1.stiffness == pytest.approx(
        res.contacts[1].mean_stiffness, rel=1e-12
    )
    assert filled.model_design.hash == res.model_design.hash
    assert {s.status for s in filled.stages} == {"cached"}
    (note,) = [r for r in filled.verdict.reasons if r["rule"] == "mesh-stiffness"]
    assert "k(t) from the loaded contact" in note["text"]
    assert filled.ok == res.ok


def test_the_cli_gives_the_same_verdict(first):
    out, res = first
    args = ["run", str(EXAMPLE), "-o", str(out.parent / "cli"), "--cache", str(out / "cache"),
            "--positions", "15", "--cell", "0.2 mm", "--tooth-size", "0.7 mm",
            "--body-tooth-size", "2 mm", "--body-size", "6 mm", "--periods", "120"]  # fmt: skip
    r = CliRunner().invoke(app, args)
    assert r.exit_code == (0 if res.ok else 1), r.output
    assert "computed" not in r.output  # every stage read from the API run's cache
    saved = json.loads((out.parent / "cli" / "verdict.json").read_text())
    assert [x["text"] for x in saved["reasons"]] == [x["text"] for x in res.verdict.reasons]
    for reason in res.verdict.reasons:
        assert reason["text"] in r.output


def test_sigterm_keeps_the_finished_stages(first):
    """SIGTERM in the middle of a stage: exit 143, one line saying how many stages the
    cache keeps, no output files, no half-written cache entry."""
    import os
    import signal
    import subprocess
    import sys

    out, _ = first
    cache = out / "cache"
    before = len(list(cache.glob("*.json")))
    folder = out.parent / "sigterm"
    args = [sys.executable, "-m", "reducerlab", "run", str(EXAMPLE), "-o", str(folder),
            "--cache", str(cache), "--positions", "15", "--cell", "0.2 mm", "--tooth-size",
            "0.7 mm", "--body-tooth-size", "2 mm", "--body-size", "6 mm",
            "--periods", "100000"]  # fmt: skip
    env = {**os.environ, "MPLBACKEND": "Agg"}
    proc = subprocess.Popen(args, stderr=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                            env=env)  # fmt: skip
    seen = []
    for line in proc.stderr:  # log lines: stderr is not a terminal
        seen.append(line)
        if "response line 1" in line:
            break
    proc.send_signal(signal.SIGTERM)
    _, rest = proc.communicate(timeout=120)
    text = "".join(seen) + rest
    assert proc.returncode == 143, text
    assert f"{before} finished stage(s) kept in {cache}" in text
    assert not folder.exists() or not any(folder.iterdir())
    assert not list(cache.glob(".tmp-*"))


def test_bodies_run_on_a_dask_cluster(first):
    """With a scheduler, the FE work not in the cache (here gear 2's body, whose blank
    changed) runs as Dask tasks; the rest is read from the cache."""
    distributed = pytest.importorskip("dask.distributed")

    out, _ = first
    with (
        distributed.Client(processes=False, n_workers=1, threads_per_worker=1) as client,
        distributed.get_task_stream(client) as tasks,
    ):
        res = run(EXAMPLE, out.parent / "dask", cache=out / "cache", scheduler=client,
                  overrides=["gear2.blank.rim=5 mm"], **KW)  # fmt: skip
    status = {s.name: s.status for s in res.stages}
    assert status["body modes gear 2"] == "computed"
    assert status["body modes gear 1"] == status["contact pair 1"] == "cached"
    names = [t["key"] for t in tasks.data]
    assert any(str(k).startswith("body_modal") for k in names), names
    assert res.bodies[2].data.attrs["rim_m"] == pytest.approx(5e-3)


def test_report_with_a_contact_puts_its_stiffness_in_the_dynamics(first):
    """``report --with contact.nc``: the report's model takes the contact's k(t); a
    contact of other teeth (another profile and pressure angle) is refused, naming the
    fields, never shown with a note."""
    from reducerlab.errors import ReducerlabError
    from reducerlab.reporting import report

    out, res = first
    rep = report(EXAMPLE, results=[out / "contact-pair1.nc"], only=["design"])
    assert rep.design.mesh1.stiffness == pytest.approx(res.contacts[1].mean_stiffness)
    other = ["surface.profile=double-arc", "normal_pressure_angle=24 deg"]
    with pytest.raises(ReducerlabError, match=r"normal_pressure_angle.*surface\.profile"):
        report(EXAMPLE, overrides=other, results=[out / "contact-pair1.nc"], only=["design"])


def test_the_contact_carries_the_root_stress_of_contact_analysis(first):
    """The run's root stress is ``contact_analysis(root_stress=True)``'s on the same
    inputs (the run's tooth models, torque and grid): the same solves, so equal to the
    rounding of the two runs' process split (rtol 1e-9)."""
    import numpy as np

    from reducerlab.analysis.contact import contact_analysis
    from reducerlab.results import Result

    out, res = first
    c = res.contacts[1]
    assert c.compliance is not None and all(x.fillet is not None for x in c.compliance)
    direct = contact_analysis(
        res.design, 1, torque=c.attrs["torque_external"], positions=CONTACT.positions,
        order=CONTACT.order, cell=CONTACT.cell, tooth_size=CONTACT.tooth_size,
        compliance=c.compliance, root_stress=True, workers=1,
    )  # fmt: skip
    for name in ("root_stress", "root_compressive", "root_von_mises"):
        np.testing.assert_allclose(c.data[name].values, direct.data[name].values, rtol=1e-9)
    assert c.attrs["root_stress_peak"] == pytest.approx(direct.attrs["root_stress_peak"], 1e-9)
    saved = Result.load(out / "contact-pair1.nc")
    np.testing.assert_array_equal(saved.data["root_stress"].values, c.data["root_stress"].values)
    # the verdict and the report's load capacity see it
    (why,) = [r for r in res.verdict.reasons if r["rule"] == "root-stress"]
    assert why["value"] == pytest.approx(c.attrs["root_stress_peak"])
    assert why["status"] in ("note", "risk")
    assert (why["status"] == "risk") == (why["threshold"] is not None
                                         and why["value"] > why["threshold"])  # fmt: skip
    cap = {s.id: s for s in res.built.sections}["capacity"]
    rows = [r for r in cap.values["beside"] if r[1] == "tooth-root stress (MPa)"]
    assert len(rows) == 1 and rows[0][3] == pytest.approx(c.attrs["root_stress_peak"] * 1e-6)


# the optional stages at CI size: 4 torques (0, 0.5, 1, 1.5 x the operating torque) at
# the contact's 15 positions; 2 x 2 layout candidates of 4 positions, no refinement
SWEEP = SweepSettings(loads=4)
LAYOUT = LayoutSettings(grid=2, refine=0, positions=4)


@pytest.fixture(scope="module")
def optional(first):
    out, _ = first
    folder = out.parent / "optional"
    seen: list[str] = []

    def sink(text: str, _fraction: float) -> None:
        stem = "layout" if text.startswith("layout") else "te_sweep"
        partial = folder / f"{stem}-pair1.partial.txt"
        seen.append(text + (" [partial]" if partial.is_file() else ""))

    res = run(EXAMPLE, folder, cache=out / "cache", te_sweep=SWEEP, layout=LAYOUT,
              progress=sink, **KW)  # fmt: skip
    return folder, res, seen


def test_the_optional_stages_run_on_the_cached_contact(first, optional):
    _, base = first
    folder, res, seen = optional
    status = {s.name: s.status for s in res.stages}
    assert status.pop("te sweep pair 1") == status.pop("layout pair 1") == "computed"
    assert set(status.values()) == {"cached"}  # the FE models and the contact: read back
    names = [s.name for s in res.stages]
    assert names.index("contact pair 1") < names.index("te sweep pair 1")
    # progress through the run's sink; the sweep's partial table while it ran, then gone
    assert any(t.startswith("te sweep pair 1: ") and t.endswith("[partial]") for t in seen)
    assert any(t.startswith("layout pair 1: ") and t.endswith("[partial]") for t in seen)
    assert not (folder / "te_sweep-pair1.partial.txt").exists()
    assert not (folder / "layout-pair1.partial.txt").exists()
    for f in ("te_sweep-pair1.nc", "te_sweep-pair1.txt", "layout-pair1.nc", "layout-pair1.txt"):
        assert (folder / f).is_file(), f
        assert folder / f in res.files
    # the sweep's row at the operating torque is the run's contact (the same cell and
    # tooth models: equal to round-off, analysis.te_sweep), the layout at that torque
    sw, c = res.te_sweeps[1], base.contacts[1]
    T = c.attrs["torque_external"]
    assert sw.torques == pytest.approx([0, 0.5 * T, T, 1.5 * T], rel=1e-12)
    assert sw.data["te_rotation"].values[2] == pytest.approx(c.data["loaded_te"].values, 1e-6)
    assert res.layouts[1].data.attrs["design_torque"] == pytest.approx(T, rel=1e-12)
    assert res.layouts[1].data.sizes["candidate"] == 4
    html = res.report.read_text(encoding="utf-8")
    assert "loaded transmission error against torque" in html
    assert "flank modification layout" in html


def test_the_optional_stages_are_cached(first, optional):
    out, _ = first
    folder, res, _ = optional
    again = run(EXAMPLE, folder, cache=out / "cache", te_sweep=SWEEP, layout=LAYOUT, **KW)
    assert {s.status for s in again.stages} == {"cached"}
    assert [s.key for s in again.stages] == [s.key for s in res.stages]
    assert again.te_sweeps[1].peak_to_peak == pytest.approx(res.te_sweeps[1].peak_to_peak, 0)
    # a changed sweep recomputes the sweep alone
    other = run(EXAMPLE, out.parent / "other", cache=out / "cache", te_sweep=5, **KW,
                write_report=False)  # fmt: skip
    status = {s.name: s.status for s in other.stages}
    assert status.pop("te sweep pair 1") == "computed"
    assert set(status.values()) == {"cached"}
