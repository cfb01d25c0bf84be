"""Gear-body modal analysis: time, peak memory and accuracy (issue 14).

First ten elastic modes of the 26-tooth gear 2 (or another gear) of
``examples/nutation_double_sided.toml`` (free-free), side by side in one run, each case
in its own process (peak memory is the process's own):

* ``P2 default``: quadratic tetrahedra on the default mesh (what ``body-modal`` runs);
* ``P2 refined``: the same at ``REFINE`` times the element sizes: the reference, and the
  convergence of the default (the change of every mode must be <= 1 %);
* ``P1 refined``: linear tetrahedra on the refined mesh's corners (the plain way: more
  elements, the same solver) and its error against the reference;
* ``P2 default, scipy SuperLU``: the default case with scipy's own factorisation instead
  of MKL PARDISO (the optional ``fast`` extra).

Run: ``.venv/bin/python benchmarks/bench_body_modal.py [GEAR]`` (several minutes; gear 2
by default, 1 for the 28-tooth ring); it prints a
Markdown table for ``benchmarks/RESULTS.md``.
"""

from __future__ import annotations

import json
import multiprocessing as mp
import os
import platform
import resource
import sys
import time
from datetime import date

os.environ.setdefault("OMP_NUM_THREADS", "2")

REFINE = 0.75
GEAR = 2


def case(name: str, factor: float, order: int, gear: int, solver: str, queue: mp.Queue) -> None:
    import numpy as np

    from reducerlab.drives import load_design
    from reducerlab.examples import example_dir
    from reducerlab.fe import Material, assemble, body_modes
    from reducerlab.fe.gear_mesh import MeshSizes, mesh_gear

    d = load_design(example_dir() / "nutation_double_sided.toml")
    from reducerlab.analysis.body_modal import gear_blank

    crown, bevel = d.tooth_generation(gear)
    rim, features = gear_blank(d, gear)
    sizes = MeshSizes.default(crown.profile.module).refined(factor)
    t0 = time.perf_counter()
    mesh = mesh_gear(crown, bevel, rim=rim, features=features, sizes=sizes)
    t1 = time.perf_counter()
    if order == 2:
        skm = mesh.skfem()
    else:
        from skfem import MeshTet

        corners = np.unique(mesh.tets[:, :4])
        t = np.searchsorted(corners, mesh.tets[:, :4])
        skm = MeshTet(mesh.points[corners].T.copy(), t.T.copy())
    K, M, _ = assemble(skm, Material(206e9, 0.29, 7850.0), order=order)
    t2 = time.perf_counter()
    modes = body_modes(K, M, 10, solver=solver)
    t3 = time.perf_counter()
    queue.put(
        {
            "case": name,
            "tets": len(mesh.tets),
            "dofs": int(K.shape[0]),
            "mesh_s": t1 - t0,
            "assemble_s": t2 - t1,
            "solve_s": t3 - t2,
            "total_s": t3 - t0,
            "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3,
            "frequencies": [float(f) for f in modes.frequencies],
        }
    )


def spawned(target, *args) -> dict:
    """``target(*args, queue)`` in a fresh (spawned) process: its own peak memory and
    thread pools; returns what it put on the queue."""
    ctx = mp.get_context("spawn")
    q: mp.Queue = ctx.Queue()
    p = ctx.Process(target=target, args=(*args, q))
    p.start()
    out = q.get()
    p.join()
    return out


def run(name: str, factor: float, order: int, gear: int, solver: str = "auto") -> dict:
    return spawned(case, name, factor, order, gear, solver)


def main() -> None:
    gear = int(sys.argv[1]) if len(sys.argv) > 1 else GEAR
    rows = [run("P2 default", 1.0, 2, gear), run(f"P2 refined x{REFINE}", REFINE, 2, gear)]
    rows.append(run(f"P1 refined x{REFINE}", REFINE, 1, gear))
    rows.append(run("P2 default, scipy SuperLU", 1.0, 2, gear, "scipy"))
    ref = rows[1]["frequencies"]
    print(f"gear {gear} body modes, {platform.processor() or platform.machine()}, "
          f"{os.cpu_count()} cores, {date.today()}, python {sys.version.split()[0]}")  # fmt: skip
    print("| case | tets | DOFs | mesh (s) | assemble (s) | solve (s) | total (s) | peak MB |"
          " max error vs P2 refined |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        err = max(abs(f / g - 1) for f, g in zip(r["frequencies"], ref, strict=True))
        print(f"| {r['case']} | {r['tets']} | {r['dofs']} | {r['mesh_s']:.1f} | "
              f"{r['assemble_s']:.1f} | {r['solve_s']:.1f} | {r['total_s']:.1f} | "
              f"{r['peak_mb']:.0f} | {100 * err:.2f} % |")  # fmt: skip
    print(json.dumps(rows))


if __name__ == "__main__":
    main()
