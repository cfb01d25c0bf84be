"""Physical quantities at the boundary: parse, check dimension, convert to SI once.

A design file may give any physical quantity as a plain number, which is read as SI
(kg, m, s, N, rad, rad/s), or as a string with units that pint understands, e.g.
``"642 g"``, ``"986900 g*mm^2"``, ``"2.2e8 N/m"``, ``"25 deg"``, ``"1500 rpm"``.
Inside reducerlab everything is SI; degrees, Hz and rpm appear only in tables,
figures and design files.

Three rules go beyond pint's dimension check (:func:`parse_quantity`):

* a string is exactly a plain number (ASCII digits, ``.`` as the decimal point, an
  optional exponent: ``"1.25"``, ``"2.2e8"``) followed by a unit expression that holds
  no number of its own (``"1/min"`` and exponents such as ``"mm^2"`` aside). ``"kg"`` is
  refused, not read as 1 kg; so are a decimal comma or a thousands separator
  (``"1,25 kg"``, which pint reads as 125 kg), digit groups (``"1 000 kg"``, read as
  0 kg, ``"1_000 kg"``), fractions and digits of other scripts (``"½ kg"``);
* angles are dimensionless to pint, so the power of the angle unit (rad, deg, rev,
  turn, rpm, rps, ...) in a value with units must match the power of ``rad`` in its
  kind's SI unit (:attr:`QuantityKind.angle_power`): ``"1500 1/min"`` or ``"25 Hz"``
  for a speed, ``"1.5e5 N*m"`` for a torsional stiffness are refused (pint would
  silently read them per radian, a factor 2 pi off for revolutions), and so is any
  angle unit on a quantity without one (``"60 N*m/rad"`` for a torque, ``"1 kg*deg"``
  for a mass, ``"25 Hz*rad"`` for a frequency, ``"0.5 deg"`` for a dimensionless number);
* every value that is not zero must have a magnitude within its kind's representable
  range (:attr:`QuantityKind.lo`, :attr:`QuantityKind.hi`, in SI). The ranges hold every
  real drive with wide margin (from MEMS to ship and mill gearboxes) and keep the
  products the model builders form (``k / m``, ``J omega^2``, ``m r^2``) finite and far
  from underflow, so that an absurd but finite value (``1.7e308 N/m``, ``1e-300 m``)
  is refused at the boundary instead of failing deep in numpy or scipy.

pint is imported lazily so that ``import reducerlab`` stays fast.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import cache
from typing import Any

import numpy as np

__all__ = [
    "DISPLAY",
    "MAX_CHARS",
    "QUANTITIES",
    "RPM",
    "SHOW_CHARS",
    "TWO_PI",
    "QuantityKind",
    "display_unit",
    "length_unit",
    "parse_quantity",
    "registry",
    "shown",
]

#: One revolution (rad).
TWO_PI = 2.0 * math.pi
#: Revolutions per minute in one rad/s: ``speed_rpm = RPM * speed``.
RPM = 60.0 / TWO_PI


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
    lo, hi : float
        Representable range of a nonzero magnitude in SI: ``0`` or
        ``lo <= |value| <= hi``. Chosen per kind so that every real drive fits with
        several decades of margin on both sides and so that products of a few such
        values stay finite (see the table :data:`QUANTITIES`).
    angle_power : int
        Power of the angle unit (rad) in ``si_unit``, checked on the units of a value
        because pint treats rad as dimensionless: 1 for an angle or an angular velocity,
        -1 for a torsional stiffness or damping, 0 (the default: angle units refused)
        for every kind without ``rad`` in its SI unit.
    """

    name: str
    si_unit: str
    example: str
    lo: float
    hi: float
    angle_power: int = 0


#: Every kind of quantity a design file may give. Ranges (nonzero magnitudes, SI):
#:
#: ========================  ==============  ==============================================
#: kind                      range           why
#: ========================  ==============  ==============================================
#: mass                      1e-9 .. 1e6     a microgram MEMS part .. a 1000 t mill gear
#: moment of inertia         1e-15 .. 1e9    1 ug at 1 um .. a wind-turbine rotor x 20
#: length                    1e-9 .. 1e3     1 nm (a transmission error) .. 1 km
#: angle                     1e-9 .. 1e3     1 nrad .. 160 turns (phases are +-360 deg)
#: stiffness                 1e-6 .. 1e18    a hair spring .. 1e16, a usual stand-in for rigid
#: torsional stiffness       1e-9 .. 1e15    a watch balance spring .. a rigid stand-in
#: damping                   1e-9 .. 1e10    N s/m
#: torsional damping         1e-12 .. 1e9    N m s/rad
#: force                     1e-9 .. 1e10    1 nN .. 1 GN x 10
#: torque                    1e-9 .. 1e10    1 nN m .. 1000x the largest gearbox torque
#: power                     1e-6 .. 1e10    W: 1 uW .. 10 GW (a power station's shaft)
#: angular velocity          1e-9 .. 1e7     1e7 rad/s (95 million rpm) keeps squares finite
#: frequency                 1e-9 .. 1e9     Hz
#: time                      1e-12 .. 1e9    1 ps .. 30 years
#: dimensionless             1e-12 .. 1e12
#: pressure                  1e-3 .. 1e13    Pa: moduli up to 10 TPa (diamond is 1.2 TPa)
#: density                   1e-3 .. 1e6     kg/m^3: gases .. 50x osmium
#: ========================  ==============  ==============================================
#:
#: With these bounds ``k / m <= 1e27 s^-2``, ``J omega^2 <= 1e23 N m`` and
#: ``m r^2 >= 1e-27 kg m^2``: far from overflow and from the subnormal range.
QUANTITIES: dict[str, QuantityKind] = {
    k.name: k
    for k in (
        QuantityKind("mass", "kg", "642 g", 1e-9, 1e6),
        QuantityKind("moment of inertia", "kg*m**2", "986900 g*mm^2", 1e-15, 1e9),
        QuantityKind("length", "m", "39.5 mm", 1e-9, 1e3),
        QuantityKind("angle", "rad", "25 deg", 1e-9, 1e3, angle_power=1),
        QuantityKind("stiffness", "N/m", "2.2e8 N/m", 1e-6, 1e18),
        QuantityKind("torsional stiffness", "N*m/rad", "1.5e5 N*m/rad", 1e-9, 1e15, -1),
        QuantityKind("damping", "N*s/m", "787 N*s/m", 1e-9, 1e10),
        QuantityKind("torsional damping", "N*m*s/rad", "2 N*m*s/rad", 1e-12, 1e9, -1),
        QuantityKind("force", "N", "100 N", 1e-9, 1e10),
        QuantityKind("torque", "N*m", "50 N*m", 1e-9, 1e10),
        QuantityKind("power", "W", "3 kW", 1e-6, 1e10),
        QuantityKind("angular velocity", "rad/s", "1500 rpm", 1e-9, 1e7, angle_power=1),
        QuantityKind("frequency", "Hz", "7880 Hz", 1e-9, 1e9),
        QuantityKind("time", "s", "2 ms", 1e-12, 1e9),
        QuantityKind("dimensionless", "", "0.5", 1e-12, 1e12),
        QuantityKind("pressure", "Pa", "206 GPa", 1e-3, 1e13),
        QuantityKind("density", "kg/m**3", "7850 kg/m^3", 1e-3, 1e6),
    )
}

#: The plain number at the start of a quantity string: ASCII digits, '.' as the decimal
#: point, an optional exponent (or inf/nan, refused later as not finite).
_NUMBER = re.compile(
    r"[+-]?(?:(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|inf|nan)", re.IGNORECASE
)
#: A unit expression may start with '1/' ("1/min"); any other leading number is refused.
_RECIPROCAL = re.compile(r"1\s*/")

#: Longest quantity string read (a number and a unit expression are far shorter; pint's
#: parser takes time quadratic in the length).
MAX_CHARS = 200

#: Longest text of a value shown in an error message (longer ones are cut, with '...').
SHOW_CHARS = 60


def shown(value: Any, limit: int = SHOW_CHARS) -> str:
    """``repr(value)`` cut to about ``limit`` characters (with an ellipsis), for messages.

    Parameters
    ----------
    value : object
        The value to show (a design value, the text of a quantity).
    limit : int
        Longest repr shown in full.

    Returns
    -------
    str
    """
    text = repr(value)
    return text if len(text) <= limit else f"{text[: limit - 4]}...{text[-1]}"


#: Units in which tables and figures show a quantity kind (SI inside): name, factor
#: from SI. Lengths below 1 mm are shown in um (backlash, transmission error).
DISPLAY: dict[str, tuple[str, float]] = {
    "angular velocity": ("rpm", RPM),
    "angle": ("deg", 180.0 / math.pi),
    "time": ("ms", 1e3),
}


def length_unit(scale: float) -> str:
    """The unit name of lengths stored in multiples of ``scale`` (m): ``"um"`` for 1e-6,
    ``"m"`` for 1, ``"2.5e-06 m"`` for a scale with no unit name."""
    names = {1.0: "m", 1e-3: "mm", 1e-6: "um", 1e-9: "nm"}
    for value, name in names.items():
        if math.isclose(scale, value, rel_tol=1e-12):
            return name
    return f"{scale:g} m"


def display_unit(kind: str | None, values: Any = None) -> tuple[str, float]:
    """``(unit, factor)`` to show values of quantity ``kind`` (SI times ``factor``):
    rpm for speeds, deg for angles, um or mm for lengths (by the largest of ``values``),
    else the SI unit; ``("", 1.0)`` for a plain number."""
    if kind is None or kind not in QUANTITIES:
        return "", 1.0
    if kind == "length":
        big = float(np.nanmax(np.abs(values))) if values is not None and np.size(values) else 0.0
        return ("um", 1e6) if big < 1e-3 else ("mm", 1e3)
    if kind in DISPLAY:
        return DISPLAY[kind]
    return QUANTITIES[kind].si_unit.replace("**", "^"), 1.0


@cache
def registry() -> Any:
    """Return the shared pint ``UnitRegistry`` (created on first use)."""
    import pint

    ureg = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
    ureg.define("rev = revolution")
    return ureg


def _article(name: str) -> str:
    return "an" if name[0] in "aeiou" else "a"


def _angle_power(q: Any) -> float:
    """Power of radian in the root units of ``q`` (deg, rev, rpm, turn all reduce to it)."""
    _, root = registry().get_root_units(q.units)
    return float(dict(root._units).get("radian", 0))


def _angle_rule(text: str, spec: QuantityKind, found: float) -> str:
    """The message for a value whose angle unit is missing, extra or in the wrong power.

    ``found`` is the power of the angle unit in the value, ``spec.angle_power`` the one
    expected.
    """
    a = _article(spec.name)
    if spec.name == "frequency":
        return (
            f"{shown(text)}: a frequency is in Hz (cycles per second); angle-based units are "
            "ambiguous here"
        )
    if spec.name == "angular velocity" and found == 0:
        what = "Hz is" if "hz" in text.lower() else "a unit of 1/time without an angle unit is"
        return (
            f"{shown(text)}: {what} ambiguous for an angular velocity (radians or revolutions "
            "per unit time?); write 'rpm', 'rev/s' or 'rad/s'"
        )
    if spec.angle_power == 0:
        unit = f"in {spec.si_unit}" if spec.si_unit else "a plain number"
        return (
            f"{shown(text)} has an angle unit (to the power {found:g}), but {a} {spec.name} "
            f"has none (it is {unit}); write e.g. {spec.example!r}"
        )
    if found == 0:
        return (
            f"{shown(text)} needs an angle unit: {a} {spec.name} is in {spec.si_unit} (a "
            f"plain number is read as SI); write e.g. {spec.example!r}"
        )
    return (
        f"{shown(text)} has an angle unit to the power {found:g}, but {a} {spec.name} "
        f"needs it to the power {spec.angle_power} ({spec.si_unit}); write e.g. "
        f"{spec.example!r}"
    )


def _in_range(value: Any, out: float, spec: QuantityKind) -> float:
    if not math.isfinite(out):
        raise ValueError(f"expected a finite {spec.name}, got {shown(value)}")
    if out != 0 and not spec.lo <= abs(out) <= spec.hi:
        unit = f" {spec.si_unit}" if spec.si_unit else ""
        text = shown(value) if isinstance(value, str) else f"{out!r}{unit}"
        conv = f" = {out!r}{unit}" if isinstance(value, str) else ""
        raise ValueError(
            f"{text}{conv} is outside the range of {_article(spec.name)} {spec.name}: "
            f"0 or a magnitude within [{spec.lo:g}, {spec.hi:g}]{unit}"
        )
    return out


def _split_number(text: str, spec: QuantityKind) -> tuple[float, str]:
    """Split ``text`` into its plain number and its unit expression (without a number).

    Raises
    ------
    ValueError
        When the text does not start with a plain number, uses a decimal comma or a
        thousands separator, or has digits after the number that are not part of the
        unit expression (digit groups, a second exponent, fractions).
    """
    a = _article(spec.name)
    example = f"write e.g. {spec.example!r}"
    if "," in text:
        raise ValueError(
            f"{shown(text)}: write 1.25, not 1,25 (no decimal commas or thousands "
            f"separators); {example}"
        )
    m = _NUMBER.match(text)
    if m is None:
        raise ValueError(
            f"{shown(text)}: a number is missing: expected {a} {spec.name} as a plain "
            f"number (digits 0-9, '.' as the decimal point) followed by its unit; {example}"
        )
    number, rest = m.group(), text[m.end() :]
    unit = rest.strip()
    after = rest[:1]
    if (
        after in ("_", ".")
        or after.isnumeric()
        or (unit[:1].isnumeric() and not _RECIPROCAL.match(unit))
    ):
        raise ValueError(
            f"{shown(text)}: not a plain number followed by a unit (digit groups such as "
            f"'1 000' or '1_000', fractions and other digits are not read); {example}"
        )
    # "25 /s" is read as 25 per second, as pint reads the whole text
    return float(number), f"1{unit}" if unit.startswith("/") else unit


def parse_quantity(value: Any, kind: str) -> float:
    """Convert a number or a string with units to a float in SI.

    Parameters
    ----------
    value : float, int or str
        A plain number (taken as SI) or a string such as ``"642 g"``: exactly a plain
        number (``[+-]digits[.digits][e[+-]digits]``) and a unit expression.
    kind : str
        A key of :data:`QUANTITIES` ("mass", "stiffness", ...).

    Returns
    -------
    float
        The magnitude in the SI unit of ``kind``: 0 or within the kind's range.

    Raises
    ------
    ValueError
        With a message naming the expected kind and an example, if the value cannot be
        parsed, is not a plain number followed by a unit, is not finite, has the wrong
        dimension, has an angle unit in another power than its kind's SI unit, or lies
        outside the kind's representable range. Values are shown cut to
        :data:`SHOW_CHARS` characters.
    """
    spec = QUANTITIES[kind]
    a = _article(spec.name)
    if isinstance(value, bool):
        raise ValueError(f"expected {a} {spec.name}, e.g. {spec.example!r}, not a boolean")
    if isinstance(value, int | float):
        try:
            out = float(value)
        except OverflowError:
            raise ValueError(f"expected a finite {spec.name}, got {shown(value)}") from None
        return _in_range(value, out, spec)
    if not isinstance(value, str):
        raise ValueError(
            f"expected {a} {spec.name} as a number (SI) or a string with units, "
            f"e.g. {spec.example!r}; got {type(value).__name__}"
        )
    import pint

    ureg = registry()
    text = value.strip()
    if not text:
        raise ValueError(f"expected {a} {spec.name}, e.g. {spec.example!r}, got an empty string")
    if len(text) > MAX_CHARS:  # pint's parser takes time quadratic in the length
        raise ValueError(
            f"{shown(text)}: {len(text)} characters is too long for {a} {spec.name} (at most "
            f"{MAX_CHARS}); write e.g. {spec.example!r}"
        )
    number, unit = _split_number(text, spec)
    if spec.name == "angular velocity" and "hz" in unit.lower():  # before pint, for 'hz'
        raise ValueError(_angle_rule(text, spec, 0))
    try:
        u = ureg.Quantity(unit) if unit else ureg.Quantity(1, "")
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError) as exc:
        raise ValueError(
            f"cannot read {shown(text)} as {a} {spec.name} ({exc}); write e.g. {spec.example!r}"
        ) from None
    except Exception as exc:  # tokenizer errors of pint are plain Python errors
        raise ValueError(
            f"cannot read {shown(text)} as {a} {spec.name} ({type(exc).__name__}); "
            f"write e.g. {spec.example!r}"
        ) from None
    if not isinstance(u, ureg.Quantity) or u.magnitude != 1:
        # a number inside the unit expression: "kg 2", "kg/2", "1.5.3 kg"
        raise ValueError(
            f"{shown(text)}: not a plain number followed by a unit: the unit part "
            f"{shown(unit)} holds a number of its own; write e.g. {spec.example!r}"
        )
    try:
        q = number * u
        out = float(q.to(spec.si_unit).magnitude)
    except pint.errors.DimensionalityError:
        got = str(u.dimensionality) if str(u.dimensionality) else "dimensionless"
        want = ureg.Quantity(1, spec.si_unit).dimensionality
        want_s = str(want) if str(want) else "dimensionless"
        raise ValueError(
            f"wrong dimension: expected {a} {spec.name} [{want_s}], e.g. {spec.example!r}, "
            f"but {shown(text)} is [{got}]"
        ) from None
    except (TypeError, ValueError, OverflowError, ArithmeticError):
        raise ValueError(
            f"cannot read {shown(text)} as {a} {spec.name}; write e.g. {spec.example!r}"
        ) from None
    if not u.unitless:
        found = _angle_power(u)
        if found != spec.angle_power:
            raise ValueError(_angle_rule(text, spec, found))
    return _in_range(value, out, spec)
