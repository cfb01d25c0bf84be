"""Paper 004 answered with regime maps: at which speeds and profile shifts (backlash,
transmission error) does the KHV drive of ``examples/khv.toml`` lose contact, rattle on
both flanks, or go period-n, quasi-periodic or chaotic?

Maps speed x x1, speed x half backlash and speed x error amplitude (each row swept up
and down in speed by continuation), for both readings of the paper's damping ratios
(Table 2's zeta = 0.1 and eta = 0.005: which is the mesh's and which the shafts'), then
prints each map's regions, the class sequence along x1 at every speed (to compare with
the paper's Fig. 7 sequence) and the speeds whose x1 sequence is richest. The findings
are recorded in docs/paper_004_regimes.md.

Run: ``python examples/paper_004_regime_maps.py OUTPUT_FOLDER [SPEEDS] [ROWS]``
(defaults 39 speeds from 100 to 2000 rpm and 15 rows; about a minute per map on two
cores). Each map's run folder is resumable.
"""

from __future__ import annotations

import sys
from itertools import groupby
from pathlib import Path

import numpy as np

from reducerlab.analysis.parameters import Axis, parse_values
from reducerlab.analysis.regime_map import regime_map
from reducerlab.drives import load_design
from reducerlab.examples import example_dir

#: The two readings of Table 2's damping ratios: (mesh zeta, shaft eta).
READINGS = {"zeta-mesh": ("0.1", "0.005"), "eta-mesh": ("0.005", "0.1")}


def sequence(labels: np.ndarray, values: np.ndarray) -> str:
    """A column of classes as runs: ``period-1 (0.416-0.55), period-2 (0.58-0.61)``."""
    out, i = [], 0
    for lab, run in groupby(labels.tolist()):
        n = len(list(run))
        out.append(f"{lab} ({values[i]:.3g}-{values[i + n - 1]:.3g})")
        i += n
    return ", ".join(out)


def run(output: Path, speeds: int = 39, rows: int = 15, periods: int = 600) -> dict:
    output.mkdir(parents=True, exist_ok=True)
    x = parse_values("input_speed", f"lin:100 rpm:2000 rpm:{speeds}")
    maps = {}
    for reading, (zeta, eta) in READINGS.items():
        design = load_design(
            example_dir() / "khv.toml",
            [f"mesh.damping_ratio={zeta}", f"shafts.damping_ratio={eta}"],
        )
        axes = {"x1": Axis.linspace("gears.x1", 0.416, 0.835, rows)}
        if reading == "zeta-mesh":  # the example's reading: backlash and error maps too
            axes["backlash"] = Axis.linspace("mesh.half_backlash", 0.25e-6, 4e-6, rows)
            axes["error"] = Axis.linspace("mesh.error_amplitude", 0.5e-6, 10e-6, rows)
        for name, y in axes.items():
            key = f"{reading}_speed_x_{name}"
            res = regime_map(design, x, y, periods=periods, keep=min(64, periods),
                             continuation="both", output=output / key)  # fmt: skip
            res.save(output / f"{key}.nc")
            res.plot().savefig(output / f"{key}.png", dpi=110)
            (output / f"{key}.txt").write_text(res.table() + "\n")
            maps[key] = res
    return maps


def report(maps: dict) -> None:
    for key, res in maps.items():
        print(res.table())
        if not key.endswith("x1"):
            continue
        ds = res.data
        rpm = ds["p0"].values * ds["p0"].attrs["display_factor"]
        x1 = ds["p1"].values
        lab = res.labels()[0]  # ascending sweep
        rich = []
        print(f"\n{key}: classes along x1 at each speed (ascending sweep)")
        for j, s in enumerate(rpm):
            col = lab[:, j]
            print(f"  {s:6.0f} rpm: {sequence(col, x1)}")
            rich.append((len(set(col.tolist()) - {"period-1"}), s))
        rich.sort(reverse=True)
        print(f"  richest speeds (distinct non-period-1 classes, rpm): {rich[:5]}\n")


if __name__ == "__main__":
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "paper-004-regime-maps")
    n_speeds = int(sys.argv[2]) if len(sys.argv) > 2 else 39
    n_rows = int(sys.argv[3]) if len(sys.argv) > 3 else 15
    report(run(out, n_speeds, n_rows))
