"""Benchmark: a 10,000-point modal sweep of a 12-DOF model.

Compares, in one run on one machine:

* reducerlab's vectorised sweep core (``K = K0 + p K1``, one batched eigenproblem),
* the whole ``reducerlab.analysis.sweep.sweep`` call (chunks written to disk, modes
  tracked by MAC, crossings/veerings detected), in this process, with and without the
  tracking (best of three each; their ratio is printed),
* the plain loop a user would write: ``scipy.linalg.eigh(K0 + p K1, M)`` per point.

The model is a 12-DOF bending-torsional-axial layout like paper 000's nutation drive
(three bodies with x, y, z and rotation, bearings, two meshes with projection
coefficients on all DOFs). The mesh stiffness of the first mesh is swept over
10,000 values. Run: ``.venv/bin/python benchmarks/modal_sweep.py``.
"""

from __future__ import annotations

import datetime as dt
import os
import platform
import tempfile
import time

import numpy as np
import scipy.linalg

from reducerlab.analysis.batch import eigh_batch
from reducerlab.analysis.sweep import Axis, sweep
from reducerlab.model import Dof, Inertia, Mesh, Model, Support

N_POINTS = 10_000


def twelve_dof() -> Model:
    rng = np.random.default_rng(0)
    bodies = ("fixed_gear", "nutating", "output")
    dofs = [Dof(b, k) for b in bodies for k in ("x", "y", "z", "rz")]
    els = []
    for b, m, J, k in zip(bodies, (0.177, 1.308, 0.333), (1.33e-4, 2.02e-3, 2.16e-4),
                          (2.2e8, 3.4e8, 2.9e8), strict=True):  # fmt: skip
        els += [Inertia(f"{b}.{q}", m) for q in "xyz"] + [Inertia(f"{b}.rz", J)]
        els += [Support(f"{b}.{q}", k) for q in "xyz"]
    for name, (a, c), k in (("mesh1", ("nutating", "fixed_gear"), 2.1e8),
                            ("mesh2", ("nutating", "output"), 2.2e8)):  # fmt: skip
        g = {f"{a}.{q}": float(rng.uniform(-0.9, 0.9)) for q in "xyz"}
        g |= {f"{c}.{q}": float(rng.uniform(-0.9, 0.9)) for q in "xyz"}
        g |= {f"{a}.rz": 0.0395, f"{c}.rz": -0.0367}
        els.append(Mesh(g, stiffness=k, name=name))
    return Model(dofs, els, name="12-DOF benchmark")


def best_of(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def main() -> None:
    model = twelve_dof()
    k = np.linspace(0.5e8, 1.0e9, N_POINTS)
    base = model.matrices()
    d = model.derivative("mesh1.stiffness")
    K0 = base.K - model.parameter("mesh1.stiffness") * d.K
    M = base.M

    def loop():
        return np.array([scipy.linalg.eigh(K0 + p * d.K, M, eigvals_only=False)[0] for p in k])

    def batched():
        return eigh_batch(M, K0 + k[:, None, None] * d.K)[0]

    def full(track=True):
        with tempfile.TemporaryDirectory() as tmp:
            return sweep(model, Axis("mesh1.stiffness", tuple(k)), output=tmp, workers=1,
                         chunk_size=N_POINTS, track=track)  # fmt: skip

    # warm imports and the compiled tracking kernel (sweeps of 2,000 steps or more)
    sweep(model, Axis("mesh1.stiffness", tuple(k[::4])), workers=1)
    t_loop, lam_loop = best_of(loop, 1)
    t_batch, lam_batch = best_of(batched)
    t_full, res = best_of(full)
    t_untracked, _ = best_of(lambda: full(track=False))
    err = np.max(np.abs(lam_batch - lam_loop) / np.max(np.abs(lam_loop), axis=1, keepdims=True))
    lines = [
        f"date: {dt.date.today().isoformat()}",
        f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}",
        f"points: {N_POINTS}, DOFs: {model.n}",
        f"per-point scipy.linalg.eigh loop: {t_loop:.3f} s",
        f"reducerlab batched eigenproblem:  {t_batch:.3f} s  (x{t_loop / t_batch:.1f})",
        f"reducerlab sweep(track=False):    {t_untracked:.3f} s  (x{t_loop / t_untracked:.1f}; "
        "linearity probe, chunk file, netCDF)",
        f"reducerlab sweep() with tracking: {t_full:.3f} s  (MAC tracking of 12 modes over "
        f"{N_POINTS} steps, {len(res.events())} events, vectorised={res.data.attrs['vectorised']})",
        f"tracked / untracked sweep:        x{t_full / t_untracked:.2f}",
        f"max relative eigenvalue difference batched vs loop: {err:.1e}",
    ]
    print("\n".join(lines))


if __name__ == "__main__":
    main()
