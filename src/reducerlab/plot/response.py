"""Figures of the steady nonlinear response and of the frequency-response curves: the
matplotlib figures the results' ``plot()`` draw and the report's time history of the
transmission error; matplotlib is imported only when a figure is built."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..analysis.frequency_response import FrequencyResponseResult
    from ..analysis.response import ResponseResult

__all__ = ["plot_frequency_response", "plot_response", "plot_transmission_error"]


def plot_response(result: ResponseResult) -> Figure:
    """Phase trajectory, Poincaré map and labelled spectrum (paper 004 Fig. 8).

    Parameters
    ----------
    result : ResponseResult
        The steady response to draw.

    Returns
    -------
    matplotlib.figure.Figure
        Three panels: the phase trajectory of the mesh deflection (the backlash shaded),
        its Poincaré map and its spectrum over multiples of the forcing frequency, the
        largest peaks labelled.
    """
    from matplotlib.figure import Figure

    ds = result.data
    fig = Figure(figsize=(11, 3.6), layout="constrained")
    a1, a2, a3 = fig.subplots(1, 3)
    d, v = ds["delta"].values * 1e6, ds["delta_velocity"].values * 1e3
    b = float(ds.attrs.get("half_backlash_m", 0.0)) * 1e6
    if b > 0:  # the backlash: no elastic force while the deflection is in it
        a1.axvspan(-b, b, color="0.85", zorder=0, label="teeth apart")
        a1.legend(fontsize=7, loc="upper right")
    a1.plot(d, v, lw=0.6)
    a1.set_xlabel("mesh deflection (um)")
    a1.set_ylabel("velocity (mm/s)")
    cls = ds.attrs.get("impact_class")
    a1.set_title(
        f"phase trajectory: {cls}, apart {100 * ds.attrs['separation_fraction']:.0f} %"
        if cls
        else "phase trajectory",
        fontsize=9,
    )
    a2.plot(ds["poincare_delta"].values * 1e6, ds["poincare_velocity"].values * 1e3, ".k")
    a2.set_xlabel("mesh deflection (um)")
    a2.set_title("Poincaré map", fontsize=9)
    x, dt = result.uniform_deflection()
    x = x - x.mean()
    amp = 2 * np.abs(np.fft.rfft(x * np.hanning(x.size))) / np.sum(np.hanning(x.size))
    f = np.fft.rfftfreq(x.size, dt) / ds.attrs["forcing_hz"]
    a3.plot(f, amp * 1e6)
    for m, a in result.peaks(5):
        a3.annotate(f"{m:.2f}x", (m, a * 1e6), fontsize=7)
    a3.set_xlim(0, 4)
    a3.set_xlabel("frequency / forcing frequency")
    a3.set_ylabel("amplitude (um)")
    dlf = ds.attrs["dynamic_load_factor"]
    a3.set_title(
        f"spectrum (DLF {dlf:.3f})" if np.isfinite(dlf) else "spectrum (no mean load)",
        fontsize=9,
    )
    for ax in (a1, a2, a3):
        ax.grid(alpha=0.3)
    fig.suptitle(ds.attrs.get("title", ""), fontsize=10)
    return fig


def plot_transmission_error(result: ResponseResult) -> Figure:
    """Dynamic transmission error and mesh deflection over the last periods of a steady
    response (the design report's time history).

    Parameters
    ----------
    result : ResponseResult
        The steady response to draw.

    Returns
    -------
    matplotlib.figure.Figure
        One panel: the dynamic transmission error and the mesh deflection (um) against
        the time (ms) from the start of the kept history.
    """
    from matplotlib.figure import Figure

    ds = result.data
    fig = Figure(figsize=(9, 3), layout="constrained")
    ax = fig.subplots()
    t = ds["time"].values
    ax.plot((t - t[0]) * 1e3, ds["dte"].values * 1e6, lw=0.8, label="DTE")
    ax.plot((t - t[0]) * 1e3, ds["delta"].values * 1e6, lw=0.8, label="mesh deflection")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("um")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return fig


def plot_frequency_response(result: FrequencyResponseResult) -> Figure:
    """RMS DTE, dynamic load factor and separation share against the parameter, the
    ascending sweep solid, the descending one dashed.

    Parameters
    ----------
    result : FrequencyResponseResult
        The frequency-response curves to draw.

    Returns
    -------
    matplotlib.figure.Figure
        Three panels sharing the parameter axis, one line per sweep direction.
    """
    from matplotlib.figure import Figure

    from ..analysis.members import axis_label, shown_values

    ds = result.data
    fig = Figure(figsize=(7.5, 6.6), layout="constrained")
    axes = fig.subplots(3, 1, sharex=True)
    x = shown_values(ds["p0"])
    style = {"up": ("-o", "k", "ascending sweep"), "down": ("--x", "C3", "descending sweep")}
    for b in ds["branch"].values.tolist():
        fmt, colour, label = style[b]
        sel = ds.sel(branch=b)
        axes[0].plot(x, sel["rms_dte"].values * 1e6, fmt, color=colour, ms=3, label=label)
        axes[1].plot(x, sel["dynamic_load_factor"].values, fmt, color=colour, ms=3)
        axes[2].plot(x, 100 * sel["separation_fraction"].values, fmt, color=colour, ms=3)
    axes[0].set_ylabel("RMS dynamic TE (um)")
    axes[1].set_ylabel("dynamic load factor")
    axes[2].set_ylabel("teeth apart (% of time)")
    axes[2].set_xlabel(axis_label(ds["p0"], ds.attrs["parameter"]))
    axes[0].legend(fontsize=7)
    axes[0].set_title(f"frequency response: {ds.attrs.get('title', '')}", fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3)
    return fig
