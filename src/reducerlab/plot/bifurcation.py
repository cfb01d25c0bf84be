"""Figures of bifurcation diagrams and regime maps: the matplotlib figures the results'
``plot()`` draw, and the interactive (plotly) ones of the design report; matplotlib and
plotly are imported only when a figure is built."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from .axes import parameter_axis, parameter_label, plain_axes, plain_axis, pretty_unit

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure
    from numpy.typing import NDArray

    from ..analysis.bifurcation import BifurcationResult
    from ..analysis.regime_map import RegimeMapResult

__all__ = [
    "MOTION_COLOURS",
    "motion_colours",
    "plot_bifurcation",
    "plot_regime_map",
    "plotly_bifurcation",
    "plotly_regime_map",
]


def plot_bifurcation(result: BifurcationResult) -> Figure:
    """Bifurcation diagram (paper 004 Fig. 7), with the motion classes as a coloured
    band underneath when the exponents were computed.

    The Poincaré points of the first sweep are black dots; those of the descending sweep
    (``continuation="both"``) red crosses and those of the random starts (``seeds``) blue
    dots. A band of impact classes is added when the result holds them.

    Parameters
    ----------
    result : BifurcationResult
        The diagram to draw.

    Returns
    -------
    matplotlib.figure.Figure
        The diagram, the class bands below it sharing its parameter axis.
    """
    from matplotlib.figure import Figure

    ds = result.data
    fig = Figure(figsize=(7.5, 5.0), layout="constrained")
    has_imp = "impact_class" in ds
    rows = 1 + ("exponent" in ds) + has_imp
    axes = fig.subplots(
        rows, 1, sharex=True, gridspec_kw={"height_ratios": [12] + [1] * (rows - 1)}
    )
    axes = np.atleast_1d(axes)
    ax = axes[0]
    band = axes[1] if "exponent" in ds else None
    imp_band = axes[-1] if has_imp else None
    x, xlabel = parameter_axis(ds["p0"], ds.attrs["parameter"])
    p = np.repeat(x, ds.sizes["point"])
    way = ds.attrs.get("continuation")
    first = {"up": "ascending sweep", "both": "ascending sweep", "down": "descending sweep"}
    ax.plot(p, ds["poincare"].values.ravel(), ".k", ms=1.0 if way is None else 2.5,
            alpha=0.6, label=first.get(way))  # fmt: skip
    if "poincare_seeds" in ds:  # runs from random starts: coexisting attractors
        ps = np.repeat(x, ds.sizes["seed"] * ds.sizes["point"])
        ax.plot(ps, ds["poincare_seeds"].values.ravel(), "o", color="C0", ms=1.6,
                alpha=0.35, mew=0, label="random starts")  # fmt: skip
    if "poincare_down" in ds:  # the other sweep, drawn so that both stay visible
        ax.plot(p, ds["poincare_down"].values.ravel(), "x", color="C3", ms=3.0,
                alpha=0.7, label="descending sweep")  # fmt: skip
    if way is not None or "poincare_seeds" in ds:
        ax.legend(fontsize=7, markerscale=2)
    edges = (
        np.concatenate([[x[0]], 0.5 * (x[1:] + x[:-1]), [x[-1]]])
        if x.size > 1
        else np.array([x[0] - 0.5, x[0] + 0.5])
    )
    if band is not None:
        _class_band(band, edges, result.labels(), "motion", "C")
    if imp_band is not None:
        _class_band(imp_band, edges, result.impacts(), "teeth", "tab:")
    axes[-1].set_xlabel(xlabel)
    plain_axes(ax)
    plain_axis(axes[-1].xaxis)
    unit = str(ds["poincare"].attrs["units"])
    ax.set_ylabel(f"Poincaré points of mesh deflection ({pretty_unit(unit)})")
    ax.set_title(_bifurcation_title(ds, "\n"), fontsize=9)
    ax.grid(alpha=0.3)
    return fig


def _drive(ds: Any) -> str:
    """The drive's name a result's figures title with: its ``title``, else the design's
    name, else ``""``."""
    import json

    title = str(ds.attrs.get("title", "") or "")
    if title:
        return title
    try:
        return str(json.loads(ds.attrs.get("design", "{}")).get("name", ""))
    except (TypeError, ValueError):
        return ""


def _bifurcation_title(ds: Any, sep: str = ": ") -> str:
    """``"DRIVE: bifurcation diagram: Poincaré points of the mesh deflection over NAME"``
    (``sep`` between the drive and the rest: a line break where the width is short)."""
    what = "bifurcation diagram: Poincaré points of the mesh deflection over " + parameter_label(
        ds.attrs["parameter"]
    )
    drive = _drive(ds)
    return f"{drive}{sep}{what}" if drive else what


#: The special motion classes' colours; the period-n classes take :data:`PERIOD_COLOURS`.
MOTION_COLOURS = {
    "quasi-periodic": "#9467bd",
    "chaotic": "#d62728",
    "unsettled": "#d3d3d3",
    "diverged": "#000000",
}
PERIOD_COLOURS = ("#1f77b4", "#2ca02c", "#ff7f0e", "#bcbd22", "#17becf", "#8c564b",
                  "#e377c2", "#aec7e8", "#98df8a", "#ffbb78", "#dbdb8d", "#9edae5",
                  "#c49c94", "#f7b6d2")  # fmt: skip


def motion_colours(classes: list[str]) -> list[str]:
    """One colour a motion class, the same in the matplotlib and the plotly maps."""
    return [MOTION_COLOURS.get(k, PERIOD_COLOURS[i % len(PERIOD_COLOURS)])
            for i, k in enumerate(classes)]  # fmt: skip


def _class_band(band: Axes, edges: NDArray, labels: list[str], title: str, palette: str) -> None:
    """A strip coloured by class per parameter value, its legend beside it (no clipping)."""
    from matplotlib.patches import Patch

    from ..analysis.impacts import IMPACT_CLASSES

    colours_c = ["C0", "C1", "C2", "C3", "C4", "C5", "C6", "C7", "C8", "C9"]
    colours_t = ["tab:green", "tab:orange", "tab:red", "tab:gray"]
    palette_list = colours_c if palette == "C" else colours_t
    order = sorted(set(labels), key=lambda k: (k == "diverged", k))
    if palette != "C":
        order = [k for k in (*IMPACT_CLASSES, "diverged") if k in set(labels)]
    colours = {k: palette_list[i % len(palette_list)] for i, k in enumerate(order)}
    if "diverged" in colours:
        colours["diverged"] = "black"
    for i, lab in enumerate(labels):
        band.axvspan(edges[i], edges[i + 1], color=colours[lab], lw=0)
    handles = [Patch(color=colours[k], label=k) for k in order]
    band.legend(handles=handles, fontsize=6, loc="center left", bbox_to_anchor=(1.01, 0.5),
                frameon=False, title=title, title_fontsize=6)  # fmt: skip
    band.set_yticks([])


def plot_regime_map(result: RegimeMapResult) -> Figure:
    """Motion-class and impact-class maps per branch (columns), points where the two
    sweeps found different attractors marked with a dot.

    Parameters
    ----------
    result : RegimeMapResult
        The map to draw.

    Returns
    -------
    matplotlib.figure.Figure
        Two rows (motion class, impact class) of one map per branch, each row's legend
        beside its last map.
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    from ..analysis.impacts import IMPACT_CLASSES
    from ..analysis.regime_map import motion_order

    ds = result.data
    branches = ds["branch"].values.tolist()
    nb = len(branches)
    fig = Figure(figsize=(4.2 * nb + 2.4, 6.6), layout="constrained")
    axes = np.atleast_2d(fig.subplots(2, nb, sharex=True, sharey=True, squeeze=False))
    cx, cy = ds["p0"], ds["p1"]
    (X, xlabel), (Y, ylabel) = parameter_axis(cx, ds.attrs["x"]), parameter_axis(cy, ds.attrs["y"])
    lab_m, lab_i = result.labels(), result.impacts()
    co = result.coexisting()
    m_classes = motion_order(np.unique(lab_m).tolist())
    i_classes = [k for k in (*IMPACT_CLASSES, "diverged") if k in set(lab_i.ravel())]
    m_col = motion_colours(m_classes)
    i_palette = {"no impact": "tab:green", "single-sided impact": "tab:orange",
                 "double-sided impact": "tab:red", "diverged": "black"}  # fmt: skip
    i_col = [i_palette[k] for k in i_classes]

    def edges(v: NDArray) -> NDArray:
        if v.size == 1:
            return np.array([v[0] - 0.5, v[0] + 0.5])
        mid = 0.5 * (v[1:] + v[:-1])
        return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])

    ex, ey = edges(X), edges(Y)
    for b, branch in enumerate(branches):
        for r, (lab, classes, colours) in enumerate(
            ((lab_m, m_classes, m_col), (lab_i, i_classes, i_col))
        ):
            ax = axes[r, b]
            idx = np.vectorize(classes.index, otypes=[float])(lab[b])
            ax.pcolormesh(ex, ey, idx, cmap=ListedColormap(colours), vmin=-0.5,
                          vmax=len(classes) - 0.5, shading="flat")  # fmt: skip
            if co.any():
                iy, ix = np.nonzero(co)
                ax.plot(X[ix], Y[iy], "o", color="white", ms=4, mec="k", mew=0.6)
            what = "motion" if r == 0 else "teeth"
            way = f"{branch} sweep" if branch != "static" else "from static equilibrium"
            ax.set_title(f"{what}: {way}", fontsize=8)
        for r, (classes, colours, title) in enumerate(
            ((m_classes, m_col, "motion"), (i_classes, i_col, "teeth"))
        ):
            if b == nb - 1:
                handles = [Patch(color=c, label=k) for k, c in zip(classes, colours,
                                                                    strict=True)]  # fmt: skip
                if r == 0 and co.any():
                    handles.append(Patch(facecolor="white", edgecolor="k",
                                         label="up != down"))  # fmt: skip
                axes[r, b].legend(handles=handles, fontsize=6, title=title,
                                  title_fontsize=7, loc="center left",
                                  bbox_to_anchor=(1.02, 0.5), frameon=False)  # fmt: skip

    for ax in axes[-1]:
        ax.set_xlabel(xlabel)
    for ax in axes[:, 0]:
        ax.set_ylabel(ylabel)
    for ax in axes.ravel():
        plain_axes(ax, xbins=4)
    fig.suptitle(_regime_title(ds), fontsize=9)
    return fig


def _regime_title(ds: Any) -> str:
    """``"DRIVE: regime map over NAME X and NAME Y"``."""
    what = f"regime map over {parameter_label(ds.attrs['x'])} and {parameter_label(ds.attrs['y'])}"
    drive = _drive(ds)
    return f"{drive}: {what}" if drive else what


def plotly_bifurcation(result: BifurcationResult) -> Any:
    """Interactive bifurcation diagram (plotly, WebGL points): the Poincaré points of the
    ascending sweep, and of the descending sweep and the random starts when the result
    holds them, against the parameter.

    Parameters
    ----------
    result : BifurcationResult

    Returns
    -------
    plotly.graph_objects.Figure
    """
    import plotly.graph_objects as go

    ds = result.data
    x, xlabel = parameter_axis(ds["p0"], ds.attrs["parameter"])
    fig = go.Figure()
    runs = [("poincare", "Poincaré points", "black")]
    if "poincare_down" in ds:
        runs.append(("poincare_down", "descending sweep", "crimson"))
    if "poincare_seeds" in ds:
        runs.append(("poincare_seeds", "random starts", "royalblue"))
    for name, label, colour in runs:
        v = ds[name].values
        per = int(np.prod(v.shape[1:]))
        fig.add_trace(
            go.Scattergl(
                x=np.repeat(x, per),
                y=v.ravel(),
                mode="markers",
                name=label,
                marker=dict(size=3, color=colour, opacity=0.6),
            )
        )
    fig.update_layout(
        title=dict(text=_bifurcation_title(ds), font=dict(size=14)),
        xaxis_title=xlabel,
        yaxis_title="Poincaré points of mesh deflection "
        f"({pretty_unit(str(ds['poincare'].attrs.get('units', '')))})",
        height=480,
        template="plotly_white",
        margin=dict(t=60, l=70, r=20, b=50),
    )
    return fig


def plotly_regime_map(result: RegimeMapResult) -> Any:
    """Interactive regime map (plotly heat map): the motion class of the first branch over
    the two parameters, hover for the class.

    Parameters
    ----------
    result : RegimeMapResult

    Returns
    -------
    plotly.graph_objects.Figure
    """
    import plotly.graph_objects as go

    ds = result.data
    (X, xlabel), (Y, ylabel) = (
        parameter_axis(ds["p0"], ds.attrs["x"]),
        parameter_axis(ds["p1"], ds.attrs["y"]),
    )
    from ..analysis.regime_map import motion_order

    lab = np.asarray(result.labels())[0]
    classes = motion_order(sorted(set(lab.ravel().tolist())))
    idx = np.vectorize(classes.index)(lab)
    n = len(classes)
    # a discrete colour bar: one band of one colour a class, named at its middle
    scale = []
    for k, colour in enumerate(motion_colours(classes)):
        scale += [[k / n, colour], [(k + 1) / n, colour]]
    fig = go.Figure(
        go.Heatmap(
            x=X,
            y=Y,
            z=idx,
            text=lab,
            hovertemplate="%{x:.4g}, %{y:.4g}: %{text}<extra></extra>",
            colorscale=scale,
            showscale=True,
            zmin=-0.5,
            zmax=n - 0.5,
            xgap=1,
            ygap=1,
            colorbar=dict(
                tickvals=list(range(n)), ticktext=classes, title="motion class", ticks=""
            ),
        )
    )
    first = str(ds["branch"].values[0]) if "branch" in ds else ""
    fig.update_layout(
        title=dict(
            text=_regime_title(ds) + (f" ({first} sweep)" if first else ""), font=dict(size=14)
        ),
        xaxis_title=xlabel,
        yaxis_title=ylabel,
        height=480,
        template="plotly_white",
        margin=dict(t=60, l=70, r=20, b=50),
    )
    return fig
