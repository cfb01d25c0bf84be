"""Nonlinear dynamics over a parameter: bifurcation diagrams (Poincaré points of the
steady state against a design field or model parameter), and single-run responses
with spectra whose peaks are labelled as multiples of the mesh frequency."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design
from ..errors import ReducerlabError
from ..model import Model
from ..results import Result, provenance
from .response import ensemble, to_system
from .sweep import Axis, _Evaluator, _resolve

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["BifurcationResult", "bifurcation", "classify", "spectrum_peaks"]


def bifurcation(
    target: Design | Model,
    axis: Axis,
    *,
    periods: int = 600,
    keep: int = 100,
    steps_per_period: int | None = None,
    line: int = 0,
    scale: float = 1e-6,
    chunk_size: int = 250,
    progress: Callable[[int, int], None] | None = None,
) -> BifurcationResult:
    """Bifurcation diagram: Poincaré points of a mesh deflection against a parameter.

    For each value the model is rebuilt (design fields) or changed (model parameters),
    its rigid motion removed, and the ensemble integrated by the compiled RK4 kernel for
    ``periods`` forcing periods; the last ``keep`` stroboscopic points of mesh ``line``'s
    deflection ``delta = G q - e`` are kept (paper 004 Fig. 7, 9, 11), in units of
    ``scale`` (m; 1 um = paper 004's b_c).
    """
    from ..drives import build_model

    if isinstance(target, Design):
        design, model = target, build_model(target)
    elif isinstance(target, Model):
        design, model = None, target
    else:
        raise ReducerlabError("bifurcation: target must be a Design or a Model")
    t = _resolve(design, model, axis.path)
    vals = [float(v) * (t.base if axis.relative else 1.0) for v in axis.values]
    if any(isinstance(v, str) for v in axis.values):
        raise ReducerlabError("bifurcation: give SI numbers for the values")
    ev = _Evaluator(design.model_dump(mode="python") if design else None, model, (t,))
    values = np.asarray(vals, float)
    n_lines = model.nonlinear().G.shape[0]
    if not 0 <= line < n_lines:
        raise ReducerlabError(f"bifurcation: line must be in 0..{n_lines - 1}, got {line}")
    points = np.empty((values.size, keep))
    chunks = [values[i : i + chunk_size] for i in range(0, values.size, chunk_size)]
    done = 0
    for chunk in chunks:
        systems = [to_system(ev.model_at([v])) for v in chunk]
        res = ensemble(
            systems, periods=periods, keep=keep, steps_per_period=steps_per_period,
            labels=[f"{axis.path} = {v:.6g}" for v in chunk],
        )  # fmt: skip
        points[done : done + len(chunk)] = res.delta_poincare[:, :keep, line] / scale
        done += len(chunk)
        if progress:
            progress(done, values.size)
    data = xr.Dataset(
        {
            "poincare": (
                ("p0", "point"),
                points,
                {"units": f"{scale:g} m", "long_name": "mesh deflection"},
            )
        },
        coords={"p0": ("p0", values, {"path": axis.path}), "point": np.arange(keep)},
        attrs={
            "title": (design.name if design else model.name) or "bifurcation",
            "parameter": axis.path,
            "periods": periods,
            "keep": keep,
            "line": line,
            **provenance(model.metadata),
        },
    )
    return BifurcationResult(data)


class BifurcationResult(Result):
    """Poincaré points (p0, point) of a mesh deflection against the parameter ``p0``."""

    kind: ClassVar[str] = "bifurcation"

    def periodicity(self, tol: float = 1e-3, max_period: int = 12) -> NDArray[np.int64]:
        """Smallest n <= max_period such that the Poincaré sequence repeats every n
        points (to ``tol`` of its range), else 0 (not periodic within max_period)."""
        pts = self.data["poincare"].values
        return np.array([_period_of(row, tol, max_period) for row in pts], dtype=np.int64)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary."""
        ds = self.data
        return {
            "parameter": ds.attrs["parameter"],
            "values": ds["p0"].values.tolist(),
            "period": self.periodicity().tolist(),
        }

    def plot(self) -> Figure:
        """Bifurcation diagram (paper 004 Fig. 7)."""
        from matplotlib.figure import Figure

        ds = self.data
        fig = Figure(figsize=(7.5, 4.2), layout="constrained")
        ax = fig.subplots()
        p = np.repeat(ds["p0"].values, ds.sizes["point"])
        ax.plot(p, ds["poincare"].values.ravel(), ",k", alpha=0.6)
        ax.set_xlabel(ds.attrs["parameter"])
        ax.set_ylabel(f"Poincaré points of mesh deflection ({ds['poincare'].attrs['units']})")
        ax.set_title(f"bifurcation diagram: {ds.attrs.get('title', '')}", fontsize=9)
        ax.grid(alpha=0.3)
        return fig


def _period_of(row: NDArray, tol: float, max_period: int) -> int:
    span = max(np.ptp(row), np.abs(row).max(), 1e-300)
    for n in range(1, max_period + 1):
        if np.all(np.abs(row[n:] - row[:-n]) <= tol * span):
            return n
    return 0


def classify(
    poincare: NDArray[np.float64],
    exponent: float,
    frequency: float,
    *,
    tol: float = 1e-3,
    max_period: int = 12,
    chaos: float = 0.01,
) -> str:
    """Label a steady motion from its Poincaré points and largest Lyapunov exponent.

    ``"chaotic"`` when the exponent exceeds ``chaos`` x the forcing frequency (1/s per
    Hz: a separation growing by e within ~100 periods), else ``"period-n"`` when the
    Poincaré sequence repeats every n <= ``max_period`` points (to ``tol`` of its
    range), else ``"quasi-periodic"``.
    """
    if exponent > chaos * frequency:
        return "chaotic"
    n = _period_of(np.asarray(poincare, float), tol, max_period)
    return f"period-{n}" if n else "quasi-periodic"


def spectrum_peaks(
    signal: NDArray[np.float64], dt: float, f_ref: float, count: int = 6
) -> list[tuple[float, float]]:
    """Largest spectral peaks of ``signal`` as ``(multiple of f_ref, amplitude)``, the
    labelling of paper 004 Fig. 8 ("0.48x, 0.57x, ...")."""
    x = np.asarray(signal, float) - np.mean(signal)
    amp = 2 * np.abs(np.fft.rfft(x * np.hanning(x.size))) / np.sum(np.hanning(x.size))
    f = np.fft.rfftfreq(x.size, dt)
    peaks = [i for i in range(1, amp.size - 1) if amp[i] >= amp[i - 1] and amp[i] > amp[i + 1]]
    peaks.sort(key=lambda i: -amp[i])
    return [(float(f[i] / f_ref), float(amp[i])) for i in peaks[:count]]
