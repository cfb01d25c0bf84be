"""Loaded transmission error against torque: one mesh cycle at several loads (issue 29).

``te_sweep(design, pair, loads=6)`` runs the loaded tooth contact analysis
(``contact.ltca.loaded_contact``) of one gear pair over one mesh cycle at ``loads``
torques from zero to ``top`` (1.5) times the design load, and reports per torque the
transmission error over the cycle, its peak-to-peak value and its first mesh harmonics
(orders 1..3 of the mesh frequency); at zero torque the TE is the unloaded TE.

Unloaded TE: the tooth contact analysis takes the least ``t / lam`` over the coarse
points of its search grid and the fine contact cells (``unloaded_te``, as
``contact_analysis`` reports it); the loaded TE, solved on the fine cells, tends as the
load vanishes to the least over the fine cells alone (``grid_unloaded_te``), which is
the zero-torque row of ``te`` so that the curves are continuous in the torque. The two
differ by the sampling of the separation field: a conjugate contact line that falls
between cell centres leaves them open by up to ``(h/2)^2 / (2 rho_red)`` (cell ``h``,
reduced radius of curvature ``rho_red``): 0.24 um for 0.1 mm cells at the pitch point
of a z 20/20, m 3 mm spur pair (measured 0.23 um), a ripple of the grid's unloaded TE
over the cycle that scales with ``h^2``.

What is made once and what per torque:

* the finite-element tooth compliance of both gears (the large cost): once;
* the contact cell size: once, from a pilot position at the design load
  (``analysis.contact.auto_cell``, as ``contact_analysis`` does at that load), so that
  the row at the design load is the single-load analysis at it;
* at each position, the unloaded separations (TCA), the contact grid and the columns of
  the compliance matrix: once, for the largest torque (``loaded_contact(...,
  torques=...)``); the complementarity problem is then solved for each torque on them,
  warm started from the contact set of the next larger torque. The grid of the largest
  load holds every cell a smaller load closes, so each row equals a single-load run on
  the same cell to round-off.

Transmission error (``te``): the rotation of gear B behind its rigid-conjugate position,
``psi_0 + psi`` (``psi_0``: unloaded, ``psi``: elastic approach), given as a length at
``te_radius`` (``analysis.contact_setup``: the wheel's base radius of a spur pair, the
length along the line of action; the internal gear's mean radius of a nutation pair).
Harmonic ``r`` has amplitude ``2 |X_r| / N`` of the discrete Fourier transform ``X`` of
the ``N`` evenly spaced positions of one mesh cycle (the exact least-squares fit of
``sum A_r cos(r omega_m t + phi_r)``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..budget import Estimate
from ..design import Design
from ..errors import ReducerlabError, names_source
from ..numformat import Column, Table, fmt
from ..results import Result, provenance
from ..threads import with_compute_threads

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "MAX_LOADS",
    "MAX_SOLVES",
    "TESweepResult",
    "design_load",
    "reference_load",
    "te_sweep",
]

Array = NDArray[np.float64]
#: torques of one sweep at most
MAX_LOADS = 41
#: position-torque solves of one sweep at most (the documented work bound: 400 positions
#: of 10 loads, or 24 positions of 41 loads, each a few tenths of a second)
MAX_SOLVES = 4000
#: bytes kept per candidate cell and torque of one chunk of positions (forces, pressures
#: and the shared cell geometry: 14 float64 fields)
CELL_BYTES = 112


class TESweepResult(Result):
    """Loaded transmission error of one gear pair over a mesh cycle against torque.

    ``data`` has dimensions ``torque`` (coordinate: the torque on gear A, N m; the first
    is 0) and ``position`` (``angle``: gear A's rotation, rad). Variables: ``te``
    (torque, position; m at ``te_radius``), ``te_rotation`` (rad of gear B),
    ``unloaded_te`` (position; m: the tooth contact analysis's, as ``contact_analysis``
    reports it), ``grid_unloaded_te`` (position; m: that of the contact grid's cells, the
    limit of the loaded TE as the load vanishes, and the zero-torque row of ``te``),
    ``peak_to_peak`` (torque; m), ``harmonic_amplitude``
    (torque, ``order`` 1..; m), ``stiffness`` (torque, position; N/m secant mesh
    stiffness ``T_B / (arm^2 psi)``, NaN at zero torque), ``peak_pressure``,
    ``interior_pressure`` (Pa), ``edge_share`` and ``pairs`` (tooth pairs loaded).
    """

    kind: ClassVar[str] = "te-sweep"
    #: the tooth compliance of both gears (in memory only)
    compliance: tuple[Any, Any] | None = None

    @property
    def torques(self) -> Array:
        """Torques on gear A (N m)."""
        return np.asarray(self.data["torque"].values, float)

    @property
    def peak_to_peak(self) -> Array:
        """TE peak-to-peak at each torque (m)."""
        return np.asarray(self.data["peak_to_peak"].values, float)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: attributes and one row a torque."""
        ds = self.data
        rows = []
        for i, t in enumerate(self.torques):
            rows.append({
                "torque_N_m": float(t),
                "te_um": [1e6 * float(v) for v in ds["te"].values[i]],
                "peak_to_peak_um": 1e6 * float(ds["peak_to_peak"].values[i]),
                "harmonics_um": [1e6 * float(v) for v in ds["harmonic_amplitude"].values[i]],
                "peak_pressure_MPa": 1e-6 * float(np.nanmax(ds["peak_pressure"].values[i])),
                "edge_share_max": float(np.nanmax(ds["edge_share"].values[i])),
            })  # fmt: skip
        out = {k: (v.item() if hasattr(v, "item") else v) for k, v in ds.attrs.items()
               if k != "design"}  # fmt: skip
        out["angle_deg"] = [float(v) for v in np.degrees(ds["angle"].values)]
        out["torques"] = rows
        return out

    def table(self) -> str:
        """Plain-text table: one row a torque."""
        a = self.data.attrs
        orders = self.data.sizes["order"]
        t = Table([Column("T_A", "N m", "torque"), Column("T_B", "N m", "torque"),
                   Column("mean TE", "um", "length"), Column("p-p", "um", "length"),
                   *(Column(f"TE_{r}", "um", "length") for r in range(1, orders + 1)),
                   Column("p_max", "MPa", "stress"), Column("edge", "%", "percent")], title=(
            f"Pair {a['pair']} ({a['pair_kind']}): loaded TE over one mesh cycle "
            f"({self.data.sizes['position']} positions) against torque on "
            f"{a['gear_a']}; design load {fmt(a['design_torque'], 'torque')} N m; TE at "
            f"r = {fmt(1e3 * a['te_radius_m'], 'length')} mm"))  # fmt: skip
        ratio = a["torque_ratio"]
        for r in self.to_dict()["torques"]:
            tq = r["torque_N_m"]
            t.add(tq, tq * ratio, float(np.mean(r["te_um"])), r["peak_to_peak_um"],
                  *r["harmonics_um"], r["peak_pressure_MPa"],
                  100 * r["edge_share_max"])  # fmt: skip
        return t.text()

    def figure(self) -> Figure:
        """TE curves overlaid; peak-to-peak and harmonics against torque."""
        from ..plot.te import plot_te_sweep

        return plot_te_sweep(self)

    plot = figure


def design_load(design: Any, pair: int = 1) -> float:
    """The torque on pair ``pair``'s gear A (N m) at the design's load: a gear_pair's
    ``[operating]`` torque or power (on the pinion), a khv design's output torque (on the
    planet), a nutation design's torque flow (external gear of the pair).

    Raises
    ------
    ReducerlabError
        The design gives no load.
    """
    from ..drives.gear_pair import GearPairDesign

    if isinstance(design, GearPairDesign):
        point = design.operating_point()
        if not point.output_torque:
            raise ReducerlabError(
                "operating.torque/operating.power: the design gives no load; give the "
                "torque or power of the sweep (--torque, --power)"
            )
        return float(point.output_torque) / abs(float(point.ratio))
    if getattr(design, "type", None) == "khv":
        # the planet drives the output through the W mechanism: its torque is the output's
        point = design.operating_point()
        if not point.output_torque:
            raise ReducerlabError(
                "operating.output_torque/output_power: the design gives no load; give the "
                "torque or power (--torque, --power)"
            )
        return abs(float(point.output_torque))
    from .torque_flow import torque_flow

    flow = torque_flow(design)
    mesh = flow.meshes.get(f"mesh{pair}")
    if mesh is None or not flow.output_torque or mesh.external_torque is None:
        raise ReducerlabError(
            "output_torque/output_power: the design gives no load for the torque flow to "
            "load the pair; give the torque or power of the sweep (--torque, --power)"
        )
    return float(mesh.external_torque)


def reference_load(
    design: Any, pair: int = 1, power: float | None = None, torque: float | None = None
) -> float:
    """The design load (N m on gear A): ``torque``, ``power`` at the input speed, or the
    design's own."""
    if power is not None and torque is not None:
        raise ReducerlabError("load: give at most one of power (W) and torque (N m)")
    for name, v in (("torque", torque), ("power", power)):
        if v is not None and not (
            isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) and v > 0
        ):
            raise ReducerlabError(f"{name}: must be a number > 0; got {v!r}")
    if torque is not None:
        return float(torque)
    if power is not None:
        speed = design.operating_speed if isinstance(design, Design) else 0.0
        if not speed:
            raise ReducerlabError("power: the design has no input speed to turn power into torque")
        return float(power) / float(speed)
    return design_load(design, pair)


def sweep_torques(reference: float, loads: int, top: float) -> Array:
    """``loads`` torques evenly from 0 to ``top * reference`` (N m)."""
    if isinstance(loads, bool) or not isinstance(loads, int) or not 2 <= loads <= MAX_LOADS:
        raise ReducerlabError(f"loads: must be an integer in 2..{MAX_LOADS}; got {loads!r}")
    if not (isinstance(top, int | float) and math.isfinite(top) and 0 < top <= 3):
        raise ReducerlabError(f"top: must be a factor in (0, 3] of the design load; got {top!r}")
    return np.linspace(0.0, top * reference, loads)


def torque_list(
    design: Any, pair: int, loads: int, top: float, torques: Sequence[float] | None,
    power: float | None, torque: float | None,
) -> tuple[float, Array]:  # fmt: skip
    """The design load (:func:`reference_load`, N m on gear A) and the torques of a
    sweep (N m, sorted): ``torques`` as given, else ``loads`` from 0 to ``top`` times
    the design load (:func:`sweep_torques`).

    Raises
    ------
    ReducerlabError
        Other than 1..``MAX_LOADS`` finite torques ``>= 0``, one of them ``> 0``.
    """
    reference = reference_load(design, pair, power, torque)
    if torques is None:
        return reference, sweep_torques(reference, loads, top)
    try:
        T = np.sort(np.atleast_1d(np.asarray(torques, float)))
    except (TypeError, ValueError):
        raise ReducerlabError(f"torques: must be numbers (N m); got {torques!r}") from None
    if T.ndim != 1 or not 1 <= T.size <= MAX_LOADS or not np.all(np.isfinite(T)):
        raise ReducerlabError(f"torques: must be 1..{MAX_LOADS} finite torques (N m)")
    if T[0] < 0 or T[-1] <= 0:
        raise ReducerlabError("torques: must be >= 0 (N m), one of them > 0")
    return reference, T


def sweep_estimate(positions: int, loads: int, cells: float = 0.0, chunk: int = 1) -> Estimate:
    """Work (position-torque solves, bounded by :data:`MAX_SOLVES`) and memory of the
    results of one chunk of positions (``cells`` candidate cells a position)."""
    return Estimate(
        f"te sweep: {positions} positions x {loads} torques",
        CELL_BYTES * cells * chunk * loads, float(positions * loads),
        "position-torque solves", MAX_SOLVES, "--positions or --sweep (positions=, loads=)",
    )  # fmt: skip


def mesh_harmonics(te: Array, orders: int) -> Array:
    """Amplitudes of orders ``1..orders`` of the mesh frequency (unit of ``te``) of
    samples at ``N`` evenly spaced positions over one mesh cycle (last axis): ``2 |X_r|
    / N`` of the discrete Fourier transform."""
    n = te.shape[-1]
    X = np.fft.rfft(te, axis=-1)
    return 2.0 * np.abs(X[..., 1 : orders + 1]) / n


@names_source
@with_compute_threads
def te_sweep(
    design: Any,
    pair: int = 1,
    *,
    loads: int = 6,
    top: float = 1.5,
    torques: Sequence[float] | None = None,
    power: float | None = None,
    torque: float | None = None,
    positions: int = 24,
    harmonics: int = 3,
    cell: float | None = None,
    tooth_size: float | None = None,
    profile: str | None = None,
    misalignment: Any = None,
    modifications: Any = None,
    compliance: tuple[Any, Any] | None = None,
    teeth: Sequence[int] | None = None,
    observe: Callable[[int, int, Any], None] | None = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
    partial: Callable[[TESweepResult], None] | None = None,
) -> TESweepResult:
    """Loaded transmission error of one gear pair over a mesh cycle against torque.

    Parameters
    ----------
    design : NutationDesign or GearPairDesign
        As :func:`~reducerlab.analysis.contact.contact_analysis`.
    pair : int
        The gear pair (1 for a gear_pair).
    loads : int
        Torques from 0 to ``top`` times the design load, evenly (2..41).
    top : float
        Largest torque over the design load.
    torques : sequence of float, optional
        The torques on gear A (N m) instead of ``loads``/``top`` (0 allowed; sorted).
    power, torque : float, optional
        The design load as power (W) at the input speed or torque on gear A (N m);
        default the design's own (:func:`design_load`).
    positions : int
        Positions over one mesh cycle, ``>= 2 harmonics + 1``.
    harmonics : int
        Mesh orders reported (1..``harmonics``).
    cell : float, optional
        Contact cell (m); default from a pilot position at the design load.
    tooth_size : float, optional
        Finite-element tooth elements (m).
    profile, misalignment : optional
        As :func:`~reducerlab.analysis.contact.contact_analysis` (nutation pairs).
    modifications : contact.modifications.PairModifications, optional
        Flank modifications of gears A and B; default the design's. The compliance is
        the unmodified teeth's: ``compliance`` from a run with other modifications serves.
    compliance : (ToothCompliance, ToothCompliance), optional
        Both gears' tooth compliances from an earlier run of the same pair.
    teeth : sequence of int, optional
        Tooth pairs examined at each position (default ``-1, 0, 1``); beyond those, both
        compliances are extended by the gears' cyclic symmetry
        (``contact.compliance.extend_teeth``; the KHV load sharing, issue 30).
    observe : callable, optional
        ``observe(i, j, run)`` with each loaded ``PositionContact`` (torque ``i``,
        position ``j``) as it comes (``analysis.khv_sharing`` reads each pair's load).
    stage, progress : callable, optional
        ``stage(text)`` per step; ``progress(done, total)`` per position.
    partial : callable, optional
        ``partial(result)`` with the positions done so far (the others NaN), after each
        chunk of positions (then about an eighth of them, each chunk started from the
        last one's grid).

    Returns
    -------
    TESweepResult
    """
    from ..contact.ltca import ContactGrid, loaded_contact
    from .contact import EDGE_BAND, PILOT, auto_cell, check_load
    from .contact_setup import pair_setup

    t0 = time.perf_counter()
    say = stage or (lambda _s: None)
    reference, T = torque_list(design, pair, loads, top, torques, power, torque)
    if isinstance(harmonics, bool) or not isinstance(harmonics, int) or harmonics < 1:
        raise ReducerlabError(f"harmonics: must be an integer >= 1; got {harmonics!r}")
    if isinstance(positions, bool) or not isinstance(positions, int):
        raise ReducerlabError(f"positions: must be an integer; got {positions!r}")
    if positions < 2 * harmonics + 1:
        raise ReducerlabError(
            f"positions: {harmonics} mesh harmonics need >= {2 * harmonics + 1}; got {positions}"
        )
    sweep_estimate(positions, T.size).check()
    setup = pair_setup(design, pair, profile=profile, misalignment=misalignment,
                       modifications=modifications)  # fmt: skip
    mp, m_n = setup.mesh_pair, setup.module
    if cell is not None and not (
        isinstance(cell, int | float) and math.isfinite(cell) and 0 < cell <= 0.5 * m_n
    ):
        raise ReducerlabError(
            f"cell: must be a length in (0, m_n/2] = (0, {0.5 * m_n * 1e3:.4g} mm]; got {cell!r}"
        )
    t_max = float(T[-1])
    check_load(mp, t_max, setup.load_radius, setup.E_star, None)
    if compliance is None:
        setup.compliance_estimate(tooth_size).check()
        comp_a, comp_b = setup.compliances(tooth_size, say, None)
    else:
        comp_a, comp_b = compliance
    grid_teeth = ContactGrid.teeth if teeth is None else tuple(sorted(int(k) for k in teeth))
    if teeth is not None and comp_a is not None:
        from ..contact.compliance import extend_teeth

        comp_a, comp_b = extend_teeth(comp_a, grid_teeth), extend_teeth(comp_b, grid_teeth)
    t_fe = time.perf_counter() - t0
    kw = {"compliance_a": comp_a, "compliance_b": comp_b, "E_star": setup.E_star}
    phis = setup.start + setup.pitch * np.arange(positions) / positions
    s0 = ContactGrid.s_max
    if cell is None:
        say("pilot contact at the design load (grid size)")
        pilot = loaded_contact(mp, reference, phis[:1], ContactGrid(PILOT * m_n), **kw)[0]
        h = auto_cell(pilot, m_n)
        s0 = pilot.s_max
    else:
        h = float(cell)
    loaded = T[T > 0]
    n_chunk = positions if partial is None else max(1, math.ceil(positions / 8))
    shape = (T.size, positions)
    fields = {k: np.full(shape, np.nan) for k in ("approach", "peak", "interior", "edge", "pairs")}
    psi0 = np.full(positions, np.nan)
    grid0 = np.full(positions, np.nan)
    grid = ContactGrid(h, s_max=s0, edge_band=EDGE_BAND * m_n, teeth=grid_teeth)
    done = 0
    say(f"loaded contact at {positions} positions x {loaded.size} torques")
    while done < positions:
        stop = min(positions, done + n_chunk)

        def report(j: int, _n: int, first: int = done) -> None:
            if progress is not None:
                progress(first + j, positions)

        runs = loaded_contact(mp, t_max, phis[done:stop], grid, **kw, progress=report,
                              torques=loaded)  # fmt: skip
        for j, per_torque in enumerate(runs, start=done):
            psi0[j] = per_torque[0].unloaded_te
            grid0[j] = per_torque[0].grid_unloaded_te
            for i, r in zip(np.flatnonzero(T > 0), per_torque, strict=True):
                fields["approach"][i, j] = r.loaded_te
                fields["peak"][i, j] = r.pressure.max()
                fields["interior"][i, j] = r.interior_peak_pressure
                fields["edge"][i, j] = r.edge_share
                fields["pairs"][i, j] = len(np.unique(r.tooth[r.force > 0]))
                if observe is not None:
                    observe(int(i), j, r)
            sweep_estimate(positions, T.size, len(per_torque[0].force), n_chunk).check()
        for name in ("peak", "interior", "edge", "pairs"):  # no load, no contact
            fields[name][T == 0, done:stop] = 0.0
        # zero load: the limit of the loaded TE, the unloaded TE of the contact grid
        fields["approach"][T == 0, done:stop] = (grid0 - psi0)[done:stop]
        # the next chunk starts from this one's last grid (the completeness check widens it)
        grid = ContactGrid(h, s_max=runs[-1][-1].s_max, edge_band=EDGE_BAND * m_n,
                           teeth=grid_teeth)  # fmt: skip
        done = stop
        if partial is not None and done < positions:
            partial(_result(design, pair, setup, T, phis, (psi0, grid0), fields, harmonics,
                            reference, h, (comp_a, comp_b), t0, t_fe))  # fmt: skip
    return _result(design, pair, setup, T, phis, (psi0, grid0), fields, harmonics, reference,
                   h, (comp_a, comp_b), t0, t_fe)  # fmt: skip


def _result(design, pair, setup, T, phis, unloaded, f, harmonics, reference, h, comp, t0, t_fe):
    """The :class:`TESweepResult` of the positions done so far (others NaN)."""
    psi0, grid0 = unloaded
    rot = psi0[None, :] + f["approach"]
    te = rot * setup.te_radius
    ratio = setup.mesh_pair.torque_ratio
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(T[:, None] > 0, T[:, None] * ratio / (setup.arm**2 * f["approach"]), np.nan)
    ds = xr.Dataset(
        {
            "angle": ("position", phis, {"units": "rad"}),
            "te": (("torque", "position"), te, {"units": "m"}),
            "te_rotation": (("torque", "position"), rot, {"units": "rad"}),
            "unloaded_te": ("position", psi0 * setup.te_radius, {"units": "m"}),
            "grid_unloaded_te": ("position", grid0 * setup.te_radius, {"units": "m"}),
            "peak_to_peak": ("torque", np.ptp(te, axis=1), {"units": "m"}),
            "harmonic_amplitude": (
                ("torque", "order"),
                mesh_harmonics(te, harmonics),
                {"units": "m"},
            ),
            "stiffness": (("torque", "position"), k, {"units": "N/m"}),
            "peak_pressure": (("torque", "position"), f["peak"], {"units": "Pa"}),
            "interior_pressure": (("torque", "position"), f["interior"], {"units": "Pa"}),
            "edge_share": (("torque", "position"), f["edge"]),
            "pairs": (("torque", "position"), f["pairs"]),
        },
        coords={
            "torque": ("torque", T, {"units": "N m"}),
            "position": np.arange(len(phis)),
            "order": np.arange(1, harmonics + 1),
        },
        attrs={
            "title": f"Loaded transmission error against torque, pair {pair}",
            **provenance(design.provenance),
        },
    )
    ca, cb = comp
    ds.attrs.update(
        pair=int(pair), pair_kind=setup.kind, gear_a=setup.gears[0], gear_b=setup.gears[1],
        design_torque=float(reference), torque_ratio=float(ratio),
        te_radius_m=setup.te_radius, lever_arm_m=setup.arm, cell_m=float(h),
        mesh_frequency=setup.mesh_frequency, teeth_a=setup.teeth[0], teeth_b=setup.teeth[1],
        positions_done=int(np.isfinite(psi0).sum()),
        fe_dofs=0 if ca is None else ca.dofs + cb.dofs, fe_seconds=float(t_fe),
        seconds=time.perf_counter() - t0,
    )  # fmt: skip
    out = TESweepResult(ds)
    out.compliance = None if ca is None else comp
    return out
