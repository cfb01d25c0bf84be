"""The registry of kinematic trains: one entry per drive kind, from which both the
kinematics-only designs (``type = "kinematics"``, field ``drive``) and the full drive
designs build their :class:`~reducerlab.kinematics.DriveKinematics`.

A new drive kind adds its kinematics class to :mod:`reducerlab.kinematics.trains` and one
:class:`Train` to :data:`TRAINS`; a kinematics-only design file then accepts it (its
tooth keys, outputs and nutation-angle rule come from the entry) with no other change.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from ..errors import ReducerlabError
from .trains import (
    CycloidBallDrive,
    DoubleNutationDrive,
    DriveKinematics,
    ExternalGearPair,
    KHVDrive,
    NutationDrive,
)

__all__ = ["TRAINS", "Train"]

Teeth = Mapping[str, int]

#: ``factory(teeth, nutation_angle, contact, output)``: a train's kinematics from its
#: tooth numbers, nutation angle (rad, None for a planar train), bevel contact type and
#: output member.
Factory = Callable[[Teeth, float | None, str, str], DriveKinematics]


@dataclass(frozen=True)
class Train:
    """A kinematic train: what a drive kind needs and how its kinematics are built.

    Attributes
    ----------
    name : str
        The drive kind (the ``drive`` of a kinematics-only design).
    teeth : tuple of str
        Keys of the tooth (lobe) numbers the train needs.
    outputs : tuple of str
        The members that may be the output; the first is the default.
    nutating : bool
        Whether a member nutates: the train then needs a nutation angle and has a bevel
        contact type (``"internal"`` or ``"external"`` cones).
    factory : callable
        ``factory(teeth, nutation_angle, contact, output) -> DriveKinematics``.
    papers : tuple of str
        Headings (their starts) of the ``docs/assumptions.md`` sections whose choices
        apply to the drive kind: the papers behind it; the report quotes them.
    """

    name: str
    teeth: tuple[str, ...]
    outputs: tuple[str, ...]
    nutating: bool
    factory: Factory
    papers: tuple[str, ...] = ()

    def teeth_rule(self, teeth: Mapping[str, object]) -> str | None:
        """The rule ``teeth`` breaks (keys missing or unknown), or None when its keys are
        exactly :attr:`teeth`."""
        missing = [k for k in self.teeth if k not in teeth]
        extra = [k for k in teeth if k not in self.teeth]
        if not (missing or extra):
            return None
        return (
            f"teeth for drive {self.name!r} must be exactly {{{', '.join(self.teeth)}}}"
            + (f"; missing {missing}" if missing else "")
            + (f"; unknown {extra}" if extra else "")
        )

    def build(
        self,
        teeth: Mapping[str, int],
        nutation_angle: float | None = None,
        contact: str | None = None,
        output: str | None = None,
    ) -> DriveKinematics:
        """The train's kinematics.

        Parameters
        ----------
        teeth : mapping of str to int
            Tooth (lobe) numbers under the keys :attr:`teeth`.
        nutation_angle : float, optional
            rad; nutating trains only.
        contact : {"internal", "external"}, optional
            Bevel contact type of a nutating train; default ``"internal"``.
        output : str, optional
            One of :attr:`outputs`; default the first.

        Raises
        ------
        ReducerlabError
            When the tooth keys are not the train's or the kinematics class refuses the
            values (tooth numbers, angle, output).
        """
        rule = self.teeth_rule(teeth)
        if rule is not None:
            raise ReducerlabError(rule)
        return self.factory(teeth, nutation_angle, contact or "internal", output or self.outputs[0])


def _nutation(z: Teeth, angle: float | None, contact: str, output: str) -> DriveKinematics:
    return NutationDrive(z["nutating"], z["central"], angle, contact, output)  # type: ignore[arg-type]


def _double_nutation(z: Teeth, angle: float | None, contact: str, _: str) -> DriveKinematics:
    return DoubleNutationDrive(z["z1"], z["z2"], z["z3"], z["z4"], angle, contact)  # type: ignore[arg-type]


def _khv(z: Teeth, angle: float | None, contact: str, output: str) -> DriveKinematics:
    return KHVDrive(z["planet"], z["ring"])


def _cycloid_ball(z: Teeth, angle: float | None, contact: str, output: str) -> DriveKinematics:
    return CycloidBallDrive(z["centre"], z["planetary"], output)


def _gear_pair(z: Teeth, angle: float | None, contact: str, output: str) -> DriveKinematics:
    return ExternalGearPair(z["pinion"], z["gear"])


#: Every kinematic train by drive kind (paper 000: nutation drives, 003: cycloid ball,
#: 004: KHV), in the order design-file messages list them.
TRAINS: dict[str, Train] = {
    t.name: t
    for t in (
        Train(
            "nutation",
            ("nutating", "central"),
            ("central", "nutating"),
            True,
            _nutation,
            papers=("Paper 000", "Paper 001", "Paper 002", "Papers 000", "Papers 001"),
        ),
        Train(
            "double_nutation",
            ("z1", "z2", "z3", "z4"),
            ("gear4",),
            True,
            _double_nutation,
            papers=("Paper 000", "Paper 001", "Paper 002", "Papers 000", "Papers 001"),
        ),
        Train("khv", ("planet", "ring"), ("planet",), False, _khv, papers=("Paper 004",)),
        Train(
            "cycloid_ball",
            ("centre", "planetary"),
            ("centre", "planetary"),
            False,
            _cycloid_ball,
            papers=("Paper 003", "Papers 000, 002, 003"),
        ),
        Train("gear_pair", ("pinion", "gear"), ("gear",), False, _gear_pair),
    )
}
