"""The mesh force law as design fields: a load exponent and its reference deflection
(issue 30), shared by the mesh tables of the gear drives (``[meshN]`` of a nutation
design, ``[mesh]`` of a KHV drive).

``exponent = p`` makes the mesh force the power law ``F = k(t) (d / p) (delta / d)^p``
beyond the backlash (``model.elements.Mesh``; ``d``: ``reference_deflection``, the
deflection at which ``k(t)`` is the tangent stiffness); ``exponent = "contact"`` (with
``stiffness = "contact"``) takes ``p`` and ``d`` from the loaded contact at the
operating torque (``analysis.contact_law``) and makes ``k(t)`` its tangent.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Annotated, Any

from pydantic import TypeAdapter, ValidationError, WrapValidator

from ..design import Stiffness
from ..design_files import field_rules

__all__ = ["LoadExponent", "check_force_law", "check_stiffness_terms", "stiffness_or"]

_STIFFNESS = TypeAdapter(Stiffness)


def stiffness_or(words: tuple[str, ...], hint: str) -> Callable[[Any, Any], float | str]:
    """The validator of a mesh table's ``stiffness``: one of ``words`` (where the law
    comes from), or a stiffness (N/m); a bad value's message ends with ``(hint)``."""

    def validate(value: Any, handler: Any) -> float | str:
        if value in words:
            return value
        try:
            return _STIFFNESS.validate_python(value)
        except ValidationError as exc:
            err = exc.errors()[0]
            msg = "must be greater than 0" if err["type"] == "greater_than" else str(err["msg"])
            msg = msg.removeprefix("Value error, ")
            raise ValueError(f"{msg} ({hint})") from None

    return validate


def _exponent_or_contact(value: Any, handler: Any) -> float | str:
    """``"contact"``, or a load exponent in ``[1, 3]``."""
    if value == "contact":
        return "contact"
    if isinstance(value, bool) or not isinstance(value, int | float) or not 1 <= value <= 3:
        raise ValueError(
            'must be a number in [1, 3] (1: linear, 1.5: Hertz\'s point contact; or "contact": '
            "the loaded contact's load exponent at the operating torque)"
        )
    return float(value)


#: A mesh table's ``exponent`` field: a number in [1, 3] or "contact"
LoadExponent = Annotated[float | str, WrapValidator(_exponent_or_contact)]


def check_force_law(exponent: float | str, reference: float, stiffness: Any) -> None:
    """Raise the design error of a mesh table whose ``exponent`` asks for the contact
    without ``stiffness = "contact"``, or is not 1 without a ``reference_deflection``."""
    if exponent == "contact" and stiffness != "contact":
        raise field_rules(("exponent", 'comes from the contact with stiffness = "contact"'))
    if exponent not in ("contact", 1.0) and not reference > 0:
        raise field_rules((
            "reference_deflection",
            "must be > 0 where exponent != 1 (the deflection at which the stiffness is "
            "the tangent)",
        ))  # fmt: skip


def check_stiffness_terms(stiffness: float, harmonics: list, phases: list) -> None:
    """Raise the design error of a mesh table whose Fourier terms (paper 000 Eq. 8) do
    not fit its mean stiffness (N/m): a phase count other than the harmonics', or
    amplitudes adding up to more than the mean (k(t) would become negative)."""
    if phases and len(phases) != len(harmonics):
        raise field_rules(("phases", f"has {len(phases)} entries, harmonics {len(harmonics)}"))
    if sum(harmonics) > stiffness:
        raise field_rules((
            "harmonics",
            f"add up to {sum(harmonics):.6g} N/m, more than the mean stiffness "
            f"{stiffness:.6g} N/m, so k(t) would become negative",
        ))  # fmt: skip
