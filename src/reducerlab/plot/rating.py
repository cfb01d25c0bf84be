"""Figure of a load-capacity rating (:class:`~reducerlab.analysis.rating.RatingResult`).

:func:`plot_rating` draws, for every gear of every rated pair, the pitting safety factor
``S_H`` (ISO 6336-2 / the bevel pairs' virtual cylindrical gears) and the tooth-root
safety factor ``S_F`` (ISO 6336-3) as bars against the minimum safety factors of the
rating's conditions; a bar short of its minimum is drawn in red. With method A (the
loaded contact analysis, ``analysis.rating_ltca``) each gear has a bar per method,
labelled ``(A)`` and ``(B)``. Plain
:class:`matplotlib.figure.Figure` (no pyplot, Agg-safe).
"""

from __future__ import annotations

import json
from typing import TYPE_CHECKING

import numpy as np

from .axes import plain_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..analysis.rating import RatingResult

__all__ = ["plot_rating"]


def plot_rating(result: RatingResult) -> Figure:
    """Safety factors ``S_H`` and ``S_F`` of every gear against their minimums.

    Parameters
    ----------
    result : RatingResult

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    pairs = result.pairs()
    cond = json.loads(result.data.attrs.get("conditions", "{}"))
    labels, s_h, s_f = [], [], []
    for name, p in pairs.items():
        methods = p.get("methods") or {"B": p}
        for key, m in methods.items():
            for gear, h, f in zip(p["gears"], m["S_H"], m["S_F"], strict=True):
                label = f"{name}: {gear}" if len(pairs) > 1 else str(gear)
                labels.append(f"{label} ({key})" if "A" in methods else label)
                s_h.append(h)
                s_f.append(f)
    fig = Figure(figsize=(8.0, 0.9 + 0.55 * len(labels)), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    y = np.arange(len(labels))
    for ax, values, key, what in (
        (axes[0], s_h, "S_Hmin", "pitting S_H"),
        (axes[1], s_f, "S_Fmin", "tooth root S_F"),
    ):
        floor = float(cond.get(key, 1.0))
        colors = ["tab:red" if v < floor else "tab:green" for v in values]
        ax.barh(y, values, color=colors, height=0.6)
        ax.axvline(floor, color="k", lw=1.2, ls="--")
        right = max(max(values) * 1.18, floor * 1.5)
        width = 0.11 * right  # a value label's width ("0.94" at 8 pt), in the axis' units
        for yi, v in zip(y, values, strict=True):
            # a label the dashed minimum would strike through goes just past it
            x = floor if v < floor < v + width else v
            ax.annotate(f"{v:.2f}", (x, yi), xytext=(3, 0), textcoords="offset points",
                        va="center", fontsize=8)  # fmt: skip
        ax.set_xlabel(f"{what} (dashed: {key} = {floor:g})")  # no legend over the bars
        ax.set_xlim(0, right)
        ax.grid(axis="x", alpha=0.3)
    axes[0].set_yticks(y, labels)
    axes[0].invert_yaxis()
    fig.suptitle(str(result.data.attrs.get("title", "Load capacity")), fontsize=10)
    return plain_figure(fig)
