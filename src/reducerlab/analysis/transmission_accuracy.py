"""Angular transmission error over one output revolution from manufacturing errors.

``transmission_accuracy(design)`` turns the drive's input through ``|i|`` revolutions
(one output revolution, without reversing), takes each gear's rotation in its mesh's
frame from the drive's kinematics (``DriveKinematics.relative_speeds``: the housing
for a gear pair, the carrier for the KHV drive's internal mesh), and adds up the lead of
the driven flank along the line of action that the gears' eccentricities and
cumulative pitch deviations give (:func:`reducerlab.kinematics.accuracy.mesh_lead`):

``delta theta_out = s / r_bB``

with ``r_bB`` the base radius of the mesh's driven gear (the gear pair's gear; the KHV
planet, whose angle relative to the carrier is the output's error because the carrier
is the input and turns exactly). The error is the output angle minus its nominal
``theta_in / i``, positive ahead in the output's turning sense; reported in arc seconds
with its peak to peak and its amplitude spectrum in orders of the output revolution
(and of the input: output order / ``|i|``).

Rigid (unloaded) kinematics, one tooth pair in contact, first order in ``e / r_b``.
Under a stated ``load`` the mesh's loaded transmission error of the contact analysis is
added (``analysis.loaded_accuracy``: its variation as the source ``mesh under load``,
its mean as the separate elastic wind-up; gear pair and KHV; a nutation drive's meshes
through its two stages: ``analysis.loaded_accuracy_nutation``). The gear pair and KHV
drives, with their assembly errors (the KHV crank, the pair's centre distance:
``analysis.accuracy_drives``); the cycloid-ball and nutation drives through their own
laws (``analysis.accuracy_drives.DRIVE_SOURCES``; under load the cycloid-ball's ball
track, ``analysis.loaded_accuracy_cycloid``, and the nutation's two meshes,
``analysis.loaded_accuracy_nutation``); the others raise naming the design type.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..errors import ReducerlabError
from ..geometry.internal_pair import inv, inv_inverse
from ..kinematics.accuracy import GearErrors, line_angle, mesh_lead, order_spectrum
from ..numformat import Column, Table, fmt
from ..results import Result, provenance
from .accuracy_drives import DRIVE_SOURCES, assembly_attrs, crank_leads

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["ARCSEC", "TransmissionAccuracyResult", "transmission_accuracy"]

Array = NDArray[np.float64]

#: one arc second in radians
ARCSEC = math.pi / (180.0 * 3600.0)


class TransmissionAccuracyResult(Result):
    """Output angle error over one output revolution and its spectrum.

    ``data``: coordinate ``output_angle`` (rad, ``samples`` even steps over one output
    revolution) with ``error`` (rad) and ``contribution`` (``source`` x
    ``output_angle``, rad: each gear's eccentricity and pitch deviations alone);
    coordinate ``order`` (of the output revolution, with ``input_order``) with
    ``amplitude`` (arcsec). Attributes: ``peak_to_peak_arcsec``, ``ratio``,
    ``drive``, ``driven_base_radius`` (m).
    """

    kind: ClassVar[str] = "transmission-accuracy"

    @property
    def error_arcsec(self) -> Array:
        """The output angle error (arcsec) over the revolution."""
        return np.asarray(self.data["error"].values, float) / ARCSEC

    @property
    def peak_to_peak(self) -> float:
        """Peak-to-peak output angle error (arcsec)."""
        return float(self.data.attrs["peak_to_peak_arcsec"])

    def largest_orders(self, n: int = 5) -> list[tuple[int, float]]:
        """The ``n`` output orders of largest amplitude (order, arcsec), order > 0,
        leaving out round-off (below ``1e-9`` of the largest)."""
        amp = np.asarray(self.data["amplitude"].values, float)
        floor = 1e-9 * amp[1:].max(initial=0.0)
        idx = [int(k) for k in np.argsort(-amp[1:], kind="stable")[:n] + 1 if amp[k] > floor]
        return [(k, float(amp[k])) for k in idx]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: attributes, peak to peak and the largest orders."""
        a = self.data.attrs
        out = {k: (v.item() if hasattr(v, "item") else v) for k, v in a.items()
               if k != "design"}  # fmt: skip
        ratio = abs(float(a["ratio"]))
        out["largest_orders"] = [
            {"output_order": k, "input_order": k / ratio, "amplitude_arcsec": v}
            for k, v in self.largest_orders()
        ]
        out["contribution_peak_to_peak_arcsec"] = {
            str(s): float(np.ptp(self.data["contribution"].sel(source=s).values) / ARCSEC)
            for s in self.data["source"].values
        }
        return out

    def table(self) -> str:
        """Plain-text summary."""
        d = self.to_dict()
        sec = partial(fmt, kind="angle")
        lines = [
            f"Transmission accuracy ({d['drive']}, i = {fmt(d['ratio'], 'ratio')}): "
            f"{d.get('basis', 'rigid kinematics')}, "
            f"{self.data.sizes['output_angle']} samples over one output revolution",
            *_load_lines(d),
            f"peak to peak: {sec(self.peak_to_peak)} arcsec",
        ]
        src = Table([Column("source", kind="text"), Column("peak to peak", "arcsec", "angle")],
                    list(d["contribution_peak_to_peak_arcsec"].items()))  # fmt: skip
        lines.append(src.text())
        if "backlash_change" in d:  # an assembly error (analysis.accuracy_drives)
            dj, dja = d["backlash_change"], d["backlash_change_arcsec"]
            lines.append(f"backlash change (centre distance): {fmt(dj * 1e6, 'length')} um "
                         f"normal, {sec(dja)} arcsec at the output")  # fmt: skip
        orders = Table([Column("output order", kind="count"), Column("input order"),
                        Column("amplitude", "arcsec", "angle")],
                       [(r["output_order"], r["input_order"], r["amplitude_arcsec"])
                        for r in d["largest_orders"]])  # fmt: skip
        lines.append(orders.text())
        return "\n".join(lines)

    def figure(self) -> Figure:
        """Error over the output revolution; its spectrum in orders."""
        from ..plot.transmission_accuracy import plot_transmission_accuracy

        return plot_transmission_accuracy(self)

    plot = figure

    @classmethod
    def from_contributions(cls, design: Any, u: Array, sources: list[str],
                           contribution: Array, ratio: float,
                           **attrs: Any) -> TransmissionAccuracyResult:  # fmt: skip
        """The result of the sources' errors ``contribution`` (rad, ``source`` x
        ``output_angle``) over the output angles ``u`` (rad): their sum, its spectrum,
        ``attrs`` added to the dataset's attributes."""
        contribution = np.reshape(np.asarray(contribution, float), (len(sources), u.size))
        error = contribution.sum(axis=0)
        orders, amp = order_spectrum(error / ARCSEC)
        ds = xr.Dataset(
            {
                "error": ("output_angle", error, {"units": "rad"}),
                "contribution": (("source", "output_angle"), contribution, {"units": "rad"}),
                "amplitude": ("order", amp, {"units": "arcsec"}),
            },
            coords={
                "output_angle": ("output_angle", u, {"units": "rad"}),
                "source": sources,
                "order": orders,
                "input_order": ("order", orders / abs(ratio)),
            },
            attrs={
                "title": "Transmission accuracy (rigid kinematics)",
                **provenance(getattr(design, "provenance", None)),
            },
        )
        ds.attrs.update(peak_to_peak_arcsec=float(np.ptp(error) / ARCSEC), ratio=ratio,
                        drive=str(design.type), **attrs)  # fmt: skip
        return cls(ds)


def _load_lines(d: dict[str, Any]) -> list[str]:
    """The table's rows of the load (none unloaded)."""
    if "load_N_m" not in d:
        return []
    if "load_summary" in d:  # a drive's own loaded law (the cycloid's ball track)
        return [str(d["load_summary"])]
    how = "reused, computed in" if d["contact_reused"] else "computed in"
    return [f"load: {fmt(d['load_N_m'], 'torque')} N m on the output "
            f"({fmt(d['mesh_torque_N_m'], 'torque')} N m on gear A of the mesh; contact {how} "
            f"{fmt(d['contact_seconds'], 'time')} s); mean wind-up of the mesh "
            f"{fmt(d['wind_up_arcsec'], 'angle')} arcsec (output behind, not in the "
            f"trace); tooth-mesh order {d['mesh_order']}"]  # fmt: skip


@dataclass(frozen=True)
class _Mesh:
    """One mesh as the accuracy law takes it: gears A (driving) and B (driven) with
    their speeds in the mesh frame per unit input speed."""

    names: tuple[str, str]
    gears: tuple[GearErrors, GearErrors]
    speeds: tuple[float, float]
    internal: bool
    working_pressure_angle: float
    pressure_angle: float
    driven_base_radius: float


def _errors(spec: Any, teeth: int) -> GearErrors:
    return GearErrors(teeth) if spec is None else spec.value(teeth)


def _mesh(design: Any) -> _Mesh:
    kind = getattr(design, "type", None)
    if kind == "gear_pair":
        rel = design.kinematics().relative_speeds(1.0)
        zp, zg = design.pinion.teeth, design.gear.teeth
        alpha = design.mesh.pressure_angle
        x = design.pinion.shift + design.gear.shift
        aw = inv_inverse(inv(alpha) + 2 * x * math.tan(alpha) / (zp + zg))
        return _Mesh(("pinion", "gear"),
                     (_errors(design.pinion.errors, zp), _errors(design.gear.errors, zg)),
                     (rel["pinion"], rel["gear"]), False, aw, alpha,
                     design.base_radius("gear"))  # fmt: skip
    if kind == "khv":
        g = design.gears
        rel = design.kinematics().relative_speeds(1.0)
        pair = g.pair()
        errors = (
            _errors(g.ring_errors, g.ring_teeth),
            _errors(g.planet_errors, g.planet_teeth),
        )
        speeds = (rel["ring K"], rel["planet V"])
        aw, rb = pair.working_pressure_angle, pair.base_radius(1)
        return _Mesh(("ring", "planet"), errors, speeds, True, aw, g.pressure_angle, rb)
    raise ReducerlabError(
        f"transmission accuracy: computed for gear_pair, khv, cycloid_ball and nutation "
        f"designs; got a {kind or type(design).__name__} design"
    )


def transmission_accuracy(
    design: Any,
    samples: int | None = None,
    load: float | str | None = None,
    *,
    rigid: bool = False,
    positions: int = 24,
    tooth_size: float | None = None,
    mesh_te: Any = None,
    phases: int | None = None,
    stage: Callable[[str], None] | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> TransmissionAccuracyResult:
    """Output angle error over one output revolution: rigid kinematics, and under
    ``load`` the mesh's loaded transmission error (``analysis.loaded_accuracy``).

    Parameters
    ----------
    design : GearPairDesign or KHVDesign
        With the gears' ``errors`` tables (``drives.accuracy_specs``); none: zero error.
    samples : int, optional
        Even steps over one output revolution, 64 .. 2**20 (resolve the pitch steps:
        at least a few per tooth passing the mesh); under load more than twice the
        tooth-mesh order. Default 4096; under load the least multiple of the
        tooth-mesh order times ``positions`` from 4096 (each contact position a sample;
        a nutation drive's: of the least common multiple of its meshes', at most 2**20).
    load : float or str, optional
        Output torque (N m, or a string with units), or ``"design"`` for the design's
        operating output torque; None: unloaded (rigid kinematics only).
    rigid : bool
        Under load, teeth rigid beyond the contact half-space (no finite-element tooth
        model: fast, for checks).
    positions : int
        Under load, positions over one mesh cycle of the contact analysis (3..400).
    tooth_size : float, optional
        Finite-element tooth element size (m), as ``te_sweep``.
    mesh_te : TESweepResult, optional
        The contact's loaded TE at this load from an earlier run (a cache): reused. A
        nutation design's: one per pair (a list in pair order, a mapping by pair number;
        a lone result for the single-sided drive).
    phases : int, optional
        Under load, a cycloid_ball design's ball-set phases over one ball pitch
        (``analysis.loaded_accuracy_cycloid``; default 256); the gear contact's options
        (``rigid``, ``positions``, ``tooth_size``, ``mesh_te``) do not apply to it.
    stage, progress : callable, optional
        The contact analysis's ``stage(text)`` and ``progress(done, total)``.

    Returns
    -------
    TransmissionAccuracyResult
        ``delta theta_out = s / r_bB`` (rad; module docstring), under load plus
        ``-TE / r_bB`` about its mean, and its spectrum.

    Raises
    ------
    ReducerlabError
        A drive other than gear_pair, khv, cycloid_ball and nutation; ``samples``,
        ``load`` or an option out of range; contact options without a load;
        ``phases`` but for a loaded cycloid-ball design.
    """
    drive = DRIVE_SOURCES.get(getattr(design, "type", None))
    if load is None and (rigid or mesh_te is not None or tooth_size is not None):
        raise ReducerlabError("rigid, tooth_size, mesh_te: apply under load only; give load")
    if phases is not None and (load is None or getattr(design, "type", None) != "cycloid_ball"):
        raise ReducerlabError("phases: applies to a cycloid_ball design under load only")
    if drive is not None:  # cycloid_ball, nutation: their own laws (accuracy_drives)
        if load is not None and design.type == "cycloid_ball":  # the ball track under load
            from .loaded_accuracy_cycloid import cycloid_loaded

            u, names, parts, attrs, under = cycloid_loaded(
                design, samples, load, rigid=rigid, positions=positions, tooth_size=tooth_size,
                mesh_te=mesh_te, phases=phases, progress=progress)  # fmt: skip
            ratio = float(design.kinematics().ratio)
            res = TransmissionAccuracyResult.from_contributions(
                design, u, names, np.array(parts), ratio, **attrs)  # fmt: skip
            under.annotate(res.data)
            return res
        if load is not None and design.type != "nutation":
            raise ReducerlabError(
                f"load: the transmission accuracy under load is computed for gear_pair, khv "
                f"and nutation designs; a {design.type} design's is rigid kinematics only"
            )
        contact = {"positions": positions, "rigid": rigid, "tooth_size": tooth_size,
                   "sweeps": mesh_te, "stage": stage, "progress": progress}  # fmt: skip
        return _drive_accuracy(design, samples, drive, load, contact)
    m = _mesh(design)
    if samples is None:
        from .loaded_accuracy import loaded_samples

        samples = 4096 if load is None else loaded_samples(design, positions, mesh_te)
    if isinstance(samples, bool) or not isinstance(samples, int) or not 64 <= samples <= 2**20:
        raise ReducerlabError(f"samples: must be an integer in 64 .. 2**20; got {samples!r}")
    kin = design.kinematics()
    ratio = float(kin.ratio)
    u = 2 * math.pi * np.arange(samples) / samples  # output angle, its own sense
    theta_in = abs(ratio) * u
    ang = [v * theta_in for v in m.speeds]
    sigma_b = 1 if m.speeds[1] > 0 else -1
    tau = line_angle(sigma_b, m.internal, m.working_pressure_angle)
    # B's lead in its mesh-frame sense is the output's when both turn alike (the KHV
    # planet's angle relative to the carrier errs as its absolute one: the carrier is exact)
    out_sense = 1.0 if (m.speeds[1] > 0) == (ratio > 0) else -1.0
    zero = [GearErrors(g.teeth) for g in m.gears]
    sources, parts = [], []
    for k, (name, g) in enumerate(zip(m.names, m.gears, strict=True)):
        for label, only in (("eccentricity", GearErrors(g.teeth, g.eccentricity, g.phase)),
                            ("pitch", GearErrors(g.teeth, pitch=g.pitch))):  # fmt: skip
            pair = [only, zero[1]] if k == 0 else [zero[0], only]
            s = mesh_lead(ang[0], ang[1], *pair, tau, m.pressure_angle)
            sources.append(f"{name} {label}")
            parts.append(out_sense * s / m.driven_base_radius)
    for name, s in crank_leads(design, ang[0], tau):  # assembly errors (the KHV crank)
        sources.append(name)
        parts.append(out_sense * s / m.driven_base_radius)
    under = None
    if load is not None:
        from .loaded_accuracy import loaded_error

        under = loaded_error(design, load, u, out_sense, m.driven_base_radius,
                             positions=positions, rigid=rigid, tooth_size=tooth_size,
                             sweep=mesh_te, stage=stage, progress=progress)  # fmt: skip
        sources.append("mesh under load")
        parts.append(under.variation)
    res = TransmissionAccuracyResult.from_contributions(
        design, u, sources, np.array(parts), ratio,
        driven_base_radius=m.driven_base_radius, line_angle=tau,
        working_pressure_angle=m.working_pressure_angle,
        **assembly_attrs(design, m.working_pressure_angle),  # backlash change
    )  # fmt: skip
    if under is not None:
        under.annotate(res.data)
    return res


def _drive_accuracy(
    design: Any,
    samples: int | None,
    drive: Any,
    load: Any = None,
    contact: dict[str, Any] | None = None,
) -> TransmissionAccuracyResult:
    """A drive with its own law (``analysis.accuracy_drives.DRIVE_SOURCES``): its
    sources over one output revolution of ``samples`` (default 4096) even steps; under
    ``load`` (nutation) each mesh's loaded TE (``analysis.loaded_accuracy_nutation``,
    with the ``contact`` options)."""
    under = None
    if load is not None:
        from .loaded_accuracy_nutation import nutation_loaded_error, nutation_loaded_samples

        contact = contact or {}
        if samples is None:
            samples = nutation_loaded_samples(design, contact["positions"], contact["sweeps"])
    samples = 4096 if samples is None else samples
    if isinstance(samples, bool) or not isinstance(samples, int) or not 64 <= samples <= 2**20:
        raise ReducerlabError(f"samples: must be an integer in 64 .. 2**20; got {samples!r}")
    u = 2 * math.pi * np.arange(samples) / samples  # output angle, its own sense
    sources, parts, attrs = drive(design, u)
    if load is not None:
        under = nutation_loaded_error(design, load, u, **(contact or {}))
        sources, parts = sources + under.sources, list(parts) + under.variations
    ratio = float(design.kinematics().ratio)
    res = TransmissionAccuracyResult.from_contributions(design, u, sources, np.array(parts),
                                                        ratio, **attrs)  # fmt: skip
    if under is not None:
        under.annotate(res.data)
    return res
