"""One number-formatting rule for every table (issue 32): :mod:`reducerlab.numformat`.

The rule per kind on closed examples, its properties for any number (hypothesis), and
the same result (the modes of ``examples/khv.toml``) shown by the command line, its
text file and the report with the same strings and units in the headers.
"""

from __future__ import annotations

import math
import re
from html.parser import HTMLParser

import pytest
from hypothesis import given
from hypothesis import strategies as st
from typer.testing import CliRunner

from reducerlab.cli import app
from reducerlab.examples import example_dir
from reducerlab.numformat import (
    DASH,
    FIXED_HIGH,
    FIXED_LOW,
    KINDS,
    Column,
    Table,
    Value,
    fmt,
    quantity_table,
    unit_kind,
)
from reducerlab.reporting.blocks import table as html_table

KHV = example_dir() / "khv.toml"


@pytest.mark.parametrize(
    ("value", "kind", "text"),
    [
        # the numbers, side by side before: 1495, 1382.35, 2238.966, 0.132669 %,
        # 2.48265e-05 %, -0.0000
        (1495, "speed", "1495"),
        (1382.35, "frequency", "1382"),
        (2238.966, "frequency", "2239"),
        (0.132669, "percent", "0.13"),
        (2.48265e-05, "percent", "0"),  # below the 0.01 % resolution: 0, not 2.48e-5
        (-0.00001, "percent", "0"),  # never -0
        (-0.0, "value", "0"),
        (-1e-20, "share", "0"),
        # significant digits, trailing zeros dropped, integers of more digits rounded
        (142.07, "frequency", "142.1"),
        (454.006, "frequency", "454"),
        (12345.6, "frequency", "12350"),
        (-10.0, "ratio", "-10"),
        (81.333333333, "ratio", "81.3333"),
        (0.005065, "value", "0.005065"),
        (11.93, "safety", "11.9"),
        (99.323, "percent", "99.3"),
        (0.00041, "share", "0.0004"),  # a kind with decimals stays fixed
        # scientific outside [1e-3, 1e6), the same significant digits
        (2.48265e-05, "value", "2.483e-5"),
        (2.1e11, "stiffness", "2.1e11"),
        (999999.6, "value", "1e6"),  # rounds up into the next power
        (0.00099996, "value", "0.001"),
        # missing values, counts, booleans, text
        (math.nan, "frequency", DASH),
        (None, "torque", DASH),
        (math.inf, "value", "inf"),
        (-math.inf, "value", "-inf"),
        (3.0, "count", "3"),
        (7, "count", "7"),
        (True, "value", "yes"),
        ("gear 2", "value", "gear 2"),
    ],
)
def test_the_rule_on_closed_examples(value, kind, text):
    assert fmt(value, kind) == text


def test_unknown_kinds_are_refused():
    with pytest.raises(KeyError):
        fmt(1.0, "frequencies")
    with pytest.raises(KeyError):
        Column("f", "Hz", "herz")


finite = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300, max_value=1e300)
real_kinds = sorted(k for k, v in KINDS.items() if not v.integer)


@given(finite, st.sampled_from(real_kinds))
def test_parsed_back_within_the_stated_precision(x, kind):
    k = KINDS[kind]
    text = fmt(x, kind)
    back = float(text)
    # rounding to d significant digits moves a number by at most half a unit of its
    # last digit: |back - x| <= 0.5 * 10**(1 - d) * |x| (1e-12 relative: the float
    # arithmetic of the rounding itself); a kind with ``decimals`` also rounds to that
    # absolute resolution, 0.5 * 10**-decimals
    bound = 0.5 * 10.0 ** (1 - k.digits) * abs(x) * (1 + 1e-12)
    if k.decimals is not None:
        bound += 0.5 * 10.0**-k.decimals * (1 + 1e-12)
    assert abs(back - x) <= bound, (x, kind, text)


@given(finite, st.sampled_from(sorted(KINDS)))
def test_never_minus_zero_and_width_bounded(x, kind):
    text = fmt(x, kind)
    assert not re.fullmatch(r"-0(\.0*)?(e.*)?", text)
    if float(text) == 0:
        assert text == "0"
    if not KINDS[kind].integer:
        # sign, "0.00" before the digits of a small fixed number, or "e-308"
        assert len(text) <= KINDS[kind].digits + 7, text
    a = abs(float(text))
    if a and not KINDS[kind].integer and KINDS[kind].decimals is None:
        assert ("e" in text) == (not FIXED_LOW <= a < FIXED_HIGH), text


@given(st.integers(min_value=-(10**12), max_value=10**12))
def test_counts_are_integers(n):
    assert fmt(n, "count") == str(n)
    assert fmt(float(n), "count") == str(n)


def test_units_go_to_the_headers_and_numbers_align_right():
    t = Table(
        [Column("mode", kind="count"), Column("frequency", "Hz", "frequency"),
         Column("whirl", kind="text")],
        [(1, 0.0, "rigid"), (2, 142.07, "forward"), (10, 2238.966, "none")],
    )  # fmt: skip
    assert t.headers == ["mode", "frequency (Hz)", "whirl"]
    lines = t.text().splitlines()
    assert lines[0] == "mode  frequency (Hz)  whirl"
    assert lines[1:] == [
        "   1               0  rigid",
        "   2           142.1  forward",
        "  10            2239  none",
    ]
    for cells in t.cells():
        assert not any(u in c for c in cells for u in ("Hz", "rpm"))


def test_a_table_of_mixed_quantities_shows_each_by_its_unit():
    t = quantity_table([("efficiency", 99.323, "%"), ("speed", 1382.35, "rpm"),
                        ("ratio", Value(81.333333, "ratio"), "")])  # fmt: skip
    assert [r[1] for r in t.cells()] == ["99.3", "1382", "81.3333"]
    assert unit_kind("N m/arcmin") == "stiffness" and unit_kind("furlong") == "value"


class _Cells(HTMLParser):
    """Header and cell texts of the first ``<table>``."""

    def __init__(self) -> None:
        super().__init__()
        self.heads: list[str] = []
        self.rows: list[list[str]] = []
        self._in: str | None = None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        if tag in ("td", "th"):
            self._in = tag

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self._in = None

    def handle_data(self, data):
        if self._in == "th":
            self.heads.append(data)
        elif self._in == "td":
            self.rows[-1].append(data)


def _rich_rows(output: str) -> tuple[list[str], list[list[str]]]:
    """Header and body cells of a rich table printed with box characters."""
    heads, rows = [], []
    for line in output.splitlines():
        if line.startswith("┃"):
            heads = [c.strip() for c in line.strip("┃").split("┃")]
        elif line.startswith("│"):
            rows.append([c.strip() for c in line.strip("│").split("│")])
    return heads, rows


def test_the_modes_read_the_same_in_the_cli_the_text_file_and_the_report(tmp_path):
    from reducerlab.analysis.modal import modal
    from reducerlab.drives import build_model, load_design
    from reducerlab.reporting import report

    res = modal(build_model(load_design(KHV)))
    want = res.table_data().cells()
    assert len(want) >= 4 and any("." in r[1] for r in want)
    # the command line's table (rich) and its text file
    run = CliRunner().invoke(app, ["modal", str(KHV), "-o", str(tmp_path / "out")])
    assert run.exit_code == 0, run.output
    heads, rows = _rich_rows(run.stdout)
    assert heads == ["mode", "frequency (Hz)", "classification"]
    assert rows == want
    text = (tmp_path / "out" / "modal.txt").read_text().splitlines()
    assert text[0].split() == ["mode", "frequency", "(Hz)", "classification"]
    assert [line.split(maxsplit=2) for line in text[1:]] == want
    # the report's table of the modes
    rep = report(KHV, only=["modal"])
    block = next(b for b in rep.section("modal").blocks if 'data-table="modes"' in b.html)
    page = _Cells()
    page.feed(block.html)
    assert page.heads == heads
    assert [r for r in page.rows if r] == want
    # any table given as a Table renders the same cells in HTML
    again = _Cells()
    again.feed(html_table(res.table_data()).html)
    assert [r for r in again.rows if r] == want


def test_the_complex_campbell_table_is_aligned():
    run = CliRunner().invoke(app, ["campbell", str(KHV), "--complex"])
    assert run.exit_code == 0, run.output
    lines = run.stdout.splitlines()
    head = next(i for i, line in enumerate(lines) if "speed (rpm)" in line)
    body = [line for line in lines[head + 1 :] if line.startswith("  ") and line.strip()]
    assert len(body) >= 3
    # every numeric column right-aligned under its header: rows end where it ends
    for name in ("speed (rpm)", "frequency (Hz)"):
        end = lines[head].index(name) + len(name)
        for line in body:
            assert line[end - 1] != " " and (len(line) == end or line[end] == " "), line
    assert "frequency (Hz)" in lines[head] and "mode" in lines[head]


def test_a_plain_report_header_gives_its_numbers_the_kind_of_its_unit():
    # sections that pass plain headers ("speed (rpm)") get the rule of the unit
    page = _Cells()
    page.feed(html_table(["mode", "speed (rpm)", "margin (%)", "k"],
                         [(3, 1382.35, 0.132669, 2.48265e-05)]).html)  # fmt: skip
    assert [r for r in page.rows if r] == [["3", "1382", "0.13", "2.483e-5"]]
