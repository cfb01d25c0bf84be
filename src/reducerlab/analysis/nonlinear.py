"""Nonlinear dynamics over a parameter: bifurcation diagrams (Poincaré points of the
steady state against a design field or model parameter), and single-run responses
with spectra whose peaks are labelled as multiples of the mesh frequency."""

from __future__ import annotations

import contextlib
import itertools
import os
import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design, field_kind
from ..errors import DivergenceError, ReducerlabError, names_source
from ..model import Model, NonlinearSystem
from ..results import Result, provenance
from ..units import display_unit, length_unit
from .impacts import IMPACT_CLASSES, contact_states, mesh_mode
from .modal import element_blocks
from .response import (
    ACCURACY,
    at_rest,
    check_stability,
    elastic_names,
    ensemble,
    forcing_period,
    rigid_reduction,
    seed_states,
    static_state,
    static_states,
    to_system,
)
from .runfolder import chunk_path, load_chunk, open_run, save_chunk
from .sweep import Axis, _Evaluator, axis_targets
from .workers import check_workers, dask_client, worker_pool

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "BifurcationResult",
    "ResponseResult",
    "bifurcation",
    "classify",
    "response",
    "spectrum_peaks",
]


@names_source
def bifurcation(
    target: Design | Model,
    axis: Axis,
    *,
    periods: int = 600,
    keep: int = 100,
    steps_per_period: int | None = None,
    period: float | None = None,
    line: int = 0,
    scale: float = 1e-6,
    chunk_size: int = 250,
    output: str | Path | None = None,
    scheduler: Any = None,
    exponents: bool = False,
    progress: Callable[[int, int], None] | None = None,
    workers: int | None = None,
    accuracy: float = ACCURACY,
    continuation: str | None = None,
    seeds: int = 0,
    seed: int = 0,
) -> BifurcationResult:
    """Bifurcation diagram: Poincaré points of a mesh deflection against a parameter.

    For each value the model is rebuilt (design fields) or changed (model parameters),
    its rigid motion removed, and the ensemble integrated by the compiled RK4 kernel for
    ``periods`` forcing periods from static equilibrium under the mean mesh stiffness;
    the last ``keep`` stroboscopic points of mesh ``line``'s
    deflection ``delta = G q - e`` are kept (paper 004 Fig. 7, 9, 11), in units of
    ``scale`` (m; 1 um = paper 004's b_c). ``period`` (s) is the forcing (sampling)
    period; by default the period of the model's first periodic law (a model without
    one needs it). Unless ``steps_per_period`` is given, each chunk's step count is the
    smallest that meets ``accuracy`` (target error of the Poincaré points relative to
    the motion's scale, default 1e-6; ``analysis.response.accurate_steps``).

    With ``continuation`` (``"up"``, ``"down"`` or ``"both"``) the values are swept in
    ascending (descending) order and each starts from the state the previous one ended
    in (sequential continuation: it follows one attractor through the range, so jumps and
    hysteresis show where attractors coexist); ``"both"`` runs the two sweeps side by
    side and stores the descending one as ``poincare_down`` (and ``exponent_down``).
    The first value starts from static equilibrium. A continuation run is sequential
    and not resumable (``output``, ``scheduler`` and ``workers`` are not used).

    With ``output``, every finished chunk of parameter values is written to
    ``output/chunks/`` at once (atomically, stamped with the run key, its index and its
    values) and a re-run with the same arguments checks those and computes only the
    missing chunks; with ``scheduler`` (a Dask address or client) the chunks run on the
    cluster. With ``exponents``, the largest Lyapunov exponent of every value is
    computed over the kept periods and :meth:`BifurcationResult.labels` / the figure's
    band give period-n, quasi-periodic or chaotic.

    With ``seeds``, every value is also integrated from that many random starts around
    its static equilibrium (:func:`~reducerlab.analysis.response.seed_states`; the
    generator is seeded by ``seed`` and the value, so a value gets the same starts in
    any chunk): ``poincare_seeds`` (p0, seed, point), with ``exponents`` also
    ``exponent_seeds``, and ``impact_class_seeds``; :meth:`BifurcationResult.coexisting`
    marks the values where a seed found another attractor than the main run.

    Flat systems are built once per value, unless every flat array is affine in the
    value (checked at four values: then they are interpolated, exactly). Per-value
    builds (Python) run in ``workers`` forked processes (default: one per core when
    there are at least 200 values; 1 = in this process), overlapped with the compiled
    integration of the previous chunk.
    """
    design, model = design_and_model(target, "bifurcation")
    values, members, base = axis_members(design, model, axis, "bifurcation")
    n_lines = base.G.shape[0]
    if not 0 <= line < n_lines:
        raise ReducerlabError(f"bifurcation: line must be in 0..{n_lines - 1}, got {line}")
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1:
        raise ReducerlabError(f"chunk_size must be a positive integer, got {chunk_size!r}")
    if continuation not in (None, "up", "down", "both"):
        raise ReducerlabError(f"continuation must be 'up', 'down' or 'both', got {continuation!r}")
    for name, v in (("seeds", seeds), ("seed", seed)):
        if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v <= 2**31:
            raise ReducerlabError(f"bifurcation: {name} must be an integer >= 0, got {v!r}")
    if continuation is not None:
        output = scheduler = None  # sequential, not resumable
        workers = 1
    if workers is None:
        workers = (os.cpu_count() or 1) if values.size >= 200 else 1
    check_workers(workers, "bifurcation")
    chunks = [values[i : i + chunk_size] for i in range(0, values.size, chunk_size)]
    folder = Path(output) if output is not None else None
    key = ""
    if folder is not None:
        spec = {"path": axis.path, "values": values.tolist(), "periods": periods, "keep": keep,
                "steps": steps_per_period, "line": line, "chunk": chunk_size,
                "exponents": bool(exponents), "scale": scale, "model": _fingerprint(base),
                "design": design.hash if design else None}  # fmt: skip
        if period is not None:  # only when given: earlier run folders keep their key
            spec["period"] = period
        if steps_per_period is None:  # the step count follows the accuracy (issue 16)
            spec["accuracy"] = accuracy
        if seeds:
            spec["seeds"], spec["seed"] = seeds, seed
        key = open_run(folder, "bifurcation.json", spec, "bifurcation run")

    def chunk_file(i: int) -> Path | None:
        return None if folder is None else chunk_path(folder, i)

    results: dict[int, NDArray] = {}
    todo = []
    for i in range(len(chunks)):  # finished chunks are checked before any new work
        f = chunk_file(i)
        if f is not None and f.exists():
            results[i] = load_chunk(f, key, i, chunks[i], ("poincare",))["poincare"]
        else:
            todo.append(i)
    if continuation is not None:  # one sequential job instead of the chunks
        chunks, results, todo = [values], {}, []
    if values.size > 8 and (todo or continuation):
        members.probe(float(values.min()), float(values.max()))
    if todo or continuation:  # a divergent linear part at either end fails at once
        ends = np.unique([values[0], values[-1]])
        check_stability(members(ends), [f"{axis.path} = {v:.6g}" for v in ends])
    job = _BifurcationChunk(
        members, axis.path, periods, keep, steps_per_period, line, scale, bool(exponents),
        period, accuracy, seeds, seed,
    )  # fmt: skip
    done = sum(len(chunks[i]) for i in results)
    if progress:
        progress(done, values.size)

    def finish(i: int, points: NDArray) -> None:
        nonlocal done
        results[i] = points
        f = chunk_file(i)
        if f is not None:
            save_chunk(f, key, i, chunks[i], {"poincare": points})
        done += len(chunks[i])
        if progress:
            progress(done, values.size)

    branches: dict[str, NDArray] = {}
    if continuation is not None:
        branches = _continue(
            members, values, continuation,
            lambda chunk, systems, y0: job.integrate(chunk, systems, y0=y0, with_end=True),
            progress,
        )  # fmt: skip
        results[0] = branches["up" if continuation != "down" else "down"]
    if scheduler is not None and todo:
        from dask.distributed import as_completed

        with dask_client(scheduler, "bifurcation") as client:
            futures = {client.submit(job, chunks[i], pure=False): i for i in todo}
            for fut in as_completed(futures):
                finish(futures[fut], fut.result())
    elif todo:
        forked = workers > 1 and members.affine is None
        # fork: the children only build models (no compiled parallel code runs in them)
        # and start without re-importing; they end with this process (see .workers), and
        # at once when this block raises (Ctrl-C, SIGTERM): the written chunks stay
        with worker_pool(workers, "fork") if forked else contextlib.nullcontext() as pool:

            def submit(i: int) -> list:
                parts = np.array_split(chunks[i], workers)
                return [pool.submit(members, part) for part in parts if part.size]

            pending = submit(todo[0]) if pool else None
            for k, i in enumerate(todo):
                if pool is None:
                    systems = members(chunks[i])
                else:
                    systems = [s for fut in pending for s in fut.result()]
                    if k + 1 < len(todo):
                        pending = submit(todo[k + 1])  # built while this chunk integrates
                finish(i, job.integrate(chunks[i], systems))
    points = np.concatenate([results[i] for i in range(len(chunks))])
    n_imp = len(IMPACT_COLUMNS)
    n_main = keep + bool(exponents) + n_imp
    points, extra = points[:, :n_main], points[:, n_main:]
    impacts, points = points[:, -n_imp:], points[:, :-n_imp]
    exponent = points[:, keep] if exponents else None
    points = points[:, :keep]
    data = xr.Dataset(
        {
            "poincare": (
                ("p0", "point"),
                points,
                {"units": length_unit(scale), "long_name": "mesh deflection"},
            )
        },
        coords={"p0": ("p0", values, axis_coord(design, axis, values)), "point": np.arange(keep)},
        attrs={
            "title": (design.name if design else model.name) or "bifurcation",
            "parameter": axis.path,
            "periods": periods,
            "keep": keep,
            "line": line,
            "forcing_hz": 1.0 / (forcing_period(base) if period is None else period),
            **provenance(model.metadata),
        },
    )
    if exponent is not None:
        data["exponent"] = (
            "p0",
            exponent,
            {"units": "1/s", "long_name": "largest Lyapunov exponent"},
        )
    for q, (name, unit) in enumerate(IMPACT_COLUMNS):
        data[name] = ("p0", impacts[:, q], {"units": unit, "over_periods": IMPACT_PERIODS})
    data.attrs["impact_classes"] = list(IMPACT_CLASSES)
    if continuation is not None:
        data.attrs["continuation"] = continuation
    if seeds:
        per = extra.reshape(values.size, seeds, -1)
        data = data.assign_coords(seed=np.arange(seeds))
        data["poincare_seeds"] = (
            ("p0", "seed", "point"),
            per[:, :, :keep],
            {"units": length_unit(scale), "long_name": "mesh deflection from random starts"},
        )
        if exponents:
            data["exponent_seeds"] = (("p0", "seed"), per[:, :, keep], {"units": "1/s"})
        data["impact_class_seeds"] = (
            ("p0", "seed"),
            per[:, :, -1],
            {"units": IMPACT_COLUMNS[-1][1]},
        )
        data.attrs["seed"] = seed
    if continuation == "both":
        down = branches["down"]
        data["poincare_down"] = (
            ("p0", "point"),
            down[:, :keep],
            {"units": length_unit(scale), "long_name": "mesh deflection, descending sweep"},
        )
        if exponents:
            data["exponent_down"] = (
                "p0",
                down[:, keep],
                {"units": "1/s", "long_name": "largest Lyapunov exponent, descending sweep"},
            )
        data["impact_class_down"] = ("p0", down[:, n_main - 1], {"units": IMPACT_COLUMNS[-1][1]})
    return BifurcationResult(data)


def _continue(
    members: Callable[[NDArray], list[NonlinearSystem]],
    values: NDArray,
    direction: str,
    run: Callable[[NDArray, list[NonlinearSystem], NDArray], tuple[NDArray, NDArray]],
    progress: Callable[[int, int], None] | None,
) -> dict[str, NDArray]:
    """Sequential continuation: the rows ``run(chunk, systems, y0)`` returns (one per
    member, with the end states), in the order of ``values``, for the ascending
    (``"up"``) and/or descending (``"down"``) sweep, each value started from the end
    state of the previous one, the first from static equilibrium; the two sweeps run
    side by side as a two-member ensemble."""
    order = np.argsort(values, kind="stable")
    sweeps = {"up": order, "down": order[::-1]}
    names = ["up", "down"] if direction == "both" else [direction]
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


def design_and_model(target: Design | Model, what: str) -> tuple[Design | None, Model]:
    """The design (None for a model) and the model of an analysis's target."""
    from ..drives import build_model

    if isinstance(target, Design):
        return target, build_model(target)
    if isinstance(target, Model):
        return None, target
    raise ReducerlabError(f"{what}: target must be a Design or a Model")


def axis_members(
    design: Design | None, model: Model, axis: Axis, what: str
) -> tuple[NDArray, _Members, NonlinearSystem]:
    """The SI values of ``axis``, the flat systems (rigid motion removed) of its values
    and the base flat system of the model."""
    group, values = axis_targets(design, model, axis, 0, what)
    ev = _Evaluator(design.model_dump(mode="python") if design else None, model, tuple(group))
    base = model.nonlinear()
    rest = at_rest(model)
    members = _Members(
        ev, rigid_reduction(rest if rest is not None else base, element_blocks(model))
    )
    return values, members, base


def _fingerprint(s: NonlinearSystem) -> str:
    """Hash of a system's flat arrays (identifies the run in a resume folder)."""
    import hashlib

    h = hashlib.sha256()
    for a in (getattr(s, f) for f in NonlinearSystem.ARRAYS):
        h.update(np.ascontiguousarray(a, dtype=float).tobytes())
    return h.hexdigest()[:16]


_FLAT = NonlinearSystem.ARRAYS


@dataclass
class _Members:
    """Flat systems (rigid motion removed) of parameter values: the model rebuilt per
    value, or, when every flat array is affine in the value (checked at both ends and
    two interior points), interpolated from the two ends: exact, and no rebuilds."""

    ev: _Evaluator
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
            if any(getattr(o, f).shape != getattr(base, f).shape for f in _FLAT):
                return
        d = {f: (getattr(top, f) - getattr(base, f)) / (hi - lo) for f in _FLAT}
        for p, o in zip(pts[2:], ss[2:], strict=True):
            for f in _FLAT:
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
            replace(base, **{f: getattr(base, f) + (float(v) - lo) * d[f] for f in _FLAT})
            for v in chunk
        ]


#: Periods at the end of each value's run read for its tooth-separation statistics.
IMPACT_PERIODS = 10

#: Per-value separation statistics of a bifurcation (``analysis.impacts``): name, unit.
IMPACT_COLUMNS = (
    ("separation_fraction", "1"),
    ("back_contact_fraction", "1"),
    ("contact_losses", "1/period"),
    ("back_impacts", "1/period"),
    ("mesh_mode_hz", "Hz"),  # the mode that strains the line most (analysis.impacts)
    ("frequency_ratio", "1"),  # forcing frequency / mesh mode (omega-bar)
    ("impact_class", "index into attrs impact_classes"),  # last (read as [:, -1])
)


@dataclass
class _BifurcationChunk:
    """Poincare points of one chunk of parameter values (picklable for Dask)."""

    members: _Members
    path: str
    periods: int
    keep: int
    steps: int | None
    line: int
    scale: float
    exponents: bool = False
    period: float | None = None  # sampling period of systems without a periodic law
    accuracy: float = ACCURACY
    seeds: int = 0  # further runs per value from random starts (seed_states)
    seed: int = 0  # of the random generator

    def __call__(self, chunk: NDArray) -> NDArray:
        return self.integrate(chunk, self.members(chunk))

    def integrate(
        self,
        chunk: NDArray,
        systems: list[NonlinearSystem],
        y0: NDArray | None = None,
        with_end: bool = False,
    ) -> Any:
        """Rows (value, points [+ exponent], impact columns [, seed columns]); with
        ``with_end`` also the end states."""
        y0 = static_states(systems) if y0 is None else y0
        labels = [f"{self.path} = {v:.6g}" for v in chunk]
        rows, res = self._run(systems, y0, labels)
        if self.seeds:  # the same values from random starts: other attractors
            many = [s for s in systems for _ in range(self.seeds)]
            bits = [np.array([v], np.float64).view(np.uint32).tolist() for v in chunk]
            rngs = [np.random.default_rng([self.seed, *b, k])
                    for b in bits for k in range(self.seeds)]  # fmt: skip
            starts = seed_states(many, np.repeat(res.period, self.seeds), rngs)
            more, _ = self._run(many, starts, [lab for lab in labels for _ in range(self.seeds)])
            # per seed: points [+ exponent] and the impact class
            per = np.concatenate([more[:, : self.keep + self.exponents], more[:, -1:]], axis=1)
            rows = np.concatenate([rows, per.reshape(len(systems), -1)], axis=1)
        end = res.poincare[:, -1]
        return (rows, end) if with_end else rows

    def _run(self, systems: list[NonlinearSystem], y0: NDArray, labels: list[str]) -> tuple:
        """Rows (points [+ exponent], impact columns) of members from ``y0``, and the
        ensemble."""
        hist = min(self.keep, IMPACT_PERIODS)
        res = ensemble(
            systems, periods=self.periods, keep=self.keep, steps_per_period=self.steps,
            labels=labels, y0=y0, period=self.period, accuracy=self.accuracy,
            on_divergence="mark", history=hist, exponents=self.exponents,
        )  # fmt: skip
        # a diverging value keeps NaN points (labelled "diverged"), the others stand
        pts = res.delta_poincare[:, : self.keep, self.line] / self.scale
        pts[res.diverged] = np.nan
        imp = np.full((len(systems), len(IMPACT_COLUMNS)), np.nan)
        for k, s in enumerate(systems):
            if not res.diverged[k]:
                d = res.delta_history[k, :, self.line]
                st = contact_states(d, float(s.half_backlash[self.line]), float(hist),
                                    -1.0 if d.mean() < 0 else 1.0,
                                    res.history_time[k])  # fmt: skip
                mode_hz, _ = mesh_mode(s, self.line)
                ratio = 1.0 / float(res.period[k]) / mode_hz if mode_hz > 0 else np.nan
                imp[k] = (st.separation_fraction, st.back_contact_fraction,
                          st.contact_losses, st.back_impacts, mode_hz, ratio,
                          IMPACT_CLASSES.index(st.impact_class))  # fmt: skip
        # the exponent of the same trajectory as the points (computed beside it)
        parts = [pts, res.exponent[:, None], imp] if self.exponents else [pts, imp]
        return np.concatenate(parts, axis=1), res


class BifurcationResult(Result):
    """Poincaré points (p0, point) of a mesh deflection against the parameter ``p0``."""

    kind: ClassVar[str] = "bifurcation"

    def periodicity(self, tol: float = 1e-3, max_period: int = 12) -> NDArray[np.int64]:
        """Smallest n <= max_period such that the Poincaré sequence repeats every n
        points (to ``tol`` of its range), else 0 (not periodic within max_period)."""
        pts = self.data["poincare"].values
        return np.array(
            [_period_of(row, tol, max_period) if np.all(np.isfinite(row)) else 0 for row in pts],
            dtype=np.int64,
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary."""
        ds = self.data
        return {
            "parameter": ds.attrs["parameter"],
            "values": ds["p0"].values.tolist(),
            "period": self.periodicity().tolist(),
        }

    def labels(self) -> list[str]:
        """Motion class of every parameter value (needs ``exponent``, see
        :func:`bifurcation` with ``exponents=True``)."""
        ds = self.data
        if "exponent" not in ds:
            raise ReducerlabError("no Lyapunov exponents: run bifurcation(..., exponents=True)")
        return self._classes(ds["poincare"].values, ds["exponent"].values)

    def impacts(self) -> list[str]:
        """Impact class of every value (``analysis.impacts``: no impact, single- or
        double-sided), "diverged" where the motion left its bounds."""
        ds = self.data
        if "impact_class" not in ds:
            raise ReducerlabError("no impact statistics in this result (an older run)")
        names = list(ds.attrs["impact_classes"])
        return [names[int(c)] if np.isfinite(c) else "diverged" for c in ds["impact_class"].values]

    def _classes(self, points: NDArray, exponent: NDArray | None) -> list[str]:
        """Motion classes of rows of points: :func:`classify` with exponents, else the
        period (``period-n`` or ``aperiodic``)."""
        f = self.data.attrs["forcing_hz"]
        out = []
        for k, row in enumerate(points):
            if not np.all(np.isfinite(row)):
                out.append("diverged")
            elif exponent is not None:
                out.append(classify(row, float(exponent[k]), f))
            else:
                n = _period_of(row, 1e-3, 12)
                out.append(f"period-{n}" if n else "aperiodic")
        return out

    def coexisting(self) -> NDArray[np.bool_]:
        """Values where another run (the descending sweep of ``continuation="both"``, or
        a random start with ``seeds``) found another attractor than the main one:
        another motion class, or a mean Poincaré deflection apart by more than
        :data:`COEXIST_TOL` of the diagram's largest Poincaré spread."""
        ds = self.data
        main = ds["poincare"].values
        lam = ds["exponent"].values if "exponent" in ds else None
        others: list[tuple[NDArray, NDArray | None]] = []
        if "poincare_down" in ds:
            ex_down = ds["exponent_down"].values if "exponent_down" in ds else None
            others.append((ds["poincare_down"].values, ex_down))
        if "poincare_seeds" in ds:
            pts = ds["poincare_seeds"].values
            ex = ds["exponent_seeds"].values if "exponent_seeds" in ds else None
            for k in range(pts.shape[1]):
                others.append((pts[:, k], None if ex is None else ex[:, k]))
        out = np.zeros(main.shape[0], bool)
        if not others:
            return out
        every = np.concatenate([main[None], *[o[0][None] for o in others]])
        size = attractor_scale(every)
        lab = self._classes(main, lam)
        for pts, ex in others:
            out |= different_attractors(main, lab, pts, self._classes(pts, ex), size)
        return out

    @property
    def diverged(self) -> NDArray[np.bool_]:
        """Parameter values whose motion left its bounds (NaN points)."""
        return ~np.all(np.isfinite(self.data["poincare"].values), axis=1)

    def plot(self) -> Figure:
        """Bifurcation diagram (paper 004 Fig. 7), with the motion classes as a coloured
        band underneath when the exponents were computed."""
        from matplotlib.figure import Figure

        ds = self.data
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
        x = shown_values(ds["p0"])
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
            _class_band(band, edges, self.labels(), "motion", "C")
        if imp_band is not None:
            _class_band(imp_band, edges, self.impacts(), "teeth", "tab:")
        axes[-1].set_xlabel(axis_label(ds["p0"], ds.attrs["parameter"]))
        ax.set_ylabel(f"Poincaré points of mesh deflection ({ds['poincare'].attrs['units']})")
        ax.set_title(f"bifurcation diagram: {ds.attrs.get('title', '')}", fontsize=9)
        ax.grid(alpha=0.3)
        return fig


def _class_band(band, edges: NDArray, labels: list[str], title: str, palette: str) -> None:
    """A strip coloured by class per parameter value, its legend beside it (no clipping)."""
    from matplotlib.patches import Patch

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


#: Two runs hold different attractors when their motion classes differ or their mean
#: Poincaré deflections differ by more than this share of the largest Poincaré spread
#: (:func:`different_attractors`).
COEXIST_TOL = 0.02


def attractor_scale(points: NDArray) -> float:
    """The size against which mean Poincaré deflections are compared: the largest spread
    of a Poincaré sequence (last axis) in ``points``, at least 1e-3 of the largest mean."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: diverged runs
        if not np.any(np.isfinite(points)):
            return 1e-300
        spread = float(np.nanmax(np.ptp(points, axis=-1)))
        mean = float(np.nanmax(np.abs(np.nanmean(points, axis=-1))))
    spread = spread if np.isfinite(spread) else 0.0
    return max(spread, 1e-3 * mean, 1e-300)


def different_attractors(
    a: NDArray, labels_a: Any, b: NDArray, labels_b: Any, size: float
) -> NDArray[np.bool_]:
    """Rows of Poincaré points ``a``, ``b`` (..., point) with their motion classes that
    belong to different attractors: different classes, or mean deflections apart by more
    than :data:`COEXIST_TOL` ``* size``."""
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: diverged runs
        apart = np.abs(np.nanmean(a, axis=-1) - np.nanmean(b, axis=-1)) > COEXIST_TOL * size
    return (np.asarray(labels_a, object) != np.asarray(labels_b, object)) | apart


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
    range), else ``"unsettled"`` when the points still converge (their spread, or for
    some n <= ``max_period`` their n-step differences ``|x[k+n] - x[k]|``, shrink from
    quarter to quarter of the sequence, the last below :data:`SETTLE` times the first: a
    transient of a lightly damped mode towards a fixed point or a period-n orbit, not an
    attractor; run more periods), else ``"quasi-periodic"``.
    """
    if exponent > chaos * frequency:
        return "chaotic"
    pts = np.asarray(poincare, float)
    n = _period_of(pts, tol, max_period)
    if n:
        return f"period-{n}"
    if pts.size >= 16 and _converging(pts, max_period):
        return "unsettled"
    return "quasi-periodic"


def _converging(pts: NDArray, max_period: int) -> bool:
    """Whether a Poincaré sequence still converges: the spread of its quarters (a
    transient towards a fixed point), or for some n <= ``max_period`` the largest n-step
    difference ``|x[k+n] - x[k]|`` in each quarter (towards a period-n orbit), shrinks
    from quarter to quarter, the last below :data:`SETTLE` times the first."""

    def shrinking(q: list[float]) -> bool:
        return q[3] < SETTLE * q[0] and all(a >= b for a, b in itertools.pairwise(q))

    if shrinking([float(np.ptp(part)) for part in np.array_split(pts, 4)]):
        return True
    for n in range(1, max_period + 1):
        diff = np.abs(pts[n:] - pts[:-n])
        if diff.size >= 8 and shrinking([float(part.max()) for part in np.array_split(diff, 4)]):
            return True
    return False


#: A Poincaré sequence whose spread shrinks from quarter to quarter, the last below this
#: fraction of the first, is still converging (``classify``: "unsettled"). A
#: quasi-periodic sequence fills its closed curve in every quarter (no steady shrinking);
#: a transient decaying by a factor 2 over the kept points ends at ~0.6.
SETTLE = 0.8


def spectrum_peaks(
    signal: NDArray[np.float64], dt: float, f_ref: float, count: int = 6
) -> list[tuple[float, float]]:
    """Largest spectral peaks of ``signal`` as ``(multiple of f_ref, amplitude)``, the
    labelling of paper 004 Fig. 8 ("0.48x, 0.57x, ...")."""
    if np.size(signal) < 4 or not (dt > 0 and f_ref > 0):
        raise ReducerlabError("spectrum_peaks: need >= 4 samples, dt > 0 and f_ref > 0")
    x = np.asarray(signal, float) - np.mean(signal)
    amp = 2 * np.abs(np.fft.rfft(x * np.hanning(x.size))) / np.sum(np.hanning(x.size))
    f = np.fft.rfftfreq(x.size, dt)
    peaks = [i for i in range(1, amp.size - 1) if amp[i] >= amp[i - 1] and amp[i] > amp[i + 1]]
    peaks.sort(key=lambda i: -amp[i])
    return [(float(f[i] / f_ref), float(amp[i])) for i in peaks[:count]]


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

    def _uniform(self) -> tuple[NDArray, float]:
        """The deflection resampled on a uniform time grid (steps differ per segment)."""
        ds = self.data
        t = ds["time"].values
        tu = np.linspace(t[0], t[-1], t.size)
        return np.interp(tu, t, ds["delta"].values), float(tu[1] - tu[0])

    def peaks(self, count: int = 6) -> list[tuple[float, float]]:
        """Largest spectral peaks of the mesh deflection, as multiples of the forcing
        frequency (paper 004 Fig. 8 labels); none when the deflection varies by less than
        :data:`NOISE_M` (1 pm: round-off of a model that nothing excites)."""
        x, dt = self._uniform()
        if np.ptp(x) <= NOISE_M:
            return []
        return spectrum_peaks(x, dt, self.data.attrs["forcing_hz"], count)

    def plot(self) -> Figure:
        """Phase trajectory, Poincaré map and labelled spectrum (paper 004 Fig. 8)."""
        from matplotlib.figure import Figure

        ds = self.data
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
        x, dt = self._uniform()
        x = x - x.mean()
        amp = 2 * np.abs(np.fft.rfft(x * np.hanning(x.size))) / np.sum(np.hanning(x.size))
        f = np.fft.rfftfreq(x.size, dt) / ds.attrs["forcing_hz"]
        a3.plot(f, amp * 1e6)
        for m, a in self.peaks(5):
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
    ``analysis.response.to_system(model)`` (the model's DOFs, less rigid motions when it
    has any); by default the static equilibrium under the mean loads. Where attractors
    coexist (gear rattle) the start decides which one the response settles on.
    ``accuracy`` is the target error of the Poincaré points relative to the motion's
    scale (``analysis.response.accurate_steps``; default 1e-6), used unless
    ``steps_per_period`` is given."""
    from ..model.laws import evaluate_flat, flat_mean
    from .response import to_system

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
