"""Compile reducerlab's numba kernels once, at install time (``make`` runs this after
``pip install``): numba caches them next to the sources, so the first report or
nonlinear run on a fresh machine does not spend a minute compiling (the one-time cost
is measured in benchmarks/RESULTS.md, "Design reports").

numba checks a cached kernel against its own source file only, not against the modules
it calls (``dynamics/kernel_laws.py``, ``model/layout.py``): the old caches are removed
first, so a changed law layout is always compiled anew (the mode-tracking kernel of
``analysis/tracking.py`` calls nothing outside its file)."""

from __future__ import annotations

import time
from pathlib import Path

from skfem import MeshTet

import reducerlab as rl
from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.parameters import parse_values
from reducerlab.analysis.response import response
from reducerlab.analysis.sweep import sweep
from reducerlab.fe.elasticity import assemble

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def main() -> None:
    t0 = time.perf_counter()
    for cache in (Path(rl.__file__).parent / "dynamics" / "__pycache__").glob("*.nb[ic]"):
        cache.unlink()
    response(rl.load_design(EXAMPLES / "gear_pair.toml"), periods=40, keep=10, history=2)
    # long runs of many DOFs take the one-period maps (dynamics/maps.py)
    response(rl.load_design(EXAMPLES / "nutation_double_sided.toml"), history=2)
    khv = rl.load_design(EXAMPLES / "khv_rattle.toml")
    bifurcation(khv, parse_values("gears.x1", "0.5,0.6"), periods=40, keep=10)
    bifurcation(khv, parse_values("gears.x1", "0.5,0.6"), periods=40, keep=10,
                continuation="up")  # fmt: skip
    # a sweep long enough to be tracked by the compiled kernel (analysis/tracking.py)
    sweep(rl.load_design(EXAMPLES / "gear_pair.toml"),
          parse_values("mesh.stiffness", "lin:1e8:1e9:3000"), workers=1)  # fmt: skip
    # the finite-element assembly (fe/kernels.py, issue 28): ~40 s to compile on a busy
    # machine, else paid by the first contact analysis or body-mode run
    assemble(MeshTet().refined(1), order=2)
    print(f"numba kernels compiled and cached in {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
