"""The verdict an engineer can trust (issue 27): one object that says whether a drive is
at risk over its operating range and at its operating point, and why.

:func:`verdict` joins

* the resonance check over the operating range (:func:`.resonance.resonance_check`),
  each crossing or near miss weighted by how strongly its excitation drives its mode
  (:mod:`.participation`: mesh strain-energy share for the mesh orders, forward-whirl
  share for the input rotation), unstable modes, and the gear-body modes crossed by
  the excitations ranked by margin;
* the nonlinear response at the operating point (:func:`.response.response`, every
  mesh line): dynamic load factor, tooth separation, back-side impacts and the motion
  class of its Poincaré points (:func:`.motion.classify`);
* the load capacity at the design's load (:mod:`.capacity_reasons`: ISO 6336 / the
  bevel pairs' virtual cylindrical gears; a safety factor below its minimum is a risk),
* reasons a caller adds (``extra_reasons``, a later ``run`` pipeline's consistency
  checks),

judged against the design's ``[check]`` table (:class:`~reducerlab.design.Thresholds`;
defaults and their basis in ``docs/assumptions.md``). The API, ``reducerlab check`` and
the design report show the same :class:`Verdict`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np

from ..design import Design, Thresholds
from ..design_files import validate_design
from ..errors import DesignError, DivergenceError, ReducerlabError, names_source
from ..model import Model
from ..numformat import fmt
from ..units import RPM
from .body_reasons import body_reasons
from .components import ComponentModes
from .reasons import plain, reason
from .resonance import ResonanceResult, format_check, percent, resonance_check

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .response import ResponseResult

__all__ = ["STATUSES", "Thresholds", "Verdict", "check_reasons", "operating_responses", "verdict"]

#: The status of a reason, in the order the verdict lists them.
STATUSES = ("risk", "note", "ok")

#: What each threshold must be, for the errors.
RULES = {
    "margin": "a fraction in (0, 1)",
    "mesh_strain_share": "a fraction in [0, 1]",
    "forward_whirl_share": "a fraction in [0, 1]",
    "dynamic_load_factor": "a number >= 1",
    "separation": "a fraction in [0, 1)",
    "back_impacts_risk": "true or false",
    "non_periodic_risk": "true or false",
}


def as_thresholds(given: Thresholds | Mapping[str, Any] | None, base: Thresholds) -> Thresholds:
    """The thresholds a verdict uses: ``given`` (a :class:`Thresholds`), or ``base``
    (the design's ``[check]`` table) with the fields of a mapping changed; a bad value
    raises :class:`ReducerlabError` naming the field and its rule."""
    if given is None:
        return base
    if isinstance(given, Thresholds):
        return given
    if not isinstance(given, Mapping):
        raise ReducerlabError(
            f"thresholds: must be a Thresholds or a mapping of its fields, got "
            f"{type(given).__name__}"
        )
    unknown = sorted(str(k) for k in given if k not in RULES)
    if unknown:
        raise ReducerlabError(
            f"thresholds: unknown field(s) {', '.join(unknown)} (allowed: {', '.join(RULES)})"
        )
    for name, value in given.items():
        try:
            validate_design(Thresholds, {name: value}, "thresholds")
        except DesignError:
            raise ReducerlabError(
                f"thresholds: {name} must be {RULES[name]}, got {value!r}"
            ) from None
    return validate_design(Thresholds, {**base.model_dump(), **given}, "thresholds")


def check_reasons(reasons: Sequence[Mapping[str, Any]], what: str = "extra_reasons") -> list[dict]:
    """Reasons in the verdict's format, checked (see :func:`verdict`): each a mapping with
    ``rule`` and ``text`` (strings, the text one line), ``status`` in :data:`STATUSES`,
    ``value`` and ``threshold`` (any JSON value, None when there is none)."""
    if isinstance(reasons, Mapping | str) or not isinstance(reasons, Sequence):
        raise ReducerlabError(f"{what}: must be a list of reason dicts")
    out = []
    for i, r in enumerate(reasons):
        where = f"{what}[{i}]"
        if not isinstance(r, Mapping):
            raise ReducerlabError(f"{where}: must be a dict, got {type(r).__name__}")
        missing = [k for k in ("rule", "status", "text", "value", "threshold") if k not in r]
        if missing:
            raise ReducerlabError(f"{where}: missing key(s) {', '.join(missing)}")
        if not (isinstance(r["rule"], str) and r["rule"]):
            raise ReducerlabError(f"{where}: rule must be a non-empty string")
        if r["status"] not in STATUSES:
            raise ReducerlabError(
                f"{where} ({r['rule']}): status must be one of {', '.join(STATUSES)}, "
                f"got {r['status']!r}"
            )
        if not (isinstance(r["text"], str) and r["text"].strip() and "\n" not in r["text"]):
            raise ReducerlabError(f"{where} ({r['rule']}): text must be one non-empty line")
        out.append({k: plain(v) for k, v in r.items()})
    return out


@dataclass
class Verdict:
    """Whether a drive is at risk, and why (:func:`verdict`).

    Attributes
    ----------
    reasons : list of dict
        Every finding and every check passed, risks first (the format is in
        :func:`verdict`).
    thresholds : Thresholds
        What counted as a risk.
    resonance : ResonanceResult or None
        The resonance check it judged, with the Campbell diagram it used (None for a
        design without an operating speed).
    responses : list of ResponseResult
        The nonlinear responses at the operating point it judged, one per mesh line.
    title : str
        The design's name.
    """

    reasons: list[dict[str, Any]]
    thresholds: Thresholds
    resonance: ResonanceResult | None = None
    responses: list[ResponseResult] = field(default_factory=list)
    title: str = ""
    speed_rpm: float = math.nan

    @property
    def ok(self) -> bool:
        """No reason is a risk."""
        return not self.risks

    @property
    def risks(self) -> list[dict[str, Any]]:
        """The reasons whose status is ``"risk"``."""
        return [r for r in self.reasons if r["status"] == "risk"]

    def to_dict(self) -> dict[str, Any]:
        """The verdict as a plain dict (JSON-ready): the resonance check's keys
        (:func:`.resonance.resonance_check`; its own ``ok`` as ``resonance_ok``) and
        ``ok``, ``reasons``, ``thresholds`` and ``responses`` (per mesh line: ``line``,
        ``dynamic_load_factor``, ``separation_fraction``, ``back_contact_fraction``,
        ``back_impacts_per_period``, ``impact_class``, ``motion``)."""
        out: dict[str, Any] = {}
        if self.resonance is not None:
            out.update(self.resonance.to_dict())
            out["resonance_ok"] = self.resonance.ok
        out.update(
            ok=self.ok,
            title=self.title,
            operating_speed_rpm=plain(self.speed_rpm),
            reasons=[dict(r) for r in self.reasons],
            thresholds=self.thresholds.model_dump(),
            responses=[_response_summary(r) for r in self.responses],
        )
        return out

    def table(self, *, resonance: bool = True) -> str:
        """The verdict as text: the resonance check's rows (``resonance=True``,
        :func:`.resonance.format_check`), then one line per reason and the verdict."""
        t = self.thresholds
        lines = [format_check(self.resonance), ""] if resonance and self.resonance else []
        at = (
            f" (operating speed {fmt(self.speed_rpm, 'speed')} rpm)"
            if math.isfinite(self.speed_rpm)
            else ""
        )
        lines.append(f"Verdict: {self.title}{at}")
        lines.append(
            f"  thresholds: margin {100 * t.margin:g} %, mesh strain >= "
            f"{100 * t.mesh_strain_share:g} %, forward whirl >= {100 * t.forward_whirl_share:g} %, "
            f"dynamic load factor <= {t.dynamic_load_factor:g}, teeth apart <= "
            f"{100 * t.separation:g} %, back-side impacts "
            f"{'risk' if t.back_impacts_risk else 'note'}, non-periodic motion "
            f"{'risk' if t.non_periodic_risk else 'note'}"
        )
        for r in self.reasons:
            lines.append(f"  {r['status'].upper():<5} {r['rule']}: {r['text']}")
        counts = {s: sum(r["status"] == s for r in self.reasons) for s in STATUSES}
        tally = f"{counts['risk']} risk(s), {counts['note']} note(s), {counts['ok']} passed"
        lines.append(f"verdict: {'OK, no risk' if self.ok else 'RISK'} ({tally})")
        return "\n".join(lines)

    def plot(self, *, fmax: float | None = None) -> Figure:
        """The Campbell diagram the verdict judged (:meth:`ResonanceResult.plot`)."""
        if self.resonance is None:
            raise ReducerlabError("verdict: no resonance check (the design has no speed)")
        return self.resonance.plot(fmax=fmax)


def _response_summary(res: ResponseResult) -> dict[str, Any]:
    a = res.data.attrs
    return {k: plain(a.get(k)) for k in (
        "line", "dynamic_load_factor", "mean_mesh_force", "separation_fraction",
        "back_contact_fraction", "back_impacts_per_period", "impact_class", "forcing_hz",
    )} | {"motion": motion_class(res)}  # fmt: skip


def motion_class(res: ResponseResult) -> str:
    """The motion class of a response's Poincaré points (:func:`.motion.classify`,
    without a Lyapunov exponent: chaos reads as ``"quasi-periodic"``, both not
    periodic); ``"not excited"`` when its deflection varies by round-off only."""
    from .motion import classify
    from .response import NOISE_M

    if float(np.ptp(res.data["delta"].values)) <= NOISE_M:
        return "not excited"
    return classify(res.data["poincare_delta"].values, 0.0, float(res.data.attrs["forcing_hz"]))


def operating_responses(
    model: Model, options: Mapping[str, Any] | None = None
) -> tuple[list[ResponseResult], list[dict[str, Any]]]:
    """The nonlinear response at the model's speed on every mesh line, and the notes
    (in the reason format) where there is none to judge: no mesh line, a model at rest,
    nothing periodic to force it. A response that diverges is a risk reason.

    Parameters
    ----------
    model : Model
        At the operating speed.
    options : mapping, optional
        Keyword arguments of :func:`.response.response` (``periods``, ``keep``, ...).
    """
    from ..dynamics.coordinates import to_system
    from ..dynamics.systems import forcing_period
    from .response import response

    flat = model.nonlinear()
    if flat.G.shape[0] == 0:
        text = "no mesh line: no nonlinear response to judge (tooth load, separation, motion)"
        return [], [reason("response", "note", text, None, None)]
    if model.speed == 0:
        return [], [reason("response", "note", "the model is at rest: no response at an "
                            "operating speed to judge", None, None)]  # fmt: skip
    opts = dict(options or {})
    if "period" not in opts:
        try:
            forcing_period(to_system(model))
        except ReducerlabError:
            text = ("nothing in the model varies periodically (constant mesh stiffness, no "
                    "transmission error or periodic load): the operating point is the static "
                    "equilibrium, its dynamic load is not judged")  # fmt: skip
            return [], [reason("response", "note", text, None, None)]
    out = []
    for line in range(flat.G.shape[0]):
        try:
            out.append(response(model, line=line, **opts))
        except DivergenceError as exc:
            name = flat.line_names[line]
            return out, [reason("response", "risk", f"mesh line '{name}': the response at the "
                                 f"operating speed diverges ({exc})", None, None,
                                 line=name)]  # fmt: skip
    return out, []


def _response_reasons(res: ResponseResult, t: Thresholds) -> list[dict[str, Any]]:
    """The reasons one mesh line's response gives (see :func:`verdict`)."""
    a = res.data.attrs
    name = str(a["line"])
    head = f"mesh line '{name}'"
    more = {"line": name}
    out = []
    motion = motion_class(res)
    dlf = float(a["dynamic_load_factor"])
    if not math.isfinite(dlf):
        force = fmt(a["mean_mesh_force"], "force")
        out.append(reason("dynamic-load-factor", "note",
                           f"{head}: no mean load (mean mesh force {force} N): "
                           "the dynamic load factor is undefined and the tooth load is not "
                           "judged; give the drive a load torque", None,
                           t.dynamic_load_factor, **more))  # fmt: skip
    else:
        bad = dlf > t.dynamic_load_factor
        out.append(reason("dynamic-load-factor", "risk" if bad else "ok",
                           f"{head}: dynamic load factor max|F|/mean F {fmt(dlf)} "
                           f"{'above' if bad else 'within'} the limit {t.dynamic_load_factor:g}",
                           dlf, t.dynamic_load_factor, **more))  # fmt: skip
    sep = float(a["separation_fraction"])
    bad = sep > t.separation
    text = (f"{head}: teeth apart {percent(sep)} % of the time ({a['impact_class']}), "
            f"{'above' if bad else 'within'} the limit {100 * t.separation:g} %"
            if sep > 0 else f"{head}: the teeth never separate")  # fmt: skip
    out.append(reason("separation", "risk" if bad else "ok", text, sep, t.separation, **more))
    back = float(a["back_impacts_per_period"])
    if back > 0:
        out.append(reason("back-impacts", "risk" if t.back_impacts_risk else "note",
                           f"{head}: back-side impacts, {fmt(back)} per forcing period (back "
                           f"flanks in contact {percent(float(a['back_contact_fraction']))} % "
                           "of the time: double-sided impact)", back, 0.0, **more))  # fmt: skip
    else:
        out.append(reason("back-impacts", "ok", f"{head}: no back-side impact", back, 0.0,
                           **more))  # fmt: skip
    keep = int(res.data.sizes["point"])
    if motion == "not excited":
        out.append(reason("motion", "note", f"{head}: not excited at the operating speed (the "
                           "mesh deflection varies by round-off only)", motion, None,
                           **more))  # fmt: skip
    elif motion.startswith("period-"):
        sub = motion != "period-1"
        text = (f"{head}: {motion} motion (a subharmonic response, {motion[7:]} forcing "
                "periods)" if sub else f"{head}: period-1 motion")  # fmt: skip
        out.append(reason("motion", "note" if sub else "ok", text, motion, None, **more))
    elif motion == "unsettled":
        out.append(reason("motion", "note", f"{head}: still settling after the run (its "
                           f"{keep} Poincaré points converge): run more periods to judge "
                           "the motion", motion, None, **more))  # fmt: skip
    else:
        out.append(reason("motion", "risk" if t.non_periodic_risk else "note",
                           f"{head}: non-periodic motion (no period <= 12 in its last {keep} "
                           "Poincaré points: quasi-periodic or chaotic)", motion, None,
                           **more))  # fmt: skip
    return out


def _row_more(row: dict[str, Any], keys: Sequence[str]) -> dict[str, Any]:
    return {k: row[k] for k in keys if k in row}


def _resonance_reasons(res: ResonanceResult, t: Thresholds) -> list[dict[str, Any]]:
    """The reasons of a resonance check: one per (mode, excitation) pair (its crossing,
    else its closest approach), body-mode findings ranked by margin, unstable modes."""
    out = []
    hz, rpm = partial(fmt, kind="frequency"), partial(fmt, kind="speed")
    lo, hi = res["speed_range_rpm"]
    rng = f"{rpm(lo)} rpm" if lo == hi else f"{rpm(lo)}-{rpm(hi)} rpm"
    seen = set()
    keys = ("mode", "excitation", "speed_rpm", "whirl", "mesh_share", "mesh_lines",
            "forward_share", "excited", "distance")  # fmt: skip
    for kind, rows in (("crossing", res["crossings"]), ("near", res["near"])):
        for r in rows:
            pair = (r["mode"], r["excitation"])
            if pair in seen:
                continue
            seen.add(pair)
            f = r.get("frequency_hz", r.get("natural_hz"))
            whirl = f", {r['whirl']} whirl" if r.get("whirl") else ""
            where = (f"crosses {r['excitation']} at {rpm(r['speed_rpm'])} rpm" if kind == "crossing"
                     else f"within {percent(r['distance'])} % of {r['excitation']} "
                     f"({hz(r['excitation_hz'])} Hz) at {rpm(r['speed_rpm'])} rpm")  # fmt: skip
            head = f"mode {r['mode']} ({hz(f)} Hz{whirl}) {where}"
            if "mesh_share" in r:
                value, limit = r["mesh_share"], t.mesh_strain_share
                why = (f"mesh strain {percent(value)} % in {_lines(r['mesh_lines'])}"
                       if r["excited"] else f"not mesh-excited (mesh strain {percent(value)} % "
                       f"< {100 * limit:g} %)")  # fmt: skip
            elif "forward_share" in r:
                value, limit = r["forward_share"], t.forward_whirl_share
                why = ("no lateral whirl: counted (runout, unbalance)" if value is None
                       else f"forward whirl {percent(value)} %" if r["excited"]
                       else f"not excited by unbalance (forward whirl {percent(value)} % < "
                       f"{100 * limit:g} %)")  # fmt: skip
            else:
                value, limit, why = None, None, "counted"
            out.append(reason(f"resonance-{kind}", "risk" if r.get("excited", True) else "note",
                               f"{head}: {why}", value, limit, frequency_hz=f,
                               **_row_more(r, keys)))  # fmt: skip
    if not seen:
        out.append(reason("resonance", "ok", f"no natural frequency crosses or comes within "
                           f"{100 * res['margin']:g} % of an excitation over {rng}", 0,
                           res["margin"]))  # fmt: skip
    out += body_reasons(res)
    worst: dict[int, dict[str, Any]] = {}
    for u in res["stability"]["unstable"]:
        w = worst.setdefault(u["mode"], {**u, "lo": u["speed_rpm"], "hi": u["speed_rpm"], "n": 0})
        w["n"] += 1
        w["lo"], w["hi"] = min(w["lo"], u["speed_rpm"]), max(w["hi"], u["speed_rpm"])
        if u["growth_rate"] > w["growth_rate"]:
            w.update(growth_rate=u["growth_rate"], frequency_hz=u["frequency_hz"])
    for m, w in sorted(worst.items()):
        text = (f"mode {m} ({hz(w['frequency_hz'])} Hz) grows at {w['n']} speed(s) in "
                f"{rpm(w['lo'])}-{rpm(w['hi'])} rpm, up to {fmt(w['growth_rate'])} "
                "1/s")  # fmt: skip
        out.append(reason("unstable", "risk", text, w["growth_rate"], 0.0, mode=m))
    if not worst:
        out.append(reason("unstable", "ok", f"every mode is stable over {rng}", 0.0, 0.0))
    return out


def _lines(names: Sequence[str]) -> str:
    """``"mesh line 'mesh'"``, ``"mesh lines 'a', 'b'"``."""
    return f"mesh line{'s' if len(names) > 1 else ''} " + ", ".join(f"'{n}'" for n in names)


@names_source
def verdict(
    target: Design | Model,
    *,
    resonance: ResonanceResult | None = None,
    responses: Sequence[ResponseResult] | None = None,
    components: Sequence[ComponentModes] | ComponentModes = (),
    extra_reasons: Sequence[Mapping[str, Any]] = (),
    thresholds: Thresholds | Mapping[str, Any] | None = None,
    run_response: bool = True,
    speed_range: tuple[float, float] | None = None,
    response_options: Mapping[str, Any] | None = None,
    capacity: bool = True,
    rating: Any = None,
) -> Verdict:
    """Whether a drive is at risk over its operating range and at its operating point.

    Parameters
    ----------
    target : Design or Model
    resonance : ResonanceResult, optional
        A resonance check already made (the report's, ``check``'s); default
        :func:`.resonance.resonance_check` with the thresholds' margin and shares, over
        ``speed_range`` with ``components``. Its rows are judged again with the
        thresholds' shares; its margin must be at least theirs (the near misses it did
        not list cannot be judged), and rows beyond the thresholds' margin are left out.
    responses : sequence of ResponseResult, optional
        Responses at the operating point already computed (one per mesh line); default
        :func:`operating_responses` when ``run_response``.
    components : ComponentModes or sequence of them
        Gear-body modes for the resonance check.
    extra_reasons : sequence of dict
        Reasons the caller adds, in the format below (checked: :func:`check_reasons`).
    thresholds : Thresholds or mapping, optional
        What counts as a risk; default the design's ``[check]`` table
        (:attr:`Design.thresholds`); a mapping changes fields of that table.
    run_response : bool
        Compute the nonlinear response at the operating point when ``responses`` is not
        given (false: the verdict judges the resonance check only, and says so).
    speed_range : tuple of float, optional
        ``(min, max)`` input speeds (rad/s) of the resonance check.
    response_options : mapping, optional
        Keyword arguments of :func:`.response.response` (``periods``, ``keep``, ...).
    capacity : bool
        Judge the load capacity of a design's gear pairs (:mod:`.capacity_reasons`;
        designs of the types the rating covers).
    rating : RatingResult, optional
        A load capacity rating already made (e.g. with method A,
        ``load_capacity(..., method="A")``); default the method B rating at the
        design's load.

    Returns
    -------
    Verdict
        ``ok`` when no reason is a risk. Each reason is a dict with at least

        * ``rule``: what was checked (``"resonance-crossing"``, ``"resonance-near"``,
          ``"resonance"``, ``"unstable"``, ``"body-crossing"``, ``"body-near"``,
          ``"body-coincidence"``, ``"body"``, ``"dynamic-load-factor"``,
          ``"separation"``, ``"back-impacts"``, ``"motion"``, ``"response"``,
          ``"capacity"``, or a caller's own);
        * ``status``: ``"risk"`` (makes the verdict fail), ``"note"`` (said, not
          failed: a crossing the excitation does not drive, an unloaded drive) or
          ``"ok"`` (a check passed);
        * ``text``: one line, numbers in Hz, rpm and %;
        * ``value`` and ``threshold``: the number judged and its limit in SI or as a
          fraction (a share 0..1, a dynamic load factor, a growth rate in 1/s; the motion
          class as a string), None where there is none;

        and context where it applies: ``mode``, ``excitation``, ``speed_rpm``,
        ``frequency_hz``, ``whirl``, ``mesh_share``, ``mesh_lines``, ``forward_share``,
        ``excited``, ``distance``, ``line`` (the mesh line), ``component``.
    """
    from ..drives import design_and_model

    design, model = design_and_model(target, "verdict")
    base = design.thresholds if design is not None else Thresholds()
    t = as_thresholds(thresholds, base)
    extra = check_reasons(extra_reasons)
    title = (design.name if design is not None else "") or model.name or ""
    if speed_range is not None:
        hi = speed_range[1]
    else:
        hi = design.operating_range()[1] if design is not None else model.speed
    reasons: list[dict[str, Any]] = []
    if resonance is None and hi > 0:
        resonance = resonance_check(target, margin=t.margin, speed_range=speed_range,
                                    components=components, mesh_strain_share=t.mesh_strain_share,
                                    forward_whirl_share=t.forward_whirl_share)  # fmt: skip
    elif resonance is not None:
        resonance = _rejudge(resonance, t)
    if resonance is None:
        reasons.append(reason("resonance", "note", "no operating speed: no resonance check "
                               "(give the design a speed or speed range)", None, None))  # fmt: skip
    else:
        reasons += _resonance_reasons(resonance, t)
    if responses is None and run_response:
        responses, notes = operating_responses(model, response_options)
        reasons += notes
    elif responses is None:
        responses = []
        reasons.append(reason("response", "note", "the nonlinear response at the operating "
                               "point was not computed: tooth load, separation and motion "
                               "not judged", None, None))  # fmt: skip
    responses = list(responses)
    from .response import ResponseResult

    for r in responses:
        if not isinstance(r, ResponseResult):
            raise ReducerlabError(
                f"verdict: responses must be ResponseResult objects, got {type(r).__name__}"
            )
        reasons += _response_reasons(r, t)
    if capacity and design is not None:
        from .capacity_reasons import capacity_reasons

        reasons += capacity_reasons(design, rating)
    reasons += extra
    reasons.sort(key=lambda r: STATUSES.index(r["status"]))
    return Verdict(reasons, t, resonance, responses, title, model.speed * RPM)


def _rejudge(res: ResonanceResult, t: Thresholds) -> ResonanceResult:
    """A given resonance check judged with the thresholds: its rows' ``excited`` from
    the thresholds' shares, its near misses within the thresholds' margin."""
    from .resonance import excited

    same = (res["margin"], res.get("mesh_strain_share"), res.get("forward_whirl_share"))
    if same == (t.margin, t.mesh_strain_share, t.forward_whirl_share):
        return res
    if t.margin > res["margin"] * (1 + 1e-12):
        raise ReducerlabError(
            f"verdict: the resonance check was made with margin {res['margin']:g}, "
            f"less than the thresholds' {t.margin:g}: make it again with that margin"
        )
    out = dict(res)
    out["crossings"] = [dict(r) for r in res["crossings"]]
    out["near"] = [dict(r) for r in res["near"] if r["distance"] <= t.margin]
    for r in out["crossings"] + out["near"]:
        r["excited"] = excited(r, t.mesh_strain_share, t.forward_whirl_share)
    out.update(margin=t.margin, mesh_strain_share=t.mesh_strain_share,
               forward_whirl_share=t.forward_whirl_share)  # fmt: skip
    if "component_near" in out:
        out["component_near"] = [r for r in res["component_near"] if r["distance"] <= t.margin]
        out["coincidences"] = [r for r in res["coincidences"] if r["distance"] <= t.margin]
    findings = [r for r in out["crossings"] + out["near"] if r["excited"]]
    body = out.get("component_crossings") or out.get("component_near") or out.get("coincidences")
    out["ok"] = not findings and not res["stability"]["unstable"] and not body
    return ResonanceResult(out, res.campbell, res.components)
