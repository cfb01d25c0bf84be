"""One reason of a verdict: a JSON-ready dict ``{rule, status, text, value, threshold,
...}`` (:func:`reducerlab.analysis.verdict.verdict` documents the rules)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["plain", "reason"]


def reason(rule: str, status: str, text: str, value: Any, threshold: Any, **more: Any) -> dict:
    """A reason: ``rule`` (its name), ``status`` (``"risk"``, ``"note"`` or ``"ok"``),
    ``text`` (one line with its number), ``value`` and ``threshold`` (the number judged
    and its limit, in the rule's unit), and any further fields, JSON-ready."""
    return {"rule": rule, "status": status, "text": text, "value": plain(value),
            "threshold": plain(threshold), **{k: plain(v) for k, v in more.items()}}  # fmt: skip


def plain(x: Any) -> Any:
    """A JSON-ready value: numpy scalars as Python ones, NaN as None."""
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, list | tuple):
        return [plain(v) for v in x]
    return x
