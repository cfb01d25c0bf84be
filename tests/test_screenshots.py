"""Report figures screenshot in headless Chromium (issue 32, ``benchmarks/screenshots.py``).

The blank detector, the figure-block parser and the offline check run everywhere; the
screenshots of one small report (the KHV drive, the fastest example with both kinds of
figure: 5 s for the report) run where Chromium is installed."""

from __future__ import annotations

import importlib.util
import io
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _script():
    spec = importlib.util.spec_from_file_location("screenshots", ROOT / "benchmarks/screenshots.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("screenshots", module)
    spec.loader.exec_module(module)
    return module


shots = _script()


def _png(draw: bool) -> bytes:
    import matplotlib

    matplotlib.use("Agg")
    import numpy as np
    from matplotlib.figure import Figure

    fig = Figure(figsize=(4, 3))
    if draw:
        ax = fig.subplots()
        x = np.linspace(0, 6, 200)
        ax.plot(x, np.sin(x), lw=2)
        ax.set_title("a drawn figure")
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=80)
    return buf.getvalue()


def test_a_blank_image_is_blank_and_a_drawn_one_is_not():
    from PIL import Image

    white = io.BytesIO()
    Image.new("RGB", (400, 300), "white").save(white, format="PNG")
    assert shots.is_blank(white.getvalue())
    assert shots.ink(white.getvalue()) == (0.0, (0, 0, 0, 0))
    assert shots.is_blank(_png(draw=False))  # an empty matplotlib canvas
    frac, box = shots.ink(_png(draw=True))
    assert not shots.is_blank(_png(draw=True)) and frac > 5 * shots.MIN_INK
    assert box[2] > box[0] and box[3] > box[1]
    # a grey page with one dot is still blank: the background is the border's colour
    grey = Image.new("RGB", (400, 300), (240, 242, 245))
    grey.putpixel((200, 150), (0, 0, 0))
    buf = io.BytesIO()
    grey.save(buf, format="PNG")
    assert shots.is_blank(buf.getvalue())


def test_figure_blocks_and_the_offline_check():
    page = (
        '<html><head><script src="plotly-1.0.min.js"></script></head><body>'
        '<section id="modal"><figure class="interactive"><div id="fig-mode-shapes"></div>'
        '<script>Plotly.newPlot("fig-mode-shapes", [{"type": "bar", "y": [1]}], '
        '{"height": 300}, {})</script><figcaption>mode shapes: choose</figcaption></figure>'
        "</section>"
        '<section id="capacity"><figure><img src="data:image/png;base64,AAAA">'
        "<figcaption>safety factors against their minimums</figcaption></figure></section>"
        '<a href="https://doi.org/10.1000/x">a paper</a></body></html>'
    )
    blocks = shots.figure_blocks(page, "r")
    assert [(b.section, b.interactive, b.type) for b in blocks] == [
        ("modal", True, "mode-shapes"),
        ("capacity", False, "capacity/safety-factors-against"),
    ]
    data, layout = blocks[0].plotly_call()
    assert data == [{"type": "bar", "y": [1]}] and layout == {"height": 300}
    assert shots.remote_resources(page) == []  # a link loads nothing
    assert shots.local_scripts(page) == ["plotly-1.0.min.js"]
    for bad in (
        '<script src="https://cdn.plot.ly/plotly.min.js"></script>',
        "<script src='//cdn.example.org/x.js'></script>",
        '<link rel="stylesheet" href="http://example.org/a.css">',
        '<img alt="" src="https://example.org/a.png">',
        "<style>@import url(https://fonts.example.org/css);</style>",
    ):
        assert shots.remote_resources(page + bad), bad


def test_contact_sheet_of_checked_figures(tmp_path):
    from PIL import Image

    png = tmp_path / "01.png"
    png.write_bytes(_png(draw=True))
    block = shots.FigureBlock("r", 1, "modal", False, "<figure></figure>", "a caption")
    ok = shots.Checked(block, tmp_path / "01.html", png=png, ink=0.1)
    bad = shots.Checked(block, tmp_path / "02.html", problems=["blank screenshot"])
    out = shots.contact_sheet("r: 2 figures", [ok, bad], tmp_path / "sheet.png")
    with Image.open(out) as im:
        assert im.width > 2 * 380 and im.height > 200
    index = shots.write_index(tmp_path, {"r": {"bytes": 10, "problems": []}}, [ok, bad])
    text = index.read_text()
    assert "| r | 1 | modal |" in text and "**FAIL**: blank screenshot" in text


@pytest.mark.skipif(
    shots.chromium() is None,
    reason="chromium is not installed "
    "(apt-get install -y chromium; `make screenshots` installs it as root)",
)
def test_report_figures_render_offline_and_are_not_blank(tmp_path):
    """The KHV report's modal, Campbell and closed-graph sections (plotly and matplotlib
    figures) with plotly.js shared beside it: every figure's standalone page is offline,
    drawn, not blank; the report itself opens with every plotly figure. Without the
    shared plotly.js, a plotly figure fails its check."""
    from reducerlab.examples import example_dir
    from reducerlab.reporting import PLOTLY_FILE, report

    r = report(example_dir() / "khv.toml", only=["modal", "campbell", "closed-graph"])
    path = r.write(tmp_path / "khv.html", plotly=tmp_path / PLOTLY_FILE)
    reports, checked = shots.check_reports(tmp_path, {"khv": path}, timeout=60, log=lambda s: None)
    assert reports["khv"]["problems"] == [], reports
    kinds = {c.block.interactive for c in checked}
    assert kinds == {True, False}, "both plotly and static figures"
    assert len(checked) >= 4
    for c in checked:
        assert c.ok, (c.block.type, c.problems)
        assert c.ink > shots.MIN_INK and c.png is not None and c.png.is_file()
        assert shots.remote_resources(c.page.read_text()) == []
    assert (tmp_path / "khv-sheet.png").is_file() and (tmp_path / "index.md").is_file()
    # the same plotly figure without its script: not drawn, and said so
    (tmp_path / PLOTLY_FILE).unlink()
    plot = next(c.block for c in checked if c.block.interactive)
    style = "<style>body { background: #fff; }</style>"
    bad = shots.check_block(plot, tmp_path / "pages" / "bare", style, PLOTLY_FILE, 60)
    assert not bad.ok
    assert any("not found" in p for p in bad.problems)
    assert any("main-svg" in p for p in bad.problems)
