"""Grid study of the double circular-arc contact (issue 29, docs/contact.md).

    python benchmarks/dblarc_grid.py [POWER_W] [FACTORS...]

Pair 1 of examples/nutation_surface.toml with the double-arc profile, 3 kW by default,
3 mesh positions: the automatic cell, then the given multiples of it (default 0.75 0.6
0.5), one finite-element compliance build reused by all. Per grid and position: mesh
stiffness, unloaded TE, interior and overall peak pressure, edge share (flank edges and
the profile corner), contact area from the pressure field and from whole cells; and
where the interior peak sits: its profile parameter, its distance (mm, along the
profile) to the transition/convex curvature jump, and the loaded cells across its patch
along the profile. About 10 minutes on 2 cores.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from reducerlab.analysis.contact import contact_analysis, contact_pair
from reducerlab.contact.ltca import _arc
from reducerlab.drives import load_design
from reducerlab.examples import example_dir


def where_peak(ds, mp) -> list[str]:
    """Location of each position's interior peak and the loaded cells across its patch
    along the profile (the cells on its face line ``v``)."""
    A = mp.flank_a
    pu, arc_u = _arc(A, True, 0.5)
    s_curv = float(np.interp(mp.crown.profile.breaks[-1], pu, arc_u))
    out = []
    pos, p, edge = ds["cell_position"].values, ds["pressure"].values, ds["edge"].values
    u, v, tooth = ds["u"].values, ds["v"].values, ds["cell_tooth"].values
    for j in np.unique(pos):
        m = (pos == j) & ~edge.astype(bool) & (p > 0)
        if not m.any():
            out.append("no interior cell")
            continue
        i = np.flatnonzero(m)[np.argmax(p[m])]
        line = (pos == j) & (tooth == tooth[i]) & (v == v[i]) & (p > 0)
        d = (float(np.interp(u[i], pu, arc_u)) - s_curv) * 1e3
        out.append(f"u {u[i]:.4f} v {v[i]:.3f} tooth {tooth[i]}: {d:+.3f} mm from the "
                   f"curvature jump, {int(line.sum())} loaded cells across")  # fmt: skip
    return out


def main(power: float, factors: list[float]) -> None:
    design = load_design(example_dir() / "nutation_surface.toml")
    mp = contact_pair(design, 1, profile="double-arc")
    kw = {"power": power, "positions": 3, "order": 1, "profile": "double-arc", "workers": 1}
    t0 = time.perf_counter()
    base = contact_analysis(design, 1, **kw)
    h = float(base.data.attrs["cell_m"])
    runs = [(1.0, base, time.perf_counter() - t0)]
    for f in factors:
        t0 = time.perf_counter()
        r = contact_analysis(design, 1, cell=f * h, compliance=base.compliance, **kw)
        runs.append((f, r, time.perf_counter() - t0))
    for f, r, sec in runs:
        d = r.data
        print(f"cell {f:.2f} x = {f * h * 1e3:.4f} mm ({sec:.0f} s)")
        print("  k (N/m)           ", np.array2string(d["stiffness"].values, precision=4))
        print("  unloaded TE (urad)", np.array2string(1e6 * d["unloaded_te"].values, precision=3))
        mpa = 1e-6
        print("  interior p (MPa)  ", np.array2string(mpa * d["interior_pressure"].values))
        print("  peak p (MPa)      ", np.array2string(mpa * d["peak_pressure"].values))
        print("  edge share        ", np.array2string(d["edge_share"].values, precision=3))
        print("  area field (mm2)  ", np.array2string(1e6 * d["contact_area"].values))
        for j, text in enumerate(where_peak(d, mp)):
            print(f"  peak {j}: {text}")
        sys.stdout.flush()


if __name__ == "__main__":
    args = [float(a) for a in sys.argv[1:]]
    main(args[0] if args else 3000.0, args[1:] or [0.75, 0.6, 0.5])
