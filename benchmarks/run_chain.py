"""The whole chain of ``reducerlab run`` on the flagship example (issue 27).

``examples/nutation_double_sided.toml`` at its operating point (1500 rpm, 120 N m on
the output), default grids: the FE tooth compliance of all four gears, the loaded
contact of both pairs at their own torques, the contact's k(t) in the model, modes and
Campbell diagram, the nonlinear response of both mesh lines, the four gear bodies' FE
modes, the verdict and the report. Three runs into one output folder, side by side:

* ``cold``: an empty stage cache (every stage computed);
* ``cached``: the same design again (every stage read from the cache; the modes,
  Campbell diagram, verdict and report are made again);
* ``damping``: the mesh damping changed (``--set mesh1.damping=...``): only the
  dynamics (responses) recomputed, no FE model and no contact.

Run: ``.venv/bin/python benchmarks/run_chain.py [OUTPUT] [--keep]``; prints a Markdown
table for ``benchmarks/RESULTS.md`` (the stages of each run, their status and seconds).
``--keep`` keeps an existing OUTPUT (and its cache) instead of starting cold: the first
run then reads every stage and stores the verdict and the report's sections, and the
``cached`` run after it is the second run of an unchanged design.
"""

from __future__ import annotations

import os
import platform
import shutil
import sys
import tempfile
import time
from datetime import date
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "nutation_double_sided.toml"


def main() -> None:
    from reducerlab.pipeline import run

    args = [a for a in sys.argv[1:] if a != "--keep"]
    keep = "--keep" in sys.argv[1:]
    out = Path(args[0]) if args else Path(tempfile.mkdtemp()) / "run"
    if not keep:
        shutil.rmtree(out, ignore_errors=True)
    print(
        f"date: {date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, {EXAMPLE.name}"
    )
    rows = []
    first = "kept cache" if keep else "cold"
    for label, sets in ((first, ()), ("cached", ()), ("damping", ("mesh1.damping=900 N*s/m",))):
        t0 = time.perf_counter()
        res = run(EXAMPLE, out, overrides=sets)
        total = time.perf_counter() - t0
        computed = [s for s in res.stages if s.status == "computed"]
        rows.append((label, total, res))
        print(
            f"\n{label}: {total:.1f} s, verdict {'ok' if res.ok else 'RISK'}, "
            f"{len(computed)} of {len(res.stages)} stages computed"
        )
        print("| stage | status | s |")
        print("|---|---|---|")
        for s in res.stages:
            print(f"| {s.name} | {s.status} | {s.seconds:.1f} |")
    cold, cached = rows[0][1], rows[1][1]
    print(
        f"\n{first} {cold:.1f} s, cached {cached:.1f} s ({cold / cached:.1f}x), "
        f"damping changed {rows[2][1]:.1f} s"
    )


if __name__ == "__main__":
    main()
