"""Benchmark: Monte-Carlo over tolerances of the KHV drive, 1000 samples (issue 31: under
10 minutes).

``examples/khv.toml`` with the ring's and the planet's eccentricities U(0, 5 um) (their
phases drawn U(0, 360 deg)), their single pitch deviations N(0, 2 um) per tooth
(closed), and the mesh's half backlash U(1, 3 um); each sample runs the torsion test
(4 steps) and the rigid transmission error (4096 steps over the output revolution), in
this process (one worker), single-threaded. A profile of 100 samples splits the time
between validating the sample's design, the torsion test and the transmission error.
Run: ``OMP_NUM_THREADS=1 .venv/bin/python benchmarks/tolerances.py``.
"""

from __future__ import annotations

import cProfile
import datetime as dt
import os
import platform
import pstats
import time

from reducerlab.analysis.tolerances import tolerances
from reducerlab.drives import load_design
from reducerlab.examples import example_dir

SAMPLES = 1000
TOLERANCES = {
    "gears.ring_errors.eccentricity": "0..5 um",
    "gears.planet_errors.eccentricity": "0..5 um",
    "gears.ring_errors.pitch_deviations": "0 +- 2 um",
    "gears.planet_errors.pitch_deviations": "0 +- 2 um",
    "mesh.half_backlash": "1..3 um",
}


def main() -> None:
    design = load_design(example_dir() / "khv.toml")
    tolerances(design, TOLERANCES, samples=2)  # imports and first calls
    t0 = time.perf_counter()
    res = tolerances(design, TOLERANCES, samples=SAMPLES, seed=0)
    wall = time.perf_counter() - t0
    print(f"date: {dt.date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, OMP_NUM_THREADS="
          f"{os.environ.get('OMP_NUM_THREADS', '(unset)')}")  # fmt: skip
    print(f"{SAMPLES} samples: {wall:.1f} s wall, {1e3 * wall / SAMPLES:.1f} ms per sample")
    print(res.table())
    prof = cProfile.Profile()
    prof.enable()
    tolerances(design, TOLERANCES, samples=100, seed=1)
    prof.disable()
    stats = pstats.Stats(prof)
    total = sum(v[3] for k, v in stats.stats.items() if k[2] == "tolerances")
    for label, name in (("validate the sample's design", "design_from_dict"),
                        ("torsion test", "torsion_test"),
                        ("transmission error", "transmission_accuracy")):  # fmt: skip
        cum = sum(v[3] for k, v in stats.stats.items() if k[2] == name)
        print(f"profile, 100 samples: {label}: {cum:.2f} s of {total:.2f} s")


if __name__ == "__main__":
    main()
