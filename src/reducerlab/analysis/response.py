"""The steady nonlinear response of one design or model: time histories of the mesh
deflection, velocity and force over the last periods, the Poincaré points, the dynamic
load factor and a spectrum whose peaks are labelled as multiples of the forcing
frequency (paper 004 Fig. 8)."""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design
from ..drives import design_and_model
from ..dynamics.accuracy import ACCURACY
from ..dynamics.coordinates import static_state, to_system
from ..dynamics.ensemble import ensemble
from ..errors import DivergenceError, ReducerlabError, names_source
from ..model import Model
from ..model.laws import evaluate_flat, flat_mean
from ..results import Result, provenance
from .impacts import contact_states, mesh_mode
from .motion import Spectrum, spectrum_peaks, windowed_spectrum

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["NOISE_M", "ResponseResult", "response"]


#: Mesh deflections below 1 pm (1e-12 m) are round-off for a gear mesh: a millionth of
#: the micron-scale transmission errors and deflections of real gears. A response whose
#: deflection varies less has no spectrum, and one whose mean mesh force is below the
#: line's stiffness times this has no mean load (no dynamic load factor).
NOISE_M = 1e-12


class ResponseResult(Result):
    """Steady response of one design: time histories of the mesh deflection (dynamic
    transmission error along the line of action), its velocity and the mesh force over
    the last periods, the Poincaré points, and the dynamic load factor."""

    kind: ClassVar[str] = "response"

    def uniform_deflection(self) -> tuple[NDArray, float]:
        """The mesh deflection resampled on a uniform time grid (steps differ per
        segment), and that grid's time step (s)."""
        ds = self.data
        t = ds["time"].values
        tu = np.linspace(t[0], t[-1], t.size)
        return np.interp(tu, t, ds["delta"].values), float(tu[1] - tu[0])

    def peaks(self, count: int = 6) -> list[tuple[float, float]]:
        """Largest spectral peaks of the mesh deflection, as multiples of the forcing
        frequency (paper 004 Fig. 8 labels); none when the deflection varies by less than
        :data:`NOISE_M` (1 pm: round-off of a model that nothing excites)."""
        x, dt = self.uniform_deflection()
        if np.ptp(x) <= NOISE_M:
            return []
        return spectrum_peaks(x, dt, self.data.attrs["forcing_hz"], count)

    def spectrum(self, pad: int = 8) -> Spectrum:
        """The Hann-windowed spectrum of the mesh deflection the figures draw: over the
        whole kept history (its resolution 1 / record length, ``history`` periods),
        zero-padded ``pad`` times (:func:`reducerlab.analysis.motion.windowed_spectrum`).
        The labelled peaks (:meth:`peaks`) come from the same record unpadded."""
        x, dt = self.uniform_deflection()
        return windowed_spectrum(x, dt, pad)

    def plot(self) -> Figure:
        """Phase trajectory, Poincaré map and labelled spectrum (paper 004 Fig. 8)."""
        from ..plot.response import plot_response

        return plot_response(self)


@names_source
def response(
    target: Design | Model,
    *,
    periods: int = 600,
    keep: int = 100,
    history: int = 20,
    steps_per_period: int | None = None,
    line: int = 0,
    period: float | None = None,
    y0: NDArray[np.float64] | None = None,
    accuracy: float = ACCURACY,
) -> ResponseResult:
    """Steady nonlinear response of a design or model (compiled kernel, rigid motion
    removed): mesh deflection, its velocity, mesh force (and its elastic and damping
    parts) and dynamic load factor over the last ``history`` periods, and the Poincaré
    points of the last ``keep``. The attributes report the tooth separation over those
    periods (``analysis.impacts``: separation and back-contact time shares, contact
    losses and back-side impacts per period, impact class) and the mesh mode
    (``mesh_mode_hz``, the natural frequency that strains the line most, and
    ``frequency_ratio``, the forcing frequency over it: omega-bar).

    ``period`` (s) is the forcing (sampling) period; by default the period of the
    model's first periodic law (a model without one needs it). ``y0`` is the initial
    state ``(q, dq/dt)`` (2n,) in the coordinates of
    ``dynamics.coordinates.to_system(model)`` (the model's DOFs, less rigid motions when it
    has any); by default the static equilibrium under the mean loads. Where attractors
    coexist (gear rattle) the start decides which one the response settles on.
    ``accuracy`` is the target error of the Poincaré points relative to the motion's
    scale (``dynamics.accuracy.accurate_steps``; default 1e-6), used unless
    ``steps_per_period`` is given."""
    _, model = design_and_model(target, "response")
    if not (isinstance(history, int) and history >= 1):
        raise ReducerlabError(f"response: history must be >= 1 period, got {history!r}")
    flat = model.nonlinear()
    n_lines = flat.G.shape[0]
    if n_lines == 0:
        raise ReducerlabError(
            "response: the model has no mesh line: a nonlinear response needs at least "
            "one mesh (or cubic spring) element"
        )
    s = to_system(model, flat=flat)
    if isinstance(line, bool) or not isinstance(line, int) or not 0 <= line < n_lines:
        raise ReducerlabError(
            f"response: line must be a mesh line index in 0..{n_lines - 1} "
            f"({', '.join(s.line_names)}), got {line!r}"
        )
    label = repr(model.name) if model.name else "the model"
    if y0 is None:
        start = static_state(s)
    else:
        start = np.asarray(y0, dtype=float)
        if start.shape != (2 * s.n,) or not np.all(np.isfinite(start)):
            raise ReducerlabError(
                f"response: y0 must be {2 * s.n} finite numbers (q, dq/dt over "
                f"{', '.join(s.dof_names)}), got shape {start.shape}"
            )
    res = ensemble([s], periods=periods, keep=keep, history=history,
                   steps_per_period=steps_per_period, y0=start,
                   period=period, labels=[label], accuracy=accuracy)  # fmt: skip
    n = s.n
    t, H = res.history_time[0], res.history[0]
    g = s.G[line]
    e = np.array([evaluate_flat(int(s.e_kind[line]), s.e_params[line], ti) for ti in t])
    delta = H[:, :n] @ g - e[:, 0]
    dvel = H[:, n:] @ g - e[:, 1]
    parts = np.array(
        [
            [p[line] for p in s.mesh_force_parts(ti, y[:n], y[n:])]
            for ti, y in zip(t, H, strict=True)
        ]
    )
    elastic, damping = parts[:, 0], parts[:, 1]
    force = elastic + damping
    mean_force = float(np.mean(force))
    side = -1.0 if np.mean(elastic) < 0 else 1.0  # the loaded flanks: mean elastic force
    states = contact_states(delta, float(s.half_backlash[line]), float(history), side, t)
    mode_hz, mode_share = mesh_mode(s, line)
    # The dynamic load factor is defined against a mean load. Without one (no torque on
    # the model) the force is round-off (1e-15 N), and a ratio of round-off would pass
    # for a result: a mean force below the line's mean stiffness times 1 pm (NOISE_M,
    # a millionth of a micron-scale transmission error) counts as none, and the factor
    # is undefined (NaN), reported as such.
    k_line = abs(flat_mean(int(s.k_kind[line]), s.k_params[line]))
    loaded = abs(mean_force) > k_line * NOISE_M
    dlf = float(np.max(np.abs(force)) / abs(mean_force)) if loaded else float("nan")
    P = res.poincare[0, :keep]
    tP = (periods - keep + np.arange(keep)) * res.period[0]
    eP = np.array([evaluate_flat(int(s.e_kind[line]), s.e_params[line], ti) for ti in tP])
    data = xr.Dataset(
        {
            "delta": (
                "time",
                delta,
                {"units": "m", "long_name": "mesh deflection delta = G q - e (tooth compliance)"},
            ),
            "dte": (
                "time",
                H[:, :n] @ g,
                {
                    "units": "m",
                    "long_name": "dynamic transmission error G q along the line "
                    "of action (delta + e)",
                },
            ),
            "static_error": ("time", e[:, 0], {"units": "m", "long_name": "e(t)"}),
            "delta_velocity": ("time", dvel, {"units": "m/s"}),
            "mesh_force": (
                "time",
                force,
                {"units": "N", "long_name": "dynamic mesh force (elastic + damping)"},
            ),
            "elastic_force": (
                "time",
                elastic,
                {"units": "N", "long_name": "elastic (tooth) mesh force, 0 with the teeth apart"},
            ),
            "damping_force": (
                "time",
                damping,
                {"units": "N", "long_name": "viscous mesh force (acts across the gap too)"},
            ),
            "dynamic_load": (
                "time",
                force / mean_force if loaded else np.full_like(force, np.nan),
                {"units": "1", "long_name": "mesh force / mean mesh force"},
            ),
            "poincare_delta": ("point", P[:, :n] @ g - eP[:, 0], {"units": "m"}),
            "poincare_velocity": ("point", P[:, n:] @ g - eP[:, 1], {"units": "m/s"}),
        },
        coords={"time": ("time", t, {"units": "s"}), "point": np.arange(keep)},
        attrs={
            "title": model.name,
            "forcing_hz": float(1.0 / res.period[0]),
            "dynamic_load_factor": dlf,
            "mean_mesh_force": mean_force,
            "line": s.line_names[line],
            "half_backlash_m": float(s.half_backlash[line]),
            "steps_per_period": int(t.size // history),
            "accuracy": float(accuracy) if steps_per_period is None else float("nan"),
            "separation_fraction": states.separation_fraction,
            "back_contact_fraction": states.back_contact_fraction,
            "contact_losses_per_period": states.contact_losses,
            "back_impacts_per_period": states.back_impacts,
            "impact_class": states.impact_class,
            "mesh_mode_hz": mode_hz,
            "mesh_mode_share": mode_share,
            "frequency_ratio": float(1.0 / res.period[0]) / mode_hz
            if mode_hz > 0
            else float("nan"),
            **provenance(model.metadata),
        },
    )
    for name, var in data.data_vars.items():
        if not np.all(np.isfinite(var.values)) and name != "dynamic_load":
            raise DivergenceError(
                f"response: the {var.attrs.get('long_name', name)} is not finite (an extreme "
                "parameter value overflowed); check the loads, stiffnesses and inertias"
            )
    return ResponseResult(data)
