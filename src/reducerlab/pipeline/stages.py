"""The stages of ``reducerlab run`` and what each depends on (its cache key's inputs).

Each stage function takes the :class:`~reducerlab.pipeline.store.Store`, computes its
key from its inputs only, and returns ``(output, Stage)``: the output read from the
store when an entry with that key exists, else computed and stored at once (so that an
interrupted run keeps every stage it finished).

=================  ================================================================
stage              key inputs
=================  ================================================================
``compliance``     the pair's tooth generation (``contact_inputs``: teeth and mean
                   radii, helix and pressure angles, ``[surface]``; a KHV drive's
                   ``[gears]``), ``[material]``, the gear (external or internal; a
                   KHV pair's planet and ring together), the FE tooth element size
                   and whether the fillet stress influence is built (``root_stress``)
``contact``        the same design fields, the torque on the external gear, the
                   misalignment, the grid (positions, Fourier order, cell) and
                   whether the tooth-root stress is computed (``root_stress``)
``te_sweep``       the contact's design fields, the torque on the external gear, the
                   sweep (loads, top, harmonics, positions), the cell and tooth size
``layout``         the compliance's design fields (a layout replaces the flank
                   modifications), the torque, the search (grid, refine, positions,
                   pressure and edge limits), the cell and tooth size
``sharing``        a KHV pair's load sharing (:mod:`.optional`): as ``te_sweep``
                   with loads, top, positions, cell and tooth size
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

from ..errors import ReducerlabError
from ..inputs import inputs_of
from .store import Store

__all__ = [
    "ContactSettings",
    "LayoutSettings",
    "Stage",
    "SweepSettings",
    "body_inputs",
    "body_stage",
    "check_integer",
    "check_positive",
    "compliance_names",
    "compliance_stage",
    "contact_stage",
    "design_inputs",
    "layout_stage",
    "operating_inputs",
    "response_stage",
    "te_sweep_stage",
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
    root_stress : bool
        Also the FE tooth-root stress of both gears at every position
        (``contact_analysis(root_stress=True)``): the tooth models are built with their
        fillet stress influence (one backward substitution per load bump more) and each
        position costs one influence-matrix product and gear B's flank parameters of
        the loaded cells more (``docs/run.md``: measured, 15-30 % of the tooth-model and
        contact stages).
    """

    positions: int = 24
    order: int = 7
    cell: float | None = None
    tooth_size: float | None = None
    root_stress: bool = True

    def __post_init__(self) -> None:
        if not isinstance(self.root_stress, bool):
            raise ReducerlabError(f"root_stress: must be true or false; got {self.root_stress!r}")


def check_integer(name: str, value: Any, lo: int, hi: int) -> None:
    """Refuse ``value`` unless an integer in ``lo..hi``, naming the setting ``name``."""
    if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
        raise ReducerlabError(f"{name}: must be an integer in {lo}..{hi}; got {value!r}")


def check_positive(name: str, value: Any, hi: float = math.inf) -> None:
    """Refuse ``value`` unless a finite number in ``(0, hi]``, naming ``name``."""
    if isinstance(value, bool) or not (
        isinstance(value, int | float) and math.isfinite(value) and 0 < value <= hi
    ):
        bound = "> 0" if hi == math.inf else f"in (0, {hi:g}]"
        raise ReducerlabError(f"{name}: must be a number {bound}; got {value!r}")


@dataclass(frozen=True)
class SweepSettings:
    """The loaded-TE torque sweep of each pair (``analysis.te_sweep.te_sweep``).

    Attributes
    ----------
    loads : int
        Torques evenly from 0 to ``top`` times the pair's operating torque (2..41).
    top : float
        Largest torque over the operating torque, in (0, 3].
    harmonics : int
        Mesh orders of the TE reported (1..20).
    positions : int or None
        Positions over one mesh cycle (>= ``2 harmonics + 1``); None: the contact's.
    """

    loads: int = 6
    top: float = 1.5
    harmonics: int = 3
    positions: int | None = None

    def __post_init__(self) -> None:
        check_integer("te_sweep.loads", self.loads, 2, 41)
        check_positive("te_sweep.top", self.top, 3.0)
        check_integer("te_sweep.harmonics", self.harmonics, 1, 20)
        if self.positions is not None:
            check_integer("te_sweep.positions", self.positions, 2 * self.harmonics + 1, 1000)

    def positions_of(self, contact: ContactSettings) -> int:
        """The sweep's positions (its own, else the contact's), checked against its
        harmonics."""
        n = contact.positions if self.positions is None else self.positions
        check_integer("te_sweep.positions", n, 2 * self.harmonics + 1, 1000)
        return n

    def estimate(self, contact: ContactSettings) -> Any:
        """The work of one pair's sweep (``te_sweep.sweep_estimate``), before any."""
        from ..analysis.te_sweep import sweep_estimate

        return sweep_estimate(self.positions_of(contact), self.loads)


@dataclass(frozen=True)
class LayoutSettings:
    """The flank modification layout of each pair (``analysis.layout``): its search.

    Attributes
    ----------
    grid : int
        Values of each amount (lead crowning, tip relief) per round (2..7).
    refine : int
        Refinement rounds of half the last step (0..3).
    positions : int
        Positions over one mesh cycle of each candidate (2..1000).
    pressure_limit : float
        Largest allowed cell pressure (Pa); default 1500 MPa
        (``analysis.layout.DEFAULT_PRESSURE_LIMIT``, ISO 6336-5 MQ case-hardened).
    edge_limit : float
        Largest allowed edge share, in (0, 1].
    """

    grid: int = 3
    refine: int = 1
    positions: int = 12
    pressure_limit: float = 1.5e9
    edge_limit: float = 0.01

    def __post_init__(self) -> None:
        check_integer("layout.grid", self.grid, 2, 7)
        check_integer("layout.refine", self.refine, 0, 3)
        check_integer("layout.positions", self.positions, 2, 1000)
        check_positive("layout.pressure_limit", self.pressure_limit)
        check_positive("layout.edge_limit", self.edge_limit, 1.0)

    @property
    def candidates(self) -> int:
        """Candidates evaluated at most: ``grid^2 (1 + refine)``."""
        return self.grid * self.grid * (1 + self.refine)

    def estimate(self) -> Any:
        """The work of one pair's layout (``layout.layout_estimate``), before any."""
        from ..analysis.layout import layout_estimate

        return layout_estimate(self.candidates, self.positions)


def design_inputs(kind: str, design: Any, attrs: dict[str, Any]) -> dict[str, Any]:
    """The design fields (SI) a result of ``kind`` reads (:func:`reducerlab.inputs.inputs_of`)."""
    return inputs_of(kind, json.loads(design.provenance["design"]), attrs)


def _quiet(_d: str, _f: float) -> None:
    return None


#: the design fields of a load, left out of the compliance's key (the unloaded,
#: unmodified teeth's): a nutation design's and a KHV design's (with the speed that turns
#: its output power into a torque, which a crowned KHV layout reads)
LOAD_FIELDS = ("output_torque", "output_power", "load_torque", "input_speed")


def _internal(design: Any) -> bool:
    """Whether ``design``'s pair is the KHV drive's internal pair (planet in ring)."""
    return getattr(design, "type", None) == "khv"


def compliance_names(design: Any, pair: int) -> list[str]:
    """The compliance stages of pair ``pair``: one per gear of a nutation pair (the
    external gear first), one for both gears of a KHV internal pair (built together by
    ``contact.internal_pair.InternalMeshPair.tooth_compliances``)."""
    if _internal(design):
        return ["compliance planet V, ring K"]
    return [f"compliance gear {2 * pair}", f"compliance gear {2 * pair - 1}"]


def _pair_compliances(design: Any, tooth_size: float | None, root_stress: bool) -> Any:
    """Both tooth compliances of a KHV design's internal pair (``PairSetup.compliances``,
    as ``contact_analysis`` builds them), for a Dask worker."""
    from ..analysis.contact_setup import pair_setup

    return pair_setup(design, 1).compliances(tooth_size, lambda _s: None, None, root_stress)


def _internal_compliance_stage(
    store: Store,
    design: Any,
    settings: ContactSettings,
    report: Report,
    submit: Callable[..., Any] | None,
) -> tuple[tuple[Any, Any], list[Stage]]:
    """The planet's and the ring's tooth compliance of a KHV design, one stage."""
    from ..analysis.contact_setup import pair_setup

    base = {k: v for k, v in design_inputs("contact", design, {"pair": 1}).items()
            if "modifications" not in k and k not in LOAD_FIELDS}  # fmt: skip
    rs = settings.root_stress
    name = compliance_names(design, 1)[0]
    record = {"design": base, "gear": "planet V, ring K", "root_stress": rs}
    key = store.key("compliance", {**record, "tooth_size": settings.tooth_size})
    hit = store.get("compliance", key, extra=True)
    if hit is not None:
        return hit[1], [Stage(name, key, "cached")]
    setup = pair_setup(design, 1)
    setup.compliance_estimate(settings.tooth_size, rs).check()
    t0 = time.perf_counter()
    report(name, 0.0)
    if submit is not None:
        comp = submit(_pair_compliances, design, settings.tooth_size, rs).result()
    else:
        comp = setup.compliances(
            settings.tooth_size, lambda s: report(f"{name}: {s}", 0.5), None, rs
        )
    store.put("compliance", key, record, extra=comp)
    report(name, 1.0)
    return comp, [Stage(name, key, "computed", time.perf_counter() - t0)]


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
    Dask client's ``submit``); by default they run here, one after the other. A KHV
    design's internal pair: both in one stage.
    """
    from ..analysis.contact import contact_pair

    if _internal(design):
        return _internal_compliance_stage(store, design, settings, report, submit)
    from ..contact.compliance import compliance_estimate, fe_tooth_compliance
    from ..fe import Material

    # the compliance is the unmodified teeth's: not keyed by the flank modifications
    base = {k: v for k, v in design_inputs("contact", design, {"pair": pair}).items()
            if "modifications" not in k and k not in LOAD_FIELDS}  # fmt: skip
    gears = (2 * pair, 2 * pair - 1)
    rs = settings.root_stress
    keys = {
        g: store.key(
            "compliance",
            {"design": base, "gear": g, "tooth_size": settings.tooth_size, "root_stress": rs},
        )
        for g in gears
    }
    found = {g: store.get("compliance", keys[g], extra=True) for g in gears}
    todo = [g for g in gears if found[g] is None]
    out: dict[int, Any] = {g: found[g][1] for g in gears if found[g] is not None}
    stages = [Stage(f"compliance gear {g}", keys[g], "cached") for g in gears if g in out]
    if todo:
        mp = contact_pair(design, pair).unmodified  # the compliance: unmodified teeth
        compliance_estimate(mp, settings.tooth_size, root_stress=rs).check()
        mat = design.material
        material = Material(mat.youngs_modulus, mat.poisson_ratio, mat.density)
        flank = {2 * pair: mp.flank_a, 2 * pair - 1: mp.flank_b}
        kw = {"material": material, "tooth_size": settings.tooth_size, "root_stress": rs}
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
            record = {"design": base, "gear": g, "root_stress": rs}
            store.put("compliance", keys[g], record, extra=comp)
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
        "root_stress": settings.root_stress,
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
        root_stress=settings.root_stress,
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


def operating_inputs(design: Any, pair: int, modifications: bool) -> dict[str, Any]:
    """The pair's design fields (as the contact's), without the flank modifications
    when ``modifications`` is false, and without the load (given as the torque)."""
    base = design_inputs("contact", design, {"pair": pair})
    return {k: v for k, v in base.items()
            if k not in ("output_torque", "output_power")
            and (modifications or "modifications" not in k)}  # fmt: skip


def te_sweep_stage(
    store: Store,
    design: Any,
    pair: int,
    torque: float,
    settings: ContactSettings,
    sweep: SweepSettings,
    compliance: tuple[Any, Any],
    report: Report = _quiet,
    partial: Callable[[Any], None] | None = None,
) -> tuple[Any, Stage]:
    """Loaded TE of pair ``pair`` against torque, from 0 to ``sweep.top`` times
    ``torque`` (N m on the external gear), on the contact stage's tooth compliance.
    ``partial(result)`` after each chunk of positions (the positions done so far)."""
    from ..analysis.te_sweep import te_sweep

    positions = sweep.positions_of(settings)
    inputs = {
        "design": operating_inputs(design, pair, True),
        "pair": pair,
        "torque": float(torque),
        "loads": sweep.loads,
        "top": float(sweep.top),
        "harmonics": sweep.harmonics,
        "positions": positions,
        "cell": settings.cell,
        "tooth_size": settings.tooth_size,
    }
    key = store.key("te_sweep", inputs)
    name = f"te sweep pair {pair}"
    hit = store.get("te_sweep", key)
    if hit is not None:
        return hit[0], Stage(name, key, "cached")
    t0 = time.perf_counter()
    report(name, 0.0)
    res = te_sweep(
        design, pair, loads=sweep.loads, top=float(sweep.top), torque=float(torque),
        positions=positions, harmonics=sweep.harmonics, cell=settings.cell,
        tooth_size=settings.tooth_size, compliance=compliance,
        stage=lambda s: report(f"{name}: {s}", 0.0),
        progress=lambda done, total: report(f"{name}: {done}/{total} positions", done / total),
        partial=partial,
    )  # fmt: skip
    res.compliance = None  # in the compliance stage's entries already
    store.put("te_sweep", key, inputs, res)
    return res, Stage(name, key, "computed", time.perf_counter() - t0)


def layout_stage(
    store: Store,
    design: Any,
    pair: int,
    torque: float,
    settings: ContactSettings,
    layout: LayoutSettings,
    compliance: tuple[Any, Any],
    report: Report = _quiet,
    partial: Callable[[Any], None] | None = None,
) -> tuple[Any, Stage]:
    """Lead crowning and tip relief of pair ``pair`` minimising the TE peak-to-peak at
    ``torque`` (N m on the external gear), on the contact stage's tooth compliance (of
    the unmodified teeth: a layout's candidates replace the design's modifications).
    ``partial(result)`` after each candidate (the candidates evaluated so far)."""
    from ..analysis.layout import modification_layout

    inputs = {
        "design": operating_inputs(design, pair, False),
        "pair": pair,
        "torque": float(torque),
        "grid": layout.grid,
        "refine": layout.refine,
        "positions": layout.positions,
        "pressure_limit": float(layout.pressure_limit),
        "edge_limit": float(layout.edge_limit),
        "cell": settings.cell,
        "tooth_size": settings.tooth_size,
    }
    key = store.key("layout", inputs)
    name = f"layout pair {pair}"
    hit = store.get("layout", key)
    if hit is not None:
        return hit[0], Stage(name, key, "cached")
    t0 = time.perf_counter()
    report(name, 0.0)
    total = layout.candidates
    res = modification_layout(
        design, pair, torque=float(torque), grid=layout.grid, refine=layout.refine,
        positions=layout.positions, cell=settings.cell, pressure_limit=layout.pressure_limit,
        edge_limit=layout.edge_limit, tooth_size=settings.tooth_size, compliance=compliance,
        stage=lambda s: report(f"{name}: {s}", 0.0),
        progress=lambda done, _n: report(f"{name}: {done} candidates", min(1.0, done / total)),
        partial=partial,
    )  # fmt: skip
    store.put("layout", key, inputs, res)
    return res, Stage(name, key, "computed", time.perf_counter() - t0)
