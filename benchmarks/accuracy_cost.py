"""Benchmark: the cost of the accuracy-driven default step count in impact cases (issue 16).

Two systems whose teeth separate every period:

* the KHV drive of paper 004 (``examples/khv.toml``, 1500 rpm: apart 31 % of the time),
  ``VALUES`` values of its input speed 1400..1600 rpm;
* the single-DOF rattle oscillator of Kahraman and Singh (1990),
  ``x'' + 0.1 x' + f(x) = 0.1 + F_a cos(1.2 t)``, ``VALUES`` values of F_a 0.15..0.25.

For each, ``VALUES`` x 600 periods through ``ensemble`` with 32 steps per period (the old
default's floor) and with the default (``accuracy = 1e-6``), timed; the error of one
period of motion (from each of 10 kept Poincaré points to the next) is measured on
``CHECK`` members against the event-located DOP853 reference (``simulate_reference``,
rtol 1e-12), relative to the displacement scale.
Run: ``.venv/bin/python benchmarks/accuracy_cost.py``.
"""

from __future__ import annotations

import datetime as dt
import math
import os
import platform
import time

import numpy as np

from reducerlab.analysis.parameters import Evaluator, resolve
from reducerlab.drives import build_model, load_design
from reducerlab.dynamics.accuracy import accurate_steps
from reducerlab.dynamics.coordinates import static_states, to_system
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.dynamics.guards import state_bounds
from reducerlab.dynamics.prepare import prepare as _prepare
from reducerlab.dynamics.reference import simulate_reference
from reducerlab.examples import example_dir
from reducerlab.model import Backlash, Dof, Fourier, Inertia, Load, Mesh, Model

VALUES, PERIODS, KEEP, CHECK = 100, 600, 20, 3


def khv_systems():
    design = load_design(example_dir() / "khv.toml")
    model = build_model(design)
    path = "input_speed"
    ev = Evaluator(design, model, (resolve(design, model, path),))
    rpm = np.linspace(1400, 1600, VALUES)
    return [to_system(ev.model_at([v * math.pi / 30])) for v in rpm]


def rattle_systems():
    out = []
    for fa in np.linspace(0.15, 0.25, VALUES):
        out.append(
            Model(
                [Dof("a", "x")],
                [
                    Inertia("a.x", 1.0),
                    Mesh({"a.x": 1.0}, 1.0, 0.1, backlash=Backlash.half(1.0)),
                    Load("a.x", Fourier(0.1, (fa,), 1.2)),
                ],
            ).nonlinear()
        )
    return out


def error(systems, res, members) -> float:
    """Largest error of one period of the kernel's motion, from each of 10 kept Poincaré
    points to the next, against the reference over the same period, relative to the
    displacement scale (a per-period error: on a chaotic attractor a longer comparison
    measures the sensitivity, not the integrator)."""
    worst = 0.0
    for e in members:
        s, T = systems[e], res.period[e]
        P = res.poincare[e]
        d = state_bounds([s], P[:1], np.array([T]))[0] / 1e6
        for j in range(10):
            ref = simulate_reference(s, np.array([T]), P[j], rtol=1e-12, atol=1e-14)[0]
            worst = max(worst, float(np.max(np.abs(P[j + 1] - ref) / d)))
    return worst


def main() -> None:
    print(f"date: {dt.date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}")  # fmt: skip
    print("| system | steps/period | time (s) | max one-period error |")
    print("|---|---|---|---|")
    for name, systems in (("KHV drive, 1400-1600 rpm", khv_systems()),
                          ("rattle oscillator, F_a 0.15-0.25", rattle_systems())):  # fmt: skip
        y0 = static_states(systems)
        members = np.linspace(0, len(systems) - 1, CHECK).astype(int)
        ensemble(systems[:2], periods=2, keep=1, y0=y0[:2], steps_per_period=32)  # compile
        prep = _prepare(systems, None, None)
        b = state_bounds(systems, y0, prep.period)
        t = time.perf_counter()
        chosen = accurate_steps(prep, systems, y0, b)
        pick = time.perf_counter() - t
        for label, steps in (("32", 32), (f"default ({chosen})", None)):
            t = time.perf_counter()
            res = ensemble(systems, periods=PERIODS, keep=KEEP, y0=y0, steps_per_period=steps)
            el = time.perf_counter() - t
            print(f"| {name} | {label} | {el:.2f} | {error(systems, res, members):.1e} |")
        print(f"| {name} | (choosing the step count: {pick:.2f} s of the default's time) | | |")


if __name__ == "__main__":
    main()
