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


def map_cost(n_values: int, repeat: int = 7) -> None:
    """Seconds per trajectory-step of building the one-period maps (``2n + 1``
    trajectories of one period per member, with every step's state kept) against the
    plain kernel's per member-step over 20 periods, same members, same steps; the two
    timed alternately, best of ``repeat`` each. Also the kernel alone on the maps' own
    trajectories (the contact system) over 20 periods without history: what one period
    with every step kept costs more per step."""
    from reducerlab.dynamics.coordinates import static_states
    from reducerlab.dynamics.kernel import block_width, rk4_ensemble
    from reducerlab.dynamics.prepare import prepare, subset

    systems = systems_for(
        "nutation_surface.toml", "mesh1.damping", np.linspace(1500.0, 2500.0, n_values)
    )
    prep = prepare(systems, None, None)
    sides = maps_module.contact_sides(prep.arrays, static_states(systems))
    E, N = prep.offs.shape
    n2 = 2 * prep.arrays.G.shape[2]
    C = n2 + 1
    Y0 = static_states(systems)
    limit = np.full((E, n2), np.inf)

    def plain():
        return rk4_ensemble(
            *prep.arrays, Y0, np.zeros(E), prep.period, prep.offs, prep.dts, prep.periodic,
            20, 1, 0, limit, block_width(E), -1, 0.0,
        )  # fmt: skip

    contact = maps_module.contact_arrays(prep.arrays, sides)
    reps = tuple(a if a.ndim == 1 else np.repeat(a, C, axis=0) for a in contact)
    Yc = np.zeros((E, C, n2))
    Yc[:, 1:, :] = np.eye(n2)
    # the code before issue 28's map work has no trajectory_width (for comparisons)
    width = getattr(maps_module, "trajectory_width", block_width)(E * C)

    def trajectories():
        return rk4_ensemble(
            *reps, Yc.reshape(E * C, n2), np.zeros(E * C), np.repeat(prep.period, C),
            np.repeat(prep.offs, C, axis=0), np.repeat(prep.dts, C, axis=0), prep.periodic,
            20, 1, 0, np.full((E * C, n2), np.inf), width, -1, 0.0,
        )  # fmt: skip

    # members built at once by map_members (8 in the code before issue 28's map work)
    size = min(E, getattr(maps_module, "map_block", lambda p: maps_module.MAP_BLOCK)(prep))

    def in_blocks():  # as map_members builds them
        for lo in range(0, E, size):
            idx = np.arange(lo, min(E, lo + size))
            maps_module.affine_maps(subset(prep, idx), sides[idx])

    maps_module.affine_maps(prep, sides)  # compile
    plain()
    trajectories()
    t_map = t_plain = t_traj = t_blocks = np.inf
    for _ in range(repeat):
        t_map = min(t_map, best(lambda: maps_module.affine_maps(prep, sides), 1)[0])
        t_plain = min(t_plain, best(plain, 1)[0])
        t_traj = min(t_traj, best(trajectories, 1)[0])
        t_blocks = min(t_blocks, best(in_blocks, 1)[0])
    per_map = t_map / (E * C * N)
    per_plain = t_plain / (E * 20 * N)
    per_traj = t_traj / (E * C * 20 * N)
    per_blocks = t_blocks / (E * C * N)
    print(f"map building ({E} members, {C} trajectories x {N} steps): "
          f"{1e6 * per_map:.2f} us per trajectory-step; plain kernel (20 periods): "
          f"{1e6 * per_plain:.2f} us per member-step ({per_map / per_plain:.2f}x); "
          f"the maps' trajectories over 20 periods, no history: {1e6 * per_traj:.2f} us "
          f"per trajectory-step; built {size} members at a time (as "
          f"map_members): {1e6 * per_blocks:.2f} us per trajectory-step "
          f"({per_blocks / per_plain:.2f}x); load average {os.getloadavg()[0]:.2f}")  # fmt: skip


if __name__ == "__main__":
    map_cost(16)
    main()
