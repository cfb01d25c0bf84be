"""Gear materials for the load capacity rating and the rating conditions (SI units).

Default material: **case-hardened wrought steel, quality MQ** of ISO 6336-5:2016
(clause 5, the diagrams for case-hardened wrought steels, surface hardness 58 to 64
HRC, core hardness >= 30 HRC): ``sigma_Hlim = 1500 MPa`` (pitting, endurance limit for
contact stress) and ``sigma_Flim = 500 MPa`` (nominal stress number for bending, the
reference test gear's ``sigma_FE = Y_ST sigma_Flim = 1000 MPa``), ``E = 206 GPa``,
``nu = 0.3`` (ISO 6336-2:2019, the steel/steel ``Z_E = 189.8 sqrt(N/mm^2)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import ReducerlabError

__all__ = ["TREATMENTS", "GearMaterial", "RatingConditions"]

#: heat treatments known to the life factors Z_NT (ISO 6336-2 Table 2) and Y_NT
#: (ISO 6336-3 Table 4)
TREATMENTS = ("case-hardened", "through-hardened", "induction-hardened", "nitrided")


def _pos(name: str, v: float) -> None:
    if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
        raise ReducerlabError(f"{name}: must be a finite number > 0; got {v!r}")


@dataclass(frozen=True)
class GearMaterial:
    """Material of one gear for the rating.

    Attributes
    ----------
    youngs_modulus : float
        ``E`` (Pa), default 206e9.
    poisson_ratio : float
        ``nu``, default 0.3.
    sigma_Hlim : float
        Allowable stress number for contact ``sigma_Hlim`` (Pa), ISO 6336-5; default
        1500e6 (case-hardened wrought steel, MQ).
    sigma_Flim : float
        Nominal stress number for bending ``sigma_Flim`` (Pa), ISO 6336-5; default 500e6
        (case-hardened wrought steel, MQ).
    treatment : str
        One of :data:`TREATMENTS`; selects the life factor lines.
    """

    youngs_modulus: float = 206e9
    poisson_ratio: float = 0.3
    sigma_Hlim: float = 1500e6
    sigma_Flim: float = 500e6
    treatment: str = "case-hardened"

    def __post_init__(self) -> None:
        for name in ("youngs_modulus", "sigma_Hlim", "sigma_Flim"):
            _pos(f"material.{name}", getattr(self, name))
        if not 0.0 <= self.poisson_ratio < 0.5:
            raise ReducerlabError(
                f"material.poisson_ratio: must be in [0, 0.5); got {self.poisson_ratio!r}"
            )
        if self.treatment not in TREATMENTS:
            raise ReducerlabError(
                f"material.treatment: one of {', '.join(TREATMENTS)}; got {self.treatment!r}"
            )


@dataclass(frozen=True)
class RatingConditions:
    """Operating and manufacturing conditions of a rating, with documented defaults.

    Attributes
    ----------
    K_A : float
        Application factor (ISO 6336-1:2019 Annex B): 1.0, uniform driver and load.
    K_v : float
        Dynamic factor: 1.1 (an input: ISO 6336-1 method B needs the pitch deviations
        and the reduced mass, which the designs do not hold).
    K_Hbeta : float
        Face load factor (contact): 1.15, the lower bound many rating codes apply when
        the face load distribution is not computed (an input).
    K_Halpha : float
        Transverse load factor: 1.0 (accuracy grade 6 or finer at moderate load,
        ISO 6336-1 Table 9); the same value is used as ``K_Falpha``.
    hours : float
        Required life (h), default 20 000.
    viscosity_40 : float
        Lubricant kinematic viscosity at 40 C (m^2/s): 220e-6 (ISO VG 220).
    rz_flank, rz_root : float
        Mean peak-to-valley roughness of the flanks and the root (m): 4.8e-6 (R_a 0.8
        um with ``R_z = 6 R_a``) and 10e-6.
    S_Hmin, S_Fmin : float
        Minimum safety factors, 1.0 and 1.4 (ISO 6336-1 leaves them to the user; these
        are common minimum values).
    rim_thickness : float or None
        Rim thickness ``s_R`` (m) under the root, None for a solid body (``Y_B = 1``).
    accuracy_grade : int
        ISO 1328-1 accuracy grade; finer than 5 enables the deep tooth factor ``Y_DT``.
    """

    K_A: float = 1.0
    K_v: float = 1.1
    K_Hbeta: float = 1.15
    K_Halpha: float = 1.0
    hours: float = 20000.0
    viscosity_40: float = 220e-6
    rz_flank: float = 4.8e-6
    rz_root: float = 10e-6
    S_Hmin: float = 1.0
    S_Fmin: float = 1.4
    rim_thickness: float | None = None
    accuracy_grade: int = 6

    def __post_init__(self) -> None:
        for name in ("K_A", "K_v", "K_Hbeta", "K_Halpha"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and math.isfinite(v) and v >= 1.0):
                raise ReducerlabError(f"{name}: must be a finite number >= 1; got {v!r}")
        for name in ("hours", "viscosity_40", "rz_flank", "rz_root", "S_Hmin", "S_Fmin"):
            _pos(name, getattr(self, name))
