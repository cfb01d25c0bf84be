"""Physical quantities at the boundary: parse, check dimension, convert to SI once.

A design file may give any physical quantity as a plain number, which is read as SI
(kg, m, s, N, rad, rad/s), or as a string with units that pint understands, e.g.
``"642 g"``, ``"986900 g*mm^2"``, ``"2.2e8 N/m"``, ``"25 deg"``, ``"1500 rpm"``.
Inside reducerlab everything is SI; degrees, Hz and rpm appear only in tables,
figures and design files.

pint is imported lazily so that ``import reducerlab`` stays fast.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import cache
from typing import Any

__all__ = ["QUANTITIES", "QuantityKind", "parse_quantity", "registry"]


@dataclass(frozen=True)
class QuantityKind:
    """A kind of physical quantity accepted in design files.

    Attributes
    ----------
    name : str
        Human name used in error messages ("stiffness").
    si_unit : str
        pint expression of the SI unit values are converted to.
    example : str
        An example string shown in error messages.
    """

    name: str
    si_unit: str
    example: str


QUANTITIES: dict[str, QuantityKind] = {
    k.name: k
    for k in (
        QuantityKind("mass", "kg", "642 g"),
        QuantityKind("moment of inertia", "kg*m**2", "986900 g*mm^2"),
        QuantityKind("length", "m", "39.5 mm"),
        QuantityKind("angle", "rad", "25 deg"),
        QuantityKind("stiffness", "N/m", "2.2e8 N/m"),
        QuantityKind("torsional stiffness", "N*m/rad", "1.5e5 N*m/rad"),
        QuantityKind("damping", "N*s/m", "787 N*s/m"),
        QuantityKind("torsional damping", "N*m*s/rad", "2 N*m*s/rad"),
        QuantityKind("force", "N", "100 N"),
        QuantityKind("torque", "N*m", "50 N*m"),
        QuantityKind("angular velocity", "rad/s", "1500 rpm"),
        QuantityKind("frequency", "Hz", "7880 Hz"),
        QuantityKind("time", "s", "2 ms"),
        QuantityKind("dimensionless", "", "0.5"),
    )
}


@cache
def registry() -> Any:
    """Return the shared pint ``UnitRegistry`` (created on first use)."""
    import pint

    ureg = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
    ureg.define("rev = revolution")
    return ureg


def _is_ambiguous_speed(text: str) -> bool:
    # Hz is cycles per second to an engineer but 1/s to pint, which would silently
    # drop a factor 2*pi when converted to rad/s.
    return "hz" in text.lower()


def parse_quantity(value: Any, kind: str) -> float:
    """Convert a number or a string with units to a float in SI.

    Parameters
    ----------
    value : float, int or str
        A plain number (taken as SI) or a string such as ``"642 g"``.
    kind : str
        A key of :data:`QUANTITIES` ("mass", "stiffness", ...).

    Returns
    -------
    float
        The magnitude in the SI unit of ``kind``.

    Raises
    ------
    ValueError
        With a message naming the expected dimension and an example, if the value
        cannot be parsed, is not finite, or has the wrong dimension.
    """
    spec = QUANTITIES[kind]
    a = "an" if spec.name[0] in "aeiou" else "a"
    if isinstance(value, bool):
        raise ValueError(f"expected {a} {spec.name}, e.g. {spec.example!r}, not a boolean")
    if isinstance(value, int | float):
        try:
            out = float(value)
        except OverflowError:
            raise ValueError(f"expected a finite {spec.name}, got {value!r}") from None
    elif isinstance(value, str):
        import pint

        ureg = registry()
        text = value.strip()
        if not text:
            raise ValueError(
                f"expected {a} {spec.name}, e.g. {spec.example!r}, got an empty string"
            )
        if kind == "angular velocity" and _is_ambiguous_speed(text):
            raise ValueError(
                "Hz is ambiguous for an angular velocity; write 'rpm', 'rev/s' or 'rad/s'"
            )
        if kind == "frequency" and re.search(r"rad|rev|rpm|rps|cycle|turn", text.lower()):
            raise ValueError(
                f"{text!r}: a frequency is in Hz (cycles per second); angle-based units are "
                "ambiguous here"
            )
        try:
            q = ureg.Quantity(text)
        except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError) as exc:
            raise ValueError(
                f"cannot read {text!r} as {a} {spec.name} ({exc}); write e.g. {spec.example!r}"
            ) from None
        except Exception as exc:  # tokenizer errors of pint are plain Python errors
            raise ValueError(
                f"cannot read {text!r} as {a} {spec.name} ({type(exc).__name__}); "
                f"write e.g. {spec.example!r}"
            ) from None
        if not isinstance(q, ureg.Quantity):  # a bare number inside a string
            q = ureg.Quantity(float(q), "")
        try:
            out = float(q.to(spec.si_unit).magnitude)
        except pint.errors.DimensionalityError:
            got = str(q.dimensionality) if str(q.dimensionality) else "dimensionless"
            want = ureg.Quantity(1, spec.si_unit).dimensionality
            want_s = str(want) if str(want) else "dimensionless"
            raise ValueError(
                f"wrong dimension: expected {a} {spec.name} [{want_s}], e.g. {spec.example!r}, "
                f"but {text!r} is [{got}]"
            ) from None
    else:
        raise ValueError(
            f"expected {a} {spec.name} as a number (SI) or a string with units, "
            f"e.g. {spec.example!r}; got {type(value).__name__}"
        )
    if not math.isfinite(out):
        raise ValueError(f"expected a finite {spec.name}, got {value!r}")
    return out
