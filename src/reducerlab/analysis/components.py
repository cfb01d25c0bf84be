"""Natural frequencies of components (gear bodies) computed elsewhere, for the resonance
verdict and the Campbell diagram.

The finite-element modes of a gear blank (paper 000 §4, :mod:`.body_modal`, or a table
from another program) enter :func:`~reducerlab.analysis.resonance.resonance_check` and
the Campbell figures as :class:`ComponentModes`: constant frequencies, drawn as
horizontal lines and checked against every excitation line and system mode.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ReducerlabError

__all__ = ["ComponentModes", "as_components"]


@dataclass(frozen=True)
class ComponentModes:
    """Natural frequencies of one component (a gear body), computed elsewhere (FE).

    Parameters
    ----------
    label : str
        Name of the component in reports and figures, e.g. ``"gear 1"``.
    frequencies : sequence of float
        Natural frequencies (Hz), ascending (repeated roots allowed), finite, > 0; the
        k-th is mode k (1-based).
    types : sequence of str, optional
        Mode type of each frequency (paper 000's names, e.g. ``"torsional"``), same
        length as ``frequencies``; empty strings where unknown. Default: all empty.
    source : str, optional
        Where the frequencies come from (a file, "ANSYS", "paper 000 Table 4", ...).
    """

    label: str
    frequencies: tuple[float, ...]
    types: tuple[str, ...] = ()
    source: str = ""

    def __post_init__(self) -> None:
        label = self.label
        if not isinstance(label, str) or not label.strip():
            raise ReducerlabError(f"ComponentModes.label must be a non-empty string, got {label!r}")
        where = f"ComponentModes {label!r}"
        raw = self.frequencies
        if isinstance(raw, str | bytes) or not isinstance(raw, Iterable):
            raise ReducerlabError(
                f"{where}: frequencies must be a sequence of numbers (Hz), got {raw!r}"
            )
        if isinstance(raw, np.ndarray) and raw.ndim != 1:
            raise ReducerlabError(
                f"{where}: frequencies must be one-dimensional, got shape {raw.shape}"
            )
        freqs = []
        for i, f in enumerate(raw):
            if isinstance(f, bool | np.bool_) or not isinstance(f, int | float | np.number):
                raise ReducerlabError(f"{where}: frequencies[{i}] must be a number (Hz), got {f!r}")
            freqs.append(float(f))
        if not freqs:
            raise ReducerlabError(f"{where}: frequencies must hold at least one frequency")
        for i, f in enumerate(freqs):
            if not (math.isfinite(f) and f > 0):
                raise ReducerlabError(
                    f"{where}: frequencies must be finite and > 0 Hz, frequencies[{i}] = {f!r}"
                )
        for i in range(1, len(freqs)):
            if freqs[i] < freqs[i - 1]:
                raise ReducerlabError(
                    f"{where}: frequencies must be ascending (mode k is the k-th "
                    f"frequency), frequencies[{i}] = {freqs[i]!r} < frequencies[{i - 1}] = "
                    f"{freqs[i - 1]!r}"
                )
        types = self.types
        if isinstance(types, str) or not isinstance(types, Iterable):
            raise ReducerlabError(
                f"{where}: types must be a sequence of strings (one a frequency), got {types!r}"
            )
        types = tuple(types)
        if not types:
            types = ("",) * len(freqs)
        bad = [t for t in types if not isinstance(t, str)]
        if bad:
            raise ReducerlabError(f"{where}: types must be strings, got {bad[0]!r}")
        if len(types) != len(freqs):
            raise ReducerlabError(
                f"{where}: types must have the same length as frequencies "
                f"({len(freqs)}), got {len(types)}"
            )
        if not isinstance(self.source, str):
            raise ReducerlabError(f"{where}: source must be a string, got {self.source!r}")
        object.__setattr__(self, "frequencies", tuple(freqs))
        object.__setattr__(self, "types", tuple(t.strip() for t in types))

    @classmethod
    def from_body_modal(
        cls, result: Any, label: str | None = None, source: str | None = None
    ) -> ComponentModes:
        """From a :class:`~reducerlab.analysis.body_modal.BodyModalResult` (or anything
        with ``frequencies`` and ``types``); label ``"gear N"`` from its attributes."""
        attrs = getattr(getattr(result, "data", None), "attrs", {}) or {}
        if label is None:
            gear = attrs.get("gear")
            label = f"gear {gear}" if gear is not None else "body"
        if source is None:
            boundary = attrs.get("boundary")
            source = "FE body modes" + (f" ({boundary})" if boundary else "")
        return cls(label, tuple(result.frequencies), tuple(result.types), source)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "label": self.label,
            "frequencies": list(self.frequencies),
            "types": list(self.types),
            "source": self.source,
        }


def as_components(components: Any) -> tuple[ComponentModes, ...]:
    """The ``components`` argument of the resonance check: a :class:`ComponentModes` or a
    sequence of them (unique labels), checked; None gives none."""
    if isinstance(components, ComponentModes):
        return (components,)
    if components is None:
        return ()
    if isinstance(components, str | bytes | dict) or not isinstance(components, Iterable):
        raise ReducerlabError(
            f"components must be a sequence of ComponentModes, got {type(components).__name__}"
        )
    out = tuple(components)
    for c in out:
        if not isinstance(c, ComponentModes):
            raise ReducerlabError(
                f"components must be a sequence of ComponentModes, got an item of type "
                f"{type(c).__name__}"
            )
    labels = [c.label for c in out]
    dup = sorted({lab for lab in labels if labels.count(lab) > 1})
    if dup:
        raise ReducerlabError(f"components: labels must be unique, {dup[0]!r} is repeated")
    return out
