"""Policies of the sweeps that follow an attractor: small validated enums shared by the
command line and the Python API (one spelling, one check)."""

from __future__ import annotations

from enum import StrEnum
from typing import Any

from ..errors import ReducerlabError

__all__ = ["Continuation"]


class Continuation(StrEnum):
    """How a parameter sweep starts each value.

    ``up`` / ``down``: each value starts from the state the previous value ended in,
    stepping up or down the axis (jumps and hysteresis show); ``both``: the two sweeps
    (coexisting attractors show where they differ); ``none``: every value starts from
    its own static equilibrium (independent runs).
    """

    UP = "up"
    DOWN = "down"
    BOTH = "both"
    NONE = "none"

    @property
    def directions(self) -> list[str]:
        """The sweep directions run: ``["up", "down"]`` for ``both``, ``[]`` for ``none``."""
        if self is Continuation.NONE:
            return []
        return ["up", "down"] if self is Continuation.BOTH else [self.value]

    @classmethod
    def parse(
        cls, value: Any, what: str, allowed: tuple[Continuation, ...] | None = None
    ) -> Continuation:
        """``value`` (a Continuation, its name ``"up"``/... or None for ``none``) as a
        Continuation, checked against ``allowed``.

        Raises
        ------
        ReducerlabError
            Naming ``what`` and the allowed values.
        """
        allowed = allowed or tuple(cls)
        names = [c.value for c in allowed]
        shown = [repr(n) for n in names] + (["None"] if cls.NONE in allowed else [])
        shown = ", ".join(shown[:-1]) + " or " + shown[-1] if len(shown) > 1 else shown[0]
        try:
            c = cls.NONE if value is None else cls(value)
        except ValueError:
            c = None
        if c is None or c not in allowed:
            raise ReducerlabError(f"{what}: continuation must be {shown}, got {value!r}")
        return c
