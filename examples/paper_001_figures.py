"""Paper 001 figures: one generated tooth of each profile and the gear pair in mesh.

Writes ``tooth_involute.png``, ``tooth_double_arc.png`` and ``pair_in_mesh.png`` to the
folder given as the first argument (default: the current folder), from
``examples/nutation_surface.toml``. Run:
``.venv/bin/python examples/paper_001_figures.py docs/figures``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from reducerlab.drives import load_design
from reducerlab.examples import example_dir
from reducerlab.geometry.solid import build_gear_solid
from reducerlab.plot.surface import plot_gear_pair, plot_tooth


def main(folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    design = load_design(example_dir() / "nutation_surface.toml")
    solids = {}
    for profile in ("involute", "double-arc"):
        for gear in (1, 2):
            crown, bevel = design.tooth_generation(gear, profile)
            solids[profile, gear] = build_gear_solid(crown, bevel, n_profile=15, n_face=9)
        fig = plot_tooth(solids[profile, 2])
        fig.savefig(folder / f"tooth_{profile.replace('-', '_')}.png", dpi=110)
    fig = plot_gear_pair(solids["involute", 2], solids["involute", 1])
    fig.savefig(folder / "pair_in_mesh.png", dpi=110)


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("."))
