"""The load capacity's reasons in the verdict (issue 29): a gear whose ISO pitting or
tooth-root safety factor falls below its minimum is a risk.

The rating is :func:`reducerlab.analysis.rating.load_capacity` at the design's own load
(ISO 6336-2/-3:2019 method B for spur and internal pairs; the bevel pairs on their
ISO 10300-1 virtual cylindrical gears), with its documented conditions
(:class:`~reducerlab.rating.material.RatingConditions`: ``S_Hmin``, ``S_Fmin``). The
verdict makes only the method B rating itself (milliseconds); a rating handed to it with
method A (the loaded contact analysis: minutes, ``reducerlab rating --method A``) is
judged by its judged safety factors: method A's for a pair method B does not cover (the
double-arc pairs), the smaller of A and B where both were computed (``method="both"``).
"""

from __future__ import annotations

from typing import Any

from ..errors import ReducerlabError
from ..numformat import fmt
from .reasons import reason

__all__ = ["capacity_reasons", "rateable"]

#: the design types the rating covers
RATED = ("gear_pair", "khv", "nutation")

_WHAT = {"S_H": ("pitting", "S_Hmin"), "S_F": ("tooth root", "S_Fmin")}


def rateable(design: Any) -> bool:
    """Whether ``design`` has gear pairs the rating covers (a nutation design only with
    its tooth surfaces: a kinematics-only one has no teeth)."""
    kind = getattr(design, "type", "")
    return kind in RATED and (kind != "nutation" or design.has_tooth_surfaces)


def capacity_reasons(design: Any, rating: Any = None) -> list[dict[str, Any]]:
    """Reasons ``capacity`` (one per gear and safety factor) of ``design``'s rating.

    Parameters
    ----------
    design : Design
    rating : RatingResult, optional
        A rating already made; default ``load_capacity(design)``.

    Returns
    -------
    list of dict
        ``risk`` where ``S < S_min``, ``ok`` otherwise (value ``S``, threshold
        ``S_min``, with ``pair`` and ``gear``); one ``note`` when the design cannot be
        rated (no load, no tooth geometry, double-arc teeth: the error's text); nothing
        for drives without gear pairs to rate.
    """
    import json

    if not rateable(design):
        return []
    if rating is None:
        from .rating import load_capacity

        try:
            rating = load_capacity(design, method="B")
        except ReducerlabError as e:
            return [reason("capacity", "note", f"load capacity not rated: {e}", None, None)]
    cond = json.loads(rating.data.attrs.get("conditions", "{}"))
    out = []
    for name, p in rating.pairs().items():
        for key, (what, floor_key) in _WHAT.items():
            floor = float(cond.get(floor_key, 1.0))
            for gear, s in zip(p["gears"], p[key], strict=True):
                status = "risk" if s < floor else "ok"
                rel = "<" if s < floor else ">="
                out.append(reason(
                    "capacity", status,
                    f"{what} safety {key} = {fmt(s, 'safety')} {rel} {floor_key} = {floor:g} "
                    f"({name}, {gear}; method {p.get('judged_by', 'B')}: {p['standard']})",
                    s, floor, pair=name, gear=str(gear), factor=key,
                ))  # fmt: skip
    return out
