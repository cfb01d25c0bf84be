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

Assembly and track errors (``TrackErrorSpec``, ``CrankErrorSpec``): the cycloid-ball
drive's ball tracks (``[centre_disc.track_errors]``, ``[planetary_disc.track_errors]``)
and the crank of the KHV and cycloid-ball drives (``[gears.crank_errors]``,
``[input_shaft.crank_errors]``); their laws are in
:mod:`reducerlab.kinematics.accuracy_assembly` and
:mod:`reducerlab.kinematics.accuracy_cycloid`.
"""

from __future__ import annotations

from pydantic import Field, model_validator

from ..design import Spec, angle_between, quantity
from ..design_files import field_rules
from ..kinematics.accuracy import GearErrors

__all__ = ["CrankErrorSpec", "GearErrorSpec", "TrackErrorSpec"]

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


class TrackErrorSpec(Spec):
    """Eccentricity of a cycloid-ball disc's groove (its trochoid's centre off the
    disc's axis), ``[centre_disc.track_errors]`` / ``[planetary_disc.track_errors]``.

    ``eccentricity`` (length, 0..1 mm; half the groove's radial runout) and
    ``eccentricity_phase``, its direction at zero rotation, counter-clockwise from the
    line of centres (the centre disc's axis to the planetary disc's centre) at zero
    input angle.
    """

    eccentricity: quantity("length", ge=0, le=LIMIT) = 0.0  # type: ignore[valid-type]
    eccentricity_phase: angle_between(-360, 360, closed=True) = 0.0  # type: ignore[valid-type]


class CrankErrorSpec(Spec):
    """Errors of the crank (the input's eccentric: the KHV carrier, the cycloid-ball
    input shaft), ``[gears.crank_errors]`` / ``[input_shaft.crank_errors]``.

    * ``radius_error`` (signed length): the eccentric journal's radius minus its nominal
      (the centre distance of the KHV pair, the cycloid-ball eccentricity ``e``);
    * ``tangential_offset`` (signed length): the journal's offset perpendicular to the
      crank, counter-clockwise positive (an angular error of the crank);
    * ``axis_offset`` (length >= 0) and ``axis_offset_phase``: the crank's axis of
      rotation off the axis of the fixed member (the KHV ring, the cycloid-ball centre
      disc's bearing axis), a housing-fixed vector; its direction counter-clockwise
      from the crank's direction at zero input angle.

    Lengths 0..1 mm in size.
    """

    radius_error: quantity("length", ge=-LIMIT, le=LIMIT) = 0.0  # type: ignore[valid-type]
    tangential_offset: quantity("length", ge=-LIMIT, le=LIMIT) = 0.0  # type: ignore[valid-type]
    axis_offset: quantity("length", ge=0, le=LIMIT) = 0.0  # type: ignore[valid-type]
    axis_offset_phase: angle_between(-360, 360, closed=True) = 0.0  # type: ignore[valid-type]
