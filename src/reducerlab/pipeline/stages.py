"""The stages of ``reducerlab run`` and what each depends on (its cache key's inputs).

Each stage function takes the :class:`~reducerlab.pipeline.store.Store`, computes its
key from its inputs only, and returns ``(output, Stage)``: the output read from the
store when an entry with that key exists, else computed and stored at once (so that an
interrupted run keeps every stage it finished).

=================  ================================================================
stage              key inputs
=================  ================================================================
``compliance``     the pair's tooth generation (``contact_inputs``: teeth and mean
                   radii, helix and pressure angles, ``[surface]``), ``[material]``,
                   the gear (external or internal) and the FE tooth element size
``contact``        the same design fields, the torque on the external gear, the
                   misalignment and the grid (positions, Fourier order, cell)
``body``           the gear's body (``body_inputs``: as above plus its blank) and the
                   mesh sizes and mode count
``response``       the whole design the model is built from (with the contact's mesh
                   stiffness in it), the mesh line and the integration settings
=================  ================================================================
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..inputs import inputs_of
from .store import Store

__all__ = [
    "ContactSettings",
    "Stage",
    "body_inputs",
    "body_stage",
    "compliance_stage",
    "contact_stage",
    "design_inputs",
    "response_stage",
]

Report = Callable[[str, float], None]
"""``report(description, fraction)``: a stage's progress, fraction in [0, 1]."""


@dataclass
class Stage:
    """What happened to one stage of a run."""

    name: str
    key: str
    status: str  # "computed", "cached" or "given"
    seconds: float = 0.0
    note: str = ""

    def to_dict(self) -> dict[str, Any]:
        return {
            "stage": self.name,
            "key": self.key,
            "status": self.status,
            "seconds": round(self.seconds, 3),
            "note": self.note,
        }


@dataclass(frozen=True)
class ContactSettings:
    """The grid of the loaded contact analysis (``contact_analysis``'s defaults).

    Attributes
    ----------
    positions : int
        Positions over one mesh cycle.
    order : int
        Harmonics of the Eq. 8 fit (paper 000: 7).
    cell : float or None
        Contact cell (m); None for the automatic grid.
    tooth_size : float or None
        FE tooth element size (m); None for ``0.3 m_n``.
    """

    positions: int = 24
    order: int = 7
    cell: float | None = None
    tooth_size: float | None = None


def design_inputs(kind: str, design: Any, attrs: dict[str, Any]) -> dict[str, Any]:
    """The design fields (SI) a result of ``kind`` reads (:func:`reducerlab.inputs.inputs_of`)."""
    return inputs_of(kind, json.loads(design.provenance["design"]), attrs)


def _quiet(_d: str, _f: float) -> None:
    return None


def compliance_stage(
    store: Store,
    design: Any,
    pair: int,
    settings: ContactSettings,
    report: Report = _quiet,
    submit: Callable[..., Any] | None = None,
) -> tuple[tuple[Any, Any], list[Stage]]:
    """The FE tooth compliance of both gears of pair ``pair`` (external, internal).

    ``submit(function, *args, **kwargs) -> future`` runs the two models elsewhere (a
    Dask client's ``submit``); by default they run here, one after the other.
    """
    from ..analysis.contact import contact_pair
    from ..contact.compliance import compliance_estimate, fe_tooth_compliance
    from ..fe import Material

    base = design_inputs("contact", design, {"pair": pair})
    gears = (2 * pair, 2 * pair - 1)
    keys = {
        g: store.key("compliance", {"design": base, "gear": g, "tooth_size": settings.tooth_size})
        for g in gears
    }
    found = {g: store.get("compliance", keys[g], extra=True) for g in gears}
    todo = [g for g in gears if found[g] is None]
    out: dict[int, Any] = {g: found[g][1] for g in gears if found[g] is not None}
    stages = [Stage(f"compliance gear {g}", keys[g], "cached") for g in gears if g in out]
    if todo:
        mp = contact_pair(design, pair).unmodified  # the compliance: unmodified teeth
        compliance_estimate(mp, settings.tooth_size).check()
        mat = design.material
        material = Material(mat.youngs_modulus, mat.poisson_ratio, mat.density)
        flank = {2 * pair: mp.flank_a, 2 * pair - 1: mp.flank_b}
        kw = {"material": material, "tooth_size": settings.tooth_size}
        futures = {}
        if submit is not None:
            futures = {g: submit(fe_tooth_compliance, flank[g], **kw) for g in todo}
        for g in todo:
            t0 = time.perf_counter()
            name = f"compliance gear {g}"
            report(name, 0.0)
            if g in futures:
                comp = futures[g].result()
            else:
                comp = fe_tooth_compliance(
                    flank[g], stage=lambda s, n=name: report(f"{n}: {s}", 0.5), **kw
                )
            store.put("compliance", keys[g], {"design": base, "gear": g}, extra=comp)
            out[g] = comp
            stages.append(Stage(name, keys[g], "computed", time.perf_counter() - t0))
            report(name, 1.0)
    return (out[2 * pair], out[2 * pair - 1]), stages


def contact_stage(
    store: Store,
    design: Any,
    pair: int,
    torque: float,
    settings: ContactSettings,
    compliance: tuple[Any, Any],
    report: Report = _quiet,
) -> tuple[Any, Stage]:
    """Loaded contact of pair ``pair`` with ``torque`` (N m) on its external gear."""
    from ..analysis.contact import contact_analysis

    base = design_inputs("contact", design, {"pair": pair})
    inputs = {
        "design": base,
        "pair": pair,
        "torque": float(torque),
        "positions": settings.positions,
        "order": settings.order,
        "cell": settings.cell,
        "tooth_size": settings.tooth_size,
        "misalignment": None,
    }
    key = store.key("contact", inputs)
    name = f"contact pair {pair}"
    hit = store.get("contact", key)
    if hit is not None:
        return _at_speed(hit[0], design), Stage(name, key, "cached")
    t0 = time.perf_counter()
    report(name, 0.0)
    res = contact_analysis(
        design,
        pair,
        torque=float(torque),
        positions=settings.positions,
        order=settings.order,
        cell=settings.cell,
        tooth_size=settings.tooth_size,
        compliance=compliance,
        stage=lambda s: report(f"{name}: {s}", 0.0),
        progress=lambda done, total: report(f"{name}: {done}/{total} positions", done / total),
    )
    store.put("contact", key, inputs, res)
    return res, Stage(name, key, "computed", time.perf_counter() - t0)


def _at_speed(res: Any, design: Any) -> Any:
    """A stored contact result read at ``design``'s speed: its ``time`` axis, speed and
    mesh frequency follow the speed (the contact itself, a function of the mesh
    position, does not)."""
    a = res.data.attrs
    pair = int(a["pair"])
    f_mesh = list(design.kinematics().mesh_frequencies(design.operating_speed).values())[pair - 1]
    if math.isclose(float(a["mesh_frequency"]), f_mesh, rel_tol=1e-12):
        return res
    n = res.data.sizes["position"]
    res.data["time"] = ("position", [k / (n * f_mesh) for k in range(n)], {"units": "s"})
    a.update(speed=float(design.operating_speed), mesh_frequency=f_mesh)
    return res


def body_inputs(
    design: Any, gear: int, sizes: tuple[float | None, float | None] = (None, None)
) -> dict[str, Any]:
    """The key inputs of gear ``gear``'s body modes: its body's design fields, the mesh
    sizes, the mode count, the boundary and the method (``body_modal``'s default)."""
    base = design_inputs("body-modal", design, {"gear": gear})
    return {"design": base, "gear": gear, "sizes": list(sizes), "count": 10, "boundary": "free",
            "method": "cyclic"}  # fmt: skip


def body_stage(
    store: Store,
    design: Any,
    gear: int,
    report: Report = _quiet,
    future: Any = None,
    sizes: tuple[float | None, float | None] = (None, None),
) -> tuple[Any, Stage]:
    """Free-free modes of gear ``gear``'s body (ten modes, no convergence run) on the
    mesh of element ``sizes`` ``(tooth, body)`` (m; None: the default). ``future``: the
    result computed elsewhere (a Dask future), stored here."""
    from ..analysis.body_modal import BodyModalResult, body_modal
    from ..analysis.gear_bodies import body_mesh_sizes

    inputs = body_inputs(design, gear, sizes)
    key = store.key("body", inputs)
    name = f"body modes gear {gear}"
    hit = store.get("body", key, extra=True)
    if hit is not None:
        res, (mesh, shapes) = hit
        return BodyModalResult(res.data, mesh, shapes), Stage(name, key, "cached")
    t0 = time.perf_counter()
    report(name, 0.0)
    if future is not None:
        res = future.result()
    else:
        res = body_modal(
            design, gear, convergence=False, sizes=body_mesh_sizes(design, gear, *sizes),
            stage=lambda s: report(f"{name}: {s}", 0.5),
        )  # fmt: skip
    store.put("body", key, inputs, res, extra=(res.mesh, res.shapes))
    return res, Stage(name, key, "computed", time.perf_counter() - t0)


def response_stage(
    store: Store, design: Any, line: int, settings: dict[str, Any], report: Report = _quiet
) -> tuple[Any, Stage]:
    """The steady nonlinear response of mesh line ``line`` of ``design``'s model at its
    operating point (``analysis.response``; ``settings`` its keyword arguments)."""
    from ..analysis.response import response

    inputs = {"design": design_inputs("response", design, {}), "line": line, **settings}
    key = store.key("response", inputs)
    name = f"response line {line + 1}"
    hit = store.get("response", key)
    if hit is not None:
        return hit[0], Stage(name, key, "cached")
    t0 = time.perf_counter()
    report(name, 0.0)
    res = response(design, line=line, **settings)
    store.put("response", key, inputs, res)
    return res, Stage(name, key, "computed", time.perf_counter() - t0)
