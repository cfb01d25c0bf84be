"""Exceptions raised by reducerlab.

Every error a user can provoke with bad input derives from :class:`ReducerlabError`, so
the command line can print its message without a traceback.
"""

from __future__ import annotations

import copy
import functools
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = [
    "BudgetError",
    "DesignError",
    "DivergenceError",
    "ModelError",
    "ReducerlabError",
    "names_source",
    "source_of",
]

F = TypeVar("F", bound=Callable[..., Any])


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


class BudgetError(ReducerlabError, ValueError):
    """The work or memory a command would need, estimated before anything is allocated
    or meshed, exceeds the machine's free memory or a documented bound. The message gives
    the estimate, the limit and the setting that controls the size
    (:mod:`reducerlab.budget`)."""


def source_of(target: Any) -> str | None:
    """Where a design or a model built from one came from (its file), if known: a
    design's ``source``, or a model's ``metadata["source"]``."""
    source = getattr(target, "source", None)
    if not isinstance(source, str):
        metadata = getattr(target, "metadata", None)
        source = metadata.get("source") if isinstance(metadata, dict) else None
    return source if isinstance(source, str) and source and source != "<design>" else None


def names_source(func: F) -> F:
    """Decorate an analysis whose first argument is a design or a model: a
    :class:`ReducerlabError` it raises starts with the design's file (``FILE: ...``), as
    every design error does, so that a user running several designs knows which one."""

    @functools.wraps(func)
    def wrapper(target: Any, *args: Any, **kwargs: Any) -> Any:
        try:
            return func(target, *args, **kwargs)
        except ReducerlabError as exc:
            source = source_of(target)
            if source is None or source in str(exc):
                raise
            new = copy.copy(exc)
            new.args = (f"{source}: {exc}", *exc.args[1:])
            raise new from None

    return wrapper  # type: ignore[return-value]
