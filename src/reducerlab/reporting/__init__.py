"""One design, one report (issue 18): a self-contained HTML file that assembles every
analysis the design supports, built from a jinja2 template.

>>> import reducerlab as rl
>>> r = rl.report("examples/gear_pair.toml")        # doctest: +SKIP
>>> r.write("gear_pair.html")                       # doctest: +SKIP

Sections appear when the design supports them (:data:`.sections.SECTIONS`); a section
that fails shows its error in place and the others still render. Interactive figures
(mode shapes, Campbell diagram) are plotly with plotly.js embedded once, each with a
static PNG for pages without scripts; the rest are matplotlib PNGs. Nothing is fetched
when the page opens.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import os
import platform
import time
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol
from urllib.parse import quote

from .. import __version__
from ..design import Design
from ..errors import ReducerlabError
from ..numformat import Column
from .blocks import Section, table
from .context import Context, repo_assumptions
from .sections import SECTIONS

__all__ = ["PLOTLY_FILE", "Report", "SectionMemo", "report", "write_index"]

TEMPLATES = Path(__file__).with_name("templates")


def _environment() -> Any:
    import jinja2

    return jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(TEMPLATES)),
        autoescape=jinja2.select_autoescape(["html", "j2"]),
        undefined=jinja2.StrictUndefined,
    )


class SectionMemo(Protocol):
    """Sections built before, by section id, for a report of the same inputs.

    The memo owns the keys: it answers a section only when everything that section
    reads is what it was when the section was saved (``reducerlab run`` keys them on
    its stages' cache keys, the design's hash and the verdict). A section that failed is
    never saved."""

    def load(self, sid: str, context: str) -> Section | None:
        """The stored section ``sid`` built in ``context``, or None. ``context`` is the
        report's digest of what it reads besides the given results and the verdict
        (the design's hash, its file's text, the overrides, the assumptions shown)."""

    def save(self, sid: str, context: str, section: Section) -> None:
        """Store section ``sid`` built in ``context``."""


@dataclass
class Report:
    """A rendered design report: its HTML, its sections (with the numbers each one
    reports, in ``values``) and the total run time (s)."""

    html: str
    design: Design
    sections: list[Section] = field(default_factory=list)
    seconds: float = 0.0
    #: the plotly.js the HTML inlines ("" without an interactive figure)
    plotly_js: str = ""

    def section(self, id: str) -> Section | None:
        """The section with this id, or None when the design has none."""
        return next((s for s in self.sections if s.id == id), None)

    @property
    def failed(self) -> list[Section]:
        return [s for s in self.sections if s.error]

    def write(self, path: str | Path, plotly: str | Path | None = None) -> Path:
        """Write the HTML to ``path`` (atomically) and return it.

        Parameters
        ----------
        path : path
            The report file.
        plotly : path, optional
            Where the reports of one folder share plotly.js (:data:`PLOTLY_FILE` in
            that folder, beside ``path``): the file is written there (unless it already
            holds the same script) and the report loads it by its name instead of
            inlining 4.6 MB of it, so it still opens offline. Default: inlined (one
            self-contained file). Without an interactive figure nothing is written.
        """
        from ..io import atomic_path

        p = Path(path)
        html = self.html
        if plotly is not None and self.plotly_js:
            js = Path(plotly)
            data = self.plotly_js.encode("utf-8")
            if not (js.is_file() and js.stat().st_size == len(data) and js.read_bytes() == data):
                with atomic_path(js) as tmp:
                    Path(tmp).write_bytes(data)
            inline = f'<script type="text/javascript">{self.plotly_js}</script>'
            html = html.replace(inline, f'<script src="{js.name}"></script>', 1)
        with atomic_path(p) as tmp:
            Path(tmp).write_text(html, encoding="utf-8")
        return p


def _design_and_text(target: Design | str | Path, overrides: Sequence[str]) -> tuple[Design, str]:
    from ..drives import load_design

    if isinstance(target, Design):
        if overrides:
            raise ReducerlabError("report: overrides apply to a design file, not a Design")
        src = Path(target.source)
        # the file's text, if the design is still what the file says (not a copy
        # changed in code, which has no "as written")
        if src.is_file() and load_design(src).hash == target.hash:
            return target, src.read_text(encoding="utf-8")
        return target, ""
    if not isinstance(target, str | Path):
        raise ReducerlabError(
            f"report: target must be a Design or a design file path, got {type(target).__name__}"
        )
    design = load_design(target, overrides)
    return design, Path(target).read_text(encoding="utf-8")


def report(
    target: Design | str | Path,
    *,
    overrides: Sequence[str] = (),
    results: Sequence[Any] = (),
    only: Sequence[str] | None = None,
    progress: Callable[[str, int, int], None] | None = None,
    verdict: Any = None,
    memo: SectionMemo | None = None,
) -> Report:
    """Build the HTML design report of a design.

    Parameters
    ----------
    target : Design, str or Path
        A validated design or a design file (TOML).
    overrides : sequence of str
        ``PATH=VALUE`` settings for a design file (as ``--set``).
    results : sequence of Result or path
        Results computed beforehand (``Result`` objects or their netCDF files): gear-body
        modes (``body-modal``, also checked in the resonance verdict), loaded contact
        (``contact``), bifurcation diagrams, regime maps, torque sweeps, layouts, a KHV
        pair's load sharing (``khv-sharing``), a torsion test (``torsion-test``, shown
        in the datasheet instead of the one the report computes), a drive's efficiency
        (``efficiency``, added to the datasheet with the starting and back-driving
        torque), a transmission accuracy (``transmission-accuracy``, shown in the
        datasheet instead of the rigid one the report computes). Each is checked against the design
        (:func:`reducerlab.inputs.check_inputs`): a result computed for other values of
        the inputs it depends on is refused, naming the fields that differ.
    only : sequence of str, optional
        Section ids to build (default: all that apply); provenance is always added.
    verdict : Verdict, optional
        The verdict to show, computed by the caller from more evidence than the report
        has (``reducerlab run``: with the consistency of its models); default the
        report's own (:meth:`.context.Context.verdict`).
    memo : SectionMemo, optional
        Sections built before for the same inputs (``reducerlab run``'s stage cache):
        each one found there is reused, not built again; each one built is saved.
    progress : callable, optional
        ``progress(description, done, total)`` before each section (``done`` sections
        of ``total``); long sections (bifurcation, regime map) also call it as they go,
        with their own count in the description.

    Returns
    -------
    Report
    """
    start = time.perf_counter()
    design, text = _design_and_text(target, overrides)
    ids = [sid for sid, _, _ in SECTIONS]
    if only is not None:
        unknown = [s for s in only if s not in ids]
        if unknown:
            raise ReducerlabError(f"report: unknown section(s) {unknown}; sections are {ids}")
    design, given = _results(results, design)
    ctx = Context(design, text, repo_assumptions(), given, overrides=tuple(overrides))
    if verdict is not None:
        ctx.cache["verdict"] = verdict
    todo = [(sid, title, build) for sid, title, build in SECTIONS if only is None or sid in only]
    context = _context_digest(ctx) if memo is not None else ""
    sections: list[Section] = []
    for k, (sid, title, build) in enumerate(todo):
        if progress is not None:
            progress(title, k, len(todo))

            def step(done: int, total: int, title: str = title, k: int = k) -> None:
                progress(f"{title}: {done}/{total}", k, len(todo))  # type: ignore[misc]

            ctx.step = step
        stored = None if memo is None else memo.load(sid, context)
        if stored is not None:
            stored.reused = True
            sections.append(stored)
            continue
        t0 = time.perf_counter()
        try:
            sec = build(ctx)
        except Exception as exc:  # a failed section shows its error; the rest renders
            sec = Section(sid, title, error=f"{type(exc).__name__}: {exc}")
            if not isinstance(exc, ReducerlabError):
                sec.details = traceback.format_exc()
        if sec is None:
            continue
        sec.seconds = time.perf_counter() - t0
        if memo is not None and not sec.error:
            memo.save(sid, context, sec)
        sections.append(sec)
    if progress is not None:
        progress("provenance", len(todo), len(todo))
    created = _dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat()
    total = time.perf_counter() - start
    sections.insert(0, _summary(design, sections))
    sections.append(_provenance(design, text, overrides, sections, created, total))
    interactive = any(b.kind == "interactive" for s in sections for b in s.blocks)
    plotly_js = ""
    if interactive:
        from plotly.offline import get_plotlyjs

        plotly_js = get_plotlyjs()
    html = (
        _environment()
        .get_template("report.html.j2")
        .render(
            title=design.name or design.type,
            design_type=design.type,
            design_hash=design.hash,
            created=created,
            version=__version__,
            sections=sections,
            plotly_js=plotly_js,
        )
    )
    return Report(html, design, sections, time.perf_counter() - start, plotly_js)


def _context_digest(ctx: Context) -> str:
    """What a section reads besides the given results and the verdict, as one digest."""
    from ..io import digest

    return digest(
        "\n\x00".join(
            [__version__, ctx.design.hash, ctx.text, *ctx.overrides, str(ctx.assumptions)]
        )
    )


def _plotly_file() -> str:
    from importlib.metadata import version

    return f"plotly-{version('plotly')}.min.js"


#: The file name of the plotly.js that the reports of one folder share
#: (:meth:`Report.write` with ``plotly=``): versioned, so reports written with another
#: plotly never load a script they were not written for.
PLOTLY_FILE = _plotly_file()

#: Kinds of results the report can take from a file.
GIVEN_KINDS = (
    "body-modal",
    "contact",
    "bifurcation",
    "regime-map",
    "response",
    "rating",
    "te-sweep",
    "layout",
    "khv-sharing",
    "torsion-test",
    "efficiency",
    "transmission-accuracy",
)


def _results(items: Sequence[Any], design: Design) -> tuple[Design, dict[str, list[Any]]]:
    """The design the report describes and the given results by kind.

    Loaded-contact results are checked against ``design`` first (the fields that
    generate their teeth) and put their k(t) into its meshes
    (:func:`~reducerlab.analysis.contact.design_with_contact`): the dynamics of the
    report are those of the contact's stiffness. Every other result is then checked
    against that design (:func:`reducerlab.inputs.check_inputs`): a result computed for
    other values of the inputs it depends on is refused, naming the fields that differ.
    """
    from ..analysis.contact import design_with_contact
    from ..inputs import check_inputs
    from ..results import Result

    loaded = []
    for item in items:
        r = item if isinstance(item, Result) else Result.load(item)
        if r.kind not in GIVEN_KINDS:
            raise ReducerlabError(
                f"report: {item}: a {r.kind!r} result; the report takes {', '.join(GIVEN_KINDS)} "
                "results (it computes the others itself)"
            )
        name = f"report: {item}" if not isinstance(item, Result) else None
        if not isinstance(item, Result):
            r.data.attrs.setdefault("source", str(item))
        loaded.append((name, r))
    out: dict[str, list[Any]] = {}
    for name, r in loaded:
        if r.kind == "contact":
            check_inputs(r, design, name)
            out.setdefault("contact", []).append(r)
    if out.get("contact"):
        design = design_with_contact(design, out["contact"])
    for name, r in loaded:
        if r.kind != "contact":
            check_inputs(r, design, name)
            out.setdefault(r.kind, []).append(r)
    return design, out


def _summary(design: Design, sections: list[Section]) -> Section:
    """The findings at a glance, taken from the other sections' values."""
    from .blocks import verdict

    s = Section("summary", "Summary")
    by = {x.id: x for x in sections if not x.error}
    rows: list[tuple[str, Any]] = [("drive", f"{design.type}: {design.name or '(unnamed)'}")]
    if "kinematics" in by:
        rows.append(("transmission ratio", by["kinematics"].values["ratio"]))
    if "modal" in by:
        f = [x for x in by["modal"].values["frequencies_hz"] if x > 0]
        rows.append(("elastic modes", len(f)))
        if f:
            rows.append(("lowest natural frequency (Hz)", min(f)))
    if "campbell" in by:  # the verdict (issue 27), as the Campbell section judged it
        v = by["campbell"].values
        risks = [r["text"] for r in v["reasons"] if r["status"] == "risk"]
        notes = sum(r["status"] == "note" for r in v["reasons"])
        passed = sum(r["status"] == "ok" for r in v["reasons"])
        if v["ok"]:
            text = f"no risk: {passed} check(s) passed, {notes} note(s)"
        else:
            more = f"; and {len(risks) - 3} more" if len(risks) > 3 else ""
            text = f"RISK ({len(risks)}): " + "; ".join(risks[:3]) + more
        s.blocks.append(verdict(v["ok"], text))
        rows.append(("verdict", "no risk" if v["ok"] else f"RISK ({len(risks)} finding(s))"))
    if "response" in by and "dynamic_load_factor" in by["response"].values:
        rows.append(("dynamic load factor", by["response"].values["dynamic_load_factor"]))
    failed = [x.title for x in sections if x.error]
    rows.append(("sections", f"{len(sections)} built" + (f", FAILED: {', '.join(failed)}"
                                                           if failed else "")))  # fmt: skip
    s.blocks.append(table(["", "value"], rows, name="summary"))
    s.values.update({k: v for k, v in rows})
    return s


def _provenance(
    design: Design,
    text: str,
    overrides: Sequence[str],
    sections: list[Section],
    created: str,
    total: float,
) -> Section:
    import numpy
    import scipy

    s = Section("provenance", "Provenance")
    file_hash = hashlib.sha256(text.encode()).hexdigest()[:16] if text else "—"
    rows = [
        ("reducerlab", __version__),
        ("created (UTC)", created),
        ("design source", design.source),
        ("design hash (SI content)", design.hash),
        ("design file hash (SHA-256)", file_hash),
        ("overrides (--set)", "; ".join(overrides) or "none"),
        (
            "python / numpy / scipy",
            f"{platform.python_version()} / {numpy.__version__} / {scipy.__version__}",
        ),
        ("machine", f"{platform.system()} {platform.machine()}"),
    ]
    s.blocks.append(table(["item", "value"], rows, name="provenance"))
    times = [
        (x.title, x.seconds, "failed" if x.error else "stored" if x.reused else "ok")
        for x in sections
    ]
    times.append(("total (analyses; rendering not included)", total, ""))
    s.blocks.append(table([Column("section", kind="text"), Column("run time", "s", "time"),
                           Column("status", kind="text")], times, name="times"))  # fmt: skip
    s.values.update(hash=design.hash, created=created, seconds={x.id: x.seconds for x in sections})
    return s


def write_index(reports: Sequence[tuple[Path, Report]], path: str | Path) -> Path:
    """Write an ``index.html`` linking reports (``(file, report)`` pairs) next to it."""
    from ..io import atomic_path

    p = Path(path)
    rows = []
    for file, rep in reports:
        camp = rep.section("campbell")
        if camp is None or camp.error:
            verdict, cls = "—", ""
        else:
            verdict, cls = ("no risk", "ok") if camp.values["ok"] else ("risk", "risk")
        rows.append(
            {
                "href": quote(Path(os.path.relpath(file, p.parent)).as_posix()),
                "file": Path(os.path.relpath(file, p.parent)).as_posix(),
                "title": rep.design.name or rep.design.type,
                "type": rep.design.type,
                "sections": len(rep.sections),
                "failed": len(rep.failed),
                "verdict": verdict,
                "verdict_class": cls,
                "seconds": rep.seconds,
            }
        )
    html = (
        _environment()
        .get_template("index.html.j2")
        .render(
            reports=rows,
            version=__version__,
            created=_dt.datetime.now(_dt.UTC).replace(microsecond=0).isoformat(),
        )
    )
    with atomic_path(p) as tmp:
        Path(tmp).write_text(html, encoding="utf-8")
    return p
