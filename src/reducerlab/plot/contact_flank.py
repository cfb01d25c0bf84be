"""The developed tooth flank of a loaded tooth contact result, and the bearing pattern
drawn on it (issue 32).

The external gear's *developed* flank: the contact cells of every tooth pair (all on the
same flank, turned by whole pitches) are placed by their flank parameters ``u``
(profile, root -> tip, vertical) and ``v`` (face, toe -> heel, horizontal), converted to
arc lengths (mm) measured from the cell points ``x, y, z``: within one tooth pair at one
position the cells are the flank turned rigidly, so the distance between neighbouring
cells is the arc length between their parameters. (A result without usable points falls
back to the bare parameters.) The flank parameters span ``[0, 1]`` over the flank, from
its root end (the root form circle of a spur gear) to the tip and from toe to heel, so
the ends of the arc lengths, extrapolated from the nearest measured spacings, give the
tooth's outline on the developed flank.

Figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot); the plotly
figure is built lazily for the report.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes

    from ..analysis.contact import ContactResult

__all__ = [
    "Flank",
    "angle_deg",
    "contact_data",
    "developed_flank",
    "flank_pattern",
    "frame_flank",
    "gear_a_name",
    "loaded_cells",
    "outline_cells",
    "peak_position",
    "pressure_mpa",
]

Array = NDArray[np.float64]


def contact_data(result: ContactResult | xr.Dataset) -> xr.Dataset:
    """The dataset of a contact result (or the dataset itself)."""
    return getattr(result, "data", result)


# ------------------------------------------------------------------ developed flank


@dataclass(frozen=True)
class Flank:
    """The cells of a result on the developed flank of the external gear.

    ``iu``, ``iv``: each cell's row (profile) and column (face) in a grid whose centres
    ``cu``, ``cv`` (mm, or bare parameters when ``mm`` is false) are the distinct
    parameter values, with empty rows or columns inserted where the values skip a
    cell; ``eu``, ``ev`` are that grid's cell edges.
    """

    iu: NDArray[np.int64]
    iv: NDArray[np.int64]
    cu: Array
    cv: Array
    eu: Array
    ev: Array
    mm: bool
    #: the distinct parameter values and their developed coordinates (before gaps)
    u_values: Array = field(default_factory=lambda: np.zeros(0))
    u_mm: Array = field(default_factory=lambda: np.zeros(0))
    v_values: Array = field(default_factory=lambda: np.zeros(0))
    v_mm: Array = field(default_factory=lambda: np.zeros(0))

    def at_u(self, u: ArrayLike) -> Array:
        """Developed profile coordinate of flank parameters ``u``, linear beyond the
        computed ones (with the slope of the nearest spacing)."""
        return _along(self.u_values, self.u_mm, u)

    def at_v(self, v: ArrayLike) -> Array:
        """Developed face coordinate of flank parameters ``v`` (as :meth:`at_u`)."""
        return _along(self.v_values, self.v_mm, v)

    @property
    def shape(self) -> tuple[int, int]:
        return len(self.cu), len(self.cv)

    def grid(self, mask: NDArray[np.bool_], values: Array | None = None) -> Array:
        """Grid of ``values`` (NaN where no cell of ``mask``); where several cells of
        ``mask`` share a grid cell (positions or tooth pairs), the largest value."""
        g = np.full(self.shape, np.nan)
        vals = np.ones(int(mask.sum())) if values is None else np.asarray(values)[mask]
        np.fmax.at(g, (self.iu[mask], self.iv[mask]), vals)
        return g

    @property
    def xlabel(self) -> str:
        return "face: toe -> heel" + (" (mm)" if self.mm else " (flank parameter v)")

    @property
    def ylabel(self) -> str:
        return "profile: root -> tip" + (" (mm)" if self.mm else " (flank parameter u)")


def _steps(idx: NDArray[np.int64], n: int, group: NDArray[np.int64], P: Array | None) -> Array:
    """Mean distance (m) between cells of the same ``group`` whose ``idx`` are ``i`` and
    ``i + 1``, for each ``i < n - 1`` (NaN where no such neighbours)."""
    out = np.full(max(n - 1, 0), np.nan)
    if P is None or n < 2:
        return out
    code = group * n + idx
    order = np.argsort(code, kind="stable")
    sc = code[order]
    j = np.searchsorted(sc, code + 1)
    j = np.minimum(j, len(sc) - 1)
    ok = (sc[j] == code + 1) & (idx < n - 1)
    if not ok.any():
        return out
    a, b = np.flatnonzero(ok), order[j[ok]]
    d = np.linalg.norm(P[a] - P[b], axis=1)
    good = np.isfinite(d)
    total = np.bincount(idx[a][good], weights=d[good], minlength=n - 1)
    count = np.bincount(idx[a][good], minlength=n - 1)
    np.divide(total, count, out=out, where=count > 0)
    return out


def _arc(values: Array, steps: Array) -> Array | None:
    """Arc length (mm) at the sorted parameter ``values`` from the measured ``steps``
    (m), the missing ones from the slope ds/dparameter of the measured ones; ``None``
    when nothing was measured."""
    if len(values) == 1:
        return np.zeros(1)
    dp = np.diff(values)
    known = np.isfinite(steps) & (dp > 0)
    if not known.any():
        return None
    mid = 0.5 * (values[:-1] + values[1:])
    slope = np.interp(mid, mid[known], steps[known] / dp[known])
    return 1e3 * np.concatenate([[0.0], np.cumsum(slope * dp)])


def _centres(c: Array, h: float) -> tuple[Array, NDArray[np.int64]]:
    """Grid centres with empty cells inserted where ``c`` skips a cell (a gap over 1.5
    typical spacings), and the index of each ``c`` among them."""
    if len(c) < 2:
        return c.copy(), np.arange(len(c))
    out, where = [c[0]], [0]
    for a, b in itertools.pairwise(c):
        extra = max(0, round((b - a) / h) - 1) if b - a > 1.5 * h else 0
        out.extend(np.linspace(a, b, extra + 2)[1:-1])
        out.append(b)
        where.append(len(out) - 1)
    return np.asarray(out), np.asarray(where)


def _edges(c: Array, h: float) -> Array:
    if len(c) == 1:
        return np.array([c[0] - 0.5 * h, c[0] + 0.5 * h])
    mid = 0.5 * (c[:-1] + c[1:])
    return np.concatenate([[2 * c[0] - mid[0]], mid, [2 * c[-1] - mid[-1]]])


def developed_flank(ds: xr.Dataset) -> Flank:
    """Developed flank coordinates of all cells (see the module docstring)."""
    u = np.asarray(ds["u"].values, float)
    v = np.asarray(ds["v"].values, float)
    U, iu = np.unique(u, return_inverse=True)
    V, iv = np.unique(v, return_inverse=True)
    P = None
    if all(k in ds for k in ("x", "y", "z")):
        P = np.stack([np.asarray(ds[k].values, float) for k in ("x", "y", "z")], axis=1)
    pos = np.asarray(ds["cell_position"].values, np.int64)
    tooth = np.asarray(ds["cell_tooth"].values, np.int64)
    _, it = np.unique(tooth, return_inverse=True)
    pt = pos * (int(it.max()) + 1 if it.size else 1) + it
    su = _arc(U, _steps(iu, len(U), pt * len(V) + iv, P))
    sv = _arc(V, _steps(iv, len(V), pt * len(U) + iu, P))
    mm = su is not None and sv is not None
    if not mm:
        su, sv = U - U[0] if len(U) else U, V - V[0] if len(V) else V
    cell = float(ds.attrs.get("cell_m", 0.0)) * (1e3 if mm else 0.0)
    hs = []
    for s in (su, sv):
        d = np.diff(s)
        hs.append(float(np.median(d[d > 0])) if (d > 0).any() else (cell or 0.05))
    cu, wu = _centres(su, hs[0])
    cv, wv = _centres(sv, hs[1])
    return Flank(wu[iu], wv[iv], cu, cv, _edges(cu, hs[0]), _edges(cv, hs[1]), mm,
                 U, su, V, sv)  # fmt: skip


def _along(x: Array, y: Array, at: ArrayLike) -> Array:
    """``y(at)`` interpolated in the increasing ``x``, extrapolated linearly."""
    a = np.asarray(at, float)
    if len(x) < 2:
        return np.full(a.shape, float(y[0]) if len(y) else 0.0)
    out = np.interp(a, x, y)
    lo, hi = (y[1] - y[0]) / (x[1] - x[0]), (y[-1] - y[-2]) / (x[-1] - x[-2])
    out = np.where(a < x[0], y[0] + lo * (a - x[0]), out)
    return np.where(a > x[-1], y[-1] + hi * (a - x[-1]), out)


def flank_pattern(fl: Flank, loaded: NDArray[np.bool_]) -> Array:
    """The contact pattern: along each profile row, the face from the first to the last
    cell loaded at any position (1; NaN outside). The contact sweeps the face row by
    row over the cycle, so this fills the gaps between the positions computed."""
    hit = np.isfinite(fl.grid(loaded))
    env = np.full(fl.shape, np.nan)
    for r in np.flatnonzero(hit.any(axis=1)):
        cols = np.flatnonzero(hit[r])
        env[r, cols[0] : cols[-1] + 1] = 1.0
    return env


def outline_cells(ax: Axes, fl: Flank, mask: NDArray[np.bool_], **kw: Any) -> None:
    """Outline of the cells of ``mask``: the cell edges between a cell of ``mask`` and
    one outside it (a staircase along the grid)."""
    from matplotlib.collections import LineCollection

    g = np.pad(np.isfinite(fl.grid(mask)), 1)
    if not g.any():
        return
    eu, ev = fl.eu, fl.ev
    segs = []
    # rows: a change between g[r, c] and g[r + 1, c] is the edge eu[r] (padded index)
    r, c = np.nonzero(g[1:, 1:-1] != g[:-1, 1:-1])
    segs += [((ev[j], eu[i]), (ev[j + 1], eu[i])) for i, j in zip(r, c, strict=True)]
    r, c = np.nonzero(g[1:-1, 1:] != g[1:-1, :-1])
    segs += [((ev[j], eu[i]), (ev[j], eu[i + 1])) for i, j in zip(r, c, strict=True)]
    ax.add_collection(LineCollection(segs, **kw))


def frame_flank(ax: Axes, fl: Flank, equal: bool = False) -> None:
    """Limits, labels (mm) and, with ``equal``, the true aspect of a developed-flank panel."""
    ax.set_xlim(fl.ev[0], fl.ev[-1])
    ax.set_ylim(fl.eu[0], fl.eu[-1])
    if fl.mm and equal:
        ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(fl.xlabel, fontsize=8)
    ax.set_ylabel(fl.ylabel, fontsize=8)
    ax.tick_params(labelsize=7)


def peak_position(ds: xr.Dataset) -> int:
    """Position with the highest peak pressure (from the cells if ``peak_pressure``
    is missing or NaN throughout)."""
    pk = np.asarray(ds["peak_pressure"].values, float) if "peak_pressure" in ds else None
    if pk is not None and np.isfinite(pk).any():
        return int(np.nanargmax(pk))
    p = np.asarray(ds["pressure"].values, float)
    if p.size and np.isfinite(p).any():
        return int(ds["cell_position"].values[np.nanargmax(p)])
    return 0


def pressure_mpa(ds: xr.Dataset, name: str) -> Array:
    """Variable ``name`` (Pa) in MPa."""
    return 1e-6 * np.asarray(ds[name].values, float)


def loaded_cells(ds: xr.Dataset) -> NDArray[np.bool_]:
    """The cells that carry load (finite positive force)."""
    f = np.asarray(ds["cell_force"].values, float)
    with np.errstate(invalid="ignore"):
        return np.isfinite(f) & (f > 0)


def angle_deg(ds: xr.Dataset) -> Array:
    """Gear A's rotation at each position (deg)."""
    return np.degrees(np.asarray(ds["angle"].values, float))


def gear_a_name(ds: xr.Dataset) -> str:
    """Gear A's name: the design's (``gear_a``: ``gear2``, ``pinion``, ``planet V``), or
    a nutation pair's external gear for results written before it was recorded."""
    name = str(ds.attrs.get("gear_a", f"gear{2 * int(ds.attrs.get('pair', 1))}"))
    return name.replace("gear", "gear ", 1) if name[4:5].isdigit() else name
