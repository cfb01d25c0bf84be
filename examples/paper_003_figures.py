"""Paper 003 Fig. 7-10: natural frequencies of the cycloid ball transmission against
planetary-disc mass, eccentricity, single-pair mesh stiffness and bearing support
stiffness, with tracked modes and veering ("mode transition") points.

Run: ``python examples/paper_003_figures.py OUTPUT_FOLDER`` (default
``paper-003-figures``); the same sweeps from the command line, e.g.::

    reducerlab sweep examples/cycloid_ball.toml -p eccentricity -v lin:1e-3:5e-3:81
"""

from __future__ import annotations

import sys
from pathlib import Path

from reducerlab.analysis.sweep import Axis, SweepResult, sweep
from reducerlab.drives import load_design
from reducerlab.examples import example_dir

BEARINGS = (
    "input_shaft.radial_stiffness+centre_disc.radial_stiffness+planetary_disc.bearing_stiffness"
)

#: (figure, parameter path, values): the paper's figures do not survive in the text, so
#: the ranges bracket the values it discusses (2.5 kg, 2.5 mm, 3e7 N/m, 1e8 N/m).
FIGURES = {
    "fig7_planetary_mass": Axis.linspace("planetary_disc.mass", 0.5, 5.0, 46),
    "fig8_eccentricity": Axis.linspace("eccentricity", 1.0e-3, 5.0e-3, 81),
    "fig9_mesh_stiffness": Axis.logspace("cycloid_pair.ball_stiffness", 3e6, 3e8, 81),
    "fig10_bearing_stiffness": Axis.logspace(BEARINGS, 1e7, 1e9, 81),
}


def run(output: Path, points: int | None = None) -> dict[str, SweepResult]:
    """Run the four sweeps into ``output`` and save one figure each."""
    design = load_design(example_dir() / "cycloid_ball.toml")
    results = {}
    for name, axis in FIGURES.items():
        if points is not None:
            vals = axis.values
            step = max(1, len(vals) // points)
            axis = Axis(axis.path, vals[::step], scale=axis.scale)
        res = sweep(design, axis, output=output / name, workers=1)
        res.plot().savefig(output / f"{name}.png", dpi=110)
        results[name] = res
    return results


if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "paper-003-figures")
    for name, res in run(out).items():
        print(name)
        for e in res.events():
            print(f"  {e['kind']} at {e['param']:.4g} between modes {e['modes']}")
