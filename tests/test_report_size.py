"""Reports of one folder share plotly.js (issue 32: a drive's report under 1.5 MB that
still opens offline): ``Report.write(path, plotly=FOLDER/PLOTLY_FILE)`` writes the
script once beside the reports and each report loads it by its name."""

from __future__ import annotations

from reducerlab.examples import example_dir
from reducerlab.reporting import PLOTLY_FILE, report

LIMIT = 1.5e6  # bytes: the bound on a drive's report


def test_a_drive_report_shares_plotly_and_stays_small(tmp_path):
    from plotly.offline import get_plotlyjs

    r = report(example_dir() / "gear_pair.toml", only=["modal"])
    assert r.plotly_js  # the modal section has interactive figures
    inline = r.write(tmp_path / "inline.html")  # the default: one self-contained file
    assert inline.stat().st_size > len(r.plotly_js)
    assert not (tmp_path / PLOTLY_FILE).exists()
    page = r.write(tmp_path / "gear_pair.html", plotly=tmp_path / PLOTLY_FILE)
    js = tmp_path / PLOTLY_FILE
    assert js.read_text(encoding="utf-8") == get_plotlyjs()
    html = page.read_text(encoding="utf-8")
    assert f'<script src="{PLOTLY_FILE}"></script>' in html  # a relative, local file
    assert "Plotly.newPlot" in html and r.plotly_js not in html
    assert page.stat().st_size < LIMIT
    first = js.stat().st_mtime_ns
    other = report(example_dir() / "khv.toml", only=["modal"])
    other.write(tmp_path / "khv.html", plotly=js)  # the same script: not rewritten
    assert js.stat().st_mtime_ns == first
    assert (tmp_path / "khv.html").stat().st_size < LIMIT


def test_a_report_without_interactive_figures_writes_no_script(tmp_path):
    r = report(example_dir() / "gear_pair.toml", only=["datasheet"])
    if r.plotly_js:  # the datasheet is drawn with matplotlib: no plotly
        raise AssertionError("the datasheet section should need no plotly.js")
    r.write(tmp_path / "sheet.html", plotly=tmp_path / PLOTLY_FILE)
    assert not (tmp_path / PLOTLY_FILE).exists()


def test_report_figures_are_palette_pngs_that_look_the_same():
    """``png_data`` stores a figure as a 256-colour palette PNG: a third of the RGBA
    bytes here, the pixels on average within a level of the full-colour rendering and
    99 % within 16 of 255 (a line plot and a colour map: median cut keeps the colours a
    figure uses)."""
    import base64
    import io

    import matplotlib

    matplotlib.use("Agg")
    import numpy as np
    from matplotlib.figure import Figure
    from PIL import Image

    from reducerlab.reporting.blocks import png_data

    fig = Figure(figsize=(6, 3))
    a, b = fig.subplots(1, 2)
    x = np.linspace(0, 10, 400)
    for k in range(5):
        a.plot(x, np.sin(x + k), label=f"mode {k}")
    a.legend()
    b.imshow(np.outer(np.linspace(0, 1, 64), np.linspace(0, 1, 64)), cmap="viridis")
    raw = io.BytesIO()
    fig.savefig(raw, format="png", dpi=110)
    uri = png_data(fig, 110)
    data = base64.b64decode(uri.split(",", 1)[1])
    pal = Image.open(io.BytesIO(data))
    full = Image.open(io.BytesIO(raw.getvalue())).convert("RGB")
    assert pal.mode == "P" and pal.size == full.size
    assert len(data) < 0.6 * len(raw.getvalue())
    diff = np.abs(np.asarray(pal.convert("RGB"), int) - np.asarray(full, int))
    # levels of 255: 0.38 on average; 11 at the 99th percentile, the antialiased edges
    # of lines and text, where the palette has no exact blend (invisible at 110 dpi)
    assert diff.mean() < 1.0 and np.percentile(diff, 99) <= 16


def test_a_cyclic_pair_of_body_modes_is_rendered_once_and_named_a_pair():
    """Gear bodies are cyclically symmetric: their n >= 1 modes come in pairs at one
    frequency, the second the first turned by a quarter wave. The report's 3-D render
    draws each pair once, labelled as a pair (its table lists both), so a run report
    with four gear bodies stays under the bound."""
    from reducerlab.reporting.sections.modes import distinct_modes

    family = [0, 0, 1, 1, 2, 3]  # the body result's repeated pairs (fe.modetypes)
    labels = ["bending (n = 2)", "bending (n = 2)", "b3", "b3", "umbrella (n = 0)", "b4"]
    keep, shown = distinct_modes(family, labels)
    assert keep == [0, 2, 4, 5]
    assert shown == ["bending (n = 2) (pair)", "b3 (pair)", "umbrella (n = 0)", "b4"]
    # two modes of two families (however close in frequency) are two modes, not a pair
    keep, shown = distinct_modes([0, 1], ["a", "b"])
    assert keep == [0, 1] and shown == ["a", "b"]
