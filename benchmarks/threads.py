"""The process's threading policy (issue 28): the loaded contact analysis with and
without it, side by side.

``reducerlab contact examples/nutation_surface.toml --pair 1 --power 3kW`` as the API
call it makes (default grids: FE tooth compliance of both gears, 24 positions, cell
from the pilot run), once with the policy off (``REDUCERLAB_THREADS=off``: OpenBLAS and
libgomp each on every core, as loaded) and once with it on, each in a fresh process
(the pools as a new command finds them), one after the other. In each, every dense
Cholesky factorisation of the contact solver is timed (``cho_factor`` wrapped: its
size and seconds, ``n^3 / 3`` flops), and after the analysis a standalone factorisation
of the median size runs in the same process (best of 5, the pools as the process has
them outside the policy): the contact's factorisation rate against it is the share the
issue asks to be >= 50 %.

Run: ``.venv/bin/python benchmarks/threads.py`` (about 6 minutes on 2 cores alone).
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import time
from datetime import date
from pathlib import Path

os.environ.setdefault("MPLBACKEND", "Agg")

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "nutation_surface.toml"


def child(policy: str) -> dict:
    """One analysis in this process, policy as ``REDUCERLAB_THREADS`` says."""
    import numpy as np
    import scipy.linalg

    import reducerlab.contact.complementarity as comp
    from reducerlab.analysis.contact import contact_analysis
    from reducerlab.drives import load_design
    from reducerlab.threads import pools

    calls: list[tuple[int, float]] = []
    real = comp.cho_factor

    def timed(a, *args, **kwargs):
        t = time.perf_counter()
        out = real(a, *args, **kwargs)
        calls.append((a.shape[0], time.perf_counter() - t))
        return out

    comp.cho_factor = timed
    design = load_design(EXAMPLE)
    stages: list[tuple[str, float]] = []
    t0 = time.perf_counter()
    contact_analysis(
        design, 1, power=3000.0, stage=lambda s: stages.append((s, time.perf_counter() - t0))
    )
    total = time.perf_counter() - t0
    comp.cho_factor = real
    sizes = np.array([n for n, _ in calls])
    secs = np.array([s for _, s in calls])
    flops = float(np.sum(sizes.astype(float) ** 3 / 3))
    n = int(np.median(sizes))
    rng = np.random.default_rng(0)
    B = rng.standard_normal((n, n))
    A = B @ B.T + n * np.eye(n)
    best = np.inf
    for _ in range(5):
        X = np.asfortranarray(A.copy())
        t = time.perf_counter()
        scipy.linalg.cho_factor(X, lower=True, overwrite_a=True, check_finite=False)
        best = min(best, time.perf_counter() - t)
    # the FE compliance of both gears ends where the pilot contact begins
    compliance = next((t for s, t in stages if s.startswith("pilot")), float("nan"))
    return {
        "policy": policy,
        "seconds": total,
        "compliance_seconds": compliance,
        "calls": len(calls),
        "median_n": n,
        "max_n": int(sizes.max()),
        "chol_seconds": float(secs.sum()),
        "chol_gflops": flops / float(secs.sum()) / 1e9,
        "standalone_gflops": n**3 / 3 / best / 1e9,
        "pools": pools(),
    }


def main() -> None:
    print(
        f"date: {date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, {EXAMPLE.name} pair 1 at 3 kW"
    )
    rows = []
    for policy in ("off", "on"):
        env = {**os.environ, "REDUCERLAB_THREADS": policy}
        out = subprocess.run(
            [sys.executable, __file__, "--child", policy],
            env=env,
            check=True,
            capture_output=True,
            text=True,
        )
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
    print(
        "| policy | analysis (s) | FE compliance (s) | Cholesky calls (median n, max n) | "
        "Cholesky (s) | in the contact (GFLOP/s) | standalone (GFLOP/s) | share |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['policy']} | {r['seconds']:.1f} | {r['compliance_seconds']:.1f} | "
            f"{r['calls']} ({r['median_n']}, {r['max_n']}) | {r['chol_seconds']:.2f} | "
            f"{r['chol_gflops']:.1f} | "
            f"{r['standalone_gflops']:.1f} | "
            f"{100 * r['chol_gflops'] / r['standalone_gflops']:.0f} % |"
        )
    off, on = rows
    print(f"speed-up of the analysis with the policy: {off['seconds'] / on['seconds']:.2f}x")
    print("pools:", ", ".join(f"{p['api']} {p['library']} {p['threads']}" for p in on["pools"]))


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "--child":
        print(json.dumps(child(sys.argv[2])))
    else:
        main()
