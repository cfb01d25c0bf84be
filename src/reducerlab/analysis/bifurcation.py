"""Bifurcation diagrams: Poincaré points of the steady state against a design field or
model parameter (paper 004 Fig. 7, 9, 11), with motion classes, tooth-separation
statistics, continuation and random starts."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design
from ..drives import design_and_model
from ..dynamics.accuracy import ACCURACY
from ..dynamics.coordinates import static_states
from ..dynamics.ensemble import ensemble
from ..dynamics.guards import check_stability, seed_states
from ..dynamics.runsize import AUTO_STEPS_FLOOR, run_estimate
from ..dynamics.systems import forcing_period
from ..errors import ReducerlabError, names_source
from ..model import Model, NonlinearSystem
from ..numformat import Column, Table
from ..results import Result, provenance
from ..units import length_unit
from .impacts import IMPACT_CLASSES, contact_states, mesh_mode
from .members import (
    Members,
    axis_coord,
    axis_members,
    continue_sweep,
    fingerprint,
    shown_values,
)
from .motion import attractor_scale, classify, different_attractors, period_of
from .parameters import Axis
from .policies import Continuation
from .runfolder import chunk_path, load_chunk, open_run, save_chunk
from .workers import check_workers, dask_client, worker_pool

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "IMPACT_COLUMNS",
    "IMPACT_PERIODS",
    "BifurcationChunk",
    "BifurcationResult",
    "bifurcation",
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
    the motion's scale, default 1e-6; ``dynamics.accuracy.accurate_steps``).

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
    its static equilibrium (:func:`~reducerlab.dynamics.guards.seed_states`; the
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
    way = Continuation.parse(continuation, "bifurcation")
    continuation = None if way is Continuation.NONE else way.value
    for name, v in (("seeds", seeds), ("seed", seed)):
        if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v <= 2**31:
            raise ReducerlabError(f"bifurcation: {name} must be an integer >= 0, got {v!r}")
    trajectories = values.size * (1 + seeds) * max(1, len(way.directions))
    run_estimate("bifurcation", trajectories, periods, steps_per_period or AUTO_STEPS_FLOOR,
                 base.n, n_lines, keep, 0, bool(exponents), at_least=steps_per_period is None,
                 control="--periods, --steps, --seeds or the number of values").check()  # fmt: skip
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
                "exponents": bool(exponents), "scale": scale, "model": fingerprint(base),
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
    job = BifurcationChunk(
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
        branches = continue_sweep(
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
        forked = workers > 1 and members.fit is None
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
        coords={
            "p0": ("p0", values, axis_coord(design, axis, values, model)),
            "point": np.arange(keep),
        },
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
class BifurcationChunk:
    """Poincare points of one chunk of parameter values (picklable for Dask)."""

    members: Members
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
            [period_of(row, tol, max_period) if np.all(np.isfinite(row)) else 0 for row in pts],
            dtype=np.int64,
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: the values in SI (``values``) and in the unit a user reads
        them in (``display_values`` in ``display_unit``: rpm for a speed...)."""
        ds = self.data
        return {
            "parameter": ds.attrs["parameter"],
            "values": ds["p0"].values.tolist(),
            "display_unit": ds["p0"].attrs.get("display_unit", ""),
            "display_values": [float(f"{x:.12g}") for x in shown_values(ds["p0"])],
            "period": self.periodicity().tolist(),
        }

    def table(self, motion: bool = False, coexisting: bool = False) -> str:
        """One line per value (in its display unit): Poincaré period (0: not periodic
        within 12), impact class, and with ``motion`` the motion class (needs
        exponents), with ``coexisting`` whether another attractor was found."""
        ds = self.data
        c = ds["p0"]
        unit = c.attrs.get("display_unit", "") or "SI"
        cols = {"period": [str(p) for p in self.periodicity()]}
        if "impact_class" in ds:
            cols["impacts"] = self.impacts()
        if motion:
            cols["motion"] = self.labels()
        if coexisting:
            cols["coexisting"] = ["yes" if x else "-" for x in self.coexisting()]
        t = Table([Column("value", unit, "parameter"), *(Column(k, kind="text") for k in cols)],
                  title=f"bifurcation over {ds.attrs['parameter']}: {c.size} values")  # fmt: skip
        for i, v in enumerate(shown_values(c)):
            t.add(v, *(col[i] for col in cols.values()))
        return t.text()

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
                n = period_of(row, 1e-3, 12)
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
        from ..plot.bifurcation import plot_bifurcation

        return plot_bifurcation(self)
