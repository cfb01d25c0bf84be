"""Frequency-response curves of the nonlinear response, swept up and down (issue 16).

The classic gear-rattle plot (Kahraman and Singh, J. Sound Vib. 142, 1990, 49-75;
Theodossiades and Natsiavas, J. Sound Vib. 229, 2000): the RMS and peak-to-peak dynamic
transmission error and the dynamic load factor of the steady motion against a parameter
(usually the speed), swept in ascending and in descending order with each value started
from the state the previous one ended in (sequential continuation). Where a no-impact
and an impacting motion coexist the two sweeps differ, and the curves jump where one of
them ceases to exist.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design
from ..drives import design_and_model
from ..dynamics.accuracy import ACCURACY
from ..dynamics.ensemble import ensemble
from ..dynamics.guards import check_stability
from ..dynamics.runsize import AUTO_STEPS_FLOOR, run_estimate
from ..errors import ReducerlabError
from ..model import Model
from ..numformat import Column, Table
from ..results import Result, provenance
from .impacts import contact_states, mesh_mode
from .members import axis_coord, axis_members, continue_sweep, shown_values
from .parameters import Axis
from .policies import Continuation

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["FrequencyResponseResult", "frequency_response"]

#: Quantities per value and branch: name, unit, long name.
QUANTITIES = (
    ("rms_dte", "m", "RMS of the dynamic transmission error about its mean"),
    ("ptp_dte", "m", "peak-to-peak dynamic transmission error"),
    ("dynamic_load_factor", "1", "largest |mesh force| / mean mesh force"),
    ("separation_fraction", "1", "share of the time with the teeth apart"),
    ("back_impacts", "1/period", "back-side impacts per period"),
    ("frequency_ratio", "1", "forcing frequency / mesh mode frequency (omega-bar)"),
)


class FrequencyResponseResult(Result):
    """RMS / peak-to-peak dynamic transmission error, dynamic load factor and tooth
    separation of the steady motion against a parameter, per sweep direction
    (``branch``: ``up``, ``down``)."""

    kind: ClassVar[str] = "frequency-response"

    def to_dict(self) -> dict[str, Any]:
        ds = self.data
        out: dict[str, Any] = {
            "parameter": ds.attrs["parameter"],
            "values": ds["p0"].values.tolist(),
            "display_unit": ds["p0"].attrs.get("display_unit", ""),
            "display_values": [float(f"{x:.12g}") for x in shown_values(ds["p0"])],
        }
        for b in ds["branch"].values.tolist():
            out[b] = {name: ds[name].sel(branch=b).values.tolist() for name, _, _ in QUANTITIES}
        return out

    def table(self) -> str:
        """One line per value (in its display unit) and sweep direction: RMS dynamic
        transmission error (um), dynamic load factor, share of the time with the teeth
        apart (%)."""
        ds = self.data
        c = ds["p0"]
        unit = c.attrs.get("display_unit", "") or "SI"
        t = Table([Column("value", unit, "parameter"), Column("sweep", kind="text"),
                   Column("RMS DTE", "um", "length"), Column("load factor"),
                   Column("teeth apart", "%", "percent")],
                  title=f"frequency response over {ds.attrs['parameter']}: "
                  f"{c.size} values")  # fmt: skip
        for i, v in enumerate(shown_values(c)):
            for b in ds["branch"].values.tolist():
                at = ds.sel(branch=b).isel(p0=i)
                t.add(v, b, 1e6 * float(at["rms_dte"]), float(at["dynamic_load_factor"]),
                      100 * float(at["separation_fraction"]))  # fmt: skip
        return t.text()

    def plot(self) -> Figure:
        """RMS DTE, dynamic load factor and separation share against the parameter, the
        ascending sweep solid, the descending one dashed."""
        from ..plot.response import plot_frequency_response

        return plot_frequency_response(self)


def frequency_response(
    target: Design | Model,
    axis: Axis,
    *,
    periods: int = 300,
    history: int = 10,
    line: int = 0,
    continuation: str = "both",
    accuracy: float = ACCURACY,
    progress: Any = None,
) -> FrequencyResponseResult:
    """Frequency-response curves of mesh line ``line`` over the values of ``axis``.

    Each value is integrated for ``periods`` forcing periods (the last ``history`` are
    measured); in each sweep direction (``continuation``: ``"up"``, ``"down"`` or
    ``"both"``, the two run side by side) a value starts from the state the previous one
    ended in, the first from static equilibrium. Per value and direction: RMS and
    peak-to-peak dynamic transmission error ``G q`` along the line, dynamic load factor
    (NaN without a mean mesh force), share of the time with the teeth apart and
    back-side impacts per period (``analysis.impacts``). A value whose motion diverges
    is NaN. Values may carry units and paths may be tied, as in ``sweep``.
    """
    design, model = design_and_model(target, "frequency_response")
    continuation = Continuation.parse(
        continuation,
        "frequency_response",
        (Continuation.UP, Continuation.DOWN, Continuation.BOTH),
    ).value
    for name, v, lo in (("periods", periods, 2), ("history", history, 1)):
        if isinstance(v, bool) or not isinstance(v, int) or v < lo:
            raise ReducerlabError(f"frequency_response: {name} must be an integer >= {lo}")
    if history > periods:
        raise ReducerlabError("frequency_response: history must be <= periods")
    values, members, base = axis_members(design, model, axis, "frequency-response")
    if not 0 <= line < base.G.shape[0]:
        raise ReducerlabError(
            f"frequency_response: line must be in 0..{base.G.shape[0] - 1}, got {line}"
        )
    directions = 2 if continuation == Continuation.BOTH.value else 1
    run_estimate("frequency-response", values.size * directions, periods, AUTO_STEPS_FLOOR,
                 base.n, base.G.shape[0], 1, 0, at_least=True,
                 control="--periods or the number of values").check()  # fmt: skip
    if values.size > 8:  # law values that follow the speed in a known form: no rebuilds
        members.probe(float(values.min()), float(values.max()))
    ends = np.unique([values.min(), values.max()])
    check_stability(members(ends), [f"{axis.path} = {v:.6g}" for v in ends])

    def run(chunk: NDArray, systems: list, y0: NDArray) -> tuple[NDArray, NDArray]:
        res = ensemble(systems, periods=periods, keep=1, history=history, y0=y0,
                       accuracy=accuracy, on_divergence="mark",
                       labels=[f"{axis.path} = {v:.6g}" for v in chunk])  # fmt: skip
        rows = np.full((len(systems), len(QUANTITIES)), np.nan)
        for k, s in enumerate(systems):
            if not res.diverged[k]:
                rows[k] = _measures(s, res, k, line, history)
        return rows, res.poincare[:, -1]

    out = continue_sweep(members, values, continuation, run, progress)
    names = list(out)
    data = xr.Dataset(
        {
            name: (
                ("branch", "p0"),
                np.stack([out[n][:, q] for n in names]),
                {"units": unit, "long_name": long},
            )
            for q, (name, unit, long) in enumerate(QUANTITIES)
        },
        coords={"branch": names, "p0": ("p0", values, axis_coord(design, axis, values, model))},
        attrs={
            "title": (design.name if design else model.name) or "frequency response",
            "parameter": axis.path,
            "periods": periods,
            "history": history,
            "line": base.line_names[line],
            "continuation": continuation,
            **provenance(model.metadata),
        },
    )
    return FrequencyResponseResult(data)


def _measures(s, res, k: int, line: int, history: int) -> NDArray:
    """The QUANTITIES of member ``k`` of an ensemble run with history."""
    n = s.n
    t = res.history_time[k]
    H = res.history[k]
    dte = H[:, :n] @ s.G[line]
    delta = res.delta_history[k, :, line]
    parts = np.array([[p[line] for p in s.mesh_force_parts(ti, y[:n], y[n:])]
                      for ti, y in zip(t, H, strict=True)])  # fmt: skip
    elastic, force = parts[:, 0], parts[:, 0] + parts[:, 1]
    mean = float(np.mean(force))
    k_scale = float(np.max(np.abs(elastic))) if elastic.size else 0.0
    dlf = (
        float(np.max(np.abs(force)) / abs(mean))
        if abs(mean) > 1e-12 * max(k_scale, 1e-300)
        else np.nan
    )
    side = -1.0 if np.mean(elastic) < 0 else 1.0
    st = contact_states(delta, float(s.half_backlash[line]), float(history), side, t)
    mode_hz, _ = mesh_mode(s, line)
    return np.array([
        float(np.sqrt(np.mean((dte - dte.mean()) ** 2))),
        float(np.ptp(dte)),
        dlf,
        st.separation_fraction,
        st.back_impacts,
        1.0 / float(res.period[k]) / mode_hz if mode_hz > 0 else np.nan,
    ])  # fmt: skip
