"""Benchmark: the KHV internal pair (examples/khv.toml, z 30/33) in the loaded tooth
contact analysis over one mesh cycle (issues 29/30).

For the FE settings of ``tests/test_internal_ltca.py`` (tooth elements 0.35 m, 4 x 6 load
points) and the defaults (0.3 m, 6 x 9): the tooth compliances of planet (rim 10 m, bore
held) and ring (rim 3.5 m, outer surface held), then ``POSITIONS`` mesh positions over
one base pitch of tooth pair 0 (from the start of the path of contact) at 100 and
300 N/mm: the tooth pairs that carry load and the mesh stiffness
``k = T_B / (r_b2^2 psi) / b`` (N/(mm um)) at each; the single-pair stiffness at the
middle of the single-pair zone with only tooth pair 0 examined; the ISO 6336-1 values
(c' with z_n2 = inf and paper 004's Eq. 8 reading, c_gamma_alpha = c' (0.75 eps + 0.25)).
Run: ``PYTHONPATH=src .venv/bin/python benchmarks/internal_ltca.py [--quick]``.
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from reducerlab.contact.halfspace import combined_modulus
from reducerlab.contact.internal_pair import InternalMeshPair
from reducerlab.contact.iso6336 import ISO_STIFFNESS_TO_SI, basic_rack_factor, iso6336_q
from reducerlab.contact.ltca import ContactGrid, loaded_contact
from reducerlab.drives import load_design
from reducerlab.examples import example_dir
from reducerlab.fe.elasticity import STEEL

POSITIONS = 12
CELL = 0.2e-3


def main(quick: bool) -> None:
    design = load_design(example_dir() / "khv.toml")
    mp = InternalMeshPair.from_khv(design)
    m, b = mp.planet.module, mp.planet.face_width
    g = design.gears
    c_b = 0.5 * (basic_rack_factor(mp.planet.dedendum, mp.planet.pressure_angle)
                 + basic_rack_factor(mp.ring.dedendum, mp.ring.pressure_angle))  # fmt: skip
    c_rack = c_b / iso6336_q(g.planet_teeth, math.inf, g.x1, g.shift2)
    c_paper = c_b / iso6336_q(g.planet_teeth, g.ring_teeth, g.x1, g.shift2, internal=True)
    eps = mp.contact_ratio
    print(f"eps_alpha {eps:.4f}; ISO c' (z_n2 = inf) {c_rack:.3f}, (paper 004 Eq. 8) "
          f"{c_paper:.3f}; c_gamma_alpha {c_rack * (0.75 * eps + 0.25):.3f} / "
          f"{c_paper * (0.75 * eps + 0.25):.3f} N/(mm um)")  # fmt: skip
    E_star = combined_modulus(STEEL.E, STEEL.nu, STEEL.E, STEEL.nu)
    s_a, s_e = mp.path_of_contact
    pb = mp.base_pitch
    mid = 0.5 * (s_e + s_a)
    settings = [(0.35, (4, 6))] if quick else [(0.35, (4, 6)), (0.3, (6, 9))]
    for tooth, grid in settings:
        t0 = time.perf_counter()
        ca, cb = mp.tooth_compliances(planet_rim=10 * m, tooth_size=tooth * m, grid=grid)
        print(f"\nFE tooth {tooth} m, grid {grid}: {time.perf_counter() - t0:.1f} s "
              f"({ca.dofs} + {cb.dofs} DOFs)")  # fmt: skip
        for w in (100e3, 300e3):
            torque = w * b * mp.working_pitch_radii[0]
            one = loaded_contact(mp, torque, [mp.position_of(mid)], ContactGrid(CELL, teeth=(0,)),
                                 compliance_a=ca, compliance_b=cb, E_star=E_star)[0]  # fmt: skip
            k1 = one.torque / (mp.ring.base_radius**2 * one.loaded_te) / b / ISO_STIFFNESS_TO_SI
            rolls = s_a + pb * (np.arange(POSITIONS) + 0.5) / POSITIONS
            t0 = time.perf_counter()
            run = loaded_contact(mp, torque, [mp.position_of(r) for r in rolls],
                                 ContactGrid(CELL), compliance_a=ca, compliance_b=cb,
                                 E_star=E_star)  # fmt: skip
            dt = time.perf_counter() - t0
            ks = [p.torque / (mp.ring.base_radius**2 * p.loaded_te) / b / ISO_STIFFNESS_TO_SI
                  for p in run]  # fmt: skip
            print(f"  {w / 1e3:.0f} N/mm: single pair alone at the zone's middle "
                  f"{k1:.3f} (ISO z_n2 = inf {100 * (k1 / c_rack - 1):+.1f} %, paper "
                  f"{100 * (k1 / c_paper - 1):+.1f} %); cycle {dt:.1f} s")  # fmt: skip
            for r, p, k in zip(rolls, run, ks, strict=True):
                pairs = sorted(np.unique(p.tooth[p.force > 0]).tolist())
                print(f"    roll {r * 1e3:6.2f} mm  pairs {pairs}  k {k:7.3f}")
            print(
                f"    mean {np.mean(ks):.3f} N/(mm um) (ISO c_gamma_alpha z_n2 = inf "
                f"{100 * (np.mean(ks) / (c_rack * (0.75 * eps + 0.25)) - 1):+.1f} %)"
            )


if __name__ == "__main__":
    main("--quick" in sys.argv)
