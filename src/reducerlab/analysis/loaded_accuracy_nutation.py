"""Transmission accuracy of the nutation drive under load: each mesh's loaded
transmission error through the drive's two stages (issue 31).

``transmission_accuracy(design, load=...)`` of a ``nutation`` design (single- or
double-sided, with ``[surface]``) adds to the rigid law of the gears' errors
(``analysis.accuracy_drives.nutation_sources``,
:mod:`reducerlab.kinematics.accuracy_nutation`) the loaded static transmission error of
each of its meshes: the loaded tooth contact analysis of pair ``j`` over one mesh cycle
(``analysis.te_sweep``, one torque), ``TE_j(phi)``: gear B's rotation ``psi_j`` behind
its rigid-conjugate position times ``te_radius = r_mB``. Gear A of pair ``j`` is the
central external gear ``2j`` (2, 4), gear B the nutating internal gear ``2j - 1`` (1,
3; ``analysis.contact_setup.pair_setup``).

**The TE as an equivalent rotation.** The lumped model's mesh deflection (paper 000
Eq. 2-4, ``drives.nutation``) is ``lambda = ... + a_y r_mn theta_n - a_y r_mc theta_c``
and the rigid law keeps ``r_mn (d theta_n + epsilon_n) = r_mc (d theta_c +
epsilon_c)``: a compression ``lambda`` of the mesh, made by the rotations with the
flanks perfect, is the same closure as an equivalent rotation of the nutating gear B
``epsilon_B = -lambda / (a_y r_mB)`` (and none of gear A). The contact's ``psi_j`` is
that compression on the flank the load presses, over the mesh lever ``a_y r_mB``
(``PairSetup.arm``): ``lambda_j = s_j a_y r_mB psi_j`` with ``s_j = +1`` or ``-1`` the
sign of the model's ``lambda_j`` under the drive's load. Hence

``epsilon_Bj = -s_j psi_j = -s_j TE_j / r_mB``,

passed through the two stages exactly as the law passes a gear error (``output_rotation``:
``d theta_13 = (r_m2 / r_m1) eps_2 - eps_1``, ``d theta_4 = (r_m3 / r_m4)(d theta_13 +
eps_3) - eps_4``; the output's error is ``sgn(i)`` times it). The sign ``s_j`` follows
from statics: the train is statically determinate (the output torque fixes each
mesh's force), so by virtual work a mesh's elastic approach under the load moves the output
with the load torque, against its turning sense: the output lags. With ``c_j`` the
law's gain of ``epsilon_Bj`` (``-1``, ``-r_m3 / r_m4`` for gear 1 of the single- and
double-sided drive, ``r_m3 / r_m4`` for gear 3) that gives ``s_j = sgn(i) sgn(c_j)``
and the output error ``-|c_j| TE_j / r_mB``: mesh 1 of the double-sided drive turns the
body back by ``TE_1 / r_m1``, carried to gear 4 by ``r_m3 / r_m4``; mesh 2 turns gear 4
back by ``TE_2 / r_m4``. ``s_j`` is checked against the model's own mesh forces in
``tests/test_loaded_accuracy_nutation.py`` (its output load and reaction through the
mesh levers: ``s_1 = -1`` for both examples, ``s_2 = +1`` double-sided, ``i > 0``).

**Periodicity.** ``TE_j`` repeats every tooth of gear A in the crank frame, the mesh
cycle: ``n_j = 2 pi |i| f_z,j(omega_in = 1)`` cycles per output revolution (the
kinematics' mesh frequencies): ``26 x 14 = 364`` for examples/nutation_surface.toml,
``26 x 105 = 2730`` and ``30 x 104 = 3120`` for examples/nutation_double_sided.toml.
The ``N`` positions of the cycle are carried to the output angle ``u`` by their
periodic piecewise-linear interpolant at the mesh phase ``n_j u``
(``analysis.loaded_accuracy.cycle_to_output``: position 0 at ``u = 0``, the cycle in
the order of the contact's positions; both meshes start in phase, which the contact
analysis does not fix). By default the output samples are the least whole multiple of
``lcm_j(n_j N_j)`` from 4096 (every position of each mesh a sample; 2**20 where that
multiple is larger).

The mean of each mesh's mapped TE is its **elastic wind-up** at the load: reported
apart (``wind_up_arcsec``, their sum, positive: the output lags; ``mesh_wind_up_arcsec``
per mesh); the trace holds the variations about them as the sources ``mesh 1 under
load``, ``mesh 2 under load``. The wind-up is the tooth contact's and bending's only
(the nutating body's bearings and the output coupling are not in it). The variations
and the rigid manufacturing errors add (first-order superposition, as
``analysis.loaded_accuracy``).

The load ``T_out`` (N m on the output, or ``"design"``) is carried losslessly to gear A
of each pair by the drive's torque flow (``kinematics.torques.mesh_torques``, as
``analysis.te_sweep.design_load`` does at the design load): ``T_out (1 - 1 / i)`` on the
fixed gear 2 (the output's torque less the input's), ``T_out`` on the output gear 4.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..kinematics.accuracy_nutation import output_rotation
from ..kinematics.torques import mesh_torques
from ..numformat import fmt
from .loaded_accuracy import (
    ARCSEC,
    check_options,
    check_samples,
    check_sweep,
    cycle_to_output,
    mesh_te,
    output_load,
)

__all__ = [
    "LoadedNutationError",
    "MeshGain",
    "mesh_gains",
    "mesh_orders",
    "nutation_loaded_error",
    "nutation_loaded_samples",
    "nutation_mesh_te",
    "pair_torques",
]

Array = NDArray[np.float64]

#: output samples at most (``transmission_accuracy``'s bound)
MAX_SAMPLES = 2**20


def _pairs(design: Any) -> int:
    if getattr(design, "type", None) != "nutation":
        raise ReducerlabError(
            f"design: the nutation drive's loaded accuracy needs a nutation design; got a "
            f"{getattr(design, 'type', None) or type(design).__name__} design"
        )
    return 2 if design.sides == "double" else 1


def pair_torques(design: Any, t_out: float) -> list[float]:
    """The torque on gear A (the central external gear 2, 4) of each pair (N m) at
    ``t_out`` (N m, > 0) on the output, lossless: the torque flow
    (``kinematics.torques.mesh_torques`` at the design's input speed)."""
    n = _pairs(design)
    point = design.operating_point()
    flow = mesh_torques(design.kinematics(), float(t_out), float(point.input_speed or 0.0))
    meshes = [flow.meshes[f"mesh{j}"] for j in range(1, n + 1)]
    return [abs(float(m.torque(m.external))) for m in meshes]


def mesh_orders(design: Any) -> list[int]:
    """Mesh cycles of each pair per output revolution, ``n_j = 2 pi |i| f_z,j(1)``.

    Raises
    ------
    ReducerlabError
        When one is not a whole number (its loaded TE would not repeat over one turn).
    """
    n = _pairs(design)
    kin = design.kinematics()
    out = []
    for j, f in enumerate(list(kin.mesh_frequencies(1.0).values())[:n], start=1):
        c = 2 * math.pi * abs(float(kin.ratio)) * float(f)
        if not (c >= 1 and abs(c - round(c)) < 1e-6 * c):
            raise ReducerlabError(
                f"load: mesh {j}'s tooth mesh repeats {c:.6g} times per output revolution, "
                "not a whole number; the loaded TE over one output revolution needs one"
            )
        out.append(round(c))
    return out


@dataclass(frozen=True)
class MeshGain:
    """How pair ``j``'s TE moves the output (module docstring).

    Attributes
    ----------
    gear : str
        Gear B, the nutating gear (``"gear 1"``, ``"gear 3"``).
    mean_radius : float
        ``r_mB`` (m).
    lever : float
        ``c_j``: the law's output rotation (crank frame, model's ``rz`` sense) per unit
        equivalent rotation ``epsilon_B``.
    flank : int
        ``s_j``: the sign of the model's mesh deflection under the load.
    """

    gear: str
    mean_radius: float
    lever: float
    flank: int

    def output_error(self, te: Array, sense: float) -> Array:
        """The output's error in its turning sense (rad) of ``te`` (m at ``r_mB``):
        ``sgn(i) c_j epsilon_B``, ``epsilon_B = -s_j TE / r_mB``; ``sense = sgn(i)``."""
        return sense * self.lever * (-self.flank * np.asarray(te, float) / self.mean_radius)


def mesh_gains(design: Any) -> list[MeshGain]:
    """Each pair's :class:`MeshGain`: ``c_j`` from the two-stage law
    (``kinematics.accuracy_nutation.output_rotation`` of a unit ``epsilon_B``) and
    ``s_j = sgn(i) sgn(c_j)`` (the output lags under the load)."""
    n = _pairs(design)
    double = n == 2
    radii = {f"gear {k}": getattr(design, f"gear{k}").mean_radius for k in range(1, 2 * n + 1)}
    sense = math.copysign(1.0, float(design.kinematics().ratio))
    out = []
    for j in range(1, n + 1):
        gear = f"gear {2 * j - 1}"
        c = float(output_rotation({gear: np.ones(1)}, radii, double)[0])
        out.append(MeshGain(gear, radii[gear], c, int(sense * math.copysign(1.0, c))))
    return out


def nutation_loaded_samples(
    design: Any, positions: int, sweeps: Any = None, least: int = 4096
) -> int:
    """The default output samples under load: the least whole multiple of
    ``lcm_j(n_j N_j)`` not below ``least`` (``N_j`` the positions of ``sweeps`` where
    given), or ``2**20`` where that is larger."""
    check_options(positions, False)
    orders = mesh_orders(design)
    given = _sweep_list(design, sweeps) if sweeps is not None else [None] * len(orders)
    step = 1
    for n, s in zip(orders, given, strict=True):
        step = math.lcm(step, n * (positions if s is None else int(s.data.sizes["position"])))
    samples = step * max(1, math.ceil(least / step))
    return samples if samples <= MAX_SAMPLES else MAX_SAMPLES


def _sweep_list(design: Any, sweeps: Any) -> list[Any]:
    """``sweeps`` (one ``TESweepResult`` per pair: a list in pair order, a mapping by
    pair number, or one result for a single-sided drive) as a list by pair."""
    n = _pairs(design)
    if isinstance(sweeps, Mapping):
        if sorted(sweeps) != list(range(1, n + 1)):
            raise ReducerlabError(
                f"mesh_te: a mapping must have the pairs 1..{n} as keys; got {sorted(sweeps)}"
            )
        out = [sweeps[j] for j in range(1, n + 1)]
    elif isinstance(sweeps, Sequence) and not isinstance(sweeps, str):
        out = list(sweeps)
    else:
        out = [sweeps]
    if len(out) != n:
        raise ReducerlabError(
            f"mesh_te: one loaded TE (te_sweep result) per pair, {n} for a {design.sides}-sided "
            f"drive; got {len(out)}"
        )
    for j, s in enumerate(out, start=1):
        data = getattr(s, "data", None)
        attrs = getattr(data, "attrs", {})
        teeth = (getattr(design, f"gear{2 * j}").teeth, getattr(design, f"gear{2 * j - 1}").teeth)
        if (data is None or attrs.get("pair_kind") != "nutation" or attrs.get("pair") != j
                or (attrs.get("teeth_a"), attrs.get("teeth_b")) != teeth):  # fmt: skip
            raise ReducerlabError(
                f"mesh_te[{j}]: must be pair {j}'s te_sweep result of this nutation design; "
                f"got {type(s).__name__} (pair {attrs.get('pair')!r}, kind "
                f"{attrs.get('pair_kind')!r}, teeth {attrs.get('teeth_a')!r}/"
                f"{attrs.get('teeth_b')!r})"
            )
    return out


def nutation_mesh_te(
    design: Any,
    torques: Sequence[float],
    *,
    positions: int = 24,
    rigid: bool = False,
    tooth_size: float | None = None,
    cell: float | None = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> list[Any]:
    """Each pair's loaded TE over one mesh cycle at its torque ``torques[j]`` on gear A
    (N m; :func:`pair_torques`): ``analysis.loaded_accuracy.mesh_te`` of pair ``j``
    (half-space teeth with ``rigid``; ``cell``: the contact cell, m, default the
    contact's own choice at the load). Every pair's work and memory (the sweep's solves,
    the finite-element tooth models) is checked before the first contact runs.

    Raises
    ------
    ReducerlabError, BudgetError
        Bad options; a pair's work or memory over the bounds.
    """
    from .contact_setup import pair_setup
    from .te_sweep import sweep_estimate

    n = _pairs(design)
    if len(torques) != n:
        raise ReducerlabError(f"torques: one per pair ({n}); got {len(torques)}")
    check_options(positions, rigid)
    sweep_estimate(positions, n).check()
    for j in range(1, n + 1):
        if not rigid:
            pair_setup(design, j).compliance_estimate(tooth_size).check()
    return [mesh_te(design, float(t), pair=j, positions=positions, rigid=rigid, cell=cell,
                    tooth_size=tooth_size, stage=stage, progress=progress)
            for j, t in enumerate(torques, start=1)]  # fmt: skip


@dataclass(frozen=True)
class LoadedNutationError:
    """The loaded meshes' share of a nutation drive's output angle error.

    Attributes
    ----------
    variations : list of ndarray
        Each mesh's output angle error about its mean (rad, ahead positive).
    wind_ups : list of float
        Each mesh's mean output lag (rad): ``|c_j| mean(TE_j) / r_mB``.
    load : float
        Output torque (N m).
    torques : list of float
        Torque on gear A of each pair (N m).
    orders : list of int
        Mesh cycles per output revolution of each pair.
    sweeps : list of TESweepResult
        Each pair's loaded TE over one cycle.
    rigid : bool
        Teeth rigid beyond the contact half-space.
    seconds : float
        Time the contact analyses took (s; the given sweeps' own records).
    reused : bool
        Whether the contacts were given (a cache), not computed in this call.
    """

    variations: list[Array]
    wind_ups: list[float]
    load: float
    torques: list[float]
    orders: list[int]
    sweeps: list[Any]
    rigid: bool
    seconds: float
    reused: bool

    @property
    def sources(self) -> list[str]:
        """The trace's sources: ``mesh 1 under load``, ``mesh 2 under load``."""
        return [f"mesh {j} under load" for j in range(1, len(self.sweeps) + 1)]

    def annotate(self, ds: xr.Dataset) -> None:
        """Put each contact cycle (``mesh{j}_te`` over ``mesh{j}_position``, m) and the
        load's attributes (``wind_up_arcsec``: the meshes' sum; ``mesh{j}_torque_N_m``,
        ``mesh{j}_order``, ``mesh{j}_wind_up_arcsec``, ...; ``load_summary``, the table's
        line) into the accuracy result's dataset ``ds``."""
        for j, s in enumerate(self.sweeps, start=1):
            ds[f"mesh{j}_te"] = (f"mesh{j}_position", np.asarray(s.data["te"].values[0], float),
                                 {"units": "m"})  # fmt: skip
            ds[f"mesh{j}_angle"] = (f"mesh{j}_position", np.asarray(s.data["angle"].values, float),
                                    {"units": "rad"})  # fmt: skip
        wind = float(sum(self.wind_ups))
        how = "reused, computed in" if self.reused else "computed in"
        on = ", ".join(fmt(t, "torque") for t in self.torques)
        ds.attrs.update(
            title=f"Transmission accuracy under {self.load:.4g} N m",
            basis="rigid kinematics + loaded mesh TE"
            + (" (half-space teeth)" if self.rigid else ""),
            load_N_m=self.load, mesh_count=len(self.sweeps), wind_up_arcsec=wind / ARCSEC,
            loaded_peak_to_peak_arcsec=float(np.ptp(sum(self.variations)) / ARCSEC),
            rigid_teeth=int(self.rigid), contact_seconds=self.seconds,
            contact_reused=int(self.reused),
            load_summary=f"load: {fmt(self.load, 'torque')} N m on the output ({on} N m on gear "
            f"A of the meshes; contacts {how} {fmt(self.seconds, 'time')} s); mean wind-up of "
            f"the meshes {fmt(wind / ARCSEC, 'angle')} arcsec (output behind, not in the "
            "trace); tooth-mesh orders "
            f"{', '.join(str(n) for n in self.orders)}",
        )  # fmt: skip
        for j, s in enumerate(self.sweeps, start=1):
            te = np.asarray(s.data["te"].values[0], float)
            ds.attrs.update(
                {
                    f"mesh{j}_torque_N_m": float(self.torques[j - 1]),
                    f"mesh{j}_order": int(self.orders[j - 1]),
                    f"mesh{j}_wind_up_arcsec": float(self.wind_ups[j - 1]) / ARCSEC,
                    f"mesh{j}_te_peak_to_peak_m": float(np.ptp(te)),
                    f"mesh{j}_te_mean_m": float(te.mean()),
                }
            )


def nutation_loaded_error(
    design: Any,
    load: Any,
    u: Array,
    *,
    positions: int = 24,
    rigid: bool = False,
    tooth_size: float | None = None,
    cell: float | None = None,
    sweeps: Any = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> LoadedNutationError:
    """The loaded meshes' share of the nutation drive's output angle error at ``load``
    (module docstring): pair ``j`` gives ``-|c_j| (TE_j(n_j u) - mean TE_j) / r_mB``.

    Parameters
    ----------
    design : NutationDesign
        With ``[surface]`` (the contact analysis generates the teeth).
    load : float, str
        Output torque (``analysis.loaded_accuracy.output_load``: N m, a string with
        units, or ``"design"``).
    u : ndarray
        Output angles (rad), evenly over one revolution.
    positions, rigid, tooth_size, cell : optional
        The contact's positions over one cycle (3..400), half-space teeth, FE tooth size
        (m), contact cell (m; default the contact's own at the load).
    sweeps : list, mapping or TESweepResult, optional
        Each pair's loaded TE at this load computed earlier (a cache): not recomputed.
    stage, progress : callable, optional
        Passed to the contact analyses.

    Returns
    -------
    LoadedNutationError

    Raises
    ------
    ReducerlabError
        A bad load, option or sweep (named); too few samples for a tooth-mesh order.
    """
    t_out = output_load(design, load)
    check_options(positions, rigid)
    orders = mesh_orders(design)
    check_samples(max(orders), len(u))
    torques = pair_torques(design, t_out)
    reused = sweeps is not None
    if sweeps is None:
        sweeps = nutation_mesh_te(design, torques, positions=positions, rigid=rigid,
                                  cell=cell, tooth_size=tooth_size, stage=stage,
                                  progress=progress)  # fmt: skip
    else:
        sweeps = _sweep_list(design, sweeps)
        for j, (s, t) in enumerate(zip(sweeps, torques, strict=True), start=1):
            check_sweep(s, t, f"mesh_te[{j}]")
    sense = math.copysign(1.0, float(design.kinematics().ratio))
    variations, wind_ups = [], []
    for gain, s, n in zip(mesh_gains(design), sweeps, orders, strict=True):
        te = np.asarray(s.data["te"].values[0], float)
        variations.append(gain.output_error(cycle_to_output(te, n, u), sense))
        wind_ups.append(-float(gain.output_error(np.array([te.mean()]), sense)[0]))
    return LoadedNutationError(
        variations=variations, wind_ups=wind_ups, load=t_out, torques=torques, orders=orders,
        sweeps=sweeps, rigid=all(s.data.attrs.get("fe_dofs", 0) == 0 for s in sweeps),
        seconds=float(sum(s.data.attrs.get("seconds", math.nan) for s in sweeps)),
        reused=reused,
    )  # fmt: skip
