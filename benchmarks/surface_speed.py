"""Benchmark: points per second of the enveloped tooth surface (paper 001), one core.

Generates one flank of the external and of the internal gear of paper 000's nutation
pair (26/28 teeth, nutation angle 5 deg, m_n = 2 mm, beta = 25 deg) from the involute
and the double circular-arc (GB/T 12759) profiles on a 1000 x 1000 grid: crown surface
(paper 001 Eq. 4), vectorised Newton solution of the meshing equation for every point,
residual from ``kinematics.mesh.relative_velocity``, rigid map to the gear frame. The
checks of ``generate_tooth`` are not included (they are per tooth, not per point).

Run: ``OMP_NUM_THREADS=1 .venv/bin/python benchmarks/surface_speed.py``.
"""

from __future__ import annotations

import datetime as dt
import math
import os
import platform
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import numpy as np

from reducerlab.geometry.bevel_surface import generate_flank, nutation_bevel_pair
from reducerlab.geometry.profiles import DoubleCircularArcProfile, InvoluteProfile
from reducerlab.geometry.solid import build_gear_solid
from reducerlab.geometry.spiral import CrownGear

N_U = N_RHO = 1000


def main() -> None:
    ext, inn = nutation_bevel_pair(26, 28, math.radians(5))
    print(f"date: {dt.date.today()}")
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores (1 thread used), "
        f"Python {platform.python_version()}, numpy {np.__version__}"
    )
    print(f"grid: {N_U} x {N_RHO} = {N_U * N_RHO} points per flank")
    for prof in (InvoluteProfile(2e-3, math.radians(20)), DoubleCircularArcProfile(2e-3)):
        crown = CrownGear.for_gear(prof, ext.teeth, ext.cone_angle, math.radians(25), 10e-3)
        u = np.linspace(0, 1, N_U)
        rho = np.linspace(*crown.rho_range, N_RHO)
        for gear in (ext, inn):
            times = []
            for _ in range(3):
                t = time.perf_counter()
                f = generate_flank(crown, gear, u, rho, 1)
                times.append(time.perf_counter() - t)
            best = min(times)
            # baseline: the same solver called point by point (a per-point loop, as a
            # MATLAB script solving the meshing equation point after point does) on a
            # sample of 400 points
            t = time.perf_counter()
            for i in range(20):
                for j in range(20):
                    generate_flank(crown, gear, u[i * 50 : i * 50 + 1], rho[j * 50 : j * 50 + 1], 1)
            loop = (time.perf_counter() - t) / 400
            print(
                f"{prof.name:10s} {gear.kind:8s}: {best:.3f} s, "
                f"{N_U * N_RHO / best / 1e6:.2f} M points/s, Newton iterations {f.iterations}, "
                f"max residual {f.max_residual:.1e}; point by point {loop * 1e6:.0f} us/point "
                f"-> x{loop * N_U * N_RHO / best:.0f}"
            )

    # closed full-gear solids (every tooth, blank, watertight triangle mesh)
    crown = CrownGear.for_gear(
        InvoluteProfile(2e-3, math.radians(20)), ext.teeth, ext.cone_angle, math.radians(25),
        10e-3,
    )  # fmt: skip
    for n_profile, n_face in ((15, 11), (41, 31)):
        t = time.perf_counter()
        mesh = build_gear_solid(crown, ext, n_profile, n_face).gear_mesh()
        dt_ = time.perf_counter() - t
        print(
            f"full gear solid, involute external, {n_profile} x {n_face} grid: "
            f"{len(mesh.faces)} triangles in {dt_:.2f} s"
        )


if __name__ == "__main__":
    main()
