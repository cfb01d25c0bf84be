"""The process's threading policy (issue 28): the loaded contact analysis with and
without it, side by side.

``reducerlab contact examples/nutation_surface.toml --pair 1 --power 3kW`` as the API
call it makes (24 positions, cell from the pilot run). The FE tooth compliance of both
gears is computed once (a first process) and handed to every run, so that each run
times the contact solver, where the dense factorisations are. Four runs, each in a
fresh process (the pools as a new command finds them), one after the other: the policy
off (``REDUCERLAB_THREADS=off``: OpenBLAS and libgomp each on every core, as loaded) and
on, alone and beside one busy process (a pure-Python loop on one core: what another
test worker or another command does to a 2-core machine). In each, every dense Cholesky
factorisation of the contact solver is timed (``cho_factor`` wrapped: its size and
seconds, ``n^3 / 3`` flops), and after the analysis a standalone factorisation of the
median size runs in the same process (best of 5, the pools as the process has them
outside the policy): the contact's factorisation rate against it is the share the issue
asks to be >= 50 %.

Run: ``.venv/bin/python benchmarks/threads.py`` (about 5 minutes on 2 cores).
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


def compliance(path: str) -> None:
    """The FE tooth compliance of pair 1's two gears, pickled to ``path``."""
    import pickle

    from reducerlab.analysis.contact import contact_pair
    from reducerlab.contact.compliance import fe_tooth_compliance
    from reducerlab.drives import load_design

    pair = contact_pair(load_design(EXAMPLE), 1)
    comps = (fe_tooth_compliance(pair.flank_a), fe_tooth_compliance(pair.flank_b))
    Path(path).write_bytes(pickle.dumps(comps))


def child(policy: str, path: str) -> dict:
    """One analysis in this process, policy as ``REDUCERLAB_THREADS`` says."""
    import pickle

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
    comps = pickle.loads(Path(path).read_bytes())
    contact_analysis(
        design, 1, power=3000.0, compliance=comps,
        stage=lambda s: stages.append((s, time.perf_counter() - t0)),
    )  # fmt: skip
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
    return {
        "policy": policy,
        "seconds": total,
        "calls": len(calls),
        "median_n": n,
        "max_n": int(sizes.max()),
        "chol_seconds": float(secs.sum()),
        "chol_gflops": flops / float(secs.sum()) / 1e9,
        "standalone_gflops": n**3 / 3 / best / 1e9,
        "pools": pools(),
    }


def main() -> None:
    import tempfile

    print(
        f"date: {date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, {EXAMPLE.name} pair 1 at 3 kW"
    )
    tmp = Path(tempfile.mkdtemp(prefix="threads-bench-"))
    comps = tmp / "compliance.pkl"
    t0 = time.perf_counter()
    subprocess.run([sys.executable, __file__, "--compliance", str(comps)], check=True)
    print(f"FE tooth compliance of both gears (policy on): {time.perf_counter() - t0:.1f} s")
    rows = []
    for busy in (False, True):
        for policy in ("off", "on"):
            hog = None
            if busy:
                hog = subprocess.Popen([sys.executable, "-c", "while True: pass"])
            try:
                env = {**os.environ, "REDUCERLAB_THREADS": policy}
                out = subprocess.run(
                    [sys.executable, __file__, "--child", policy, str(comps)],
                    env=env, check=True, capture_output=True, text=True,
                )  # fmt: skip
            finally:
                if hog is not None:
                    hog.kill()
                    hog.wait()
            row = json.loads(out.stdout.strip().splitlines()[-1])
            row["load"] = "one busy core" if busy else "alone"
            rows.append(row)
    print(
        "| machine | policy | contact solver (s) | Cholesky calls (median n, max n) | "
        "Cholesky (s) | in the contact (GFLOP/s) | standalone (GFLOP/s) | share |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(
            f"| {r['load']} | {r['policy']} | {r['seconds']:.1f} | "
            f"{r['calls']} ({r['median_n']}, {r['max_n']}) | {r['chol_seconds']:.2f} | "
            f"{r['chol_gflops']:.1f} | {r['standalone_gflops']:.1f} | "
            f"{100 * r['chol_gflops'] / r['standalone_gflops']:.0f} % |"
        )
    for load in ("alone", "one busy core"):
        off, on = (r for r in rows if r["load"] == load)
        print(f"{load}: contact solver {off['seconds'] / on['seconds']:.2f}x faster with the "
              f"policy, Cholesky {off['chol_seconds'] / on['chol_seconds']:.2f}x")  # fmt: skip
    pools = rows[1]["pools"]
    print("pools:", ", ".join(f"{p['api']} {p['library']} {p['threads']}" for p in pools))


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "--compliance":
        compliance(sys.argv[2])
    elif len(sys.argv) > 3 and sys.argv[1] == "--child":
        print(json.dumps(child(sys.argv[2], sys.argv[3])))
    else:
        main()
