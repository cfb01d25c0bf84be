"""Figures of kinematic results."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ReducerlabError
from .axes import plain_figure

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..analysis.kinematics import KinematicsResult

__all__ = ["plot_angular_velocity"]

LABELS = {"body": ("ω_x", "ω_y", "ω_z"), "fixed": ("ω_ξ", "ω_η", "ω_ζ")}


def plot_angular_velocity(result: KinematicsResult) -> Figure:
    """Body- and fixed-frame angular-velocity components (rad/s) of the nutating gear
    against the input angle over one revolution (paper 002's Euler kinematics)."""
    from matplotlib.figure import Figure

    ds = result.data
    if "omega" not in ds:
        raise ReducerlabError(f"{ds.attrs.get('title', 'this drive')} has no nutating member")
    fig = Figure(figsize=(9, 3.6), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    x = ds["input_angle"].values
    for ax, frame in zip(axes, ("body", "fixed"), strict=True):
        w = ds["omega"].sel(frame=frame).values
        for k, lab in enumerate(LABELS[frame]):
            ax.plot(x, w[:, k], label=lab)
        ax.set_title(f"{frame} frame", fontsize=9)
        ax.set_xlabel("input angle (deg)")
        ax.set_xlim(x[0], x[-1])
        # a turn in quarters: the labels, fixed, are spaced as the panels' gap allows
        ax.set_xticks(np.arange(math.ceil(x[0] / 90), math.floor(x[-1] / 90) + 1) * 90.0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    # the gap between the panels holds the last label of the left one ("360") and the
    # first of the right one ("0") apart
    fig.get_layout_engine().set(wspace=0.08)
    axes[0].set_ylabel("angular velocity (rad/s)")
    fig.suptitle(
        f"{ds.attrs.get('title', '')}: nutating gear, ratio {result.ratio:.6g}", fontsize=10
    )
    return plain_figure(fig)
