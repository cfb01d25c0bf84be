"""One rule for the numbers of every table: significant digits by quantity kind, units
in the headers (issue 32).

A number is shown by :func:`fmt` with the significant digits of its *kind*:

=============  ==========================================================  ======  ========
kind           quantities                                                  digits  decimals
=============  ==========================================================  ======  ========
``frequency``  natural, mesh and excitation frequencies (Hz)               4       —
``speed``      member and crossing speeds (rpm)                            4       —
``torque``     torques (N m)                                               4       —
``force``      forces (N)                                                  4       —
``stiffness``  stiffnesses (N/m, N m/rad, N m/arcmin)                      4       —
``stress``     stresses and pressures (MPa)                                4       —
``length``     lengths, deflections, errors (mm, um)                       4       —
``angle``      angles (deg, arcmin, arcsec)                                4       —
``power``      power and power loss (W)                                    4       —
``time``       times (s)                                                   3       —
``value``      any other quantity (the default)                            4       —
``ratio``      transmission ratios (exact kinematics, ``-81.3333``)        6       —
``parameter``  a swept parameter's values (neighbours of a fine grid        6       —
               stay apart)
``exact``      values the user wrote, echoed (design inputs)               10      —
``safety``     safety factors (S_H, S_F: ISO 6336 prints three)            3       —
``percent``    shares, margins, efficiencies, deviations (%)               3       2
``share``      dimensionless shares and sensitivities (0..1)               3       4
``count``      counts, mode numbers, tooth numbers, orders                 integer
=============  ==========================================================  ======  ========

The rules, for every kind:

* at most ``digits`` significant digits, trailing zeros after the point dropped
  (``454.006`` Hz is ``454``, a ratio of ``-10.0`` is ``-10``, never ``1500.0000``);
* a kind with ``decimals`` rounds to that many places as well (an absolute resolution:
  ``0.132669 %`` is ``0.13``, ``2.48265e-05 %`` is ``0``): below the resolution a
  share is 0 for a reader, and a catalogue prints it so;
* fixed notation for ``1e-3 <= |x| < 1e6`` (``1382.35`` Hz is ``1382``, ``12345.6`` Hz
  is ``12350``), scientific with the same significant digits outside (``2.483e-5``,
  ``2.1e11``); a kind with ``decimals`` stays fixed below (``0.0004``);
* never ``-0``: a value that rounds to zero is ``0``;
* a missing value (None, NaN) is an em dash ``—``, infinities ``inf`` and ``-inf``;
* a ``count`` is an integer (``3``, not ``3.0``); booleans read ``yes`` and ``no``;
* units belong to the column header, ``name (unit)``, never to the cells; numeric
  columns are right-aligned.

:class:`Table` holds columns (:class:`Column`: name, unit, kind) and rows of raw values
and renders them as plain aligned text (the ``.txt`` files and the commands' tables),
as a rich table (:meth:`Table.rich`) and, through ``reporting.blocks.table``, as the
report's HTML table: the same strings in all three (``tests/test_numbers.py``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = [
    "DASH", "KINDS", "Column", "Kind", "Table", "Value", "fmt", "is_number", "quantity_table",
    "unit_kind",
]  # fmt: skip

DASH = "—"
"""What a missing value (None, NaN) shows."""

#: Fixed notation inside ``[FIXED_LOW, FIXED_HIGH)`` of ``|x|``; scientific outside.
FIXED_LOW = 1e-3
FIXED_HIGH = 1e6


@dataclass(frozen=True)
class Kind:
    """How one kind of quantity is shown: ``digits`` significant digits, at most
    ``decimals`` places after the point (None: no limit), ``integer`` for counts."""

    digits: int
    decimals: int | None = None
    integer: bool = False


KINDS: dict[str, Kind] = {
    "frequency": Kind(4),
    "speed": Kind(4),
    "torque": Kind(4),
    "force": Kind(4),
    "stiffness": Kind(4),
    "stress": Kind(4),
    "length": Kind(4),
    "angle": Kind(4),
    "power": Kind(4),
    "time": Kind(3),
    "value": Kind(4),
    "ratio": Kind(6),
    "parameter": Kind(6),
    "exact": Kind(10),
    "safety": Kind(3),
    "percent": Kind(3, decimals=2),
    "share": Kind(3, decimals=4),
    "count": Kind(0, integer=True),
}
"""The kinds of quantity and how each is shown (the module's table)."""


def is_number(x: Any) -> bool:
    """True for an int or float (numpy's too), not for a bool."""
    return isinstance(x, int | float | np.integer | np.floating) and not isinstance(
        x, bool | np.bool_
    )


def _strip(text: str) -> str:
    """Drop trailing zeros after a decimal point (and the point)."""
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return text


def _scientific(v: float, digits: int) -> str:
    mantissa, _, exponent = f"{v:.{digits - 1}e}".partition("e")
    return f"{_strip(mantissa)}e{int(exponent)}"


def fmt(value: Any, kind: str = "value") -> str:
    """``value`` as a table shows a quantity of ``kind`` (see the module's table).

    Parameters
    ----------
    value : float, int, bool, None or str
        The number in the unit of its column (Hz, rpm, %, ...); text is returned as is.
    kind : str
        A key of :data:`KINDS`.

    Returns
    -------
    str

    Raises
    ------
    KeyError
        An unknown kind.
    """
    k = KINDS[kind]
    if value is None:
        return DASH
    if isinstance(value, bool | np.bool_):
        return "yes" if value else "no"
    if not is_number(value):
        return str(value)
    v = float(value)
    if math.isnan(v):
        return DASH
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if k.integer:
        return str(round(v))
    if k.decimals is not None:
        v = round(v, k.decimals)  # the kind's resolution
    if v == 0:
        return "0"  # never -0
    r = float(f"{v:.{k.digits - 1}e}")  # rounded to the significant digits
    a = abs(r)
    if (a < FIXED_LOW and k.decimals is None) or a >= FIXED_HIGH:
        return _scientific(r, k.digits)
    places = max(k.digits - 1 - math.floor(math.log10(a)), 0)
    if k.decimals is not None:
        places = min(places, k.decimals)
    return _strip(f"{r:.{places}f}")


#: The kind of a quantity given in a unit (a table of mixed quantities, one a row,
#: whose unit column names each row's unit): :func:`unit_kind`.
UNIT_KINDS: dict[str, str] = {
    "Hz": "frequency", "rpm": "speed", "N m": "torque", "N": "force",
    "N/m": "stiffness", "N m/rad": "stiffness", "N m/arcmin": "stiffness",
    "N/(mm um)": "stiffness", "MPa": "stress", "Pa": "stress", "sqrt(MPa)": "stress",
    "m": "length", "mm": "length", "um": "length", "deg": "angle", "rad": "angle",
    "arcmin": "angle", "arcsec": "angle", "W": "power", "s": "time", "%": "percent",
}  # fmt: skip


def unit_kind(unit: str) -> str:
    """The kind of a quantity in ``unit`` (:data:`UNIT_KINDS`), ``"value"`` for any
    other unit."""
    return UNIT_KINDS.get(unit.strip(), "value")


@dataclass(frozen=True)
class Value:
    """A number with its own kind, for a cell of a column of mixed quantities (a
    datasheet's value column, each row's unit in a unit column)."""

    number: float | None
    kind: str = "value"

    def __str__(self) -> str:
        return fmt(self.number, self.kind)


@dataclass(frozen=True)
class Column:
    """A column: its ``name``, the ``unit`` of its numbers (shown in the header) and the
    ``kind`` of quantity (:data:`KINDS`), or ``"text"`` for a column of words."""

    name: str
    unit: str = ""
    kind: str = "value"

    def __post_init__(self) -> None:
        if self.kind != "text" and self.kind not in KINDS:
            raise KeyError(f"column {self.name!r}: unknown kind {self.kind!r}")

    @property
    def header(self) -> str:
        """``name (unit)``, or the name alone."""
        return f"{self.name} ({self.unit})" if self.unit else self.name

    @property
    def numeric(self) -> bool:
        """True for a column of numbers (right-aligned)."""
        return self.kind != "text"

    def cell(self, value: Any) -> str:
        """``value`` as this column shows it."""
        if isinstance(value, Value):
            return str(value)
        if self.kind == "text":
            return DASH if value is None else str(value)
        return fmt(value, self.kind)


@dataclass
class Table:
    """A table of raw values with typed columns; :meth:`text`, :meth:`rich` and the
    report's ``reporting.blocks.table`` render the same cells.

    Attributes
    ----------
    columns : sequence of Column
    rows : list of sequences
        Raw values (numbers in the columns' units, text, None).
    title : str
        A line above the table (plain text and rich).
    """

    columns: Sequence[Column]
    rows: list[Sequence[Any]] = field(default_factory=list)
    title: str = ""

    def add(self, *values: Any) -> None:
        """Append a row (one value per column)."""
        if len(values) != len(self.columns):
            raise ValueError(f"row of {len(values)} values for {len(self.columns)} columns")
        self.rows.append(values)

    @property
    def headers(self) -> list[str]:
        """The column headers, ``name (unit)``."""
        return [c.header for c in self.columns]

    def cells(self) -> list[list[str]]:
        """Every row's cells as text."""
        return [[c.cell(v) for c, v in zip(self.columns, row, strict=True)] for row in self.rows]

    def text(self, indent: str = "") -> str:
        """Plain aligned text: the title, the headers, one line a row; numeric columns
        right-aligned, text columns left-aligned, two spaces between columns."""
        cells = self.cells()
        heads = self.headers
        widths = [max([len(h), *(len(r[i]) for r in cells)]) for i, h in enumerate(heads)]

        def line(items: Iterable[str]) -> str:
            parts = [
                s.rjust(w) if c.numeric else s.ljust(w)
                for s, w, c in zip(items, widths, self.columns, strict=True)
            ]
            return (indent + "  ".join(parts)).rstrip()

        lines = [self.title] if self.title else []
        lines.append(line(heads))
        lines += [line(r) for r in cells]
        return "\n".join(lines)

    def rich(self) -> Any:
        """A ``rich.table.Table`` of the same cells; headers never cut (each column is
        at least as wide as its header) and numbers never wrapped."""
        from rich.table import Table as RichTable

        t = RichTable(title=self.title or None)
        cells = self.cells()
        for i, c in enumerate(self.columns):
            widest = max([len(c.header), *(len(r[i]) for r in cells)])
            t.add_column(
                c.header,
                justify="right" if c.numeric else "left",
                min_width=widest if c.numeric else len(c.header),
                no_wrap=c.numeric,
                overflow="fold",
            )
        for r in cells:
            t.add_row(*r)
        return t


def quantity_table(rows: Iterable[tuple[str, float | Value | None, str]], title: str = "") -> Table:
    """A table of mixed quantities, one a row: ``(quantity, value, unit)``, each value
    shown by the kind of its unit (:func:`unit_kind`; a :class:`Value` by its own); the
    units in their own column."""
    t = Table([Column("quantity", kind="text"), Column("value"), Column("unit", kind="text")],
              title=title)  # fmt: skip
    for label, v, unit in rows:
        t.add(label, v if isinstance(v, Value) else Value(v, unit_kind(unit)), unit)
    return t
