"""Loaded tooth contact analysis: one mesh cycle of one pair (issue 15).

Pair 1 of ``examples/nutation_surface.toml`` (involute, 3 kW at 1500 rpm on the external
gear). The finite-element tooth compliance of both gears is built once (its time is
stated separately), then, side by side in one run:

* ``reducerlab``: what ``reducerlab contact`` runs: the automatic grid, candidate cells
  from the coarse separation, primal-dual active set warm-started from the previous
  position, ``POSITIONS`` positions;
* ``plain``: the way it is written first: every fine cell of every tooth pair within a
  fixed 10 um separation in the problem at every position, a cold start and the
  monotone one-point-at-a-time active set (Lawson-Hanson) for every position; run on
  ``PLAIN`` of the positions (it is slow) and compared per position.

Both reach the same KKT point: the script checks that the mesh stiffness and contact
area agree. Run: ``.venv/bin/python benchmarks/bench_contact.py``; prints a Markdown
table for ``benchmarks/RESULTS.md``.
"""

from __future__ import annotations

import math
import os
import platform
import time
from datetime import date

os.environ.setdefault("OMP_NUM_THREADS", "2")

POSITIONS = 24
PLAIN = 3


def main() -> None:
    import numpy as np

    import reducerlab.contact.complementarity as cp
    from reducerlab.analysis.contact import PILOT, auto_cell, contact_pair
    from reducerlab.contact.compliance import fe_tooth_compliance
    from reducerlab.contact.halfspace import combined_modulus
    from reducerlab.contact.ltca import ContactGrid, loaded_contact
    from reducerlab.drives import load_design
    from reducerlab.examples import example_dir

    design = load_design(example_dir() / "nutation_surface.toml")
    pair = contact_pair(design, 1)
    m_n = pair.crown.profile.module
    torque = 3000.0 / design.input_speed
    t0 = time.perf_counter()
    ca = fe_tooth_compliance(pair.flank_a)
    cb = fe_tooth_compliance(pair.flank_b)
    build = time.perf_counter() - t0
    E = combined_modulus(2.06e11, 0.3, 2.06e11, 0.3)
    phis = 2 * math.pi / pair.external.teeth * np.arange(POSITIONS) / POSITIONS
    kw = {"compliance_a": ca, "compliance_b": cb, "E_star": E}
    t0 = time.perf_counter()
    pilot = loaded_contact(pair, torque, phis[:1], ContactGrid(PILOT * m_n), **kw)
    cell = auto_cell(pilot[0], m_n)
    runs = loaded_contact(pair, torque, phis, ContactGrid(cell), **kw)
    ours = time.perf_counter() - t0
    # the plain way on the first PLAIN positions
    steps, cp.PDAS_STEPS = cp.PDAS_STEPS, 0
    t0 = time.perf_counter()
    plain = [
        loaded_contact(pair, torque, [phi], ContactGrid(cell, s_max=1e-5), **kw)[0]
        for phi in phis[:PLAIN]
    ]
    plain_t = time.perf_counter() - t0
    cp.PDAS_STEPS = steps
    for a, b in zip(runs[:PLAIN], plain, strict=True):
        assert abs(a.loaded_te / b.loaded_te - 1) < 1e-6, (a.loaded_te, b.loaded_te)
        assert abs(a.contact_area / b.contact_area - 1) < 1e-6
    per_ours = ours / POSITIONS
    per_plain = plain_t / PLAIN
    cells = np.mean([len(r.force) for r in runs])
    cells_plain = np.mean([len(r.force) for r in plain])
    threads = os.environ["OMP_NUM_THREADS"]
    print(f"date: {date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, OMP_NUM_THREADS={threads}")  # fmt: skip
    print(f"FE tooth compliance of both gears (built once): {build:.1f} s "
          f"({ca.dofs} + {cb.dofs} DOFs, {ca.matrix.shape[0]} loads each)")  # fmt: skip
    print(f"contact cell {cell * 1e3:.4f} mm")
    print("| case       | positions | cells/position | s/position | total (s) |")
    print(f"| reducerlab | {POSITIONS:>9} | {cells:>14.0f} | {per_ours:>10.2f} | {ours:>9.1f} |")
    print(f"| plain      | {PLAIN:>9} | {cells_plain:>14.0f} | {per_plain:>10.2f} | "
          f"{plain_t:>9.1f} |")  # fmt: skip
    print(f"ratio per position: {per_plain / per_ours:.1f}x")


if __name__ == "__main__":
    main()
