"""Discover the scalar parameters of a model (for sensitivities and sweeps)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from .assembly import Model
from .laws import TimeLaw

__all__ = ["parameter_paths"]


def _scalars(obj: Any, prefix: str) -> list[tuple[str, float]]:
    out: list[tuple[str, float]] = []
    for f in dataclasses.fields(obj):
        if f.name == "name":
            continue
        v = getattr(obj, f.name)
        if isinstance(v, bool):
            continue
        if isinstance(v, int | float | np.floating):
            out.append((f"{prefix}.{f.name}", float(v)))
        elif isinstance(v, TimeLaw):  # its mean, a field or derived (piecewise law)
            out.append((f"{prefix}.{f.name}", float(v.mean)))
    return out


def parameter_paths(model: Model) -> list[tuple[str, float]]:
    """``(path, value)`` of every scalar element parameter that affects ``M`` or ``K``.

    Loads and parameters that only enter the nonlinear terms (damping, backlash) are
    listed too when they are scalars; ``"speed"`` is listed when an element depends on
    it.
    """
    out: list[tuple[str, float]] = []
    for e in model.elements:
        for path, value in _scalars(e, e.name):
            d = model.derivative(path)
            if np.any(d.M) or np.any(d.K):
                out.append((path, value))
    d = model.derivative("speed")
    if np.any(d.K) or np.any(d.M):
        out.append(("speed", model.speed))
    return out
