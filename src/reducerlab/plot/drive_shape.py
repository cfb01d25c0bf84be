"""Mode shapes as the drive's bodies moving (issue 32): each body of the lumped model drawn
at its place in the drive (:class:`~reducerlab.drives.places.DriveLayout`) as circles
with a pointer and an axle, so that a translation moves it, a tilt tips it and a twist
turns its pointer; the motion of a mode is scaled so that the largest displacement of any
drawn point is a stated fraction of the drive's size.

:func:`plot_drive_shapes` is the still (matplotlib: one 3-D panel per mode, grey at
rest, coloured at the mode's peak); :func:`plotly_drive_shapes` the report's
interactive 3-D figure, animated over one period, with a mode menu. Plotly is imported
only when its figure is built.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..analysis.modal import ModalResult
    from ..drives.places import DriveLayout, Place

__all__ = [
    "FRACTION",
    "FRAMES_PER_CYCLE",
    "body_points",
    "deformed_points",
    "mode_amplitude",
    "plot_drive_shapes",
    "plotly_drive_shapes",
    "shape_values",
]

#: Largest drawn displacement of a mode as a fraction of the drive's size.
FRACTION = 0.15
#: Animation frames over one period (the distinct ones are shared: sin takes 7 values).
FRAMES_PER_CYCLE = 12
#: Segments of each drawn circle.
SEGMENTS = 20
#: Body colours (matplotlib's tab10, as the bar charts of :mod:`reducerlab.plot.modal`).
COLOURS = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#7f7f7f",
    "#bcbd22",
    "#17becf",
)


def body_points(place: Place, segments: int = SEGMENTS) -> NDArray[np.float64]:
    """Points (m, rows of x, y, z) of one continuous line drawn for a body at rest: the
    axle through its centre and, per circle, a diameter along its ``e1`` that reaches
    out past the rim as a pointer on one side (so that a turn shows) and the circle
    (the line runs back over itself where it must: no gaps, so that the coordinates
    pack as integers in :func:`plotly_drive_shapes`)."""
    e1, e2, a = place.frame()
    c = np.asarray(place.centre)
    offs = [off for off, _ in place.rings]
    stub = 0.25 * place.radius
    parts = [c + (min(offs) - stub) * a]
    phi = np.linspace(0.0, 2 * math.pi, segments + 1)
    for off, r in sorted(place.rings):
        mid = c + off * a
        parts += [mid, mid - r * e1, mid, mid + 1.3 * r * e1]
        parts += list(mid + r * (np.outer(np.cos(phi), e1) + np.outer(np.sin(phi), e2)))
        parts.append(mid)
    parts.append(c + (max(offs) + stub) * a)
    return np.array(parts)


def shape_values(result: ModalResult, mode: int) -> dict[str, float]:
    """The mass-normalised shape of a 1-based ``mode`` as ``{"body.kind": value}`` (SI)."""
    j = _index(result, mode)
    return dict(zip(result.dof_names, (float(v) for v in result.shapes[:, j]), strict=True))


def deformed_points(
    layout: DriveLayout, values: dict[str, float], scale: float, segments: int = SEGMENTS
) -> dict[str, NDArray[np.float64]]:
    """Every body's drawn points (m) moved by ``scale`` times the DOF ``values``."""
    motion = layout.motion(values, scale)
    out = {}
    for p in layout.places:
        t, R = motion[p.body]
        c = np.asarray(p.centre)
        out[p.body] = c + t + (body_points(p, segments) - c) @ R.T
    return out


def mode_amplitude(
    layout: DriveLayout, values: dict[str, float], fraction: float = FRACTION
) -> float:
    """Factor on the DOF values that makes the largest displacement of any drawn point
    ``fraction`` of the drive's size (small-motion displacement, by a difference)."""
    big = max((abs(v) for v in values.values()), default=0.0)
    if big == 0.0 or not math.isfinite(big):
        return 0.0
    h = 1e-7 * layout.size / big
    rest = deformed_points(layout, {}, 0.0)
    moved = deformed_points(layout, values, h)
    disp = max(float(np.nanmax(np.linalg.norm(moved[b] - rest[b], axis=1))) for b in rest)
    return 0.0 if disp == 0.0 else fraction * layout.size * h / disp


def _index(result: ModalResult, mode: int) -> int:
    modes = [int(m) for m in result.data["mode"].values]
    if mode not in modes:
        raise ReducerlabError(
            f"modes: mode {mode} does not exist; the result has modes 1..{len(modes)}"
        )
    return modes.index(mode)


def _chosen(result: ModalResult, modes: Sequence[int] | None, limit: int | None) -> list[int]:
    """The 1-based modes to draw: those given, else the elastic ones (at most ``limit``)."""
    ds = result.data
    if modes is not None:
        out = [int(m) for m in modes]
        for m in out:
            _index(result, m)
    else:
        out = [int(m) for m, r in zip(ds["mode"].values, ds["rigid"].values, strict=True) if not r]
        out = out[:limit] if limit else out
    if not out:
        raise ReducerlabError("modes: the result has no elastic mode to draw")
    return out


def _title(result: ModalResult, mode: int) -> str:
    j = _index(result, mode)
    f = float(result.data["frequency"].values[j])
    return f"mode {mode}: {f:.4g} Hz — {result.data['classification'].values[j]}"


def _check_fraction(fraction: float) -> None:
    if not (isinstance(fraction, int | float) and 0 < fraction <= 0.5):
        raise ReducerlabError(f"fraction must be a number in (0, 0.5], got {fraction!r}")


def _moving(layout: DriveLayout, result: ModalResult) -> list[Place]:
    """The places of bodies with DOFs (the fixed members are drawn at rest only)."""
    bodies = {str(b) for b in result.data["body"].values}
    return [p for p in layout.places if p.body in bodies]


def plot_drive_shapes(
    result: ModalResult,
    layout: DriveLayout,
    modes: Sequence[int] | None = None,
    *,
    fraction: float = FRACTION,
    panel: float = 3.4,
) -> Figure:
    """The mode shapes as the drive moving: one 3-D panel per mode (three a row), the
    drive at rest in grey and at the mode's peak in colour, one colour per body.

    Parameters
    ----------
    result : ModalResult
    layout : DriveLayout
        Where the bodies sit (:func:`reducerlab.drives.drive_layout`).
    modes : sequence of int, optional
        1-based modes; every elastic mode by default.
    fraction : float
        Largest drawn displacement over the drive's size, in (0, 0.5].
    panel : float
        Width of one panel (in).
    """
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the 3-D projection)

    _check_fraction(fraction)
    chosen = _chosen(result, modes, None)
    ncol = min(3, len(chosen))
    nrow = math.ceil(len(chosen) / ncol)
    fig = Figure(figsize=(panel * ncol, 0.88 * panel * nrow + 0.8), layout="constrained")
    rest = deformed_points(layout, {}, 0.0)
    moving = _moving(layout, result)
    colour = {p.body: COLOURS[i % len(COLOURS)] for i, p in enumerate(moving)}
    lo, hi = _bounds([rest], layout.size * fraction)
    for i, m in enumerate(chosen):
        ax = fig.add_subplot(nrow, ncol, i + 1, projection="3d")
        values = shape_values(result, m)
        peak = deformed_points(layout, values, mode_amplitude(layout, values, fraction))
        for p in layout.places:
            style = dict(color="0.7", lw=0.8) if p in moving else dict(color="0.4", lw=1.0, ls="--")
            ax.plot(*(1e3 * rest[p.body].T), **style)
        for p in moving:
            ax.plot(*(1e3 * peak[p.body].T), color=colour[p.body], lw=1.4)
        ax.set_xlim(1e3 * lo[0], 1e3 * hi[0])
        ax.set_ylim(1e3 * lo[1], 1e3 * hi[1])
        ax.set_zlim(1e3 * lo[2], 1e3 * hi[2])
        ax.set_box_aspect(tuple(hi - lo), zoom=1.35)
        ax.view_init(elev=30, azim=-60)
        ax.set_title(_title(result, m).replace(" — ", "\n", 1), fontsize=9)
        ax.grid(False)
        for name, axis in zip("xyz", (ax.xaxis, ax.yaxis, ax.zaxis), strict=True):
            axis.set_ticks([])
            axis.set_pane_color((1.0, 1.0, 1.0, 0.0))
            axis.set_label_text(name, fontsize=8, color="0.35")
            axis.labelpad = -12
    handles = [Line2D([], [], color=colour[p.body], label=p.label) for p in moving]
    handles.append(Line2D([], [], color="0.7", label="at rest"))
    handles += [
        Line2D([], [], color="0.4", ls="--", label=p.label)
        for p in layout.places
        if p not in moving
    ]
    fig.legend(handles=handles, loc="outside lower center", ncol=min(len(handles), 5), fontsize=8)
    fig.suptitle(
        f"{layout.name}: mode shapes\nlargest motion drawn as {100 * fraction:.0f} % of the "
        f"drive's size ({1e3 * layout.size:.3g} mm)",
        fontsize=10,
    )
    return fig


def _bounds(
    states: Sequence[dict[str, NDArray[np.float64]]], margin: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    pts = np.vstack([p for s in states for p in s.values()])
    return np.nanmin(pts, axis=0) - margin, np.nanmax(pts, axis=0) + margin


class _Grid:
    """Integer coordinates for plotly: a point ``p`` (m) is sent as ``round((p - origin)
    / unit)`` in int16 (two bytes a value as a typed array, a quarter of the text of a
    rounded float); the axes are labelled back in mm."""

    STEPS = 30000

    def __init__(self, lo: NDArray[np.float64], hi: NDArray[np.float64]) -> None:
        self.lo, self.hi = lo, hi
        self.origin = 0.5 * (lo + hi)
        self.unit = float(np.max(hi - lo)) / (2 * self.STEPS)

    def xyz(self, pts: NDArray[np.float64]) -> dict[str, NDArray[np.int16]]:
        q = np.rint((pts - self.origin) / self.unit).astype(np.int16)
        return {"x": q[:, 0], "y": q[:, 1], "z": q[:, 2]}

    def gapped(self, parts: Sequence[NDArray[np.float64]]) -> dict[str, NDArray[np.float32]]:
        """Several lines in one trace, NaN between them (float32)."""
        gap = np.full((1, 3), np.nan)
        pts = np.vstack([np.vstack([p, gap]) for p in parts])
        q = np.rint((pts - self.origin) / self.unit).astype(np.float32)
        return {"x": q[:, 0], "y": q[:, 1], "z": q[:, 2]}

    def axis(self, k: int, title: str) -> dict[str, Any]:
        """A scene axis over the grid's range, ticked at round mm values."""
        lo_mm, hi_mm = 1e3 * self.lo[k], 1e3 * self.hi[k]
        raw = (hi_mm - lo_mm) / 5
        mag = 10 ** math.floor(math.log10(raw))
        step = next(m * mag for m in (1, 2, 2.5, 5, 10) if m * mag >= raw)
        ticks = np.arange(math.ceil(lo_mm / step), math.floor(hi_mm / step) + 1) * step
        to_grid = (ticks / 1e3 - self.origin[k]) / self.unit
        ends = [
            (float(self.lo[k]) - self.origin[k]) / self.unit,
            (float(self.hi[k]) - self.origin[k]) / self.unit,
        ]
        return dict(
            title=title,
            range=[float(e) for e in ends],
            tickvals=[round(float(v), 1) for v in to_grid],
            ticktext=[f"{t:g}" for t in ticks],
            showbackground=False,
            gridcolor="#e5e5e5",
            zeroline=False,
        )


def plotly_drive_shapes(
    result: ModalResult,
    layout: DriveLayout,
    modes: Sequence[int] | None = None,
    *,
    fraction: float = FRACTION,
    limit: int | None = 12,
    cycles: int = 3,
) -> Any:
    """Interactive 3-D figure (plotly) of the mode shapes as the drive moving: a menu
    picks the mode, play animates it over ``cycles`` periods
    (:data:`FRAMES_PER_CYCLE` frames each), grey is the drive at rest.

    Parameters
    ----------
    result : ModalResult
    layout : DriveLayout
    modes : sequence of int, optional
        1-based modes; by default the elastic ones, the first ``limit`` of them.
    fraction : float
        Largest drawn displacement over the drive's size, in (0, 0.5].
    limit : int or None
        At most this many modes by default (the report's size).
    cycles : int
        Periods played by the play button.

    Returns
    -------
    plotly.graph_objects.Figure
        Trace 0 the moving bodies at rest, then one trace per fixed member (drawn
        still); from ``layout.meta["first_mode_trace"]`` one trace per (mode, moving
        body), the first mode's visible, at the mode's peak; frames ``s0`` .. ``s6``
        hold every mode at ``sin(w t)`` = ``layout.meta["frame_levels"]`` (-1 .. 1),
        shared by the play sequence. Coordinates are integers on a grid
        (``layout.meta["grid"]``: origin
        and unit in m), the axes ticked in mm.
    """
    import plotly.graph_objects as go

    _check_fraction(fraction)
    chosen = _chosen(result, modes, limit)
    moving = _moving(layout, result)
    colour = {p.body: COLOURS[i % len(COLOURS)] for i, p in enumerate(moving)}
    rest = deformed_points(layout, {}, 0.0)
    phases = 2 * math.pi * np.arange(FRAMES_PER_CYCLE) / FRAMES_PER_CYCLE
    levels = sorted({round(math.sin(p), 9) for p in phases})
    amp = []
    for m in chosen:
        values = shape_values(result, m)
        amp.append((values, mode_amplitude(layout, values, fraction)))
    # states[level][mode][body]
    states = [[deformed_points(layout, v, a * s) for v, a in amp] for s in levels]
    top = levels.index(1.0)
    lo, hi = _bounds(
        [st for level in (states[0], states[top]) for st in level] + [rest], 0.04 * layout.size
    )
    grid = _Grid(lo, hi)
    fixed = [p for p in layout.places if p not in moving]
    fig = go.Figure()
    fig.add_trace(
        go.Scatter3d(
            **grid.gapped([rest[p.body] for p in moving]),
            mode="lines",
            line=dict(color="#b8b8b8", width=2),
            name="at rest",
            hoverinfo="skip",
        )
    )
    for p in fixed:  # members without DOFs (the KHV ring): still, named
        fig.add_trace(
            go.Scatter3d(
                **grid.xyz(rest[p.body]),
                mode="lines",
                line=dict(color="#6b6b6b", width=3, dash="dash"),
                name=p.label,
                hoverinfo="name",
            )
        )
    first = len(fig.data)
    for j in range(len(chosen)):
        for p in moving:
            fig.add_trace(
                go.Scatter3d(
                    **grid.xyz(states[top][j][p.body]),
                    mode="lines",
                    name=p.label,
                    line=dict(color=colour[p.body], width=5),
                    visible=j == 0,
                    legendgroup=p.body,
                    hoverinfo="name",
                )
            )
    traces = list(range(first, len(fig.data)))
    fig.frames = [
        go.Frame(
            name=f"s{k}",
            traces=traces,
            data=[
                go.Scatter3d(**grid.xyz(states[k][j][p.body]))
                for j in range(len(chosen))
                for p in moving
            ],
        )
        for k in range(len(levels))
    ]
    names = [f"s{levels.index(round(math.sin(p), 9))}" for p in phases]
    sequence = names * cycles + names[: FRAMES_PER_CYCLE // 4 + 1]  # ends at the peak
    span = hi - lo
    scale_note = (
        f"largest motion drawn as {100 * fraction:.0f} % of the drive's size "
        f"({1e3 * layout.size:.3g} mm)"
    )
    titles = [f"{_title(result, m)}<br><sub>{scale_note}</sub>" for m in chosen]
    per_mode = len(moving)
    menu = [
        dict(
            label=_title(result, m),
            method="update",
            args=[
                {"visible": [True] * first + [k // per_mode == j for k in range(len(traces))]},
                {"title.text": titles[j]},
            ],
        )
        for j, m in enumerate(chosen)
    ]
    play = dict(
        type="buttons",
        direction="left",
        x=0.0,
        xanchor="left",
        y=0.0,
        yanchor="bottom",
        buttons=[
            dict(
                label="▶ play",
                method="animate",
                args=[
                    sequence,
                    dict(
                        frame=dict(duration=70, redraw=True),
                        mode="immediate",
                        transition=dict(duration=0),
                        fromcurrent=False,
                    ),
                ],
            ),
            dict(
                label="❚❚ pause",
                method="animate",
                args=[[None], dict(frame=dict(duration=0, redraw=False), mode="immediate")],
            ),
        ],
    )
    fig.update_layout(
        title=dict(text=titles[0], x=0.5, y=0.96, font=dict(size=13)),
        updatemenus=[
            dict(
                buttons=menu,
                direction="down",
                x=0.0,
                xanchor="left",
                y=1.0,
                yanchor="top",
                active=0,
                showactive=True,
            ),
            play,
        ],
        scene=dict(
            xaxis=grid.axis(0, "x (mm)"),
            yaxis=grid.axis(1, "y (mm)"),
            zaxis=grid.axis(2, "z (mm)"),
            aspectmode="manual",
            aspectratio=dict(zip("xyz", (float(v) for v in span / span.max()), strict=True)),
            camera=dict(eye=dict(x=1.0, y=-1.3, z=0.7)),
        ),
        height=640,
        margin=dict(t=70, l=10, r=10, b=10),
        legend=dict(x=1.0, xanchor="right", y=0.9),
        meta=dict(
            frame_levels=levels,
            first_mode_trace=first,
            modes=chosen,
            amplitude=[a for _, a in amp],
            grid=dict(origin=[float(v) for v in grid.origin], unit=grid.unit),
        ),
        template="none",  # no template: its 6.5 kB per figure; colours set here
        font=dict(family="Open Sans, Arial, sans-serif", color="#2a3f5f"),
    )
    return fig
