"""Benchmark: the design report of every bundled example (issue 18, target <= 30 s each
on 2 cores).

For each example ``reducerlab report EXAMPLE -o OUT.html`` runs as a user runs it: a
fresh process (imports, numba's cached kernels, every analysis, the rendering, the
file), timed from outside; the report's own provenance block gives the time of each
section, which is printed beside it.

Run: ``.venv/bin/python benchmarks/report_speed.py`` (about a minute).
"""

from __future__ import annotations

import datetime as dt
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy
import scipy

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent / "reducerlab"
LIMIT = 30.0


def main() -> None:
    examples = sorted((ROOT / "examples").glob("*.toml"))
    print(f"date: {dt.date.today()}")
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}, numpy {numpy.__version__}, scipy {scipy.__version__}"
    )
    print(f"{'example':<28} {'wall (s)':>9} {'size (MB)':>10}  slowest sections (s)")
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for path in examples:
            out = Path(tmp) / f"{path.stem}.html"
            t0 = time.perf_counter()
            r = subprocess.run([str(BIN), "report", str(path), "-o", str(out)],
                               capture_output=True, text=True,
                               env={**os.environ, "MPLBACKEND": "Agg"})  # fmt: skip
            wall = time.perf_counter() - t0
            if r.returncode != 0:
                print(f"{path.stem}: FAILED\n{r.stdout}\n{r.stderr}")
                continue
            rows = re.findall(r"^  (.+?)\s+([0-9.]+) s  ok$", r.stdout, flags=re.M)
            slow = sorted(((float(t), name.strip()) for name, t in rows), reverse=True)[:3]
            text = ", ".join(f"{n} {t:.1f}" for t, n in slow)
            size = out.stat().st_size / 1e6
            print(f"{path.stem:<28} {wall:9.1f} {size:10.1f}  {text}")
            worst = max(worst, wall)
    verdict = "within" if worst <= LIMIT else "OVER"
    print(f"slowest report: {worst:.1f} s ({verdict} the {LIMIT:.0f} s target)")


if __name__ == "__main__":
    main()
