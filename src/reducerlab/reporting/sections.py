"""Sections of the design report (issue 18). Each builder takes the report's
:class:`Context` and returns a :class:`~.blocks.Section`, or None when the design does
not support it (a kinematics-only design has no modes). Builders call the same API a
user would (``modal``, ``campbell``, ``resonance_check``, ``response`` ...), so the
numbers in the report are the API's."""

from __future__ import annotations

import html
import math
import re
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..design import Design, apply_overrides, field_kind
from ..errors import ReducerlabError
from ..model import Model
from ..units import QUANTITIES
from .blocks import Block, Section, details, figure, interactive, note, pre, table, verdict

__all__ = ["SECTIONS", "Context"]

RPM = 60.0 / (2.0 * math.pi)

#: Papers whose choices in docs/assumptions.md apply to each drive (the design type, or
#: for a kinematics-only design its ``drive``); a section applies when its heading
#: starts with one of these.
PAPERS = {
    "nutation": ("Paper 000", "Paper 001", "Paper 002", "Papers 000", "Papers 001"),
    "cycloid": ("Paper 003", "Papers 000, 002, 003"),
    "khv": ("Paper 004",),
}


def _drive_family(design: Design) -> str:
    name = str(getattr(design, "drive", design.type))
    return next((k for k in PAPERS if k in name), "")


@dataclass
class Context:
    """What every section reads: the design, its file text, and results computed once
    and shared (the model, the modal result)."""

    design: Design
    text: str = ""
    assumptions: str = ""
    results: dict[str, list[Any]] = field(default_factory=dict)
    #: ``PATH=VALUE`` settings applied to the file (``--set``).
    overrides: tuple[str, ...] = ()
    cache: dict[str, Any] = field(default_factory=dict)
    #: ``step(done, total)`` inside a long section (the report's progress display).
    step: Callable[[int, int], None] | None = None

    def given(self, kind: str) -> list[Any]:
        """Results of ``kind`` handed to the report (``--with`` files)."""
        return self.results.get(kind, [])

    def components(self) -> list[Any]:
        """Gear-body modes given to the report, for the resonance check."""
        from ..analysis.campbell import ComponentModes

        return [
            ComponentModes.from_body_modal(r, source=r.attrs.get("source", ""))
            for r in self.given("body-modal")
        ]

    def model(self) -> Model:
        if "model" not in self.cache:
            from ..drives import build_model

            self.cache["model"] = build_model(self.design)
        return self.cache["model"]

    def modal(self) -> Any:
        if "modal" not in self.cache:
            from ..analysis.modal import modal

            self.cache["modal"] = modal(self.model())
        return self.cache["modal"]

    def has_model(self) -> bool:
        from ..drives import has_model

        return has_model(self.design)


def _flatten(data: Any, prefix: str = "") -> list[tuple[str, Any]]:
    out: list[tuple[str, Any]] = []
    if isinstance(data, dict):
        for k, v in data.items():
            out += _flatten(v, f"{prefix}.{k}" if prefix else str(k))
    elif isinstance(data, list) and any(isinstance(v, dict) for v in data):
        for i, v in enumerate(data):
            out += _flatten(v, f"{prefix}.{i}")
    else:
        out.append((prefix, data))
    return out


def _lookup(data: Any, path: str) -> Any:
    for part in path.split("."):
        if isinstance(data, dict) and part in data:
            data = data[part]
        elif isinstance(data, list) and part.isdigit() and int(part) < len(data):
            data = data[int(part)]
        else:
            return None
    return data


def assumption_sections(text: str, family: str) -> list[tuple[str, str]]:
    """``(heading, body)`` of the docs/assumptions.md sections that apply to a drive
    family (a key of :data:`PAPERS`)."""
    keys = PAPERS.get(family, ())
    parts = re.split(r"^## ", text, flags=re.M)[1:]
    out = []
    for part in parts:
        heading, _, body = part.partition("\n")
        if any(heading.startswith(k) for k in keys):
            out.append((heading.strip(), body.strip()))
    return out


def design_section(ctx: Context) -> Section:
    """Design inputs as written (with their units) and in SI, and the assumptions."""
    d = ctx.design
    s = Section("design", "Design inputs")
    written = tomllib.loads(ctx.text.removeprefix("\ufeff")) if ctx.text else {}
    if written and ctx.overrides:
        written = apply_overrides(written, ctx.overrides)
    rows = []
    for key, value in _flatten(d.model_dump(mode="json", exclude={"report"})):
        if key in ("name", "description"):
            continue
        as_written = _lookup(written, key)
        kind = field_kind(d, key)
        rows.append((key, "" if as_written is None else str(as_written),
                     value if isinstance(value, int | float) else str(value),
                     QUANTITIES[kind].si_unit if kind else ""))  # fmt: skip
    s.blocks.append(note(f"{d.name or d.type}: type = {d.type!r}, source {d.source}"))
    if d.description:
        s.blocks.append(note(d.description))
    if ctx.overrides:
        s.blocks.append(note("Set on the command line (--set), shown as written below: "
                             + "; ".join(ctx.overrides), "warning"))  # fmt: skip
    inputs = table(["field", "as written", "SI value", "SI unit"], rows, digits=8, name="inputs")
    s.blocks.append(details(f"all {len(rows)} fields, as written and in SI", inputs.html, "table"))
    if ctx.text:
        s.blocks.append(details("the design file", f"<pre>{html.escape(ctx.text)}</pre>", "pre"))
    sections = assumption_sections(ctx.assumptions, _drive_family(d))
    if sections:
        items = "".join(details(h, f"<pre>{html.escape(b)}</pre>").html for h, b in sections)
        s.blocks.append(
            note("Choices in force where the papers are silent or ambiguous (docs/assumptions.md):")
        )
        s.blocks.append(Block(f'<div class="assumptions">{items}</div>', "assumptions"))
    s.values["inputs"] = len(rows)
    return s


def kinematics_section(ctx: Context) -> Section | None:
    if not hasattr(ctx.design, "kinematics"):
        return None
    from ..analysis.kinematics import kinematics
    from ..drives import kinematics_of

    drive, speed = kinematics_of(ctx.design)
    res = kinematics(drive, speed, title=ctx.design.name, metadata=ctx.design.provenance)
    ds = res.data
    s = Section("kinematics", "Kinematics")
    ratio = float(ds.attrs["ratio"])
    s.values.update(
        ratio=ratio,
        speed_rpm=[float(v) for v in ds["speed_rpm"].values],
        mesh_hz=[float(v) for v in ds["mesh_frequency"].values],
    )
    s.blocks.append(
        table(
            ["quantity", "value"],
            [
                ("transmission ratio i = omega_in / omega_out", ratio),
                ("input speed (rpm)", float(ds.attrs["input_speed_rad_s"]) * RPM),
            ],
            digits=8,
            name="ratio",
        )
    )
    members = [
        (str(m), float(v)) for m, v in zip(ds["member"].values, ds["speed_rpm"].values, strict=True)
    ]
    s.blocks.append(table(["member", "speed (rpm)"], members, digits=8, name="members"))
    meshes = [
        (str(m), float(v))
        for m, v in zip(ds["mesh"].values, ds["mesh_frequency"].values, strict=True)
    ]
    s.blocks.append(table(["mesh", "mesh frequency (Hz)"], meshes, digits=8, name="meshes"))
    if "omega" in ds:
        s.blocks.append(figure(res.plot(), "angular velocity over one input turn"))
    return s


def _mode_shapes_plotly(res: Any) -> Any:
    """Interactive bar chart of mass-weighted mode shapes, one mode per menu entry."""
    import plotly.graph_objects as go

    ds = res.data
    dofs = [str(d) for d in ds["dof"].values]
    ke = ds["kinetic_energy"].values  # (mode, dof), sums to 1 per mode
    sign = np.sign(ds["shape"].values.T)
    amp = sign * np.sqrt(np.clip(ke, 0.0, None))
    fig = go.Figure()
    n = amp.shape[0]
    labels = []
    for j in range(n):
        f = float(ds["frequency"].values[j])
        cls = str(ds["classification"].values[j])
        labels.append(f"mode {j + 1}: {f:.5g} Hz ({cls})")
        a = amp[j] / max(float(np.max(np.abs(amp[j]))), 1e-300)
        fig.add_trace(
            go.Bar(
                x=dofs,
                y=a,
                name=f"mode {j + 1}",
                visible=j == min(1, n - 1),
                hovertemplate="%{x}: %{y:.3f}<extra></extra>",
            )
        )
    buttons = [
        dict(
            label=labels[j],
            method="update",
            args=[{"visible": [k == j for k in range(n)]}, {"title.text": labels[j]}],
        )
        for j in range(n)
    ]
    fig.update_layout(
        updatemenus=[
            dict(
                buttons=buttons, direction="down", x=0, xanchor="left", y=1.18, active=min(1, n - 1)
            )
        ],
        title=dict(text=labels[min(1, n - 1)], x=0.5, y=0.97, font=dict(size=13)),
        yaxis_title="mass-weighted amplitude (largest 1)",
        height=430,
        margin=dict(t=90, l=60, r=20, b=90),
        template="plotly_white",
        showlegend=False,
    )
    return fig


def modal_section(ctx: Context) -> Section | None:
    if not ctx.has_model():
        return None
    res = ctx.modal()
    ds = res.data
    s = Section("modal", "Natural frequencies and mode shapes")
    freq = [float(f) for f in ds["frequency"].values]
    s.values["frequencies_hz"] = freq
    rows = [
        (int(m), f, str(c))
        for m, f, c in zip(ds["mode"].values, freq, ds["classification"].values, strict=True)
    ]
    s.blocks.append(
        table(["mode", "frequency (Hz)", "classification"], rows, digits=7, name="modes")
    )
    if ds.attrs.get("skew_velocity_terms"):
        s.blocks.append(
            note(
                "The model has gyroscopic, Coriolis or circulatory terms; these "
                "undamped modes leave them out (see the Campbell section).",
                "warning",
            )
        )
    s.blocks.append(
        interactive(
            _mode_shapes_plotly(res),
            res.plot_shapes(),
            "mode shapes: choose a mode",
            div_id="mode-shapes",
        )
    )
    s.blocks.append(figure(res.plot_energy(), "kinetic and strain energy shares"))
    return s


def _sensitivity_plotly(ds: Any) -> Any:
    """Heat map of relative sensitivities (mode x parameter)."""
    import plotly.graph_objects as go

    rel = ds["relative"].values
    lim = float(np.nanmax(np.abs(rel))) if np.any(np.isfinite(rel)) else 1.0
    modes = [
        f"{int(m)}: {f:.5g} Hz"
        for m, f in zip(ds["mode"].values, ds["frequency"].values, strict=True)
    ]
    fig = go.Figure(
        go.Heatmap(
            z=rel,
            x=[str(p) for p in ds["parameter"].values],
            y=modes,
            zmin=-lim,
            zmax=lim,
            colorscale="RdBu_r",
            colorbar=dict(title="(p/f) df/dp"),
            hovertemplate="mode %{y}<br>%{x}<br>(p/f) df/dp = %{z:.4f}<extra></extra>",
        )
    )
    fig.update_layout(
        height=max(320, 60 + 28 * len(modes)),
        template="plotly_white",
        margin=dict(t=20, l=120, r=20, b=160),
        yaxis_autorange="reversed",
    )
    return fig


def sensitivity_section(ctx: Context) -> Section | None:
    if not ctx.has_model():
        return None
    from ..analysis.modal import frequency_sensitivity
    from ..model.inspect import parameter_paths

    model = ctx.model()
    params = [p for p, _ in parameter_paths(model)]
    res = frequency_sensitivity(model, params, ctx.modal())
    ds = res.data
    rel = ds["relative"].values  # (mode, parameter)
    s = Section("sensitivity", "Sensitivity of the natural frequencies")
    rows = []
    for j, m in enumerate(ds["mode"].values):
        r = rel[j]
        if not np.any(np.isfinite(r)) or float(ds["frequency"].values[j]) == 0.0:
            continue
        k = int(np.nanargmax(np.abs(r)))
        rows.append(
            (int(m), float(ds["frequency"].values[j]), str(ds["parameter"].values[k]), float(r[k]))
        )
    s.values["top"] = rows
    s.blocks.append(
        note(
            "Relative sensitivity (p / f) df/dp: a 1 % rise of the parameter "
            "moves the frequency by that many per cent (exact derivatives)."
        )
    )
    s.blocks.append(
        table(
            ["mode", "frequency (Hz)", "most sensitive parameter", "(p/f) df/dp"],
            rows,
            digits=4,
            name="sensitivity",
        )
    )
    s.blocks.append(
        interactive(
            _sensitivity_plotly(ds),
            res.plot(),
            "relative sensitivities (p/f) df/dp, every mode and parameter: hover for values",
            div_id="sensitivity-map",
        )
    )
    return s


def _campbell_plotly(res: Any, check: dict[str, Any]) -> Any:
    """Interactive Campbell diagram: branches, excitation lines, crossings, range."""
    import plotly.graph_objects as go

    ds = res.data
    rpm = ds["speed"].values * RPM
    fig = go.Figure()
    lo, hi = ds.attrs["operating_min_rad_s"] * RPM, ds.attrs["operating_max_rad_s"] * RPM
    if hi > 0:
        fig.add_vrect(
            x0=lo,
            x1=max(hi, lo + 1e-9),
            fillcolor="rgba(60,120,200,0.12)",
            line_width=0,
            annotation_text="operating range",
        )
    whirl = ds["whirl"].values if "whirl" in ds else None
    stable = ds["stable"].values if "stable" in ds else None
    for j, m in enumerate(ds["mode"].values):
        f = ds["frequency"].values[:, j]
        if np.all(np.nan_to_num(f) == 0):
            continue
        text = None if whirl is None else [str(w) for w in whirl[:, j]]
        name = f"mode {int(m)}"
        if text:  # whirl at the top speed (hover: at each speed; branches may swap)
            name += f" ({text[-1]} at top speed)"
        fig.add_trace(
            go.Scatter(
                x=rpm,
                y=f,
                mode="lines",
                name=name,
                text=text,
                hovertemplate="%{x:.0f} rpm, %{y:.5g} Hz"
                + (" %{text}" if text else "")
                + "<extra>mode "
                + str(int(m))
                + "</extra>",
            )
        )
        if stable is not None and not stable[:, j].all():
            bad = ~stable[:, j]
            fig.add_trace(
                go.Scatter(
                    x=rpm[bad],
                    y=f[bad],
                    mode="markers",
                    showlegend=False,
                    marker=dict(color="red", symbol="x", size=7),
                    name=f"mode {int(m)} unstable",
                )
            )
    for k, e in enumerate(ds["excitation"].values):
        fig.add_trace(
            go.Scatter(
                x=rpm,
                y=ds["excitation_frequency"].values[:, k],
                mode="lines",
                line=dict(dash="dash", color="gray", width=1),
                name=str(e),
                hovertemplate=str(e) + ": %{y:.5g} Hz<extra></extra>",
            )
        )
    for comp in check.get("components", ()):
        for f in comp["frequencies"]:
            fig.add_hline(y=f, line=dict(color="darkorange", width=1, dash="dot"))
        fig.add_trace(
            go.Scatter(
                x=[rpm[0]],
                y=[comp["frequencies"][0]],
                mode="lines",
                line=dict(color="darkorange", dash="dot"),
                name=f"{comp['label']} body modes",
            )
        )
    cr = check.get("crossings", [])
    if cr:
        fig.add_trace(
            go.Scatter(
                x=[c["speed_rpm"] for c in cr],
                y=[c["frequency_hz"] for c in cr],
                mode="markers",
                marker=dict(color="crimson", size=10, symbol="circle-open", line=dict(width=2)),
                name="crossings in range",
                text=[f"mode {c['mode']} x {c['excitation']}" for c in cr],
                hovertemplate="%{text}<br>%{x:.5g} rpm, %{y:.5g} Hz<extra></extra>",
            )
        )
    top = float(np.nanmax(ds["frequency"].values)) if ds["frequency"].size else 1.0
    fig.update_layout(
        xaxis_title="input speed (rpm)",
        yaxis_title="frequency (Hz)",
        yaxis_range=[0, 1.05 * top],
        height=520,
        template="plotly_white",
        margin=dict(t=30, l=60, r=20, b=50),
    )
    return fig


def campbell_section(ctx: Context) -> Section | None:
    if not ctx.has_model():
        return None
    from ..analysis.campbell import campbell, format_check, operating_range, resonance_check
    from ..analysis.complex_modal import complex_campbell

    _, hi = operating_range(ctx.design)
    if hi == 0:
        return None
    s = Section("campbell", "Campbell diagram and resonance verdict")
    check = resonance_check(ctx.design, components=ctx.components())
    gyro = check["frequencies"] != "undamped"
    res = complex_campbell(ctx.design) if gyro else campbell(ctx.design)
    s.values.update(
        ok=bool(check["ok"]),
        crossings=check["crossings"],
        near=check["near"],
        unstable=check["stability"]["unstable"],
    )
    text = format_check(check)
    s.blocks.append(
        verdict(
            check["ok"],
            "no resonance in the operating range"
            if check["ok"]
            else "RESONANCE RISK: see the findings below",
        )
    )
    s.blocks.append(
        interactive(
            _campbell_plotly(res, check),
            res.plot(),
            "Campbell diagram: hover for values, drag to zoom"
            + (" (damped, whirl-split branches)" if gyro else ""),
            div_id="campbell",
        )
    )
    head = ["mode", "excitation", "speed (rpm)", "frequency (Hz)"] + (["whirl"] if gyro else [])
    rows = [
        (c["mode"], c["excitation"], c["speed_rpm"], c["frequency_hz"])
        + ((c["whirl"],) if gyro else ())
        for c in check["crossings"]
    ]
    if rows:
        s.blocks.append(
            table(
                head,
                rows,
                name="crossings",
                caption="crossings in the operating range",
            )
        )
    near = [
        (
            r["mode"],
            r["excitation"],
            r["speed_rpm"],
            r["natural_hz"],
            r["excitation_hz"],
            100 * r["distance"],
        )
        + ((r["whirl"],) if gyro else ())
        for r in check["near"]
    ]
    if near:
        s.blocks.append(
            table(
                [
                    "mode",
                    "excitation",
                    "speed (rpm)",
                    "natural (Hz)",
                    "excitation (Hz)",
                    "margin (%)",
                ]
                + (["whirl"] if gyro else []),
                near,
                name="near",
                caption=f"modes within {100 * check['margin']:g} % of an "
                "excitation (closest approach)",
            )
        )
    if check.get("components"):
        from ..plot.components import plot_component_comparison

        s.blocks.append(
            figure(
                plot_component_comparison(check),
                "gear-body modes against the excitations and the system modes (paper 000 Table 5)",
            )
        )
    s.blocks.append(pre(text))
    return s


def response_section(ctx: Context) -> Section | None:
    if not ctx.has_model():
        return None
    model = ctx.model()
    if model.nonlinear().G.shape[0] == 0 or model.speed == 0:
        return None
    from matplotlib.figure import Figure

    from ..analysis.nonlinear import NOISE_M, response
    from ..analysis.response import forcing_period, to_system

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
    res = response(model)
    ds = res.data
    a = ds.attrs
    if float(np.ptp(ds["delta"].values)) <= NOISE_M:
        s.values["dynamic_load_factor"] = float("nan")
        s.blocks.append(
            note(
                "The drive is not excited at the operating speed: its mesh deflection varies by "
                f"less than {NOISE_M * 1e6:g} um (round-off), so there is no dynamic response to "
                "show. Give a load (input_torque) and a transmission error or mesh-stiffness "
                "harmonics to see one."
            )
        )
        return s
    dlf = float(a["dynamic_load_factor"])
    peaks = res.peaks(5)
    s.values.update(
        dynamic_load_factor=dlf,
        peaks=peaks,
        impact_class=str(a.get("impact_class", "")),
        separation_fraction=float(a.get("separation_fraction", 0.0)),
    )
    rows = [
        ("forcing frequency (Hz)", float(a["forcing_hz"])),
        ("dynamic load factor max|F| / mean F", dlf),
        ("mesh deflection peak-to-peak (um)", float(np.ptp(ds["delta"].values)) * 1e6),
        ("dynamic transmission error peak-to-peak (um)", float(np.ptp(ds["dte"].values)) * 1e6),
        ("time with teeth apart (%)", 100 * float(a.get("separation_fraction", 0.0))),
        ("impact class", str(a.get("impact_class", "")) or "—"),
        ("spectral peaks (x forcing)", ", ".join(f"{m:.3g}x" for m, _ in peaks) or "—"),
    ]
    s.blocks.append(table(["quantity", "value"], rows, digits=6, name="response"))
    s.blocks.append(
        figure(res.plot(), "phase trajectory, Poincaré map and spectrum of the mesh deflection")
    )
    fig = Figure(figsize=(9, 3), layout="constrained")
    ax = fig.subplots()
    t = ds["time"].values
    ax.plot((t - t[0]) * 1e3, ds["dte"].values * 1e6, lw=0.8, label="DTE")
    ax.plot((t - t[0]) * 1e3, ds["delta"].values * 1e6, lw=0.8, label="mesh deflection")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("um")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    s.blocks.append(figure(fig, "dynamic transmission error over the last periods"))
    return s


def surfaces_section(ctx: Context) -> Section | None:
    d = ctx.design
    if getattr(d, "surface", None) is None or not hasattr(d, "tooth_generation"):
        return None
    from ..geometry import generate_tooth
    from ..geometry.solid import build_gear_solid
    from ..plot.surface import plot_tooth

    s = Section("surfaces", "Tooth surfaces")
    if d.gear_count > 2:
        s.blocks.append(
            note(
                "Pair 1 (gears 1 and 2) shown; 'reducerlab surface --gear N' generates the others."
            )
        )
    rows = []
    for gear in (1, 2):
        crown, bevel = d.tooth_generation(gear)
        tooth = generate_tooth(crown, bevel, 15, 15)
        solid = build_gear_solid(
            crown, bevel, n_profile=15, n_face=15, n_land=3, n_space=7, rim=d.surface.rim
        )
        rows.append(
            (
                f"gear {gear}",
                bevel.kind,
                bevel.teeth,
                math.degrees(bevel.cone_angle),
                crown.profile.name,
                tooth.report.summary().splitlines()[0],
            )
        )
        s.blocks.append(figure(plot_tooth(solid), f"gear {gear}: one tooth sector", dpi=90))
    s.blocks.insert(
        0,
        table(
            ["gear", "kind", "teeth", "pitch cone (deg)", "profile", "check"], rows, name="gears"
        ),
    )
    return s


def closed_graph_section(ctx: Context) -> Section | None:
    if ctx.design.type != "khv" or not hasattr(ctx.design, "gears"):
        return None
    from ..plot.khv import plot_closed_graph

    gears = ctx.design.gears
    pair = gears.pair()
    s = Section("closed-graph", "Closed graph of the internal pair")
    rows = [(c.name, "ok" if c.ok else "FAIL", c.margin, c.rule) for c in pair.conditions()]
    s.values["conditions_ok"] = all(c.ok for c in pair.conditions())
    s.blocks.append(table(["condition", "", "margin", "rule"], rows, name="conditions"))
    s.blocks.append(
        figure(
            plot_closed_graph(pair, gears.shift_line if gears.x2 is None else None),
            "closed graph: feasible shift coefficients and the design point",
        )
    )
    return s


def _foreign(ctx: Context, result: Any) -> Any:
    """A warning block when a given result was computed from another design."""
    theirs = result.attrs.get("design_hash")
    if theirs and theirs != ctx.design.hash:
        return note(
            f"computed from another design (hash {theirs}, this one {ctx.design.hash}): "
            "shown as given",
            "warning",
        )
    return None


def bodies_section(ctx: Context) -> Section | None:
    given = ctx.given("body-modal")
    if not given:
        return None
    s = Section("bodies", "Gear-body modes (finite elements)")
    s.blocks.append(
        note(
            "Free-body finite-element modes of the gear blanks (paper 000 §4), "
            "from 'reducerlab body-modal' results; the resonance verdict above "
            "checks them against the excitations and the system modes."
        )
    )
    for r in given:
        ds = r.data
        label = str(ds.attrs.get("title", "gear body"))
        w = _foreign(ctx, r)
        if w is not None:
            s.blocks.append(w)
        rows = [
            (int(m), float(f), str(t))
            for m, f, t in zip(
                ds["mode"].values, ds["frequency"].values, ds["type"].values, strict=True
            )
        ]
        s.values.setdefault("frequencies_hz", []).append([row[1] for row in rows])
        s.blocks.append(
            table(
                ["mode", "frequency (Hz)", "type"], rows, digits=6, caption=label, name="body-modes"
            )
        )
    return s


def contact_section(ctx: Context) -> Section | None:
    given = ctx.given("contact")
    if not given:
        return None
    from ..plot.contact import plot_contact

    s = Section("contact", "Loaded tooth contact")
    for r in given:
        w = _foreign(ctx, r)
        if w is not None:
            s.blocks.append(w)
        summ = r.summary()
        s.values.setdefault("summaries", []).append(summ)
        rows = [
            ("mean mesh stiffness (N/m)", summ["k_mean"]),
            ("transmission error peak-to-peak (um)", summ["te_peak_to_peak"] * 1e6),
            ("peak contact pressure (MPa)", summ["peak_pressure_max"] * 1e-6),
            ("interior contact pressure (MPa)", summ["interior_pressure_max"] * 1e-6),
            ("von Mises stress, max (MPa)", summ["von_mises_max"] * 1e-6),
            ("mean contact area (mm^2)", summ["contact_area_mean"] * 1e6),
            ("mean normal force (N)", summ["normal_force_mean"]),
        ]
        s.blocks.append(
            table(
                ["quantity", "value"],
                rows,
                digits=5,
                name="contact",
                caption=str(r.attrs.get("title", "")),
            )
        )
        s.blocks.append(
            figure(
                plot_contact(r),
                "contact pattern, mesh stiffness and transmission error over the mesh cycle",
            )
        )
    return s


def _bifurcation_plotly(res: Any) -> Any:
    import plotly.graph_objects as go

    from ..analysis.nonlinear import axis_label, shown_values

    ds = res.data
    x = shown_values(ds["p0"])
    fig = go.Figure()
    runs = [("poincare", "Poincaré points", "black")]
    if "poincare_down" in ds:
        runs.append(("poincare_down", "descending sweep", "crimson"))
    if "poincare_seeds" in ds:
        runs.append(("poincare_seeds", "random starts", "royalblue"))
    for name, label, colour in runs:
        v = ds[name].values
        per = int(np.prod(v.shape[1:]))
        fig.add_trace(
            go.Scattergl(
                x=np.repeat(x, per),
                y=v.ravel(),
                mode="markers",
                name=label,
                marker=dict(size=3, color=colour, opacity=0.6),
            )
        )
    fig.update_layout(
        xaxis_title=axis_label(ds["p0"], ds.attrs["parameter"]),
        yaxis_title=f"Poincaré points ({ds['poincare'].attrs.get('units', '')})",
        height=480,
        template="plotly_white",
        margin=dict(t=30, l=70, r=20, b=50),
    )
    return fig


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
    req, results = _wanted(ctx, "bifurcation", "bifurcation")
    if req is None and not results:
        return None
    s = Section("bifurcation", "Bifurcation diagram")
    if req is not None:
        from ..analysis.nonlinear import bifurcation
        from ..analysis.sweep import parse_values

        field_ = "report.bifurcation.values"
        axis = _requested(field_, parse_values, req.parameter, req.values, limit=400)
        results.append(
            bifurcation(ctx.design, axis, periods=req.periods, keep=req.keep, progress=ctx.step)
        )
    for r in results:
        w = _foreign(ctx, r)
        if w is not None:
            s.blocks.append(w)
        period = r.periodicity()
        s.values.setdefault("periods", []).append(period.tolist())
        s.blocks.append(
            interactive(
                _bifurcation_plotly(r),
                r.plot(),
                f"bifurcation diagram over {r.data.attrs['parameter']}: drag to zoom",
                div_id=f"bifurcation-{len(s.values['periods'])}",
            )
        )
        counts: dict[str, int] = {}
        for p in period:
            key = f"period-{p}" if p else "not periodic (<= 12)"
            counts[key] = counts.get(key, 0) + 1
        s.blocks.append(table(["motion", "values"], sorted(counts.items()), name="periodicity"))
    return s


def _regime_plotly(res: Any) -> Any:
    import plotly.graph_objects as go

    from ..analysis.nonlinear import axis_label, shown_values

    ds = res.data
    X, Y = shown_values(ds["p0"]), shown_values(ds["p1"])
    lab = np.asarray(res.labels())[0]
    classes = sorted(set(lab.ravel().tolist()))
    idx = np.vectorize(classes.index)(lab)
    fig = go.Figure(
        go.Heatmap(
            x=X,
            y=Y,
            z=idx,
            text=lab,
            hovertemplate="%{x:.4g}, %{y:.4g}: %{text}<extra></extra>",
            colorscale="Viridis",
            showscale=True,
            zmin=-0.5,
            zmax=len(classes) - 0.5,
            colorbar=dict(tickvals=list(range(len(classes))), ticktext=classes, title="motion"),
        )
    )
    fig.update_layout(
        xaxis_title=axis_label(ds["p0"], ds.attrs["x"]),
        yaxis_title=axis_label(ds["p1"], ds.attrs["y"]),
        height=480,
        template="plotly_white",
        margin=dict(t=30, l=70, r=20, b=50),
    )
    return fig


def regime_map_section(ctx: Context) -> Section | None:
    req, results = _wanted(ctx, "regime_map", "regime-map")
    if req is None and not results:
        return None

    s = Section("regime-map", "Regime map")
    if req is not None:
        from ..analysis.regime_map import regime_map
        from ..analysis.sweep import parse_path_values

        axes = [_requested(f"report.regime_map.{name}", parse_path_values, getattr(req, name),
                           limit=200) for name in ("x", "y")]  # fmt: skip
        results.append(
            regime_map(ctx.design, axes[0], axes[1], periods=req.periods, keep=req.keep,
                       progress=ctx.step)
        )  # fmt: skip
    for k, r in enumerate(results):
        w = _foreign(ctx, r)
        if w is not None:
            s.blocks.append(w)
        lab = np.asarray(r.labels())
        s.values.setdefault("classes", []).append(sorted(set(lab.ravel().tolist())))
        s.blocks.append(
            interactive(
                _regime_plotly(r),
                r.plot(),
                "motion class over the two parameters (first branch): hover for values",
                div_id=f"regime-map-{k + 1}",
            )
        )
    return s


#: Section builders in report order (provenance is added by the report itself).
SECTIONS: list[tuple[str, str, Callable[[Context], Section | None]]] = [
    ("design", "Design inputs", design_section),
    ("kinematics", "Kinematics", kinematics_section),
    ("modal", "Natural frequencies and mode shapes", modal_section),
    ("sensitivity", "Sensitivity", sensitivity_section),
    ("campbell", "Campbell diagram and resonance verdict", campbell_section),
    ("bodies", "Gear-body modes", bodies_section),
    ("response", "Nonlinear response", response_section),
    ("bifurcation", "Bifurcation diagram", bifurcation_section),
    ("regime-map", "Regime map", regime_map_section),
    ("surfaces", "Tooth surfaces", surfaces_section),
    ("closed-graph", "Closed graph", closed_graph_section),
    ("contact", "Loaded tooth contact", contact_section),
]


def repo_assumptions() -> str:
    """docs/assumptions.md: of the source checkout, or the copy a wheel ships in
    ``reducerlab/data``; '' when neither is there."""
    here = Path(__file__).resolve()
    for path in (
        here.parents[3] / "docs" / "assumptions.md",
        here.parents[1] / "data" / "assumptions.md",
    ):
        if path.is_file():
            return path.read_text(encoding="utf-8")
    return ""
