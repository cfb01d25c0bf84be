"""Every figure of the design reports, screenshot in headless Chromium (issue 32).

The reports of the bundled drive examples are written into one folder, sharing
``plotly-VERSION.min.js`` beside them (:meth:`reducerlab.reporting.Report.write` with
``plotly=``), with a small loaded-contact result and a coarse gear-body modal result
handed to two of them so that their renders appear too. Then, for every figure block of
each report (a matplotlib PNG ``<figure>`` or an interactive plotly ``<figure
class="interactive">``), a standalone page holding just that block (the report's style,
the shared plotly.js by its relative name) is checked offline (no ``http(s)://``
script, stylesheet, image or frame source), opened in headless Chromium with every
network request sent to a dead proxy, its DOM dumped after the scripts ran (a plotly
figure must hold its ``main-svg`` and its drawn traces; no console error) and
screenshot; the screenshot must not be blank (a fraction of non-background pixels
above :data:`MIN_INK`). Each report is also opened whole (all its plotly figures
drawn, no console error) and must stay under :data:`MAX_REPORT` bytes.

Writes into the output folder: the reports, ``pages/REPORT/NN.html`` and ``.png``,
``REPORT-sheet.png`` (a contact sheet: each screenshot's thumbnail with its type and
caption) and ``index.md`` (figure type, caption, bytes in the report, ink, pass/fail);
prints a summary and exits 1 naming every blank or failed figure and every report over
the bound.

Run: ``make screenshots`` or
``MPLBACKEND=Agg .venv/bin/python benchmarks/screenshots.py -o screenshots-output``
(about 6 minutes on 2 cores; Chromium: ``apt-get install -y chromium``).
"""

from __future__ import annotations

import argparse
import base64
import datetime as dt
import html as htmllib
import io
import json
import os
import platform
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: the reports: example stem -> the small results handed to it, so that their figures
#: appear (rigid or coarse runs, seconds each; the KHV pair's sharing ~40 s)
EXAMPLES: dict[str, tuple[str, ...]] = {
    "gear_pair": ("te-sweep", "layout"),
    "khv": ("khv-sharing",),
    "khv_rattle": (),
    "cycloid_ball": (),
    "nutation_double_sided": ("body-modal",),
    "nutation_surface": ("contact",),
}
#: reports of a variant of an example, with only the sections it adds: name -> (the
#: example, the text that replaces its ``[report.bifurcation]`` table on, sections)
VARIANTS: dict[str, tuple[str, str, tuple[str, ...]]] = {
    "khv_rattle_regime_map": (
        "khv_rattle",
        '[report.regime_map]\nx = "gears.x1=0.5,0.65,0.8"\n'
        'y = "input_speed=1100 rpm,1300 rpm"\nperiods = 60\nkeep = 16\n',
        ("regime-map",),
    ),
}
#: issue 32: a drive's report (without the shared plotly.js) under 1.5 MB
MAX_REPORT = 1.5e6
#: a screenshot whose non-background pixels are fewer than this fraction is blank
MIN_INK = 0.005
#: how far (levels of 255, any channel) a pixel must differ from the background
INK_LEVEL = 24
WIDTH = 1200
#: plotly trace types drawn in WebGL (a canvas, no SVG trace group)
GL_TYPES = (
    "scattergl",
    "scatter3d",
    "surface",
    "mesh3d",
    "cone",
    "streamtube",
    "volume",
    "isosurface",
    "heatmapgl",
    "splom",
    "parcoords",
)


# ---------------------------------------------------------------- figure blocks


@dataclass
class FigureBlock:
    """One figure of a report: its section, kind, type, caption and HTML."""

    report: str
    index: int
    section: str
    interactive: bool
    html: str
    caption: str
    div_id: str = ""

    @property
    def type(self) -> str:
        """The figure's type: its ``data-figure`` name if the block has one, else the
        plotly div's id (without a trailing number) or the section and the caption's
        words before a colon or comma."""
        m = re.search(r'data-figure="([^"]+)"', self.html)
        if m:
            return m.group(1)
        if self.div_id:
            return re.sub(r"-\d+$", "", self.div_id.removeprefix("fig-"))
        cap = self.caption
        head, sep, rest = cap.partition(": ")
        if sep and re.search(r"\d", head):  # "mesh1: ...", "gear 2: ...": not the type
            cap = rest
        words = re.split(r"[:;,(]", cap)[0].strip().split()[:3]
        return f"{self.section}/" + "-".join(w.lower() for w in words or ["figure"])

    @property
    def bytes(self) -> int:
        return len(self.html.encode("utf-8"))

    def images(self) -> list[bytes]:
        """The PNGs embedded in the block (the static figure or the noscript fallback)."""
        return [
            base64.b64decode(m.group(1))
            for m in re.finditer(r'src="data:image/png;base64,([^"]+)"', self.html)
        ]

    def plotly_call(self) -> tuple[list[dict], dict]:
        """The traces and the layout of the block's ``Plotly.newPlot`` call."""
        m = re.search(r"Plotly\.newPlot\(\s*", self.html)
        if not m:
            return [], {}
        dec = json.JSONDecoder()
        i = m.end()
        out = []
        for _ in range(3):
            value, i = dec.raw_decode(self.html, i)
            out.append(value)
            while self.html[i] in ", \n\t":
                i += 1
        return out[1], out[2]


def figure_blocks(page: str, report: str = "") -> list[FigureBlock]:
    """The figure blocks of a report's HTML, in order, with their section ids."""
    sections = [(m.start(), m.group(1)) for m in re.finditer(r'<section id="([^"]+)"', page)]
    out = []
    for m in re.finditer(r"<figure(?:\s[^>]*)?>.*?</figure>", page, flags=re.S):
        block = m.group(0)
        sid = next((s for pos, s in reversed(sections) if pos < m.start()), "")
        cap = re.search(r"<figcaption>(.*?)</figcaption>", block, flags=re.S)
        div = re.search(r'<div id="(fig-[^"]+)"', block)
        out.append(
            FigureBlock(
                report=report,
                index=len(out) + 1,
                section=sid,
                interactive='class="interactive"' in block.split(">", 1)[0],
                html=block,
                caption=htmllib.unescape(cap.group(1)) if cap else "",
                div_id=div.group(1) if div else "",
            )
        )
    return out


_REMOTE = re.compile(
    r"<(?:script|img|iframe|embed|source|audio|video)\b[^>]*\bsrc\s*=\s*[\"']?\s*(?:https?:)?//"
    r"|<link\b[^>]*\bhref\s*=\s*[\"']?\s*(?:https?:)?//"
    r"|@import\s+(?:url\()?[\"']?\s*(?:https?:)?//"
    r"|url\(\s*[\"']?\s*(?:https?:)?//",
    flags=re.I,
)


def remote_resources(page: str) -> list[str]:
    """The network resources a page would load (script, stylesheet, image, frame or CSS
    ``url()`` with an ``http(s)://`` or protocol-relative address): empty when it opens
    offline. Links (``<a href>``) load nothing and are not counted."""
    return [page[m.start() : m.end() + 60] for m in _REMOTE.finditer(page)]


def local_scripts(page: str) -> list[str]:
    """The ``src`` of each external script of a page."""
    return re.findall(r"<script\b[^>]*\bsrc=\"([^\"]+)\"", page)


PROBE = """<script>
window.addEventListener("load", function () { setTimeout(function () {
  var b = document.body, imgs = document.images, bad = 0;
  for (var i = 0; i < imgs.length; i++)
    if (!imgs[i].complete || imgs[i].naturalWidth === 0) bad++;
  b.setAttribute("data-height", document.documentElement.scrollHeight);
  b.setAttribute("data-broken-images", bad);
  b.setAttribute("data-plotly", typeof Plotly === "undefined" ? "missing" : Plotly.version);
}, 1000); });
</script>"""


def standalone_page(block: FigureBlock, style: str, plotly_src: str | None) -> str:
    """A page holding just ``block``, styled as the report, loading plotly.js from
    ``plotly_src`` (a relative file name) when the block is interactive."""
    script = f'<script src="{plotly_src}"></script>' if block.interactive and plotly_src else ""
    title = htmllib.escape(f"{block.report} #{block.index}: {block.type}")
    return (
        f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>{title}</title>'
        f'{style}{script}</head><body><main><section id="{block.section}">'
        f"{block.html}</section></main>{PROBE}</body></html>\n"
    )


# ---------------------------------------------------------------- pixels


def ink(png: bytes | Path, level: int = INK_LEVEL) -> tuple[float, tuple[int, int, int, int]]:
    """The fraction of pixels that differ from the background (the commonest colour of
    the image's border) by more than ``level`` in any channel, and their bounding box
    (left, top, right, bottom; all zeros when there is none)."""
    import numpy as np
    from PIL import Image

    data = png.read_bytes() if isinstance(png, Path) else png
    with Image.open(io.BytesIO(data)) as im:
        a = np.asarray(im.convert("RGB"), dtype=np.int16)
    border = np.concatenate([a[0], a[-1], a[:, 0], a[:, -1]])
    colours, counts = np.unique(border, axis=0, return_counts=True)
    bg = colours[np.argmax(counts)]
    mask = (np.abs(a - bg) > level).any(axis=2)
    if not mask.any():
        return 0.0, (0, 0, 0, 0)
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    box = (int(cols[0]), int(rows[0]), int(cols[-1]) + 1, int(rows[-1]) + 1)
    return float(mask.mean()), box


def is_blank(png: bytes | Path, bound: float = MIN_INK) -> bool:
    """True when the image's ink (:func:`ink`) is below ``bound``."""
    return ink(png)[0] < bound


# ---------------------------------------------------------------- chromium


def chromium() -> str | None:
    """The Chromium executable on PATH, or None."""
    for name in ("chromium", "chromium-browser", "google-chrome", "headless_shell"):
        path = shutil.which(name)
        if path:
            return path
    return None


def run_chromium(args: Sequence[str], timeout: float) -> tuple[int, str, str]:
    """Run headless Chromium once (its own profile, every request to a dead proxy so
    nothing is fetched), killing its whole process group after ``timeout`` s."""
    exe = chromium()
    if exe is None:
        raise RuntimeError("chromium is not installed (apt-get install -y chromium)")
    with tempfile.TemporaryDirectory(prefix="rl-chromium-") as profile:
        cmd = [
            exe,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--no-first-run",
            "--disable-extensions",
            "--disable-dev-shm-usage",
            f"--user-data-dir={profile}",
            "--proxy-server=127.0.0.1:9",
            "--proxy-bypass-list=<-loopback>",
            "--enable-logging=stderr",
            "--v=0",
            *args,
        ]
        proc = subprocess.Popen(
            cmd,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            start_new_session=True,
            env={**os.environ, "LANG": "C.UTF-8"},
        )
        try:
            out, err = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            out, err = proc.communicate()
            return 124, out, err
        return proc.returncode, out, err


def console_errors(stderr: str) -> list[str]:
    """The page's console errors in Chromium's log (uncaught exceptions, failed loads)."""
    lines = [ln for ln in stderr.splitlines() if "CONSOLE" in ln]
    bad = ("error", "uncaught", "failed", "refused", "not defined")
    return [ln.split("] ", 1)[-1][:200] for ln in lines if any(b in ln.lower() for b in bad)]


def dump_dom(page: Path, timeout: float, width: int = WIDTH) -> tuple[str, list[str]]:
    """The page's DOM after its scripts ran (5 s of virtual time) and its console errors."""
    rc, out, err = run_chromium(
        [
            f"--window-size={width},900",
            "--virtual-time-budget=5000",
            "--dump-dom",
            page.resolve().as_uri(),
        ],
        timeout,
    )
    errors = console_errors(err)
    if rc != 0:
        errors.append(f"chromium --dump-dom exited {rc}")
    return out, errors


def screenshot(page: Path, png: Path, height: int, timeout: float, width: int = WIDTH) -> str:
    """Screenshot ``page`` into ``png`` (``width`` x ``height``); "" or what went wrong."""
    png.unlink(missing_ok=True)
    rc, _, _ = run_chromium(
        [
            f"--window-size={width},{height}",
            "--virtual-time-budget=5000",
            f"--screenshot={png.resolve()}",
            page.resolve().as_uri(),
        ],
        timeout,
    )
    if rc != 0 or not png.is_file():
        return f"chromium --screenshot exited {rc}" + ("" if png.is_file() else ", no image")
    return ""


def _attr(dom: str, name: str) -> str:
    m = re.search(rf'<body[^>]*\b{name}="([^"]*)"', dom)
    return m.group(1) if m else ""


def plotly_problems(block: FigureBlock, dom: str) -> list[str]:
    """What is missing from a plotly figure's DOM: its ``main-svg``, a drawn group per
    visible SVG trace type, a WebGL canvas for GL traces."""
    data, _ = block.plotly_call()
    visible = [t for t in data if t.get("visible", True) not in (False, "legendonly")]
    problems = []
    if not data:
        problems.append("no Plotly.newPlot call in the block")
    if 'class="main-svg"' not in dom:
        problems.append("no main-svg: plotly did not draw")
    gl = [t for t in visible if t.get("type", "scatter") in GL_TYPES]
    svg = [t for t in visible if t.get("type", "scatter") not in GL_TYPES]
    drawn = len(re.findall(r'class="trace[ "]', dom)) + dom.count('class="hm"')
    if svg and drawn == 0:
        problems.append(f"{len(svg)} visible SVG trace(s), none drawn")
    if gl and "<canvas" not in dom:
        problems.append(f"{len(gl)} WebGL trace(s), no canvas")
    return problems


# ---------------------------------------------------------------- the checks


@dataclass
class Checked:
    """A figure block and what its checks found."""

    block: FigureBlock
    page: Path
    png: Path | None = None
    ink: float = 0.0
    size: tuple[int, int] = (0, 0)
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.problems


def check_block(
    block: FigureBlock, folder: Path, style: str, plotly_file: str | None, timeout: float
) -> Checked:
    """Write ``block``'s standalone page in ``folder``, check that it is offline, dump
    its DOM, screenshot it (cropped to the page's content) and judge the screenshot."""
    folder.mkdir(parents=True, exist_ok=True)
    src = None
    if plotly_file:
        src = os.path.relpath(folder.parent.parent / plotly_file, folder).replace(os.sep, "/")
    text = standalone_page(block, style, src)
    page = folder / f"{block.index:02d}.html"
    page.write_text(text, encoding="utf-8")
    c = Checked(block, page)
    c.problems += [f"remote resource: {r}" for r in remote_resources(text)]
    for s in local_scripts(text):
        if not (folder / s).is_file():
            c.problems.append(f"script {s} not found beside the page")
    for k, png in enumerate(block.images()):
        what = "fallback PNG" if block.interactive else "embedded PNG"
        if is_blank(png):
            c.problems.append(f"{what} {k + 1} is blank")
    if block.interactive and not block.images():
        c.notes.append("no static fallback")
    dom, errors = dump_dom(page, timeout)
    c.problems += [f"console: {e}" for e in errors]
    if _attr(dom, "data-broken-images") not in ("", "0"):
        c.problems.append(f"{_attr(dom, 'data-broken-images')} image(s) did not load")
    if block.interactive:
        if _attr(dom, "data-plotly") in ("", "missing"):
            c.problems.append("plotly.js did not load")
        c.problems += plotly_problems(block, dom)
    height = int(_attr(dom, "data-height") or 900)
    height = min(max(height + 8, 200), 4000)
    shot = folder / f"{block.index:02d}.png"
    err = screenshot(page, shot, height, timeout)
    if err:
        c.problems.append(err)
        return c
    c.png = shot
    _, box = ink(shot)
    if box[2] > box[0]:
        from PIL import Image

        with Image.open(shot) as im:  # crop to the figure and its caption
            pad = 6
            im.crop(
                (
                    max(box[0] - pad, 0),
                    max(box[1] - pad, 0),
                    min(box[2] + pad, im.width),
                    min(box[3] + pad, im.height),
                )
            ).save(shot)
    c.ink, _ = ink(shot)
    from PIL import Image

    with Image.open(shot) as im:
        c.size = im.size
    if c.ink < MIN_INK:
        c.problems.append(f"blank screenshot (ink {c.ink:.4f} < {MIN_INK})")
    return c


def check_report(path: Path, plotly_file: str, timeout: float) -> list[str]:
    """A whole report: under the size bound, offline, every plotly figure drawn and no
    console error when it opens."""
    page = path.read_text(encoding="utf-8")
    problems = []
    size = path.stat().st_size
    if size > MAX_REPORT:
        problems.append(f"{size} bytes, over the {MAX_REPORT:.0f} byte bound")
    problems += [f"remote resource: {r}" for r in remote_resources(page)]
    for s in local_scripts(page):
        if not (path.parent / s).is_file():
            problems.append(f"script {s} not found beside the report")
    if "Plotly.newPlot" in page and plotly_file not in local_scripts(page):
        problems.append(f"plotly figures without the shared {plotly_file}")
    dom, errors = dump_dom(path, timeout)
    problems += [f"console: {e}" for e in errors]
    want = page.count("Plotly.newPlot(")
    # each plot has one main-svg, plus one for the modebar/info layer
    got = dom.count('<div class="plot-container plotly"')
    if got < want:
        problems.append(f"{got} of {want} plotly figures drawn when the report opens")
    return problems


# ---------------------------------------------------------------- outputs


def _font(size: int):  # type: ignore[no-untyped-def]
    from PIL import ImageFont

    for name in ("DejaVuSans.ttf", "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"):
        try:
            return ImageFont.truetype(name, size)
        except OSError:
            continue
    return ImageFont.load_default(size=size)


def contact_sheet(
    title: str, checked: Sequence[Checked], out: Path, *, thumb: int = 380, columns: int = 3
) -> Path:
    """A montage of the screenshots' thumbnails, each with its number, type, caption
    and pass/fail, under ``title``."""
    import textwrap

    from PIL import Image, ImageDraw

    small, big = _font(13), _font(20)
    cells = []
    for c in checked:
        if c.png is not None and c.png.is_file():
            with Image.open(c.png) as im:
                im = im.convert("RGB")
                im.thumbnail((thumb, int(thumb * 1.6)))
                img = im.copy()
        else:
            img = Image.new("RGB", (thumb, thumb // 2), (250, 225, 225))
        status = "ok" if c.ok else "FAIL: " + "; ".join(c.problems)
        text = f"#{c.block.index} {c.block.type} [{status}]\n{c.block.caption}"
        lines = [ln for para in text.splitlines() for ln in textwrap.wrap(para, 52) or [""]]
        cells.append((img, lines[:5], c.ok))
    rows = [cells[i : i + columns] for i in range(0, len(cells), columns)]
    heights = [max(img.height for img, _, _ in r) + 16 * 5 + 20 for r in rows]
    sheet = Image.new("RGB", (columns * (thumb + 20) + 20, 50 + sum(heights)), "white")
    draw = ImageDraw.Draw(sheet)
    draw.text((20, 14), title, fill=(20, 30, 50), font=big)
    y = 50
    for r, h in zip(rows, heights, strict=True):
        for k, (img, lines, ok) in enumerate(r):
            x = 20 + k * (thumb + 20)
            sheet.paste(img, (x, y))
            draw.rectangle(
                (x - 1, y - 1, x + img.width, y + img.height),
                outline=(200, 205, 215) if ok else (200, 30, 30),
                width=1 if ok else 3,
            )
            for j, ln in enumerate(lines):
                colour = (20, 30, 50) if ok or j else (180, 20, 20)
                draw.text((x, y + img.height + 4 + 16 * j), ln, fill=colour, font=small)
        y += h
    sheet.save(out)
    return out


def write_index(
    out: Path, reports: dict[str, dict], checked: Sequence[Checked], shared: str = ""
) -> Path:
    """``index.md``: each report (size, checks) and each figure (type, caption, bytes in
    the report, ink, screenshot, pass/fail)."""
    lines = [
        "# Report figures in headless Chromium",
        "",
        f"{dt.datetime.now(dt.UTC):%Y-%m-%d %H:%M} UTC, {_machine()}",
        "",
        *([f"Shared by the reports: {shared}", ""] if shared else []),
        "| report | bytes | figures | failed | problems |",
        "|---|---:|---:|---:|---|",
    ]
    for name, r in reports.items():
        mine = [c for c in checked if c.block.report == name]
        lines.append(
            f"| [{name}]({name}.html) ([sheet]({name}-sheet.png)) | {r['bytes']} | {len(mine)} "
            f"| {sum(not c.ok for c in mine)} | {'; '.join(r['problems']) or 'ok'} |"
        )
    lines += [
        "",
        "| report | # | section | type | caption | kind | bytes | ink | screenshot | result |",
        "|---|---:|---|---|---|---|---:|---:|---|---|",
    ]
    for c in checked:
        b = c.block
        shot = f"[png]({c.png.relative_to(out)})" if c.png else "—"
        res = "pass" if c.ok else "**FAIL**: " + "; ".join(c.problems).replace("|", "/")
        if c.notes:
            res += " (" + "; ".join(c.notes) + ")"
        cap = b.caption.replace("|", "/")
        kind = "plotly" if b.interactive else "png"
        lines.append(
            f"| {b.report} | {b.index} | {b.section} | {b.type} | {cap} | {kind} | {b.bytes} "
            f"| {c.ink:.3f} | {shot} | {res} |"
        )
    path = out / "index.md"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _machine() -> str:
    exe = chromium()
    ver = ""
    if exe:
        try:
            ver = subprocess.run(
                [exe, "--version"], capture_output=True, text=True, timeout=30
            ).stdout.strip()
        except (OSError, subprocess.TimeoutExpired):
            ver = exe
    return (
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, {ver}"
    )


# ---------------------------------------------------------------- reports


def given_results(stem: str, kinds: Sequence[str]) -> list:
    """Small results for the report of ``stem`` so that their figures appear: a rigid
    loaded contact of pair 1 (5 positions), the coarse FE modes of gear body 2, a
    rigid-teeth TE sweep (3 loads) and modification layout (2 x 2), the KHV pair's load
    sharing on coarse FE tooth compliances (4 torques, 6 positions)."""
    import reducerlab as rl
    from reducerlab.examples import example_dir

    design = rl.load_design(example_dir() / f"{stem}.toml")
    out = []
    if "contact" in kinds:
        from reducerlab.analysis.contact import contact_analysis

        out.append(contact_analysis(design, 1, torque=19.1, positions=5, order=2, rigid=True))
    if "body-modal" in kinds:
        from reducerlab.analysis.body_modal import body_modal
        from reducerlab.fe.gear_mesh import MeshSizes

        m_n = design.tooth_generation(2)[0].profile.module
        out.append(
            body_modal(design, 2, count=4, sizes=MeshSizes(0.8 * m_n, 2.5 * m_n), convergence=False)
        )
    if "te-sweep" in kinds:
        from reducerlab.analysis.te_sweep import te_sweep

        out.append(te_sweep(design, loads=3, positions=7, cell=1e-4, compliance=(None, None)))
    if "layout" in kinds:
        from reducerlab.analysis.layout import modification_layout

        out.append(
            modification_layout(
                design, grid=2, refine=0, positions=3, cell=1e-4, compliance=(None, None)
            )
        )
    if "khv-sharing" in kinds:
        from reducerlab.analysis.contact_setup import pair_setup
        from reducerlab.analysis.khv_sharing import load_sharing

        setup = pair_setup(design)
        mp = setup.mesh_pair
        coarse = mp.tooth_compliances(
            material=setup.material, grid=(4, 6), tooth_size=0.35 * mp.planet.module
        )
        out.append(
            load_sharing(
                design, torques=[0.0, 5.0, 50.0, 75.0], positions=6, cell=0.25e-3, compliance=coarse
            )
        )
    return out


def write_reports(
    out: Path,
    examples: dict[str, Sequence[str]],
    *,
    results: bool = True,
    variants: Sequence[str] = (),
    log=print,
) -> dict[str, Path]:
    """Write the report of each example (with its given results) and of each variant of
    :data:`VARIANTS` into ``out``, sharing plotly.js."""
    from reducerlab.examples import example_dir
    from reducerlab.reporting import PLOTLY_FILE, report

    out.mkdir(parents=True, exist_ok=True)
    todo: list[tuple[str, Path, Sequence[str], Sequence[str] | None]] = [
        (stem, example_dir() / f"{stem}.toml", kinds if results else (), None)
        for stem, kinds in examples.items()
    ]
    for name in variants:
        stem, table, only = VARIANTS[name]
        text = (example_dir() / f"{stem}.toml").read_text(encoding="utf-8")
        design = out / "designs" / f"{name}.toml"
        design.parent.mkdir(exist_ok=True)
        design.write_text(text.split("[report.bifurcation]")[0] + table, encoding="utf-8")
        todo.append((name, design, (), only))
    paths = {}
    for name, design, kinds, only in todo:
        t0 = time.perf_counter()
        given = given_results(name, kinds) if kinds else []
        r = report(design, results=given, only=only)
        paths[name] = r.write(out / f"{name}.html", plotly=out / PLOTLY_FILE)
        failed = ", ".join(s.id for s in r.failed)
        log(
            f"report {name}: {time.perf_counter() - t0:.1f} s, "
            f"{paths[name].stat().st_size} bytes"
            + (f", FAILED sections: {failed}" if failed else "")
        )
    return paths


def check_reports(
    out: Path, paths: dict[str, Path], *, timeout: float = 60.0, log=print
) -> tuple[dict[str, dict], list[Checked]]:
    """Check every report of ``paths`` (in ``out``) and each of its figures."""
    from reducerlab.reporting import PLOTLY_FILE

    reports: dict[str, dict] = {}
    checked: list[Checked] = []
    for name, path in paths.items():
        page = path.read_text(encoding="utf-8")
        style = "".join(re.findall(r"<style>.*?</style>", page, flags=re.S)[:1])
        blocks = figure_blocks(page, name)
        mine = []
        for b in blocks:
            c = check_block(b, out / "pages" / name, style, PLOTLY_FILE, timeout)
            mine.append(c)
            log(
                f"  {name} #{b.index:02d} {b.type:<34} {'ok' if c.ok else 'FAIL'} "
                f"ink {c.ink:.3f} {'; '.join(c.problems)}"
            )
        problems = check_report(path, PLOTLY_FILE, timeout)
        reports[name] = {
            "bytes": path.stat().st_size,
            "problems": problems,
            "failed_sections": page.count('data-status="error"'),
        }
        if reports[name]["failed_sections"]:
            problems.append(f"{reports[name]['failed_sections']} failed section(s)")
        contact_sheet(
            f"{name}: {len(blocks)} figures, {path.stat().st_size / 1e6:.2f} MB",
            mine,
            out / f"{name}-sheet.png",
        )
        checked += mine
    js = out / PLOTLY_FILE
    shared = f"`{PLOTLY_FILE}`, {js.stat().st_size} bytes" if js.is_file() else ""
    write_index(out, reports, checked, shared)
    return reports, checked


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-o", "--output", type=Path, default=ROOT / "screenshots-output")
    ap.add_argument(
        "--examples",
        default=",".join([*EXAMPLES, *VARIANTS]),
        help="comma-separated example stems (default: %(default)s)",
    )
    ap.add_argument(
        "--no-results",
        action="store_true",
        help="no contact, body-modal, TE sweep, layout or sharing result handed to the reports",
    )
    ap.add_argument("--timeout", type=float, default=90.0, help="seconds per chromium call")
    args = ap.parse_args(argv)
    sys.stdout.reconfigure(line_buffering=True)  # type: ignore[union-attr]
    if chromium() is None:
        print(
            "screenshots: chromium not found; install it (Debian: apt-get install -y "
            "chromium) and run again",
            file=sys.stderr,
        )
        return 2
    names = [s for s in args.examples.split(",") if s]
    examples = {s: EXAMPLES.get(s, ()) for s in names if s not in VARIANTS}
    variants = [s for s in names if s in VARIANTS]
    out: Path = args.output
    if out.exists():
        shutil.rmtree(out / "pages", ignore_errors=True)
    t0 = time.perf_counter()
    print(f"date: {dt.datetime.now(dt.UTC):%Y-%m-%d %H:%M} UTC; machine: {_machine()}")
    paths = write_reports(out, examples, results=not args.no_results, variants=variants)
    t1 = time.perf_counter()
    from reducerlab.reporting import PLOTLY_FILE

    reports, checked = check_reports(out, paths, timeout=args.timeout)
    t2 = time.perf_counter()
    kinds = Counter(c.block.type for c in checked)
    print(
        f"\n{len(checked)} figures ({len(kinds)} types) in {len(reports)} reports; "
        f"reports {t1 - t0:.0f} s, chromium checks {t2 - t1:.0f} s"
    )
    print(f"{'report':<24} {'bytes':>9} {'figures':>8} {'failed':>7}  problems")
    for name, r in reports.items():
        mine = [c for c in checked if c.block.report == name]
        print(
            f"{name:<24} {r['bytes']:>9} {len(mine):>8} {sum(not c.ok for c in mine):>7}  "
            f"{'; '.join(r['problems']) or 'ok'}"
        )
    bad = [c for c in checked if not c.ok]
    for c in bad:
        print(
            f"FAILED {c.block.report} #{c.block.index} {c.block.type} ({c.block.caption}): "
            f"{'; '.join(c.problems)}"
        )
    over = {n: r for n, r in reports.items() if r["problems"]}
    for n, r in over.items():
        print(f"FAILED report {n}: {'; '.join(r['problems'])}")
    js = out / PLOTLY_FILE
    if js.is_file():
        print(f"shared by the reports: {PLOTLY_FILE}, {js.stat().st_size} bytes")
    print(f"index: {out / 'index.md'}")
    return 1 if bad or over else 0


if __name__ == "__main__":
    sys.exit(main())
