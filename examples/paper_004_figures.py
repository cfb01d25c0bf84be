"""Paper 004 Fig. 7-11 with the example KHV design: bifurcation over x1 (Fig. 7), the
response at the paper's x1 values (Fig. 8), and bifurcation over the half backlash
(Fig. 9) and the transmission-error amplitude (Fig. 11) at three x1. The paper's
unstated parameters are our choices (docs/assumptions.md), so its regimes need not
appear; the script reports the motion class of every point.

Run: ``python examples/paper_004_figures.py OUTPUT_FOLDER [POINTS]``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.response import response
from reducerlab.analysis.sweep import Axis
from reducerlab.drives import load_design
from reducerlab.examples import example_dir

X1_FIG8 = (0.5, 0.565, 0.585, 0.63, 0.761, 0.8)
X1_THREE = (0.5, 0.761, 0.83)


def _with_x1(design, x1: float):
    return design.with_values({"gears.x1": x1}, f"x1 = {x1}")


def run(output: Path, points: int = 200, periods: int = 600, keep: int = 100) -> dict:
    """All figures into ``output``; returns the periodicity found per diagram."""
    output.mkdir(parents=True, exist_ok=True)
    design = load_design(example_dir() / "khv.toml")
    found = {}
    fig7 = bifurcation(design, Axis.linspace("gears.x1", 0.416, 0.835, points),
                       periods=periods, keep=keep)  # fmt: skip
    fig7.plot().savefig(output / "fig7_x1.png", dpi=110)
    found["fig7"] = fig7.periodicity().tolist()
    for x1 in X1_FIG8:
        res = response(_with_x1(design, x1), periods=periods, keep=keep, history=20)
        res.plot().savefig(output / f"fig8_x1_{x1:g}.png", dpi=110)
    for x1 in X1_THREE:
        d = _with_x1(design, x1)
        b = bifurcation(d, Axis.linspace("mesh.half_backlash", 0.0, 2.2e-6, points // 2),
                        periods=periods, keep=keep)  # fmt: skip
        b.plot().savefig(output / f"fig9_backlash_x1_{x1:g}.png", dpi=110)
        e = bifurcation(d, Axis.linspace("mesh.error_amplitude", 0.0, 10e-6, points // 2),
                        periods=periods, keep=keep)  # fmt: skip
        e.plot().savefig(output / f"fig11_error_x1_{x1:g}.png", dpi=110)
        found[f"fig9_{x1}"] = b.periodicity().tolist()
        found[f"fig11_{x1}"] = e.periodicity().tolist()
    return found


if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "paper-004-figures")
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 200
    for name, periods in run(out, n).items():
        counts = {p: periods.count(p) for p in sorted(set(periods))}
        print(name, "periodicity counts (0 = not periodic within 12):", counts)
