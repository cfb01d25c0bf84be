"""Transmission accuracy of the cycloid-ball drive under load: the ball track's elastic
wind-up over the crank phase (issue 31).

``transmission_accuracy(design, load=...)`` for a ``cycloid_ball`` design adds to the
rigid-kinematics error of its track and crank errors (``analysis.accuracy_drives.
cycloid_sources``) the static wind-up of the ball track under the output load, which
varies as the ball set moves past the line of centres (``contact.ball_track``,
docs/ball_track.md: which balls carry, and on which lines, changes with the phase).

**Static solution, input held.** At the torque ``T`` on the centre disc and the ball
set's phase ``psi_0`` the track's equilibrium (:func:`reducerlab.contact.ball_track.
ball_loads`, the exact minimum of its Hertz energy) gives the relative displacement
``s`` of the centre disc against the planetary disc at the pitch point, across the line
of centres (paper 003's ``delta_23 = x2 - x3 + u2 - u3``). With the input (the crank,
hence the planetary disc's centre) held and the discs' bearings rigid, ``x2 = x3 = 0``
and ``s = r_2 theta_2 - r_3 theta_3``:

* centre disc output (the planetary disc kept from turning): ``T = T_out`` and the
  output twists by ``theta_2 = s / r_2``;
* planetary disc output (the centre disc held): the centre disc reacts
  ``T = T_out z_c / z_p`` (the generalised force ``T / r_2`` on ``s`` is
  ``T_out / r_3``) and the output twists by ``theta_3 = -s / r_3``, ``|s| / r_3``.

Both twists lag the output behind its rigid position (the load brakes it; drive mode),
so the output angle errs by ``-w(psi_0)``, ``w = s / r_out``. The line of centres
(``y``) is held by default: the crank's eccentric bearing, rigid like the rest, holds
the planetary disc's centre (``"free"``, the planetary disc floating along the line of
centres, is the ball-track analysis' default and gives a 1 % larger wind-up for the
example).

**Period.** With one clearance for every ball the track is the same each time the ball
set has moved on by one ball pitch ``2 pi / Z`` relative to the line of centres: once
per lobe of either groove passing it, the ball-engagement frequency of the kinematics.
Per output revolution that is ``n = 2 pi |i| f_b(omega_in = 1)`` periods, which for
either output is ``z_c z_p / 2`` (centre output: ``z_p`` per input turn times
``|i| = z_c / 2``; planetary output: ``z_c`` times ``|i| = z_p / 2``): 760 for the
38/40-lobe example. The ball set moves by ``d psi_0 = -(n / Z) du`` with the output
angle ``u`` (``contact.ball_track``: ``-(z_p / Z)`` of the input angle for the centre
output; the discs turn alike in the frame of the eccentric for the planetary output),
ball 0 on the pitch point's direction at ``u = 0``.

**Sampling.** ``phases`` static solves at ``psi_0 = -2 pi j / (Z N)`` over one period,
carried to the output by the same periodic piecewise-linear interpolant as the gear
mesh's loaded TE (``analysis.loaded_accuracy.cycle_to_output``), every phase a sample
by default. The wind-up jumps where a line's groove wall turns undercut
(docs/ball_track.md), so the sampled statistics converge like ``1 / N``: the default
:data:`DEFAULT_PHASES` (256) gives the example's mean wind-up within 1e-4, its peak to
peak within 0.5 % and its first ball-pattern harmonic within 0.2 % of a 768-phase run
(``tests/test_loaded_accuracy_cycloid.py``; measured 3e-5, 0 and 6e-4, and within 5e-5,
1e-6 and 7e-4 of 4096 phases).

The mean of ``w`` over the period is the track's **elastic wind-up** at the load,
reported apart (``wind_up_arcsec``, positive: the output lags); the trace holds the
variation about it as the source ``"ball track under load"``. It is the ball track's
wind-up only: the cross-ball mechanism, the end cover's support and the bearings are
the torsion test's (``analysis.torsion_test``). The loaded variation and the rigid error
of the track and crank errors add (first-order superposition: the track is solved with
its nominal grooves and clearances, not re-solved with the errors' clearance changes).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..budget import Estimate
from ..errors import ReducerlabError
from .accuracy_drives import cycloid_sources
from .loaded_accuracy import ARCSEC, cycle_to_output, output_load

__all__ = [
    "DEFAULT_PHASES",
    "MAX_PHASES",
    "LoadedTrackError",
    "ball_pattern_order",
    "cycloid_loaded",
    "cycloid_loaded_sources",
    "loaded_track_error",
    "track_estimate",
    "track_torque",
    "track_wind_up",
]

Array = NDArray[np.float64]

#: ball-set phases over one ball pitch by default (convergence: module docstring)
DEFAULT_PHASES = 256
#: phases at most (each one static solve of the track, about 5 ms for 39 balls)
MAX_PHASES = 4096
#: samples over one output revolution at most (``transmission_accuracy``'s bound)
MAX_SAMPLES = 2**20


def _check_design(design: Any) -> None:
    if getattr(design, "type", None) != "cycloid_ball":
        raise ReducerlabError(
            "ball track under load: a cycloid_ball design is needed; got type = "
            f"{getattr(design, 'type', None)!r}"
        )


def ball_pattern_order(design: Any) -> int:
    """Periods of the ball pattern per output revolution, ``n = 2 pi |i| f_b(1)``
    (``f_b``: the ball-engagement frequency of the kinematics, Hz per rad/s of the
    input), ``z_c z_p / 2`` for either output (module docstring).

    Raises
    ------
    ReducerlabError
        Not a cycloid_ball design, or ``n`` not a whole number (an odd ``z_c``: the
        pattern then repeats over two output revolutions).
    """
    _check_design(design)
    kin = design.kinematics()
    n = 2 * math.pi * abs(float(kin.ratio)) * float(kin.mesh_frequencies(1.0)["ball engagement"])
    if not (n >= 1 and abs(n - round(n)) < 1e-9 * n):
        raise ReducerlabError(
            f"centre_disc.lobes: with {design.centre_disc.lobes} lobes the ball pattern "
            f"repeats z_c z_p / 2 = {n:.6g} times per output revolution, not a whole number; "
            "the loaded accuracy over one output revolution needs an even number of lobes"
        )
    return round(n)


def track_torque(design: Any, t_out: float) -> float:
    """Torque (N m) on the centre disc's track at ``t_out`` (N m) on the output:
    ``t_out`` (centre output) or ``t_out z_c / z_p`` (planetary output, the centre
    disc's reaction)."""
    if design.output == "planetary":
        return float(t_out) * design.centre_disc.lobes / design.planetary_disc.lobes
    return float(t_out)


def _output_radius(design: Any) -> float:
    """``r_out`` (m): ``r_2`` (centre output) or ``r_3`` (planetary output)."""
    disc = design.planetary_disc if design.output == "planetary" else design.centre_disc
    return float(design.pitch_radius(disc.lobes))


def _check_phases(phases: Any) -> int:
    if (
        isinstance(phases, bool)
        or not isinstance(phases, (int, np.integer))
        or not (8 <= phases <= MAX_PHASES)
    ):
        raise ReducerlabError(
            f"phases: must be an integer in 8..{MAX_PHASES} (ball-set positions over one "
            f"ball pitch, each a static solve of the ball track); got {phases!r}"
        )
    return int(phases)


def track_estimate(phases: int, balls: int, samples: int = 0) -> Estimate:
    """Work (``phases`` static solves of the track) and memory (each phase's line forces
    and approaches, and ``samples`` output angles of a few traces) of the loaded
    cycloid-ball accuracy; at most :data:`MAX_PHASES` phases."""
    memory = 8.0 * (4 * phases * 2 * balls + 8 * samples)
    return Estimate(
        f"ball track under load: {phases} static solves of {balls} balls", memory,
        float(phases), "phases", float(MAX_PHASES), "phases (--phases)",
    )  # fmt: skip


def track_wind_up(
    design: Any,
    t_out: float,
    phases: int = DEFAULT_PHASES,
    y: Literal["held", "free"] = "held",
    progress: Callable[[int, int], None] | None = None,
) -> tuple[Array, Array, Array]:
    """The output's static twist under ``t_out`` (N m on the output, > 0), input held, at
    ``phases`` ball-set phases ``psi_0 = -2 pi j / (Z N)`` over one ball pitch:
    ``w = |s| / r_out`` (module docstring).

    Returns
    -------
    psi0 : ndarray
        The phases (rad).
    twist : ndarray
        ``w`` (rad, positive: the output lags).
    loaded : ndarray
        Balls carrying load at each phase.
    """
    from ..contact.ball_track import ball_loads

    _check_design(design)
    phases = _check_phases(phases)
    if y not in ("held", "free"):
        raise ReducerlabError(f"y: must be 'held' or 'free'; got {y!r}")
    track = design.ball_track()
    T = track_torque(design, t_out)
    psi = -2 * math.pi * np.arange(phases) / (track.balls * phases)
    s = np.zeros(phases)
    loaded = np.zeros(phases)
    for j, p in enumerate(psi):
        r = ball_loads(track, T, float(p), y)
        s[j], loaded[j] = r.s, r.loaded
        if progress is not None:
            progress(j + 1, phases)
    return psi, np.abs(s) / _output_radius(design), loaded


@dataclass(frozen=True)
class LoadedTrackError:
    """The loaded ball track's share of the output angle error.

    Attributes
    ----------
    variation : ndarray
        Output angle error about its mean over the output revolution (rad, ahead
        positive): ``-(w(psi_0(u)) - mean w)``.
    wind_up : float
        Mean lag of the output (rad), ``mean w``.
    load, torque : float
        Output torque and the centre disc's track torque (N m).
    order : int
        Ball-pattern periods per output revolution.
    psi0, twist, loaded : ndarray
        Per phase: ``psi_0`` (rad), the twist ``w`` (rad) and the loaded balls.
    y : str
        The planetary disc along the line of centres (``"held"``, ``"free"``).
    seconds : float
        Time the static solves took (s).
    """

    variation: Array
    wind_up: float
    load: float
    torque: float
    order: int
    psi0: Array
    twist: Array
    loaded: Array
    y: str
    seconds: float

    def annotate(self, ds: xr.Dataset) -> None:
        """Put the track's twist over one period (``track_twist`` on ``track_phase``)
        and the load's attributes into the accuracy result's dataset ``ds``."""
        ds["track_twist"] = ("track_phase", self.twist, {"units": "rad"})
        ds["track_loaded_balls"] = ("track_phase", self.loaded)
        ds.coords["track_phase"] = ("track_phase", self.psi0, {"units": "rad"})
        ds.attrs.update(
            title=f"Transmission accuracy under {self.load:.4g} N m",
            basis=f"rigid kinematics + ball track under load (y {self.y})",
            load_N_m=self.load, track_torque_N_m=self.torque,
            wind_up_arcsec=self.wind_up / ARCSEC, ball_pattern_order=self.order,
            track_phases=int(self.psi0.size), track_y=self.y,
            loaded_peak_to_peak_arcsec=float(np.ptp(self.variation) / ARCSEC),
            track_twist_peak_to_peak_arcsec=float(np.ptp(self.twist) / ARCSEC),
            loaded_balls_min=int(self.loaded.min()), loaded_balls_max=int(self.loaded.max()),
            track_seconds=self.seconds,
            load_summary=(
                f"load: {self.load:.4g} N m on the output ({self.torque:.4g} N m on the "
                f"centre disc's track, y {self.y}; {self.psi0.size} phases a ball pitch in "
                f"{self.seconds:.3g} s); mean wind-up of the ball track "
                f"{self.wind_up / ARCSEC:.4g} arcsec (output behind, not in the trace); "
                f"ball-pattern order {self.order}"
            ),
        )  # fmt: skip


def loaded_track_error(
    design: Any,
    load: Any,
    u: Array,
    *,
    phases: int = DEFAULT_PHASES,
    y: Literal["held", "free"] = "held",
    progress: Callable[[int, int], None] | None = None,
) -> LoadedTrackError:
    """The loaded ball track's share of the output angle error at ``load`` (module
    docstring), over the output angles ``u`` (rad, evenly over one revolution).

    Raises
    ------
    ReducerlabError, BudgetError
        A bad load, ``phases`` or ``y``; too few samples for the ball-pattern order;
        work over the bound.
    """
    t_out = output_load(design, load)
    phases = _check_phases(phases)
    order = ball_pattern_order(design)
    if 2 * order >= len(u):
        raise ReducerlabError(
            f"samples: the ball pattern repeats {order} times per output revolution; it "
            f"needs more than {2 * order} samples; got {len(u)}"
        )
    track_estimate(phases, design.balls, len(u)).check()
    t0 = time.perf_counter()
    psi, twist, loaded = track_wind_up(design, t_out, phases, y, progress)
    seconds = time.perf_counter() - t0
    return LoadedTrackError(
        variation=-cycle_to_output(twist, order, u), wind_up=float(twist.mean()),
        load=t_out, torque=track_torque(design, t_out), order=order, psi0=psi,
        twist=twist, loaded=loaded, y=y, seconds=seconds,
    )  # fmt: skip


def cycloid_loaded_sources(
    design: Any,
    samples: int | None,
    load: Any,
    *,
    phases: int | None = None,
    y: Literal["held", "free"] = "held",
    progress: Callable[[int, int], None] | None = None,
) -> tuple[Array, list[str], list[Array], dict[str, Any], LoadedTrackError]:
    """The sources of a cycloid_ball design's output angle error over one output
    revolution under ``load``: its rigid sources (``accuracy_drives.cycloid_sources``)
    and ``"ball track under load"`` (module docstring); ``transmission_accuracy`` makes
    them its result and :meth:`LoadedTrackError.annotate` adds the wind-up.

    Parameters
    ----------
    design : CycloidBallDesign
        With the ball and groove fields of ``[cycloid_pair]``.
    samples : int, optional
        Even steps over one output revolution, 64 .. 2**20, more than twice the
        ball-pattern order; default the least multiple of the order times ``phases``
        from 4096 (every phase a sample: 194560 for the example).
    load : float or str
        Output torque (N m, a string with units, or ``"design"``).
    phases : int, optional
        Ball-set phases over one ball pitch, 8 .. 4096; default :data:`DEFAULT_PHASES`.
    y : {"held", "free"}
        The planetary disc along the line of centres.
    progress : callable, optional
        ``progress(done, total)`` after each phase.

    Returns
    -------
    u : ndarray
        Output angles (rad).
    sources : list of str
    parts : list of ndarray
        Each source's output angle error (rad, ahead positive) over ``u``.
    attrs : dict
        The rigid sources' attributes.
    under : LoadedTrackError
    """
    phases = DEFAULT_PHASES if phases is None else _check_phases(phases)
    order = ball_pattern_order(design)
    if samples is None:
        step = order * phases
        samples = step * max(1, math.ceil(4096 / step))
        if samples > MAX_SAMPLES:
            raise ReducerlabError(
                f"phases: {phases} phases at the ball-pattern order {order} ask for "
                f"{samples} samples, more than {MAX_SAMPLES}; give fewer phases or samples"
            )
    if (
        isinstance(samples, bool)
        or not isinstance(samples, int)
        or not (64 <= samples <= MAX_SAMPLES)
    ):
        raise ReducerlabError(f"samples: must be an integer in 64 .. 2**20; got {samples!r}")
    u = 2 * math.pi * np.arange(samples) / samples
    under = loaded_track_error(design, load, u, phases=phases, y=y, progress=progress)
    sources, parts, attrs = cycloid_sources(design, u)
    sources.append("ball track under load")
    parts.append(under.variation)
    return u, sources, parts, attrs, under


def cycloid_loaded(
    design: Any,
    samples: int | None,
    load: Any,
    *,
    rigid: bool = False,
    positions: int = 24,
    tooth_size: float | None = None,
    mesh_te: Any = None,
    phases: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[Array, list[str], list[Array], dict[str, Any], LoadedTrackError]:
    """``transmission_accuracy(design, load=...)``'s sources of a cycloid_ball design:
    the gear contact's options refused by name (the ball track has no teeth), then
    :func:`cycloid_loaded_sources`.

    Raises
    ------
    ReducerlabError
        ``rigid``, ``tooth_size``, ``mesh_te`` given, or ``positions`` other than its
        default 24 (the gear contact's positions over a mesh cycle: the ball track takes
        ``phases``).
    """
    given = [name for name, v in (("rigid", rigid), ("tooth_size", tooth_size),
                                  ("mesh_te", mesh_te)) if v not in (False, None)]  # fmt: skip
    if positions != 24:
        given.append("positions")
    if given:
        raise ReducerlabError(
            f"{', '.join(given)}: options of the gear contact; a cycloid_ball design under "
            "load solves its ball track (give phases, the ball-set positions over one ball "
            "pitch, instead of positions)"
        )
    return cycloid_loaded_sources(design, samples, load, phases=phases, progress=progress)
