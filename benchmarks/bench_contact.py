"""Loaded tooth contact analysis: one mesh cycle of one pair (issue 15).

Pair 1 of ``examples/nutation_surface.toml`` (involute, 3 kW at 1500 rpm on the external
gear). The finite-element tooth compliance of both gears is built once (its time is
stated separately), then, side by side in one run:

* ``reducerlab``: what ``reducerlab contact`` runs after the compliance: the pilot
  position that sizes the grid, then ``POSITIONS`` positions (20, the issue's cycle,
  and 24, the CLI default) with the automatic grid, candidate cells from the coarse
  separation, the compliance columns of the loaded cells only, made by compiled
  kernels (``contact.cellmatrix``), primal-dual active set warm started from the
  previous position;
* ``plain``: the way it is written first, in numpy: every fine cell of every tooth
  pair within a fixed 10 um separation in the problem at every position, the
  whole compliance matrix: the half-space part from ``rectangle_influence`` on full
  (n, n) arrays, the bending part as the dense product ``W K W^T``, a cold start from
  the first point to touch and the monotone active-set method (Lawson-Hanson) for
  every position; run on ``PLAIN`` of the positions (it is slow) and compared per
  position.

Both reach the same KKT point: the script checks that the loaded transmission error
and the contact area agree. Run: ``.venv/bin/python benchmarks/bench_contact.py``;
prints a Markdown table for ``benchmarks/RESULTS.md``.
"""

from __future__ import annotations

import math
import os
import platform
import time
from datetime import date

os.environ.setdefault("OMP_NUM_THREADS", "2")

POSITIONS = (20, 24)
PLAIN = 2


def _numpy_influence(points, axes_u, axes_v, half_u, half_v, E_star, same_body=None):
    """``contact.halfspace.influence_matrix`` written with numpy arrays of all pairs."""
    import numpy as np

    from reducerlab.contact.halfspace import rectangle_influence

    P = np.asarray(points)
    W = np.cross(axes_u, axes_v)
    d = P[:, None, :] - P[None, :, :]
    dx = np.einsum("ijk,jk->ij", d, axes_u)
    dy = np.einsum("ijk,jk->ij", d, axes_v)
    dz = np.einsum("ijk,jk->ij", d, W)
    r2 = dx**2 + dy**2
    with np.errstate(divide="ignore", invalid="ignore"):
        stretch = np.where(r2 > 0, np.sqrt(1 + dz**2 / r2), 1.0)
    dx, dy = dx * stretch, dy * stretch
    dx = np.where((r2 == 0) & (dz != 0), np.abs(dz), dx)
    C = rectangle_influence(dx, dy, half_u[None, :], half_v[None, :])
    C /= (math.pi * E_star * 4 * half_u * half_v)[None, :]
    if same_body is not None:
        C[same_body[:, None] != same_body[None, :]] = 0.0
    return 0.5 * (C + C.T)


def _plain_compliance(points, axes_u, axes_v, half_u, half_v, E_star, body, bending=()):
    """The whole cell compliance matrix at once, in numpy: the half-space part on
    arrays of all pairs plus the dense products ``W K W^T``."""
    import numpy as np

    C = _numpy_influence(points, axes_u, axes_v, half_u, half_v, E_star, body)
    for comp, tooth, u, v in bending:
        cols, w = comp.stencil(tooth, u, v)
        Wd = np.zeros((len(cols), comp.matrix.shape[0]))
        np.add.at(Wd, (np.arange(len(cols))[:, None], cols), w)
        C += Wd @ comp.matrix @ Wd.T
    return C


def main() -> None:
    import numpy as np

    import reducerlab.contact.cellmatrix as cm
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
    pitch = 2 * math.pi / pair.external.teeth
    kw = {"compliance_a": ca, "compliance_b": cb, "E_star": E}
    # warm the compiled kernels (their one-off compilation is cached on disk)
    loaded_contact(pair, torque, [0.0], ContactGrid(PILOT * m_n), **kw)
    rows = []
    for n in POSITIONS:
        phis = pitch * np.arange(n) / n
        t0 = time.perf_counter()
        pilot = loaded_contact(pair, torque, phis[:1], ContactGrid(PILOT * m_n), **kw)
        cell = auto_cell(pilot[0], m_n)
        runs = loaded_contact(pair, torque, phis, ContactGrid(cell), **kw)
        rows.append((n, time.perf_counter() - t0, runs))
    # the plain way on the first PLAIN positions of the 24
    phis = pitch * np.arange(POSITIONS[-1]) / POSITIONS[-1]
    saved = (cp.PDAS_STEPS, cp._winkler_set, cm.CellCompliance)
    cp.PDAS_STEPS = 0
    cp._winkler_set = lambda d, g, lam, load, usable: np.array(  # first point to touch
        [int(np.argmin(np.where(usable, g / np.where(usable, lam, 1.0), np.inf)))]
    )
    cm.CellCompliance = _plain_compliance
    t0 = time.perf_counter()
    plain = [
        loaded_contact(pair, torque, [phi], ContactGrid(cell, s_max=1e-5), **kw)[0]
        for phi in phis[:PLAIN]
    ]
    plain_t = time.perf_counter() - t0
    cp.PDAS_STEPS, cp._winkler_set, cm.CellCompliance = saved
    ours24 = rows[-1][2]
    for a, b in zip(ours24[:PLAIN], plain, strict=True):
        assert abs(a.loaded_te / b.loaded_te - 1) < 1e-6, (a.loaded_te, b.loaded_te)
        assert abs(a.contact_area / b.contact_area - 1) < 1e-6
    per_plain = plain_t / PLAIN
    cells_plain = np.mean([len(r.force) for r in plain])
    threads = os.environ["OMP_NUM_THREADS"]
    print(f"date: {date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, OMP_NUM_THREADS={threads}")  # fmt: skip
    print(f"FE tooth compliance of both gears (built once): {build:.1f} s "
          f"({ca.dofs} + {cb.dofs} DOFs, {ca.matrix.shape[0]} loads each)")  # fmt: skip
    print(f"contact cell {cell * 1e3:.4f} mm")
    print("| case       | positions | cells/position | s/position | cycle (s) |")
    for n, t, runs in rows:
        cells = np.mean([len(r.force) for r in runs])
        print(f"| reducerlab | {n:>9} | {cells:>14.0f} | {t / n:>10.2f} | {t:>9.1f} |")
    print(f"| plain      | {PLAIN:>9} | {cells_plain:>14.0f} | {per_plain:>10.2f} | "
          f"{per_plain * POSITIONS[-1]:>9.1f} |")  # fmt: skip
    per_ours = rows[-1][1] / POSITIONS[-1]
    print(f"ratio per position (24-position cycle): {per_plain / per_ours:.1f}x")


if __name__ == "__main__":
    main()
