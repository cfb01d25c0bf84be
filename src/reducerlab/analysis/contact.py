"""Loaded tooth contact analysis of a nutation design's gear pair (papers 001, 000 §2.3)
or of a spur ``gear_pair`` (pinion and wheel; ``analysis.contact_setup``).

``contact_analysis(design, pair, power=...)`` generates both gears of the pair from the
design's ``[surface]`` table (paper 001), builds the finite-element bending compliance
of each gear's teeth (``contact.compliance``), and runs the loaded tooth contact
analysis (``contact.ltca``) at evenly spaced positions over one mesh cycle. Per
position: unloaded and loaded transmission error, contact area, peak pressure, the
resultant contact force and its components, the largest subsurface von Mises stress
and its depth, and the mesh stiffness; over the cycle, the Fourier series of paper
000's Eq. 8 fitted to ``k(t)`` (default order 7).

Load: ``torque`` on the pair's external gear, or ``power`` with the design's
``input_speed`` as that gear's speed (paper 001's set-up: the external bevel gear on
the input shaft at 1500 rpm, 1 kW and 3 kW).
"""

from __future__ import annotations

import functools
import json
import math
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design
from ..errors import ReducerlabError, names_source
from ..numformat import Column, Table, fmt
from ..results import Result, provenance

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "ContactResult",
    "auto_cell",
    "check_load",
    "check_misalignment",
    "contact_analysis",
    "contact_pair",
    "design_with_contact",
    "design_with_mesh",
]

# the contact's k(t) into a design: its own module, importable from here as before
from ..threads import with_compute_threads
from .contact_mesh import design_with_contact, design_with_mesh

# the pairs of the designs (nutation, spur): their own module, importable from here
from .contact_setup import check_misalignment, contact_pair

Stage = Callable[[str], None]
#: cell of the pilot run that sizes the contact grid, in normal modules
PILOT = 0.1
#: cells across the narrowest contact patch of the pilot run (``auto_cell``)
ACROSS = 10
#: width of the flank-edge band (normal modules) outside which ``interior_pressure`` is
#: taken: fixed in length, so that it does not move with the grid
EDGE_BAND = 0.1
#: loaded cells the automatic grid aims to stay below
MAX_CELLS = 1200
#: bounds of the automatic cell, in normal modules
CELL_RANGE = (0.01, 0.1)
#: largest load, as the mean strain ``p / E*`` it would cause spread evenly over the
#: whole flank of every tooth pair examined: 1 %, above the yield strain of any gear
#: steel (about 0.7 % at 1.5 GPa), while the real contact band, a fraction of the
#: flank, carries many times that mean (``check_load``)
LOAD_STRAIN = 0.01


def auto_cell(run: Any, module: float) -> float:
    """Fine cell size (m) from a pilot position: ``ACROSS`` cells across the patch that
    carries the largest load (width = its area over its length along its long axis),
    at least so coarse that the pilot's loaded area holds ``MAX_CELLS`` cells, within
    ``CELL_RANGE`` normal modules. (Patches at the start or end of engagement are
    narrow but lightly loaded; sizing the grid on them would only cost time.)"""
    loaded = run.force > 0
    teeth = np.unique(run.tooth[loaded])
    main = max(teeth, key=lambda k: run.force[run.tooth == k].sum())
    m = (run.tooth == main) & loaded
    P = run.points[m]
    d = P - P.mean(axis=0)
    axis = np.linalg.svd(d, full_matrices=False)[2][0] if len(P) > 1 else np.zeros(3)
    length = float(np.ptp(d @ axis)) + math.sqrt(float(np.median(run.area[m])))
    w = float(run.area[m].sum()) / length
    floor = math.sqrt(float(run.area[loaded].sum()) / MAX_CELLS)
    lo, hi = CELL_RANGE
    return float(np.clip(max(w / ACROSS, floor), lo * module, hi * module))


class ContactResult(Result):
    """Loaded tooth contact over one mesh cycle of a gear pair.

    ``data`` has dimension ``position`` (angle of the external gear over one pitch, rad,
    and ``time`` at the design's speed) with ``unloaded_te`` and ``loaded_te`` (rad of
    the internal gear), ``te`` (loaded minus unloaded, m at the internal gear's mean
    radius), ``stiffness`` (N/m, paper 000's mesh stiffness), ``stiffness_fit``,
    ``contact_area`` (m^2), ``peak_pressure`` (Pa, over all cells), ``interior_pressure``
    (Pa, away from the flank edges) and ``edge_share`` (load fraction on edge cells: edge
    contact, where the computed pressure depends on the grid), ``normal_force`` (N, sum of the
    cell forces), ``force`` (N, components ``x, y, z`` of the resultant on the external
    gear in the pair's frame, ``axis`` dimension), ``von_mises`` (Pa, largest subsurface
    value under the interior cells) and ``von_mises_depth`` (m), ``pairs`` (tooth pairs
    in contact); dimension
    ``harmonic`` with ``amplitude`` (N/m) and ``phase`` (rad) of Eq. 8; dimension
    ``cell`` (the contact grid of every position, concatenated) with ``cell_position``,
    ``cell_tooth``, ``u``, ``v`` (flank parameters of the external gear), ``x, y, z``
    (m), ``area``, ``separation`` (m), ``cell_force`` (N), ``pressure`` (Pa) and ``edge``
    (1 on a flank edge); with ``root_stress``, dimensions ``gear`` and ``tooth_pair``
    with the root stresses of ``analysis.contact_rootstress.ROOT_VARIABLES``.
    """

    kind: ClassVar[str] = "contact"
    #: the tooth compliance of both gears (in memory only, not in the netCDF file)
    compliance: tuple[Any, Any] | None = None

    @property
    def stiffness(self) -> NDArray[np.float64]:
        """Mesh stiffness at each position (N/m)."""
        return np.asarray(self.data["stiffness"].values, float)

    @property
    def mean_stiffness(self) -> float:
        """``k_m`` of the Fourier fit (N/m)."""
        return float(self.data.attrs["k_mean"])

    def harmonics(self) -> tuple[list[float], list[float]]:
        """``(k_r, phi_r)`` of Eq. 8: amplitudes (N/m) and phases (rad)."""
        return (
            [float(v) for v in self.data["amplitude"].values],
            [float(v) for v in self.data["phase"].values],
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: attributes, one row a position, the Fourier terms."""
        ds = self.data
        rows = []
        for i in range(ds.sizes["position"]):
            f = ds["force"].values[i]
            rows.append({
                "angle_deg": float(np.degrees(ds["angle"].values[i])),
                "unloaded_te_urad": 1e6 * float(ds["unloaded_te"].values[i]),
                "te_um": 1e6 * float(ds["te"].values[i]),
                "stiffness_N_per_m": float(ds["stiffness"].values[i]),
                "contact_area_mm2": 1e6 * float(ds["contact_area"].values[i]),
                "peak_pressure_MPa": 1e-6 * float(ds["peak_pressure"].values[i]),
                "interior_pressure_MPa": 1e-6 * float(ds["interior_pressure"].values[i]),
                "edge_share": float(ds["edge_share"].values[i]),
                "normal_force_N": float(ds["normal_force"].values[i]),
                "force_N": [float(v) for v in f],
                "von_mises_MPa": 1e-6 * float(ds["von_mises"].values[i]),
                "von_mises_depth_mm": 1e3 * float(ds["von_mises_depth"].values[i]),
                "pairs_in_contact": int(ds["pairs"].values[i]),
            })  # fmt: skip
        amp, ph = self.harmonics()
        out = {k: _plain(v) for k, v in ds.attrs.items() if k not in ("design",)}
        out["positions"] = rows
        out["fourier"] = {
            "k_mean_N_per_m": float(ds.attrs["k_mean"]),
            "amplitudes_N_per_m": amp,
            "phases_rad": ph,
            "residual": float(ds.attrs["fit_residual"]),
        }
        return out

    def summary(self) -> dict[str, float]:
        """Cycle averages and extremes (SI)."""
        ds = self.data
        return {
            "contact_area_mean": float(ds["contact_area"].mean()),
            "peak_pressure_max": float(ds["peak_pressure"].max()),
            "interior_pressure_max": float(ds["interior_pressure"].max()),
            "edge_share_max": float(ds["edge_share"].max()),
            "von_mises_max": float(ds["von_mises"].max()),
            "force_x_mean_abs": float(np.abs(ds["force"].sel(axis="x")).mean()),
            "normal_force_mean": float(ds["normal_force"].mean()),
            "k_mean": float(ds.attrs["k_mean"]),
            "te_peak_to_peak": float(ds["te"].max() - ds["te"].min()),
        }

    def table(self) -> str:
        """Plain-text table over the cycle."""
        a = self.data.attrs
        t = Table([Column("angle", "deg", "angle"), Column("TE", "um", "length"),
                   Column("k", "N/m", "stiffness"), Column("area", "mm2"),
                   Column("p_max", "MPa", "stress"), Column("p_int", "MPa", "stress"),
                   Column("edge", "%", "percent"), Column("F_x", "N", "force"),
                   Column("vM_max", "MPa", "stress"), Column("depth", "mm", "length"),
                   Column("pairs", kind="count")], title=(
            f"Pair {a['pair']} ({a['profile']}): T_ext = {fmt(a['torque_external'], 'torque')} "
            f"N m, T_int = {fmt(a['torque_internal'], 'torque')} N m; k_m = "
            f"{fmt(a['k_mean'], 'stiffness')} N/m (Eq. 8, order {a['order']}, residual "
            f"{fmt(100 * a['fit_residual'], 'percent')} %)"))  # fmt: skip
        for r in self.to_dict()["positions"]:
            t.add(r["angle_deg"], r["te_um"], r["stiffness_N_per_m"], r["contact_area_mm2"],
                  r["peak_pressure_MPa"], r["interior_pressure_MPa"], 100 * r["edge_share"],
                  r["force_N"][0], r["von_mises_MPa"], r["von_mises_depth_mm"],
                  r["pairs_in_contact"])  # fmt: skip
        return t.text()

    def figure(self) -> Figure:
        """Pressure map, k(t) with its Fourier fit, TE and stress over the cycle."""
        from ..plot.contact import plot_contact

        return plot_contact(self)


def _plain(v: Any) -> Any:
    """An attribute as plain Python: a numpy scalar as its number, an array (a range
    read back from netCDF) as a list."""
    if hasattr(v, "tolist"):
        return v.tolist()
    return v.item() if hasattr(v, "item") else v


def _load(design: Any, power: float | None, torque: float | None) -> float:
    if (power is None) == (torque is None):
        raise ReducerlabError("load: give exactly one of power (W) and torque (N m)")
    if torque is not None:
        if not (isinstance(torque, (int, float)) and math.isfinite(torque) and torque > 0):
            raise ReducerlabError(f"torque: must be a number > 0 (N m); got {torque!r}")
        return float(torque)
    if not (isinstance(power, (int, float)) and math.isfinite(power) and power > 0):
        raise ReducerlabError(f"power: must be a number > 0 (W); got {power!r}")
    speed = design.operating_speed if isinstance(design, Design) else None
    if not speed:
        raise ReducerlabError("power: the design has no input_speed to turn power into torque")
    if getattr(design, "type", None) == "khv":  # the planet turns at the output speed
        speed = speed / abs(design.operating_point().ratio)
    return float(power) / float(speed)


def check_load(pair: Any, torque: float, radius: float, E_star: float, speed: float | None,
               power: bool = False) -> None:  # fmt: skip
    """Refuse a torque on the external gear that no elastic tooth contact carries.

    The normal force of the mesh is at least the tangential force ``torque / radius``
    (``radius``: the external gear's mean radius). Spread evenly over the whole flank of
    every tooth pair the contact grid examines, it must not strain the flanks by more
    than :data:`LOAD_STRAIN` (mean pressure ``LOAD_STRAIN E*``). Beyond it the solution
    is meaningless (the linear elastic contact model, the elastic approach as large as
    the contact) and the solver would widen its grid to whole flanks, for minutes,
    before failing; it is refused before any work.

    Raises
    ------
    ReducerlabError
        Naming the load (``power`` or ``torque``), the pressure, the bound and the largest
        load allowed.
    """
    from ..contact.ltca import ContactGrid, flank_size

    height, width = flank_size(pair.flank_a)
    area = len(ContactGrid.teeth) * height * width
    force = torque / radius
    limit = LOAD_STRAIN * E_star * area
    if force <= limit:
        return
    t_max = limit * radius
    what = (
        f"power: {torque * speed:.4g} W at {speed * 30 / math.pi:.5g} rpm ({torque:.4g} N m "
        "on the external gear)"
        if power and speed
        else f"torque: {torque:.4g} N m on the external gear"
    )
    most = f"{t_max * speed:.4g} W" if power and speed else f"{t_max:.4g} N m"
    raise ReducerlabError(
        f"{what} presses the teeth with at least {force:.4g} N: "
        f"{force / area * 1e-9:.4g} GPa spread over the whole flanks of the "
        f"{len(ContactGrid.teeth)} tooth pairs examined ({area * 1e6:.4g} mm^2), more than "
        f"{LOAD_STRAIN:.0%} of E* = {E_star * 1e-9:.4g} GPa: the flanks would yield "
        f"everywhere and no elastic contact exists; at most {most}"
    )


#: the fixed frame of a result's force vector, by pair kind
FRAMES = {
    "nutation": "x: normal of the plane of the two axes (tangential at the mesh); y: along "
    "the pitch line; z: crown gear axis",
    "spur": "fixed frame: z the pinion axis, x towards the wheel axis",
    "internal": "fixed frame: z the planet axis, x away from the ring axis",
}


@names_source
@with_compute_threads
def contact_analysis(
    design: Any,
    pair: int = 1,
    *,
    power: float | None = None,
    torque: float | None = None,
    positions: int = 24,
    order: int = 7,
    cell: float | None = None,
    face_cell: float | None = None,
    profile: str | None = None,
    misalignment: Any = None,
    tooth_size: float | None = None,
    rigid: bool = False,
    compliance: tuple[Any, Any] | None = None,
    workers: int | None = None,
    stage: Stage | None = None,
    progress: Callable[[int, int], None] | None = None,
    modifications: Any = None,
    root_stress: bool = False,
) -> ContactResult:
    """Loaded tooth contact analysis of one gear pair over a mesh cycle.

    Parameters
    ----------
    design : NutationDesign, GearPairDesign or KHVDesign
        A nutation design with ``[surface]`` (and ``[material]``, default paper 000's
        steel), a spur ``gear_pair`` with ``mesh.face_width`` (pinion = the "external"
        gear A, wheel = the "internal" gear B; lever ``r_b2``), or a ``khv`` design's
        internal pair (planet = gear A, ring = gear B; lever ``r_b2`` of the ring; the
        ring's compliance covers tooth pairs -1, 0, 1 only: ``analysis.contact_setup``).
    pair : int
        1 (gears 1-2) or 2 (gears 3-4); 1 for a gear_pair.
    power, torque : float
        Exactly one: power (W) at the design's input speed on the external gear (the
        pinion; a khv design's planet at the output speed), or the torque on it (N m).
    positions : int
        Positions over one mesh cycle (one pitch of the external gear), >= 2 order + 1.
    order : int
        Harmonics of the Eq. 8 fit (paper 000: 7).
    cell : float, optional
        Fine contact cell (m), along the profile and the face; default from pilot runs
        at the analysed positions (cells of ``0.1 m_n``): 3 cells across the Hertz
        half-width of the narrowest patch of the cycle, 40 along the shortest, at most
        ``MAX_CELLS`` loaded cells, each within ``CELL_RANGE``
        (``contact.ltca.auto_grid``; profile and face cells differ); ``0.1 m_n`` when ``rigid``.
    face_cell : float, optional
        Fine contact cell along the face (m), with ``cell`` (then the profile's); default
        ``cell``. ``attrs["cell_m"]`` and ``attrs["face_cell_m"]`` of a result give its
        grid, e.g. to halve it.
    profile : {"involute", "double-arc"}, optional
        Overrides ``surface.profile``.
    misalignment : contact.flanks.Misalignment, optional
    tooth_size : float, optional
        Element size of the finite-element tooth models (m); default ``0.3 m_n``.
    rigid : bool
        Teeth rigid beyond the local (half-space) contact deformation: no
        finite-element models (a quick estimate of the contact pattern; the mesh
        stiffness is then far too high).
    compliance : (ToothCompliance, ToothCompliance), optional
        The external and internal gears' tooth compliance from an earlier run
        (``result.compliance``) of the same pair and profile: skips the finite-element
        models when only the load changes.
    workers : int, optional
        Processes (this one included): the two gears' compliances at once and the
        positions in chunks (``analysis.contact_workers``); default 2 on a machine with
        two cores or more and elastic teeth, 1 when ``rigid``. The results are those of
        one process, to rounding.
    stage, progress : callable, optional
        ``stage(text)`` at each preparation step; ``progress(done, total)`` per position.
    modifications : contact.modifications.PairModifications, optional
        Flank modifications of the external (``a``) and internal (``b``) gear; default
        the design's (``[gearN.modifications]``, ``surface.flank_modifications``). The
        tooth compliance is that of the unmodified teeth: ``compliance`` from a run with
        other modifications serves unchanged.
    root_stress : bool
        Also the tooth-root stresses of both gears at every position (the tooth models'
        fillet stress influence, ``analysis.contact_rootstress``).
    """
    from ..contact.ltca import ContactGrid, auto_grid, grid_estimate, loaded_contact
    from ..contact.meshstiffness import fit_fourier
    from .contact_law import TANGENT_LOAD, add_load_exponent, split_loads
    from .contact_rootstress import add_root_stress, check_root_compliance
    from .contact_setup import pair_setup
    from .contact_workers import contact_pool, contact_processes

    t0 = time.perf_counter()
    say = stage or (lambda _s: None)
    T_a = _load(design, power, torque)
    if isinstance(positions, bool) or not isinstance(positions, int) or positions < 2:
        raise ReducerlabError(f"positions: must be an integer >= 2; got {positions!r}")
    if isinstance(order, bool) or not isinstance(order, int) or order < 0:
        raise ReducerlabError(f"order: must be an integer >= 0; got {order!r}")
    if 2 * order + 1 > positions:
        raise ReducerlabError(
            f"order: {order} harmonics need positions >= {2 * order + 1}; got {positions}"
        )
    setup = pair_setup(design, pair, profile=profile, misalignment=misalignment,
                       modifications=modifications)  # fmt: skip
    mp, m_n = setup.mesh_pair, setup.module
    if cell is not None and not (
        isinstance(cell, (int, float)) and math.isfinite(cell) and 0 < cell <= 0.5 * m_n
    ):
        raise ReducerlabError(
            f"cell: must be a length in (0, m_n/2] = (0, {0.5 * m_n * 1e3:.4g} mm]; got {cell!r}"
        )
    nu, E_star = setup.material.nu, setup.E_star
    check_load(mp, T_a, setup.load_radius, E_star, design.operating_speed, power is not None)
    if face_cell is not None and (cell is None or not (
        isinstance(face_cell, (int, float)) and math.isfinite(face_cell)
        and 0 < face_cell <= 0.5 * m_n
    )):  # fmt: skip
        raise ReducerlabError(
            f"face_cell: must be a length in (0, m_n/2] = (0, {0.5 * m_n * 1e3:.4g} mm], "
            f"given with cell; got {face_cell!r} (cell {cell!r})"
        )
    if cell is not None:
        grid_estimate(mp, ContactGrid(float(cell), face_cell=face_cell)).check()
    if root_stress:
        check_root_compliance(compliance, rigid)
    n = contact_processes(workers, rigid=rigid, positions=positions)
    fe = compliance is None and not rigid
    if fe:
        setup.compliance_estimate(tooth_size, root_stress).check()
    phis = setup.start + setup.pitch * np.arange(positions) / positions
    with contact_pool(n) as pool:
        comp_a, comp_b = None, None
        if compliance is not None and not rigid:
            comp_a, comp_b = compliance
        elif fe:
            comp_a, comp_b = setup.compliances(tooth_size, say, pool, root_stress)
        kw = {"compliance_a": comp_a, "compliance_b": comp_b, "E_star": E_star}
        s0 = ContactGrid.s_max
        h_v = None
        if cell is None and rigid:
            h = PILOT * m_n  # the quick pattern: the pilot's grid
        elif cell is None:
            say(f"pilot contact at {positions} positions (grid size)")
            pilot = loaded_contact(mp, T_a, phis, ContactGrid(PILOT * m_n), **kw)
            h, h_v = auto_grid(mp, pilot, E_star, PILOT * m_n,
                               (CELL_RANGE[0] * m_n, CELL_RANGE[1] * m_n), MAX_CELLS)  # fmt: skip
            s0 = pilot[0].s_max  # the separation the pilot needed: the first guess
            grid_estimate(mp, ContactGrid(h, face_cell=h_v)).check()
        else:
            h, h_v = float(cell), None if face_cell is None else float(face_cell)
        say(f"loaded contact at {positions} positions" + (f" ({n} processes)" if pool else ""))
        grid = ContactGrid(h, s_max=s0, edge_band=EDGE_BAND * m_n, face_cell=h_v)
        kw["torques"] = (T_a, TANGENT_LOAD * T_a)  # and the load exponent (contact_law)
        if pool is None:
            runs, low = split_loads(loaded_contact(mp, T_a, phis, grid, **kw, progress=progress))
            vm, depth = _stresses(runs, nu, h)
        else:  # each process the stresses of its positions too
            post = functools.partial(_stresses, nu=nu, cell=h)
            raw, (vm, depth) = pool.positions((mp, T_a), phis, {"grid": grid, **kw}, progress,
                                              post)  # fmt: skip
            runs, low = split_loads(raw)
    # lever of the lumped model's mesh on gear B (paper 000 Eq. 2-4; spur: r_b2)
    arm = setup.arm
    T_b = runs[0].torque
    approach = np.array([r.loaded_te for r in runs])
    k = T_b / (arm**2 * approach)
    fit = fit_fourier(k, order)
    f_mesh = setup.mesh_frequency
    force = np.array([r.force_vector for r in runs])
    cells = _cells_dataset(runs)
    ds = xr.Dataset(
        {
            "angle": ("position", phis, {"units": "rad"}),
            "time": ("position", _times(positions, f_mesh), {"units": "s"}),
            "unloaded_te": ("position", [r.unloaded_te for r in runs], {"units": "rad"}),
            "loaded_te": ("position", approach + [r.unloaded_te for r in runs], {"units": "rad"}),
            "te": ("position", approach * setup.te_radius, {"units": "m"}),
            "stiffness": ("position", k, {"units": "N/m"}),
            "stiffness_fit": (
                "position",
                fit(2 * math.pi * np.arange(positions) / positions),
                {"units": "N/m"},
            ),
            "contact_area": ("position", [r.contact_area for r in runs], {"units": "m^2"}),
            "peak_pressure": ("position", [r.pressure.max() for r in runs], {"units": "Pa"}),
            "interior_pressure": (
                "position",
                [r.interior_peak_pressure for r in runs],
                {"units": "Pa"},
            ),
            "edge_share": ("position", [r.edge_share for r in runs]),
            "normal_force": ("position", [r.force.sum() for r in runs], {"units": "N"}),
            "force": (("position", "axis"), force, {"units": "N"}),
            "von_mises": ("position", vm, {"units": "Pa"}),
            "von_mises_depth": ("position", depth, {"units": "m"}),
            "pairs": ("position", [len(np.unique(r.tooth[r.force > 0])) for r in runs]),
            "amplitude": ("harmonic", fit.amplitudes, {"units": "N/m"}),
            "phase": ("harmonic", fit.phases, {"units": "rad"}),
            **cells,
        },
        coords={
            "position": np.arange(positions),
            "axis": ["x", "y", "z"],
            "harmonic": np.arange(1, order + 1),
        },
        attrs={"title": f"Loaded tooth contact, pair {pair}", **provenance(design.provenance)},
    )
    ds.attrs.update(
        pair=int(pair), profile=setup.profile, pair_kind=setup.kind,
        gear_a=setup.gears[0], gear_b=setup.gears[1],
        teeth_external=setup.teeth[0], teeth_internal=setup.teeth[1],
        torque_external=T_a, torque_internal=T_b, speed=float(design.input_speed),
        mesh_frequency=f_mesh, k_mean=fit.mean, fit_residual=fit.residual, order=order,
        cell_m=h, face_cell_m=grid.cell_v, rigid=int(rigid), lever_arm_m=arm,
        modifications=json.dumps(mp.modifications.to_dict()),
        fe_dofs=0 if comp_a is None else comp_a.dofs + comp_b.dofs,
        seconds=time.perf_counter() - t0,
        frame=FRAMES[setup.kind],
        flank_u_range=[float(x) for x in mp.flank_a.u_range],
        flank_tip_end=int(getattr(mp.flank_a, "tip_end", 1)),
    )  # fmt: skip
    ds = add_load_exponent(ds, runs, low, arm)
    if root_stress:
        ds = add_root_stress(ds, mp, runs, comp_a, comp_b)
    out = ContactResult(ds)
    out.compliance = None if comp_a is None else (comp_a, comp_b)
    return out


def _times(positions: int, f_mesh: float) -> NDArray:
    """Time of each position (s) at the mesh frequency; NaN for a design at rest."""
    if not f_mesh:
        return np.full(positions, np.nan)
    return np.arange(positions) / (positions * f_mesh)


def _stresses(runs: list, nu: float, cell: float) -> tuple[NDArray, NDArray]:
    """Largest subsurface von Mises stress (Pa) and its depth (m) at each position,
    under the interior cells (outside the flank-edge band, where the field does not
    depend on the grid), over the contact patches of all tooth pairs, each patch on the
    tangent plane of its peak cell (``contact.halfspace.subsurface_stress``); of a
    load sweep's positions (lists), the first load's."""
    from scipy.optimize import minimize_scalar

    from ..contact.halfspace import subsurface_stress, von_mises

    runs = [r[0] if isinstance(r, list) else r for r in runs]

    depths = np.linspace(1.0, 30.0, 59) * cell
    vm, depth = [], []
    for r in runs:
        best = (0.0, math.nan)
        loaded = r.force > 0
        for k in np.unique(r.tooth[loaded]):
            m = (r.tooth == k) & loaded
            inner = m & ~r.edge
            if not inner.any():
                continue
            i0 = np.flatnonzero(inner)[np.argmax(r.pressure[inner])]
            n0 = r.normals[i0]
            e1 = np.cross(n0, [0.0, 0.0, 1.0])
            if np.linalg.norm(e1) < 1e-6:
                e1 = np.cross(n0, [1.0, 0.0, 0.0])
            e1 /= np.linalg.norm(e1)
            e2 = np.cross(n0, e1)
            d = r.points[m] - r.points[i0]
            xy = np.stack([d @ e1, d @ e2], axis=1)
            half = 0.5 * np.sqrt(r.area[m])
            p = r.pressure[m]
            # search under the most loaded interior cells
            cand = np.flatnonzero(inner[m])
            cand = cand[np.argsort(p[cand])[-40:]]

            def field(pts: NDArray, xy=xy, half=half, p=p) -> NDArray:
                return von_mises(subsurface_stress(xy, half, half, p, pts, nu))

            pts = np.array([[*xy[c], z] for c in cand for z in depths])
            v = field(pts)
            j = int(np.argmax(v))
            c, z0 = cand[j // len(depths)], depths[j % len(depths)]
            res = minimize_scalar(
                lambda z, q=xy[c], f=field: -f(np.array([[*q, z]]))[0],
                bounds=(max(depths[0], z0 - cell), z0 + cell), method="bounded",
                options={"xatol": 1e-3 * cell},
            )  # fmt: skip
            if -res.fun > best[0]:
                best = (float(-res.fun), float(res.x))
        vm.append(best[0])
        depth.append(best[1])
    return np.array(vm), np.array(depth)


def _cells_dataset(runs: list) -> dict[str, Any]:
    cat = lambda f: np.concatenate([f(r) for r in runs])  # noqa: E731
    pos = cat(lambda r: np.full(len(r.force), runs.index(r)))
    P = cat(lambda r: r.points)
    return {
        "cell_position": ("cell", pos),
        "cell_tooth": ("cell", cat(lambda r: r.tooth)),
        "u": ("cell", cat(lambda r: r.uv[:, 0])),
        "v": ("cell", cat(lambda r: r.uv[:, 1])),
        "x": ("cell", P[:, 0], {"units": "m"}),
        "y": ("cell", P[:, 1], {"units": "m"}),
        "z": ("cell", P[:, 2], {"units": "m"}),
        "area": ("cell", cat(lambda r: r.area), {"units": "m^2"}),
        "separation": ("cell", cat(lambda r: r.separation), {"units": "m"}),
        "cell_force": ("cell", cat(lambda r: r.force), {"units": "N"}),
        "pressure": ("cell", cat(lambda r: r.pressure), {"units": "Pa"}),
        "edge": ("cell", cat(lambda r: r.edge).astype(np.int8)),
    }
