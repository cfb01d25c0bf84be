"""The members of a parameter sweep of the nonlinear engine: the flat systems (rigid
motion removed) of an axis's values, built per value or interpolated where they are
affine in it; sequential continuation over the values; the axis's coordinate and its
display unit. Shared by bifurcation diagrams, regime maps and frequency responses."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design, field_kind
from ..dynamics.coordinates import elastic_names, rigid_reduction, static_states, to_system
from ..dynamics.systems import at_rest
from ..errors import ReducerlabError
from ..model import Model, NonlinearSystem
from ..model.rigid import element_blocks
from ..units import display_unit
from .parameters import Axis, Evaluator, Target, axis_targets
from .policies import Continuation

__all__ = [
    "FLAT",
    "Members",
    "axis_coord",
    "axis_label",
    "axis_members",
    "continue_sweep",
    "fingerprint",
    "shown_values",
    "target_members",
]


def continue_sweep(
    members: Callable[[NDArray], list[NonlinearSystem]],
    values: NDArray,
    direction: str | Continuation,
    run: Callable[[NDArray, list[NonlinearSystem], NDArray], tuple[NDArray, NDArray]],
    progress: Callable[[int, int], None] | None,
) -> dict[str, NDArray]:
    """Sequential continuation: the rows ``run(chunk, systems, y0)`` returns (one per
    member, with the end states), in the order of ``values``, for the ascending
    (``"up"``) and/or descending (``"down"``) sweep, each value started from the end
    state of the previous one, the first from static equilibrium; the two sweeps run
    side by side as a two-member ensemble. ``direction``: ``"up"``, ``"down"`` or
    ``"both"`` (a :class:`~reducerlab.analysis.policies.Continuation` or its value)."""
    order = np.argsort(values, kind="stable")
    sweeps = {"up": order, "down": order[::-1]}
    names = Continuation(direction).directions
    out: dict[str, NDArray] = {}
    state: dict[str, NDArray | None] = dict.fromkeys(names)
    for step in range(values.size):
        idx = [int(sweeps[name][step]) for name in names]
        chunk = values[idx]
        systems = members(chunk)
        y0 = static_states(systems)
        for k, name in enumerate(names):
            if state[name] is not None and np.all(np.isfinite(state[name])):
                y0[k] = state[name]
        rows, ends = run(chunk, systems, y0)
        for k, name in enumerate(names):
            if name not in out:
                out[name] = np.full((values.size, rows.shape[1]), np.nan)
            out[name][idx[k]] = rows[k]
            state[name] = ends[k]
        if progress:
            progress(step + 1, values.size)
    return out


def axis_coord(design: Design | None, axis: Axis, values: NDArray) -> dict[str, Any]:
    """Attributes of a parameter coordinate: its path, its unit inside (SI) and the unit
    figures show it in (``display_unit``, ``display_factor``: rpm for a speed, um or mm
    for a length, deg for an angle; :func:`reducerlab.units.display_unit`)."""
    path = axis.path.split("+")[0].strip().removeprefix("design:")
    kind = field_kind(design, path) if design is not None and ":" not in path else None
    unit, factor = display_unit(kind, values)
    return {"path": axis.path, "units": "SI", "display_unit": unit, "display_factor": factor}


def axis_label(coord: xr.DataArray, name: str) -> str:
    """``name (unit)`` for a coordinate with display attributes, else ``name``."""
    unit = coord.attrs.get("display_unit", "")
    return f"{name} ({unit})" if unit else name


def shown_values(coord: xr.DataArray) -> NDArray:
    """A coordinate's values in its display unit."""
    return coord.values * coord.attrs.get("display_factor", 1.0)


def axis_members(
    design: Design | None, model: Model, axis: Axis, what: str
) -> tuple[NDArray, Members, NonlinearSystem]:
    """The SI values of ``axis``, the flat systems (rigid motion removed) of its values
    and the base flat system of the model."""
    group, values = axis_targets(design, model, axis, 0, what)
    members, base = target_members(design, model, group, what)
    return values, members, base


def target_members(
    design: Design | None,
    model: Model,
    targets: list[Target] | tuple[Target, ...],
    what: str = "sweep",
) -> tuple[Members, NonlinearSystem]:
    """The flat systems (rigid motion removed, one transform for all) of the model at
    values of ``targets``, and the model's base flat system."""
    base = model.nonlinear()
    rest = at_rest(model)
    members = Members(
        Evaluator(design, model, tuple(targets), what),
        rigid_reduction(rest if rest is not None else base, element_blocks(model)),
    )
    return members, base


def fingerprint(s: NonlinearSystem) -> str:
    """Hash of a system's flat arrays (identifies the run in a resume folder)."""
    import hashlib

    h = hashlib.sha256()
    for a in (getattr(s, f) for f in NonlinearSystem.ARRAYS):
        h.update(np.ascontiguousarray(a, dtype=float).tobytes())
    return h.hexdigest()[:16]


#: The flat arrays of a system that :class:`Members` interpolates when they are affine in
#: the value.
FLAT = NonlinearSystem.ARRAYS


@dataclass
class Members:
    """Flat systems (rigid motion removed) of parameter values: the model rebuilt per
    value, or, when every flat array is affine in the value (checked at both ends and
    two interior points), interpolated from the two ends: exact, and no rebuilds."""

    ev: Evaluator
    T: NDArray | None  # rigid-motion reduction of the base model, shared by the members
    affine: tuple[float, NonlinearSystem, dict[str, NDArray]] | None = None
    fixed: tuple[float, ...] = ()  # values of the evaluator's further axes (regime maps)

    def one(self, v: float) -> NonlinearSystem:
        model = self.ev.model_at([v, *self.fixed])
        s = model.nonlinear()
        if self.T is not None:
            rest = at_rest(model)
            try:
                return s.reduced(
                    self.T,
                    elastic_names(self.T),
                    rest_stiffness=None if rest is None else rest.K,
                )[0]
            except ReducerlabError:  # the value changed the rigid motion itself
                pass
        return to_system(model, flat=s)

    def probe(self, lo: float, hi: float) -> None:
        """Detect affine dependence on the value over [lo, hi]."""
        if not hi > lo:
            return
        pts = [lo, hi, lo + 0.37 * (hi - lo), lo + 0.61 * (hi - lo)]
        try:
            ss = [self.one(p) for p in pts]
        except ReducerlabError:
            return  # let the per-value path report the failing value
        base, top = ss[0], ss[1]
        for o in ss[1:]:
            if o.dof_names != base.dof_names or any(
                not np.array_equal(getattr(o, k), getattr(base, k))
                for k in ("k_kind", "e_kind", "f_kind")
            ):
                return
            if any(getattr(o, f).shape != getattr(base, f).shape for f in FLAT):
                return
        d = {f: (getattr(top, f) - getattr(base, f)) / (hi - lo) for f in FLAT}
        for p, o in zip(pts[2:], ss[2:], strict=True):
            for f in FLAT:
                # element by element (an array may mix periods in ms with stiffness
                # coefficients in 1e8 N/m): relative to the element's own size
                got = getattr(o, f)
                want = getattr(base, f) + (p - lo) * d[f]
                size = np.maximum.reduce(
                    [np.abs(got), np.abs(want), np.abs(getattr(base, f)), np.abs(getattr(top, f))]
                )
                if np.any(np.abs(got - want) > 1e-11 * size):
                    return
        self.affine = (lo, base, d)

    def __call__(self, chunk: NDArray) -> list[NonlinearSystem]:
        if self.affine is None:
            return [self.one(float(v)) for v in chunk]
        lo, base, d = self.affine
        return [
            replace(base, **{f: getattr(base, f) + (float(v) - lo) * d[f] for f in FLAT})
            for v in chunk
        ]
