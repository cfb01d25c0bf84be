"""Fuzz the newer commands (issue 26): every hostile case of ``tests/fuzz_commands.py``
and seeded random pairs of them, each in its own process under a memory cap and a time
limit, and count what happened.

Outcomes: ``refused`` (exit 2, one clean message, no traceback), of which ``named``
names the option or the design field; ``ran`` (exit 0 or 1: the command accepted the
input); ``traceback`` (an exception that is not a ``ReducerlabError``, or a traceback
printed); ``memory`` (MemoryError or killed by the cap); ``timeout`` (still working
after the limit, killed).

A parent process imports reducerlab once and forks a child per case (the child sets
``RLIMIT_AS`` and runs the command line in-process), so a case costs its own work, not
an interpreter start.

Run: ``.venv/bin/python benchmarks/fuzz_commands.py [--limit S] [--cap GIB] [--pairs N]
[--seed K] [--json FILE]``; prints the counts and every case that was not refused.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import multiprocessing as mp
import os
import platform
import resource
import sys
import tempfile
import time
import traceback
from datetime import date
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
os.environ.setdefault("MPLBACKEND", "Agg")

from fuzz_commands import Case, cases, combinations


def _child(args: tuple[str, ...], cap: int, out_path: str) -> None:  # pragma: no cover
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    from reducerlab.cli import app

    buf = io.StringIO()
    code, kind = 0, "ok"
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
        try:
            app(list(args), prog_name="reducerlab")
        except SystemExit as e:
            code = e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
        except MemoryError:
            code, kind = 1, "memory"
        except BaseException:
            code, kind = 1, "traceback"
            traceback.print_exc(file=buf)
    Path(out_path).write_text(json.dumps({"code": code, "kind": kind, "text": buf.getvalue()}))


def run_case(case: Case, limit: float, cap: int, scratch: str) -> dict:
    out = os.path.join(scratch, "case.json")
    with contextlib.suppress(FileNotFoundError):
        os.remove(out)
    p = mp.get_context("fork").Process(target=_child, args=(case.args, cap, out))
    t0 = time.perf_counter()
    p.start()
    p.join(limit)
    if p.is_alive():
        p.kill()
        p.join()
        return {"case": case.label, "outcome": "timeout", "seconds": limit}
    seconds = time.perf_counter() - t0
    if not os.path.exists(out):
        return {"case": case.label, "outcome": "memory", "seconds": seconds,
                "text": f"killed (exit {p.exitcode})"}  # fmt: skip
    rec = json.loads(Path(out).read_text())
    text = rec["text"]
    if rec["kind"] == "memory" or "MemoryError" in text:
        outcome = "memory"
    elif rec["kind"] == "traceback" or "Traceback" in text:
        outcome = "traceback"
    elif rec["code"] == 2:
        outcome = "named" if any(n in text for n in case.names) else "refused"
    else:
        outcome = "ran"
    return {"case": case.label, "outcome": outcome, "seconds": round(seconds, 2),
            "text": text.strip()[-300:]}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--limit", type=float, default=120.0, help="seconds per case")
    ap.add_argument("--cap", type=float, default=8.0, help="address-space cap, GiB")
    ap.add_argument("--pairs", type=int, default=40, help="random two-option cases")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--json", type=Path, default=None)
    a = ap.parse_args()
    from typer.testing import CliRunner

    from reducerlab.cli import app

    # import once, before forking: a refused case then costs milliseconds, not imports
    with tempfile.TemporaryDirectory() as tmp:
        for c in cases(tmp):
            if c.args[-1] == "nan":
                CliRunner().invoke(app, list(c.args))

    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "folder").mkdir()
        (Path(tmp) / "note.txt").write_text("not a result\n")
        todo = cases(tmp) + combinations(tmp, a.pairs, a.seed)
        records = []
        for i, c in enumerate(todo):
            os.chdir(tmp)
            r = run_case(c, a.limit, int(a.cap * 2**30), tmp)
            records.append(r)
            print(f"[{i + 1}/{len(todo)}] {r['outcome']:9s} {r['seconds']:7.1f} s  {c.label}",
                  flush=True)  # fmt: skip
    counts: dict[str, int] = {}
    for r in records:
        counts[r["outcome"]] = counts.get(r["outcome"], 0) + 1
    print(
        f"\n{date.today()} {platform.node()} {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores; {len(records)} cases, limit {a.limit:g} s, cap {a.cap:g} GiB"
    )
    for k in ("named", "refused", "ran", "traceback", "memory", "timeout"):
        print(f"  {k:9s} {counts.get(k, 0)}")
    for r in records:
        if r["outcome"] not in ("named",):
            print(f"\n{r['outcome']}: {r['case']}\n  {r.get('text', '')[-200:]}")
    if a.json:
        a.json.write_text(json.dumps({"counts": counts, "records": records}, indent=1))


if __name__ == "__main__":
    main()
