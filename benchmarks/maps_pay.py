"""Maps tried only where they can pay (issue 28): ``ensemble(method="auto")`` on the KHV
drive, whose teeth separate in the first period at every value, against
``method="rk4"``, side by side in one run, with and without the first-period check
(:func:`reducerlab.dynamics.maps.separate_at_once`; "without" replaces it by one that
says no member separates: the behaviour before the check).

The KHV example over ``gears.x1`` (paper 004 Fig. 7 setting, as
``benchmarks/bifurcation.py``), N values x 600 mesh periods, best of 5 each, and the
single-sided nutation drive (one mesh line: the maps apply where its teeth stay in
contact) for the check's cost.

Run: ``.venv/bin/python benchmarks/maps_pay.py [N_VALUES]``.
"""

from __future__ import annotations

import datetime as dt
import os
import platform
import sys
import time

import numpy as np

import reducerlab.dynamics.maps as maps_module
from reducerlab.dynamics.ensemble import ensemble

sys.path.insert(0, os.path.dirname(__file__))
from bifurcation import systems_for

PERIODS, KEEP = 600, 100
KW = {"periods": PERIODS, "keep": KEEP}


def best(fn, repeat: int = 5) -> tuple[float, object]:
    out, t_best = None, np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        t_best = min(t_best, time.perf_counter() - t)
    return t_best, out


def main() -> None:
    n_values = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    print(f"date: {dt.date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}")  # fmt: skip
    real = maps_module.separate_at_once
    cases = [
        ("KHV, gears.x1", "khv.toml", "gears.x1", np.linspace(0.416, 0.835, n_values)),
        ("single-sided nutation drive, mesh1.damping", "nutation_surface.toml", "mesh1.damping",
         np.linspace(1500.0, 2500.0, max(8, n_values // 25))),
    ]  # fmt: skip
    print("| case | values x periods | rk4 (s) | auto, no check (s) | auto (s) | mapped |")
    print("|---|---|---|---|---|---|")
    for label, file, path, values in cases:
        systems = systems_for(file, path, values)
        ensemble(systems[:2], method="auto", **KW)  # compile
        t_rk4, _ = best(lambda s=systems: ensemble(s, method="rk4", **KW))
        maps_module.separate_at_once = lambda prep, Y0, *a: np.zeros(len(Y0), bool)
        try:
            t_old, _ = best(lambda s=systems: ensemble(s, method="auto", **KW))
        finally:
            maps_module.separate_at_once = real
        t_new, res = best(lambda s=systems: ensemble(s, method="auto", **KW))
        print(f"| {label} | {len(values)} x {PERIODS} | {t_rk4:.2f} | {t_old:.2f} "
              f"({t_old / t_rk4:.2f}x rk4) | {t_new:.2f} ({t_new / t_rk4:.2f}x rk4) | "
              f"{int(res.mapped.sum())} of {len(values)} |")  # fmt: skip


def map_cost(n_values: int) -> None:
    """Seconds per trajectory-step of building the one-period maps (``2n + 1``
    trajectories of one period per member, with every step's state kept) against the
    plain kernel's per member-step over one period, same members, same steps."""
    from reducerlab.dynamics.coordinates import static_states
    from reducerlab.dynamics.kernel import block_width, rk4_ensemble
    from reducerlab.dynamics.prepare import prepare

    systems = systems_for(
        "nutation_surface.toml", "mesh1.damping", np.linspace(1500.0, 2500.0, n_values)
    )
    prep = prepare(systems, None, None)
    sides = maps_module.contact_sides(prep.arrays, static_states(systems))
    E, N = prep.offs.shape
    n2 = 2 * prep.arrays.G.shape[2]
    Y0 = static_states(systems)
    limit = np.full((E, n2), np.inf)

    def plain():
        return rk4_ensemble(
            *prep.arrays, Y0, np.zeros(E), prep.period, prep.offs, prep.dts, prep.periodic,
            20, 1, 0, limit, block_width(E), -1, 0.0,
        )  # fmt: skip

    maps_module.affine_maps(prep, sides)  # compile
    plain()
    t_map, _ = best(lambda: maps_module.affine_maps(prep, sides))
    t_plain, _ = best(plain)
    per_map = t_map / (E * (n2 + 1) * N)
    per_plain = t_plain / (E * 20 * N)
    print(f"map building ({E} members, {n2 + 1} trajectories x {N} steps): "
          f"{1e6 * per_map:.2f} us per trajectory-step; plain kernel (20 periods): "
          f"{1e6 * per_plain:.2f} us per member-step ({per_map / per_plain:.2f}x)")  # fmt: skip


if __name__ == "__main__":
    map_cost(16)
    main()
