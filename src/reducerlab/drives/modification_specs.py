"""Flank modifications as design fields (crowning, tip and root relief, slopes).

One table per gear (``[gearN.modifications]`` of a nutation design,
``[pinion.modifications]`` / ``[gear.modifications]`` of a gear pair,
``[gears.planet_modifications]`` / ``[gears.ring_modifications]`` of a KHV drive) gives
that gear's loaded flank its modification, in the terms of ISO 21771 §9 (``C_beta``,
``C_alpha``, ``C_a`` and ``L_Ca``, ``C_f`` and ``L_Cf``, ``f_Hbeta``, ``f_Halpha``); the
switch ``flank_modifications = "crowned"`` (in ``[surface]``, ``[mesh]``, ``[gears]``)
gives every gear without its own table the default crowned layout of
:func:`reducerlab.contact.modifications.crowned_layout`, sized by the design load;
``"none"`` (the default) leaves them unmodified. The law is in
:mod:`reducerlab.contact.modifications`; docs/contact.md lists fields and defaults.
"""

from __future__ import annotations

from typing import Literal

from pydantic import model_validator

from ..contact.modifications import MAX_AMOUNT, FlankModification
from ..design import Spec, quantity
from ..design_files import field_rules

__all__ = ["Layout", "ModificationSpec"]

#: The switch of the default layout: ``"none"`` (unmodified) or ``"crowned"``
Layout = Literal["none", "crowned"]

Amount = quantity("length", ge=0, le=MAX_AMOUNT)
Slope = quantity("length", ge=-MAX_AMOUNT, le=MAX_AMOUNT)
ReliefLength = quantity("length", ge=0)


class ModificationSpec(Spec):
    """Modifications of one gear's loaded flank (lengths; a design file may say
    ``"12 um"``).

    Attributes
    ----------
    lead_crowning : float
        ``C_beta`` (m): ease-off at each end of the face, parabolic from its middle.
    profile_crowning : float
        ``C_alpha`` (m): ease-off at each end of the active profile, parabolic.
    tip_relief, tip_relief_length : float
        ``C_a`` (m) at the tip, running out over ``L_Ca`` (m, along the profile: the roll
        length of an involute, the arc length of a bevel flank).
    root_relief, root_relief_length : float
        ``C_f`` (m) at the root end of the active flank, over ``L_Cf`` (m).
    relief_shape : {"linear", "parabolic"}
    lead_slope, profile_slope : float
        ``f_Hbeta``, ``f_Halpha`` (m, signed): ease-off difference between the face ends
        (second minus first) and between tip and root end.
    corner_relief, corner_relief_length : float
        ``C_c`` (m) at the profile's corner (the double arc's concave/transition joint),
        running out over ``L_Cc`` (m, along the profile) on each side of it.
    transition_relief, transition_relief_length : float
        ``C_t`` (m) over the whole transition piece of the profile (the double arc's
        transition arc), running out over ``L_Ct`` (m, along the profile) beyond each
        end.
    """

    lead_crowning: Amount = 0.0  # type: ignore[valid-type]
    profile_crowning: Amount = 0.0  # type: ignore[valid-type]
    tip_relief: Amount = 0.0  # type: ignore[valid-type]
    tip_relief_length: ReliefLength = 0.0  # type: ignore[valid-type]
    root_relief: Amount = 0.0  # type: ignore[valid-type]
    root_relief_length: ReliefLength = 0.0  # type: ignore[valid-type]
    relief_shape: Literal["linear", "parabolic"] = "linear"
    lead_slope: Slope = 0.0  # type: ignore[valid-type]
    profile_slope: Slope = 0.0  # type: ignore[valid-type]
    corner_relief: Amount = 0.0  # type: ignore[valid-type]
    corner_relief_length: ReliefLength = 0.0  # type: ignore[valid-type]
    transition_relief: Amount = 0.0  # type: ignore[valid-type]
    transition_relief_length: ReliefLength = 0.0  # type: ignore[valid-type]

    @model_validator(mode="after")
    def _lengths(self) -> ModificationSpec:
        for amount in ("tip_relief", "root_relief", "corner_relief", "transition_relief"):
            if getattr(self, amount) > 0 and getattr(self, f"{amount}_length") <= 0:
                raise field_rules((
                    f"{amount}_length",
                    f"must be > 0 with {amount} = {getattr(self, amount) * 1e6:.4g} um (the "
                    "length over which the relief runs out)",
                ))  # fmt: skip
        return self

    def value(self) -> FlankModification:
        """The modification as the contact analysis takes it."""
        return FlankModification(**self.model_dump())
