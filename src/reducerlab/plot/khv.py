"""The closed graph of an internal gear pair (paper 004 Fig. 3)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import ReducerlabError
from ..geometry import InternalGearPair
from .axes import plain_figure, scaled_unit

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "closed_graph",
    "plot_clearances",
    "plot_closed_graph",
    "plot_load_sharing",
    "plot_mesh_stiffness",
]

LIMITS = (
    "contact ratio",
    "involute interference",
    "tip overlap interference",
    "pointed planet teeth",
)


def closed_graph(
    base: InternalGearPair,
    x1: np.ndarray,
    x2: np.ndarray,
) -> dict[str, np.ndarray]:
    """Margins of every feasibility condition on the grid ``x1 x x2`` (rows: x2)."""
    out = {name: np.full((x2.size, x1.size), np.nan) for name in LIMITS}
    for i, b in enumerate(x2):
        for j, a in enumerate(x1):
            try:
                g = InternalGearPair(
                    base.z1, base.z2, base.module, float(a), float(b), addendum=base.addendum,
                    pressure_angle=base.pressure_angle, face_width=base.face_width,
                )  # fmt: skip
                conds = {c.name: c.margin for c in g.conditions()}
            except (ReducerlabError, ValueError, ZeroDivisionError):
                continue
            for name in LIMITS:
                v = conds[name]
                out[name][i, j] = np.clip(v, -10, 10) if np.isfinite(v) else 10.0
    return out


def plot_closed_graph(
    pair: InternalGearPair,
    line: tuple[float, float, float, float] | None = None,
    x1_range: tuple[float, float] = (-0.2, 1.4),
    x2_range: tuple[float, float] = (-0.1, 1.6),
    n: int = 121,
) -> Figure:
    """x1 vs x2 with the limit lines of each condition, the feasible region shaded, the
    design point and, if given, the design line through two points (paper's line 4)."""
    from matplotlib.figure import Figure

    x1 = np.linspace(*x1_range, n)
    x2 = np.linspace(*x2_range, n)
    margins = closed_graph(pair, x1, x2)
    fig = Figure(figsize=(6.6, 5.6), layout="constrained")
    ax = fig.subplots()
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    # where no pair can be built (no positive working pressure angle) every margin is
    # NaN: that region is hatched, and the limit lines are contours of the margins
    # inside the rest only (a NaN taken as negative drew the region's grid-stepped edge
    # as a limit)
    invalid = np.all([np.isnan(m) for m in margins.values()], axis=0)
    feasible = ~invalid
    handles = []
    reached = {}
    for k, (name, m) in enumerate(margins.items()):
        feasible &= np.nan_to_num(m, nan=-1.0) >= 0
        inside = m[np.isfinite(m)]
        reached[name] = inside.size > 0 and inside.min() < 0 < inside.max()
        if reached[name]:
            ax.contour(x1, x2, np.ma.masked_invalid(m), levels=[0.0], colors=[f"C{k}"],
                       linewidths=1.6)  # fmt: skip
            text = f"{k + 1}: {name} limit"
        else:  # listed, but it has no line to draw here
            low = float(inside.min()) if inside.size else float("nan")
            text = f"{k + 1}: {name}: not reached here (margin >= {low:.2g})"
        handles.append(Line2D([], [], color=f"C{k}", ls="-" if reached[name] else ":",
                              label=text))  # fmt: skip
    ax.contourf(x1, x2, feasible.astype(float), levels=[0.5, 1.5], colors=["0.85"])
    if invalid.any():
        ax.contourf(x1, x2, invalid.astype(float), levels=[0.5, 1.5], colors="none",
                    hatches=["xx"])  # fmt: skip
        handles.append(Patch(facecolor="none", edgecolor="0.3", hatch="xx",
                             label="no pair: no positive working pressure angle"))  # fmt: skip
    if line is not None:
        a1, a2, b1, b2 = line
        xs = np.array(x1_range)
        ax.plot(xs, a2 + (b2 - a2) * (xs - a1) / (b1 - a1), "k--", lw=1.0,
                label="design line (through M, N)")  # fmt: skip
        ax.plot([a1, b1], [a2, b2], "ks", ms=5)
        ax.annotate("M", (a1, a2), xytext=(4, -12), textcoords="offset points")
        ax.annotate("N", (b1, b2), xytext=(4, -12), textcoords="offset points")
    where = _on_limits(pair, margins, x1, x2)
    label = f"design ({pair.x1:.3f}, {pair.x2:.3f}){where}"
    ax.plot([pair.x1], [pair.x2], "r*", ms=14, label=label)
    ax.set_xlabel("x1 (planet)")
    ax.set_ylabel("x2 (ring)")
    ax.set_xlim(*x1_range)
    ax.set_ylim(*x2_range)
    ax.set_title(
        f"closed graph z1={pair.z1}, z2={pair.z2}, ha*={pair.addendum:g} (grey: feasible)",
        fontsize=9,
    )
    ax.legend(handles=handles + ax.get_legend_handles_labels()[0], fontsize=7,
              loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, frameon=False)  # fmt: skip
    ax.grid(alpha=0.3)
    return plain_figure(fig)


def _on_limits(
    pair: InternalGearPair, margins: dict[str, np.ndarray], x1: np.ndarray, x2: np.ndarray
) -> str:
    """``": on limit 3 (margin 0.003)"`` where the design's margin of a drawn condition
    is smaller than the change of that margin across one grid cell (the point sits on
    the line as drawn), else ``""``."""
    own = {c.name: c.margin for c in pair.conditions()}
    said = []
    for k, (name, m) in enumerate(margins.items()):
        if name not in own or not np.isfinite(own[name]) or not np.isfinite(m).any():
            continue
        step = np.nanmax(np.abs(np.concatenate([np.diff(m, axis=0).ravel(),
                                                np.diff(m, axis=1).ravel()])))  # fmt: skip
        if abs(own[name]) <= step:
            said.append(f"on limit {k + 1} (margin {own[name]:.2g})")
    return ": " + ", ".join(said) if said else ""


def plot_mesh_stiffness(laws: dict[str, object], periods: float = 2.0) -> Figure:
    """Mesh stiffness over ``periods`` mesh periods for several laws (paper 004 Fig. 5),
    against time in mesh periods; each law's mean dashed."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 4.6), layout="constrained")
    ax = fig.subplots()
    s = np.linspace(0, periods, 2001)
    curves = {label: law(s * law.period) for label, law in laws.items()}  # type: ignore[attr-defined,operator]
    factor, unit = scaled_unit(np.concatenate([*curves.values(), [0.0]]), "N/m")
    for k, (label, law) in enumerate(laws.items()):
        ax.plot(s, curves[label] * factor, color=f"C{k}", label=label)
        ax.axhline(law.mean * factor, color=f"C{k}", ls="--", lw=0.8)  # type: ignore[attr-defined]
    ax.set_xlabel("time (mesh periods)")
    ax.set_ylabel(f"mesh stiffness ({unit})")
    ax.set_title("time-varying mesh stiffness (dashed: mean)", fontsize=9)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.15), frameon=False)
    ax.grid(alpha=0.3)
    return plain_figure(fig)


def plot_clearances(rolls: np.ndarray, teeth: list[int], clearance: np.ndarray) -> Figure:
    """Unloaded drive-flank clearance of each tooth pair (um, log scale) over one mesh
    cycle (``contact.internal_pair.tooth_pair_clearances``); a pair in contact is drawn
    at 1e-3 um."""
    import matplotlib
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 4.8), layout="constrained")
    ax = fig.subplots()
    x = (rolls - rolls[0]) * 1e3
    ax.set_prop_cycle(color=[matplotlib.colormaps["tab20"](i % 20) for i in range(len(teeth))])
    for j, k in enumerate(teeth):
        y = clearance[:, j] * 1e6
        if k == 0 or not np.any(np.isfinite(y)):
            continue
        ax.semilogy(x, np.where(np.isfinite(y), np.maximum(y, 1e-3), np.nan), "-o", ms=3,
                    label=f"pair {k:+d}")  # fmt: skip
    ax.set_xlabel("pair 0's contact along the line of action, from the path's start (mm)")
    ax.set_ylabel("ring rotation to close the pair, r_b2 psi (um)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, ncol=2)
    ax.set_title("unloaded drive-flank clearances of the tooth pairs over one mesh cycle")
    return plain_figure(fig)


def plot_load_sharing(result, shown: int = 3) -> Figure:
    """The KHV pair's load sharing (``analysis.khv_sharing.SharingResult``): each tooth
    pair's share against the mesh position at ``shown`` torques (the largest and
    evenly below it), the loaded TE at those torques, the tooth pairs in contact
    (least, mean, most over the cycle) and the mesh stiffness per face width (mean of
    the secant ``k(t)``, its range, and the mean tangent stiffness) against torque."""
    from matplotlib.figure import Figure

    ds = result.data
    T = result.torques
    b = float(ds.attrs["face_width_m"])
    pitch = float(ds["angle"].values[1] - ds["angle"].values[0]) * ds.sizes["position"]
    x = (ds["angle"].values - ds["angle"].values[0]) / pitch
    loaded = np.flatnonzero(T > 0)
    pick = loaded[np.unique(np.linspace(0, loaded.size - 1, min(shown, loaded.size)).round()
                            .astype(int))]  # fmt: skip
    fig = Figure(figsize=(11, 7.5), layout="constrained")
    (a1, a2), (a3, a4) = fig.subplots(2, 2)
    styles = ["-", "--", ":", "-."]
    for n, i in enumerate(pick):
        for j, k in enumerate(result.pairs):
            y = ds["share"].values[i, :, j]
            if not np.any(y > 0):
                continue
            a1.plot(x, y, styles[n % 4], color=f"C{j}", marker="o", ms=2,
                    label=f"pair {k:+d}, {T[i]:.3g} N m")  # fmt: skip
        a2.plot(x, ds["te"].values[i] * 1e6, styles[n % 4], color="k", label=f"{T[i]:.3g} N m")
    a1.set_xlabel("mesh position (mesh cycles; pair 0 mid-path at 0.5)")
    a1.set_ylabel("share of the load")
    a1.set_title("load share of each tooth pair", fontsize=9)
    # below its panel: the shares fill the panel's width and height
    a1.legend(fontsize=6, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.16),
              frameon=False)  # fmt: skip
    a2.set_xlabel("mesh position (mesh cycles)")
    a2.set_ylabel("loaded TE r_b2 psi (um)")
    a2.set_title("loaded transmission error", fontsize=9)
    a2.legend(fontsize=7, ncol=3, loc="upper center", bbox_to_anchor=(0.5, -0.16),
              frameon=False)  # fmt: skip
    n = ds["pairs"].values[loaded]
    a3.plot(T[loaded], n.min(axis=1), "v-", label="least")
    a3.plot(T[loaded], n.mean(axis=1), "o-", label="mean over the cycle")
    a3.plot(T[loaded], n.max(axis=1), "^-", label="most")
    a3.set_xlabel("torque on the planet (N m)")
    a3.set_ylabel("tooth pairs in contact")
    a3.legend(fontsize=7)
    a3.set_title("tooth pairs in contact against torque", fontsize=9)
    scale = 1e-9 / b  # N/m -> N/(mm um) per face width
    k = ds["stiffness"].values[loaded] * scale
    a4.fill_between(T[loaded], np.nanmin(k, axis=1), np.nanmax(k, axis=1), color="C0",
                    alpha=0.2, label="k(t) range")  # fmt: skip
    a4.plot(T[loaded], ds["mean_stiffness"].values[loaded] * scale, "o-", color="C0",
            label="mean secant k")  # fmt: skip
    a4.plot(T[loaded], ds["mean_tangent_stiffness"].values[loaded] * scale, "s--",
            color="C1", label="mean tangent dT/dpsi")  # fmt: skip
    a4.set_xlabel("torque on the planet (N m)")
    a4.set_ylabel("mesh stiffness per face width (N/(mm um))")
    a4.legend(fontsize=7)
    a4.set_title("mesh stiffness k = T_ring / (r_b2^2 psi) against torque", fontsize=9)
    for a in (a1, a2, a3, a4):
        a.grid(alpha=0.3)
    fig.suptitle(f"KHV pair load sharing, pairs {ds.attrs['pairs_examined']}", fontsize=10)
    return plain_figure(fig)
