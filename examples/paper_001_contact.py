"""Paper 001's loaded contact comparison: involute vs double circular-arc nutation bevel
gears at 1 kW and 3 kW, 1500 rpm on the external gear (the paper's set-up), by the
quasi-static loaded tooth contact analysis of reducerlab (docs/contact.md).

    python examples/paper_001_contact.py [OUTPUT_DIR]

Writes contact_<profile>_<power>.nc/.png and paper_001_contact.json (the table of
docs/contact.md). The gears are examples/nutation_surface.toml's (paper 001 gives no
gear data: docs/assumptions.md). About 5 minutes on 2 cores.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from reducerlab.analysis.contact import contact_analysis
from reducerlab.drives import load_design
from reducerlab.examples import example_dir

#: paper 001's table (averages over 0.5-1 s of its explicit dynamic FE run)
PAPER = {
    ("involute", 3000): {"area_mm2": 1.85, "force_x_N": 425, "von_mises_MPa": 687},
    ("involute", 1000): {"area_mm2": 1.12, "force_x_N": 198, "von_mises_MPa": 351},
    ("double-arc", 3000): {"area_mm2": 3.47, "force_x_N": 312, "von_mises_MPa": 238},
    ("double-arc", 1000): {"area_mm2": 3.21, "force_x_N": 288, "von_mises_MPa": 215},
}


def main(out: Path) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    design = load_design(example_dir() / "nutation_surface.toml")
    rows = {}
    for profile in ("involute", "double-arc"):
        comp = None
        for power in (1000, 3000):
            t0 = time.perf_counter()
            res = contact_analysis(design, 1, power=power, profile=profile, compliance=comp)
            comp = res.compliance
            res.save(out / f"contact_{profile}_{power // 1000}kW.nc")
            res.figure().savefig(out / f"contact_{profile}_{power // 1000}kW.png", dpi=120)
            s = res.summary()
            rows[f"{profile} {power // 1000} kW"] = {
                "contact_area_mm2": 1e6 * s["contact_area_mean"],
                "force_x_N": s["force_x_mean_abs"],
                "normal_force_N": s["normal_force_mean"],
                "peak_pressure_MPa": 1e-6 * s["peak_pressure_max"],
                "interior_pressure_MPa": 1e-6 * s["interior_pressure_max"],
                "edge_share_max": s["edge_share_max"],
                "von_mises_MPa": 1e-6 * s["von_mises_max"],
                "k_mean_N_per_m": s["k_mean"],
                "te_peak_to_peak_um": 1e6 * s["te_peak_to_peak"],
                "cell_mm": 1e3 * res.data.attrs["cell_m"],
                "seconds": time.perf_counter() - t0,
                "paper": PAPER[(profile, power)],
            }
            print(profile, power, json.dumps(rows[f"{profile} {power // 1000} kW"]), flush=True)
    for profile in ("involute", "double-arc"):
        a, b = rows[f"{profile} 3 kW"], rows[f"{profile} 1 kW"]
        rows[f"{profile} stress ratio 3/1 kW"] = {
            "von_mises": a["von_mises_MPa"] / b["von_mises_MPa"],
            "interior_pressure": a["interior_pressure_MPa"] / b["interior_pressure_MPa"],
            "paper": PAPER[(profile, 3000)]["von_mises_MPa"]
            / PAPER[(profile, 1000)]["von_mises_MPa"],
        }
    (out / "paper_001_contact.json").write_text(json.dumps(rows, indent=2) + "\n")
    return rows


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else Path("paper-001-contact"))
