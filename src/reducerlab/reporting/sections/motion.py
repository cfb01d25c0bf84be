"""Report sections on the nonlinear motion of the drive: the response at the operating
speed, bifurcation diagrams and regime maps (requested by the design's ``[report]`` table
or given as results)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ...errors import ReducerlabError
from ...plot.axes import parameter_label
from ...plot.bifurcation import plotly_bifurcation, plotly_regime_map
from ...plot.response import orbit_note, plot_transmission_error
from ..blocks import Section, figure, interactive, note, table
from ..context import Context

__all__ = ["bifurcation_section", "regime_map_section", "response_section"]


def response_section(ctx: Context) -> Section | None:
    """The nonlinear steady response at the operating speed (mesh deflection, DTE,
    dynamic load factor, impacts, spectrum)."""
    if not ctx.has_model():
        return None
    model = ctx.model()
    if model.nonlinear().G.shape[0] == 0 or model.speed == 0:
        return None
    from ...analysis.response import response
    from ...dynamics.coordinates import to_system
    from ...dynamics.systems import forcing_period

    s = Section("response", "Nonlinear response at the operating speed")
    try:
        forcing_period(to_system(model))
    except ReducerlabError:
        s.blocks.append(
            note(
                "Nothing in the model varies periodically (constant mesh "
                "stiffness, no transmission error or periodic load): the "
                "response at the operating speed is the static equilibrium."
            )
        )
        return s
    done, _ = ctx.responses()  # the verdict's (or the run's): computed once
    results = done or [response(model)]
    for res in results:
        _one_response(s, res, len(results) > 1)
    return s


def _one_response(s: Section, res: Any, several: bool) -> None:
    """The table and figures of one mesh line's response; the section's values (dynamic
    load factor, impact class, separation) are those of the worst line."""
    from ...analysis.response import NOISE_M

    ds = res.data
    a = ds.attrs
    line = str(a.get("line", ""))
    head = f"{line}: " if several else ""
    if float(np.ptp(ds["delta"].values)) <= NOISE_M:
        s.values.setdefault("dynamic_load_factor", float("nan"))
        s.blocks.append(
            note(
                f"{head}The drive is not excited at the operating speed: its mesh deflection "
                f"varies by less than {NOISE_M * 1e6:g} um (round-off), so there is no dynamic "
                "response to show. Give a load (output_torque) and a transmission error or "
                "mesh-stiffness harmonics to see one."
            )
        )
        return
    dlf = float(a["dynamic_load_factor"])
    peaks = res.peaks(5)
    sep = float(a.get("separation_fraction", 0.0))
    worst = s.values.get("dynamic_load_factor")
    if worst is None or not np.isfinite(worst) or dlf > worst:
        s.values.update(
            dynamic_load_factor=dlf, peaks=peaks, impact_class=str(a.get("impact_class", ""))
        )
    s.values["separation_fraction"] = max(sep, s.values.get("separation_fraction", 0.0))
    rows = [
        ("forcing frequency (Hz)", float(a["forcing_hz"])),
        ("dynamic load factor max|F| / mean F", dlf),
        ("mesh deflection peak-to-peak (um)", float(np.ptp(ds["delta"].values)) * 1e6),
        ("dynamic transmission error peak-to-peak (um)", float(np.ptp(ds["dte"].values)) * 1e6),
        ("time with teeth apart (%)", 100 * sep),
        ("impact class", str(a.get("impact_class", "")) or "—"),
        ("spectral peaks (x forcing)", ", ".join(f"{m:.3g}x" for m, _ in peaks) or "—"),
    ]
    name = f"response-{line}" if several else "response"
    s.blocks.append(table([f"{head}quantity", "value"], rows, name=name))
    sp = res.spectrum()
    small = orbit_note(ds)  # a small vibration about the static deflection: how small
    s.blocks.append(
        figure(
            res.plot(),
            f"{head}phase trajectory, Poincaré map and spectrum of the mesh deflection; the "
            f"spectrum over the last {sp.record * float(a['forcing_hz']):.3g} periods under a "
            f"{sp.window} window, its resolution Δf = 1 / record = {sp.resolution:.3g} Hz"
            + (f"; the {small}" if small else ""),
        )
    )
    s.blocks.append(
        figure(
            plot_transmission_error(res), f"{head}dynamic transmission error over the last periods"
        )
    )


def _requested(field_: str, parse: Callable[..., Any], *args: str, limit: int) -> Any:
    """An axis a design's ``[report]`` table asks for, its errors naming the field."""

    try:
        return parse(*args, limit=limit, option=field_)
    except ReducerlabError as exc:
        text = str(exc)
        raise ReducerlabError(text if text.startswith(field_) else f"{field_}: {text}") from None


def _wanted(ctx: Context, request: str, kind: str) -> tuple[Any, list[Any]]:
    """The design's ``[report]`` request of this name and the given results of ``kind``."""
    req = getattr(ctx.design.report, request) if ctx.design.report else None
    return req, list(ctx.given(kind))


def bifurcation_section(ctx: Context) -> Section | None:
    """Bifurcation diagrams: the design's ``[report.bifurcation]`` request and those given."""
    req, results = _wanted(ctx, "bifurcation", "bifurcation")
    if req is None and not results:
        return None
    s = Section("bifurcation", "Bifurcation diagram")
    if req is not None:
        from ...analysis.bifurcation import bifurcation
        from ...analysis.parameters import parse_values

        field_ = "report.bifurcation.values"
        axis = _requested(field_, parse_values, req.parameter, req.values, limit=400)
        results.append(
            bifurcation(ctx.design, axis, periods=req.periods, keep=req.keep, progress=ctx.step)
        )
    for r in results:
        period = r.periodicity()
        s.values.setdefault("periods", []).append(period.tolist())
        s.blocks.append(
            interactive(
                plotly_bifurcation(r),
                r.plot(),
                f"bifurcation diagram over {parameter_label(r.data.attrs['parameter'])} "
                f"({r.data.attrs['parameter']}): drag to zoom",
                div_id=f"bifurcation-{len(s.values['periods'])}",
            )
        )
        counts: dict[str, int] = {}
        for p in period:
            key = f"period-{p}" if p else "not periodic (<= 12)"
            counts[key] = counts.get(key, 0) + 1
        s.blocks.append(table(["motion", "values"], sorted(counts.items()), name="periodicity"))
    return s


def regime_map_section(ctx: Context) -> Section | None:
    """Regime maps: the design's ``[report.regime_map]`` request and those given."""
    req, results = _wanted(ctx, "regime_map", "regime-map")
    if req is None and not results:
        return None

    s = Section("regime-map", "Regime map")
    if req is not None:
        from ...analysis.parameters import parse_path_values
        from ...analysis.regime_map import regime_map

        axes = [_requested(f"report.regime_map.{name}", parse_path_values, getattr(req, name),
                           limit=200) for name in ("x", "y")]  # fmt: skip
        results.append(
            regime_map(
                ctx.design, axes[0], axes[1], periods=req.periods, keep=req.keep, progress=ctx.step
            )
        )
    for k, r in enumerate(results):
        lab = np.asarray(r.labels())
        s.values.setdefault("classes", []).append(sorted(set(lab.ravel().tolist())))
        s.blocks.append(
            interactive(
                plotly_regime_map(r),
                r.plot(),
                "motion class over the two parameters (first branch): hover for values",
                div_id=f"regime-map-{k + 1}",
            )
        )
    return s
