"""Report section on load capacity (issue 29): the ISO 6336 / ISO 10300 safety factors of
every gear pair, beside the stresses the loaded tooth contact analysis computed.

The rating is computed here from the design at its own load
(:func:`reducerlab.analysis.rating.load_capacity`: milliseconds); a rating result handed
to the report (``--with rating.nc``) is used instead. The contact
results handed to the report add, per pair, the LTCA's interior peak contact pressure
beside ISO's nominal contact stress ``sigma_H``, and the FE tooth-root stress (when the
contact was run with ``root_stress``) beside ISO's ``sigma_F``; a torque sweep
(``te-sweep``) and a modification layout (``layout``) handed to the report add their
figures. The standard's and the LTCA's stresses differ in kind: the standard's nominal
values carry its load factors (``K_A K_v K_Hbeta K_Halpha``), the LTCA's are the static
stresses of the modelled flanks, so they are compared, not equated.
"""

from __future__ import annotations

import math
from typing import Any

from ...errors import ReducerlabError
from ...numformat import Column
from ..blocks import Section, figure, note, table
from ..context import Context

__all__ = ["capacity_section"]


def _rating(ctx: Context) -> tuple[Any | None, str]:
    from ...analysis.capacity_reasons import rateable

    given = ctx.given("rating")
    if given:
        return given[0], ""
    if not rateable(ctx.design):
        return None, ""
    from ...analysis.rating import load_capacity

    try:
        return load_capacity(ctx.design, method="B"), ""
    except ReducerlabError as e:  # no load, no tooth geometry, double-arc teeth
        return None, str(e)


def _beside(rating: Any, contacts: list[Any]) -> list[tuple[Any, ...]]:
    """Rows: pair, quantity, ISO value, LTCA value (MPa)."""
    rows = []
    names = list(rating.pairs())
    for r in contacts:
        pair = int(r.attrs.get("pair", 1))
        name = names[pair - 1] if pair - 1 < len(names) else names[0]
        summ = r.summary()

        def iso(symbol: str, gear: str, name: str = name) -> float:
            try:
                return rating.value(symbol, gear, name) * 1e-6
            except ReducerlabError:
                return math.nan

        rows.append(
            (
                name,
                "contact stress (MPa)",
                iso("sigma_H", "1"),
                summ["interior_pressure_max"] * 1e-6,
                "ISO sigma_H (gear 1) / LTCA interior peak pressure",
            )
        )
        peak = r.attrs.get("root_stress_peak")
        if peak is not None:
            rows.append(
                (
                    name,
                    "tooth-root stress (MPa)",
                    max(iso("sigma_F", "1"), iso("sigma_F", "2")),
                    float(peak) * 1e-6,
                    "ISO sigma_F (larger gear) / FE largest principal in the fillet",
                )
            )
    return rows


def capacity_section(ctx: Context) -> Section | None:
    """Safety factors per ISO 6336-2/-3 (ISO 10300 method B1 for bevel pairs) and the
    LTCA's stresses beside them."""
    rating, why = _rating(ctx)
    if rating is None:
        if not why:
            return None
        s = Section("capacity", "Load capacity")
        s.blocks.append(note(f"No rating: {why}"))
        return s
    s = Section("capacity", "Load capacity")
    pairs = rating.pairs()
    s.values["safety"] = pairs
    s.values["minimum"] = rating.minimum_safety
    rows = []
    for name, p in pairs.items():
        methods = p.get("methods") or {"B": p}
        for key, m in methods.items():
            for gear, h, f in zip(p["gears"], m["S_H"], m["S_F"], strict=True):
                rows.append((name, gear, key, h, f, m["standard"]))
        if len(methods) > 1:
            for gear, h, f in zip(p["gears"], p["S_H"], p["S_F"], strict=True):
                rows.append((name, gear, "judged", h, f, p["standard"]))
    s.blocks.append(
        table(
            [
                Column("pair", kind="text"),
                Column("gear", kind="text"),
                Column("method", kind="text"),
                Column("S_H", kind="safety"),
                Column("S_F", kind="safety"),
                Column("standard", kind="text"),
            ],
            rows,
            name="safety",
            caption="pitting and tooth-root safety factors",
        )
    )
    s.blocks.append(figure(rating.figure(), "safety factors against their minimums"))
    contacts = ctx.given("contact")
    if contacts:
        beside = _beside(rating, contacts)
        s.values["beside"] = beside
        s.blocks.append(
            table(
                [
                    Column("pair", kind="text"),
                    Column("quantity", kind="text"),
                    Column("ISO", kind="stress"),
                    Column("LTCA", kind="stress"),
                    Column("what", kind="text"),
                ],
                beside,
                name="iso-vs-ltca",
                caption="the standard's nominal stresses (with its load factors) "
                "beside the loaded contact's static stresses",
            )
        )
    for r in ctx.given("te-sweep"):
        s.blocks.append(
            figure(
                r.figure(),
                "loaded transmission error against torque: "
                "TE over the mesh cycle, peak-to-peak and mesh harmonics",
            )
        )
    for r in ctx.given("layout"):
        s.blocks.append(
            figure(
                r.figure(),
                "flank modification layout: TE peak-to-peak over "
                "lead crowning and tip relief, infeasible candidates hatched",
            )
        )
    cond = rating.data.attrs.get("conditions", "")
    s.blocks.append(
        note(
            f"Rating conditions (K-factors, life, lubricant, minimums): {cond}. "
            "Every factor with its clause: 'reducerlab rating DESIGN'."
        )
    )
    return s
