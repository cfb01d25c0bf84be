"""Paper 000 Tables 4-5: the four gear bodies of the double-sided nutation drive.

Runs ``body_modal`` (default mesh, free-free, with the convergence run) on gears 1-4 of
``examples/nutation_double_sided.toml`` and prints Markdown tables of our frequencies
and mode types beside the paper's, for ``docs/body_modes.md``. About 10 minutes on two
cores.

    .venv/bin/python examples/paper_000_body_modes.py > table4.md
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

from reducerlab.analysis.body_modal import body_modal
from reducerlab.drives import load_design

HERE = Path(__file__).resolve().parent

#: Paper 000 Table 4: (frequency Hz, vibration mode) of the first ten modes per gear.
TABLE_4 = {
    1: [(4162.7, "torsional"), (4182.3, "torsional"), (5466.4, "folding"),
        (5468.2, "folding"), (6307, "umbrella"), (9498.1, "circumferential"),
        (12080, "bending"), (12082, "bending"), (12718, "radial"), (12750, "radial")],
    2: [(10987, "torsional"), (10988, "torsional"), (11184, "circumferential"),
        (12006, "folding"), (16625, "folding"), (16626, "bending"), (19579, "bending"),
        (24417, "circumferential"), (24451, "bending"), (28769, "bending")],
    3: [(3894.6, "torsional"), (3917.1, "torsional"), (4956.9, "folding"),
        (4957.3, "folding"), (5298.1, "umbrella"), (8777.3, "circumferential"),
        (10547, "bending"), (10548, "bending"), (11979, "radial"), (11985, "radial")],
    4: [(7583.6, "torsional"), (7588.8, "torsional"), (10996, "folding"),
        (11232, "folding"), (11233, "bending"), (12474, "circumferential"),
        (17943, "bending"), (17943, "bending"), (20412, "radial"), (20404, "radial")],
}  # fmt: skip
#: Paper 000 Table 1: masses (g).
MASS = {1: 642, 2: 177, 3: 666, 4: 333}


def main() -> None:
    design = load_design(HERE / "nutation_double_sided.toml")
    results = {}
    for gear in (1, 2, 3, 4):
        res = body_modal(design, gear, stage=lambda s, g=gear: print(f"gear {g}: {s}",
                                                                     file=sys.stderr))  # fmt: skip
        results[gear] = res.to_dict()
    for gear, r in results.items():
        print(f"\n### Gear {gear} (z = {r['teeth']}, {r['gear_kind']}): mass "
              f"{1e3 * r['mass_kg']:.0f} g (Table 1: {MASS[gear]} g), {r['tetrahedra']} "
              f"tets, {r['dofs']} DOFs, largest change from the 1.5x coarser mesh "
              f"{100 * r['max_change_from_coarser']:.2f} %\n")  # fmt: skip
        print("| order | paper (Hz) | paper type | ours (Hz) | our type (n, circles) | change |")
        print("|---|---|---|---|---|---|")
        for (fp, tp), m in zip(TABLE_4[gear], r["modes"], strict=True):
            ch = m["change_from_coarser"]
            print(f"| {m['mode']} | {fp:g} | {tp} | {m['frequency_hz']:.0f} | {m['type']} "
                  f"({m['nodal_diameters']}, {m['nodal_circles']}) | "
                  f"{'-' if ch is None else f'{100 * ch:+.2f} %'} |")  # fmt: skip
    print("\n<!-- " + json.dumps(results) + " -->")


if __name__ == "__main__":
    main()
