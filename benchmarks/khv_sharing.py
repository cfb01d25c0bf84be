"""Benchmark: the KHV pair's load sharing against torque (issue 30), examples/khv.toml.

1. ``extension``: the ring's and the planet's tooth compliance of teeth -2 ... 2 two
   ways: the finite-element model of a seven-tooth sector (``internal_tooth_compliance``
   and ``spur_tooth_compliance`` with ``teeth=(-2, ..., 2)``) and the block-Toeplitz
   extension of the five-tooth model's teeth -1, 0, 1
   (``contact.compliance.extend_teeth``). Each block's difference in the Frobenius norm,
   over that of the seven-tooth model's own block of tooth 0; and the tip row's mean
   diagonal compliance (m/N).
2. ``sharing``: ``analysis.khv_sharing.load_sharing`` with the default finite-element
   settings (tooth elements 0.3 m, 6 x 9 load points) and contact cell (pilot), 24
   positions, torques on the planet 0 ... 250 N m (the design load is 50 N m; at 300 N m the
   tips passing, pair +8, would close and the analysis refuses): the
   table of ``SharingResult.table`` and the shares of each pair per position.

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/khv_sharing.py [extension|sharing]
[--quick]`` (``--quick``: tooth elements 0.35 m, 4 x 6 load points, 12 positions).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from reducerlab.contact.compliance import extend_teeth
from reducerlab.contact.internal_pair import InternalMeshPair, internal_tooth_compliance
from reducerlab.drives import load_design
from reducerlab.examples import example_dir

TORQUES = [0.0, 10.0, 25.0, 50.0, 75.0, 125.0, 175.0, 250.0]


def extension(quick: bool) -> None:
    from reducerlab.contact.spur_pair import spur_tooth_compliance

    design = load_design(example_dir() / "khv.toml")
    mp = InternalMeshPair.from_khv(design)
    m = mp.ring.module
    kw = {"tooth_size": (0.35 if quick else 0.3) * m, "grid": (4, 6) if quick else (6, 9)}
    five_seven = (
        ("ring", lambda teeth: internal_tooth_compliance(mp.ring, -1, teeth=teeth, **kw)),
        ("planet", lambda teeth: spur_tooth_compliance(mp.planet, 1, teeth=teeth, **kw)),
    )
    for name, build in five_seven:
        t0 = time.perf_counter()
        five = build((-1, 0, 1))
        t5 = time.perf_counter() - t0
        seven = build((-2, -1, 0, 1, 2))
        t7 = time.perf_counter() - t0 - t5
        print(f"\n{name}, {kw}: five-tooth sector {five.dofs} DOFs {t5:.1f} s, "
              f"seven-tooth {seven.dofs} DOFs {t7:.1f} s")  # fmt: skip
        _compare(five, seven)


def _compare(five, seven) -> None:
    """The blocks of the extension of ``five`` against those of ``seven``."""
    ext = extend_teeth(five, (-2, -1, 0, 1, 2))
    L = len(five.u_nodes) * len(five.v_nodes)
    nu = len(five.u_nodes)

    def blk(c, i, j):
        a, b = c.teeth.index(i), c.teeth.index(j)
        return c.matrix[a * L : (a + 1) * L, b * L : (b + 1) * L]

    ref = np.linalg.norm(blk(seven, 0, 0))
    print("block (i, j)   |seven|/|seven_00|   |extension - seven|/|seven_00|")
    for i, j in ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2), (-1, 1), (-2, 1), (-2, 2)):
        s = blk(seven, i, j)
        e = blk(ext, i, j)
        print(f"({i:+d}, {j:+d})        {np.linalg.norm(s) / ref:8.4f}"
              f"           {np.linalg.norm(e - s) / ref:8.4f}")  # fmt: skip

    def tip(c, i, j):
        d = np.diag(blk(c, i, j)).reshape(nu, -1)
        return float(d[-1].mean())

    print("tip row, mean diagonal (m/N): tooth 0 own / tooth +2 own / tooth 0 under +1 / +2")
    for name, c in (("seven-tooth FE", seven), ("extension", ext)):
        print(f"  {name:15s} {tip(c, 0, 0):.4e} {tip(c, 2, 2):.4e} {tip(c, 0, 1):.4e} "
              f"{tip(c, 0, 2):.4e}")  # fmt: skip


def sharing(quick: bool) -> None:
    from reducerlab.analysis.khv_sharing import load_sharing

    design = load_design(example_dir() / "khv.toml")
    t0 = time.perf_counter()
    res = load_sharing(
        design, torques=TORQUES, positions=12 if quick else 24,
        tooth_size=3.5e-3 * (0.35 if quick else 0.3), stage=print,
    )  # fmt: skip
    print(f"{time.perf_counter() - t0:.1f} s; cell {res.data.attrs['cell_m'] * 1e3:.3g} mm; "
          f"FE {res.data.attrs['fe_dofs']} DOFs")  # fmt: skip
    print(res.table())
    ds = res.data
    b = float(ds.attrs["face_width_m"])
    for i, t in enumerate(res.torques):
        if t <= 0:
            continue
        print(f"\n{t:g} N m: position, pairs, k (N/(mm um)), TE (um), shares {res.pairs}")
        for j in range(ds.sizes["position"]):
            sh = " ".join(f"{v:6.3f}" for v in ds["share"].values[i, j])
            print(f"  {j:2d}  {int(ds['pairs'].values[i, j])}  "
                  f"{ds['stiffness'].values[i, j] * 1e-9 / b:6.2f}  "
                  f"{ds['te'].values[i, j] * 1e6:7.3f}  {sh}")  # fmt: skip


if __name__ == "__main__":
    args = sys.argv[1:]
    quick = "--quick" in args
    parts = [a for a in args if not a.startswith("--")] or ["extension", "sharing"]
    for part in parts:
        {"extension": extension, "sharing": sharing}[part](quick)
