"""Report sections on the gear geometry: tooth surfaces, the closed graph of an internal
pair, and loaded tooth contact results given to the report (with a KHV pair's load
sharing against torque, ``khv-sharing``: ``report --with`` or ``run --sharing``)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...numformat import Column, fmt, quantity_table
from ..blocks import Section, figure, interactive, note, table
from ..context import Context

__all__ = ["ball_track_section", "closed_graph_section", "contact_section", "surfaces_section"]


def surfaces_section(ctx: Context) -> Section | None:
    """One tooth sector of each gear of pair 1 (designs with tooth surfaces)."""
    d = ctx.design
    if not d.has_tooth_surfaces:
        return None
    from ...geometry import generate_tooth
    from ...geometry.solid import build_gear_solid
    from ...plot.surface import plot_tooth

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
    """The internal pair's closed graph and its conditions (KHV designs, whose gears
    are an internal pair)."""
    if ctx.design.type != "khv":
        return None
    from ...plot.khv import plot_closed_graph

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


def _sharing_rows(res: Any) -> list[tuple[Any, ...]]:
    """One row a torque of a :class:`~reducerlab.analysis.khv_sharing.SharingResult`:
    torque (N m), tooth pairs in contact over the cycle (least-most), mean secant and
    tangent stiffness (N/m), TE peak-to-peak (um); NaN where a torque has none (zero)."""
    ds = res.data
    rows = []
    for i, t in enumerate(res.torques):
        n = ds["pairs"].values[i]
        seen = n[np.isfinite(n)]
        lo, hi = (int(seen.min()), int(seen.max())) if t > 0 and seen.size else (0, 0)
        pairs = "-" if hi == 0 else str(lo) if lo == hi else f"{lo}-{hi}"
        rows.append((float(t), pairs, float(ds["mean_stiffness"].values[i]),
                     float(ds["mean_tangent_stiffness"].values[i]),
                     1e6 * float(ds["peak_to_peak"].values[i])))  # fmt: skip
    return rows


def _sharing_blocks(s: Section, given: list[Any]) -> None:
    """The load sharing results' tables and figures, into ``s``."""
    for r in given:
        rows = _sharing_rows(r)
        s.values.setdefault("sharing", []).append(rows)
        a = r.data.attrs
        s.blocks.append(
            table(
                [Column("torque on the planet", "N m", "torque"),
                 Column("tooth pairs in contact", kind="text"),
                 Column("mean k", "N/m", "stiffness"), Column("mean tangent k", "N/m", "stiffness"),
                 Column("TE peak-to-peak", "um", "length")],
                rows, name="khv-sharing",
                caption=f"KHV internal pair: load sharing against torque over one mesh "
                f"cycle ({r.data.sizes['position']} positions), tooth pairs examined "
                f"{a.get('pairs_examined', '')}, design load "
                f"{fmt(float(a['design_torque']), 'torque')} N m",
            )
        )  # fmt: skip
        s.blocks.append(
            figure(
                r.figure(),
                "load share of each tooth pair over the mesh cycle; tooth pairs in "
                "contact and mean mesh stiffness against torque",
            )
        )


def contact_section(ctx: Context) -> Section | None:
    """Loaded tooth contact results given to the report, and a KHV pair's load sharing
    against torque."""
    given = ctx.given("contact")
    sharing = ctx.given("khv-sharing")
    if not given and not sharing:
        return None
    from ...plot.contact import plot_contact
    from ...plot.contact_pattern import plotly_bearing_pattern

    s = Section("contact", "Loaded tooth contact")
    for r in given:
        summ = r.summary()
        s.values.setdefault("summaries", []).append(summ)
        rows = [
            ("mean mesh stiffness", summ["k_mean"], "N/m"),
            ("transmission error peak-to-peak", summ["te_peak_to_peak"] * 1e6, "um"),
            ("peak contact pressure", summ["peak_pressure_max"] * 1e-6, "MPa"),
            ("interior contact pressure", summ["interior_pressure_max"] * 1e-6, "MPa"),
            ("von Mises stress, max", summ["von_mises_max"] * 1e-6, "MPa"),
            ("mean contact area", summ["contact_area_mean"] * 1e6, "mm^2"),
            ("mean normal force", summ["normal_force_mean"], "N"),
        ]
        s.blocks.append(
            table(
                quantity_table(rows),
                name="contact",
                caption=str(r.attrs.get("title", "")),
            )
        )
        pair = int(r.attrs.get("pair", len(s.blocks)))
        s.blocks.append(
            interactive(
                plotly_bearing_pattern(r),
                None,  # its still is panel (a) of the overview below
                "bearing pattern: the highest contact pressure over the mesh cycle on the "
                "developed flank, inside its outline (hover for values)",
                div_id=f"bearing-pattern-{pair}",
            )
        )
        s.blocks.append(
            figure(
                plot_contact(r),
                "bearing pattern, mesh stiffness (with the Eq. 8 law the dynamic model uses), "
                "transmission error and stresses over one mesh period",
            )
        )
    _sharing_blocks(s, sharing)
    return s


def ball_track_section(ctx: Context) -> Section | None:
    """The cycloid ball drive's ball track against torque (``analysis.ball_track``):
    loaded balls, torsional stiffness and the largest ball force from zero to 1.5 times
    the load, the balls' forces round the track at the load (designs that give the
    balls and grooves: ``CycloidBallDesign.ball_track``)."""
    d = ctx.design
    if d.type != "cycloid_ball" or not hasattr(d, "ball_track"):
        return None
    from ...errors import ReducerlabError

    try:
        d.ball_track()
    except ReducerlabError:  # the design gives no balls and grooves
        return None
    from ...analysis.ball_track import ball_track_analysis

    s = Section("ball-track", "Ball track: load sharing and stiffness")

    res = ball_track_analysis(d, points=7, phases=4)
    rows = [
        (r["torque_N_m"], f"{r['loaded_min']}-{r['loaded_max']}",
         r["torsional_stiffness_N_m_per_rad"] / 1e3, r["translational_stiffness_N_per_m"],
         r["max_force_N"])
        for r in res.summary()
    ]  # fmt: skip
    at = min(res.summary(), key=lambda r: abs(r["torque_N_m"] - res.attrs["rated_torque_N_m"]))
    s.values.update({
        "rated_torque": res.attrs["rated_torque_N_m"], "loaded_at_rated": at["loaded_max"],
        "torsional_stiffness_at_rated": at["torsional_stiffness_N_m_per_rad"],
        "undercut_lines": res.attrs["undercut_lines"],
    })  # fmt: skip
    s.blocks.append(
        table(
            [Column("torque", "N m", "torque"), Column("loaded balls", kind="text"),
             Column("torsional stiffness", "kN m/rad", "stiffness"),
             Column("K_mx", "N/m", "stiffness"), Column("largest ball force", "N", "force")],
            rows, name="ball-track",
            caption=f"{res.attrs['balls']} balls; mean over 4 positions of the ball set; "
            f"{res.attrs['undercut_lines']} of {2 * res.attrs['balls']} contact lines undercut",
        )
    )  # fmt: skip
    s.blocks.append(figure(res.plot(), "track stiffness and loaded balls against torque; "
                           "ball forces at the load"))  # fmt: skip
    return s
