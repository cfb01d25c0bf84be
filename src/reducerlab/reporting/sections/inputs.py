"""Report sections on what the drive is: its design inputs (as written and in SI, with
the papers' assumptions in force) and its kinematics."""

from __future__ import annotations

import html
import re
import tomllib
from typing import Any

from ...design import NOT_ANALYSED, Design, field_kind
from ...design_files import apply_overrides, lookup
from ...kinematics import TRAINS
from ...numformat import Column, Value, quantity_table
from ...units import QUANTITIES, RPM
from ..blocks import Block, Section, details, figure, note, table
from ..context import Context

__all__ = ["assumption_sections", "design_section", "drive_papers",
           "kinematics_section"]  # fmt: skip


def drive_papers(design: Design) -> tuple[str, ...]:
    """Headings (their starts) of the docs/assumptions.md sections that apply to the
    design's drive: the ``papers`` of its kinematic train
    (:data:`reducerlab.kinematics.TRAINS`), none for a drive without one."""
    train = TRAINS.get(design.drive_name)
    return train.papers if train is not None else ()


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


def assumption_sections(text: str, keys: tuple[str, ...]) -> list[tuple[str, str]]:
    """``(heading, body)`` of the docs/assumptions.md sections whose headings start with
    one of ``keys`` (see :func:`drive_papers`)."""
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
    for key, value in _flatten(d.model_dump(mode="json", exclude=set(NOT_ANALYSED))):
        if key in ("name", "description"):
            continue
        as_written = lookup(written, key)
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
    inputs = table([Column("field", kind="text"), Column("as written", kind="text"),
                    Column("SI value", kind="exact"), Column("SI unit", kind="text")],
                   rows, name="inputs")  # fmt: skip
    s.blocks.append(details(f"all {len(rows)} fields, as written and in SI", inputs.html, "table"))
    if ctx.text:
        s.blocks.append(details("the design file", f"<pre>{html.escape(ctx.text)}</pre>", "pre"))
    sections = assumption_sections(ctx.assumptions, drive_papers(d))
    if sections:
        items = "".join(details(h, f"<pre>{html.escape(b)}</pre>").html for h, b in sections)
        s.blocks.append(
            note("Choices in force where the papers are silent or ambiguous (docs/assumptions.md):")
        )
        s.blocks.append(Block(f'<div class="assumptions">{items}</div>', "assumptions"))
    s.values["inputs"] = len(rows)
    return s


def kinematics_section(ctx: Context) -> Section | None:
    """Transmission ratio, member speeds, mesh frequencies (designs with kinematics)."""
    if ctx.design.kinematics() is None:
        return None
    from ...analysis.kinematics import kinematics
    from ...drives import kinematics_of

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
            quantity_table(
                [
                    ("transmission ratio i = omega_in / omega_out", Value(ratio, "ratio"), ""),
                    ("input speed", float(ds.attrs["input_speed_rad_s"]) * RPM, "rpm"),
                ]
            ),
            name="ratio",
        )
    )
    members = [
        (str(m), float(v)) for m, v in zip(ds["member"].values, ds["speed_rpm"].values, strict=True)
    ]
    s.blocks.append(table([Column("member", kind="text"), Column("speed", "rpm", "speed")],
                          members, name="members"))  # fmt: skip
    meshes = [
        (str(m), float(v))
        for m, v in zip(ds["mesh"].values, ds["mesh_frequency"].values, strict=True)
    ]
    heads = [Column("mesh", kind="text"), Column("mesh frequency", "Hz", "frequency")]
    s.blocks.append(table(heads, meshes, name="meshes"))
    if "omega" in ds:
        s.blocks.append(figure(res.plot(), "angular velocity over one input turn"))
    return s
