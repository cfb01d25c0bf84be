"""The resonance verdict over the operating speed range (paper 000's closing check).

:func:`resonance_check` lists every crossing of a natural frequency with an excitation
line inside the range, every (mode, excitation) pair closer than a margin, the modes
that grow (complex modes at each speed) and, with gear-body modes
(:class:`~reducerlab.analysis.components.ComponentModes`, paper 000 §4), their crossings
with the excitation lines and coincidences with the system modes (paper 000 Table 5).
Its :class:`ResonanceResult` carries the Campbell diagram the verdict used: the undamped
one, or the damped, whirl-split branches of :func:`.complex_modal.complex_campbell` when
the model has gyroscopic, Coriolis or circulatory terms. The report and ``check -o``
draw that diagram (:meth:`ResonanceResult.plot`) and never compute it again.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from functools import partial
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design, Thresholds
from ..errors import ReducerlabError, names_source
from ..model import Model
from ..numformat import fmt
from ..units import RPM, TWO_PI
from .campbell import CampbellResult, campbell
from .complex_modal import ComplexCampbellResult, complex_campbell, modes_over
from .components import ComponentModes, as_components
from .excitation import operating_range
from .modal import has_skew_terms
from .participation import participation

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "ResonanceResult",
    "drive_note",
    "excited",
    "format_check",
    "format_components",
    "percent",
    "resonance_check",
]


class ResonanceResult(dict[str, Any]):
    """The verdict of :func:`resonance_check` and the Campbell diagram it used.

    A :class:`dict` (JSON-ready as it stands: ``res["ok"]``, ``res["crossings"]``,
    ``json.dumps(res)``; see :func:`resonance_check` for its keys), with

    Attributes
    ----------
    campbell : CampbellResult or ComplexCampbellResult
        The diagram the verdict read its excitation lines and crossings from: undamped,
        or damped and whirl-split (``self["frequencies"]`` tells which), over 0 to 1.5x
        the top of the checked range and the checked speeds.
    components : tuple of ComponentModes
        The gear bodies the verdict checked (empty without).
    """

    def __init__(
        self,
        verdict: dict[str, Any],
        campbell: CampbellResult | ComplexCampbellResult,
        components: Sequence[ComponentModes] = (),
    ) -> None:
        super().__init__(verdict)
        self.campbell = campbell
        self.components = tuple(components)

    @property
    def ok(self) -> bool:
        """No finding: no crossing, near miss, unstable mode or body-mode finding."""
        return bool(self["ok"])

    def to_dict(self) -> dict[str, Any]:
        """The verdict as a plain dict (JSON-ready)."""
        return dict(self)

    def table(self) -> str:
        """The verdict as text (:func:`format_check`)."""
        return format_check(self)

    def plot(self, *, fmax: float | None = None) -> Figure:
        """The Campbell diagram the verdict used, with the gear-body modes as horizontal
        lines (:func:`~reducerlab.plot.campbell.plot_resonance`).

        Parameters
        ----------
        fmax : float, optional
            Top of the frequency axis (Hz); default 1.05 x the highest body mode with
            components, else 1.1 x the highest natural frequency.
        """
        from ..plot.campbell import plot_resonance

        return plot_resonance(self, fmax=fmax)

    def plot_components(self) -> Figure:
        """The gear-body modes against the system modes, order by order (paper 000
        Table 5; :func:`~reducerlab.plot.components.plot_component_comparison`)."""
        from ..plot.components import plot_component_comparison

        return plot_component_comparison(self)


@names_source
def resonance_check(
    target: Design | Model,
    *,
    margin: float | None = None,
    speed_range: tuple[float, float] | None = None,
    points: int = 101,
    components: Sequence[ComponentModes] | ComponentModes = (),
    mesh_strain_share: float | None = None,
    forward_whirl_share: float | None = None,
) -> ResonanceResult:
    """Resonance verdict over the operating speed range (paper 000's closing check).

    Lists every crossing of a natural frequency with an excitation inside the range,
    and every (mode, excitation) pair whose frequencies come within ``margin``
    (relative to the excitation) somewhere in the range, with the closest approach.

    Each row says how strongly its excitation drives its mode
    (:mod:`.participation`): a mesh order (transmission error) through the mode's
    strain-energy share in the mesh lines it acts on (``mesh_share``, ``mesh_lines``),
    the input rotation (unbalance) through the share of the mode's lateral motion that
    whirls forward (``forward_share``; None for a mode without lateral motion, which
    counts). A row is ``excited`` when that share reaches ``mesh_strain_share`` or
    ``forward_whirl_share``; only excited rows are findings (the others stay listed:
    "not mesh-excited", "backward whirl").

    With ``components`` (finite-element modes of the gear bodies, paper 000 §4), each
    body mode is also checked against

    * every excitation line: a constant body frequency ``f`` meets the line
      ``order * speed / 2 pi`` at exactly ``speed = 2 pi f / order``
      (``component_crossings`` when inside the range); ``component_near`` lists the
      (body mode, excitation) pairs within ``margin`` (relative to the excitation) at
      their exact closest approach in the range;
    * every elastic system natural frequency at the speeds of the range
      (``coincidences`` when within ``margin``, relative to the system frequency):
      paper 000's Table 5 comparison.

    Parameters
    ----------
    target : Design or Model
    margin : float, optional
        Relative distance to an excitation that counts, in (0, 1) (0.10 = 10 %);
        default the design's ``[check]`` margin (:class:`~reducerlab.design.Thresholds`).
    speed_range : tuple of float, optional
        ``(min, max)`` input speeds (rad/s); default the design's operating range
        (:func:`~reducerlab.analysis.excitation.operating_range`).
    points : int
        Speeds checked across the range.
    components : ComponentModes or sequence of them
        Gear-body modes to check (unique labels).
    mesh_strain_share, forward_whirl_share : float, optional
        The shares from which a mesh-order or rotation row is excited, in [0, 1];
        default the design's ``[check]`` table (0.01 each, ``docs/assumptions.md``).

    Returns
    -------
    ResonanceResult
        A dict ``{"ok": bool, "margin": ..., "mesh_strain_share": ...,
        "forward_whirl_share": ..., "speed_range_rpm": [...], "crossings": [...],
        "near": [...], "title": ...}``; with components also ``"component_crossings"``,
        ``"component_near"``, ``"coincidences"``, ``"components"`` (per body: label,
        frequencies, types, source and its ``closest`` approach to an excitation and
        to a system mode) and ``"system"`` (the system natural frequencies over the
        range: ``frequencies_hz`` at its top speed, ``min_hz``, ``max_hz``). ``ok`` is
        False if any list of findings holds an excited row (every body-mode row and
        unstable mode counts). Its ``campbell`` is the Campbell diagram used (complex
        branches with gyroscopic, Coriolis or circulatory terms).
    """
    from ..drives import design_and_model

    limits = target.thresholds if isinstance(target, Design) else Thresholds()
    margin = limits.margin if margin is None else margin
    mesh_strain_share = limits.mesh_strain_share if mesh_strain_share is None else mesh_strain_share
    forward_whirl_share = (
        limits.forward_whirl_share if forward_whirl_share is None else forward_whirl_share
    )
    if isinstance(margin, bool) or not (isinstance(margin, int | float) and 0 < margin < 1):
        raise ReducerlabError(f"margin must be a fraction in (0, 1), got {margin!r}")
    for what, v in (("mesh_strain_share", mesh_strain_share),
                    ("forward_whirl_share", forward_whirl_share)):  # fmt: skip
        if isinstance(v, bool) or not (isinstance(v, int | float) and 0 <= v <= 1):
            raise ReducerlabError(f"{what} must be a fraction in [0, 1], got {v!r}")
    comps = as_components(components)
    lo, hi = speed_range if speed_range is not None else operating_range(target)
    if not (0 <= lo <= hi) or not math.isfinite(hi):
        raise ReducerlabError(f"speed range must satisfy 0 <= min <= max, got ({lo}, {hi})")
    if hi == 0:
        raise ReducerlabError("the design has no operating speed: give a speed range")
    speeds = np.linspace(lo, hi, points) if hi > lo else np.array([lo])
    grid = np.unique(np.concatenate([speeds, np.linspace(0.0, 1.5 * hi, 201)]))
    _, model = design_and_model(target, "resonance check")
    # gyroscopic, Coriolis or circulatory terms: check the damped, whirl-split branches
    rows = modes_over(model, speeds)  # complex modes at each speed: stability
    gyroscopic = has_skew_terms(model.with_speed(float(hi)))
    res: CampbellResult | ComplexCampbellResult
    res = complex_campbell(target, grid) if gyroscopic else campbell(target, grid)
    ds = res.data
    # the checked speeds on the diagram's tracked modes (the grid holds them exactly)
    at = np.searchsorted(ds["speed"].values, speeds)
    freq = np.nan_to_num(ds["frequency"].values[at], nan=0.0)
    sorted_mode = ds["sorted_mode"].values[at]
    whirl = ds["whirl"].values[at] if gyroscopic else None
    orders = dict(zip([str(e) for e in ds["excitation"].values], ds["order"].values, strict=True))
    near = []
    for name, order in orders.items():
        fe = order * speeds / TWO_PI
        for j in range(freq.shape[1]):
            fn = freq[:, j]
            if np.all(fn <= 0):
                continue
            with np.errstate(divide="ignore", invalid="ignore"):
                rel = np.where(fe > 0, np.abs(fn - fe) / fe, np.inf)
            i = int(np.argmin(rel))
            if rel[i] <= margin:
                near.append(
                    {
                        "mode": j + 1,
                        "sorted_mode": int(sorted_mode[i, j]),
                        "excitation": name,
                        "speed_rpm": float(speeds[i] * RPM),
                        "natural_hz": float(fn[i]),
                        "excitation_hz": float(fe[i]),
                        "distance": float(rel[i]),
                    }
                    | ({"whirl": str(whirl[i, j])} if whirl is not None else {})
                )
    crossings = [c for c in res.crossings() if lo <= c["speed_rad_s"] <= hi]
    near.sort(key=lambda r: r["distance"])
    _participation(model, crossings + near, orders, gyroscopic)
    for row in crossings + near:
        row["excited"] = excited(row, mesh_strain_share, forward_whirl_share)
    stability = _stability(rows, speeds)
    findings = [r for r in crossings + near if r["excited"]]
    report: dict[str, Any] = {
        "ok": not findings and not stability["unstable"],
        "margin": margin,
        "mesh_strain_share": mesh_strain_share,
        "forward_whirl_share": forward_whirl_share,
        "frequencies": "complex (damped, whirl-split)" if gyroscopic else "undamped",
        "speed_range_rpm": [lo * RPM, hi * RPM],
        "crossings": crossings,
        "near": near,
        "stability": stability,
        "title": ds.attrs.get("title", ""),
    }
    if comps:
        plain = {name: float(order) for name, order in orders.items()}
        report.update(_component_check(comps, plain, speeds, freq, float(lo), float(hi), margin))
        report["ok"] = report["ok"] and not (
            report["component_crossings"] or report["component_near"] or report["coincidences"]
        )
    return ResonanceResult(report, res, comps)


def _participation(
    model: Model, rows: list[dict[str, Any]], orders: dict[str, float], gyroscopic: bool
) -> None:
    """:func:`~.participation.participation` of rows named by their tracked mode: the
    shares are read from the mode's number in frequency order at the row's speed
    (``sorted_mode``), the numbering the participation measures use."""
    shown = [{**r, "mode": r.get("sorted_mode", r["mode"])} for r in rows]
    participation(model, shown, orders, gyroscopic)
    for row, done in zip(rows, shown, strict=True):
        row.update({k: v for k, v in done.items() if k not in row})


def excited(row: dict[str, Any], mesh_strain_share: float, forward_whirl_share: float) -> bool:
    """Whether a crossing or near row's excitation drives its mode: its ``mesh_share``
    reaches ``mesh_strain_share``, or its ``forward_share`` reaches
    ``forward_whirl_share`` (a mode without lateral motion, share None, counts); a row
    without either (an excitation the verdict cannot weigh) counts."""
    if "mesh_share" in row:
        return bool(row["mesh_share"] >= mesh_strain_share)
    share = row.get("forward_share")
    return share is None or bool(share >= forward_whirl_share)


def _stability(rows: list[xr.Dataset], speeds: NDArray) -> dict[str, Any]:
    """From the complex modes at each speed (damping, gyroscopic and Coriolis terms): the
    modes that grow (``unstable``) and the smallest damping ratio of an elastic mode."""
    unstable, least = [], None
    for w, ds in zip(speeds, rows, strict=True):
        elastic = ds["whirl"].values != "rigid"
        for m, f, z, g, ok in zip(ds["mode"].values[elastic], ds["frequency"].values[elastic],
                                  ds["damping_ratio"].values[elastic],
                                  ds["growth_rate"].values[elastic],
                                  ds["stable"].values[elastic], strict=True):  # fmt: skip
            if not ok:
                unstable.append({"mode": int(m), "speed_rpm": float(w * RPM),
                                 "frequency_hz": float(f), "growth_rate": float(g)})  # fmt: skip
            if least is None or z < least["damping_ratio"]:
                least = {"mode": int(m), "speed_rpm": float(w * RPM), "frequency_hz": float(f),
                         "damping_ratio": float(z)}  # fmt: skip
    return {"unstable": unstable, "least_damped": least}


def _component_check(
    components: tuple[ComponentModes, ...],
    orders: dict[str, float],
    speeds: NDArray,
    freq: NDArray,
    lo: float,
    hi: float,
    margin: float,
) -> dict[str, Any]:
    """Body modes against excitation lines (exact) and system natural frequencies."""
    crossings, near, coincidences, summary = [], [], [], []
    for comp in components:
        best_exc: dict[str, Any] | None = None
        best_sys: dict[str, Any] | None = None
        for k, (f, kind) in enumerate(zip(comp.frequencies, comp.types, strict=True), 1):
            head = {"component": comp.label, "mode": k, "type": kind}
            for name, order in orders.items():
                w_star = TWO_PI * f / order  # f = order w / 2 pi: exact for a constant f
                if lo <= w_star <= hi:
                    crossings.append(
                        {
                            **head,
                            "excitation": name,
                            "speed_rad_s": w_star,
                            "speed_rpm": w_star * RPM,
                            "frequency_hz": f,
                        }
                    )
                # |f - fe| / fe = |f / fe - 1| is monotone on either side of w*: the
                # closest approach in the range is at w* clipped to it
                w = min(max(w_star, lo), hi)
                fe = order * w / TWO_PI
                row = {
                    **head,
                    "excitation": name,
                    "speed_rpm": w * RPM,
                    "natural_hz": f,
                    "excitation_hz": fe,
                    "distance": abs(f - fe) / fe,
                }
                if row["distance"] <= margin:
                    near.append(row)
                if best_exc is None or row["distance"] < best_exc["distance"]:
                    best_exc = row
            for j in range(freq.shape[1]):
                fn = freq[:, j]
                if np.all(fn <= 0):
                    continue  # rigid (0 Hz) or divergent throughout
                with np.errstate(divide="ignore", invalid="ignore"):
                    rel = np.where(fn > 0, np.abs(f - fn) / fn, np.inf)
                i = int(np.argmin(rel))
                row = {
                    **head,
                    "system_mode": j + 1,
                    "speed_rpm": float(speeds[i] * RPM),
                    "natural_hz": f,
                    "system_hz": float(fn[i]),
                    "distance": float(rel[i]),
                }
                if row["distance"] <= margin:
                    coincidences.append(row)
                if best_sys is None or row["distance"] < best_sys["distance"]:
                    best_sys = row
        strip = ("component",)
        summary.append(
            {
                **comp.to_dict(),
                "closest": {
                    "excitation": None
                    if best_exc is None
                    else {k: v for k, v in best_exc.items() if k not in strip},
                    "system_mode": None
                    if best_sys is None
                    else {k: v for k, v in best_sys.items() if k not in strip},
                },
            }
        )
    crossings.sort(key=lambda r: r["speed_rad_s"])
    near.sort(key=lambda r: r["distance"])
    coincidences.sort(key=lambda r: r["distance"])
    return {
        "component_crossings": crossings,
        "component_near": near,
        "coincidences": coincidences,
        "components": summary,
        "system": {
            "speed_rpm": [float(speeds[0] * RPM), float(speeds[-1] * RPM)],
            "frequencies_hz": [float(v) for v in freq[-1]],
            "min_hz": [float(v) for v in freq.min(axis=0)],
            "max_hz": [float(v) for v in freq.max(axis=0)],
        },
    }


def format_check(report: dict[str, Any]) -> str:
    """Human-readable verdict of :func:`resonance_check`."""
    hz, rpm = partial(fmt, kind="frequency"), partial(fmt, kind="speed")
    lo, hi = report["speed_range_rpm"]
    rng = f"{rpm(lo)} rpm" if lo == hi else f"{rpm(lo)}-{rpm(hi)} rpm"
    m = 100 * report["margin"]
    lines = [f"Resonance check: {report['title']} over {rng}, margin {fmt(m, 'percent')} %"]
    if report.get("frequencies", "undamped") != "undamped":
        lines.append(f"  frequencies: {report['frequencies']}")
    for c in report["crossings"]:
        whirl = f", {c['whirl']} whirl" if c.get("whirl") else ""
        lines.append(
            f"  CROSSING  mode {c['mode']} with {c['excitation']} at {rpm(c['speed_rpm'])} rpm "
            f"({hz(c['frequency_hz'])} Hz{whirl}){drive_note(c, report)}"
        )
    for r in report["near"]:
        lines.append(
            f"  NEAR      mode {r['mode']} ({hz(r['natural_hz'])} Hz"
            + (f", {r['whirl']} whirl" if r.get("whirl") else "")
            + ") within "
            f"{percent(r['distance'])} % of {r['excitation']} ({hz(r['excitation_hz'])} Hz) "
            f"at {rpm(r['speed_rpm'])} rpm{drive_note(r, report)}"
        )
    lines += format_components(report).splitlines()
    st = report.get("stability")
    if st is not None:
        for u in st["unstable"][:10]:
            lines.append(
                f"  UNSTABLE  mode {u['mode']} ({hz(u['frequency_hz'])} Hz) grows at "
                f"{fmt(u['growth_rate'])} 1/s at {rpm(u['speed_rpm'])} rpm"
            )
        if len(st["unstable"]) > 10:
            lines.append(f"  ... {len(st['unstable']) - 10} more unstable (mode, speed) pairs")
        z = st["least_damped"]
        if z is not None:
            lines.append(
                f"  DAMPING   least damped: mode {z['mode']} ({hz(z['frequency_hz'])} Hz), "
                f"damping ratio {fmt(z['damping_ratio'])} at {rpm(z['speed_rpm'])} rpm"
            )
    lines.append(
        "resonance: no resonance risk" if report["ok"] else "resonance: RESONANCE RISK (see above)"
    )
    return "\n".join(lines)


def format_components(report: dict[str, Any]) -> str:
    """The gear-body part of :func:`format_check`: body-mode crossings, near misses,
    coincidences with system modes and each body's closest approaches (empty without
    components)."""
    hz, rpm = partial(fmt, kind="frequency"), partial(fmt, kind="speed")
    lines: list[str] = []
    for c in report.get("component_crossings", ()):
        lines.append(
            f"  CROSSING  {_body_mode(c)} with {c['excitation']} at {rpm(c['speed_rpm'])} rpm "
            f"({hz(c['frequency_hz'])} Hz)"
        )
    for r in report.get("component_near", ()):
        lines.append(
            f"  NEAR      {_body_mode(r)} ({hz(r['natural_hz'])} Hz) within "
            f"{percent(r['distance'])} % of {r['excitation']} ({hz(r['excitation_hz'])} Hz) "
            f"at {rpm(r['speed_rpm'])} rpm"
        )
    for r in report.get("coincidences", ()):
        lines.append(
            f"  COINCIDE  {_body_mode(r)} ({hz(r['natural_hz'])} Hz) within "
            f"{percent(r['distance'])} % of system mode {r['system_mode']} "
            f"({hz(r['system_hz'])} Hz) at {rpm(r['speed_rpm'])} rpm"
        )
    for comp in report.get("components", ()):
        f = comp["frequencies"]
        parts = [f"  BODY      {comp['label']}: {len(f)} mode(s) {hz(f[0])}-{hz(f[-1])} Hz"]
        ex, sy = comp["closest"]["excitation"], comp["closest"]["system_mode"]
        if ex is not None:
            parts.append(
                f"closest excitation {percent(ex['distance'])} % (mode {ex['mode']} x "
                f"{ex['excitation']})"
            )
        if sy is not None:
            parts.append(
                f"closest system mode {percent(sy['distance'])} % (mode {sy['mode']} ~ "
                f"system mode {sy['system_mode']})"
            )
        lines.append(", ".join(parts))
    return "\n".join(lines)


def percent(share: float) -> str:
    """A share (0..1) in per cent by the ``percent`` rule of :mod:`reducerlab.numformat`
    (three significant digits, two places at most: ``"3.05"``, ``"0.13"``, ``"0"``)."""
    return fmt(100 * share, "percent")


def drive_note(row: dict[str, Any], report: dict[str, Any]) -> str:
    """``", mesh strain 0 %: not mesh-excited (< 1 %)"``: how strongly a crossing or near
    row's excitation drives its mode (empty for a row without the measure)."""
    if "mesh_share" in row:
        text = f", mesh strain {percent(row['mesh_share'])} %"
        if not row.get("excited", True):
            text += f": not mesh-excited (< {100 * report['mesh_strain_share']:g} %)"
        return text
    if "forward_share" not in row:
        return ""
    share = row["forward_share"]
    if share is None:
        return ", no lateral whirl (counted)"
    text = f", forward whirl {percent(share)} %"
    if not row.get("excited", True):
        text += (
            f": not excited by unbalance (forward whirl < "
            f"{100 * report['forward_whirl_share']:g} %)"
        )
    return text


def _body_mode(row: dict[str, Any]) -> str:
    """``"gear 1 mode 3 (folding)"`` of a component row."""
    kind = f" ({row['type']})" if row.get("type") else ""
    return f"{row['component']} mode {row['mode']}{kind}"
