"""Figures of component (gear-body) modes against the drive's natural frequencies.

:func:`plot_component_comparison` is paper 000's Table 5 as a figure: the system's and
every gear body's modes on one frequency axis with the excitation frequencies over the
operating range (what lies near what, never mode i beside body mode i). :func:`draw_component_lines`
adds the body modes to a Campbell diagram (:func:`~reducerlab.plot.campbell.plot_campbell`
with ``components``): a body mode is a constant frequency, a horizontal line, and it
meets the excitation line ``order * speed / 2 pi`` at ``speed = 2 pi f / order``.

Figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot, Agg-safe).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ReducerlabError

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.components import ComponentModes

__all__ = [
    "BODY_COLOUR",
    "bodies_above",
    "body_label",
    "close_groups",
    "component_label",
    "draw_component_lines",
    "group_label",
    "plot_component_comparison",
]

#: Colour map of the components (the excitation lines use the default cycle).
CMAP = "Dark2"
#: Line style and colour of a body mode in a Campbell diagram: grey dash-dot, apart from
#: the system modes' solid colours and the excitation lines' dark dashes.
BODY_STYLE = "-."
BODY_COLOUR = "#6e6e6e"
#: Body modes closer than this fraction of the frequency axis share one label.
CLOSE = 0.02
#: System modes closer than this fraction of the frequency axis share one number.
LABEL_GAP = 0.012


def _figure(**kw: object) -> Figure:
    from matplotlib.figure import Figure

    return Figure(**kw)  # no pyplot: no global state, works headless


def _colour(i: int) -> Any:
    import matplotlib as mpl

    cmap = mpl.colormaps[CMAP]
    return cmap(i % cmap.N)


def component_label(label: str, frequency: float, kind: str = "") -> str:
    """``"gear 1: 4162.7 Hz (torsional)"`` (no type: no parentheses)."""
    return f"{label}: {frequency:.5g} Hz" + (f" ({kind})" if kind else "")


def _as_components(components: Any) -> list[ComponentModes]:
    """ComponentModes from ComponentModes objects or the report's component dicts."""
    from ..analysis.components import ComponentModes

    if isinstance(components, ComponentModes | Mapping):
        components = [components]
    if components is None or isinstance(components, str) or not isinstance(components, Iterable):
        raise ReducerlabError("components must be a sequence of ComponentModes")
    out = []
    for c in components:
        if isinstance(c, ComponentModes):
            out.append(c)
        elif isinstance(c, Mapping) and "label" in c and "frequencies" in c:
            out.append(
                ComponentModes(
                    c["label"], tuple(c["frequencies"]), tuple(c.get("types", ())),
                    c.get("source", "") or "",
                )
            )  # fmt: skip
        else:
            raise ReducerlabError(
                f"components must be ComponentModes (or a report's component entries), "
                f"got {type(c).__name__}"
            )
    return out


#: Marker of each gear-body mode type in :func:`plot_component_comparison`.
TYPE_MARKERS = {"torsional": "o", "radial": "s", "folding": "^", "umbrella": "v",
                "axial": "D", "bending": "P", "": "d"}  # fmt: skip


def plot_component_comparison(
    data: Mapping[str, Any] | Sequence[float] | Any,
    components: Sequence[ComponentModes] | None = None,
    *,
    orders: Mapping[str, float] | None = None,
    speed_range_rpm: tuple[float, float] | None = None,
    log: bool = False,
    title: str | None = None,
) -> Figure:
    """The drive's natural frequencies, the gear bodies' modes and the excitation
    frequencies on one frequency axis (paper 000's Table 5 as a figure): a row of
    markers per body (marker by mode type), a row for the system's modes (each as the
    band of frequencies it takes over the operating range, its value at the top speed
    marked and numbered), and each excitation's frequencies over the operating range as
    a shaded band (a line at one operating speed) across every row. What lies near
    what is read along the axis; no mode is paired with another by its index.

    Parameters
    ----------
    data : dict or sequence of float
        A :func:`~reducerlab.analysis.resonance.resonance_check` result made with
        components (its ``system`` frequencies over the range, its ``components``, and
        from its diagram the excitation orders and the range), or the system natural
        frequencies (Hz; rigid modes 0) with ``components`` given, or a ``(system
        frequencies, components)`` pair.
    components : sequence of ComponentModes, optional
        The bodies; with a report, they replace the report's.
    orders : mapping, optional
        Excitation name -> order; default the resonance result's (none otherwise).
    speed_range_rpm : tuple of float, optional
        Operating range (rpm) of the excitation bands; default the report's.
    log : bool
        Logarithmic frequency axis (0 Hz left out).
    title : str, optional
    """
    lo_hz = hi_hz = None
    if isinstance(data, Mapping):
        if "system" not in data or "components" not in data:
            raise ReducerlabError(
                "plot_component_comparison: the report has no component modes; run "
                "resonance_check with components"
            )
        system = data["system"]["frequencies_hz"]
        lo_hz, hi_hz = data["system"].get("min_hz"), data["system"].get("max_hz")
        comps = _as_components(components if components is not None else data["components"])
        title = title if title is not None else data.get("title", "")
        speed_range_rpm = speed_range_rpm or tuple(data.get("speed_range_rpm", ())) or None
        diagram = getattr(data, "campbell", None)
        if orders is None and diagram is not None:
            ds = diagram.data
            orders = dict(zip(map(str, ds["excitation"].values), map(float, ds["order"].values),
                              strict=True))  # fmt: skip
    else:
        if (
            components is None
            and isinstance(data, tuple)
            and len(data) == 2
            and not isinstance(data[1], int | float | np.number)
        ):
            data, components = data
        if components is None:
            raise ReducerlabError(
                "plot_component_comparison: give the components with the system frequencies"
            )
        system = data
        comps = _as_components(components)
    system = np.asarray(system, dtype=float).ravel()
    if not comps:
        raise ReducerlabError("plot_component_comparison: no components to compare")
    from .campbell_style import excitation_label, excitation_styles

    rows = len(comps) + 1
    fig = _figure(figsize=(9.0, 1.7 + 0.6 * rows), layout="constrained")
    ax = fig.subplots()
    every = [f for c in comps for f in c.frequencies] + [f for f in system if f > 0]
    top = 1.08 * max(every) if every else 1.0
    y0 = rows - 1  # the system's row on top
    for j, f in enumerate(system):
        if not f > 0:
            continue
        if lo_hz is not None and hi_hz is not None and hi_hz[j] > lo_hz[j]:
            ax.plot([lo_hz[j], hi_hz[j]], [y0, y0], color="0.35", lw=5, alpha=0.5,
                    solid_capstyle="butt", gid="system-band")  # fmt: skip
        ax.plot([f], [y0], "|", color="k", ms=14, mew=2, gid="system-mode")
    _system_labels(ax, system, y0, top)
    types_seen: dict[str, str] = {}
    for i, c in enumerate(comps):
        y = rows - 2 - i
        for f, kind in zip(c.frequencies, c.types, strict=True):
            mk = TYPE_MARKERS.get(kind, "d")
            types_seen.setdefault(kind or "(type not given)", mk)
            ax.plot([f], [y], mk, color=_colour(i), ms=7, mec="k", mew=0.5, gid="body-mode")
    if orders:
        lo_rpm, hi_rpm = speed_range_rpm if speed_range_rpm else (0.0, 0.0)
        styles = excitation_styles(len(orders))
        for (name, q), (colour, dash, _) in zip(orders.items(), styles, strict=True):
            f0, f1 = q * lo_rpm / 60.0, q * hi_rpm / 60.0  # Hz at the range's ends
            if f0 > top or f1 <= 0:
                continue
            label = excitation_label(name, q)
            if f1 > f0:
                ax.axvspan(f0, min(f1, top), color=colour, alpha=0.15, lw=0, gid="excitation",
                           label=f"{label}: {f0:.4g}-{f1:.4g} Hz")  # fmt: skip
            else:
                ax.axvline(f0, color=colour, linestyle=dash, lw=1.3, gid="excitation",
                           label=f"{label}: {f0:.4g} Hz")  # fmt: skip
    from matplotlib.lines import Line2D

    handles, _ = ax.get_legend_handles_labels()
    handles += [Line2D([], [], marker=mk, color="0.5", mec="k", ls="none", label=kind)
                for kind, mk in types_seen.items()]  # fmt: skip
    if log:
        ax.set_xscale("log")
        ax.set_xlim(min(every) / 1.5 if every else 1.0, top * 1.5)
    else:
        ax.set_xlim(0, top)
    ax.set_ylim(-0.7, rows - 0.05)  # room above the system row for two rows of numbers
    legend_rows = -(-len(handles) // 2) if len(handles) > 3 else len(handles)
    fig.set_size_inches(9.0, 2.0 + 0.55 * rows + 0.18 * legend_rows)
    ax.set_yticks(range(rows))
    rng = f" ({speed_range_rpm[0]:.4g}-{speed_range_rpm[1]:.4g} rpm)" if speed_range_rpm else ""
    ax.set_yticklabels([c.label for c in reversed(comps)] + [f"system{rng}"])
    ax.set_xlabel("frequency (Hz)")
    ax.set_title(
        "Natural frequencies of the drive and the gear bodies against the excitations"
        + (f"\n{title}" if title else ""), fontsize=9,
    )  # fmt: skip
    from matplotlib.transforms import ScaledTranslation

    below = ax.transAxes + ScaledTranslation(0, -34 / 72, fig.dpi_scale_trans)  # under the label
    ax.legend(handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, 0.0),
              bbox_transform=below, borderaxespad=0, ncol=2 if len(handles) > 3 else 1,
              frameon=False)  # the legend below: the axis keeps the figure's width  # fmt: skip
    ax.grid(alpha=0.3, axis="x")
    return fig


def _system_labels(ax: Axes, system: np.ndarray, y: float, top: float) -> None:
    """The system modes' numbers above their marks: modes closer than a label's width
    share one label (``"3, 4"``), and neighbouring labels that would still touch are
    staggered in height."""
    rows = [(float(f), str(j + 1)) for j, f in enumerate(system) if f > 0]
    last_x, last_w, level = -np.inf, 0.0, 0
    for group in close_groups(rows, LABEL_GAP * top):
        x = float(np.mean([f for f, _ in group]))
        text = ", ".join(sorted((m for _, m in group), key=int))
        w = LABEL_GAP * top * len(text)  # about a character per LABEL_GAP of the axis
        level = 1 - level if x - last_x < 0.5 * (w + last_w) + 0.5 * LABEL_GAP * top else 0
        ax.annotate(text, (x, y), xytext=(0, 9 + 10 * level), textcoords="offset points",
                    ha="center", fontsize=8, gid="system-label")  # fmt: skip
        last_x, last_w = x, w


def draw_component_lines(
    ax: Axes,
    components: Sequence[ComponentModes],
    orders: Sequence[float],
    rpm_range: tuple[float, float],
    fmax: float,
) -> list[Any]:
    """Draw each body mode below ``fmax`` as a horizontal line over ``rpm_range`` in
    the body-mode style (:data:`BODY_COLOUR`, :data:`BODY_STYLE`: grey dash-dot, never
    a system mode's colour), labelled at the line ``"gear N body: f Hz (type)"``, and
    mark its crossings with the excitation lines ``order * speed / 2 pi`` (at
    ``speed = 60 f / order`` rpm, open diamonds).

    Returns one legend proxy for all the body modes shown (none when none is).
    """
    from matplotlib.lines import Line2D

    comps = _as_components(components)
    r0, r1 = rpm_range
    shown = []
    for i, c in enumerate(comps):
        xs, ys = [], []
        rows = [(f, kind) for f, kind in zip(c.frequencies, c.types, strict=True) if f <= fmax]
        for f, kind in rows:
            ax.plot([r0, r1], [f, f], linestyle=BODY_STYLE, color=BODY_COLOUR, lw=1.0,
                    label=body_label(c.label, f, kind), gid="component-mode")  # fmt: skip
            for order in orders:
                rpm = 60.0 * f / float(order)  # 2 pi f / order rad/s in rpm
                if r0 <= rpm <= r1:
                    xs.append(rpm)
                    ys.append(f)
        left = i % 2 == 0  # alternate sides between the bodies (the modes end right)
        for group in close_groups(rows, CLOSE * fmax):
            text = group_label(c.label + " body", group)
            ax.text(r0 if left else r1, group[0][0], " " + text + " ", fontsize=7.5,
                    color=BODY_COLOUR, ha="left" if left else "right", va="bottom",
                    clip_on=True, gid="component-label")  # fmt: skip
        if xs:
            ax.plot(xs, ys, "D", ls="none", mfc="none", color=BODY_COLOUR, ms=6, mew=1.3,
                    gid="component-crossing")  # fmt: skip
        if rows:
            shown.append(c.label)
    if not shown:
        return []
    label = f"gear-body modes, FE ({', '.join(shown)}): named at the line"
    return [Line2D([], [], linestyle=BODY_STYLE, color=BODY_COLOUR, lw=1.0, marker="D",
                   mfc="none", label=label)]  # fmt: skip


def bodies_above(components: Sequence[Any], fmax: float) -> str:
    """``"gear 2 body modes above 3.3 kHz: 3746, 5790, 8860 Hz"`` (empty when none is)."""
    from .campbell_style import hz

    parts = []
    for c in _as_components(components):
        fs = sorted({float(f"{f:.4g}") for f in c.frequencies if f > fmax})
        if fs:
            parts.append(f"{c.label} body modes above {hz(fmax)}: "
                         + ", ".join(f"{f:g}" for f in fs) + " Hz")  # fmt: skip
    return "; ".join(parts)


def body_label(label: str, frequency: float, kind: str = "") -> str:
    """``"gear 2 body: 3746.3 Hz (bending)"``."""
    return component_label(label + " body", frequency, kind)


def close_groups(rows: list[tuple[float, str]], gap: float) -> list[list[tuple[float, str]]]:
    """Ascending (frequency, type) rows in runs whose neighbours are within ``gap`` Hz
    (their labels would overlap)."""
    groups: list[list[tuple[float, str]]] = []
    for row in sorted(rows):
        if groups and row[0] - groups[-1][-1][0] <= gap:
            groups[-1].append(row)
        else:
            groups.append([row])
    return groups


def group_label(label: str, group: list[tuple[float, str]]) -> str:
    """``"gear 1: 4162.7 Hz (torsional)"``, for close modes ``"gear 1: 5466.4 / 5468.2
    Hz (folding)"``, for a repeated one ``"gear 1: 3746.3 Hz (bending) x 2"``."""
    freqs = list(dict.fromkeys(f"{f:.5g}" for f, _ in group))
    kinds = list(dict.fromkeys(k for _, k in group if k))
    text = f"{label}: {' / '.join(freqs)} Hz" + (f" ({', '.join(kinds)})" if kinds else "")
    return text + (f" x {len(group)}" if len(freqs) == 1 and len(group) > 1 else "")
