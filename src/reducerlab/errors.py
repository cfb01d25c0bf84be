"""Exceptions raised by reducerlab.

Every error a user can provoke with bad input derives from :class:`ReducerlabError`, so
the command line can print its message without a traceback.
"""

from __future__ import annotations

__all__ = ["DesignError", "DivergenceError", "ModelError", "ReducerlabError"]


class ReducerlabError(Exception):
    """Base class of all errors caused by user input or user-built models."""


class DesignError(ReducerlabError, ValueError):
    """A design file or design dictionary broke a rule of its schema.

    The message names the source (file), the field path, the offending value and the
    rule, one line per problem.
    """

    def __init__(self, message: str, problems: list[str] | None = None) -> None:
        super().__init__(message)
        self.problems = problems or [message]


class ModelError(ReducerlabError, ValueError):
    """A :class:`~reducerlab.model.Model` or one of its elements is inconsistent."""


class DivergenceError(ReducerlabError):
    """A time integration would give (or gave) unbounded motion: the linear part has a
    divergent (negative-stiffness) mode, or the state left its bound. The message names
    the physical DOF(s), the time and the member (parameter value)."""
