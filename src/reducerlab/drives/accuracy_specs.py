"""Manufacturing errors of a gear as design fields (transmission accuracy, issue 31).

One table per gear (``[pinion.errors]`` / ``[gear.errors]`` of a gear pair,
``[gears.planet_errors]`` / ``[gears.ring_errors]`` of a KHV drive):

* ``eccentricity`` ``e`` (length >= 0): offset of the base circle's centre from the
  gear's axis (a gear whose radial runout ``F_r`` is all eccentricity has
  ``e = F_r / 2``);
* ``eccentricity_phase`` ``phi0``: its direction at zero rotation, counter-clockwise
  from the line of centres (from the driving gear's axis to the driven gear's);
* ``pitch_deviations``: the single pitch deviations ``f_pt,k`` (ISO 1328-1, on the
  reference circle, signed lengths), one per tooth, from tooth ``k`` to ``k + 1``; they
  close (sum zero).

The law is :mod:`reducerlab.kinematics.accuracy`; ``analysis.transmission_accuracy``
uses it.
"""

from __future__ import annotations

from pydantic import Field, model_validator

from ..design import Spec, angle_between, quantity
from ..design_files import field_rules
from ..kinematics.accuracy import GearErrors

__all__ = ["GearErrorSpec"]

#: 1 mm: far beyond any gear that meshes at all; catches "5" meant as um
LIMIT = 1e-3


class GearErrorSpec(Spec):
    """Eccentricity and single pitch deviations of one gear (lengths; a design file may
    say ``"5 um"``)."""

    eccentricity: quantity("length", ge=0, le=LIMIT) = 0.0  # type: ignore[valid-type]
    eccentricity_phase: angle_between(-360, 360, closed=True) = 0.0  # type: ignore[valid-type]
    pitch_deviations: list[quantity("length", ge=-LIMIT, le=LIMIT)] = Field(  # type: ignore[valid-type]
        default_factory=list
    )

    @model_validator(mode="after")
    def _closed(self) -> GearErrorSpec:
        f = self.pitch_deviations
        total = sum(f)
        if f and abs(total) > 1e-6 * sum(abs(v) for v in f):
            raise field_rules((
                "pitch_deviations",
                f"add up to {total * 1e6:.4g} um, not 0: the single pitch deviations of a "
                "whole gear close",
            ))  # fmt: skip
        return self

    def check_teeth(self, path: str, teeth: int) -> list[tuple[str, str]]:
        """The problem, named by ``path``, when the pitch list does not fit ``teeth``."""
        n = len(self.pitch_deviations)
        if n and n != teeth:
            return [(f"{path}.pitch_deviations", f"has {n} entries for {teeth} teeth; give one "
                     "per tooth or none")]  # fmt: skip
        return []

    def value(self, teeth: int) -> GearErrors:
        """The errors as :mod:`reducerlab.kinematics.accuracy` takes them."""
        return GearErrors(teeth, self.eccentricity, self.eccentricity_phase,
                          tuple(self.pitch_deviations))  # fmt: skip
