"""The ``[material]`` table of the cylindrical designs (``gear_pair``, ``khv``): elastic
constants and the material limits of the load capacity rating (issue 29).

Defaults: case-hardened wrought steel of quality MQ, ISO 6336-5:2016 (the diagrams for
case-hardened wrought steels): ``sigma_Hlim = 1500 MPa``, ``sigma_Flim = 500 MPa``;
``E = 206 GPa``, ``nu = 0.3`` (the steel of ISO 6336-2's ``Z_E = 189.8``).
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from ..design import Spec, quantity

__all__ = ["GearMaterialSpec", "Treatment"]

#: heat treatments known to the rating's life factors (ISO 6336-2 Table 2, -3 Table 4)
Treatment = Literal["case-hardened", "through-hardened", "induction-hardened", "nitrided"]


class GearMaterialSpec(Spec):
    """Material of both gears (``[material]``): ``youngs_modulus``, ``poisson_ratio``,
    the allowable stress numbers ``sigma_Hlim`` (contact) and ``sigma_Flim`` (bending) of
    ISO 6336-5, the ``treatment`` that selects the life factor lines and the Coulomb
    ``friction_coefficient`` of the tooth contacts in ``[0, 0.3]``."""

    youngs_modulus: quantity("pressure", gt=0) = 206e9  # type: ignore[valid-type]
    poisson_ratio: float = Field(0.3, ge=0.0, lt=0.5)
    sigma_Hlim: quantity("pressure", gt=0) = 1500e6  # type: ignore[valid-type]
    sigma_Flim: quantity("pressure", gt=0) = 500e6  # type: ignore[valid-type]
    treatment: Treatment = "case-hardened"
    #: Coulomb coefficient of the tooth contacts (``analysis.efficiency``): lubricated
    #: steel gears in mixed friction run at 0.04 to 0.08 (Niemann/Winter Vol. II, 1989)
    friction_coefficient: float = Field(0.05, ge=0.0, le=0.3)
