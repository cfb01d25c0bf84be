"""Benchmark: the cost of the load-dependent (power-law) mesh force in the compiled
kernel against today's linear law (issue 30).

The same ensembles integrated twice, side by side in one run: each mesh line linear
(``F = k(t) f``) and as a power law ``F = k(t) (d / p) (f / d)^p`` with the same
tangent stiffness at the operating deflection ``d`` (``model.elements.Mesh``):

* the KHV drive of paper 004 (``examples/khv.toml``), ``VALUES`` input speeds
  1400..1600 rpm, its mesh made Hertzian (``p = 1.5``, ``d``: the static mesh
  deflection at the design load) only to time the law (its teeth are line contacts);
* paper 003's cycloid ball drive on its ball track (``examples/cycloid_ball.toml``,
  ``cycloid_pair.stiffness_source = "contact"``: ``p = 1.5`` from the track, no
  clearance), ``VALUES`` input speeds 1400..1600 rpm, against the same model with its
  line linear.

For each: ``PERIODS`` periods at a fixed step count (the cost per step), then with the
default accuracy rule (``accuracy = 1e-6``: the step count each law needs), timed after
a warm-up run that compiles the kernel. Run:
``.venv/bin/python benchmarks/power_law_cost.py``.
"""

from __future__ import annotations

import dataclasses
import datetime as dt
import math
import os
import platform
import time

import numpy as np

from reducerlab.analysis.parameters import Evaluator, resolve
from reducerlab.drives import build_model, load_design
from reducerlab.dynamics.coordinates import static_state, to_system
from reducerlab.dynamics.ensemble import ensemble
from reducerlab.examples import example_dir
from reducerlab.model import Mesh, Model

VALUES, PERIODS, KEEP, FIXED = 64, 1500, 10, 64


def with_law(model: Model, exponent: float | None) -> Model:
    """``model`` with every mesh line linear (``exponent=None``) or a power law of
    ``exponent`` through its static deflection (the tangent kept)."""
    s = to_system(model)
    q = static_state(s)[: s.n]
    elements = []
    lines = iter(range(s.G.shape[0]))
    for e in model.elements:
        if isinstance(e, Mesh):
            m = next(lines)
            if exponent is None:
                e = dataclasses.replace(e, exponent=1.0, reference_deflection=0.0)
            else:
                d = abs(float(s.G[m] @ q)) or 1e-6
                e = dataclasses.replace(e, exponent=exponent, reference_deflection=d)
        elements.append(e)
    return Model(model.dofs, elements, speed=model.speed, name=model.name)


def systems(example: str, sets: list[str], exponent: float | None) -> list:
    design = load_design(example_dir() / example, sets)
    model = with_law(build_model(design), exponent)
    ev = Evaluator(design, model, (resolve(design, model, "input_speed"),))
    rpm = np.linspace(1400, 1600, VALUES)
    return [to_system(with_law(ev.model_at([v * math.pi / 30]), exponent)) for v in rpm]


def timed(sys_list, steps):
    t0 = time.perf_counter()
    r = ensemble(sys_list, periods=PERIODS, keep=KEEP, steps_per_period=steps, method="rk4")
    return time.perf_counter() - t0, r.steps_per_period


def main() -> None:
    cases = [
        ("KHV drive, mesh linear", "khv.toml", [], None),
        ("KHV drive, mesh p = 1.5", "khv.toml", [], 1.5),
        ("cycloid ball track, line linear", "cycloid_ball.toml",
         ['cycloid_pair.stiffness_source="contact"'], None),
        ("cycloid ball track, Hertzian line", "cycloid_ball.toml",
         ['cycloid_pair.stiffness_source="contact"'], "design"),
    ]  # fmt: skip
    print(f"date: {dt.date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}; {VALUES} members x {PERIODS} periods")  # fmt: skip
    print("| system | steps/period | time (s) | per step and member (us) |")
    print("|---|---|---|---|")
    for label, example, sets, exponent in cases:
        if exponent == "design":
            design = load_design(example_dir() / example, sets)
            model = build_model(design)
            ev = Evaluator(design, model, (resolve(design, model, "input_speed"),))
            sl = [
                to_system(ev.model_at([v * math.pi / 30])) for v in np.linspace(1400, 1600, VALUES)
            ]
        else:
            sl = systems(example, sets, exponent)
        timed(sl[:2], FIXED)  # compile
        for steps in (FIXED, None):
            t, n = timed(sl, steps)
            per = t / (VALUES * PERIODS * n) * 1e6
            name = f"{n}" if steps else f"default ({n})"
            print(f"| {label} | {name} | {t:.2f} | {per:.3f} |")


if __name__ == "__main__":
    main()
