"""Degrees of freedom: named coordinates of named bodies."""

from __future__ import annotations

import re
from dataclasses import dataclass

from ..errors import ModelError

__all__ = ["FAMILIES", "KINDS", "Dof"]

#: DOF kinds and the family each belongs to in energy classifications.
#: ``x, y`` translations across the body's axis, ``z`` translation along it,
#: ``rx, ry`` rotations (tilts) about the cross axes, ``rz`` rotation about the body's
#: own axis, ``u`` the equivalent linear displacement ``u = r * rz`` of a rotation at
#: radius ``r`` (paper 003 Eq. 3-7, paper 004 Eq. 1).
FAMILIES: dict[str, str] = {
    "x": "translational",
    "y": "translational",
    "z": "axial",
    "rx": "tilting",
    "ry": "tilting",
    "rz": "torsional",
    "u": "torsional",
}
KINDS = tuple(FAMILIES)
_BODY = re.compile(r"^[A-Za-z_][A-Za-z0-9_\-]*$")


@dataclass(frozen=True)
class Dof:
    """One generalised coordinate.

    Parameters
    ----------
    body : str
        Name of the body the coordinate belongs to (letters, digits, ``_``, ``-``).
    kind : str
        One of :data:`KINDS`.
    radius : float, optional
        Radius (m) of the equivalent linear displacement; required for kind ``u`` and
        forbidden for the others.

    Notes
    -----
    The DOF's name is ``"body.kind"``; elements refer to DOFs by that name. Its unit is
    m for translations and ``u``, rad for rotations.
    """

    body: str
    kind: str
    radius: float | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.body, str) or not _BODY.match(self.body):
            raise ModelError(
                f"Dof body {self.body!r}: must be a name of letters, digits, '_' or '-' "
                "starting with a letter"
            )
        if self.kind not in FAMILIES:
            raise ModelError(f"Dof {self.body}.{self.kind}: kind must be one of {KINDS}")
        if self.kind == "u":
            ok = isinstance(self.radius, int | float) and not isinstance(self.radius, bool)
            if not ok or not (0 < self.radius < float("inf")):
                raise ModelError(
                    f"Dof {self.name}: an equivalent linear displacement needs a radius > 0 m"
                )
        elif self.radius is not None:
            raise ModelError(f"Dof {self.name}: only kind 'u' takes a radius")

    @property
    def name(self) -> str:
        """``"body.kind"``."""
        return f"{self.body}.{self.kind}"

    @property
    def family(self) -> str:
        """Energy-classification family (translational, axial, tilting, torsional)."""
        return FAMILIES[self.kind]

    @property
    def is_rotation(self) -> bool:
        """True for rotations measured in rad (rx, ry, rz)."""
        return self.kind in ("rx", "ry", "rz")

    @property
    def unit(self) -> str:
        """SI unit of the coordinate."""
        return "rad" if self.is_rotation else "m"
