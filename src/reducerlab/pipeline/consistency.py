"""Consistency of the models a run combines (issue 27): the lumped bodies against the
finite-element gear bodies, the design's mesh stiffness against the loaded contact's.

Each check is a verdict reason (:mod:`reducerlab.analysis.verdict`'s format: ``rule``,
``status``, ``text``, ``value``, ``threshold``). A lumped gear whose mass or moment of
inertia differs from its FE body's by more than the tolerance is a ``risk``: the
natural frequencies the verdict judged belong to another body than the one whose
modes it compared them with. The mesh stiffness is a ``note``: the run puts the
contact's k(t) into the model, so the design's value is replaced, and the note says by
how much.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..numformat import fmt

__all__ = ["TOLERANCE", "body_consistency", "stiffness_consistency"]

#: Default relative tolerance between a lumped gear's mass or moment of inertia and its
#: FE body's (``[check] consistency``, :class:`reducerlab.design.Thresholds`): 10 %, the
#: spread of a natural frequency by about 5 % (f ~ 1/sqrt(m)), half the 10 % margin the
#: resonance check keeps.
TOLERANCE = 0.10


def _reason(
    rule: str, status: str, text: str, value: float, threshold: float | None
) -> dict[str, Any]:
    return {"rule": rule, "status": status, "text": text, "value": value, "threshold": threshold}


def body_consistency(
    design: Any, bodies: Mapping[int, Any], tolerance: float = TOLERANCE
) -> list[dict[str, Any]]:
    """Mass and moments of inertia of each lumped gear against its FE body.

    Parameters
    ----------
    design : NutationDesign
        Gears ``gear1..gear4`` with ``mass`` (kg) and ``J_x, J_y, J_z`` (kg m^2).
    bodies : mapping
        Gear number -> its :class:`~reducerlab.analysis.body_modal.BodyModalResult`
        (attributes ``mass_kg``, ``J_x_kg_m2``, ``J_z_kg_m2``).
    tolerance : float
        Largest relative difference that is consistent.

    Returns
    -------
    list of dict
        One reason per gear: ``risk`` naming the quantities beyond the tolerance, else
        ``ok`` with the largest difference.
    """
    out = []
    for g, res in sorted(bodies.items()):
        gear = getattr(design, f"gear{g}")
        a = res.data.attrs
        rows = [
            ("mass", gear.mass, a.get("mass_kg"), 1e3, "g"),
            ("J_z", gear.J_z, a.get("J_z_kg_m2"), 1e9, "g mm^2"),
            ("J_x", gear.J_x, a.get("J_x_kg_m2"), 1e9, "g mm^2"),
        ]
        diffs = [
            (q, lum, float(fe), s, u, lum / float(fe) - 1.0)
            for q, lum, fe, s, u in rows
            if fe is not None and float(fe) > 0
        ]
        if not diffs:
            continue
        worst = max(diffs, key=lambda r: abs(r[5]))
        bad = [r for r in diffs if abs(r[5]) > tolerance]
        shown = bad or [worst]
        text = f"gear {g}: lumped " + ", ".join(
            f"{q} {fmt(lum * s)} {u} against the FE body's {fmt(fe * s)} {u} "
            f"({fmt(100 * d, 'percent')} %)"
            for q, lum, fe, s, u, d in shown
        )
        if bad:
            text += (
                f": beyond {100 * tolerance:g} %, the lumped model is not this body; "
                f"make gear{g}'s mass and moments the body's, or its blank the gear's"
            )
        out.append(
            _reason("body-consistency", "risk" if bad else "ok", text, abs(worst[5]), tolerance)
        )
    return out


def _design_stiffness(design: Any, pair: int) -> tuple[float | None, str]:
    """The mean mesh stiffness the design gives pair ``pair`` (N/m) and what it is: a
    nutation design's ``[meshN] stiffness`` when a number; a KHV design's ISO law
    (paper 004 Eq. 7-9, its mean) whatever ``[mesh] stiffness`` says."""
    if getattr(design, "type", None) == "khv":
        return design.stiffness_law().mean, "the ISO 6336 law (paper 004 Eq. 9)"
    spec = getattr(design, f"mesh{pair}")
    return (spec.stiffness if isinstance(spec.stiffness, float) else None), "the design"


def stiffness_consistency(design: Any, contacts: Mapping[int, Any]) -> list[dict[str, Any]]:
    """The design's mean mesh stiffness against the loaded contact's ``k_m`` (a
    ``note`` per pair: the run uses the contact's)."""
    out = []
    for pair, res in sorted(contacts.items()):
        k_c = res.mean_stiffness
        k_d, what = _design_stiffness(design, pair)
        T = float(res.data.attrs["torque_external"])
        if k_d:
            d = k_c / k_d - 1.0
            text = (
                f"mesh {pair}: loaded contact at {fmt(T, 'torque')} N m gives k_m = "
                f"{fmt(k_c, 'stiffness')} N/m, {what} {fmt(k_d, 'stiffness')} N/m "
                f"({fmt(100 * d, 'percent')} %); the run uses the contact's k(t)"
            )
            value = abs(d)
        else:
            text = (f"mesh {pair}: k(t) from the loaded contact at {fmt(T, 'torque')} N m, "
                    f"k_m = {fmt(k_c, 'stiffness')} N/m")  # fmt: skip
            value = 0.0
        out.append(_reason("mesh-stiffness", "note", text, value, None))
    return out
