"""Loaded TE against torque: a 6-load sweep against a single-load run (issue 29).

``examples/gear_pair.toml`` (spur z 25/60, m 3 mm, b 20 mm, 60 N m on the pinion), one
mesh cycle of 24 positions, side by side in one run, each in one process:

* ``single``: ``contact_analysis(design, torque=60 N m, positions=24, workers=1)``, the
  single-load run (finite-element tooth compliance of both gears, pilot position, the
  24 positions with their subsurface stresses);
* ``sweep``: ``te_sweep(design, loads=6)`` (0 to 1.5 x 60 N m): one compliance build,
  the pilot at the design load, then at each position the grid and compliance columns
  made once for 90 N m and the complementarity problem solved for the 5 loaded torques;
* the same two after the compliance (``compliance=``), and the bare
  ``loaded_contact`` of one load against ``loaded_contact(..., torques=5 loads)`` on the
  same grid: what the load sweep itself costs.

The script checks that the sweep's row at 60 N m equals the single run's loaded TE.
Run: ``.venv/bin/python benchmarks/te_sweep.py [--sweep-first]``; prints the lines for
``benchmarks/RESULTS.md``.
"""

from __future__ import annotations

import os
import platform
import sys
import time
from datetime import date
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "1")

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "gear_pair.toml"
POSITIONS = 24
LOADS = 6


def main() -> None:
    import numpy as np
    import scipy

    from reducerlab.analysis.contact import EDGE_BAND, contact_analysis
    from reducerlab.analysis.contact_setup import pair_setup
    from reducerlab.analysis.te_sweep import design_load, te_sweep
    from reducerlab.contact.ltca import ContactGrid, loaded_contact
    from reducerlab.drives import load_design

    design = load_design(EXAMPLE)
    T_d = design_load(design)

    def run_single() -> tuple:
        t = time.perf_counter()
        out = contact_analysis(design, torque=T_d, positions=POSITIONS, workers=1)
        return out, time.perf_counter() - t

    def run_sweep() -> tuple:
        t = time.perf_counter()
        out = te_sweep(design, loads=LOADS, positions=POSITIONS)
        return out, time.perf_counter() - t

    # the first of the two pays the process's warm-up (imports, compiled kernels loaded
    # from numba's cache, gmsh): --sweep-first swaps the order to bracket it
    if "--sweep-first" in sys.argv:
        (sweep, t_sweep), (single, t_single) = run_sweep(), run_single()
    else:
        (single, t_single), (sweep, t_sweep) = run_single(), run_sweep()
    comp = sweep.compliance
    h = float(sweep.attrs["cell_m"])
    assert h == single.attrs["cell_m"], "the same pilot sizes both grids"
    r_b2 = design.spur_pair().wheel.base_radius
    T = sweep.torques

    # the single run again after the compliance, at the sweep's largest torque on its
    # cell: its loaded TE is the sweep's last row
    t = time.perf_counter()
    top = contact_analysis(design, torque=float(T[-1]), positions=POSITIONS, workers=1,
                           compliance=comp, cell=h)  # fmt: skip
    t_single_c = time.perf_counter() - t
    ref = top.data["loaded_te"].values
    diff = np.max(np.abs(sweep.data["te"].values[-1] / r_b2 - ref))
    rel = diff / np.max(np.abs(ref))
    t = time.perf_counter()
    te_sweep(design, loads=LOADS, positions=POSITIONS, compliance=comp, cell=h)
    t_sweep_c = time.perf_counter() - t
    # the command's path: partial results after each eighth of the positions (each chunk
    # a new loaded_contact call, started from the last chunk's grid)
    t = time.perf_counter()
    te_sweep(design, loads=LOADS, positions=POSITIONS, compliance=comp, cell=h,
             partial=lambda _r: None)  # fmt: skip
    t_sweep_p = time.perf_counter() - t

    setup = pair_setup(design)
    kw = {"compliance_a": comp[0], "compliance_b": comp[1], "E_star": setup.E_star}
    phis = setup.start + setup.pitch * np.arange(POSITIONS) / POSITIONS
    grid = ContactGrid(h, edge_band=EDGE_BAND * setup.module)
    t = time.perf_counter()
    loaded_contact(setup.mesh_pair, float(T[-1]), phis, grid, **kw)
    t_lc1 = time.perf_counter() - t
    t = time.perf_counter()
    loaded_contact(setup.mesh_pair, float(T[-1]), phis, grid, **kw, torques=T[T > 0])
    t_lcn = time.perf_counter() - t

    order = "sweep first" if "--sweep-first" in sys.argv else "single first"
    print(f"date: {date.today().isoformat()}; {order}")
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python "
          f"{platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}; "
          f"load average {os.getloadavg()[0]:.2f} at the end")  # fmt: skip
    print(f"design: {EXAMPLE.name}, {POSITIONS} positions, {LOADS} loads 0..{T[-1]:.4g} N m, "
          f"cell {h * 1e3:.3g} mm, FE {sweep.attrs['fe_dofs']} DOFs (both gears)")  # fmt: skip
    print(f"single-load contact_analysis (FE + pilot + positions): {t_single:.1f} s")
    print(
        f"6-load te_sweep (FE + pilot + positions):           {t_sweep:.1f} s  "
        f"(x{t_sweep / t_single:.2f}; its FE {sweep.attrs['fe_seconds']:.1f} s)"
    )
    print(
        f"after the compliance: single (at {T[-1]:.4g} N m) {t_single_c:.1f} s, sweep "
        f"{t_sweep_c:.1f} s (x{t_sweep_c / t_single_c:.2f}), sweep with partial results "
        f"(the command's chunks) {t_sweep_p:.1f} s"
    )
    print(
        f"loaded_contact alone, same grid: 1 load {t_lc1:.1f} s, {int((T > 0).sum())} loads "
        f"{t_lcn:.1f} s (x{t_lcn / t_lc1:.2f})"
    )
    print(f"sweep row at {T[-1]:.4g} N m vs single run: max |dpsi| {diff:.2e} rad ({rel:.1e} rel)")


if __name__ == "__main__":
    main()
