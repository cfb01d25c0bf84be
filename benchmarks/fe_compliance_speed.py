"""The FE tooth compliance, before and after issue 28's compiled assembly and
forward-substitution solve, side by side in one run.

Pair 1 of ``examples/nutation_surface.toml`` (the profile gear, ``flank_a``):

1. **Assembly** of the five-tooth model's curved quadratic tetrahedra: scikit-fem's
   ``asm`` (stiffness and mass, as ``fe.assemble`` did) against the compiled kernels
   (``fe.kernels``, the stiffness alone as the compliance needs it; and with the mass,
   as the body modes need it), interleaved, best of ``REPEAT``; the matrices compared.
2. **The whole compliance** of the gear (``fe_tooth_compliance``, ``_legacy=True``:
   scikit-fem's assembly and PARDISO's whole solve, against the default), interleaved,
   best of ``REPEAT``, after one untimed call that builds the sector solid (cached per
   process); the influence matrices compared.
3. **The contact command** end to end, ``reducerlab contact
   examples/nutation_surface.toml --pair 1 --power 3kW`` in a fresh process, against
   the 164 s measured before issue 28 (``benchmarks/RESULTS.md``, "Threads and the gear
   sector solid"; the policy off then, on now).

With ``--reference SRC [SRC ...]`` only the contact command is timed, with this tree's
package and with other checkouts' ``src`` (e.g. ``git archive`` of the commits before),
interleaved, best of ``$REPEAT`` (default ``REPEAT``).

The machine is shared: the load average is printed with each line. Run:
``.venv/bin/python benchmarks/fe_compliance_speed.py [--reference SRC ...]``; prints a block
for ``benchmarks/RESULTS.md``.
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import tempfile
import time
from datetime import date
from pathlib import Path

os.environ.setdefault("OMP_NUM_THREADS", "2")

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "nutation_surface.toml"
REPEAT = 2
#: ``reducerlab contact ... --pair 1 --power 3kW`` before issue 28 (s)
BEFORE = 164.0


def load() -> str:
    """The 1-minute load average."""
    return Path("/proc/loadavg").read_text().split()[0]


def best(fn, repeat: int = REPEAT) -> tuple[float, object]:
    """Best wall time of ``repeat`` calls (s) and the last result."""
    times, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return min(times), out


def main() -> None:
    import numpy as np

    from reducerlab.analysis.contact import contact_pair
    from reducerlab.contact import compliance as comp
    from reducerlab.drives import load_design
    from reducerlab.fe.elasticity import STEEL, assemble
    from reducerlab.fe.gear_mesh import MeshSizes, mesh_gear

    omp = os.environ["OMP_NUM_THREADS"]
    print(f"date: {date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, OMP_NUM_THREADS={omp}")  # fmt: skip
    flank = contact_pair(load_design(EXAMPLE), 1).flank_a
    m_n = flank.crown.profile.module
    t = time.perf_counter()
    mesh = mesh_gear(flank.crown, flank.gear, sizes=MeshSizes(0.3 * m_n, m_n), sectors=range(-2, 3))
    print(f"sector solid and mesh (first, untimed below): {time.perf_counter() - t:.1f} s")
    skm = mesh.skfem()
    print(f"model: {skm.t.shape[1]} curved P2 tetrahedra, load {load()}")
    assemble(skm, STEEL, 2)  # compile / load the kernels' cache
    rows = []
    for _ in range(REPEAT):  # interleaved
        t_old, (K0, M0, _) = best(lambda: assemble(skm, STEEL, 2, _engine="skfem"), 1)
        t_k, (K1, _, _) = best(lambda: assemble(skm, STEEL, 2, mass=False), 1)
        t_km, (K2, M2, _) = best(lambda: assemble(skm, STEEL, 2), 1)
        rows.append((t_old, t_k, t_km))
        print(f"  assembly: scikit-fem K+M {t_old:.2f} s, compiled K {t_k:.2f} s, "
              f"compiled K+M {t_km:.2f} s, load {load()}", flush=True)  # fmt: skip
    t_old, t_k, t_km = (min(r[i] for r in rows) for i in range(3))
    dk = abs(K1 - K0).max() / abs(K0).max()
    dm = abs(M2 - M0).max() / abs(M0).max()
    print(f"assembly, best of {REPEAT}: scikit-fem (K and M) {t_old:.2f} s; compiled: K alone "
          f"{t_k:.2f} s ({t_old / t_k:.1f}x), K and M {t_km:.2f} s ({t_old / t_km:.1f}x); "
          f"max |dK|/max|K| {dk:.1e}, max |dM|/max|M| {dm:.1e}")  # fmt: skip
    del K0, M0, K1, K2, M2

    rows = []
    for _ in range(REPEAT):
        t_old, c_old = best(lambda: comp.fe_tooth_compliance(flank, _legacy=True), 1)
        t_new, c_new = best(lambda: comp.fe_tooth_compliance(flank), 1)
        rows.append((t_old, t_new))
        print(f"  compliance: before {t_old:.1f} s, now {t_new:.1f} s, load {load()}", flush=True)
    t_old, t_new = (min(r[i] for r in rows) for i in range(2))
    d = np.abs(c_new.matrix - c_old.matrix).max() / np.abs(c_old.matrix).max()
    print(f"compliance of one gear ({c_new.dofs} DOFs, 162 loads), best of {REPEAT}: before "
          f"{t_old:.1f} s, now {t_new:.1f} s ({t_old / t_new:.2f}x); "
          f"max |dK_FE|/max|K_FE| {d:.1e}")  # fmt: skip

    t_cmd = command(ROOT / "src")
    print(f"reducerlab contact ... --pair 1 --power 3kW (fresh process): {t_cmd:.1f} s; "
          f"before issue 28: {BEFORE:.0f} s: {BEFORE / t_cmd:.2f}x")  # fmt: skip


def command(src: Path) -> float:
    """Wall time (s) of ``reducerlab contact ... --pair 1 --power 3kW`` in a fresh
    process with the package from ``src``; prints the load before and after."""
    env = dict(os.environ, PYTHONPATH=str(src), MPLBACKEND="Agg")
    before = load()
    with tempfile.TemporaryDirectory() as out:
        cmd = [sys.executable, "-m", "reducerlab", "contact", str(EXAMPLE), "--pair", "1",
               "--power", "3kW", "-o", out]  # fmt: skip
        t = time.perf_counter()
        subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL, cwd=out)
        t_cmd = time.perf_counter() - t
    print(f"  contact command, {src}: {t_cmd:.1f} s, load {before} -> {load()}", flush=True)
    return t_cmd


def commands(references: list[Path], repeat: int) -> None:
    """The contact command with each of ``references`` (other checkouts' ``src``, e.g.
    ``git archive`` of older commits) and with this tree's package, interleaved, best of
    ``repeat``."""
    print(f"date: {date.today()}, machine: {platform.machine()}, {os.cpu_count()} cores")
    trees = [*references, ROOT / "src"]
    rows = [[command(src) for src in trees] for _ in range(repeat)]
    t_new = min(r[-1] for r in rows)
    for i, src in enumerate(references):
        t_ref = min(r[i] for r in rows)
        print(f"contact command, best of {repeat}: {src} {t_ref:.1f} s, this tree {t_new:.1f} s "
              f"({t_ref / t_new:.2f}x)")  # fmt: skip


if __name__ == "__main__":
    if len(sys.argv) >= 3 and sys.argv[1] == "--reference":
        commands([Path(a) for a in sys.argv[2:]], int(os.environ.get("REPEAT", REPEAT)))
    else:
        main()
