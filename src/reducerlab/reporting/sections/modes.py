"""Report sections on the linear vibration of the drive: natural frequencies and mode
shapes, their sensitivities, the Campbell diagram with the verdict, and the gear-body
modes given to the report."""

from __future__ import annotations

from typing import Any

import numpy as np

from ...analysis.resonance import format_components
from ...drives import drive_layout
from ...numformat import Column
from ...plot.campbell import plotly_campbell
from ...plot.campbell_style import excitation_label, modes_text, unique_crossings
from ...plot.drive_shape import plotly_drive_shapes
from ...plot.modal import plotly_mode_shapes, plotly_sensitivity
from ..blocks import Block, Section, figure, interactive, note, pre, table, verdict
from ..context import Context

__all__ = [
    "bodies_section",
    "campbell_section",
    "crossing_rows",
    "modal_section",
    "sensitivity_section",
]


def modal_section(ctx: Context) -> Section | None:
    """Natural frequencies, classification, mode shapes and energy shares."""
    if not ctx.has_model():
        return None
    res = ctx.modal()
    ds = res.data
    s = Section("modal", "Natural frequencies and mode shapes")
    freq = [float(f) for f in ds["frequency"].values]
    s.values["frequencies_hz"] = freq
    s.blocks.append(table(res.table_data(), name="modes"))
    if ds.attrs.get("skew_velocity_terms"):
        s.blocks.append(
            note(
                "The model has gyroscopic, Coriolis or circulatory terms; these "
                "undamped modes leave them out (see the Campbell section).",
                "warning",
            )
        )
    elastic = [int(m) for m, r in zip(ds["mode"].values, ds["rigid"].values, strict=True) if not r]
    if elastic:
        layout = drive_layout(ctx.design, ctx.model())
        shown = plotly_drive_shapes(res, layout)
        count = len(shown.layout.meta["modes"])
        s.blocks.append(
            interactive(
                shown,
                res.plot_drive(layout, elastic[:3], panel=2.8),
                "mode shapes as the drive moving: the bodies of the model at their places "
                "in the drive, grey at rest; choose a mode, press play, drag to turn"
                + (f" (the first {count} elastic modes)" if count < len(elastic) else ""),
                div_id="drive-shapes",
            )
        )
    s.blocks.append(
        interactive(
            plotly_mode_shapes(res),
            res.plot_shapes(elastic[:3] or None),
            "mode shapes DOF by DOF (the mass-normalised shape, translations in m over "
            "rotations in rad, as 'reducerlab modal -o' draws them): choose a mode",
            div_id="mode-shapes",
        )
    )
    s.blocks.append(figure(res.plot_energy(), "kinetic and strain energy shares"))
    return s


def sensitivity_section(ctx: Context) -> Section | None:
    """Relative sensitivities of every natural frequency to every model parameter."""
    if not ctx.has_model():
        return None
    from ...analysis.modal import frequency_sensitivity
    from ...model.inspect import parameter_paths

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
            [
                Column("mode", kind="count"),
                Column("frequency", "Hz", "frequency"),
                Column("most sensitive parameter", kind="text"),
                Column("(p/f) df/dp", kind="share"),
            ],
            rows,
            name="sensitivity",
        )
    )
    cells = res.map_cells()
    s.values["map_left_out"] = {
        "rigid_modes": cells.rigid,
        "negligible": cells.negligible,
        "at_zero": cells.at_zero,
    }
    if cells.modes and cells.parameters:
        s.blocks.append(
            interactive(
                plotly_sensitivity(res),
                res.plot(),
                "relative sensitivities (p/f) df/dp of the elastic modes (rigid-body modes "
                "left out), every parameter that moves a mode by 0.005 or more: hover for "
                "values",
                div_id="sensitivity-map",
            )
        )
    if cells.negligible or cells.at_zero:
        s.blocks.append(note(cells.note()))
    return s


def campbell_section(ctx: Context) -> Section | None:
    """The verdict (issue 27: the resonance check over the operating range, each
    crossing weighted by how strongly its excitation drives the mode, and the nonlinear
    response at the operating point) and the Campbell diagram it used (damped,
    whirl-split branches with gyroscopic terms), with the given body modes."""
    if not ctx.has_model():
        return None
    _, hi = ctx.design.operating_range()
    if hi == 0:
        return None
    s = Section("campbell", "Campbell diagram and verdict")
    v = ctx.verdict()
    check = v.resonance
    gyro = check["frequencies"] != "undamped"
    res = check.campbell  # the diagram the verdict used: never computed again
    s.values.update(
        ok=v.ok,
        resonance_ok=check.ok,
        crossings=check["crossings"],
        near=check["near"],
        unstable=check["stability"]["unstable"],
        reasons=v.reasons,
    )
    risks = v.risks
    s.blocks.append(
        verdict(
            v.ok,
            "no risk in the operating range or at the operating point"
            if v.ok
            else f"RISK: {len(risks)} finding(s), see the reasons below",
        )
    )
    s.blocks.append(
        table(
            ["status", "rule", "reason", "value", "threshold"],
            [
                (
                    r["status"].upper(),
                    r["rule"],
                    r["text"],
                    _shown(r["value"]),
                    _shown(r["threshold"]),
                )
                for r in v.reasons
            ],
            name="reasons",
            caption="the verdict's reasons (thresholds: the design's "
            "[check] table, docs/assumptions.md)",
        )
    )
    s.blocks.append(
        interactive(
            plotly_campbell(res, check),
            check.plot(),
            "Campbell diagram: hover for values, drag to zoom"
            + (" (damped, whirl-split branches)" if gyro else ""),
            div_id="campbell",
        )
    )
    rows = crossing_rows(check, gyro)
    s.values["crossing_table"] = rows
    if rows:
        s.blocks.append(
            table(
                [
                    "mode",
                    "excitation",
                    "kind",
                    "speed (rpm)",
                    "frequency (Hz)",
                    "margin (%)",
                    "drive (%)",
                    "excited",
                ]
                + (["whirl"] if gyro else []),
                rows,
                name="crossings",
                caption="each crossing of the diagram once (the modes of a repeated "
                "frequency together), and the modes within "
                f"{100 * check['margin']:g} % of an excitation in the operating range "
                "(near: closest approach); margin: a crossing's distance from the "
                "operating range (relative to its nearest end, 0 inside), a near row's "
                "distance from the excitation; drive: the mode's mesh strain (mesh "
                "orders) or forward whirl (1x input) share",
            )
        )
    least = check.get("stability", {}).get("least_damped")
    if least is not None:
        s.blocks.append(
            note(
                f"Least damped mode over the checked speeds: mode {least['mode']} "
                f"({least['frequency_hz']:.5g} Hz) at {least['speed_rpm']:.5g} rpm, damping "
                f"ratio {least['damping_ratio']:.3g}."
            )
        )
    if check.get("components"):
        s.blocks.append(
            figure(
                check.plot_components(),
                "gear-body modes and the system modes on one frequency axis, with the "
                "excitation frequencies over the operating range (paper 000 Table 5)",
            )
        )
        s.blocks.append(pre(format_components(check)))
    return s


def crossing_rows(check: dict, gyro: bool) -> list[tuple]:
    """One row per crossing of the verdict's diagram (the tracked modes of a repeated
    frequency in one row) and per near miss that is not a crossing in the range:
    ``(modes, excitation with its order, kind, speed rpm, frequency Hz, margin %,
    drive %, excited[, whirl])``."""
    res = check.campbell
    ds = res.data
    orders = dict(zip(map(str, ds["excitation"].values), ds["order"].values, strict=True))
    lo, hi = check["speed_range_rpm"]
    judged = {(c["excitation"], f"{c['speed_rpm']:.6g}", c["mode"]): c for c in check["crossings"]}
    rows: list[tuple] = []
    for group in unique_crossings(res.crossings()):
        c = group[0]
        w = c["speed_rpm"]
        done = [judged.get((r["excitation"], f"{r['speed_rpm']:.6g}", r["mode"])) for r in group]
        done = [d for d in done if d is not None]
        if lo <= w <= hi:
            kind, margin = "crossing in range", 0.0
        else:
            edge = lo if w < lo else hi
            kind = "crossing outside range"
            margin = 100 * (w - edge) / edge if edge > 0 else float("nan")
        shares = [_drive(d) for d in done]
        drive = max((x for x in shares if x == x), default=float("nan"))
        label = excitation_label(c["excitation"], orders[c["excitation"]])
        judged_text = "yes" if any(d["excited"] for d in done) else ("no" if done else "")
        rows.append(
            (modes_text(group).split(" ", 1)[1], label, kind, w, c["frequency_hz"], margin,
             drive, judged_text)
            + ((c.get("whirl", ""),) if gyro else ())
        )  # fmt: skip
    crossed = {(c["mode"], c["excitation"]) for c in check["crossings"]}
    for r in check["near"]:
        if (r["mode"], r["excitation"]) in crossed:
            continue  # listed as its crossing
        rows.append(
            (str(r["mode"]), excitation_label(r["excitation"], orders[r["excitation"]]), "near",
             r["speed_rpm"], r["natural_hz"], 100 * r["distance"], _drive(r),
             "yes" if r["excited"] else "no")
            + ((r.get("whirl", ""),) if gyro else ())
        )  # fmt: skip
    return rows


def _drive(row: dict) -> float:
    """A row's mesh strain or forward whirl share in per cent (NaN where none)."""
    share = row.get("mesh_share", row.get("forward_share"))
    return float("nan") if share is None else 100 * share


def _shown(x: object) -> object:
    """A reason's value or threshold for a table cell (None: empty)."""
    return "" if x is None else x


def distinct_modes(families: Any, labels: list[str]) -> tuple[list[int], list[str]]:
    """The modes a render shows: a repeated pair of a cyclically symmetric body (two
    modes at one frequency, the second the first turned by a quarter wave) once,
    labelled as a pair; the table above still lists both.

    Parameters
    ----------
    families : array_like of int (modes,)
        Each mode's family (the body result's ``family``: its repeated pair, grouped
        by :func:`~reducerlab.fe.modetypes.mode_families`), modes ascending.
    labels : list of str
        The modes' type names.

    Returns
    -------
    keep : list of int
        Indices of the modes drawn: the first of each family.
    labels : list of str
        Their labels, ``" (pair)"`` added where the family has two modes.
    """
    fam = np.asarray(families).tolist()
    keep = [i for i, k in enumerate(fam) if k not in fam[:i]]
    return keep, [labels[i] + (" (pair)" if fam.count(fam[i]) > 1 else "") for i in keep]


def _body_render(r: Any, label: str, bodies: int) -> Block:
    """A body's modes as an interactive 3-D render (its surface decimated so that the
    report's bodies stay within a few hundred kB together) over the static grid of
    renders."""
    from ...plot.body import plot_body_modes_grid
    from ...plot.body_plotly import MAX_FACES, plotly_body_modes

    a = r.data.attrs
    title = f"Gear {a.get('gear')} body modes ({a.get('boundary')})"
    ds = r.data  # a result built by hand may lack the families: each mode its own
    family = ds["family"].values if "family" in ds else np.arange(ds.sizes["mode"])
    keep, labels = distinct_modes(family, r.labels)
    shapes = np.asarray(r.shapes)[:, :, keep]
    freqs = np.asarray(r.frequencies)[keep]
    args = (r.mesh.points, r.mesh.tets[:, :4], shapes, freqs, labels, title)
    faces = max(MAX_FACES // 4, MAX_FACES // bodies)
    # the still for readers without scripts only where one or two bodies are shown: the
    # renders of four gear bodies with their stills would pass the report's 1.5 MB
    still = plot_body_modes_grid(*args, side=1.6 if bodies == 1 else 1.2) if bodies <= 2 else None
    return interactive(
        plotly_body_modes(*args, max_faces=faces),
        still,
        f"{label}: mode shapes, the surface coloured by the displacement magnitude: "
        "choose a mode, drag to turn",
        div_id=f"body-modes-{a.get('gear', 0)}",
    )


def bodies_section(ctx: Context) -> Section | None:
    """Gear-body (finite-element) modes given to the report."""
    given = ctx.given("body-modal")
    if not given:
        return None
    s = Section("bodies", "Gear-body modes (finite elements)")
    s.blocks.append(
        note(
            "Free-body finite-element modes of the gear blanks (paper 000 §4), "
            "from 'reducerlab body-modal' or 'reducerlab run' results; the verdict above "
            "checks them against the excitations and the system modes (renders where the "
            "mesh is at hand: computed in this run, not read from a netCDF file)."
        )
    )
    for r in given:
        ds = r.data
        label = str(ds.attrs.get("title", "gear body"))
        rows = [
            (int(m), float(f), str(t))
            for m, f, t in zip(
                ds["mode"].values, ds["frequency"].values, ds["type"].values, strict=True
            )
        ]
        s.values.setdefault("frequencies_hz", []).append([row[1] for row in rows])
        s.blocks.append(
            table(
                [
                    Column("mode", kind="count"),
                    Column("frequency", "Hz", "frequency"),
                    Column("type", kind="text"),
                ],
                rows,
                caption=label,
                name="body-modes",
            )
        )
        if r.mesh is not None and r.shapes is not None:  # computed here, or by a run
            s.blocks.append(_body_render(r, label, len(given)))
        mass = ds.attrs.get("mass_kg")
        if mass is not None:
            s.values.setdefault("mass_kg", []).append(float(mass))
    return s
