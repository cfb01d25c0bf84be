"""Gear geometry: involute functions and internal gear pairs with profile shift."""

from .internal_pair import InternalGearPair, inv, inv_inverse

__all__ = ["InternalGearPair", "inv", "inv_inverse"]
