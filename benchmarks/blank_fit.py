"""Mass and moments of inertia of a finite-element gear body, without its modes (issue 27).

``reducerlab run`` compares each lumped gear's mass and ``J_x, J_y, J_z`` (the design's
``gearN.mass``, ``gearN.J_*``) with those of its finite-element body
(``analysis/body_modal.py``) and calls a difference over ``[check] consistency`` a
risk. Choosing a blank (``[gearN.blank]``: rim, bore, web, hub, hub_length) that
matches the lumped values needs many bodies, and only their mass matrices: this script
meshes the gear exactly as ``body_modal`` does (``_mesh``: the same CAD solid, blank and
curved quadratic tetrahedra), assembles the consistent mass matrix alone (no stiffness,
no eigen-solution) and evaluates it as ``body_modal`` does (``_translation_mass``,
``_rigid_inertia``: ``J`` about the body's centre of mass, ``z`` the gear axis).

Mass and inertia converge much faster than frequencies (they integrate the density over
the volume; quadratic tetrahedra with curved edges represent the solid's surfaces almost
exactly), so a coarse mesh suffices: ``COARSE`` times the default element sizes (tooth
size capped at half the tooth depth, as ``body_modal``'s convergence run). For gear 2 of
``examples/nutation_double_sided.toml`` (its earlier blank: 30 mm bore, default web and
hub) the coarse mesh (11 908 tetrahedra) gives the mass 0.008 % and ``J_x, J_y, J_z``
0.017 % below the default mesh's (29 510 tetrahedra; ``--compare``). The CAD work
dominates the time, so the coarse mesh saves less than its size suggests: 11 s against
17 s for gear 2, 30-60 s for the nutating gears on two shared cores.

Usage (from the repository root)::

    PYTHONPATH=src .venv/bin/python benchmarks/blank_fit.py DESIGN --gear N \
        [--set gearN.blank.rim="8 mm" ...] [--compare] [--json]

``--set`` takes the design overrides of the command line (``PATH=VALUE``); ``--compare``
also meshes the default sizes and prints the relative differences. Python:
``fe_mass_inertia(design, gear)`` returns ``{"mass": kg, "J_x": kg m^2, ...}``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

#: Element sizes of the fit's mesh, relative to the default (``MeshSizes.default``).
COARSE = 2.0
KEYS = ("mass", "J_x", "J_y", "J_z")


def mass_matrix(skm: Any, density: float) -> tuple[Any, Any]:
    """Consistent mass matrix (kg) of quadratic tetrahedra and its vector basis, as
    :func:`reducerlab.fe.assemble` builds it (without the stiffness)."""
    from skfem import Basis, BilinearForm, ElementTetP2, ElementVector, asm
    from skfem.helpers import dot

    basis = Basis(skm, ElementVector(ElementTetP2()), intorder=4)

    @BilinearForm
    def mass(u: Any, v: Any, _: Any) -> Any:
        return density * dot(u, v)

    return asm(mass, basis).tocsr(), basis


def fe_mass_inertia(design: Any, gear: int, factor: float = COARSE) -> dict[str, Any]:
    """Mass (kg), ``J_x, J_y, J_z`` (kg m^2, about the centre of mass, z the gear axis)
    of gear ``gear``'s finite-element body, meshed at ``factor`` times the default
    element sizes (1: ``body_modal``'s mesh), its centre of mass ``z_c`` (m, gear frame:
    apex at the origin) and the mesh's size (``tetrahedra``)."""
    import numpy as np

    from reducerlab.analysis.body_modal import (
        _mesh,
        _rigid_inertia,
        _translation_mass,
        body_estimate,
        check_bodies,
        gear_blank,
    )
    from reducerlab.fe.gear_mesh import MeshSizes, max_tooth_size

    check_bodies(design)
    crown, bevel = design.tooth_generation(gear)
    rim, features = gear_blank(design, gear)
    sizes = MeshSizes.default(crown.profile.module).refined(factor)
    cap = max_tooth_size(crown, bevel, rim)
    sizes = MeshSizes(min(sizes.tooth, cap), max(sizes.body, min(sizes.tooth, cap)))
    t0 = time.perf_counter()
    budget = body_estimate(design, gear, sizes, "full").check()
    mesh = _mesh(design, gear, crown, bevel, rim, features, sizes, lambda _s: None, budget)
    M, basis = mass_matrix(mesh.skfem(), design.material.density)
    mass = _translation_mass(basis, M)
    J_x, J_y, J_z = _rigid_inertia(basis, M, mass)
    ez, zf = np.zeros(M.shape[0]), np.zeros(M.shape[0])
    ez[basis.nodal_dofs[2]] = ez[basis.edge_dofs[2]] = 1.0
    zf[ez > 0] = np.asarray(basis.doflocs)[2, ez > 0]
    z_c = float(ez @ (M @ zf)) / mass  # centre of mass on the axis (apex at z = 0)
    return {
        "mass": mass, "J_x": J_x, "J_y": J_y, "J_z": J_z, "z_c": z_c,
        "tetrahedra": len(mesh.tets), "seconds": time.perf_counter() - t0,
        "rim_mm": rim * 1e3, "blank": repr(features),
    }  # fmt: skip


def lumped(design: Any, gear: int) -> dict[str, float]:
    """The design's lumped mass (kg) and ``J_x, J_y, J_z`` (kg m^2) of gear ``gear``."""
    g = getattr(design, f"gear{gear}")
    return {k: float(getattr(g, k)) for k in KEYS}


def report(fe: dict[str, Any], lump: dict[str, float]) -> str:
    """One line a quantity: FE (g, g mm^2), lumped, difference (%)."""
    lines = []
    for k in KEYS:
        scale = 1e3 if k == "mass" else 1e9
        unit = "g" if k == "mass" else "g mm^2"
        lines.append(
            f"  {k:<4} FE {fe[k] * scale:>12.6g} {unit:<6}  lumped {lump[k] * scale:>12.6g}  "
            f"{100 * (fe[k] / lump[k] - 1):+7.2f} %"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    from reducerlab.drives import load_design

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("design", type=Path)
    ap.add_argument("--gear", type=int, required=True)
    ap.add_argument("--set", action="append", default=[], metavar="PATH=VALUE")
    ap.add_argument("--factor", type=float, default=COARSE, help="element sizes / default")
    ap.add_argument("--compare", action="store_true", help="also the default mesh")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args(argv)
    design = load_design(a.design, a.set)
    fe = fe_mass_inertia(design, a.gear, a.factor)
    lump = lumped(design, a.gear)
    out: dict[str, Any] = {"gear": a.gear, "fe": fe, "lumped": lump}
    if a.compare:
        ref = fe_mass_inertia(design, a.gear, 1.0)
        out["default_mesh"] = ref
        out["coarse_vs_default"] = {k: fe[k] / ref[k] - 1 for k in KEYS}
    if a.json:
        print(json.dumps(out))
        return 0
    print(f"gear {a.gear}: rim {fe['rim_mm']:.4g} mm, {fe['blank']}")
    print(f"mesh x{a.factor:g}: {fe['tetrahedra']} tets, {fe['seconds']:.1f} s")
    print(report(fe, lump))
    if a.compare:
        ref = out["default_mesh"]
        print(f"default mesh: {ref['tetrahedra']} tets, {ref['seconds']:.1f} s")
        print(report(ref, lump))
        print("coarse vs default: " + ", ".join(
            f"{k} {100 * v:+.3f} %" for k, v in out["coarse_vs_default"].items()))  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
