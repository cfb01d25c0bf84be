"""Paper 000 Fig. 5-6: natural frequencies of the double-sided nutation drive with the
mean mesh stiffness, and with the nutating gears' support stiffness, at 100, 150, 200
and 250 % of the design value, with tracked modes.

Run: ``python examples/paper_000_figures.py OUTPUT_FOLDER``; from the command line::

    reducerlab sweep examples/nutation_double_sided.toml \\
        -p "mesh1.stiffness+mesh2.stiffness" -v "100%,150%,200%,250%"
"""

from __future__ import annotations

import sys
from pathlib import Path

from reducerlab.analysis.parameters import parse_values
from reducerlab.analysis.sweep import SweepResult, sweep
from reducerlab.drives import load_design
from reducerlab.examples import example_dir

FIGURES = {
    "fig5_mesh_stiffness": "mesh1.stiffness+mesh2.stiffness",
    "fig6_nutating_support_stiffness": "support13.k_x+support13.k_y+support13.k_z",
}
FACTORS = "100%,150%,200%,250%"


def run(output: Path) -> dict[str, SweepResult]:
    """Both relative sweeps into ``output``, with a figure each."""
    design = load_design(example_dir() / "nutation_double_sided.toml")
    out = {}
    for name, path in FIGURES.items():
        res = sweep(design, parse_values(path, FACTORS), output=output / name, workers=1)
        res.plot().savefig(output / f"{name}.png", dpi=110)
        out[name] = res
    return out


if __name__ == "__main__":
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else "paper-000-figures")
    for name, res in run(folder).items():
        print(name)
        print(res.table())
