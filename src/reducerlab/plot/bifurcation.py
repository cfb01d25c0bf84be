"""Interactive figures (plotly) of bifurcation diagrams and regime maps, for the design
report; plotly is imported only when a figure is built. (Their matplotlib figures are the
results' own ``plot()``.)"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from ..analysis.bifurcation import BifurcationResult
    from ..analysis.regime_map import RegimeMapResult

__all__ = ["plotly_bifurcation", "plotly_regime_map"]


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

    from ..analysis.members import axis_label, shown_values

    ds = result.data
    x = shown_values(ds["p0"])
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
        xaxis_title=axis_label(ds["p0"], ds.attrs["parameter"]),
        yaxis_title=f"Poincaré points ({ds['poincare'].attrs.get('units', '')})",
        height=480,
        template="plotly_white",
        margin=dict(t=30, l=70, r=20, b=50),
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

    from ..analysis.members import axis_label, shown_values

    ds = result.data
    X, Y = shown_values(ds["p0"]), shown_values(ds["p1"])
    lab = np.asarray(result.labels())[0]
    classes = sorted(set(lab.ravel().tolist()))
    idx = np.vectorize(classes.index)(lab)
    fig = go.Figure(
        go.Heatmap(
            x=X,
            y=Y,
            z=idx,
            text=lab,
            hovertemplate="%{x:.4g}, %{y:.4g}: %{text}<extra></extra>",
            colorscale="Viridis",
            showscale=True,
            zmin=-0.5,
            zmax=len(classes) - 0.5,
            colorbar=dict(tickvals=list(range(len(classes))), ticktext=classes, title="motion"),
        )
    )
    fig.update_layout(
        xaxis_title=axis_label(ds["p0"], ds.attrs["x"]),
        yaxis_title=axis_label(ds["p1"], ds.attrs["y"]),
        height=480,
        template="plotly_white",
        margin=dict(t=30, l=70, r=20, b=50),
    )
    return fig
