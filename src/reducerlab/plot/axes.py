"""Readable axes for the matplotlib figures: tick labels as plain numbers (no offset such
as ``1e-12+4.286e-1`` and no ``1e8`` multiplier above the axis), few ticks, and the unit
of display chosen from the data's size (um or nm instead of m, mrad instead of rad,
MN/m instead of N/m), so that the plain numbers stay short.

matplotlib is imported only inside the functions (figures are built on demand)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = [
    "FLAT_SPAN",
    "ROUND_OFF_SPAN",
    "fit_limits",
    "parameter_axis",
    "parameter_label",
    "plain_axes",
    "plain_axis",
    "plain_figure",
    "pretty_unit",
    "scaled_unit",
]

#: SI prefixes by power of ten.
PREFIXES = {-15: "f", -12: "p", -9: "n", -6: "µ", -3: "m", 0: "", 3: "k", 6: "M", 9: "G", 12: "T"}

#: Units that take no prefix (their numbers are shown as they are).
_UNPREFIXED = ("rpm", "deg", "%", "dB", "°")


def pretty_unit(unit: str) -> str:
    """A unit as a figure writes it: ``"kg*m^2"`` -> ``"kg·m²"``, ``"um"`` -> ``"µm"``,
    ``"N*m/rad"`` -> ``"N·m/rad"``."""
    text = unit.replace("**", "^").replace("*", "·")
    for plain, sup in (("^2", "²"), ("^3", "³"), ("^-1", "⁻¹")):
        text = text.replace(plain, sup)
    if text.startswith("um"):
        text = "µ" + text[1:]
    return text


def scaled_unit(values: Any, unit: str) -> tuple[float, str]:
    """The factor and unit to show ``values`` (in ``unit``, SI) with: the SI prefix
    (a power of 1000) that brings the largest magnitude into [1, 1000).

    Parameters
    ----------
    values : array_like
        The values in ``unit`` (non-finite ones are ignored).
    unit : str
        The SI unit (``"m"``, ``"m/s"``, ``"N/m"``, ``"rad"``, ``"kg*m^2"``, ...).

    Returns
    -------
    factor : float
        Multiply the values by it to show them.
    unit : str
        The unit they are shown in (``"µm"``, ``"mm/s"``, ``"MN/m"``, ``"mrad"``; a unit
        with no prefix form such as ``kg·m²`` is scaled as ``"10⁻³ kg·m²"``).
    """
    v = np.asarray(values, dtype=float)
    v = np.abs(v[np.isfinite(v)])
    big = float(v.max()) if v.size else 0.0
    if not unit or unit in _UNPREFIXED or big == 0.0:
        return 1.0, pretty_unit(unit)
    power = 3 * math.floor(math.log10(big) / 3)
    power = min(max(power, min(PREFIXES)), max(PREFIXES))
    if unit.startswith("kg"):  # the base unit carries a prefix already: k for 1e3 g
        if unit == "kg":
            power = min(max(power, -6), 0)  # mg, g, kg
            name = {-6: "mg", -3: "g", 0: "kg"}[power]
            return 10.0 ** (-power), name
        if power == 0:
            return 1.0, pretty_unit(unit)
        exponent = str(power).translate(str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹"))
        return 10.0 ** (-power), f"10{exponent} {pretty_unit(unit)}"
    return 10.0 ** (-power), PREFIXES[power] + pretty_unit(unit)


def plain_axis(axis: Any, nbins: int = 5) -> None:
    """Plain tick labels on one axis (an ``ax.xaxis`` or ``ax.yaxis``): no offset, no
    scientific multiplier, at most ``nbins`` + 1 ticks at 1-2-2.5-5 steps. A log axis
    keeps its own locator and formatter."""
    from matplotlib.ticker import MaxNLocator, ScalarFormatter

    if axis.get_scale() != "linear":
        return
    fmt = ScalarFormatter(useOffset=False)
    fmt.set_scientific(False)
    axis.set_major_formatter(fmt)
    axis.set_major_locator(MaxNLocator(nbins=nbins, steps=[1, 2, 2.5, 5, 10]))


def plain_axes(ax: Axes, xbins: int = 5, ybins: int = 5) -> None:
    """:func:`plain_axis` on both axes of ``ax``."""
    plain_axis(ax.xaxis, xbins)
    plain_axis(ax.yaxis, ybins)


#: A view whose span is below this share of its values' size shows round-off (a
#: constant that varies in its last digits): :func:`plain_figure` widens it.
ROUND_OFF_SPAN = 1e-6

#: The span such a view is widened to, as a share of its values' size (a constant drawn
#: as a flat line, ticks of four digits).
FLAT_SPAN = 1e-2


def fit_limits(values: Any, margin: float = 0.08, floor: float = 0.0) -> tuple[float, float]:
    """Limits that show ``values`` with ``margin`` of their range on each side; a range
    below ``floor`` (a span the figure must show at least, e.g. the orbit's size against
    the round-off spread of coinciding points) is widened to ``floor`` about the centre,
    and one below :data:`ROUND_OFF_SPAN` of the values' size (a constant up to
    round-off) to :data:`FLAT_SPAN` of it.

    Parameters
    ----------
    values : array_like
        The values to show (non-finite ones are ignored).
    margin : float
        Share of the range added on each side.
    floor : float
        The smallest span shown (same unit as the values).

    Returns
    -------
    tuple of float
        ``(low, high)``.
    """
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if not v.size:
        return 0.0, 1.0
    lo, hi = float(v.min()), float(v.max())
    size = max(abs(lo), abs(hi))
    span = max(hi - lo, floor)
    if span < ROUND_OFF_SPAN * size:  # a constant up to round-off: drawn flat
        span = FLAT_SPAN * size
    if span <= 0.0:  # all zero and no floor
        span = 1.0
    mid = 0.5 * (lo + hi)
    half = 0.5 * span * (1.0 + 2.0 * margin)
    return mid - half, mid + half


#: Readable names of the design and model fields figures sweep, by the path's last part.
PARAMETER_WORDS = {
    "x1": "profile shift coefficient x1",
    "x2": "profile shift coefficient x2",
    "shift": "profile shift coefficient",
    "input_speed": "input speed",
    "speed": "speed",
    "half_backlash": "half backlash",
    "output_torque": "output torque",
    "output_power": "output power",
    "torque": "torque",
    "power": "power",
    "face_width": "face width",
    "pressure_angle": "pressure angle",
    "k": "stiffness",
    "c": "damping",
}

#: Parents of a path that add nothing to its name (the design's groups).
_GROUPS = ("gears", "operating", "design", "report")


def parameter_label(path: str) -> str:
    """A parameter's name as an axis shows it, from its path: ``"gears.x1"`` ->
    ``"profile shift coefficient x1"``, ``"input_speed"`` -> ``"input speed"``,
    ``"mesh.half_backlash"`` -> ``"mesh half backlash"`` (the readable words of
    :data:`PARAMETER_WORDS`, else the path's parts with spaces)."""
    parts = [p for p in str(path).replace(":", ".").split(".") if p]
    if not parts:
        return str(path)
    leaf = parts[-1]
    words = PARAMETER_WORDS.get(leaf, leaf.replace("_", " "))
    owners = [p.replace("_", " ") for p in parts[:-1] if p not in _GROUPS]
    return " ".join([*owners, words])


def parameter_axis(coord: Any, name: str) -> tuple[Any, str]:
    """A swept parameter's values and axis label as figures show them: the coordinate's
    display unit (``display_unit``, ``display_factor``: rpm for a speed, deg for an
    angle, um or mm for a length, else the SI unit such as N/m or kg·m²), an SI prefix
    on top where the unit takes one (2e8 N/m as 200 MN/m), and the parameter's name.

    Parameters
    ----------
    coord : xarray.DataArray
        The parameter coordinate (values in SI, display attributes as
        :func:`reducerlab.analysis.members.axis_coord` writes them).
    name : str
        The parameter's path (shown by its readable name, :func:`parameter_label`).

    Returns
    -------
    values : ndarray
        The values in the unit shown.
    label : str
        ``"name (unit)"``, or ``"name"`` for a plain number.
    """
    name = parameter_label(name)
    unit = str(coord.attrs.get("display_unit", ""))
    x = np.asarray(coord.values, dtype=float) * float(coord.attrs.get("display_factor", 1.0))
    if not unit:
        return x, name
    if unit in ("um", "mm", "ms"):  # display units that carry their prefix already
        return x, f"{name} ({unit})"
    factor, shown = scaled_unit(x, unit)
    return x * factor, f"{name} ({shown})"


def plain_figure(fig: Any, nbins: int = 6) -> Any:
    """Plain tick labels on every axis of ``fig`` (:func:`plain_axis`; a colorbar keeps
    its locator and takes the plain formatter; log axes, axes with ticks the figure
    placed itself, such as categories, and non-rectilinear axes are left as they are)
    and no view spanning round-off: an axis
    whose span is below :data:`ROUND_OFF_SPAN` of its values' size (a constant speed
    that varies in its fifteenth digit) is widened to :data:`FLAT_SPAN` of it about its
    centre, so that it reads as the constant it is instead of ``1e-13+1.5708e2``.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    nbins : int
        The most ticks (less one) on an axis.

    Returns
    -------
    matplotlib.figure.Figure
        ``fig``, changed in place.
    """
    from matplotlib.ticker import FixedLocator, ScalarFormatter

    for ax in fig.axes:
        if ax.name != "rectilinear":  # polar, 3-D: their own ticks
            continue
        colorbar = ax.get_label() == "<colorbar>"
        for axis, get, put in (
            (ax.xaxis, ax.get_xlim, ax.set_xlim),
            (ax.yaxis, ax.get_ylim, ax.set_ylim),
        ):
            if axis.get_scale() != "linear" or isinstance(axis.get_major_locator(), FixedLocator):
                continue  # log axes, and ticks the figure placed (categories, none)
            if colorbar:
                fmt = ScalarFormatter(useOffset=False)
                fmt.set_scientific(False)
                axis.set_major_formatter(fmt)
                continue
            lo, hi = get()
            size = max(abs(lo), abs(hi))
            if size > 0 and abs(hi - lo) < ROUND_OFF_SPAN * size:
                mid, half = 0.5 * (lo + hi), 0.5 * FLAT_SPAN * size
                put(mid - half, mid + half)
            plain_axis(axis, nbins)
    return fig
