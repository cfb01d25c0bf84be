"""Benchmark: a KHV bifurcation diagram (paper 004 Fig. 7 setting) with the compiled
RK4 ensemble kernel, against ``solve_ivp`` RK45 (rtol 1e-8), the baseline a user picks.

Prints the wall time of model building and of the kernel for N_VALUES x 600 mesh
periods, the end-to-end ``bifurcation()`` call over a design field (every value a
rebuilt, validated design) and over a model parameter (no rebuild), the per-trajectory
time of a sample of solve_ivp runs and the speed-up, and the same kernel on the 12-DOF
nutation drive. Run:
``.venv/bin/python benchmarks/bifurcation.py [N_VALUES]``.
"""

from __future__ import annotations

import datetime as dt
import os
import platform
import sys
import time

import numpy as np
import scipy.integrate

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.parameters import Axis, Evaluator, resolve
from reducerlab.drives import build_model, load_design
from reducerlab.dynamics.coordinates import static_state, to_system
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.systems import forcing_period
from reducerlab.examples import example_dir

PERIODS, KEEP = 600, 100


def systems_for(design_file: str, path: str, values: np.ndarray):
    design = load_design(example_dir() / design_file)
    model = build_model(design)
    ev = Evaluator(design, model, (resolve(design, model, path),))
    return [to_system(ev.model_at([v])) for v in values]


def _timed(fn) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def measured_peak_gflops() -> float:
    """Practical peak: double-precision GEMM through numpy's BLAS on all cores."""
    a = np.random.default_rng(0).standard_normal((2000, 2000))
    a @ a
    t = time.perf_counter()
    for _ in range(3):
        a @ a
    return 3 * 2 * 2000**3 / (time.perf_counter() - t) / 1e9


def flops_per_trajectory(s, steps_per_period: int) -> float:
    """Floating-point operations of one trajectory, counted from the kernel's loops (the
    law table is built once per run and not counted)."""
    n, L = s.n, s.G.shape[0]
    rhs = 4 * n * n + L * (4 * n + 10 + 2 * n)  # M^-1 K, M^-1 C; deflections, force, M^-1 G^T
    step = 4 * rhs + 3 * 2 * (2 * n) + 8 * (2 * n) + 2 * (2 * n)  # stages, update, check
    return float(step * steps_per_period * PERIODS)


def main() -> None:
    n_values = int(sys.argv[1]) if len(sys.argv) > 1 else 1000
    values = np.linspace(0.416, 0.835, n_values)
    t0 = time.perf_counter()
    systems = systems_for("khv.toml", "gears.x1", values)
    t_build = time.perf_counter() - t0
    ensemble(systems[:2], periods=2, keep=1)  # compile (cached on disk after the first run)
    y0 = np.array([static_state(s) for s in systems])
    t_kernel = min(_timed(lambda: ensemble(systems, periods=PERIODS, keep=KEEP, y0=y0))
                   for _ in range(3))  # fmt: skip
    design = load_design(example_dir() / "khv.toml")
    t_design = _timed(
        lambda: bifurcation(design, Axis("gears.x1", values), periods=PERIODS, keep=KEEP)
    )
    backlash = np.linspace(0.5e-6, 5e-6, n_values)
    t_model = _timed(
        lambda: bifurcation(
            design, Axis("mesh.backlash.half_width", backlash), periods=PERIODS, keep=KEEP
        )
    )
    # baseline: solve_ivp RK45, rtol 1e-8, on a few members
    sample = systems[:: max(1, n_values // 3)][:3]
    t0 = time.perf_counter()
    for s in sample:
        T = forcing_period(s)
        t_eval = np.arange(500, 600) * T
        y0 = np.zeros(2 * s.n)
        scipy.integrate.solve_ivp(
            s.rhs, (0, PERIODS * T), y0, method="RK45", rtol=1e-8, atol=1e-14, t_eval=t_eval
        )
    t_ivp = (time.perf_counter() - t0) / len(sample)
    per = t_kernel / n_values
    from reducerlab.dynamics.steps import steps_for

    steps = steps_for(systems[0], forcing_period(systems[0]))
    gflops = flops_per_trajectory(systems[0], steps) * n_values / t_kernel / 1e9
    peak = measured_peak_gflops()
    # 12-DOF nutation drive through the same kernel (mesh stiffness sweep, 100 values)
    nut = systems_for("nutation_double_sided.toml", "mesh1.stiffness",
                      np.linspace(1.5e8, 3e8, 100))  # fmt: skip
    ensemble(nut[:2], periods=2, keep=1)
    t0 = time.perf_counter()
    ensemble(nut, periods=PERIODS, keep=KEEP)
    t_nut = time.perf_counter() - t0
    print(f"date: {dt.date.today().isoformat()}")
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}"
    )
    print(f"KHV (3 elastic DOF) {n_values} values x {PERIODS} mesh periods:")
    print(f"  serial per-value model building (one process): {t_build:.2f} s")
    print(f"  kernel (ensemble() on the built systems, best of 3): {t_kernel:.2f} s")
    print(f"  bifurcation() end to end over gears.x1 (design rebuilt per value): {t_design:.2f} s")
    print(f"  bifurcation() end to end over mesh.backlash.half_width (model parameter): "
          f"{t_model:.2f} s")  # fmt: skip
    print(f"  {per * 1e3:.2f} ms per trajectory (kernel, 2 threads)")
    print(f"  solve_ivp RK45 rtol 1e-8: {t_ivp:.2f} s/trajectory -> speed-up x{t_ivp / per:.0f}")
    print(f"  {steps} steps per period; kernel {gflops:.2f} GFLOP/s against a measured DGEMM")
    print(f"  peak of {peak:.1f} GFLOP/s ({100 * gflops / peak:.1f} %)")
    nut_steps = steps_for(nut[0], forcing_period(nut[0]))
    print(
        f"nutation drive (11 elastic DOF) 100 values x {PERIODS} periods x {nut_steps} steps: "
        f"kernel {t_nut:.2f} s, "
        f"{flops_per_trajectory(nut[0], nut_steps) * 100 / t_nut / 1e9:.2f} GFLOP/s"
    )


if __name__ == "__main__":
    main()
