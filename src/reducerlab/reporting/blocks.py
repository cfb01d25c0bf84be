"""HTML building blocks of the design report: escaped tables (numbers by the one rule of
:mod:`reducerlab.numformat`) with the full-precision value of every number
(``data-value``), matplotlib figures as embedded PNG, plotly
figures as ``<div>`` drawn by the plotly.js embedded once in the page."""

from __future__ import annotations

import base64
import html
import io
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from ..numformat import Column, Table, Value, is_number, unit_kind

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "Block",
    "Cell",
    "details",
    "figure",
    "header_kind",
    "interactive",
    "note",
    "pre",
    "table",
    "verdict",
]


@dataclass(frozen=True)
class Block:
    """One piece of a section: its HTML (already escaped) and a kind for the template."""

    html: str
    kind: str = "html"


@dataclass(frozen=True)
class Cell:
    """A table cell: ``text`` as shown and, for a number, its full ``value``."""

    text: str
    value: float | None = None


def header_kind(header: str) -> str:
    """The kind of the numbers under a plain header: by the unit it ends with,
    ``"speed (rpm)"`` → ``speed``, ``"margin (%)"`` → ``percent``
    (:func:`~reducerlab.numformat.unit_kind`); ``value`` without one."""
    m = re.search(r"\(([^()]*)\)\s*$", header)
    return unit_kind(m.group(1)) if m else "value"


def _cell(x: Any, column: Column | None, kind: str = "value") -> Cell:
    """A cell of a value in ``column`` (:func:`~reducerlab.numformat.fmt` by the
    column's kind); in an untyped column (a plain header) an integer is a count and any
    other number of ``kind`` (:func:`header_kind`)."""
    if isinstance(x, Cell):
        return x
    if isinstance(x, Value):
        return Cell(str(x), None if x.number is None else float(x.number))
    if column is None:
        kind = "count" if isinstance(x, int | np.integer) else kind
        column = Column("", kind=kind if is_number(x) else "text")
    text = column.cell(x)
    if column.numeric and is_number(x):
        return Cell(text, float(x))
    return Cell(text)


def table(
    headers: Sequence[str | Column] | Table,
    rows: Sequence[Sequence[Any]] = (),
    *,
    caption: str = "",
    name: str = "",
) -> Block:
    """A table; numbers are shown by the one rule of :mod:`reducerlab.numformat` (the
    kind of a :class:`~reducerlab.numformat.Column`, units in its header) and keep their
    full value in ``data-value`` (what the tests compare with the API). ``headers`` may
    be a whole :class:`~reducerlab.numformat.Table` (then without ``rows``): the same
    cells as its plain text and the command line's table. ``name`` sets ``data-table``."""
    if isinstance(headers, Table):
        if not caption and headers.title:
            caption = headers.title
        headers, rows = headers.columns, headers.rows
    columns = [h if isinstance(h, Column) else None for h in headers]
    kinds = [header_kind(h) if isinstance(h, str) else "value" for h in headers]
    out = [f'<table class="data" data-table="{html.escape(name)}">']
    if caption:
        out.append(f"<caption>{html.escape(caption)}</caption>")
    heads = [h.header if isinstance(h, Column) else h for h in headers]
    out.append("<thead><tr>")
    for h, c in zip(heads, columns, strict=True):
        cls = ' class="num"' if c is not None and c.numeric else ""
        out.append(f"<th{cls}>{html.escape(h)}</th>")
    out.append("</tr></thead><tbody>")
    for row in rows:
        cells = []
        for i, x in enumerate(row):
            inside = i < len(columns)
            c = _cell(x, columns[i] if inside else None, kinds[i] if inside else "value")
            if c.value is None:
                cells.append(f"<td>{html.escape(c.text)}</td>")
            else:
                cells.append(f'<td class="num" data-value="{c.value!r}">{html.escape(c.text)}</td>')
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</tbody></table>")
    return Block("".join(out), "table")


def png_data(fig: Figure, dpi: int = 110) -> str:
    """``data:`` URI of a matplotlib figure rendered as PNG, reduced to an adaptive
    256-colour palette (median cut, no dithering) and optimised: a plot's lines, text
    and colour maps keep their colours to a few levels of 255, at a third of the bytes
    of the RGBA image (issue 32: the report's size is mostly its figures)."""
    from PIL import Image

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    buf.seek(0)
    with Image.open(buf) as im:
        pal = im.convert("RGB").quantize(
            colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE
        )
    out = io.BytesIO()
    pal.save(out, format="PNG", optimize=True)
    return "data:image/png;base64," + base64.b64encode(out.getvalue()).decode("ascii")


def figure(fig: Figure, caption: str = "", *, dpi: int = 110) -> Block:
    """A static matplotlib figure, embedded."""
    cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
    return Block(
        f'<figure><img alt="{html.escape(caption or "figure")}" '
        f'src="{png_data(fig, dpi)}">{cap}</figure>',
        "figure",
    )


#: Resolution (dpi) of an interactive figure's still, shown only where scripts do not
#: run: a thumbnail that keeps a report of a drive with several body renders under
#: 1.5 MB (issue 32).
FALLBACK_DPI = 60


def interactive(fig: Any, fallback: Figure | None, caption: str = "", *, div_id: str) -> Block:
    """A plotly figure (its script needs the page's embedded plotly.js) with the static
    ``fallback`` shown where scripts do not run."""
    body = fig.to_html(
        full_html=False,
        include_plotlyjs=False,
        div_id=f"fig-{div_id}",
        config={"displaylogo": False, "responsive": True},
    )
    still = ""
    if fallback is not None:
        src = png_data(fallback, FALLBACK_DPI)
        still = f'<noscript><img alt="static version" src="{src}"></noscript>'
    cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
    return Block(f'<figure class="interactive">{body}{still}{cap}</figure>', "interactive")


def note(text: str, kind: str = "note") -> Block:
    """A short paragraph (``kind``: note, warning, ok)."""
    return Block(f'<p class="{kind}">{html.escape(text)}</p>', kind)


def details(summary: str, inner_html: str, kind: str = "details") -> Block:
    """A collapsed ``<details>`` block: ``summary`` (text) over ``inner_html`` (HTML)."""
    return Block(f"<details><summary>{html.escape(summary)}</summary>{inner_html}</details>", kind)


def pre(text: str) -> Block:
    """Preformatted text (a verdict, a design file)."""
    return Block(f"<pre>{html.escape(text)}</pre>", "pre")


def verdict(ok: bool, text: str) -> Block:
    """A coloured verdict line."""
    cls = "ok" if ok else "risk"
    return Block(f'<p class="verdict {cls}">{html.escape(text)}</p>', "verdict")


@dataclass
class Section:
    """One section of the report: id, title, blocks, the numbers it reports (by key),
    its run time (s) and, if it failed, the error shown in its place."""

    id: str
    title: str
    blocks: list[Block] = field(default_factory=list)
    values: dict[str, Any] = field(default_factory=dict)
    seconds: float = 0.0
    error: str | None = None
    details: str | None = None
    #: Read from a :class:`~reducerlab.reporting.SectionMemo` (built by an earlier
    #: report of the same inputs); ``seconds`` is then the time it took to build.
    reused: bool = False
