"""Transmission accuracy under load: the mesh's loaded transmission error through the
drive's kinematics (issue 31).

``transmission_accuracy(design, load=...)`` adds to the rigid-kinematics error of the
manufacturing errors (``analysis.transmission_accuracy``) the loaded static
transmission error of the drive's mesh at that load: the loaded tooth contact analysis
over one mesh cycle (``analysis.te_sweep``, one torque), gear B's rotation behind its
rigid-conjugate position as a length ``TE(phi)`` along the line of action.

Mapping to the output (first order, like the rigid term):

* the flanks' approach ``TE`` along the line of action makes the mesh's driven gear
  (the gear pair's gear; the KHV planet, driven by the ring in the carrier frame, where
  the output load brakes it) lag by ``TE / r_bB``, ``r_bB`` its base radius (the
  rigid term's divisor: a length along the line of action is the same arc on either
  base circle). In the output's turning sense the output errs by ``-TE / r_bB`` (the
  KHV carrier, the input, turns exactly: the planet's lag relative to it is the
  output's);
* ``TE`` is periodic over one mesh cycle, a tooth's pitch of either gear in the mesh
  frame: ``n_z = 2 pi |i| f_z(omega_in = 1)`` cycles per output revolution (``f_z``:
  the tooth-mesh frequency of the kinematics, Hz per rad/s of the input). Gear pair:
  ``n_z = z_gear`` (the gear is the output); KHV (carrier input, ring fixed, planet
  output): the ring turns ``|i|`` times per output turn in the carrier frame, so
  ``n_z = z_K |i| = z_K z_V / (z_K - z_V)`` output orders, ``z_K`` input orders (330
  and 33 for examples/khv.toml);
* the ``N`` positions of the contact's cycle are carried to the output angle ``u`` by
  their periodic piecewise-linear interpolant at the mesh phase ``n_z u`` (position 0
  at ``u = 0``, the cycle run in the order of the contact's positions). Linear, not
  trigonometric: the trace then never leaves the range of the computed positions (a
  trigonometric interpolant through 7 or 24 samples of a TE with the kinks of the
  contact ratio's changes overshoots between them, which would add a peak to peak no
  contact gave), and its mean over a cycle is the positions' mean. By default the
  output samples are a whole multiple ``M`` of ``n_z N`` (every position is a
  sample); then mesh harmonic ``r`` of the contact (amplitude ``2 |X_r| / N``, ``X``
  the DFT of the positions) becomes the line at output order ``r n_z`` with amplitude
  ``2 |X_r| / N * (sin(pi r / N) / (M sin(pi r / (N M))))^2 / r_bB`` (the linear
  interpolation's response, ``sinc^2(r / N)`` for large ``M``: 0.994 for ``r = 1``,
  ``N = 24``), and the spectrum holds only multiples of ``n_z``.

The mean of ``-TE / r_bB`` over the cycle is the mesh's **elastic wind-up** at the
load: it shifts the output angle but is not a variation of it, so it is reported on
its own (``wind_up_arcsec``, positive: the output lags) and the trace holds the
variation about it (its peak to peak is unchanged by a constant). It is the wind-up of
the tooth contact and bending only (shafts, bearings and the KHV output coupling are
the torsion test's, ``analysis.torsion_test``). The loaded variation and the rigid
manufacturing error add (first-order superposition, both small against the pitch; the
contact of the perfect teeth is not re-solved with the errors in the flanks).

The load ``T_out`` (N m on the output; ``"design"``: the design's operating output
torque) is carried to gear A of the contact pair losslessly: the pinion's
``T_out / |i|`` of a gear pair, the planet's ``T_out`` of a KHV drive
(``analysis.te_sweep.design_load``'s conventions).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..units import parse_quantity

__all__ = [
    "LoadedMeshError",
    "check_options",
    "check_samples",
    "check_sweep",
    "cycle_to_output",
    "loaded_error",
    "loaded_samples",
    "mesh_cycles",
    "mesh_te",
    "mesh_torque",
    "output_load",
]

Array = NDArray[np.float64]

#: one arc second in radians
ARCSEC = math.pi / (180.0 * 3600.0)
#: positions over one mesh cycle at most (each one loaded contact solve)
MAX_POSITIONS = 400


def output_load(design: Any, load: Any) -> float:
    """The output torque (N m, > 0) of ``load``: a torque (a number in N m or a string
    with units, ``"60 N*m"``) or ``"design"``, the design's operating output torque.

    Raises
    ------
    ReducerlabError
        Naming ``load`` and the rule.
    """
    if isinstance(load, str) and load.strip().lower() == "design":
        point = design.operating_point()
        if not point.output_torque:
            raise ReducerlabError(
                "load: 'design' asks for the design's operating output torque, but the design "
                "gives no load (operating torque or power); give a torque, e.g. '60 N*m'"
            )
        return abs(float(point.output_torque))
    try:
        value = parse_quantity(load, "torque")
    except ValueError as exc:
        raise ReducerlabError(
            f"load: the torque on the output, or 'design' for the design's own: {exc}"
        ) from None
    if not value > 0:
        raise ReducerlabError(f"load: must be a torque > 0 on the output (N m); got {load!r}")
    return value


def mesh_torque(design: Any, t_out: float) -> float:
    """The torque on gear A of the contact pair (N m) at ``t_out`` on the output,
    lossless: the pinion's ``t_out / |i|`` (gear pair), the planet's ``t_out`` (KHV: the
    planet drives the output through the W mechanism)."""
    if getattr(design, "type", None) == "khv":
        return float(t_out)
    return float(t_out) / abs(float(design.kinematics().ratio))


def mesh_cycles(design: Any) -> int:
    """Mesh cycles per output revolution ``n_z = 2 pi |i| f_z(1)`` (module docstring).

    Raises
    ------
    ReducerlabError
        When it is not a whole number (the loaded TE would not repeat over one turn).
    """
    kin = design.kinematics()
    f = float(sum(kin.mesh_frequencies(1.0).values()))
    n = 2 * math.pi * abs(float(kin.ratio)) * f
    if not (n >= 1 and abs(n - round(n)) < 1e-6 * n):
        raise ReducerlabError(
            f"load: the tooth mesh repeats {n:.6g} times per output revolution, not a whole "
            "number; the loaded TE over one output revolution needs a whole number"
        )
    return round(n)


def cycle_to_output(te: Array, cycles: int, u: Array) -> Array:
    """The periodic piecewise-linear interpolant of ``te`` (``N`` evenly spaced samples
    over one mesh cycle, position 0 at phase 0, any unit) at the mesh phase
    ``cycles * u`` (``u``: output angle, rad), less the samples' mean (the interpolant's
    mean over a cycle)."""
    n = te.size
    x = (cycles * np.asarray(u, float) / (2 * math.pi)) % 1.0 * n
    return np.interp(x, np.arange(n + 1), np.append(te, te[0])) - te.mean()


def loaded_samples(design: Any, positions: int, sweep: Any = None, least: int = 4096) -> int:
    """The default output samples under load: the least whole multiple of ``n_z N``
    (every contact position a sample; ``N`` the positions of ``sweep`` where given)
    not below ``least``."""
    check_options(positions, False)
    if sweep is not None:
        positions = int(sweep.data.sizes["position"])
    step = mesh_cycles(design) * positions
    return step * max(1, math.ceil(least / step))


def check_samples(order: int, samples: int) -> None:
    """Refuse fewer than ``2 order + 1`` output samples for a loaded TE that repeats
    ``order`` times per output revolution (its tooth-mesh order, Nyquist)."""
    if 2 * order >= samples:
        raise ReducerlabError(
            f"samples: the loaded TE repeats {order} times per output revolution; its "
            f"tooth-mesh order needs more than {2 * order} samples; got {samples}"
        )


def check_options(positions: Any, rigid: Any) -> None:
    """Refuse a ``rigid`` other than a bool and ``positions`` other than an integer in
    3..:data:`MAX_POSITIONS` (``ReducerlabError`` naming the field and the rule)."""
    if not isinstance(rigid, bool):
        raise ReducerlabError(f"rigid: must be true or false; got {rigid!r}")
    if (
        isinstance(positions, bool)
        or not isinstance(positions, int)
        or not 3 <= positions <= MAX_POSITIONS
    ):
        raise ReducerlabError(
            f"positions: must be an integer in 3..{MAX_POSITIONS} (positions over one mesh "
            f"cycle of the loaded contact); got {positions!r}"
        )


def mesh_te(
    design: Any,
    torque: float,
    *,
    pair: int = 1,
    positions: int = 24,
    rigid: bool = False,
    cell: float | None = None,
    tooth_size: float | None = None,
    compliance: tuple[Any, Any] | None = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> Any:
    """The loaded TE of the design's mesh ``pair`` (1; a double-sided nutation drive's 1
    or 2) over one cycle at ``torque`` on gear A (N m):
    ``te_sweep`` at that one torque, its work and memory checked first (the sweep's
    position-torque solves; the finite-element tooth models unless ``rigid``: teeth
    rigid beyond the contact half-space, no finite-element build, for checks, or
    ``compliance``: both gears' tooth models built earlier, the run's compliance stage).

    Returns
    -------
    TESweepResult
        One torque row.

    Raises
    ------
    ReducerlabError, BudgetError
        Bad options; work or memory over the bounds.
    """
    from .contact_setup import pair_setup
    from .te_sweep import sweep_estimate, te_sweep

    check_options(positions, rigid)
    sweep_estimate(positions, 1).check()
    if not rigid and compliance is None:
        pair_setup(design, pair).compliance_estimate(tooth_size).check()
    return te_sweep(design, pair, torques=[torque], torque=torque, positions=positions,
                    harmonics=1, cell=cell, tooth_size=tooth_size,
                    compliance=(None, None) if rigid else compliance, stage=stage,
                    progress=progress)  # fmt: skip


@dataclass(frozen=True)
class LoadedMeshError:
    """The loaded mesh's share of the output angle error.

    Attributes
    ----------
    variation : ndarray
        Output angle error about its mean over the output revolution (rad, ahead
        positive).
    wind_up : float
        Mean lag of the output (rad): ``mean(TE) / r_bB``.
    load : float
        Output torque (N m).
    torque : float
        Torque on gear A of the contact pair (N m).
    cycles : int
        Mesh cycles per output revolution.
    sweep : TESweepResult
        The contact's loaded TE over one cycle.
    rigid : bool
        Teeth rigid beyond the contact half-space.
    seconds : float
        Time the contact analysis took (s; the given ``sweep``'s own record).
    reused : bool
        Whether the contact was given (a cache), not computed in this call.
    """

    variation: Array
    wind_up: float
    load: float
    torque: float
    cycles: int
    sweep: Any
    rigid: bool
    seconds: float
    reused: bool

    def annotate(self, ds: xr.Dataset) -> None:
        """Put the contact's cycle (``mesh_te`` over ``mesh_position``, m) and the load's
        attributes into the accuracy result's dataset ``ds``."""
        s = self.sweep.data
        te = np.asarray(s["te"].values[0], float)
        ds["mesh_te"] = ("mesh_position", te, {"units": "m"})
        ds["mesh_angle"] = ("mesh_position", np.asarray(s["angle"].values, float),
                            {"units": "rad"})  # fmt: skip
        ds.attrs.update(
            title=f"Transmission accuracy under {self.load:.4g} N m",
            basis="rigid kinematics + loaded mesh TE"
            + (" (half-space teeth)" if self.rigid else ""),
            load_N_m=self.load, mesh_torque_N_m=self.torque,
            wind_up_arcsec=self.wind_up / ARCSEC, mesh_order=self.cycles,
            mesh_te_peak_to_peak_m=float(np.ptp(te)), mesh_te_mean_m=float(te.mean()),
            loaded_peak_to_peak_arcsec=float(np.ptp(self.variation) / ARCSEC),
            rigid_teeth=int(self.rigid), contact_seconds=self.seconds,
            contact_reused=int(self.reused),
        )  # fmt: skip


def check_sweep(sweep: Any, torque: float, field: str = "mesh_te") -> None:
    """A given ``sweep`` (``TESweepResult``) must be one torque row at ``torque`` (N m on
    gear A); ``field`` names it in the error."""
    data = getattr(sweep, "data", None)
    if data is None or "torque" not in getattr(data, "coords", {}) or "te" not in data:
        raise ReducerlabError(
            f"{field}: must be a te_sweep result (TESweepResult); got {type(sweep).__name__}"
        )
    T = np.asarray(data["torque"].values, float)
    if T.size != 1 or not math.isclose(float(T[0]), torque, rel_tol=1e-9):
        raise ReducerlabError(
            f"{field}: must be the loaded TE at the one torque {torque:.6g} N m on gear A of "
            f"the pair; got torques {[float(t) for t in T]}"
        )


def loaded_error(
    design: Any,
    load: Any,
    u: Array,
    out_sense: float,
    driven_base_radius: float,
    *,
    positions: int = 24,
    rigid: bool = False,
    tooth_size: float | None = None,
    sweep: Any = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> LoadedMeshError:
    """The loaded mesh's share of the output angle error at ``load`` (module docstring).

    Parameters
    ----------
    design : GearPairDesign or KHVDesign
    load : float, str
        Output torque (:func:`output_load`).
    u : ndarray
        Output angles (rad), evenly over one revolution.
    out_sense : float
        +1 when the mesh's driven gear turns in the mesh frame as the output turns, else
        -1 (the rigid term's sign).
    driven_base_radius : float
        ``r_bB`` (m).
    positions, rigid, tooth_size : optional
        The contact's positions over one cycle, half-space teeth, FE tooth size (m).
    sweep : TESweepResult, optional
        The contact's loaded TE at this load computed earlier (a cache): not recomputed.
    stage, progress : callable, optional
        Passed to the contact analysis.

    Returns
    -------
    LoadedMeshError

    Raises
    ------
    ReducerlabError
        A bad load or option; too few samples for the tooth-mesh order.
    """
    t_out = output_load(design, load)
    check_options(positions, rigid)
    cycles = mesh_cycles(design)
    check_samples(cycles, len(u))
    torque = mesh_torque(design, t_out)
    reused = sweep is not None
    if sweep is None:
        sweep = mesh_te(design, torque, positions=positions, rigid=rigid,
                        tooth_size=tooth_size, stage=stage, progress=progress)  # fmt: skip
    else:
        check_sweep(sweep, torque)
    te = np.asarray(sweep.data["te"].values[0], float)
    values = cycle_to_output(te, cycles, u)
    return LoadedMeshError(
        variation=-out_sense * values / driven_base_radius,
        wind_up=out_sense * float(te.mean()) / driven_base_radius,
        load=t_out, torque=torque, cycles=cycles, sweep=sweep,
        rigid=bool(sweep.data.attrs.get("fe_dofs", 0) == 0),
        seconds=float(sweep.data.attrs.get("seconds", math.nan)), reused=reused,
    )  # fmt: skip
