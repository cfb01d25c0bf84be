"""Benchmark: the datasheet of the double-sided nutation example (issue 31: under 2
minutes on 2 cores with the cached contact reused).

``reducerlab.pipeline.datasheet.datasheet`` on ``examples/nutation_double_sided.toml``
with its defaults (torsion test with Coulomb friction, 20 steps; the transmission
accuracy under the rated torque, both meshes' loaded TE; the efficiency of both bevel
meshes from the loaded contact at 1/4, 1/2 and 1 times rated; finite-element teeth, 12
positions a mesh cycle), three times on one stage cache:

1. **cold**: empty cache, the four gears' finite-element tooth models built;
2. **after a run**: the tooth models in the cache (as ``reducerlab run`` of the design
   leaves them in ``OUTPUT/cache``: the same compliance stage and key), the loaded TE
   and the efficiency computed: the case the issue's target names;
3. **repeated**: everything read from the cache.

Run: ``.venv/bin/python benchmarks/datasheet_speed.py`` (the threads as the package
sets them: both cores).
"""

from __future__ import annotations

import datetime as dt
import os
import platform
import tempfile
import time
from pathlib import Path

from reducerlab.drives import load_design
from reducerlab.examples import example_dir
from reducerlab.pipeline.datasheet import datasheet


def _timed(design, cache: Path) -> tuple[float, object]:
    t0 = time.perf_counter()
    sheet = datasheet(design, cache=cache)
    return time.perf_counter() - t0, sheet


def main() -> None:
    design = load_design(example_dir() / "nutation_double_sided.toml")
    print(f"date: {dt.date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, load average {os.getloadavg()[0]:.2f}")  # fmt: skip
    with tempfile.TemporaryDirectory() as tmp:
        cache = Path(tmp) / "cache"
        cold, sheet = _timed(design, cache)
        for f in [*cache.glob("efficiency-*"), *cache.glob("accuracy_mesh_te-*")]:
            f.unlink()  # keep the tooth models only: "after a run"
        warm, _ = _timed(design, cache)
        again, _ = _timed(design, cache)
    for st in sheet.stages:
        print(f"  cold stage {st.name}: {st.status} {st.seconds:.1f} s")
    print(f"cold (tooth models built):      {cold:7.1f} s")
    print(f"after a run (tooth models cached): {warm:7.1f} s")
    print(f"repeated (all cached):          {again:7.1f} s")
    print(sheet.table())


if __name__ == "__main__":
    main()
