"""Interactive 3-D renders of the vibration modes of a solid body (issue 32): the gear
body's surface, deformed by the chosen mode and coloured by its displacement magnitude,
in a plotly figure with one entry per mode in a dropdown.

The surface is the body's boundary (:func:`~reducerlab.plot.body.body_surface`),
decimated by vertex clustering (:func:`decimate_surface`) to a few thousand triangles at
most, each cluster drawn at the mesh point nearest its centre with that point's exact
displacement; coordinates are written in mm to four significant digits, so a report
carries a body's ten modes in a few hundred kB. The undeformed body is a faint outline
of its feature edges (:func:`~reducerlab.plot.body.feature_edges`). As in the
matplotlib renders (:mod:`reducerlab.plot.body`) the largest displacement of each mode
is drawn as :data:`~reducerlab.plot.body.DEFORMATION` (8 %) of the body's size: mode
shapes have no physical amplitude.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError
from ..fe.vtu import finite_array
from .body import (
    AZIM,
    CBAR_LABEL,
    DEFORMATION,
    feature_edges,
    mode_set,
    view_elevation,
)

__all__ = ["MAX_FACES", "decimate_surface", "plotly_body_modes"]

Array = NDArray[np.float64]

#: Triangles of a render at most (after decimation).
MAX_FACES = 1500
#: Largest side of the drawn body's box in scene units, and the camera's distance.
ZOOM, EYE = 1.0, 1.4
#: Significant digits of the coordinates written into the figure.
DIGITS = 4


def decimate_surface(
    points: ArrayLike, faces: ArrayLike, max_faces: int = MAX_FACES
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """A coarser version of a closed triangulated surface by quadric edge collapses.

    Garland and Heckbert's quadric error metric with half-edge collapses: the edge
    whose collapse onto one of its two ends moves the surface least (the summed squared
    distances to the planes of the faces around the removed end, area weighted) goes
    first, until at most ``max_faces`` triangles are left; a collapse that would turn a
    triangle over is not made. The points kept are points of the surface, so a field
    given at them (a mode shape) is exact there.

    Parameters
    ----------
    points : array_like (n, 3)
        Points (any length unit).
    faces : array_like of int (k, 3)
        Triangles (indices into ``points``), consistently oriented.
    max_faces : int
        Largest number of triangles of the result (>= 4).

    Returns
    -------
    vertices : ndarray of int (v,)
        Indices into ``points`` of the points kept.
    triangles : ndarray of int (t, 3)
        Triangles as indices into ``vertices``, oriented as the given ones; the
        surface itself when it has no more than ``max_faces`` triangles. ``t`` may
        exceed ``max_faces`` when no collapse is left that keeps every triangle's side.
    """
    p = finite_array("points", points)
    f = np.asarray(faces, dtype=np.int64)
    if isinstance(max_faces, bool) or not isinstance(max_faces, int) or max_faces < 4:
        raise ReducerlabError(f"max_faces: must be an integer >= 4, got {max_faces!r}")
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0:
        raise ReducerlabError(f"faces: must have shape (k, 3) with k >= 1, got {f.shape}")
    if f.min() < 0 or f.max() >= len(p):
        raise ReducerlabError(f"faces: indices must be in 0..{len(p) - 1}")
    if len(f) > max_faces:
        f = _collapse(p, f.copy(), max_faces)
    used = np.unique(f)
    return used, np.searchsorted(used, f)


def _collapse(p: Array, f: NDArray[np.int64], target: int) -> NDArray[np.int64]:
    """The triangles left after quadric half-edge collapses down to ``target``."""
    import heapq

    a = p[f[:, 0]]
    n = np.cross(p[f[:, 1]] - a, p[f[:, 2]] - a)
    area = np.linalg.norm(n, axis=1)
    unit = n / np.maximum(area, 1e-300)[:, None]
    plane = np.c_[unit, -np.einsum("ij,ij->i", unit, a)]  # (k, 4)
    kq = np.einsum("i,ij,ik->ijk", area, plane, plane)  # area-weighted quadrics
    Q = np.zeros((len(p), 4, 4))
    for c in range(3):
        np.add.at(Q, f[:, c], kq)
    hom = np.c_[p, np.ones(len(p))]
    around: list[set[int]] = [set() for _ in range(len(p))]
    for i, tri in enumerate(f.tolist()):
        for v in tri:
            around[v].add(i)
    alive = np.ones(len(f), dtype=bool)
    gone = np.zeros(len(p), dtype=bool)
    version = np.zeros(len(p), dtype=np.int64)
    heap: list[tuple[float, int, int, int, int]] = []

    def push(u: int, w: int) -> None:
        q = Q[u] + Q[w]
        cu, cw = float(hom[w] @ q @ hom[w]), float(hom[u] @ q @ hom[u])  # remove u; w
        if cu <= cw:  # remove u, keep w
            heapq.heappush(heap, (cu, u, w, int(version[u]), int(version[w])))
        else:
            heapq.heappush(heap, (cw, w, u, int(version[w]), int(version[u])))

    edges = np.unique(np.sort(np.r_[f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]], axis=1), axis=0)
    q = Q[edges[:, 0]] + Q[edges[:, 1]]
    keep1 = np.einsum("ei,eij,ej->e", hom[edges[:, 1]], q, hom[edges[:, 1]])  # remove 0
    keep0 = np.einsum("ei,eij,ej->e", hom[edges[:, 0]], q, hom[edges[:, 0]])  # remove 1
    for (u, w), c1, c0 in zip(edges.tolist(), keep1.tolist(), keep0.tolist(), strict=True):
        heap.append((c1, u, w, 0, 0) if c1 <= c0 else (c0, w, u, 0, 0))
    heapq.heapify(heap)
    count = len(f)
    tri = f.tolist()  # python lists in the loop: a collapse touches a few triangles
    pts = p.tolist()
    nrm = n.tolist()
    while count > target and heap:
        _, u, w, vu, vw = heapq.heappop(heap)
        if gone[u] or gone[w] or version[u] != vu or version[w] != vw:
            continue
        shared = [i for i in around[u] if w in tri[i]]
        if not shared:
            continue
        moved = [i for i in around[u] if w not in tri[i]]
        # the link condition (the surface stays a manifold): the common neighbours of
        # u and w are the third corners of the triangles on their edge
        third = {v for i in shared for v in tri[i]} - {u, w}
        if _neighbours(tri, around, u) & _neighbours(tri, around, w) != third:
            continue
        if any(_turns(pts, tri[i], u, w, nrm[i]) for i in moved):
            continue
        for i in shared:
            alive[i] = False
            count -= 1
            for v in tri[i]:
                around[v].discard(i)
        for i in moved:
            tri[i] = [w if v == u else v for v in tri[i]]
            around[w].add(i)
        around[u].clear()
        gone[u] = True
        Q[w] += Q[u]
        # only the costs of w's edges change (its quadric; w itself stays put)
        version[w] += 1
        for x in _neighbours(tri, around, w):
            push(w, x)
    return np.asarray(tri, dtype=np.int64).reshape(-1, 3)[alive]


def _neighbours(tri: list[list[int]], around: list[set[int]], v: int) -> set[int]:
    """The vertices that share a triangle with ``v``."""
    return {x for i in around[v] for x in tri[i]} - {v}


def _turns(pts: list[list[float]], tri: list[int], u: int, w: int, normal: list[float]) -> bool:
    """Whether triangle ``tri`` with its corner ``u`` moved to ``w`` faces against (or
    across) its original ``normal`` or collapses to a line."""
    a, b, c = (pts[w if v == u else v] for v in tri)
    e = (b[0] - a[0], b[1] - a[1], b[2] - a[2])
    g = (c[0] - a[0], c[1] - a[1], c[2] - a[2])
    m = (e[1] * g[2] - e[2] * g[1], e[2] * g[0] - e[0] * g[2], e[0] * g[1] - e[1] * g[0])
    return m[0] * normal[0] + m[1] * normal[1] + m[2] * normal[2] <= 0.0


def _rounded(x: Array, size: float) -> list[float]:
    """``x`` to :data:`DIGITS` significant digits of ``size`` (plain floats for JSON)."""
    dec = max(0, DIGITS - 1 - math.floor(math.log10(size))) if size > 0 else DIGITS
    return np.round(np.asarray(x, dtype=float), dec).tolist()


def plotly_body_modes(
    points: ArrayLike,
    tets_or_faces: ArrayLike,
    shapes: ArrayLike,
    frequencies: ArrayLike,
    types: Sequence[str],
    title: str,
    *,
    max_faces: int = MAX_FACES,
    elev: float | None = None,
    azim: float = AZIM,
) -> Any:
    """The mode shapes of a body as one interactive 3-D render, a dropdown choosing the
    mode.

    Parameters
    ----------
    points : array_like (n, 3)
        Mesh points (m).
    tets_or_faces : array_like of int (m, 4) or (k, 3)
        Linear tetrahedra or boundary triangles, as
        :func:`~reducerlab.plot.body.plot_body_mode` takes them.
    shapes : array_like (n, 3, modes)
        Mode shapes at the points (any scale).
    frequencies : array_like (modes,)
        Natural frequencies (Hz).
    types : sequence of str (modes,)
        Mode names (e.g. ``"bending (n = 2)"``).
    title : str
        The figure's title; the chosen mode is added to it.
    max_faces : int
        Triangles drawn at most (:func:`decimate_surface`).
    elev, azim : float
        View angles (deg) of the initial camera, as the matplotlib renders.

    Returns
    -------
    plotly.graph_objects.Figure
        Trace 0 a ``Mesh3d`` of the deformed surface (mm) whose ``intensity`` is the
        displacement magnitude over its largest value at each drawn point (colour bar
        ``|u| (normalised)``), trace 1 the undeformed feature edges (faint lines);
        ``layout.updatemenus[0]`` has one button per mode (label ``"mode m: f Hz,
        type"``) that puts that mode's surface and intensity into trace 0.
    """
    import plotly.graph_objects as go

    p, faces, s, f = mode_set(points, tets_or_faces, shapes, frequencies, types)
    modes = s.shape[2]
    if not isinstance(title, str):
        raise ReducerlabError(f"title: must be a str, got {title!r}")
    elev = view_elevation(p, faces) if elev is None else float(elev)
    verts, tris = decimate_surface(p, faces, max_faces)
    x0 = p[verts]
    on = np.unique(faces)
    size = float(np.max(np.ptp(p[on], axis=0)))
    size_mm = 1e3 * size
    labels, deformed = [], []
    for m in range(modes):
        u = s[verts, :, m]
        mag = float(np.linalg.norm(s[on, :, m], axis=1).max())
        scale = DEFORMATION * size / mag if mag > 0 and size > 0 else 0.0
        q = 1e3 * (x0 + scale * u)
        level = np.linalg.norm(u, axis=1) / mag if mag > 0 else np.zeros(len(verts))
        deformed.append(
            {
                "x": [_rounded(q[:, 0], size_mm)],
                "y": [_rounded(q[:, 1], size_mm)],
                "z": [_rounded(q[:, 2], size_mm)],
                "intensity": [np.round(level, 2).tolist()],  # 1 % of the colour scale
            }
        )
        labels.append(f"mode {m + 1}: {f[m]:.0f} Hz, {types[m]}")
    note = (
        f"largest displacement drawn as {100 * DEFORMATION:.0f} % of the body size "
        f"({DEFORMATION * size_mm:.3g} mm); grey lines: undeformed edges"
    )
    first = deformed[0]
    mesh = go.Mesh3d(
        x=first["x"][0], y=first["y"][0], z=first["z"][0],
        i=tris[:, 0].tolist(), j=tris[:, 1].tolist(), k=tris[:, 2].tolist(),
        intensity=first["intensity"][0], intensitymode="vertex", colorscale="Viridis",
        cmin=0.0, cmax=1.0, flatshading=True, name="deformed",
        colorbar={"title": {"text": CBAR_LABEL, "side": "right"}, "len": 0.7},
        lighting={"ambient": 0.55, "diffuse": 0.6, "specular": 0.1, "roughness": 0.9},
        hovertemplate="|u| / |u|max = %{intensity:.2f}<extra></extra>",
    )  # fmt: skip
    edges, _ = feature_edges(x0, tris)  # of the decimated surface: a third of the bytes
    seg = np.full((len(edges), 3, 3), np.nan)
    seg[:, :2] = 1e3 * x0[edges]
    seg = seg.reshape(-1, 3)
    outline = go.Scatter3d(
        x=_rounded(seg[:, 0], size_mm), y=_rounded(seg[:, 1], size_mm),
        z=_rounded(seg[:, 2], size_mm), mode="lines", name="undeformed",
        line={"color": "rgba(60,60,60,0.3)", "width": 1}, hoverinfo="skip", showlegend=False,
    )  # fmt: skip
    every = np.concatenate([1e3 * x0] + [np.c_[d["x"][0], d["y"][0], d["z"][0]] for d in deformed])
    box = np.maximum(np.ptp(every, axis=0), 1e-9)
    e, a = math.radians(elev), math.radians(azim)
    eye = EYE * np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    buttons = [
        {
            "label": labels[m],
            "method": "update",
            "args": [
                deformed[m],
                {"title.text": f"{title}<br><sub>{labels[m]}; {note}</sub>"},
                [0],
            ],
        }
        for m in range(modes)
    ]
    hidden = {"visible": False}
    fig = go.Figure([mesh, outline])
    menu = {"buttons": buttons, "direction": "down", "x": 0.0, "xanchor": "left", "y": 1.0,
            "yanchor": "top", "showactive": True, "active": 0}  # fmt: skip
    scene = {
        "xaxis": hidden, "yaxis": hidden, "zaxis": hidden, "aspectmode": "manual",
        "aspectratio": dict(zip("xyz", (ZOOM * box / box.max()).tolist(), strict=True)),
        "camera": {"eye": dict(zip("xyz", eye.tolist(), strict=True))},
    }  # fmt: skip
    fig.update_layout(
        title={"text": f"{title}<br><sub>{labels[0]}; {note}</sub>", "font": {"size": 14}},
        scene=scene,
        updatemenus=[menu],
        margin={"l": 0, "r": 0, "t": 70, "b": 0},
        height=520,
        template="plotly_white",
    )
    return fig
