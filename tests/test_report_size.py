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
