"""Figures of component (gear-body) modes against the drive's natural frequencies.

:func:`plot_component_comparison` is paper 000's Table 5 as a figure: for each order
1..N, the system natural frequency next to each gear body's. :func:`draw_component_lines`
adds the body modes to a Campbell diagram (:func:`~reducerlab.plot.campbell.plot_campbell`
with ``components``): a body mode is a constant frequency, a horizontal line, and it
meets the excitation line ``order * speed / 2 pi`` at ``speed = 2 pi f / order``.

Figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot, Agg-safe).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ReducerlabError

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.components import ComponentModes

__all__ = ["component_label", "draw_component_lines", "plot_component_comparison"]

#: Colour map of the components (the excitation lines use the default cycle).
CMAP = "Dark2"
#: Line style of a body mode in a Campbell diagram.
BODY_STYLE = (0, (6, 3))
#: Body modes closer than this fraction of the frequency axis share one label.
CLOSE = 0.02


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


def plot_component_comparison(
    data: Mapping[str, Any] | Sequence[float] | Any,
    components: Sequence[ComponentModes] | None = None,
    *,
    count: int | None = None,
    log: bool = False,
    title: str | None = None,
) -> Figure:
    """Natural frequencies of the drive and of each component, order by order (paper
    000's Table 5): a group of bars per order 1..N, the system's first, each component
    bar labelled with its mode type.

    Parameters
    ----------
    data : dict or sequence of float
        A :func:`~reducerlab.analysis.resonance.resonance_check` report made with
        components (its ``system`` frequencies at the top speed of the range and its
        ``components``), or the system natural frequencies (Hz, ascending; rigid modes
        0) with ``components`` given, or a ``(system frequencies, components)`` pair.
    components : sequence of ComponentModes, optional
        The bodies; with a report, they replace the report's.
    count : int, optional
        Orders shown (1..count); default: the most modes of a component.
    log : bool
        Logarithmic frequency axis (0 Hz bars are then left out).
    """
    speed_note = ""
    if isinstance(data, Mapping):
        if "system" not in data or "components" not in data:
            raise ReducerlabError(
                "plot_component_comparison: the report has no component modes; run "
                "resonance_check with components"
            )
        system = data["system"]["frequencies_hz"]
        rpm = data["system"].get("speed_rpm")
        if rpm:
            speed_note = f" at {rpm[-1]:.6g} rpm"
        comps = _as_components(components if components is not None else data["components"])
        title = title if title is not None else data.get("title", "")
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
    n = max(len(c.frequencies) for c in comps)
    if count is not None:
        if isinstance(count, bool) or not isinstance(count, int) or count < 1:
            raise ReducerlabError(f"count must be a positive integer, got {count!r}")
        n = count
    x = np.arange(1, n + 1)
    groups = 1 + len(comps)
    width = 0.84 / groups
    fig = _figure(figsize=(min(12.0, max(6.0, 0.45 * n * groups + 2.0)), 4.6), layout="constrained")
    ax = fig.subplots()

    def heights(values: Sequence[float]) -> Any:
        h = np.full(n, np.nan)
        m = min(n, len(values))
        h[:m] = np.asarray(values[:m], dtype=float)
        if log:
            h[~(h > 0)] = np.nan
        return h

    offset = (np.arange(groups) - (groups - 1) / 2) * width
    hs = heights(system)
    ax.bar(x + offset[0], hs, width, color="0.55", label=f"system{speed_note}")
    top = np.nanmax(hs) if np.any(np.isfinite(hs)) else 0.0
    for i, c in enumerate(comps):
        h = heights(c.frequencies)
        top = max(top, np.nanmax(h) if np.any(np.isfinite(h)) else 0.0)
        ax.bar(x + offset[i + 1], h, width, color=_colour(i), label=c.label)
        for k in range(min(n, len(c.frequencies))):
            if not math.isfinite(h[k]):
                continue
            kind = c.types[k]
            ax.text(x[k] + offset[i + 1], h[k], f" {c.frequencies[k]:.5g}" +
                    (f" {kind}" if kind else ""), rotation=90, ha="center", va="bottom",
                    fontsize=6, clip_on=True)  # fmt: skip
    for k in range(min(n, hs.size)):
        if math.isfinite(hs[k]):
            ax.text(x[k] + offset[0], hs[k], f" {hs[k]:.5g}", rotation=90, ha="center",
                    va="bottom", fontsize=6, color="0.3", clip_on=True)  # fmt: skip
    if log:
        ax.set_yscale("log")
        ax.set_ylim(top=top * 3.0 if top > 0 else 10.0)
    else:
        ax.set_ylim(0, top * 1.3 if top > 0 else 1.0)
    ax.set_xticks(x)
    ax.set_xlabel("order")
    ax.set_ylabel("natural frequency (Hz)")
    ax.set_title(
        "Natural frequencies of the drive and the gear bodies" + (f"\n{title}" if title else ""),
        fontsize=9,
    )
    ax.legend(fontsize=7, ncol=min(groups, 5))
    ax.grid(alpha=0.3, axis="y")
    return fig


def draw_component_lines(
    ax: Axes,
    components: Sequence[ComponentModes],
    orders: Sequence[float],
    rpm_range: tuple[float, float],
    fmax: float,
) -> list[Any]:
    """Draw each body mode below ``fmax`` as a horizontal dashed line over
    ``rpm_range`` (labelled ``"gear N: f Hz (type)"``) and mark its crossings with the
    excitation lines ``order * speed / 2 pi`` (at ``speed = 60 f / order`` rpm).

    Returns one legend proxy per component that has a mode in the range.
    """
    from matplotlib.lines import Line2D

    comps = _as_components(components)
    r0, r1 = rpm_range
    proxies = []
    for i, c in enumerate(comps):
        col = _colour(i)
        xs, ys = [], []
        rows = [(f, kind) for f, kind in zip(c.frequencies, c.types, strict=True) if f <= fmax]
        for f, kind in rows:
            ax.plot([r0, r1], [f, f], linestyle=BODY_STYLE, color=col, lw=0.9,
                    label=component_label(c.label, f, kind), gid="component-mode")  # fmt: skip
            for order in orders:
                rpm = 60.0 * f / float(order)  # 2 pi f / order rad/s in rpm
                if r0 <= rpm <= r1:
                    xs.append(rpm)
                    ys.append(f)
        right = len(proxies) % 2 == 0  # alternate sides between the bodies shown
        for group in _close_groups(rows, CLOSE * fmax):
            text = _group_label(c.label, group)
            ax.text(r1 if right else r0, group[0][0], text + " " if right else " " + text,
                    fontsize=6, color=col, ha="right" if right else "left", va="bottom",
                    clip_on=True)  # fmt: skip
        if xs:
            ax.plot(xs, ys, "D", ls="none", mfc="none", color=col, ms=6, mew=1.3,
                    gid="component-crossing")  # fmt: skip
        if rows:
            proxy = Line2D([], [], linestyle=BODY_STYLE, color=col, lw=0.9, marker="D",
                           mfc="none", label=f"{c.label} body modes")  # fmt: skip
            proxies.append(proxy)
    return proxies


def _close_groups(rows: list[tuple[float, str]], gap: float) -> list[list[tuple[float, str]]]:
    """Ascending (frequency, type) rows in runs whose neighbours are within ``gap`` Hz
    (their labels would overlap)."""
    groups: list[list[tuple[float, str]]] = []
    for row in rows:
        if groups and row[0] - groups[-1][-1][0] <= gap:
            groups[-1].append(row)
        else:
            groups.append([row])
    return groups


def _group_label(label: str, group: list[tuple[float, str]]) -> str:
    """``"gear 1: 4162.7 Hz (torsional)"``, or for close modes
    ``"gear 1: 5466.4 / 5468.2 Hz (folding)"``."""
    if len(group) == 1:
        return component_label(label, *group[0])
    kinds = list(dict.fromkeys(k for _, k in group if k))
    freqs = " / ".join(f"{f:.5g}" for f, _ in group)
    return f"{label}: {freqs} Hz" + (f" ({', '.join(kinds)})" if kinds else "")
