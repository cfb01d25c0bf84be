"""Renders of the vibration modes of solid bodies (gear bodies, issue 14).

The deformed body is drawn from its boundary triangles (:func:`~reducerlab.fe.vtu.
boundary_faces`) as one ``Poly3DCollection``, each face coloured by the displacement
magnitude (normalised to the largest in the mode) and shaded by a light from the
viewer's upper left; the undeformed body is a faint outline of its feature edges (where
the surface bends by more than 40 deg). The projection is orthographic and the faces
turned away from the viewer are left out (they are hidden on a closed surface), which
halves the polygons matplotlib has to sort by depth: a body of ~50 000 boundary
triangles draws in a few seconds. The displacement is scaled so that its largest value
is 8 % of the body's size unless a scale is given (mode shapes have no physical
amplitude).

Figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot, Agg-safe); the
surfaces are rasterised in vector output (PDF, SVG) so that the files stay small.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import ReducerlabError
from ..fe.vtu import finite_array

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "AZIM",
    "DEFORMATION",
    "ELEV",
    "body_surface",
    "feature_edges",
    "plot_body_mode",
    "plot_body_modes_grid",
    "view_elevation",
]

Array = NDArray[np.float64]

#: Largest drawn displacement as a fraction of the body's size (its bounding box's
#: largest side) when no scale is given.
DEFORMATION = 0.08
#: View (deg): elevation (its sign by :func:`view_elevation`) and azimuth.
ELEV, AZIM = 30.0, -60.0
#: Surface bend (deg) above which an edge is drawn in the undeformed outline.
FEATURE_ANGLE = 40.0
CMAP = "viridis"
#: Fraction of its cell's width or height that a render spans.
FILL = 0.92
CBAR_LABEL = "|u| (normalised)"
#: Width (pt) of the face-coloured edges that close the seams between faces.
SEAM = 0.4


def plot_body_mode(
    points: ArrayLike,
    tets_or_faces: ArrayLike,
    displacement: ArrayLike,
    title: str,
    scale: float | None = None,
    *,
    elev: float | None = None,
    azim: float = AZIM,
) -> Figure:
    """One mode shape of a body: the deformed surface coloured by ``|u|``.

    Parameters
    ----------
    points : array_like (n, 3)
        Mesh points (m). Points used by no face or tetrahedron are ignored.
    tets_or_faces : array_like of int (m, 4) or (k, 3)
        Linear tetrahedra (their boundary is drawn; for quadratic ones pass
        ``tets[:, :4]``) or the boundary triangles themselves, consistently oriented as
        :func:`~reducerlab.fe.vtu.boundary_faces` gives them (all turned inward when
        they enclose a negative volume): the faces turned away from the viewer are not
        drawn.
    displacement : array_like (n, 3)
        Displacement of every point (any scale, e.g. a mass-normalised mode shape).
    title : str
        E.g. ``"Gear 1, mode 3: 5466 Hz, folding (n = 2)"``.
    scale : float, optional
        Drawn displacement = ``scale * displacement`` (m per unit of the displacement);
        by default the largest is :data:`DEFORMATION` (8 %) of the body's size.
    elev, azim : float
        View angles (deg), as :meth:`~mpl_toolkits.mplot3d.axes3d.Axes3D.view_init`.
        By default ``elev`` is :data:`ELEV` (30 deg) from the side the body's tooth
        flanks face (:func:`view_elevation`), ``azim`` :data:`AZIM`.

    Returns
    -------
    matplotlib.figure.Figure
        With a colour bar ``|u| (normalised)`` (``|u|`` over its largest value).
    """
    from matplotlib.figure import Figure

    p, faces = body_surface(points, tets_or_faces)
    u = _displacement("displacement", displacement, len(p))
    if not isinstance(title, str):
        raise ReducerlabError(f"title: must be a str, got {title!r}")
    scale = _scale(scale)
    edges = feature_edges(p, faces)
    elev = view_elevation(p, faces) if elev is None else _angle("elev", elev)
    azim = _angle("azim", azim)
    aspect = _aspect(p, faces, elev, azim)
    side, head, foot, bar = 6.0, 0.45, 0.3, 1.0  # inches
    cell = side * aspect
    w, h = side + bar, head + cell + foot
    fig = Figure(figsize=(w, h))
    ax = _axes3d(fig, 0.0, foot + cell / 2, side, cell)
    _, pct = _draw(ax, p, faces, edges, u, scale, elev, azim, aspect)
    _colorbar(fig, side + 0.15, foot + 0.1 * cell, 0.8 * cell)
    fig.suptitle(title, fontsize=10, y=1 - 0.1 / h, va="top")
    note = (
        "undeformed shape (no displacement)"
        if pct == 0
        else f"largest displacement drawn as {pct:.3g} % of the body size; "
        "grey lines: undeformed edges"
    )
    fig.text(0.08 / w, 0.08 / h, note, fontsize=7, color="0.35", ha="left", va="bottom")
    return fig


def mode_set(
    points: ArrayLike,
    tets_or_faces: ArrayLike,
    shapes: ArrayLike,
    frequencies: ArrayLike,
    types: Sequence[str],
) -> tuple[Array, NDArray[np.int64], Array, Array]:
    """A body's modes checked for a render: the boundary surface, the shapes (n, 3,
    modes) at the points and one frequency (Hz) and one type name per mode.

    Returns
    -------
    points, faces, shapes, frequencies
        As :func:`body_surface` gives them, the shapes with a mode axis.
    """
    p, faces = body_surface(points, tets_or_faces)
    s = finite_array("shapes", shapes)
    if s.ndim == 2:
        s = s[:, :, None]
    if s.ndim != 3 or s.shape[:2] != (len(p), 3) or s.shape[2] == 0:
        raise ReducerlabError(
            f"shapes: must have shape ({len(p)}, 3, modes) for {len(p)} points, got "
            f"{np.shape(shapes)}"
        )
    modes = s.shape[2]
    f = finite_array("frequencies", frequencies)
    if f.shape != (modes,):
        raise ReducerlabError(f"frequencies: need one per mode ({modes}), got shape {f.shape}")
    if isinstance(types, str) or not all(isinstance(t, str) for t in types):
        raise ReducerlabError("types: must be a sequence of str, one per mode")
    if len(types) != modes:
        raise ReducerlabError(f"types: need one per mode ({modes}), got {len(types)}")
    return p, faces, s, f


def plot_body_modes_grid(
    points: ArrayLike,
    tets_or_faces: ArrayLike,
    shapes: ArrayLike,
    frequencies: ArrayLike,
    types: Sequence[str],
    title: str,
    *,
    ncols: int = 5,
    elev: float | None = None,
    azim: float = AZIM,
    side: float = 2.8,
) -> Figure:
    """Small renders of many mode shapes of one body, one panel per mode (``ncols``
    across: 2 x 5 for ten modes), for a report.

    Parameters
    ----------
    points, tets_or_faces
        As :func:`plot_body_mode`.
    shapes : array_like (n, 3, modes)
        Mode shapes at the points (any scale; each drawn with its largest displacement
        :data:`DEFORMATION` of the body's size).
    frequencies : array_like (modes,)
        Natural frequencies (Hz).
    types : sequence of str (modes,)
        Mode names (e.g. ``"folding (n = 2)"``), under each panel's frequency.
    title : str
        The figure's title.
    ncols : int
        Panels per row (1..10).
    elev, azim : float
        View angles (deg), by default as :func:`plot_body_mode`.
    side : float
        Width of a panel (in, 1..6): 2.8 for a page, 1.6 for a report's still.
    """
    from matplotlib.figure import Figure

    p, faces, s, f = mode_set(points, tets_or_faces, shapes, frequencies, types)
    modes = s.shape[2]
    if not isinstance(title, str):
        raise ReducerlabError(f"title: must be a str, got {title!r}")
    if isinstance(ncols, bool) or not isinstance(ncols, int) or not 1 <= ncols <= 10:
        raise ReducerlabError(f"ncols: must be an integer in 1..10, got {ncols!r}")
    if isinstance(side, bool) or not isinstance(side, int | float) or not 1.0 <= side <= 6.0:
        raise ReducerlabError(f"side: must be a width in 1..6 in, got {side!r}")
    ncol = min(ncols, modes)
    nrow = math.ceil(modes / ncol)
    edges = feature_edges(p, faces)
    elev = view_elevation(p, faces) if elev is None else _angle("elev", elev)
    azim = _angle("azim", azim)
    aspect = _aspect(p, faces, elev, azim)
    head, label, foot, bar = 0.45, 0.4, 0.1, 0.9  # inches
    cell = side * aspect
    w, h = ncol * side + bar, head + nrow * (label + cell) + foot
    fig = Figure(figsize=(w, h))
    for i in range(modes):
        row, col = divmod(i, ncol)
        top = h - head - row * (label + cell)
        ax = _axes3d(fig, col * side, top - label - cell / 2, side, cell)
        _draw(ax, p, faces, edges, s[:, :, i], None, elev, azim, aspect, lw=0.25)
        fig.text((col + 0.5) * side / w, (top - 0.05) / h, f"mode {i + 1}: {f[i]:.0f} Hz\n"
                 f"{types[i]}", fontsize=8, ha="center", va="top")  # fmt: skip
    body = h - head - foot
    _colorbar(fig, ncol * side + 0.15, foot + 0.2 * body, min(0.6 * body, 3.0))
    fig.suptitle(title, fontsize=10, y=1 - 0.1 / h, va="top")
    return fig


def view_elevation(points: ArrayLike, faces: ArrayLike) -> float:
    """The view elevation (deg) that shows a gear's teeth: :data:`ELEV` from the side
    of ``z`` its tooth flanks face.

    The flanks are the faces whose unit normal has a component of more than 0.3 along
    the circumferential direction about the ``z`` axis; when the mean axial component
    of their normals (area-weighted) is below -0.05 the teeth face ``-z`` (an external
    bevel gear in its frame, apex at the origin below it) and ``-ELEV`` is returned,
    else ``+ELEV`` (also for bodies without such faces).
    """
    p = np.asarray(points, dtype=float)
    f = np.asarray(faces, dtype=np.int64)
    a = p[f[:, 0]]
    n = np.cross(p[f[:, 1]] - a, p[f[:, 2]] - a)
    area = np.linalg.norm(n, axis=1)
    ok = area > 0
    n, area, c = n[ok] / area[ok, None], area[ok], p[f[ok]].mean(axis=1)
    r = np.hypot(c[:, 0], c[:, 1])
    tangential = np.abs(c[:, 0] * n[:, 1] - c[:, 1] * n[:, 0]) / np.maximum(r, 1e-300)
    flank = (tangential > 0.3) & (r > 0)
    if not flank.any():
        return ELEV
    nz = float(np.sum(area[flank] * n[flank, 2]) / np.sum(area[flank]))
    return -ELEV if nz < -0.05 else ELEV


# -- drawing -----------------------------------------------------------------------------


def _axes3d(fig: Figure, x0: float, cy: float, side: float, cell: float) -> Any:
    """A 3-D axes, a square of ``side`` (in) from ``x0`` (in) centred at height ``cy``
    (in), for a render in its middle ``cell`` (in) of height. The square may reach into
    its neighbours' or out of the figure: it has no background, the body is zoomed to
    fit the cell (:func:`_draw`) and ``savefig(bbox_inches="tight")`` sees the cell."""
    from matplotlib.transforms import Bbox, TransformedBbox

    w, h = fig.get_size_inches()
    ax = fig.add_axes((x0 / w, (cy - side / 2) / h, side / w, side / h), projection="3d")
    ax.patch.set_visible(False)
    inches = Bbox.from_extents(x0, cy - cell / 2, x0 + side, cy + cell / 2)
    ax.get_tightbbox = lambda *_a, **_k: TransformedBbox(inches, fig.dpi_scale_trans)
    return ax


def _colorbar(fig: Figure, x0: float, y0: float, height: float) -> Any:
    """The colour bar ``|u| (normalised)``, 0.15 in wide, at ``(x0, y0)`` (in)."""
    import matplotlib as mpl
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    w, h = fig.get_size_inches()
    cax = fig.add_axes((x0 / w, y0 / h, 0.15 / w, height / h))
    mappable = ScalarMappable(norm=Normalize(0.0, 1.0), cmap=mpl.colormaps[CMAP])
    cbar = fig.colorbar(mappable, cax=cax)
    cbar.set_label(CBAR_LABEL, fontsize=8)
    cbar.ax.tick_params(labelsize=7)
    return cbar


def _aspect(p: Array, faces: NDArray[np.int64], elev: float, azim: float) -> float:
    """Height over width (0.4 .. 1) of the body's view, with room for the deformation:
    the cell each render is fitted into."""
    eye, right = _eye(elev, azim)
    q = p[np.unique(faces)]
    size = float(np.max(np.ptp(q, axis=0)))
    x, y = q @ right, q @ np.cross(eye, right)
    margin = 2 * DEFORMATION * size
    return float(np.clip((np.ptp(y) + margin) / max(np.ptp(x) + margin, 1e-300), 0.4, 1.0))


def _eye(elev: float, azim: float) -> tuple[Array, Array]:
    """Unit vectors towards the viewer and to the screen's right (orthographic view)."""
    e, a = math.radians(elev), math.radians(azim)
    eye = np.array([math.cos(e) * math.cos(a), math.cos(e) * math.sin(a), math.sin(e)])
    right = np.array([-math.sin(a), math.cos(a), 0.0])
    return eye, right


def _normals(p: Array, faces: NDArray[np.int64]) -> Array:
    a = p[faces[:, 0]]
    n = np.cross(p[faces[:, 1]] - a, p[faces[:, 2]] - a)
    return n / np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)


def _draw(
    ax: Any,
    p: Array,
    faces: NDArray[np.int64],
    edges: tuple[NDArray[np.int64], NDArray[np.int64]],
    u: Array,
    scale: float | None,
    elev: float,
    azim: float,
    aspect: float,
    lw: float = 0.35,
) -> tuple[float, float]:
    """Draw one deformed body on ``ax``, fitted into the middle ``aspect`` (height over
    width) of its square; returns the scale used and the largest drawn displacement in
    percent of the body's size."""
    import matplotlib as mpl
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    verts = np.unique(faces)
    lo, hi = p[verts].min(axis=0), p[verts].max(axis=0)
    size = float(np.max(hi - lo))
    mag = np.linalg.norm(u, axis=1)
    umax = float(mag[verts].max())
    if scale is None:
        scale = DEFORMATION * size / umax if umax > 0 and size > 0 else 0.0
    pct = 100.0 * scale * umax / size if size > 0 else 0.0
    q = (p + scale * u) * 1e3  # mm
    eye, right = _eye(elev, azim)
    n = _normals(q, faces)
    front = n @ eye > 0.0
    if not np.any(front):  # e.g. a single face seen from behind: draw all
        front[:] = True
    fr = faces[front]
    light = eye + 0.6 * np.cross(eye, right) - 0.5 * right  # from the upper left
    light /= np.linalg.norm(light)
    k = 0.42 + 0.58 * np.clip(n[front] @ light, 0.0, 1.0)
    level = mag[fr].mean(axis=1) / max(umax, 1e-300)
    if umax > 0:
        rgb = mpl.colormaps[CMAP](level)[:, :3] * k[:, None]
    else:  # no displacement: the body in light grey
        rgb = np.full((len(fr), 3), 0.8) * k[:, None]
    poly = Poly3DCollection(q[fr], facecolors=rgb, edgecolors=rgb, linewidths=SEAM, zorder=1)
    poly.set_rasterized(True)
    ax.add_collection3d(poly)
    # the undeformed outline: its edges on the side facing the viewer, drawn under the
    # deformed surface (seen where the body has moved away from them)
    toward = _normals(p, faces) @ eye > 0.0
    seen = edges[0][toward[edges[1]].any(axis=1)]
    ax.computed_zorder = False
    if len(seen):
        ax.add_collection3d(
            Line3DCollection(p[seen] * 1e3, colors=[(0.2, 0.2, 0.2, 0.5)], linewidths=lw, zorder=0)
        )
    box = np.concatenate([p[verts] * 1e3, q[verts]])
    blo, bhi = box.min(axis=0), box.max(axis=0)
    mid, half = 0.5 * (blo + bhi), 0.5 * np.maximum(bhi - blo, 1e-3 * max(size * 1e3, 1e-12))
    ax.set_xlim(mid[0] - half[0], mid[0] + half[0])
    ax.set_ylim(mid[1] - half[1], mid[1] + half[1])
    ax.set_zlim(mid[2] - half[2], mid[2] + half[2])
    ax.set_proj_type("ortho")
    # zoom so that the body's view fills its cell (matplotlib fits the box's diagonal:
    # the box's norm is 1.906 zoom, the axes span 1.85 such units, orthographic)
    rel = box - mid
    width = 2 * float(np.max(np.abs(rel @ right)))
    height = 2 * float(np.max(np.abs(rel @ np.cross(right, eye))))
    zoom = FILL * 1.85 / 1.906 * 2 * float(np.linalg.norm(half)) / max(width, height / aspect)
    ax.set_box_aspect(tuple(half), zoom=zoom)
    ax.view_init(elev=elev, azim=azim)
    ax.set_axis_off()
    return scale, pct


def feature_edges(
    p: Array, faces: NDArray[np.int64]
) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Feature edges: edges (e, 2) of the surface where it bends by more than
    :data:`FEATURE_ANGLE` and its open edges (used by one face), with the two faces
    (e, 2) at each (the same face twice at an open edge)."""
    e = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    owner = np.tile(np.arange(len(faces)), 3)
    key = e[:, 0] * (int(faces.max()) + 1) + e[:, 1]
    order = np.argsort(key, kind="stable")
    key, e, owner = key[order], e[order], owner[order]
    start = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    count = np.diff(np.r_[start, len(key)])
    n = _normals(p, faces)
    one = start[count == 1]
    two = start[count >= 2]  # (a non-manifold edge: its first two faces)
    bend = np.einsum("ij,ij->i", n[owner[two]], n[owner[two + 1]])
    two = two[(bend < math.cos(math.radians(FEATURE_ANGLE))) | (count[count >= 2] > 2)]
    edges = np.concatenate([e[one], e[two]])
    at = np.concatenate([np.c_[owner[one], owner[one]], np.c_[owner[two], owner[two + 1]]])
    return edges, at


# -- input checks ------------------------------------------------------------------------


def _displacement(name: str, value: ArrayLike, n: int) -> Array:
    u = finite_array(name, value)
    if u.shape != (n, 3):
        raise ReducerlabError(f"{name}: must have shape ({n}, 3) for {n} points, got {u.shape}")
    return u


def _angle(name: str, value: float) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | np.floating | np.integer):
        raise ReducerlabError(f"{name}: must be a number (deg), got {value!r}")
    if not math.isfinite(value):
        raise ReducerlabError(f"{name}: must be finite, got {value!r}")
    return float(value)


def _scale(scale: float | None) -> float | None:
    if scale is None:
        return None
    if isinstance(scale, bool) or not isinstance(scale, int | float | np.floating | np.integer):
        raise ReducerlabError(f"scale: must be a number, got {scale!r}")
    if not (math.isfinite(scale) and scale >= 0):
        raise ReducerlabError(f"scale: must be finite and >= 0, got {scale!r}")
    return float(scale)


def body_surface(points: ArrayLike, tets_or_faces: ArrayLike) -> tuple[Array, NDArray[np.int64]]:
    """The checked points (m) and the outward boundary triangles of a body given by
    its linear tetrahedra (m, 4) or its boundary triangles (k, 3), as
    :func:`plot_body_mode` takes them."""
    from ..fe.vtu import boundary_faces, checked_points, checked_tets

    p = checked_points(points)
    a = np.asarray(tets_or_faces)
    if a.ndim == 2 and a.shape[1] == 4:
        faces = boundary_faces(checked_tets(a, len(p), "tets_or_faces"), p)
    elif a.ndim == 2 and a.shape[1] == 3:
        if a.dtype == object or not np.issubdtype(a.dtype, np.integer):
            raise ReducerlabError("tets_or_faces: must be an array of integer vertex indices")
        faces = a.astype(np.int64)
        if faces.size and (faces.min() < 0 or faces.max() >= len(p)):
            raise ReducerlabError(
                f"tets_or_faces: vertex indices must be in 0..{len(p) - 1} for {len(p)} points"
            )
    else:
        raise ReducerlabError(
            "tets_or_faces: must have shape (m, 4) (tetrahedra; pass tets[:, :4] for "
            f"quadratic ones) or (k, 3) (boundary triangles), got {a.shape}"
        )
        # a closed surface oriented inward (negative enclosed volume): turn it outward
        c = p[faces].sum(axis=1)
        a0 = p[faces[:, 0]]
        n = np.cross(p[faces[:, 1]] - a0, p[faces[:, 2]] - a0)
        if np.einsum("ij,ij->", c, n) < 0:
            faces = faces[:, ::-1].copy()
    if len(faces) == 0:
        raise ReducerlabError("tets_or_faces: no faces to draw")
    return p, faces
