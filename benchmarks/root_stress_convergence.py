"""Benchmark: convergence of the FE tooth-root stress of the bevel tooth models and the
KHV ring (docs/contact.md, "Tooth-root stress").

Bevel: pair 1 of ``examples/nutation_surface.toml``, each gear's tooth model built with
``root_stress=True`` at the tooth element sizes and root-band sizes of ``BEVEL_RUNS``
(``fe_tooth_compliance(fillet_size=...)``, ``fe.gear_mesh.FILLET_BAND``; the "wide"
band of docs/contact.md's table was ``FILLET_BAND = (0.25, 0.65)``,
``FILLET_GRADING = 0.5``, set by hand); a line load of
1 kN across the face at ``u = 0.8`` of tooth 0 (``line_load_root_stress``): the tensile
root stress (largest principal, loaded fillet, face-end zones excluded), the face-end
value apart, the compressive side, and the mean of the 1 mm face slices' fillet maxima
over the middle half of the face (robust to which node sits nearest the peak).
Ring: ``tests/published/test_iso6336_internal_root_stress.py``'s ring at 0.3, 0.25 and
0.2 m against ISO 6336-3 method B.

Corner: the joint of flank and space bottom of both gears of the same pair, from the
generated sections (the internal gear's root fillet: docs/contact.md; a corner before issue 29).

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/root_stress_convergence.py
[bevel|external|internal|ring|corner]`` (``external``/``internal``: one gear's bevel runs)
(the finest runs need 4-7 GB; set ``REDUCERLAB_MEMORY_LIMIT`` above the conservative
estimate, e.g. 20G, where the machine has the memory).
"""

from __future__ import annotations

import itertools
import math
import resource
import sys
import time

import numpy as np

from reducerlab.contact.rootstress import bump_amplitudes, line_load_root_stress
from reducerlab.fe.stress import principal_stresses

#: (gear "a" external / "b" internal, tooth size, root-band size), in m_n; a band size
#: equal to the tooth size: no band (the plain model); 0.3 / 0.2: the default
BEVEL_RUNS = (
    ("a", 0.4, 0.4), ("a", 0.3, 0.3), ("a", 0.25, 0.25), ("a", 0.3, 0.2), ("a", 0.3, 0.15),
    ("b", 0.3, 0.3), ("b", 0.25, 0.25), ("b", 0.3, 0.2), ("b", 0.3, 0.15),
)  # fmt: skip
RING_SIZES = (0.3, 0.25, 0.2)


def slice_mean(c, u: float, force: float, width: float = 1e-3) -> float:
    """Mean over the middle half of the face of the loaded fillet's largest principal
    stress in face slices of ``width`` (Pa), tooth 0 under a line load at ``u``."""
    inf = c.fillet
    v = (np.arange(81) + 0.5) / 81
    a = bump_amplitudes(c, np.zeros(81, int), np.full(81, u), v, np.full(81, force / 81))
    s = principal_stresses(inf.stress(a))[:, 2]
    m = (inf.tooth == 0) & (inf.side == 1)
    z, s = inf.face[m], s[m]
    half = 0.5 * (z.max() - z.min())
    edges = np.arange(-0.5 * half, 0.5 * half + 1e-12, width)
    return float(np.mean([s[(z >= lo) & (z < hi)].max() for lo, hi in itertools.pairwise(edges)]))


def bevel(gears: str = "ab") -> None:
    from reducerlab.analysis.contact import contact_pair
    from reducerlab.contact.compliance import fe_tooth_compliance
    from reducerlab.drives import load_design
    from reducerlab.examples import example_dir

    mp = contact_pair(load_design(example_dir() / "nutation_surface.toml"), 1)
    print("gear teeth band | DOFs | tensile end-zone compressive MPa | slice mean | s")
    for which, ts, fs in BEVEL_RUNS:
        if which not in gears:
            continue
        flank = mp.flank_a if which == "a" else mp.flank_b
        m = flank.crown.profile.module
        t = time.time()
        c = fe_tooth_compliance(flank, tooth_size=ts * m, root_stress=True,
                                fillet_size=fs * m)  # fmt: skip
        dt = time.time() - t
        r = line_load_root_stress(c, 0, 0.8, 1000.0)
        i = r.teeth.index(0)
        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6
        print(f"{which} {ts} {fs} | {c.dofs} | {r.tensile[i] / 1e6:.2f} "
              f"{r.end_tensile[i] / 1e6:.2f} {r.compressive[i] / 1e6:.2f} | "
              f"{slice_mean(c, 0.8, 1000.0) / 1e6:.2f} | {dt:.0f} (face "
              f"{r.tensile_face[i] * 1e3:+.2f} mm, tangent {math.degrees(r.tensile_angle[i]):.1f}"
              f" deg, peak RSS {rss:.2f} GB)", flush=True)  # fmt: skip


def root_corner() -> None:
    """The joint of flank B and the space bottom in a mid-face transverse section of
    each gear of pair 1 (``geometry.solid.build_gear_solid``, the sections the FE solid
    is lofted through): how far the section's tangent turns from the last flank segment
    to the first bottom segment (deg; a generated fillet turns by a few degrees per
    segment, a corner by the whole angle between flank and bottom at once), and the
    heights (m_n) of the flank's end and the nominal root cone."""
    from reducerlab.analysis.contact import contact_pair
    from reducerlab.drives import load_design
    from reducerlab.examples import example_dir
    from reducerlab.geometry.solid import build_gear_solid, cone_coordinates

    mp = contact_pair(load_design(example_dir() / "nutation_surface.toml"), 1)
    for flank in (mp.flank_a, mp.flank_b):
        gear, m = flank.gear, flank.crown.profile.module
        solid = build_gear_solid(flank.crown, gear, n_profile=21, n_face=7, n_land=2, n_space=9)
        L, h, psi = cone_coordinates(solid.loop[3], gear.cone_angle)
        y = psi * float(np.mean(L)) * math.sin(gear.cone_angle)  # arc length, m
        k = np.arange(len(h))[solid.parts["B"]][-1]  # flank B's end at the space
        t0 = np.array([y[k] - y[k - 1], h[k] - h[k - 1]])
        t1 = np.array([y[k + 1] - y[k], h[k + 1] - h[k]])
        turn = math.degrees(math.atan2(t0[0] * t1[1] - t0[1] * t1[0], t0 @ t1))
        print(f"{gear.kind} (z = {gear.teeth}): tangent turns by {abs(turn):.1f} deg at the "
              f"flank/space joint; flank end at h = {h[k] / m:+.3f} m_n, root cone "
              f"{solid.blank.root / m:+.3f} m_n")  # fmt: skip


def ring() -> None:
    sys.path.insert(0, "tests/published")
    import test_iso6336_internal_root_stress as t

    from reducerlab.contact.internal_pair import internal_tooth_compliance
    from reducerlab.rating.iso6336_3 import root_stress_nominal

    xi, _ = t._outer_single_contact()
    g = t.RING
    u = (xi - g.form_roll) / (g.tip_roll - g.form_roll)
    force = t.W * t.B / math.cos(g.pressure_angle)
    iso = root_stress_nominal(t.W * t.B, t.B, t.M, t._iso())
    print(f"ISO sigma_F0 {iso / 1e6:.2f} MPa")
    for ts in RING_SIZES:
        tic = time.time()
        c = internal_tooth_compliance(g, -1, tooth_size=ts * t.M, root_stress=True)
        r = line_load_root_stress(c, 0, u, force)
        i = r.teeth.index(0)
        print(f"{ts} m | {c.dofs} DOFs | {r.tensile[i] / 1e6:.2f} MPa (FE/ISO "
              f"{r.tensile[i] / iso:.3f}) | slice mean {slice_mean(c, u, force) / 1e6:.2f} | "
              f"{r.compressive[i] / 1e6:.2f} | {time.time() - tic:.0f} s", flush=True)  # fmt: skip


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "bevel"
    {
        "bevel": bevel,
        "external": lambda: bevel("a"),
        "internal": lambda: bevel("b"),
        "ring": ring,
        "corner": root_corner,
    }[what]()
