"""Benchmark: the cost of classification and of regime maps (issue 16).

1. Lyapunov exponents. ``bifurcation(..., exponents=True)`` computes each value's
   largest exponent inside the compiled kernel, beside the trajectory whose points it
   classifies. Side by side on the KHV drive (``examples/khv.toml``, ``VALUES`` values
   of x1, 600 periods): the plain diagram, the diagram with exponents, and the way
   exponents were computed before (and the way a user would add them to the kernel's
   trajectories): a second run of reference/perturbed pairs, the kernel called once per
   period from Python, separation measured and renormalised in numpy (Benettin).
2. Regime map. ``regime_map`` over speed x x1 (continuation both ways, exponents), its
   rows integrated together as one ensemble, against the same map as one
   ``bifurcation(continuation="both", exponents=True)`` per row.

Run: ``.venv/bin/python benchmarks/nonlinear_maps.py``.
"""

from __future__ import annotations

import datetime as dt
import math
import os
import platform
import time

import numpy as np

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.members import axis_members
from reducerlab.analysis.parameters import Axis, parse_values
from reducerlab.analysis.regime_map import regime_map
from reducerlab.drives import build_model, load_design
from reducerlab.dynamics.coordinates import static_states
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.guards import state_bounds
from reducerlab.dynamics.kernel import block_width, rk4_ensemble
from reducerlab.dynamics.prepare import prepare as _prepare
from reducerlab.dynamics.prepare import with_steps as _with_steps
from reducerlab.examples import example_dir

VALUES, PERIODS, KEEP = 100, 600, 100


def per_period_exponents(systems, y0, steps: int, transient: int, d0: float = 1e-9):
    """Benettin's method with the kernel called once per period (the old way)."""
    pairs = [s for s in systems for _ in range(2)]
    prep = _with_steps(_prepare(pairs, steps, None), pairs, steps)
    T = prep.period
    Y = np.repeat(y0, 2, axis=0)
    bounds = state_bounds(pairs, Y, T)
    bw, n = block_width(len(pairs)), systems[0].n

    def one(Y, k):
        P, _, _, _ = rk4_ensemble(*prep.arrays, Y, k * T, T, prep.offs, prep.dts,
                                  prep.periodic, 1, 1, 0, bounds, bw, -1, 0.0)  # fmt: skip
        return P[:, 1].copy()

    for k in range(transient):
        Y = one(Y, k)
    ref = Y[0::2]
    amp = np.maximum(np.abs(ref[:, :n]).max(axis=1, keepdims=True), 1e-12)
    w = 2 * math.pi / T[0::2, None]
    scale = np.concatenate([np.repeat(amp, n, 1), np.repeat(amp * w, n, 1)], axis=1)
    Y[1::2] = Y[0::2]
    Y[1::2, 0] += d0 * scale[:, 0]
    total = np.zeros(len(systems))
    for k in range(transient, PERIODS):
        Y = one(Y, k)
        diff = (Y[1::2] - Y[0::2]) / scale
        d = np.linalg.norm(diff, axis=1)
        d = np.where(d > 0, d, d0)
        total += np.log(d / d0)
        Y[1::2] = Y[0::2] + (diff * (d0 / d)[:, None]) * scale
    return total / ((PERIODS - transient) * T[0::2])


def main() -> None:
    print(f"date: {dt.date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}")  # fmt: skip
    d = load_design(example_dir() / "khv.toml")
    axis = Axis.linspace("gears.x1", 0.416, 0.835, VALUES)
    bifurcation(d, Axis.linspace("gears.x1", 0.5, 0.6, 2), periods=4, keep=2,
                exponents=True)  # fmt: skip  # compile
    t = time.perf_counter()
    plain = bifurcation(d, axis, periods=PERIODS, keep=KEEP)
    t_plain = time.perf_counter() - t
    t = time.perf_counter()
    classified = bifurcation(d, axis, periods=PERIODS, keep=KEEP, exponents=True)
    t_ex = time.perf_counter() - t
    values, members, _ = axis_members(d, build_model(d), axis, "benchmark")
    systems = members(values)
    y0 = static_states(systems)
    steps = ensemble(systems, periods=PERIODS, keep=1, y0=y0).steps_per_period
    t = time.perf_counter()
    lam = per_period_exponents(systems, y0, steps, PERIODS - KEEP)
    t_loop = time.perf_counter() - t
    diff = np.max(np.abs(lam - classified.data["exponent"].values))
    print(f"KHV, {VALUES} values of x1 x {PERIODS} periods ({steps} steps/period):")
    print(f"  bifurcation, points only:                {t_plain:.2f} s")
    print(f"  bifurcation with exponents (in kernel):  {t_ex:.2f} s "
          f"({t_ex / t_plain:.2f}x the points alone)")  # fmt: skip
    print(f"  exponents by a per-period Python loop:   {t_loop:.2f} s on top of the points "
          f"({(t_plain + t_loop) / t_ex:.1f}x slower in all); exponents agree to "
          f"{diff:.1e} 1/s")  # fmt: skip
    assert plain.data["poincare"].shape == classified.data["poincare"].shape

    x = parse_values("input_speed", "lin:100 rpm:2000 rpm:20")
    y = Axis.linspace("gears.x1", 0.416, 0.835, 8)
    t = time.perf_counter()
    rm = regime_map(d, x, y, periods=PERIODS, keep=64, continuation="both")
    t_map = time.perf_counter() - t
    t = time.perf_counter()
    rows = []
    for v in y.values:
        dv = load_design(example_dir() / "khv.toml", [f"gears.x1={v!r}"])
        rows.append(bifurcation(dv, x, periods=PERIODS, keep=64, exponents=True,
                                continuation="both"))  # fmt: skip
    t_rows = time.perf_counter() - t
    same = sum(rm.labels()[0, j].tolist() == r.labels() for j, r in enumerate(rows))
    print(f"regime map speed x x1, {x.values.__len__()} x {len(y.values)} points, both "
          f"sweeps, {PERIODS} periods, exponents:")  # fmt: skip
    print(f"  regime_map (rows as one ensemble):       {t_map:.2f} s")
    print(
        f"  one bifurcation(continuation='both') per row: {t_rows:.2f} s "
        f"({t_rows / t_map:.1f}x); rows with the same ascending labels: {same}/{len(rows)}"
    )


if __name__ == "__main__":
    main()
