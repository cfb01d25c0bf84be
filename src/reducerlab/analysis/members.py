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

from ..design import Design
from ..dynamics.coordinates import elastic_names, rigid_reduction, static_states, to_system
from ..dynamics.systems import at_rest
from ..errors import ReducerlabError
from ..model import Model, NonlinearSystem
from ..model.rigid import element_blocks
from ..units import display_unit
from .parameters import Axis, Evaluator, Target, axis_targets, parameter_kind
from .policies import Continuation

__all__ = [
    "FLAT",
    "FORMS",
    "Fit",
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


def axis_coord(
    design: Design | None, axis: Axis, values: NDArray, model: Model | None = None
) -> dict[str, Any]:
    """Attributes of a parameter coordinate: its path, its unit inside (SI) and the unit
    figures show it in (``display_unit``, ``display_factor``: rpm for a speed, um or mm
    for a length, deg for an angle, else the SI unit such as N/m;
    :func:`reducerlab.units.display_unit`), the quantity found for a design field or,
    with ``model`` given, a model parameter
    (:func:`reducerlab.analysis.parameters.parameter_kind`)."""
    kind = parameter_kind(design, model, axis.path)
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


#: The flat arrays of a system that :class:`Members` interpolates when they follow the
#: value in a known form.
FLAT = NonlinearSystem.ARRAYS

#: Relative tolerance, element by element, of the probe that accepts a form: round-off
#: of the few operations that build a system, far below any physical effect.
FIT_TOL = 1e-11


#: The forms a sweep's flat arrays may follow, as powers of ``u = v / ref``: affine
#: (damping, backlash, error amplitudes, stiffness values...), and the forms a speed
#: ``v`` enters in: law frequencies (``v``), periods and loads at constant power
#: (``1 / v``), gyroscopic terms (``v``), centrifugal stiffening and drag (``v^2``).
FORMS = {"affine": (0, 1), "speed": (0, 1, 2, -1)}


@dataclass(frozen=True)
class Fit:
    """The flat arrays of a sweep's members as functions of the value ``v``:
    ``X(v) = sum_p X_p u^p`` element by element over the powers ``p`` of
    :data:`FORMS` ``[form]``, ``u = v / ref``; elements equal at every probe point are
    kept as they are (law rows hold piece counts that must stay exact integers)."""

    form: str
    ref: float
    base: NonlinearSystem
    coef: dict[str, tuple[NDArray, NDArray]]  # varying mask, X_p (powers, elements)

    def at(self, v: float) -> NonlinearSystem:
        """The members' system at the value ``v``."""
        u = float(v) / self.ref
        powers = np.array([u**p for p in FORMS[self.form]])
        out = {}
        for f, (mask, c) in self.coef.items():
            a = getattr(self.base, f).copy()
            a[mask] = powers @ c
            out[f] = a
        return replace(self.base, **out)


def _fit(points: list[float], systems: list[NonlinearSystem], form: str) -> Fit | None:
    """The :class:`Fit` of ``form`` through the first probe systems (as many as the form
    has powers), or None when any other probe point leaves it (beyond :data:`FIT_TOL`
    of the element's own size) or the systems differ in shape or kind."""
    base = systems[0]
    for o in systems[1:]:
        if o.dof_names != base.dof_names or any(
            not np.array_equal(getattr(o, k), getattr(base, k))
            for k in ("k_kind", "e_kind", "f_kind")
        ):
            return None
        if any(getattr(o, f).shape != getattr(base, f).shape for f in FLAT):
            return None
    powers = FORMS[form]
    n_fit = len(powers)
    if len(points) <= n_fit:
        raise ValueError("_fit: the form needs points beyond those that fix it")
    ref = 0.5 * (abs(points[0]) + abs(points[1]))
    u = np.asarray(points, float) / ref
    basis = np.stack([u**p for p in powers], axis=1)
    solve = np.linalg.inv(basis[:n_fit])
    coef = {}
    for f in FLAT:
        stack = np.stack([getattr(s, f) for s in systems])
        mask = np.any(stack != stack[0], axis=0)
        if not mask.any():
            continue
        vals = stack[:, mask]  # (points, varying elements)
        c = solve @ vals[:n_fit]
        # element by element (a row may mix periods in ms with stiffness coefficients in
        # 1e8 N/m): relative to the element's own size over the probe points
        size = np.abs(vals).max(axis=0)
        if np.any(np.abs(basis @ c - vals) > FIT_TOL * size):
            return None
        coef[f] = (mask, c)
    return Fit(form, ref, base, coef)


@dataclass
class Members:
    """Flat systems (rigid motion removed) of parameter values: the model rebuilt per
    value, or, when every flat array follows the value in a known form (checked element
    by element at probe points beyond those that fix it: :data:`FORMS`), evaluated from
    that form: exact to round-off, and no rebuilds."""

    ev: Evaluator
    T: NDArray | None  # rigid-motion reduction of the base model, shared by the members
    fit: Fit | None = None
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
        """Find the form in which the flat arrays follow the value over [lo, hi]
        (:data:`FORMS`): affine (built at four points: two fix it, two check it), else,
        for a positive range, the speed form (three more points: four fix it, three
        check it). Leaves :attr:`fit` None (one build per value) when neither holds."""
        if not hi > lo:
            return
        at = [0.0, 1.0, 0.37, 0.61, 0.13, 0.83, 0.5]
        pts = [lo + a * (hi - lo) for a in at]
        try:
            ss = [self.one(p) for p in pts[:4]]
            self.fit = _fit(pts[:4], ss, "affine")
            if self.fit is not None or lo <= 0.0:
                return
            ss += [self.one(p) for p in pts[4:]]
        except ReducerlabError:
            return  # let the per-value path report the failing value
        self.fit = _fit(pts, ss, "speed")

    def __call__(self, chunk: NDArray) -> list[NonlinearSystem]:
        if self.fit is None:
            return [self.one(float(v)) for v in chunk]
        return [self.fit.at(float(v)) for v in chunk]
