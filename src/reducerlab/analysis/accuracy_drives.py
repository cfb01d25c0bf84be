"""Transmission-error sources of the cycloid-ball drive and the gear drives' assembly
errors, read from a design (issue 31; used by ``analysis.transmission_accuracy``).

Each function returns the sources' names and their output angle errors (rad, positive
ahead in the output's turning sense) over the output angles ``u`` (rad) of one output
revolution, the input turning counter-clockwise by ``|i| u``. The laws are in
:mod:`reducerlab.kinematics.accuracy_cycloid` and
:mod:`reducerlab.kinematics.accuracy_assembly`; docs/datasheet.md "Transmission
accuracy" gives the fields and the examples' numbers.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..kinematics.accuracy_assembly import axis_offset_lead, backlash_change, planet_axis_lead
from ..kinematics.accuracy_cycloid import centres_offset, output_error, transmission_offset
from ..kinematics.accuracy_nutation import (
    eccentricity_rotation,
    output_rotation,
    pitch_rotation,
    radial_ratio,
)

__all__ = [
    "DRIVE_SOURCES",
    "assembly_attrs",
    "crank_leads",
    "cycloid_sources",
    "nutation_sources",
]

Array = NDArray[np.float64]


def cycloid_sources(design: Any, u: Array) -> tuple[list[str], list[Array], dict[str, Any]]:
    """The cycloid-ball drive's sources: each groove's eccentricity, the crank's axis
    offset and tangential offset (its radius error moves the planetary disc along the
    line of centres: the balls' clearances change, not the output angle; first order).
    The attribute ``line_of_centres_offset_max`` (m) is the largest ``|c_y|`` over the
    revolution: ball ``i``'s clearance changes by ``c_y cos(theta_i)``.

    ``c_x`` (the centre disc's groove minus the planetary disc's along the
    transmission direction, in the frame of the eccentric) gives ``-c_x / r_2``
    (centre disc output) or ``c_x / r_3`` (planetary disc output, the centre disc
    fixed); ``r = z e / 2``.
    """
    ratio = float(design.kinematics().ratio)
    phi = abs(ratio) * np.asarray(u, float)
    turned = phi / ratio  # the output disc's rotation, counter-clockwise
    zero = np.zeros_like(phi)
    centre, planetary = (turned, zero) if design.output == "centre" else (zero, turned)
    r2 = design.pitch_radius(design.centre_disc.lobes)
    r3 = design.pitch_radius(design.planetary_disc.lobes)
    sense = math.copysign(1.0, ratio)  # the output turns with sign(1 / i)
    out: list[tuple[str, Array]] = []
    c_y = np.zeros_like(phi)  # along the line of centres: the balls' clearances
    t2 = design.centre_disc.track_errors
    if t2 is not None:
        c = transmission_offset(t2.eccentricity, t2.eccentricity_phase, centre, phi)
        out.append(("centre disc track eccentricity", c))
        c_y += centres_offset(t2.eccentricity, t2.eccentricity_phase, centre, phi)
    t3 = design.planetary_disc.track_errors
    if t3 is not None:
        c = -transmission_offset(t3.eccentricity, t3.eccentricity_phase, planetary, phi)
        out.append(("planetary disc track eccentricity", c))
        c_y -= centres_offset(t3.eccentricity, t3.eccentricity_phase, planetary, phi)
    k = design.input_shaft.crank_errors
    if k is not None:
        c_y -= centres_offset(k.axis_offset, k.axis_offset_phase, zero, phi) + k.radius_error
        # the crank moves the planetary disc (c_3): its axis offset is housing-fixed; its
        # tangential offset lies along -x (z x y) in the frame of the eccentric
        out.append(("crank axis offset", -transmission_offset(k.axis_offset, k.axis_offset_phase,
                                                              zero, phi)))  # fmt: skip
        out.append(("crank tangential offset", np.full_like(phi, k.tangential_offset)))
    names = [n for n, _ in out]
    parts = [sense * output_error(c, design.output, r2, r3) for _, c in out]
    return names, parts, {"output": str(design.output), "centre_pitch_radius": r2,
                          "planetary_pitch_radius": r3,
                          "line_of_centres_offset_max": float(np.abs(c_y).max())}  # fmt: skip


def crank_leads(design: Any, ring_angle: Array, line_angle: float) -> list[tuple[str, Array]]:
    """The KHV drive's crank errors (``[gears.crank_errors]``) as leads ``s`` (m) of the
    planet's flank in the carrier frame; none for another drive (the gear pair's
    centre-distance error gives none: :mod:`reducerlab.kinematics.accuracy_assembly`).

    ``ring_angle``: the ring's rotation in the carrier frame (rad).
    """
    if getattr(design, "type", None) != "khv" or design.gears.crank_errors is None:
        return []
    k = design.gears.crank_errors
    a = np.asarray(ring_angle, float)
    axis = planet_axis_lead(k.radius_error, k.tangential_offset, line_angle)
    return [
        ("crank radius and tangential offset", np.full_like(a, axis)),
        ("crank axis offset", axis_offset_lead(a, k.axis_offset, k.axis_offset_phase, line_angle)),
    ]


def assembly_attrs(design: Any, working_pressure_angle: float) -> dict[str, float]:
    """``backlash_change`` (m, normal backlash) from the gear pair's centre-distance
    error or the KHV crank's radius error, and ``backlash_change_arcsec`` at the
    output (over the driven gear's base radius); empty without one."""
    kind = getattr(design, "type", None)
    if kind == "gear_pair":
        da = design.mesh.centre_distance_error
        rb_sum, rb_out, internal = design.base_radius("pinion") + design.base_radius("gear"), \
            design.base_radius("gear"), False  # fmt: skip
    elif kind == "khv" and design.gears.crank_errors is not None:
        da = design.gears.crank_errors.radius_error
        pair = design.gears.pair()
        rb_sum, rb_out, internal = pair.base_radius(2) - pair.base_radius(1), \
            pair.base_radius(1), True  # fmt: skip
    else:
        return {}
    if not da:
        return {}
    dj = backlash_change(da, rb_sum, working_pressure_angle, internal)
    return {"backlash_change": dj, "backlash_change_arcsec": dj / rb_out / (math.pi / 648000)}


def nutation_sources(design: Any, u: Array) -> tuple[list[str], list[Array], dict[str, Any]]:
    """The nutation drive's sources: each bevel gear's eccentricity and pitch
    deviations (``[gearK.errors]``) as equivalent rotations in the crank frame, through
    the drive's two stages (:mod:`reducerlab.kinematics.accuracy_nutation`). The normals
    are the drive model's (paper 000 Eq. 4 with ``helix_angle``)."""
    kin = design.kinematics()
    ratio = float(kin.ratio)
    theta_in = abs(ratio) * np.asarray(u, float)
    double = design.sides == "double"
    rel = kin.relative_speeds(1.0)
    if not double:
        rel = {"gear 1": rel["nutating gear"], "gear 2": rel["central gear"]}
    cones = [c for pair in design.cones(design.theta) for c in pair]
    names = [f"gear {k}" for k in range(1, 5 if double else 3)]
    radii = {n: getattr(design, f"gear{k + 1}").mean_radius for k, n in enumerate(names)}
    beta, alpha_n = design.helix_angle, design.normal_pressure_angle
    sense = math.copysign(1.0, ratio)
    sources: list[str] = []
    parts: list[Array] = []
    for k, name in enumerate(names):
        spec = getattr(design, f"gear{k + 1}").errors
        if spec is None:
            continue
        angle = rel[name] * theta_in
        ecc = eccentricity_rotation(spec.eccentricity, spec.eccentricity_phase, angle,
                                    radial_ratio(cones[k], beta, alpha_n), radii[name])  # fmt: skip
        turning = 1 if rel[name] > 0 else -1
        teeth = getattr(design, f"gear{k + 1}").teeth
        pitch = pitch_rotation(tuple(spec.pitch_deviations), angle, teeth, radii[name], turning)
        for label, eps in (("eccentricity", ecc), ("pitch", pitch)):
            sources.append(f"{name} {label}")
            parts.append(sense * output_rotation({name: eps}, radii, double))
    return sources, parts, {"sides": str(design.sides), "nutation_angle": design.theta}


#: drive type -> its sources (names, output angle errors, attributes) over ``u``
DRIVE_SOURCES = {"cycloid_ball": cycloid_sources, "nutation": nutation_sources}
