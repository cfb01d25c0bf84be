"""``run``: one design at its operating point through every link of the chain the
drive supports, to one verdict and one report (issue 27).

The chain: the torque flow (the operating point's load to every mesh, by virtual work
through the drive's kinematics) -> the loaded tooth contact of each gear pair at its
own torque, with the FE tooth-root stress (designs with tooth surfaces) -> optionally
the pair's loaded-TE torque sweep and flank modification layout (a KHV drive's load
sharing against torque) -> the contact's k(t) in the lumped model ->
modes, complex modes and Campbell diagram -> the nonlinear response at the operating
point under load, every mesh line -> the gear bodies' FE modes -> the verdict (resonance,
nonlinear response, bodies, consistency of the models) -> one report with every
section. Each stage is cached by what it depends on (:mod:`.stages`, :mod:`.store`):
a second run of an unchanged design reads every stage, and changing damping recomputes
no finite-element model and no contact.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..design import Design
from ..errors import ReducerlabError
from ..threads import with_compute_threads
from .consistency import body_consistency, stiffness_consistency
from .datasheet import datasheet_stages
from .optional import (
    SHARING_STAGE,
    SharingSettings,
    check_optional,
    dask_context,
    optional_settings,
    pair_torque,
    partial_writer,
    sharing_stage,
)
from .stages import (
    ContactSettings,
    LayoutSettings,
    Stage,
    SweepSettings,
    body_inputs,
    body_stage,
    compliance_names,
    compliance_stage,
    contact_stage,
    layout_stage,
    response_stage,
    te_sweep_stage,
)
from .store import Store

__all__ = ["RunResult", "run", "run_plan"]

Progress = Callable[[str, float], None]
"""``progress(description, fraction of the whole run)``."""

#: Seconds each stage takes on the 2-core reference machine (benchmarks/RESULTS.md):
#: the weights of the run's overall fraction (and so of its ETA).
WEIGHTS = {
    "compliance": 36.0,
    "contact": 12.0,
    # the optional stages: measured against the contact in the same run (docs/run.md:
    # the sweep about a contact's time, the default layout about three)
    "te_sweep": 12.0,
    "layout": 38.0,
    # the KHV load sharing: the unloaded clearances of every tooth pair, then a sweep
    "sharing": 15.0,
    "body": 32.0,
    "response": 60.0,
    "dynamics": 15.0,
    "report": 25.0,
}


@dataclass
class RunResult:
    """Everything one run computed.

    Attributes
    ----------
    design : Design
        The design as given.
    model_design : Design
        The design the dynamics used: the given one with each contact's k(t) in its
        mesh (``[meshN]`` mean, harmonics and phases of paper 000's Eq. 8; a KHV
        drive's ``[mesh]``).
    flow : TorqueFlow or None
        The operating point's torques at every mesh.
    contacts, bodies : dict
        Pair -> ContactResult (with the FE tooth-root stress when the contact settings
        ask for it: ``root_stress``); gear -> BodyModalResult.
    responses : list of ResponseResult
        One per mesh line, at the operating point.
    verdict : Verdict
    stages : list of Stage
        What was computed, read from the cache or given, with the seconds it took.
    report : Path or None
        The report file.
    built : Report or None
        The report itself (its sections and their values).
    files : list of Path
        Every file written into the output folder.
    seconds : float
    te_sweeps, layouts : dict
        Pair -> TESweepResult; pair -> LayoutResult (the optional stages; empty when
        not asked for).
    sharing : SharingResult or None
        A KHV drive's load sharing against torque (the optional stage; None when not
        asked for).
    datasheet : list of Result
        The datasheet's efficiency (and a KHV drive's accuracy under load), when asked.
    """

    design: Design
    model_design: Design
    flow: Any
    contacts: dict[int, Any]
    bodies: dict[int, Any]
    responses: list[Any]
    verdict: Any
    stages: list[Stage]
    report: Path | None = None
    built: Any = None
    files: list[Path] = field(default_factory=list)
    seconds: float = 0.0
    te_sweeps: dict[int, Any] = field(default_factory=dict)
    layouts: dict[int, Any] = field(default_factory=dict)
    sharing: Any = None
    datasheet: list[Any] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """The verdict: no risk found."""
        return bool(self.verdict.ok)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready record of the run: stages and verdict."""
        return {
            "design": self.design.source,
            "ok": self.ok,
            "seconds": round(self.seconds, 3),
            "stages": [s.to_dict() for s in self.stages],
            "verdict": self.verdict.to_dict(),
        }


def run_plan(
    design: Design,
    bodies: bool = True,
    te_sweep: bool = False,
    layout: bool = False,
    sharing: bool = False,
) -> list[tuple[str, str]]:
    """``(stage kind, name)`` of every stage a run of ``design`` goes through, in order
    (``te_sweep``, ``layout``: with those optional stages of each pair; ``sharing``:
    with a KHV drive's load sharing, after its pair's compliance, computed for it when
    the design asks for no contact)."""
    from ..drives import has_model

    plan: list[tuple[str, str]] = []
    pairs = _pairs(design)
    for p in pairs:
        plan += [("compliance", name) for name in compliance_names(design, p)]
        plan.append(("contact", f"contact pair {p}"))
        if te_sweep:
            plan.append(("te_sweep", f"te sweep pair {p}"))
        if layout:
            plan.append(("layout", f"layout pair {p}"))
    if sharing and design.type == "khv":
        if 1 not in pairs:
            plan += [("compliance", name) for name in compliance_names(design, 1)]
        plan.append(("sharing", SHARING_STAGE))
    if has_model(design):
        plan.append(("dynamics", "modes and Campbell diagram"))
        plan += [("response", f"response line {j + 1}") for j in range(_lines(design))]
    if bodies:
        plan += [("body", f"body modes gear {g}") for g in _body_gears(design)]
    plan.append(("report", "report"))
    return plan


def _pairs(design: Design) -> list[int]:
    """Gear pairs whose loaded contact the run computes: every pair of a design with
    tooth surfaces; a KHV drive's pair with ``[mesh] stiffness = "contact"`` (docs/run.md)."""
    if design.has_tooth_surfaces:
        return list(range(1, design.gear_count // 2 + 1))
    if getattr(design, "contact_stiffness", False):
        return [1]
    return []


def _body_gears(design: Design) -> list[int]:
    """Gears whose FE body modes the run computes: those of a design with tooth surfaces."""
    return list(range(1, design.gear_count + 1)) if design.has_tooth_surfaces else []


def _lines(design: Design) -> int:
    """Mesh lines of the design's model: one per gear pair whose contact the run
    computes (known before the contact fills a ``stiffness = "contact"``, which the
    model cannot be built without), else counted on the model."""
    if _pairs(design):
        return len(_pairs(design))
    from ..drives import build_model

    return int(build_model(design).nonlinear().G.shape[0])


class _Tracker:
    """The run's overall fraction from the stages' weights: stages read from the cache
    count nothing, so the ETA is that of the work left."""

    def __init__(self, plan: list[tuple[str, str]], sink: Progress | None) -> None:
        self.weight = {name: WEIGHTS[kind] for kind, name in plan}
        self.total = sum(self.weight.values()) or 1.0
        self.done = 0.0
        self.sink = sink

    def skip(self, name: str) -> None:
        """A stage that costs nothing (read from the cache)."""
        self.total -= self.weight.pop(name, 0.0)
        self.total = max(self.total, 1e-9)

    def report(self, description: str, fraction: float) -> None:
        if self.sink is None:
            return
        stage = description.split(":")[0]
        w = self.weight.get(stage, 0.0)
        self.sink(description, min(1.0, (self.done + w * fraction) / self.total))

    def finish(self, name: str) -> None:
        self.done += self.weight.pop(name, 0.0)
        if self.sink is not None:
            self.sink(name, min(1.0, self.done / self.total))


@with_compute_threads
def run(
    target: Design | str | Path,
    output: str | Path | None = None,
    *,
    overrides: Sequence[str] = (),
    cache: str | Path | None = None,
    contact: ContactSettings | None = None,
    bodies: bool = True,
    body_sizes: tuple[float | None, float | None] = (None, None),
    response: dict[str, Any] | None = None,
    te_sweep: int | SweepSettings | None = None,
    layout: bool | LayoutSettings = False,
    sharing: int | SharingSettings | None = None,
    datasheet: bool = False,
    scheduler: Any = None,
    progress: Progress | None = None,
    write_report: bool = True,
) -> RunResult:
    """Take a design at its operating point through the whole chain.

    Parameters
    ----------
    target : Design or path
        The design (or its TOML file, with ``overrides``).
    output : path, optional
        Folder for the report (``report.html``), the verdict (``verdict.json``), the
        run record (``run.json``) and every stage's result (netCDF); none written
        without it.
    overrides : sequence of str
        ``PATH=VALUE`` settings for a design file (as ``--set``).
    cache : path, optional
        The stage cache; default ``OUTPUT/cache`` (a run without output and cache caches
        nothing between runs).
    contact : ContactSettings, optional
        The contact grid (default: ``contact_analysis``'s) and whether the contact
        computes the FE tooth-root stress (default yes: ``docs/run.md``, its cost).
    bodies : bool
        Compute the gear bodies' FE modes (designs with tooth surfaces).
    body_sizes : (float or None, float or None)
        Element sizes ``(tooth, body)`` of the gear-body meshes (m); None: the default
        (:func:`~reducerlab.analysis.gear_bodies.body_mesh_sizes`).
    response : dict, optional
        Keyword arguments of :func:`~reducerlab.analysis.response.response` (periods,
        keep, history, accuracy...).
    te_sweep : int or SweepSettings, optional
        The loaded-TE torque sweep of every pair (``analysis.te_sweep``) at that many
        torques from 0 to 1.5 times the pair's operating torque (an int, 2..41), or
        with its settings; None (default): none. Written as ``te_sweep-pairN.nc`` and
        ``.txt``; the positions done so far as ``te_sweep-pairN.partial.txt`` while it
        runs.
    layout : bool or LayoutSettings
        The flank modification layout of every pair (``analysis.layout``) at its
        operating torque (true: the default search); false (default): none. Written as
        ``layout-pairN.nc`` and ``.txt``; the candidates so far as
        ``layout-pairN.partial.txt`` while it runs.
    sharing : int or SharingSettings, optional
        A KHV design's load sharing against torque (``analysis.khv_sharing``, its
        internal pair) at that many torques from 0 to 1.5 times the planet's operating
        torque (an int, 2..41), or with its settings; None (default): none. On the
        compliance stage's tooth models (computed for it under ``stiffness = "iso"``).
        Written as ``sharing-pair1.nc`` and ``.txt``; the positions so far as
        ``sharing-pair1.partial.txt`` while it runs. Another drive type is refused.
    datasheet : bool
        Also the datasheet's contact stages on the run's tooth models
        (:func:`.datasheet.datasheet_stages`: the efficiency with the starting and
        back-driving torque, a KHV or nutation drive's transmission accuracy under
        load), in the report's Datasheet section, written as ``efficiency.nc`` and
        ``accuracy.nc``.
    scheduler : str or dask.distributed.Client, optional
        Run the independent finite-element work (tooth compliance, gear bodies) on a
        Dask cluster; here, one after the other, without.
    progress : callable, optional
        ``progress(description, fraction)`` with the fraction of the whole run.
    write_report : bool
        Build the HTML report (needs ``output``).

    Returns
    -------
    RunResult
    """
    import tempfile

    from ..analysis.contact import design_with_contact
    from ..analysis.torque_flow import torque_flow
    from ..drives import has_model, load_design

    t0 = time.perf_counter()
    sweep, lay, share = optional_settings(te_sweep, layout, sharing)
    if contact is not None and not isinstance(contact, ContactSettings):
        raise ReducerlabError(f"contact: must be a ContactSettings; got {contact!r}")
    design = target if isinstance(target, Design) else load_design(target, overrides)
    settings = contact or ContactSettings()
    # response()'s defaults written out: the same run with or without them has one key
    response = {"periods": 600, "keep": 100, "history": 20, **(response or {})}
    out_dir = None if output is None else Path(output)
    if cache is not None:
        store = Store(cache)
    elif out_dir is not None:
        store = Store(out_dir / "cache")
    else:
        store = Store(tempfile.mkdtemp(prefix="reducerlab-run-"))
    flow = torque_flow(design)
    pairs = _pairs(design)
    check_optional(design, pairs, settings, sweep, lay, share)
    share_torque = None if share is None else pair_torque(flow, 1)  # no load: refused now
    plan = run_plan(design, bodies, sweep is not None, lay is not None, share is not None)
    track = _Tracker(plan, progress)
    stages: list[Stage] = []

    def record(st: Stage) -> None:
        stages.append(st)
        if st.status == "cached":
            track.skip(st.name)
        else:
            track.finish(st.name)

    with dask_context(scheduler) as client:
        submit = None if client is None else client.submit
        body_futures = {}
        gears = _body_gears(design) if bodies else []
        if gears and client is not None:  # every body not stored, at once
            from ..analysis.body_modal import body_modal
            from ..analysis.gear_bodies import body_mesh_sizes

            body_futures = {
                g: client.submit(body_modal, design, g, convergence=False,
                                 sizes=body_mesh_sizes(design, g, *body_sizes))
                for g in gears
                if not store.has("body", store.key("body", body_inputs(design, g, body_sizes)))
            }  # fmt: skip
        contacts: dict[int, Any] = {}
        sweeps: dict[int, Any] = {}
        layouts: dict[int, Any] = {}
        comps: dict[int, Any] = {}
        for p in pairs:
            torque = pair_torque(flow, p)
            comp, sts = compliance_stage(store, design, p, settings, track.report, submit)
            comps[p] = comp
            for st in sts:
                record(st)
            res, st = contact_stage(store, design, p, torque, settings, comp, track.report)
            record(st)
            contacts[p] = res
            if sweep is not None:
                partial = partial_writer(out_dir, f"te_sweep-pair{p}.partial.txt")
                res, st = te_sweep_stage(store, design, p, torque, settings, sweep, comp,
                                         track.report, partial)  # fmt: skip
                record(st)
                sweeps[p] = res
                if out_dir is not None:
                    (out_dir / f"te_sweep-pair{p}.partial.txt").unlink(missing_ok=True)
            if lay is not None:
                partial = partial_writer(out_dir, f"layout-pair{p}.partial.txt")
                res, st = layout_stage(store, design, p, torque, settings, lay, comp,
                                       track.report, partial)  # fmt: skip
                record(st)
                layouts[p] = res
                if out_dir is not None:
                    (out_dir / f"layout-pair{p}.partial.txt").unlink(missing_ok=True)
        shared = None
        if share is not None:  # a KHV drive: its pair's tooth models, computed if not yet
            if 1 not in comps:
                comps[1], sts = compliance_stage(store, design, 1, settings, track.report,
                                                 submit)  # fmt: skip
                for st in sts:
                    record(st)
            partial = partial_writer(out_dir, "sharing-pair1.partial.txt")
            shared, st = sharing_stage(store, design, share_torque, settings, share, comps[1],
                                       track.report, partial)  # fmt: skip
            record(st)
            if out_dir is not None:
                (out_dir / "sharing-pair1.partial.txt").unlink(missing_ok=True)
        model_design = design_with_contact(design, contacts.values())
        sheet: list[Any] = []
        if datasheet:  # on the run's tooth models; computed on the report's design
            sheet, sts = datasheet_stages(store, model_design, comps, settings, track.report)
            for st in sts:
                record(st)
        responses: list[Any] = []
        if has_model(model_design):
            track.finish("modes and Campbell diagram")  # computed by the verdict below
            lines = sum(kind == "response" for kind, _ in plan)  # counted once, in the plan
            for j in range(lines):
                res, st = response_stage(store, model_design, j, response, track.report)
                record(st)
                responses.append(res)
        body_results: dict[int, Any] = {}
        for g in gears:
            res, st = body_stage(store, design, g, track.report, body_futures.get(g), body_sizes)
            record(st)
            body_results[g] = res
    reasons = stiffness_consistency(design, contacts) + body_consistency(
        design, body_results, model_design.thresholds.consistency
    )
    evidence = {
        "design": model_design.hash,
        "stages": [st.key for st in stages],
        "reasons": reasons,
    }
    verdict_key = store.key("verdict", evidence)
    stored = store.get("verdict", verdict_key, extra=True)
    if stored is not None:
        verdict = stored[1]
    else:
        verdict = _verdict(model_design, responses, body_results, reasons, contacts)
        store.put("verdict", verdict_key, evidence, extra=verdict)
    result = RunResult(
        design, model_design, flow, contacts, body_results, responses, verdict, stages,
        te_sweeps=sweeps, layouts=layouts, sharing=shared, datasheet=sheet,
    )  # fmt: skip
    if out_dir is not None:
        body_keys = [st.key for st in stages if st.name.startswith("body modes")]
        memo = _SectionMemo(store, verdict_key, body_keys)
        _write(result, out_dir, write_report, track.report, t0, memo)
    track.finish("report")
    result.seconds = time.perf_counter() - t0
    return result


def _verdict(
    design: Design,
    responses: list[Any],
    bodies: dict[int, Any],
    reasons: list[dict[str, Any]],
    contacts: dict[int, Any],
) -> Any:
    """The verdict from every piece of evidence of the run: with the contacts' FE
    tooth-root stress beside the rating's permissible stress
    (``analysis.contact_rootstress.root_stress_reasons``)."""
    from ..analysis.components import ComponentModes
    from ..analysis.contact_rootstress import root_stress_reasons
    from ..analysis.verdict import verdict

    if any("root_stress" in c.data for c in contacts.values()):
        from ..analysis.capacity_reasons import rateable
        from ..analysis.rating import load_capacity

        rating = None
        if rateable(design):
            try:
                rating = load_capacity(design)
            except ReducerlabError:  # said by the capacity reasons; the peak stays a note
                rating = None
        reasons = [*reasons, *root_stress_reasons(contacts, rating)]
    components = [ComponentModes.from_body_modal(r) for _, r in sorted(bodies.items())]
    return verdict(design, responses=responses, components=components, extra_reasons=reasons)


class _SectionMemo:
    """The report's sections in the stage cache (:class:`~reducerlab.reporting.SectionMemo`).

    A section's key is the report's context (design hash, file text, overrides), the
    verdict's key (which covers the model design and every stage's key: what each given
    result was computed from) and the section's id; the gear-body section reads nothing
    but the body results given to the report (their tables and mode-shape renders), so
    its key is the body stages' keys alone, and a run that changes only the dynamics
    (damping) reuses its renders. The datasheet reads the model design alone (its
    torsion test), so its key is the context (the model design's hash) alone."""

    #: Sections keyed on the body stages alone; on the report's context alone.
    BODY_ONLY, DESIGN_ONLY = ("bodies",), ("datasheet",)

    def __init__(self, store: Store, verdict_key: str, body_keys: list[str]) -> None:
        self.store, self.verdict_key, self.body_keys = store, verdict_key, body_keys

    def _key(self, sid: str, context: str) -> tuple[str, dict[str, Any]]:
        if sid in self.BODY_ONLY:
            inputs: dict[str, Any] = {"section": sid, "bodies": self.body_keys}
        elif sid in self.DESIGN_ONLY:
            inputs = {"section": sid, "context": context}
        else:
            inputs = {"section": sid, "context": context, "evidence": self.verdict_key}
        return self.store.key("section", inputs), inputs

    def load(self, sid: str, context: str) -> Any:
        key, _ = self._key(sid, context)
        got = self.store.get("section", key, extra=True)
        return None if got is None else got[1]

    def save(self, sid: str, context: str, section: Any) -> None:
        key, inputs = self._key(sid, context)
        self.store.put("section", key, inputs, extra=section)


def _write(
    result: RunResult,
    out_dir: Path,
    write_report: bool,
    report: Progress,
    t0: float,
    memo: _SectionMemo | None = None,
) -> None:
    """The run's files, moved into ``out_dir`` together: every stage's result, the
    verdict, the run record and the report."""
    from ..io import OutputSet, stamp

    files = OutputSet(out_dir, "-o")
    names = []
    with files:
        for p, r in result.contacts.items():
            names.append(f"contact-pair{p}.nc")
            r.save(files.path(names[-1]))
        for g, r in result.bodies.items():
            names.append(f"body-gear{g}.nc")
            r.save(files.path(names[-1]))
        for j, r in enumerate(result.responses):
            names.append(f"response-line{j + 1}.nc")
            r.save(files.path(names[-1]))
        for r in result.datasheet:
            names.append(f"{'efficiency' if r.kind == 'efficiency' else 'accuracy'}.nc")
            r.save(files.path(names[-1]))
        optional = (
            ("te_sweep", result.te_sweeps),
            ("layout", result.layouts),
            ("sharing", {} if result.sharing is None else {1: result.sharing}),
        )
        for stem, results in optional:
            for p, r in results.items():
                names.append(f"{stem}-pair{p}.nc")
                r.save(files.path(names[-1]))
                names.append(f"{stem}-pair{p}.txt")
                files.path(names[-1]).write_text(r.table() + "\n")
        prov = stamp(result.model_design.provenance)
        names.append("verdict.json")
        files.path("verdict.json").write_text(
            json.dumps({**result.verdict.to_dict(), **prov}, indent=2, default=str) + "\n"
        )
        if write_report:
            from ..reporting import report as build_report

            report("report", 0.0)
            given = [*result.contacts.values(), *result.bodies.values(), *result.responses,
                     *result.te_sweeps.values(), *result.layouts.values(),
                     *([] if result.sharing is None else [result.sharing]),
                     *result.datasheet]  # fmt: skip
            rep = build_report(
                result.model_design,
                results=given,
                verdict=result.verdict,
                progress=lambda d, k, n: report(f"report: {d}", k / max(n, 1)),
                memo=memo,
            )
            names.append("report.html")
            shared = None
            if rep.plotly_js:  # the folder's shared plotly.js (reporting.PLOTLY_FILE)
                from ..reporting import PLOTLY_FILE

                names.append(PLOTLY_FILE)
                shared = files.path(PLOTLY_FILE)
            rep.write(files.path("report.html"), plotly=shared)
            result.built = rep
        result.seconds = time.perf_counter() - t0  # the whole run, its files but this one
        names.append("run.json")
        files.path("run.json").write_text(
            json.dumps({**result.to_dict(), **prov}, indent=2, default=str) + "\n"
        )
    result.files = [out_dir / n for n in names]
    result.report = out_dir / "report.html" if write_report else None
