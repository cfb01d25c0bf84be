"""Figures of a loaded tooth contact analysis (:class:`~reducerlab.analysis.contact.ContactResult`).

:func:`plot_contact` draws the overview of one mesh cycle (2 x 2): the contact pattern
and pressure on the external gear's flank, the mesh stiffness ``k(t)`` with the Fourier
series of paper 000's Eq. 8 (paper 000 Fig. 3), the loaded transmission error, and the
peak contact pressure and largest subsurface von Mises stress with the number of tooth
pairs in contact. :func:`plot_pressure_map` draws the pressure on each loaded tooth pair
at one position.

The flank maps use the external gear's *developed* flank: the contact cells of every
tooth pair (all on the same flank, turned by whole pitches) are placed by their flank
parameters ``u`` (profile, root -> tip, vertical) and ``v`` (face, toe -> heel,
horizontal), converted to arc lengths (mm) measured from the cell points ``x, y, z``:
within one tooth pair at one position the cells are the flank turned rigidly, so the
distance between neighbouring cells is the arc length between their parameters. (A
result without usable points falls back to the bare parameters.)

Figures are plain :class:`matplotlib.figure.Figure` objects (no pyplot, Agg-safe);
quantities are SI in the dataset and drawn in mm, MPa, um, deg and ms.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..analysis.contact import ContactResult

__all__ = ["plot_contact", "plot_pressure_map"]

Array = NDArray[np.float64]

#: colour map of the contact pressure
CMAP = "viridis"
#: colour of the contact pattern (envelope of the loaded cells over the cycle)
PATTERN = "0.82"
PRESSURE_LABEL = "contact pressure (MPa)"
#: the positions' patches are outlined (white) in the overview when less than this
#: fraction of the pattern's cells is loaded at more than one position
OUTLINES = 0.5


def _figure(**kw: object) -> Figure:
    from matplotlib.figure import Figure

    return Figure(**kw)  # no pyplot: no global state, works headless


def _data(result: ContactResult | xr.Dataset) -> xr.Dataset:
    return getattr(result, "data", result)


# ------------------------------------------------------------------ developed flank


@dataclass(frozen=True)
class _Flank:
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


def _flank(ds: xr.Dataset) -> _Flank:
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
    return _Flank(wu[iu], wv[iv], cu, cv, _edges(cu, hs[0]), _edges(cv, hs[1]), mm)


def _pattern(fl: _Flank, loaded: NDArray[np.bool_]) -> Array:
    """The contact pattern: along each profile row, the face from the first to the last
    cell loaded at any position (1; NaN outside). The contact sweeps the face row by
    row over the cycle, so this fills the gaps between the positions computed."""
    hit = np.isfinite(fl.grid(loaded))
    env = np.full(fl.shape, np.nan)
    for r in np.flatnonzero(hit.any(axis=1)):
        cols = np.flatnonzero(hit[r])
        env[r, cols[0] : cols[-1] + 1] = 1.0
    return env


def _outline(ax: Axes, fl: _Flank, mask: NDArray[np.bool_], **kw: Any) -> None:
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


def _frame(ax: Axes, fl: _Flank, equal: bool = False) -> None:
    ax.set_xlim(fl.ev[0], fl.ev[-1])
    ax.set_ylim(fl.eu[0], fl.eu[-1])
    if fl.mm and equal:
        ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(fl.xlabel, fontsize=8)
    ax.set_ylabel(fl.ylabel, fontsize=8)
    ax.tick_params(labelsize=7)


def _peak_position(ds: xr.Dataset) -> int:
    """Position with the highest peak pressure (from the cells if ``peak_pressure``
    is missing or NaN throughout)."""
    pk = np.asarray(ds["peak_pressure"].values, float) if "peak_pressure" in ds else None
    if pk is not None and np.isfinite(pk).any():
        return int(np.nanargmax(pk))
    p = np.asarray(ds["pressure"].values, float)
    if p.size and np.isfinite(p).any():
        return int(ds["cell_position"].values[np.nanargmax(p)])
    return 0


def _mpa(ds: xr.Dataset, name: str) -> Array:
    return 1e-6 * np.asarray(ds[name].values, float)


def _loaded(ds: xr.Dataset) -> NDArray[np.bool_]:
    f = np.asarray(ds["cell_force"].values, float)
    with np.errstate(invalid="ignore"):
        return np.isfinite(f) & (f > 0)


def _angle_deg(ds: xr.Dataset) -> Array:
    return np.degrees(np.asarray(ds["angle"].values, float))


def _gear_a(ds: xr.Dataset) -> str:
    """Gear A's name: the design's (``gear_a``: ``gear2``, ``pinion``, ``planet V``), or
    a nutation pair's external gear for results written before it was recorded."""
    name = str(ds.attrs.get("gear_a", f"gear{2 * int(ds.attrs.get('pair', 1))}"))
    return name.replace("gear", "gear ", 1) if name[4:5].isdigit() else name


# ------------------------------------------------------------------ panels


def _panel_pattern(ax: Axes, ds: xr.Dataset, fl: _Flank, fig: Figure) -> None:
    from matplotlib.colors import ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    loaded = _loaded(ds)
    pressure = _mpa(ds, "pressure")
    pos = np.asarray(ds["cell_position"].values, np.int64)
    _frame(ax, fl)
    ax.set_title(f"(a) contact pattern and pressure on {_gear_a(ds)}'s flank", fontsize=9)
    if not loaded.any():
        ax.text(0.5, 0.5, "no loaded cells", transform=ax.transAxes, ha="center")
        return
    env = _pattern(fl, loaded)
    ax.pcolormesh(fl.ev, fl.eu, np.ma.masked_invalid(env), cmap=ListedColormap([PATTERN]),
                  vmin=0, vmax=1)  # fmt: skip
    vmax = float(np.nanmax(pressure[loaded])) if np.isfinite(pressure[loaded]).any() else 1.0
    im = ax.pcolormesh(fl.ev, fl.eu, np.ma.masked_invalid(fl.grid(loaded, pressure)),
                       cmap=CMAP, vmin=0.0, vmax=vmax or 1.0)  # fmt: skip
    # flank cells loaded at more than one position (the positions' patches overlap)
    hits = np.zeros(fl.shape, int)
    for i in range(ds.sizes["position"]):
        hits += np.isfinite(fl.grid(loaded & (pos == i)))
    overlap = float((hits > 1).sum()) / max(1, int((hits > 0).sum()))
    cb = fig.colorbar(im, ax=ax, shrink=0.95, pad=0.02)
    cb.set_label(PRESSURE_LABEL + (", highest over the cycle" if overlap else ""), fontsize=8)
    cb.ax.tick_params(labelsize=7)
    if overlap < OUTLINES:  # patches mostly apart: separate them
        for i in range(ds.sizes["position"]):
            _outline(ax, fl, loaded & (pos == i), colors="w", linewidths=0.5, alpha=0.8)
    j = _peak_position(ds)
    at = loaded & (pos == j)
    _outline(ax, fl, at, colors="k", linewidths=1.2)
    handles = [Patch(color=PATTERN, label=f"pattern over the cycle ({ds.sizes['position']} "
                                          "positions)")]  # fmt: skip
    if at.any() and np.isfinite(pressure[at]).any():
        i = np.flatnonzero(at)[np.nanargmax(pressure[at])]
        ax.plot(fl.cv[fl.iv[i]], fl.cu[fl.iu[i]], marker="*", ms=11, mfc="w", mec="k", ls="",
                clip_on=False)  # fmt: skip
        handles.append(Line2D([], [], color="k", lw=1.0, marker="*", ms=9, mfc="w", mec="k",
                              label=f"position {j} ({_angle_deg(ds)[j]:.2f} deg): "
                                    f"p_max = {pressure[i]:.0f} MPa"))  # fmt: skip
    ax.legend(handles=handles, fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.13),
              ncol=2, frameon=False)  # fmt: skip


def _panel_stiffness(ax: Axes, ds: xr.Dataset) -> None:
    n = ds.sizes["position"]
    k = 1e-8 * np.asarray(ds["stiffness"].values, float)
    f_mesh = float(ds.attrs.get("mesh_frequency", 0.0) or 0.0)
    t = np.asarray(ds["time"].values, float) if "time" in ds else None
    if f_mesh > 0:
        period = 1.0 / f_mesh
    elif t is not None and n > 1:
        period = n * float(t[1] - t[0])
    else:
        period = 0.0
    if period > 0:
        scale, xlabel = 1e3, "time t (ms)"
        x = t if t is not None else period * np.arange(n) / n
        x_end = period
    else:  # no time scale: the mesh phase
        scale, xlabel = 1.0, "mesh phase t / T_m"
        x, x_end = np.arange(n) / n, 1.0
    ax.plot(scale * x, k, "o", color="k", ms=4, label=f"LTCA ({n} positions)", clip_on=False)
    a = ds.attrs
    if "k_mean" in a:
        km = 1e-8 * float(a["k_mean"])
        if "amplitude" in ds and "phase" in ds:
            amp = 1e-8 * np.asarray(ds["amplitude"].values, float)
            ph = np.asarray(ds["phase"].values, float)
            r = np.arange(1, len(amp) + 1)
            xx = np.linspace(0.0, x_end, 400)
            fit = km + np.sum(amp * np.cos(np.multiply.outer(2 * math.pi * xx / x_end, r) + ph),
                              axis=-1)  # fmt: skip
            res = float(a.get("fit_residual", math.nan))
            ax.plot(scale * xx, fit, "--", color="tab:red", lw=1.4,
                    label=f"Eq. 8, order {a.get('order', len(amp))} "
                          f"(residual {100 * res:.2g} %)")  # fmt: skip
        ax.axhline(km, color="0.45", lw=0.9, ls=":", label=f"k_m = {km:.4g} x 10^8 N/m")
    ax.set_xlim(0.0, scale * x_end)
    ax.set_xlabel(xlabel, fontsize=8)
    ax.set_ylabel("mesh stiffness k (10^8 N/m)", fontsize=8)
    ax.set_title("(b) mesh stiffness over one mesh period", fontsize=9)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="best")


def _panel_te(ax: Axes, ds: xr.Dataset) -> None:
    ang = _angle_deg(ds)
    te = 1e6 * np.asarray(ds["te"].values, float)
    ax.plot(ang, te, "o-", color="tab:blue", ms=4, lw=1.2)
    if np.isfinite(te).any():
        ptp = float(np.nanmax(te) - np.nanmin(te))
        ax.text(0.02, 0.95, f"peak to peak {ptp:.3g} um", transform=ax.transAxes, va="top",
                fontsize=7)  # fmt: skip
    ax.set_xlabel(f"rotation of {_gear_a(ds)} (deg)", fontsize=8)
    ax.set_ylabel("loaded transmission error (um)", fontsize=8)
    ax.set_title("(c) loaded transmission error", fontsize=9)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)


def _panel_stress(ax: Axes, ds: xr.Dataset) -> Axes:
    ang = _angle_deg(ds)
    pk = _mpa(ds, "peak_pressure")
    vm = _mpa(ds, "von_mises")
    if "von_mises_depth" in ds:  # 0 with no depth: no interior cell, not computed
        vm = np.where(np.isfinite(np.asarray(ds["von_mises_depth"].values, float)), vm, np.nan)
    ax.plot(ang, pk, "o-", color="tab:red", ms=4, lw=1.2, label="peak contact pressure")
    vm_label = "max subsurface von Mises"
    if not np.isfinite(vm).any():
        vm_label += " (not computed)"
    ax.plot(ang, vm, "s-", color="tab:purple", ms=4, lw=1.2, label=vm_label)
    top = np.nanmax(np.concatenate([pk, vm, [0.0]]))
    ax.set_ylim(0.0, 1.12 * top if top > 0 else 1.0)
    ax.set_xlabel(f"rotation of {_gear_a(ds)} (deg)", fontsize=8)
    ax.set_ylabel("stress (MPa)", fontsize=8)
    ax.set_title("(d) contact pressure and subsurface stress", fontsize=9)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)
    tw = ax.twinx()
    pairs = np.asarray(ds["pairs"].values, float)
    tw.plot(ang, pairs, drawstyle="steps-mid", color="0.35", ls="--", lw=1.0, marker="_",
            ms=8, label="tooth pairs in contact")  # fmt: skip
    hi = int(np.nanmax(pairs)) if np.isfinite(pairs).any() else 1
    tw.set_ylim(0, hi + 1)
    tw.set_yticks(range(hi + 2))
    tw.set_ylabel("tooth pairs in contact", fontsize=8)
    tw.tick_params(labelsize=7)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = tw.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="lower left")
    return tw


def _title(ds: xr.Dataset) -> str:
    a = ds.attrs
    parts = [str(a.get("title", "Loaded tooth contact"))]
    extra = []
    if "profile" in a:
        extra.append(str(a["profile"]))
    if "torque_external" in a:
        extra.append(f"T on {_gear_a(ds)} = {float(a['torque_external']):.4g} N m")
    if int(a.get("rigid", 0)):
        extra.append("rigid teeth")
    if extra:
        parts.append(", ".join(extra))
    return ": ".join(parts)


# ------------------------------------------------------------------ public


def plot_contact(result: ContactResult) -> Figure:
    """Overview of a loaded tooth contact analysis over one mesh cycle (2 x 2 panels).

    Parameters
    ----------
    result : ContactResult
        Or its dataset.

    Returns
    -------
    matplotlib.figure.Figure
        (a) the contact pattern on the external gear's developed flank (light grey:
        along each profile row, the face between the first and last cell loaded at
        any position) under the loaded cells of every position coloured by their
        pressure (MPa; the highest where positions overlap; each position's patches
        outlined in white when they mostly do not overlap), the position with the
        highest peak pressure outlined in black and its peak cell starred; (b) the
        mesh stiffness at each position (10^8 N/m) over one mesh period with the
        Fourier series of paper 000's Eq. 8 (dashed red) and ``k_m``; (c) the loaded
        transmission error (um); (d) the peak contact pressure and the largest
        subsurface von Mises stress (MPa; gaps where it was not computed: NaN, or no
        cell away from the flank edges) with the tooth pairs in contact (twin axis).
    """
    ds = _data(result)
    fl = _flank(ds)
    fig = _figure(figsize=(12.0, 8.0), layout="constrained")
    (a, b), (c, d) = fig.subplots(2, 2)
    _panel_pattern(a, ds, fl, fig)
    _panel_stiffness(b, ds)
    _panel_te(c, ds)
    _panel_stress(d, ds)
    fig.suptitle(_title(ds), fontsize=10)
    return fig


def plot_pressure_map(result: ContactResult, position: int | None = None) -> Figure:
    """Contact pressure at one position, one panel per loaded tooth pair.

    Parameters
    ----------
    result : ContactResult
        Or its dataset.
    position : int, optional
        Index of the position (``0 .. positions - 1``); default the one with the
        highest peak pressure.

    Returns
    -------
    matplotlib.figure.Figure
        Each tooth pair in contact side by side on the external gear's developed flank
        (mm): the cycle's contact pattern in light grey, the pair's loaded cells
        coloured by pressure (MPa, one scale for all panels), the highest cell starred.
        A position without loaded cells gives one panel that says so.
    """
    ds = _data(result)
    n = ds.sizes["position"]
    if position is None:
        position = _peak_position(ds)
    elif (
        isinstance(position, bool)
        or not isinstance(position, (int, np.integer))
        or not (0 <= position < n)
    ):
        raise ReducerlabError(f"position: must be an integer in 0..{n - 1}; got {position!r}")
    j = int(position)
    fl = _flank(ds)
    loaded = _loaded(ds)
    pos = np.asarray(ds["cell_position"].values, np.int64)
    tooth = np.asarray(ds["cell_tooth"].values, np.int64)
    pressure = _mpa(ds, "pressure")
    force = np.asarray(ds["cell_force"].values, float)
    here = loaded & (pos == j)
    teeth = [int(k) for k in np.unique(tooth[here])]
    ncol = max(1, len(teeth))
    width, height = float(np.ptp(fl.ev)), float(np.ptp(fl.eu))
    equal = fl.mm and width <= 4 * height
    panel_w = 4.6 if width >= height else 3.2
    ratio = height / width if equal and width > 0 else 0.5
    fig = _figure(figsize=(panel_w * ncol + 1.0, min(6.0, max(1.0, panel_w * ratio)) + 1.3),
                  layout="constrained")  # fmt: skip
    axes = np.atleast_1d(fig.subplots(1, ncol, sharex=True, sharey=True, squeeze=False)).ravel()
    env = _pattern(fl, loaded) if loaded.any() else None
    from matplotlib.colors import ListedColormap

    finite = here & np.isfinite(pressure)
    vmax = float(pressure[finite].max()) if finite.any() else 1.0
    im = None
    top = int(np.flatnonzero(finite)[np.argmax(pressure[finite])]) if finite.any() else -1
    for ax, k in zip(axes, teeth or [None], strict=True):
        _frame(ax, fl, equal=equal)
        if env is not None:
            ax.pcolormesh(fl.ev, fl.eu, np.ma.masked_invalid(env),
                          cmap=ListedColormap([PATTERN]), vmin=0, vmax=1)  # fmt: skip
        if k is None:
            ax.text(0.5, 0.5, f"no loaded cells at position {j}", transform=ax.transAxes,
                    ha="center", va="center", fontsize=8)  # fmt: skip
            continue
        m = here & (tooth == k)
        im = ax.pcolormesh(fl.ev, fl.eu, np.ma.masked_invalid(fl.grid(m, pressure)),
                           cmap=CMAP, vmin=0.0, vmax=vmax or 1.0)  # fmt: skip
        p_k = float(np.nanmax(pressure[m])) if np.isfinite(pressure[m]).any() else math.nan
        ax.set_title(f"tooth pair {k}: F = {np.nansum(force[m]):.4g} N, "
                     f"p_max = {p_k:.0f} MPa", fontsize=8)  # fmt: skip
        if top >= 0 and tooth[top] == k:
            ax.plot(fl.cv[fl.iv[top]], fl.cu[fl.iu[top]], marker="*", ms=11, mfc="w", mec="k",
                    clip_on=False)  # fmt: skip
    for ax in axes[1:]:
        ax.set_ylabel("")
    if im is not None:
        cb = fig.colorbar(im, ax=list(axes), shrink=0.95, pad=0.01, aspect=15)
        cb.set_label(PRESSURE_LABEL, fontsize=8)
        cb.ax.tick_params(labelsize=7)
    t = ""
    if "time" in ds:
        t = f", t = {1e3 * float(ds['time'].values[j]):.4g} ms"
    fig.suptitle(f"{_title(ds)}\nposition {j}: {_gear_a(ds)} at "
                 f"{_angle_deg(ds)[j]:.3f} deg{t}", fontsize=9)  # fmt: skip
    return fig
