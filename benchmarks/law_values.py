"""Benchmark (issue 28): a bifurcation diagram over a value that changes only the laws
(the input speed: law frequencies, periods, loads) with the members evaluated from
their form (``analysis.members.FORMS``) against the same call with every value's model
rebuilt (the probe switched off), and against the same call with the members handed
over ready-made (the kernel and the chunk bookkeeping alone: "kernel").

Side by side in one process, best of 3 each, interleaved. Run:
``.venv/bin/python benchmarks/law_values.py [N_VALUES]``.
"""

from __future__ import annotations

import datetime as dt
import os
import platform
import sys
import time
from dataclasses import replace
from unittest import mock

import numpy as np

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.members import Members, target_members
from reducerlab.analysis.parameters import Axis, resolve
from reducerlab.drives import build_model, load_design
from reducerlab.examples import example_dir

PERIODS, KEEP = 600, 100
CASES = (  # design, speeds (rad/s), values
    ("khv.toml", (100.0, 300.0), 1000),
    ("nutation_double_sided.toml", (100.0, 220.0), 100),
)


def best(fn, n=3) -> float:
    out = []
    for _ in range(n):
        t = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t)
    return min(out)


def main() -> None:
    scale = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0
    print(f"date: {dt.datetime.now(dt.UTC):%Y-%m-%d %H:%M} UTC, machine: {platform.machine()}, "
          f"{os.cpu_count()} cores, Python {platform.python_version()}, "
          f"load average {os.getloadavg()[0]:.2f}")  # fmt: skip
    head = ("design", "values x periods", "kernel (s)", "bifurcation, rebuilt (s)",
            "bifurcation, evaluated (s)", "rebuilt / kernel", "evaluated / kernel",
            "form")  # fmt: skip
    print("| " + " | ".join(head) + " |")
    print("|---|---|---|---|---|---|---|---|")
    builds = []
    for name, (lo, hi), n in CASES:
        n = max(9, int(n * scale))
        design = load_design(example_dir() / name)
        model = build_model(design)
        values = np.linspace(lo, hi, n)
        members, _ = target_members(design, model, [resolve(design, model, "input_speed")])
        members.probe(lo, hi)
        built = dict(zip(values.tolist(), members(values), strict=True))
        axis = Axis("input_speed", values)

        def served(self, chunk, built=built):  # handed over ready-made: no build at all
            return [built[float(v)] for v in chunk]

        def kernel(design=design, axis=axis, served=served):
            with mock.patch.object(Members, "__call__", served):
                return bifurcation(design, axis, periods=PERIODS, keep=KEEP)

        def evaluated(design=design, axis=axis):
            return bifurcation(design, axis, periods=PERIODS, keep=KEEP)

        def rebuilt(design=design, axis=axis):
            with mock.patch.object(Members, "probe", lambda self, lo, hi: None):
                return bifurcation(design, axis, periods=PERIODS, keep=KEEP)

        plain = replace(members, fit=None)  # the same members, built value by value
        t_fit = best(lambda m=members, v=values: m(v))
        t_one = best(lambda m=plain, v=values: m(v))
        builds.append(f"{name}: members of {n} values built {t_one:.2f} s, evaluated from "
                      f"their form {t_fit:.3f} s ({t_one / t_fit:.0f}x)")  # fmt: skip
        a, b = evaluated(), rebuilt()  # same diagram both ways
        diff = np.nanmax(np.abs(a.data["poincare"].values - b.data["poincare"].values))
        size = np.nanmax(np.abs(b.data["poincare"].values))
        t_k, t_r, t_e = [], [], []
        for _ in range(3):  # interleaved
            t_k.append(best(kernel, 1))
            t_r.append(best(rebuilt, 1))
            t_e.append(best(evaluated, 1))
        k, r, e = min(t_k), min(t_r), min(t_e)
        form = members.fit.form if members.fit is not None else "rebuilt"
        print(f"| {name} | {n} x {PERIODS} | {k:.2f} | {r:.2f} | {e:.2f} | {r / k:.2f}x | "
              f"{e / k:.2f}x | {form} (largest difference {diff / size:.1e} of the "
              f"largest point) |")  # fmt: skip

    print("\n".join(builds))


if __name__ == "__main__":
    main()
