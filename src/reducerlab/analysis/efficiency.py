"""Mesh power loss and efficiency from Coulomb friction at the loaded tooth contacts.

``efficiency(design, mu=0.05, torques=...)`` runs the loaded tooth contact analysis of
every gear pair of a design over one mesh cycle at several torques on one contact grid
(``analysis.te_sweep``, ``loaded_contact(..., torques=)``) and, at each position, the
Coulomb friction power ``sum_i mu F_i |v_s,i|`` of the contact cells
(``contact.friction``: sliding velocities from the pair's kinematics in the frame
where its axes are fixed, the carrier frame of a planetary or nutation drive). Its mean
over the evenly spaced positions of one mesh cycle is the mesh power loss ``P_V``.

Powers (at the design's input speed; every loss and power is proportional to the
speed at constant ``mu``, so the efficiencies do not depend on it):

* **rolling power** of a pair ``P_W = |T_A phi_dot|``: the power the mesh transmits in
  its own frame (``T_A``: torque on gear A, ``phi_dot``: A's speed in that frame,
  ``2 pi f_z / z_A`` from the tooth-mesh frequency ``f_z``). The mesh efficiency in
  that frame is ``eta_0 = 1 - P_V / P_W``; for a gear pair on fixed axes it is the
  pair's efficiency (ISO/TR 14179-2's ``P_VZ / P_A``).
* **drive efficiency** ``eta = 1 - sum P_V / P_0`` with ``P_0 = T_out |omega_out|`` the
  lossless transmitted power at that load (the design's output power scaled with the
  torque). The friction power is frame invariant (the relative velocity of the two
  flanks at a point is the same in every frame), so the losses add up directly; with
  ``P_V = (1 - eta_0) P_W`` this is Müller's rolling-power relation
  ``1 - eta = (1 - eta_0) P_W / P_0`` (H. W. Müller, *Epicyclic Drive Trains*, Wayne
  State University Press, 1982, ch. 5, "rolling power"; Kudryavtsev's formulas reduce
  to it to first order in the loss). For a KHV drive with carrier input and fixed ring
  ``P_W / P_0 = z_ring / (z_ring - z_planet)``: the high ratio multiplies the mesh
  loss. First order in the loss: the torques are the frictionless torque flow's.

A cycloid-ball design has its own model, ``analysis.cycloid_efficiency`` (the spin and
the differential sliding of its rolling balls; the same result kind), to which
``reducerlab efficiency`` sends it.

Out of scope: rolling (EHL film) loss, bearing and seal losses, churning and windage,
starting and back-driving torque.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..errors import ReducerlabError, names_source
from ..numformat import Column, Table, fmt
from ..results import Result, provenance
from ..threads import with_compute_threads

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "DEFAULT_MU",
    "EfficiencyResult",
    "efficiency",
    "friction_coefficient",
    "gear_pairs",
    "load_grid",
]

Array = NDArray[np.float64]

#: Coulomb coefficient when neither the call nor the design gives one: a mean value of
#: lubricated steel gear meshes in mixed friction (Niemann/Winter Vol. II, 1989: 0.04 to
#: 0.08 at usual loads and speeds)
DEFAULT_MU = 0.05


class EfficiencyResult(Result):
    """Friction power loss and efficiency of a drive's meshes against torque.

    ``data`` has dimensions ``pair`` (1..), ``torque`` (coordinate: the torque on gear A
    of pair 1, N m), ``position`` (one mesh cycle) and ``speed`` (input speeds, rad/s).
    Variables: ``loss`` (pair, torque, position; W at the design speed), ``mesh_loss``
    (pair, torque; W, the mean over the cycle), ``rolling_power`` (pair, torque; W),
    ``mesh_efficiency`` (pair, torque), ``output_power`` (torque; W, lossless),
    ``output_torque`` (torque; N m, the drive's output torque at that load),
    ``efficiency`` (torque), ``loss_at_speed`` (torque, speed; W, all pairs),
    ``sliding_speed`` (pair, position; m/s, the largest at a loaded cell at the
    largest torque) and ``pair_torque`` (pair, torque; N m on each pair's gear A).
    """

    kind: ClassVar[str] = "efficiency"

    @property
    def efficiency(self) -> Array:
        """Drive efficiency at each torque."""
        return np.asarray(self.data["efficiency"].values, float)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: attributes and one row a torque."""
        ds = self.data
        out = {k: (v.item() if hasattr(v, "item") else v) for k, v in ds.attrs.items()
               if k != "design"}  # fmt: skip
        out["torques"] = [
            {
                "torque_N_m": float(t),
                "mesh_loss_W": [float(v) for v in ds["mesh_loss"].values[:, i]],
                "mesh_efficiency": [float(v) for v in ds["mesh_efficiency"].values[:, i]],
                "output_power_W": float(ds["output_power"].values[i]),
                "efficiency": float(ds["efficiency"].values[i]),
            }
            for i, t in enumerate(ds["torque"].values)
        ]
        out["speeds_rad_s"] = [float(v) for v in ds["speed"].values]
        out["loss_at_speed_W"] = [[float(v) for v in row] for row in ds["loss_at_speed"].values]
        return out

    def table(self) -> str:
        """Plain-text table: one row a torque."""
        a = self.data.attrs
        n = self.data.sizes["pair"]
        cols = [Column("T_A", "N m", "torque")]
        for p in range(1, n + 1):
            cols += [Column(f"P_V{p}", "W", "power"), Column(f"eta0_{p}")]
        t = Table([*cols, Column("P_0", "W", "power"), Column("eta")], title=(
            f"Mesh friction loss, mu = {fmt(a['mu'])} "
            f"({a.get('model', 'Coulomb, sliding only')}), "
            f"{self.data.sizes['position']} positions a mesh cycle, input "
            f"{fmt(a['input_speed_rad_s'] * 30 / math.pi, 'speed')} rpm; drive efficiency "
            f"1 - sum P_V / P_0"))  # fmt: skip
        for r in self.to_dict()["torques"]:
            pairs = [x for v, e in zip(r["mesh_loss_W"], r["mesh_efficiency"], strict=True)
                     for x in (v, e)]  # fmt: skip
            t.add(r["torque_N_m"], *pairs, r["output_power_W"], r["efficiency"])
        return t.text()

    def figure(self) -> Figure:
        """Efficiency against torque; loss over the mesh cycle."""
        from ..plot.efficiency import plot_efficiency

        return plot_efficiency(self)

    plot = figure


def friction_coefficient(design: Any, mu: float | None) -> float:
    """``mu`` if given, else the design's ``material.friction_coefficient``, else
    :data:`DEFAULT_MU`, checked (``contact.friction.check_friction_coefficient``)."""
    from ..contact.friction import check_friction_coefficient

    if mu is not None:
        return check_friction_coefficient(mu)
    value = getattr(getattr(design, "material", None), "friction_coefficient", None)
    if value is None:
        return DEFAULT_MU
    return check_friction_coefficient(value, "material.friction_coefficient")


def gear_pairs(design: Any) -> tuple[int, ...]:
    """The design's gear pairs (1 for a gear_pair or khv; a nutation drive's meshes)."""
    from ..drives.gear_pair import GearPairDesign

    if isinstance(design, GearPairDesign) or getattr(design, "type", None) == "khv":
        return (1,)
    return tuple(range(1, len(design.kinematics().mesh_frequencies(1.0)) + 1))


def load_grid(
    ref: float,
    torques: Sequence[float] | None,
    loads: int,
    top: float,
    speeds: Sequence[float] | None,
    speed0: float,
) -> tuple[Array, Array]:
    """The torques (N m, ascending) and input speeds (rad/s) of an efficiency: the
    given ``torques`` (1..41, > 0), else ``loads`` torques from ``top / loads`` to
    ``top`` times ``ref`` (the design's); the given ``speeds``, else ``speed0``.

    Raises
    ------
    ReducerlabError
        Naming ``loads``, ``top``, ``torques`` or ``speeds`` and the rule.
    """
    if torques is None:
        if isinstance(loads, bool) or not isinstance(loads, int) or not 1 <= loads <= 41:
            raise ReducerlabError(f"loads: must be an integer in 1..41; got {loads!r}")
        if not (isinstance(top, int | float) and math.isfinite(top) and 0 < top <= 3):
            raise ReducerlabError(f"top: must be a factor in (0, 3]; got {top!r}")
        T = ref * top * np.arange(1, loads + 1) / loads
    else:
        T = np.sort(np.atleast_1d(np.asarray(torques, float)))
        if T.ndim != 1 or not 1 <= T.size <= 41 or not np.all(np.isfinite(T) & (T > 0)):
            raise ReducerlabError("torques: must be 1..41 finite torques > 0 (N m)")
    W = np.atleast_1d(np.asarray([speed0] if speeds is None else speeds, float))
    if W.ndim != 1 or not W.size or not np.all(np.isfinite(W) & (W > 0)):
        raise ReducerlabError("speeds: must be input speeds > 0 (rad/s)")
    return T, W


@names_source
@with_compute_threads
def efficiency(
    design: Any,
    *,
    mu: float | None = None,
    torques: Sequence[float] | None = None,
    loads: int = 4,
    top: float = 1.5,
    speeds: Sequence[float] | None = None,
    positions: int = 24,
    cell: float | None = None,
    tooth_size: float | None = None,
    rigid: bool = False,
    compliance: Sequence[tuple[Any, Any]] | None = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> EfficiencyResult:
    """Friction loss and efficiency of every mesh of ``design`` against torque.

    Parameters
    ----------
    design : GearPairDesign, KHV design or NutationDesign (with ``[surface]``)
        A cycloid-ball design is refused, naming
        :func:`~reducerlab.analysis.cycloid_efficiency.cycloid_efficiency`.
    mu : float, optional
        Coulomb coefficient in ``[0, 0.3]``; default the design's
        ``material.friction_coefficient``, else :data:`DEFAULT_MU`.
    torques : sequence of float, optional
        Torques on gear A of pair 1 (N m, > 0); the other pairs carry the torque flow's
        share at the same load. Default ``loads`` torques from ``top / loads`` to
        ``top`` times the design load.
    loads, top : int, float
        As above (``loads`` in 1..41).
    speeds : sequence of float, optional
        Input speeds (rad/s) of ``loss_at_speed``; default the design's operating speed.
    positions : int
        Positions over one mesh cycle (>= 3).
    cell, tooth_size : float, optional
        Contact cell and finite-element tooth size (m), as ``te_sweep``.
    rigid : bool
        Teeth rigid beyond the contact half-space (no finite-element build): fast, for
        checks; the load sharing of the tooth pairs is then that of contact alone.
    compliance : sequence of (ToothCompliance, ToothCompliance), optional
        Both gears' finite-element tooth compliances of every pair, built earlier (the
        run's compliance stage, ``pipeline.stages.compliance_stage``): no model is
        built again.
    stage, progress : callable, optional
        ``stage(text)``; ``progress(done, total)`` per position.

    Returns
    -------
    EfficiencyResult

    Raises
    ------
    ReducerlabError
        A bad coefficient, torque or speed, a design without load or speed.
    """
    from ..contact.friction import friction_power, sliding_velocities
    from .contact_setup import pair_setup
    from .te_sweep import design_load, sweep_estimate, te_sweep

    if getattr(design, "type", None) == "cycloid_ball":  # rolling balls: their own model
        raise ReducerlabError(
            "design: a cycloid_ball design has no tooth contacts; its balls' spin and "
            "sliding are analysis.cycloid_efficiency.cycloid_efficiency (`reducerlab "
            "efficiency` takes it there)"
        )
    t0 = time.perf_counter()
    mu = friction_coefficient(design, mu)
    if isinstance(positions, bool) or not isinstance(positions, int) or positions < 3:
        raise ReducerlabError(f"positions: must be an integer >= 3; got {positions!r}")
    point = design.operating_point()
    speed0 = float(design.operating_speed or 0.0)
    if not speed0:
        raise ReducerlabError("operating speed: the design has no input speed for the losses")
    if not point.output_torque:
        raise ReducerlabError("load: the design gives no load (output torque or power)")
    pairs = gear_pairs(design)
    ref = np.array([design_load(design, p) for p in pairs])
    T, W = load_grid(float(ref[0]), torques, loads, top, speeds, speed0)
    scale = T / ref[0]  # load over the design load
    setups = [pair_setup(design, p) for p in pairs]
    if compliance is not None and (rigid or len(compliance) != len(pairs)):
        raise ReducerlabError(
            f"compliance: give one (gear A, gear B) pair of tooth compliances for each of "
            f"the design's {len(pairs)} gear pairs, and not with rigid teeth"
        )
    for setup in setups:  # every pair's work bounds before any finite-element build
        sweep_estimate(positions, T.size).check()
        if not rigid and compliance is None:
            setup.compliance_estimate(tooth_size).check()
    loss = np.full((len(pairs), T.size, positions), np.nan)
    rolling = np.zeros((len(pairs), T.size))
    vmax = np.zeros((len(pairs), positions))
    for k, (p, setup) in enumerate(zip(pairs, setups, strict=True)):
        mp = setup.mesh_pair
        phi_dot = 2 * math.pi * setup.mesh_frequency / setup.teeth[0]
        Tk = ref[k] * scale
        rolling[k] = Tk * phi_dot

        def observe(i: int, j: int, run: Any, mp: Any = mp, k: int = k, w: float = phi_dot) -> None:
            loss[k, i, j] = float(friction_power(mp, run, mu, w).sum())
            if i == T.size - 1:
                v = sliding_velocities(mp, run.phi, run.points, run.normals).speed * w
                vmax[k, j] = float(v[run.force > 0].max())

        if stage is not None:
            stage(f"pair {p}: loaded contact at {positions} positions x {T.size} torques")
        given = None if compliance is None else tuple(compliance[k])
        te_sweep(design, p, torques=Tk, positions=positions, harmonics=1, cell=cell,
                 tooth_size=tooth_size, compliance=(None, None) if rigid else given,
                 observe=observe, progress=progress)  # fmt: skip
    mesh_loss = loss.mean(axis=2)
    p_out = point.power * scale
    eta = 1.0 - mesh_loss.sum(axis=0) / p_out
    ds = xr.Dataset(
        {
            "loss": (("pair", "torque", "position"), loss, {"units": "W"}),
            "mesh_loss": (("pair", "torque"), mesh_loss, {"units": "W"}),
            "rolling_power": (("pair", "torque"), rolling, {"units": "W"}),
            "mesh_efficiency": (("pair", "torque"), 1.0 - mesh_loss / rolling),
            "output_power": ("torque", p_out, {"units": "W"}),
            "output_torque": ("torque", abs(point.output_torque) * scale, {"units": "N m"}),
            "efficiency": ("torque", eta),
            "loss_at_speed": (
                ("torque", "speed"),
                mesh_loss.sum(axis=0)[:, None] * W[None, :] / speed0,
                {"units": "W"},
            ),
            "sliding_speed": (("pair", "position"), vmax, {"units": "m/s"}),
            "pair_torque": (("pair", "torque"), ref[:, None] * scale[None, :], {"units": "N m"}),
        },
        coords={
            "pair": list(pairs),
            "torque": ("torque", T, {"units": "N m"}),
            "position": np.arange(positions),
            "speed": ("speed", W, {"units": "rad/s"}),
        },
        attrs={"title": "Mesh friction loss and efficiency", **provenance(design.provenance)},
    )
    ds.attrs.update(mu=mu, input_speed_rad_s=speed0, design_torque=float(ref[0]),
                    ratio=abs(float(design.kinematics().ratio)),
                    rigid=int(bool(rigid)), seconds=time.perf_counter() - t0)  # fmt: skip
    return EfficiencyResult(ds)
