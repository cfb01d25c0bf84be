"""The bearing pattern of a loaded tooth contact result drawn on the tooth flank
(issue 32): the highest contact pressure over the mesh cycle at every point of the
external gear's developed flank (:mod:`reducerlab.plot.contact_flank`), inside the
flank's outline (root end, tip, toe and heel), as an engineer reads a marking-compound
pattern.

The cells of one tooth pair at one position form a band of the flank around its contact
line, on a grid of flank parameters ``(u, v)``; each position computes its own rows of
``u``. So that the bands of all positions add up to one smooth pattern, each band's
pressure (zero on its unloaded cells) is interpolated along the profile onto one regular
set of rows, column by column, and the largest value over the positions and tooth pairs
is kept (NaN where no position computed that point: the flank outside every band).

:func:`plot_bearing_pattern` is the matplotlib figure, :func:`plotly_bearing_pattern`
the interactive one of the report (hover for the pressure); :func:`draw_bearing_pattern`
draws the pattern on a given axes (the overview's panel (a)).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .contact_flank import angle_deg, contact_data, developed_flank, gear_a_name

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.contact import ContactResult

__all__ = [
    "bearing_pattern",
    "draw_bearing_pattern",
    "plot_bearing_pattern",
    "plotly_bearing_pattern",
]

Array = NDArray[np.float64]

CMAP = "viridis"
#: Rows of the regular grid along the profile.
ROWS = 120
PRESSURE_LABEL = "highest contact pressure over the cycle (MPa)"


def bearing_pattern(result: ContactResult | xr.Dataset, rows: int = ROWS) -> dict[str, Any]:
    """The bearing pattern on the developed flank.

    Parameters
    ----------
    result : ContactResult or its dataset
    rows : int
        Rows of the regular grid along the profile (>= 2).

    Returns
    -------
    dict
        ``profile`` (rows,) and ``face`` (columns,): the grid's developed coordinates
        (mm from the flank's root end and its toe; bare flank parameters when the result
        has no cell points, ``mm`` false); ``pressure`` (rows, columns): the highest
        contact pressure over the cycle (Pa; 0 where computed and never loaded, NaN
        where no position computed that point); ``outline``: the developed coordinates
        of the flank's ``root`` end and ``tip`` (from the result's ``flank_u_range``;
        else the ends of the computed rows, ``tip_known`` false) and of its ``toe`` and
        ``heel`` (``v`` = 0 and 1); ``peak``: (face, profile, Pa) of the highest cell,
        at ``peak_position``.
    """
    ds = contact_data(result)
    fl = developed_flank(ds)
    u = np.asarray(ds["u"].values, float)
    v = np.asarray(ds["v"].values, float)
    p = np.asarray(ds["pressure"].values, float)
    f = np.asarray(ds["cell_force"].values, float)
    with np.errstate(invalid="ignore"):
        p = np.where(np.isfinite(f) & (f > 0) & np.isfinite(p), p, 0.0)
    pos = np.asarray(ds["cell_position"].values, np.int64)
    tooth = np.asarray(ds["cell_tooth"].values, np.int64)
    rng = ds.attrs.get("flank_u_range")
    known = rng is not None and len(np.atleast_1d(rng)) == 2
    if known:
        lo, hi = (float(x) for x in np.atleast_1d(rng))
        if int(ds.attrs.get("flank_tip_end", 1)) < 0:
            lo, hi = hi, lo
    else:
        lo, hi = float(u.min()), float(u.max())
    ur = np.linspace(min(lo, hi, u.min()), max(lo, hi, u.max()), max(int(rows), 2))
    V = np.unique(v)
    col = np.searchsorted(V, v)
    grid = np.full((len(ur), len(V)), np.nan)
    # each band, interpolated along the profile onto the rows
    group = pos * (int(tooth.max() - tooth.min()) + 1) + (tooth - tooth.min())
    order = np.lexsort((u, col, group))
    g, c = group[order], col[order]
    cuts = np.flatnonzero((g[1:] != g[:-1]) | (c[1:] != c[:-1])) + 1
    for part in np.split(order, cuts):
        if len(part) < 2:
            continue
        line = np.interp(ur, u[part], p[part], left=np.nan, right=np.nan)
        j = col[part[0]]
        grid[:, j] = np.fmax(grid[:, j], line)
    _sweep(grid, ur, u, col, p, pos, tooth, ds.sizes["position"])
    root, tip = fl.at_u([lo, hi])
    toe, heel = fl.at_v([0.0, 1.0])
    profile, face = fl.at_u(ur) - root, fl.at_v(V) - toe
    k = int(np.argmax(p))
    return {
        "profile": profile,
        "face": face,
        "pressure": grid,
        "mm": fl.mm,
        "tip_known": known,
        "outline": {"root": 0.0, "tip": float(tip - root), "toe": 0.0, "heel": float(heel - toe)},
        "peak": (float(fl.at_v(v[k]) - toe), float(fl.at_u(u[k]) - root), float(p[k])),
        "peak_position": int(pos[k]),
    }


def _sweep(
    grid: Array,
    ur: Array,
    u: Array,
    col: NDArray[np.int64],
    p: Array,
    pos: NDArray[np.int64],
    tooth: NDArray[np.int64],
    positions: int,
) -> None:
    """Add to ``grid`` the pressure between positions: in each column, the loaded line
    of a tooth pair moves from its centre ``u_c`` at one position to the next (the same
    pair at the next position; after the last position, the neighbouring pair at the
    first, which continues it), its peak pressure interpolated linearly on the way."""
    on = p > 0
    if not on.any():
        return
    key = (pos[on] * 1000 + (tooth[on] + 500)) * len(grid[0]) + col[on]
    uniq, inv = np.unique(key, return_inverse=True)
    w = np.bincount(inv, p[on])
    centre = np.bincount(inv, p[on] * u[on]) / w
    peak = np.zeros(len(uniq))
    np.maximum.at(peak, inv, p[on])
    line: dict[tuple[int, int, int], tuple[float, float]] = {}
    for kk, uc, pk in zip(uniq.tolist(), centre.tolist(), peak.tolist(), strict=True):
        c = kk % len(grid[0])
        rest = kk // len(grid[0])
        line[(rest // 1000, rest % 1000 - 500, c)] = (uc, pk)
    for (j, k, c), (u0, p0) in line.items():
        nxt = (
            [line.get((j + 1, k, c))]
            if j + 1 < positions
            else [line.get((0, k + 1, c)), line.get((0, k - 1, c))]
        )
        prev = line.get((j - 1, k, c))
        nxt = [x for x in nxt if x is not None]
        if not nxt:
            continue
        if len(nxt) > 1 and prev is not None:  # the pair that continues the motion
            guess = 2 * u0 - prev[0]
            nxt = [min(nxt, key=lambda x: abs(x[0] - guess))]
        u1, p1 = nxt[0]
        a, b = min(u0, u1), max(u0, u1)
        rows = (ur >= a) & (ur <= b)
        if rows.any() and b > a:
            val = p0 + (p1 - p0) * (ur[rows] - u0) / (u1 - u0)
            grid[rows, c] = np.fmax(grid[rows, c], val)


def _labels(bp: dict[str, Any]) -> tuple[str, str]:
    unit = "mm" if bp["mm"] else "flank parameter"
    return (f"face width from the toe ({unit})", f"profile from the root end ({unit})")


def _edge_names(bp: dict[str, Any]) -> tuple[str, str]:
    """Names of the profile ends: the flank's, or the ends of the computed rows."""
    if bp["tip_known"]:
        return "root end of the flank", "tip"
    return "lowest computed row", "highest computed row"


def draw_bearing_pattern(ax: Axes, result: ContactResult | xr.Dataset, fig: Figure) -> Any:
    """Draw the bearing pattern on ``ax`` (its colour bar beside it): the pressure map,
    the flank's outline with its edges named, the loaded area's border (white) and the
    highest cell (star). Returns the colour bar."""
    from matplotlib.lines import Line2D

    ds = contact_data(result)
    bp = bearing_pattern(ds)
    x, y, z = bp["face"], bp["profile"], 1e-6 * bp["pressure"]
    o = bp["outline"]
    top = max(float(np.nanmax(z)) if np.isfinite(z).any() else 0.0, 1e-6 * bp["peak"][2])
    im = ax.pcolormesh(x, y, np.ma.masked_invalid(np.where(z > 0, z, np.nan)), cmap=CMAP,
                       vmin=0.0, vmax=top or 1.0, shading="nearest")  # fmt: skip
    ax.pcolormesh(x, y, np.ma.masked_invalid(np.where(z == 0, 1.0, np.nan)), cmap="Greys",
                  vmin=0.0, vmax=4.0, shading="nearest", zorder=0)  # fmt: skip
    if top > 0:
        ax.contour(x, y, np.nan_to_num(z), levels=[0.02 * top], colors="w", linewidths=0.8)
    rx = [o["toe"], o["heel"], o["heel"], o["toe"], o["toe"]]
    ry = [o["root"], o["root"], o["tip"], o["tip"], o["root"]]
    ax.plot(rx, ry, color="k", lw=1.4, clip_on=False)
    root, tip = _edge_names(bp)
    kw = {"fontsize": 7, "color": "0.15", "clip_on": False}
    ax.text(0.5 * (o["toe"] + o["heel"]), o["tip"], tip, ha="center", va="bottom", **kw)
    ax.text(0.5 * (o["toe"] + o["heel"]), o["root"], root, ha="center", va="top", **kw)
    ax.text(o["toe"], 0.5 * o["tip"], "toe ", ha="right", va="center", rotation=90, **kw)
    ax.text(o["heel"], 0.5 * o["tip"], " heel", ha="left", va="center", rotation=90, **kw)
    px, py, pp = bp["peak"]
    j = bp["peak_position"]
    ax.plot(px, py, marker="*", ms=11, mfc="w", mec="k", ls="", clip_on=False)
    span = max(o["heel"] - o["toe"], 1e-12)
    pad = 0.06 * span
    ax.set_xlim(o["toe"] - pad, o["heel"] + pad)
    ax.set_ylim(min(o["root"], float(y.min())) - pad, max(o["tip"], float(y.max())) + pad)
    if bp["mm"]:
        ax.set_aspect("equal", adjustable="box")
    xl, yl = _labels(bp)
    ax.set_xlabel(xl, fontsize=8)
    ax.set_ylabel(yl, fontsize=8)
    ax.tick_params(labelsize=7)
    ax.locator_params(nbins=6)
    cax = ax.inset_axes((1.03, 0.0, 0.025, 1.0))  # as tall as the flank
    cb = fig.colorbar(im, cax=cax)
    cb.set_label(PRESSURE_LABEL, fontsize=8)
    cb.ax.tick_params(labelsize=7)
    star = f"p_max = {1e-6 * pp:.0f} MPa at position {j} ({angle_deg(ds)[j]:.2f} deg)"
    handles = [
        Line2D([], [], color="k", lw=1.4, label="flank outline"),
        Line2D([], [], color="w", lw=3, marker="s", mfc="0.85", mec="0.85",
               label="computed, never loaded"),
        Line2D([], [], ls="", marker="*", ms=9, mfc="w", mec="k", label=star),
    ]  # fmt: skip
    ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2),
              ncol=3, frameon=False)  # fmt: skip
    return cb


def plot_bearing_pattern(result: ContactResult | xr.Dataset) -> Figure:
    """The bearing pattern on gear A's developed flank, its outline drawn and named.

    Parameters
    ----------
    result : ContactResult or its dataset

    Returns
    -------
    matplotlib.figure.Figure
        One panel (mm, true scale): the highest contact pressure over the cycle
        (:func:`bearing_pattern`, MPa colour bar), light grey where computed and never
        loaded, the loaded area's border in white, the flank's outline with its root
        end, tip, toe and heel named, and the highest cell starred.
    """
    from matplotlib.figure import Figure

    ds = contact_data(result)
    fig = Figure(figsize=(7.5, 4.6), layout="constrained")
    ax = fig.add_subplot()
    draw_bearing_pattern(ax, ds, fig)
    ax.set_title(f"bearing pattern on {gear_a_name(ds)}'s flank over one mesh cycle "
                 f"({ds.sizes['position']} positions)", fontsize=9)  # fmt: skip
    return fig


def plotly_bearing_pattern(result: ContactResult | xr.Dataset) -> Any:
    """The bearing pattern as an interactive heat map (hover for the pressure).

    Returns
    -------
    plotly.graph_objects.Figure
        Trace 0 a ``Heatmap`` of the highest pressure over the cycle (MPa, to 0.1 MPa;
        gaps where never computed), trace 1 the flank's outline, trace 2 the highest
        cell; the axes in mm at true scale.
    """
    import plotly.graph_objects as go

    ds = contact_data(result)
    bp = bearing_pattern(ds)
    o = bp["outline"]
    z = np.round(1e-6 * bp["pressure"], 1).astype(np.float32)
    xl, yl = _labels(bp)
    top = max(float(np.nanmax(z)) if np.isfinite(z).any() else 0.0, 1e-6 * bp["peak"][2])
    heat = go.Heatmap(
        x=np.round(bp["face"], 3).astype(np.float32),
        y=np.round(bp["profile"], 3).astype(np.float32),
        z=z, colorscale="Viridis", zmin=0.0, zmax=top or 1.0,
        colorbar={"title": {"text": "p_max (MPa)"}},
        hovertemplate="face %{x:.2f} mm, profile %{y:.2f} mm: %{z:.0f} MPa<extra></extra>",
        name="pressure",
    )  # fmt: skip
    outline = go.Scatter(
        x=[o["toe"], o["heel"], o["heel"], o["toe"], o["toe"]],
        y=[o["root"], o["root"], o["tip"], o["tip"], o["root"]],
        mode="lines", line={"color": "black", "width": 2}, name="flank outline",
        hoverinfo="skip",
    )  # fmt: skip
    px, py, pp = bp["peak"]
    star = go.Scatter(
        x=[px], y=[py], mode="markers", name=f"p_max = {1e-6 * pp:.0f} MPa",
        marker={"symbol": "star", "size": 14, "color": "white", "line": {"color": "black",
                                                                         "width": 1}},
    )  # fmt: skip
    root, tip = _edge_names(bp)
    mid = 0.5 * (o["toe"] + o["heel"])
    notes = [
        {"x": mid, "y": o["tip"], "text": tip, "yanchor": "bottom"},
        {"x": mid, "y": o["root"], "text": root, "yanchor": "top"},
        {"x": o["toe"], "y": 0.5 * o["tip"], "text": "toe", "xanchor": "right"},
        {"x": o["heel"], "y": 0.5 * o["tip"], "text": "heel", "xanchor": "left"},
    ]
    fig = go.Figure([heat, outline, star])
    fig.update_layout(
        title=f"bearing pattern on {gear_a_name(ds)}'s flank: highest contact pressure over "
        f"one mesh cycle ({ds.sizes['position']} positions)",
        xaxis={"title": xl, "constrain": "domain"},
        yaxis={"title": yl, "scaleanchor": "x", "scaleratio": 1},
        annotations=[{**n, "showarrow": False, "font": {"size": 11}} for n in notes],
        legend={"orientation": "h", "y": -0.25},
        height=420,
        template="plotly_white",
    )
    return fig
