"""The design inputs a result depends on: recorded in the result, checked against a
design before the result is used (issue 26).

A result that one command saves and another reads back (``check --body-modes``,
``report --with``, and any later command that takes saved results) must belong to the
design it is used with. Every result therefore carries the record of its inputs:

- ``inputs``: a JSON object ``{field path: SI value}`` of the design fields the result
  depends on (``gear2.teeth``, ``surface.face_width``, ``material.density``...), and
- ``inputs_digest``: a SHA-256 of that object (a record edited by hand is noticed).

:meth:`reducerlab.results.Result.save` writes the record from the design the result
recorded (its SI JSON, stamped since the first release); :func:`check_inputs` compares a
result's record with the values the current design gives at the same paths and refuses
the result, naming the first fields that differ, when any does.

Which fields a result depends on is its kind's rule: by default every field of the
design except its title, description, ``[report]`` and ``[check]`` tables (a result
computed from a model depends on all of it); a kind may narrow it with a rule named in
:data:`RULES`
(``body-modal``: the fields that generate that one gear's body, so that a changed
operating speed does not refuse a gear's modes; ``contact``: the fields that generate the
pair's teeth). Computation settings that are not part
of the design (mesh sizes, boundary, mode count) stay in the result's own attributes:
they are the user's choice, not the design's.
"""

from __future__ import annotations

import importlib
import json
from collections.abc import Callable, Mapping
from typing import Any

from .errors import ReducerlabError
from .io import digest

__all__ = [
    "IGNORED",
    "RULES",
    "check_inputs",
    "differences",
    "input_record",
    "inputs_of",
    "recorded_inputs",
]

#: Design fields no analysis reads: never part of a result's inputs.
IGNORED = ("name", "description", "report", "check")

#: Result kind -> ``"module:function"`` giving the design paths a result of that kind
#: depends on, as ``function(design, attrs) -> list of paths`` (None: the whole design).
#: A path names a field or a table (all fields below it). Imported when first needed,
#: like the result classes of :mod:`reducerlab.results`.
RULES: dict[str, str] = {
    "body-modal": "reducerlab.analysis.gear_bodies:body_inputs",
    "contact": "reducerlab.analysis.gear_bodies:contact_inputs",
    # a torque sweep and a modification layout read the pair's teeth as its contact does
    # (their loads, grids and candidates are their own attributes)
    "te-sweep": "reducerlab.analysis.gear_bodies:contact_inputs",
    "khv-sharing": "reducerlab.analysis.gear_bodies:contact_inputs",
    "layout": "reducerlab.analysis.gear_bodies:contact_inputs",
}

Rule = Callable[[Mapping[str, Any], Mapping[str, Any]], "list[str] | None"]

#: How many differing fields an error names.
SHOWN = 4


def _rule(kind: str) -> Rule | None:
    target = RULES.get(kind)
    if target is None:
        return None
    module, _, name = target.partition(":")
    return getattr(importlib.import_module(module), name)


def _flatten(tree: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    """``{dotted path: value}`` of the leaves (lists are leaves); None values left out
    (a field not set)."""
    out: dict[str, Any] = {}
    for key, value in tree.items():
        path = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out.update(_flatten(value, path + "."))
        elif value is not None:
            out[path] = value
    return out


def inputs_of(kind: str, design: Mapping[str, Any], attrs: Mapping[str, Any]) -> dict[str, Any]:
    """The inputs a result of ``kind`` with attributes ``attrs`` (``gear``...) takes from
    ``design`` (its SI dump, as recorded in results): ``{path: value}``, sorted."""
    flat = _flatten({k: v for k, v in design.items() if k not in IGNORED})
    rule = _rule(kind)
    paths = None if rule is None else rule(design, attrs)
    if paths is not None:
        flat = {
            k: v for k, v in flat.items() if any(k == p or k.startswith(p + ".") for p in paths)
        }
    return dict(sorted(flat.items()))


def input_record(kind: str, attrs: Mapping[str, Any]) -> dict[str, str]:
    """The attributes ``inputs`` and ``inputs_digest`` of a result of ``kind`` whose
    attributes (``attrs``) hold the design it was computed from; ``{}`` when they hold
    none (a result of a model built in code)."""
    text = attrs.get("design")
    if not isinstance(text, str) or not text:
        return {}
    record = json.dumps(inputs_of(kind, json.loads(text), attrs), sort_keys=True)
    return {"inputs": record, "inputs_digest": digest(record)}


def recorded_inputs(kind: str, attrs: Mapping[str, Any], name: str) -> dict[str, Any]:
    """The inputs a result recorded: its ``inputs`` record, or for a result that has
    none (one in memory, or a file written before the record existed) the inputs of the
    design it recorded.

    Raises
    ------
    ReducerlabError
        Naming ``name`` when the result records no design at all, or when its record
        does not match its digest (edited).
    """
    text = attrs.get("inputs")
    if isinstance(text, str) and text:
        if digest(text) != attrs.get("inputs_digest"):
            raise ReducerlabError(
                f"{name}: its record of the design inputs does not match its digest "
                "(edited or damaged); recompute the result"
            )
        return dict(json.loads(text))
    record = input_record(kind, attrs)
    if not record:
        raise ReducerlabError(
            f"{name}: the {kind} result carries no record of the design it was computed "
            "from (no 'design' or 'inputs' attribute), so it cannot be checked against "
            "this design; recompute it with this version of reducerlab"
        )
    return dict(json.loads(record["inputs"]))


_MISSING = object()


def _shown(value: Any) -> str:
    if value is _MISSING:
        return "(not set)"
    if isinstance(value, float):
        return f"{value:.12g}"  # SI values converted from units: no round-off digits
    text = json.dumps(value) if not isinstance(value, str) else repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def differences(
    recorded: Mapping[str, Any], current: Mapping[str, Any]
) -> list[tuple[str, Any, Any]]:
    """``(path, recorded value, current value)`` of every path whose values differ
    (a path set on one side only included), ``type`` first, then in path order."""
    keys = sorted(set(recorded) | set(current), key=lambda k: (k != "type", k))
    out = []
    for k in keys:
        a, b = recorded.get(k, _MISSING), current.get(k, _MISSING)
        if a is _MISSING or b is _MISSING or a != b:
            out.append((k, a, b))
    return out


def check_inputs(result: Any, design: Any, name: str | None = None) -> None:
    """Refuse ``result`` unless it was computed from ``design``'s values of the inputs
    it depends on.

    Parameters
    ----------
    result : Result
        A result (loaded from a file or computed in this session).
    design : Design
        The design it is to be used with.
    name : str, optional
        How to name the result in the message (its file); default its kind.

    Raises
    ------
    ReducerlabError
        ``NAME was computed for gear 2 of FILE (type nutation), not for this design
        (FILE2): gear2.teeth 40 ≠ 38, ...`` naming the first fields that differ (the
        result's value first), or the result carries no record of its design.
    """
    attrs = dict(result.attrs)
    kind = str(getattr(result, "kind", "result"))
    name = name or f"the {kind} result"
    if attrs.get("design_hash") and attrs.get("design_hash") == design.hash:
        return  # the same design, field for field
    recorded = recorded_inputs(kind, attrs, name)
    here = json.loads(design.provenance["design"])
    current = inputs_of(kind, here, attrs)
    mine = set(recorded) | set(current)
    flat = _flatten({k: v for k, v in here.items() if k not in IGNORED})
    current = {k: flat[k] for k in mine if k in flat}
    diff = differences(recorded, current)
    if not diff:
        return
    source = attrs.get("source") or "another design"
    what = f"gear {attrs['gear']} of {source}" if "gear" in attrs else str(source)
    typ = recorded.get("type")
    what += f" (type {typ})" if typ else ""
    shown = ", ".join(f"{k} {_shown(a)} ≠ {_shown(b)}" for k, a, b in diff[:SHOWN])
    more = f" and {len(diff) - SHOWN} more" if len(diff) > SHOWN else ""
    raise ReducerlabError(
        f"{name} was computed for {what}, not for this design ({design.source}): "
        f"{shown}{more} (the result's value ≠ this design's); recompute it for this design"
    )
