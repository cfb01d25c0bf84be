"""A flank modification layout at the design load: lead crowning and tip relief that
minimise the peak-to-peak transmission error under a pressure limit and without edge
contact (issue 29).

``modification_layout(design, pair)`` evaluates candidate pairs of amounts
``(C_beta, C_a)``: lead crowning ``C_beta`` and parabolic tip relief ``C_a`` over the
outer ``TIP_SHARE`` (20 %) of the active profile (``contact.modifications``, ISO 21771
§9), the same on both gears' loaded flanks. Each candidate is a loaded tooth contact
analysis over one mesh cycle at the design torque (``contact.ltca.loaded_contact``) on
one contact cell and one finite-element tooth compliance (the unmodified teeth's: a
modification of micrometres does not change the tooth's bending, see
``contact.modifications``), so the finite-element models are built once.

A candidate is **feasible** when over the cycle its largest cell pressure stays at or
below ``pressure_limit`` and its largest edge share (load fraction on the cells within
``0.1 m_n`` of a flank edge, ``ContactResult.edge_share``) below ``edge_limit`` (1 %:
no edge contact). Among the feasible ones the layout takes the least TE peak-to-peak.

Search: a ``grid x grid`` grid over ``[0, 2 delta]`` for both amounts, ``delta = F_t /
(b c_gamma)`` the mesh deflection at the design load (ISO 6336-1's ``c_gamma`` = 20
N/(mm um), the scale of ``contact.modifications.crowned_layout``), then ``refine``
rounds of a ``grid x grid`` grid of half the step around the best feasible candidate
(or, if none is feasible, the one nearest to feasibility). A coarse search of the
trade-off, not an optimiser: the answer is the best of the candidates evaluated, on
their grid.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from functools import partial
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr

from ..budget import Estimate
from ..errors import ReducerlabError, names_source
from ..numformat import Column, Table, fmt
from ..results import Result, provenance
from ..threads import with_compute_threads

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["DEFAULT_PRESSURE_LIMIT", "MAX_CANDIDATE_SOLVES", "LayoutResult", "modification_layout"]

#: Default limit of the peak contact pressure (Pa): 1500 MPa, the allowable stress number
#: for contact sigma_Hlim of case-hardened wrought steel of quality MQ (ISO 6336-5:2016,
#: Fig. 9, at the middle of its range), a flank that carries it for 5e7 cycles
DEFAULT_PRESSURE_LIMIT = 1.5e9
#: Largest edge share of a feasible layout: no edge contact
DEFAULT_EDGE_LIMIT = 0.01
#: candidate-position solves of one layout at most (17 candidates of 24 positions ~ 400)
MAX_CANDIDATE_SOLVES = 2000


class LayoutResult(Result):
    """The candidates of a modification layout (:func:`modification_layout`).

    ``data`` has dimension ``candidate`` with ``crowning`` (``C_beta`` of each flank, m),
    ``relief`` (``C_a`` of each flank, m), ``peak_to_peak`` (TE, m at ``te_radius``),
    ``peak_pressure`` (Pa, largest cell pressure over the cycle), ``edge_share`` (largest
    over the cycle), ``feasible`` (1/0) and ``round`` (0 coarse, then refinements).
    Attributes: ``best_crowning``, ``best_relief``, ``best_peak_to_peak`` (NaN when no
    candidate is feasible), ``unmodified_peak_to_peak``, ``delta`` (m),
    ``pressure_limit`` (Pa), ``edge_limit``, ``design_torque`` (N m on gear A).
    """

    kind: ClassVar[str] = "layout"

    @property
    def best(self) -> tuple[float, float] | None:
        """``(C_beta, C_a)`` (m) of the best feasible candidate, or None."""
        a = self.data.attrs
        if not math.isfinite(a["best_crowning"]):
            return None
        return float(a["best_crowning"]), float(a["best_relief"])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: attributes and one row a candidate."""
        ds = self.data
        rows = [
            {
                "crowning_um": 1e6 * float(ds["crowning"].values[i]),
                "relief_um": 1e6 * float(ds["relief"].values[i]),
                "peak_to_peak_um": 1e6 * float(ds["peak_to_peak"].values[i]),
                "peak_pressure_MPa": 1e-6 * float(ds["peak_pressure"].values[i]),
                "edge_share": float(ds["edge_share"].values[i]),
                "feasible": bool(ds["feasible"].values[i]),
            }
            for i in range(ds.sizes["candidate"])
        ]
        out = {k: (v.item() if hasattr(v, "item") else v) for k, v in ds.attrs.items()
               if k != "design"}  # fmt: skip
        out["candidates"] = rows
        return out

    def table(self) -> str:
        """Plain-text table of the candidates, best first among the feasible."""
        a = self.data.attrs
        best = self.best
        um = partial(fmt, kind="length")
        head = (
            f"Flank modification layout at {fmt(a['design_torque'], 'torque')} N m: "
            + (
                f"lead crowning {um(best[0] * 1e6)} um, tip relief {um(best[1] * 1e6)} um "
                f"(each flank): TE p-p {um(a['best_peak_to_peak'] * 1e6)} um against "
                f"{um(a['unmodified_peak_to_peak'] * 1e6)} um unmodified"
                if best
                else "no candidate is feasible"
            )
            + f" (p <= {fmt(a['pressure_limit'] * 1e-6, 'stress')} MPa, edge share < "
            f"{fmt(100 * a['edge_limit'], 'percent')} %)"
        )
        t = Table([Column("C_beta", "um", "length"), Column("C_a", "um", "length"),
                   Column("TE p-p", "um", "length"), Column("p_max", "MPa", "stress"),
                   Column("edge", "%", "percent"), Column("feasible", kind="text")],
                  title=head)  # fmt: skip
        rows = self.to_dict()["candidates"]
        rows.sort(key=lambda r: (not r["feasible"], r["peak_to_peak_um"]))
        for r in rows:
            t.add(r["crowning_um"], r["relief_um"], r["peak_to_peak_um"], r["peak_pressure_MPa"],
                  100 * r["edge_share"], "yes" if r["feasible"] else "no")  # fmt: skip
        return t.text()

    def figure(self) -> Figure:
        """TE peak-to-peak over the two amounts, the infeasible region marked."""
        from ..plot.te import plot_layout

        return plot_layout(self)

    plot = figure


def layout_estimate(candidates: int, positions: int) -> Estimate:
    """Work of a layout: candidate-position solves, bounded by
    :data:`MAX_CANDIDATE_SOLVES`."""
    return Estimate(
        f"layout: {candidates} candidates x {positions} positions", 0.0,
        float(candidates * positions), "candidate-position solves", MAX_CANDIDATE_SOLVES,
        "grid=, refine=, positions=",
    )  # fmt: skip


def _axis(name: str, given: Sequence[float] | None, delta: float, grid: int) -> np.ndarray:
    if given is None:
        return np.linspace(0.0, 2.0 * delta, grid)
    a = np.unique(np.asarray(given, float))
    if a.ndim != 1 or a.size < 2 or not np.all(np.isfinite(a)) or a[0] < 0:
        raise ReducerlabError(f"{name}: must be at least two amounts >= 0 (m); got {given!r}")
    return a


@names_source
@with_compute_threads
def modification_layout(
    design: Any,
    pair: int = 1,
    *,
    torque: float | None = None,
    power: float | None = None,
    crowning: Sequence[float] | None = None,
    relief: Sequence[float] | None = None,
    grid: int = 3,
    refine: int = 1,
    positions: int = 12,
    cell: float | None = None,
    pressure_limit: float = DEFAULT_PRESSURE_LIMIT,
    edge_limit: float = DEFAULT_EDGE_LIMIT,
    tooth_size: float | None = None,
    compliance: tuple[Any, Any] | None = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
    partial: Callable[[LayoutResult], None] | None = None,
) -> LayoutResult:
    """Lead crowning and tip relief minimising the TE peak-to-peak at the design load.

    Parameters
    ----------
    design : NutationDesign or GearPairDesign
        As :func:`~reducerlab.analysis.contact.contact_analysis`.
    pair : int
    torque, power : float, optional
        The design load (N m on gear A, or W at the input speed); default the design's.
    crowning, relief : sequence of float, optional
        The coarse grid's amounts of lead crowning and tip relief of each flank (m);
        default ``grid`` values over ``[0, 2 delta]``.
    grid : int
        Values per amount of the coarse grid and of each refinement (2..7).
    refine : int
        Refinement rounds (0..3), each of half the last step.
    positions : int
        Positions over one mesh cycle of each candidate (>= 2).
    cell : float, optional
        Contact cell (m); default from a pilot position of the unmodified pair.
    pressure_limit : float
        Largest allowed cell pressure (Pa); default :data:`DEFAULT_PRESSURE_LIMIT`.
    edge_limit : float
        Largest allowed edge share (fraction, default 0.01).
    tooth_size : float, optional
    compliance : (ToothCompliance, ToothCompliance), optional
        Both gears' tooth compliances from an earlier run (any modifications).
    stage, progress : callable, optional
        ``stage(text)``; ``progress(done, total)`` per candidate.
    partial : callable, optional
        ``partial(result)`` after each candidate: the layout of the candidates evaluated
        so far (its best among them).
    """
    from ..contact.ltca import ContactGrid, loaded_contact
    from ..contact.modifications import (
        C_GAMMA,
        TIP_SHARE,
        FlankCoordinates,
        FlankModification,
        PairModifications,
    )
    from .contact import EDGE_BAND, PILOT, auto_cell, check_load
    from .contact_setup import pair_setup
    from .te_sweep import reference_load

    t0 = time.perf_counter()
    say = stage or (lambda _s: None)
    for name, v, lo, hi in (("grid", grid, 2, 7), ("refine", refine, 0, 3)):
        if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
            raise ReducerlabError(f"{name}: must be an integer in {lo}..{hi}; got {v!r}")
    if isinstance(positions, bool) or not isinstance(positions, int) or positions < 2:
        raise ReducerlabError(f"positions: must be an integer >= 2; got {positions!r}")
    for name, v in (("pressure_limit", pressure_limit), ("edge_limit", edge_limit)):
        if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
            raise ReducerlabError(f"{name}: must be a number > 0; got {v!r}")
    n_max = grid * grid * (1 + refine)
    layout_estimate(n_max, positions).check()
    T_d = reference_load(design, pair, power, torque)
    plain = pair_setup(design, pair, modifications=PairModifications())
    mp0, m_n = plain.mesh_pair, plain.module
    check_load(mp0, T_d, plain.load_radius, plain.E_star, None)
    coords = [FlankCoordinates.of(f) for f in (mp0.flank_a, mp0.flank_b)]
    delta = T_d / plain.load_radius / (coords[0].face * C_GAMMA)
    C_axis = _axis("crowning", crowning, delta, grid)
    R_axis = _axis("relief", relief, delta, grid)
    if compliance is None:
        plain.compliance_estimate(tooth_size).check()
        compliance = plain.compliances(tooth_size, say, None)
    kw = {"compliance_a": compliance[0], "compliance_b": compliance[1], "E_star": plain.E_star}
    phis = plain.start + plain.pitch * np.arange(positions) / positions
    if cell is None:
        say("pilot contact of the unmodified pair (grid size)")
        h = auto_cell(loaded_contact(mp0, T_d, phis[:1], ContactGrid(PILOT * m_n), **kw)[0], m_n)
    else:
        h = float(cell)
    grid_ = ContactGrid(h, edge_band=EDGE_BAND * m_n)
    done: dict[tuple[float, float], tuple[float, float, float, int]] = {}

    def evaluate(c: float, r: float, rnd: int) -> None:
        key = (round(c, 15), round(r, 15))
        if key in done:
            return
        mods = [FlankModification(lead_crowning=c, tip_relief=r,
                                  tip_relief_length=TIP_SHARE * k.profile,
                                  relief_shape="parabolic") for k in coords]  # fmt: skip
        mp = pair_setup(design, pair, modifications=PairModifications(*mods)).mesh_pair
        runs = loaded_contact(mp, T_d, phis, grid_, **kw)
        te = np.array([r_.unloaded_te + r_.loaded_te for r_ in runs]) * plain.te_radius
        peak = max(float(r_.pressure.max()) for r_ in runs)
        edge = max(r_.edge_share for r_ in runs)
        done[key] = (float(np.ptp(te)), peak, edge, rnd)
        if progress is not None:
            progress(len(done), n_max)
        if partial is not None:
            partial(result())

    def feasible(v: tuple[float, float, float, int]) -> bool:
        return v[1] <= pressure_limit and v[2] < edge_limit

    def score(item) -> tuple:
        (_, v) = item
        # feasible first by TE p-p; else nearest to feasibility (relative excess)
        excess = max(v[1] / pressure_limit - 1, 0) + max(v[2] / edge_limit - 1, 0)
        return (0, v[0]) if feasible(v) else (1, excess)

    def result() -> LayoutResult:
        """The layout of the candidates evaluated so far."""
        keys = list(done)
        vals = np.array([done[k] for k in keys])
        ok = np.array([feasible(done[k]) for k in keys])
        (bc, br), bv = min(done.items(), key=score)
        has_best = feasible(bv)
        zero = done.get((0.0, 0.0))
        ds = xr.Dataset(
            {
                "crowning": ("candidate", [k[0] for k in keys], {"units": "m"}),
                "relief": ("candidate", [k[1] for k in keys], {"units": "m"}),
                "peak_to_peak": ("candidate", vals[:, 0], {"units": "m"}),
                "peak_pressure": ("candidate", vals[:, 1], {"units": "Pa"}),
                "edge_share": ("candidate", vals[:, 2]),
                "feasible": ("candidate", ok.astype(np.int8)),
                "round": ("candidate", vals[:, 3].astype(np.int64)),
            },
            coords={"candidate": np.arange(len(keys))},
            attrs={
                "title": f"Flank modification layout, pair {pair}",
                **provenance(design.provenance),
            },
        )
        nan = float("nan")
        ds.attrs.update(
            pair=int(pair), pair_kind=plain.kind, design_torque=float(T_d), delta=float(delta),
            pressure_limit=float(pressure_limit), edge_limit=float(edge_limit),
            best_crowning=bc if has_best else nan, best_relief=br if has_best else nan,
            best_peak_to_peak=bv[0] if has_best else nan,
            unmodified_peak_to_peak=zero[0] if zero else nan,
            te_radius_m=plain.te_radius, cell_m=float(h), positions=int(positions),
            tip_relief_share=TIP_SHARE, relief_shape="parabolic",
            seconds=time.perf_counter() - t0,
        )  # fmt: skip
        return LayoutResult(ds)

    say(f"{C_axis.size * R_axis.size} candidates at {positions} positions")
    for c in C_axis:
        for r in R_axis:
            evaluate(float(c), float(r), 0)
    step_c, step_r = float(np.max(np.diff(C_axis))), float(np.max(np.diff(R_axis)))
    for rnd in range(1, refine + 1):
        (c0, r0), _ = min(done.items(), key=score)
        say(f"refinement {rnd} around C_beta {c0 * 1e6:.3g} um, C_a {r0 * 1e6:.3g} um")
        for c in np.linspace(c0 - step_c / 2, c0 + step_c / 2, grid):
            for r in np.linspace(r0 - step_r / 2, r0 + step_r / 2, grid):
                if c >= 0 and r >= 0:
                    evaluate(float(c), float(r), rnd)
        step_c, step_r = step_c / 2, step_r / 2
    return result()
