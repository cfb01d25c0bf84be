"""Mesh stiffness of spur gear pairs after ISO 6336-1 (method B), with profile shift,
and the parabolic single/double-tooth time law of paper 004 (Eq. 7-10).

``q' = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1^2
+ C9 x2^2`` (mm um/N), the single-pair stiffness per unit face width is ``c' = 1/q'``
and, with the correction factor 0.8 of solid gears, the pitch-point stiffness of a
pair of face width ``b`` is ``k_C = 0.8 b / q'`` (paper 004 Eq. 7, with b in mm it is
N/um; here everything is SI). For internal gearing paper 004 (Eq. 8) flips the signs of
the two ``x2`` terms; ``internal=True`` does the same.

ISO 6336-1's single stiffness ``c'`` and mesh stiffness ``c_gamma_alpha`` (method B) of
a :class:`~reducerlab.geometry.spur.SpurGear` pair: :func:`single_pair_stiffness`,
:func:`mesh_stiffness_c_gamma`.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from ..errors import ReducerlabError
from ..model import PiecewisePolynomial

if TYPE_CHECKING:
    from ..geometry.spur import SpurGear

__all__ = [
    "E_STEEL",
    "ISO6336_Q",
    "ISO_STIFFNESS_TO_SI",
    "MIN_SPECIFIC_LOAD",
    "basic_rack_factor",
    "iso6336_q",
    "mesh_stiffness_c_gamma",
    "pitch_point_stiffness",
    "single_double_law",
    "single_pair_stiffness",
]

#: Coefficients C1..C9 of ISO 6336-1 for q' (mm um / N). Paper 004 prints C1 = 0.04732;
#: the standard's value is 0.04723 (see docs/assumptions.md).
ISO6336_Q = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)


def iso6336_q(z1: float, z2: float, x1: float, x2: float, *, internal: bool = False) -> float:
    """Minimum flexibility ``q'`` of a tooth pair (mm um/N) for equivalent tooth numbers
    ``z1, z2`` and shift coefficients ``x1, x2`` (paper 004 Eq. 8)."""
    c1, c2, c3, c4, c5, c6, c7, c8, c9 = ISO6336_Q
    s = -1.0 if internal else 1.0  # the x2 terms: "+" for inner gearing in paper 004
    q = (
        c1 + c2 / z1 + c3 / z2 + c4 * x1 + c5 * x1 / z1
        + s * c6 * x2 + s * c7 * x2 / z2 + c8 * x1**2 + c9 * x2**2
    )  # fmt: skip
    if not q > 0:
        raise ReducerlabError(f"ISO 6336 flexibility q' = {q:.4g} is not positive")
    return q


def pitch_point_stiffness(
    face_width: float, z1: float, z2: float, x1: float, x2: float, *, internal: bool = False,
    correction: float = 0.8,
) -> float:  # fmt: skip
    """Single-pair stiffness at the pitch point ``k_C = 0.8 b / q'`` (N/m; b in m).

    ``q'`` is in mm um/N, so ``b[mm] / q'`` is in N/um: ``k_C = 0.8 b[mm] / q' * 1e6``
    N/m (paper 004 Eq. 7 writes ``0.8e3 b / q`` in N/mm).
    """
    if not face_width > 0:
        raise ReducerlabError(f"face width must be > 0 m, got {face_width!r}")
    q = iso6336_q(z1, z2, x1, x2, internal=internal)
    return correction * (face_width * 1e3) / q * 1e6


def single_double_law(k_pitch: float, contact_ratio: float, mesh_period: float,
                      ref_speed: float | None = None) -> PiecewisePolynomial:  # fmt: skip
    """Mesh stiffness over one mesh period (paper 004 Eq. 9, intervals derived).

    A single pair along its path of contact ``tau in [0, eps]`` (in base pitches) has
    the parabola ``k_s(tau) = A tau^2 + B tau + C`` with ``A = -2k'/eps^2``,
    ``B = 2k'/eps``, ``C = k'``: ``k'`` at engagement and exit, ``1.5 k' = k_C`` at
    mid-path. Within a mesh period (phase ``s in [0, 1)``) two pairs mesh for
    ``s < eps - 1`` (``k_s(s) + k_s(s + 1)``) and one pair after it (``k_s(s)``); the
    printed Eq. 9 assigns the two expressions to the opposite intervals. The mean is
    the exact integral, ``(4/3) k' eps = 0.8889 eps k_C``.
    """
    if not 1.0 < contact_ratio < 2.0:
        raise ReducerlabError(
            f"the single/double-tooth law needs 1 < contact ratio < 2, got {contact_ratio:.4g}"
        )
    kp = k_pitch / 1.5
    e = contact_ratio
    A, B, C = -2 * kp / e**2, 2 * kp / e, kp
    return PiecewisePolynomial(
        period=mesh_period,
        breaks=(0.0, e - 1.0),
        coefficients=((A + B + 2 * C, 2 * (A + B), 2 * A), (C, B, A)),
        ref_speed=ref_speed,
    )


# ---------------------------------------------------------------------------------------
# ISO 6336-1 tooth stiffness parameters c' and c_gamma (method B) of spur gear pairs
# ---------------------------------------------------------------------------------------

#: 1 N/(mm um) (ISO 6336's unit of stiffness per face width) in SI, N/m per m: 1e9 N/m^2.
ISO_STIFFNESS_TO_SI = 1e9
#: Young's modulus of steel E_st behind ISO 6336-1's stiffness values (Pa): 206000 N/mm^2.
E_STEEL = 206e9
#: ISO 6336-1: method B stiffness values hold for a specific load F_t K_A / b >= 100 N/mm
#: (in SI: 1e5 N/m).
MIN_SPECIFIC_LOAD = 1e5


def _spur_gears(pinion: Any, wheel: Any) -> None:
    from ..geometry.spur import SpurGear

    for name, g in (("pinion", pinion), ("wheel", wheel)):
        if not isinstance(g, SpurGear):
            raise ReducerlabError(f"{name}: must be a SpurGear; got {type(g).__name__}")


def basic_rack_factor(dedendum: float, pressure_angle: float) -> float:
    """Basic rack factor ``C_B = (1 + 0.5 (1.2 - h_fP/m_n)) (1 - 0.02 (20 - alpha_Pn))``
    of ISO 6336-1 (method B), ``h_fP/m_n`` the dedendum coefficient of the basic rack,
    ``alpha_Pn`` its pressure angle **in degrees** (``pressure_angle`` is given in rad).
    ISO 53 (``h_fP = 1.25 m_n``, 20 deg): ``C_B = 0.975``."""
    return (1 + 0.5 * (1.2 - dedendum)) * (1 - 0.02 * (20.0 - math.degrees(pressure_angle)))


def single_pair_stiffness(
    pinion: SpurGear,
    wheel: SpurGear,
    *,
    correction: float = 0.8,
    blank_factor: float = 1.0,
    youngs_modulus: float | None = None,
    specific_load: float | None = None,
    si: bool = False,
    check_range: bool = True,
) -> float:
    """Single stiffness ``c'`` of a spur gear tooth pair, ISO 6336-1:2019 clause 9
    (tooth stiffness parameters), method B.

    ``c' = c'_th C_M C_R C_B cos(beta)`` with the theoretical single stiffness
    ``c'_th = 1 / q'`` (:func:`iso6336_q`, ``z_n = z`` and ``cos(beta) = 1`` for spur
    gears), the correction factor ``C_M = 0.8`` (the difference between the theoretical
    values of solid disc gears and measured ones), the gear blank factor ``C_R = 1`` for
    solid gears (rim thickness ``s_R >= 3.5 m_n``) and the basic rack factor ``C_B``
    (:func:`basic_rack_factor`; the mean of pinion and wheel when their basic racks
    differ). Other materials than steel/steel: times ``E / E_st``,
    ``E_st = 206000 N/mm^2``.

    Validity (as stated by ISO 6336-1): the values hold for a specific load
    ``F_t K_A / b >= 100 N/mm``; for lower loads the standard reduces ``c'`` by
    ``((F_t K_A / b) / 100 N/mm)^0.25`` (applied when ``specific_load`` is given; this
    factor is quoted from public transcriptions of the standard, e.g. the
    ``gfsReboucas/Drivetrain`` ISO 6336 classes and Python ports, not from the standard's
    text, which was not available). ``q'`` is the regression for external gears with
    ``x1 >= x2`` and ``-0.5 <= x1 + x2 <= 2`` (``check_range``). The spread of the
    measurements the regression was fitted to could not be found in an accessible source;
    it is not stated here.

    Parameters
    ----------
    pinion, wheel : SpurGear
        The pair (:mod:`reducerlab.geometry.spur`); their teeth, shifts, dedendum and
        pressure angle enter.
    correction : float
        ``C_M`` (0.8).
    blank_factor : float
        ``C_R`` (1 for solid gears).
    youngs_modulus : float, optional
        ``E = 2 E1 E2 / (E1 + E2)`` (Pa) for non-steel pairs; default steel.
    specific_load : float, optional
        ``F_t K_A / b`` in **N/m** (SI; 100 N/mm = 1e5 N/m); below 1e5 N/m the reduction
        above is applied.
    si : bool
        Return N/m per metre of face width (N/m^2) instead of N/(mm um).
    check_range : bool
        Raise when ``x1 < x2`` or ``x1 + x2`` is outside ``[-0.5, 2]``.

    Returns
    -------
    float
        ``c'`` in N/(mm um) (ISO 6336), or N/m^2 with ``si``.

    Raises
    ------
    ReducerlabError
        Not two :class:`SpurGear`, a factor not > 0, or the shifts outside the
        regression's range.
    """
    _spur_gears(pinion, wheel)
    for name, v in (("correction", correction), ("blank_factor", blank_factor)):
        if (
            isinstance(v, bool)
            or not isinstance(v, int | float)
            or not (math.isfinite(v) and v > 0)
        ):
            raise ReducerlabError(f"{name}: must be a finite number > 0; got {v!r}")
    x1, x2 = pinion.shift, wheel.shift
    if check_range and (x1 < x2 or not -0.5 <= x1 + x2 <= 2.0):
        raise ReducerlabError(
            f"pinion.shift, wheel.shift: ISO 6336-1's q' regression needs x1 >= x2 and "
            f"-0.5 <= x1 + x2 <= 2; got x1 = {x1:.4g}, x2 = {x2:.4g} (check_range=False "
            "to extrapolate)"
        )
    c_th = 1.0 / iso6336_q(pinion.teeth, wheel.teeth, x1, x2)
    c_b = 0.5 * (
        basic_rack_factor(pinion.dedendum, pinion.pressure_angle)
        + basic_rack_factor(wheel.dedendum, wheel.pressure_angle)
    )
    c = c_th * correction * blank_factor * c_b
    if youngs_modulus is not None:
        if (
            isinstance(youngs_modulus, bool)
            or not isinstance(youngs_modulus, int | float)
            or not (math.isfinite(youngs_modulus) and youngs_modulus > 0)
        ):
            raise ReducerlabError(
                f"youngs_modulus: must be a modulus > 0 Pa; got {youngs_modulus!r}"
            )
        c *= youngs_modulus / E_STEEL
    if specific_load is not None:
        w = specific_load
        if (
            isinstance(w, bool)
            or not isinstance(w, int | float)
            or not (math.isfinite(w) and w > 0)
        ):
            raise ReducerlabError(f"specific_load: must be a load > 0 N/m; got {w!r}")
        if w < MIN_SPECIFIC_LOAD:
            c *= (w / MIN_SPECIFIC_LOAD) ** 0.25
    return c * ISO_STIFFNESS_TO_SI if si else c


def mesh_stiffness_c_gamma(
    pinion: SpurGear,
    wheel: SpurGear,
    *,
    contact_ratio: float | None = None,
    center_distance: float | None = None,
    si: bool = False,
    **kwargs: Any,
) -> float:
    """Mean mesh stiffness per unit face width ``c_gamma_alpha = c' (0.75 eps_alpha +
    0.25)`` of ISO 6336-1:2019 clause 9, method B, for spur gears (``eps_beta = 0``).

    Parameters
    ----------
    pinion, wheel : SpurGear
    contact_ratio : float, optional
        ``eps_alpha``; default that of
        ``SpurPair(pinion, wheel, center_distance)`` (:mod:`reducerlab.geometry.spur`).
    center_distance : float, optional
        Working centre distance (m) for the contact ratio; default zero backlash.
    si : bool
        Return N/m per metre of face width (N/m^2) instead of N/(mm um).
    **kwargs
        Passed to :func:`single_pair_stiffness`.

    Notes
    -----
    The same limits as :func:`single_pair_stiffness` apply (specific load >= 100 N/mm).
    Transcriptions of the standard also quote a reduction of ``c_gamma_alpha`` by 10 %
    for spur gears with ``eps_alpha < 1.2``; it is not applied here.
    """
    from ..geometry.spur import SpurPair

    _spur_gears(pinion, wheel)
    if contact_ratio is None:
        contact_ratio = SpurPair(pinion, wheel, center_distance).contact_ratio
    eps = contact_ratio
    if (
        isinstance(eps, bool)
        or not isinstance(eps, int | float)
        or not (math.isfinite(eps) and eps >= 1)
    ):
        raise ReducerlabError(f"contact_ratio: must be a number >= 1; got {eps!r}")
    c = single_pair_stiffness(pinion, wheel, si=si, **kwargs)
    return c * (0.75 * eps + 0.25)
