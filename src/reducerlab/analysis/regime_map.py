"""Regime maps: the motion class and the impact class of the steady nonlinear response
over two parameters (issue 16).

The question a gear-rattle study asks of a drive, "at which speeds and profile shifts
(backlash, errors, ...) does it lose contact, rattle, or go period-n, quasi-periodic or
chaotic?", is answered by a 2-D map: for every pair of values the steady motion of
mesh line ``line`` is classified from its Poincaré points and its largest Lyapunov
exponent (:func:`~reducerlab.analysis.motion.classify`, the exponent computed inside
the compiled kernel beside the points' own trajectory), and its impact class and tooth
separation are read from the last periods (:mod:`.impacts`).

Along the ``x`` axis (usually the speed) each row is swept by sequential continuation
(``"up"``, ``"down"`` or ``"both"``: each value starts from the state the previous one
ended in, so a row follows one attractor and jumps where it ceases to exist); with
``continuation=None`` every point starts from static equilibrium. The rows (values of
``y``) are independent: a chunk of rows runs as one ensemble in the compiled kernel
(every row and direction a member, in parallel on the cores), each finished chunk is
written to the run folder at once (resumable like sweeps and bifurcations, see
:mod:`.runfolder`) and with a Dask scheduler the chunks run on the cluster.
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..design import Design
from ..drives import design_and_model
from ..dynamics.accuracy import ACCURACY
from ..dynamics.coordinates import static_states
from ..dynamics.guards import check_stability
from ..dynamics.runsize import AUTO_STEPS_FLOOR, run_estimate
from ..errors import ReducerlabError, names_source
from ..model import Model, NonlinearSystem
from ..numformat import Column, Table, fmt
from ..results import Result, provenance
from ..units import length_unit
from .bifurcation import IMPACT_COLUMNS, BifurcationChunk
from .impacts import IMPACT_CLASSES
from .members import Members, axis_coord, fingerprint, shown_values, target_members
from .motion import attractor_scale, classify, different_attractors
from .parameters import Axis, axis_targets
from .policies import Continuation
from .runfolder import chunk_path, load_chunk, open_run, save_chunk
from .workers import dask_client

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["RegimeMapResult", "motion_order", "regime_map"]

#: Most points of a regime map (both axes together).
MAX_POINTS = 250_000


@names_source
def regime_map(
    target: Design | Model,
    x: Axis,
    y: Axis,
    *,
    periods: int = 600,
    keep: int = 64,
    line: int = 0,
    scale: float = 1e-6,
    continuation: str | None = "up",
    accuracy: float = ACCURACY,
    steps_per_period: int | None = None,
    period: float | None = None,
    rows_per_chunk: int = 4,
    output: str | Path | None = None,
    scheduler: Any = None,
    progress: Callable[[int, int], None] | None = None,
) -> RegimeMapResult:
    """Motion class and impact class of the steady response over two parameters.

    Parameters
    ----------
    target : Design or Model
    x, y : Axis
        The two parameters (design fields with units, model parameters, tied paths
        ``a+b``, as in :func:`~reducerlab.analysis.sweep.sweep`); ``x`` is swept by
        continuation within each row, ``y`` indexes the rows.
    periods, keep : int
        Forcing periods integrated per point (transient included) and Poincaré points
        kept (the exponent is measured over the same last ``keep`` periods).
    line : int
        The mesh line whose deflection is mapped.
    scale : float
        Unit of the stored Poincaré points (m), 1e-6: um.
    continuation : {"up", "down", "both", None}
        Sweep direction(s) along ``x``; ``None``: every point from static equilibrium.
        With ``"both"`` the two sweeps are stored as branches and
        :meth:`RegimeMapResult.coexisting` marks where they found different attractors.
    accuracy : float
        Target error of the Poincaré points (see
        :func:`~reducerlab.dynamics.ensemble.ensemble`); ignored with
        ``steps_per_period``.
    period : float, optional
        Sampling period (s) of systems without a periodic law.
    rows_per_chunk : int
        Rows per chunk: the unit of work written to the run folder and sent to Dask.
    output : path, optional
        Run folder: ``regime_map_run.json`` and ``chunks/``; a re-run with the same
        arguments computes only the missing chunks.
    scheduler : str or dask Client, optional
        Run the chunks on a Dask cluster.
    progress : callable, optional
        ``progress(done, total)`` in points.

    Returns
    -------
    RegimeMapResult
        ``poincare`` (branch, p1, p0, point), ``exponent`` (1/s) and the per-point
        impact statistics of :data:`~reducerlab.analysis.bifurcation.IMPACT_COLUMNS` over
        (branch, p1, p0); ``p0`` holds the ``x`` values and ``p1`` the ``y`` values (SI).
    """
    design, model = design_and_model(target, "regime_map")
    way = Continuation.parse(continuation, "regime_map")
    continuation = None if way is Continuation.NONE else way.value
    for name, v, lo in (("periods", periods, 1), ("keep", keep, 1),
                        ("rows_per_chunk", rows_per_chunk, 1)):  # fmt: skip
        if isinstance(v, bool) or not isinstance(v, int) or v < lo:
            raise ReducerlabError(f"regime_map: {name} must be an integer >= {lo}, got {v!r}")
    if keep > periods:
        raise ReducerlabError(f"regime_map: keep = {keep} must be <= periods = {periods}")
    gx, xv = axis_targets(design, model, x, 0, "regime-map")
    gy, yv = axis_targets(design, model, y, 1, "regime-map")
    if {(t.where, t.path) for t in gx} & {(t.where, t.path) for t in gy}:
        raise ReducerlabError(f"regime_map: x {x.path!r} and y {y.path!r} share a parameter")
    if xv.size * yv.size > MAX_POINTS:
        raise ReducerlabError(
            f"regime_map: {xv.size} x {yv.size} points; at most {MAX_POINTS} are allowed"
        )
    members, base = target_members(design, model, [*gx, *gy], "regime-map")
    branches = 2 if continuation == Continuation.BOTH.value else 1
    run_estimate("regime-map", xv.size * yv.size * branches, periods,
                 steps_per_period or AUTO_STEPS_FLOOR, base.n, base.G.shape[0], keep, 0, True,
                 at_least=steps_per_period is None,
                 control="--periods, --steps or the number of points").check()  # fmt: skip
    if not 0 <= line < base.G.shape[0]:
        raise ReducerlabError(f"regime_map: line must be in 0..{base.G.shape[0] - 1}, got {line}")
    job = _RegimeChunk(members, xv, yv, x.path, periods, keep, steps_per_period, line, scale,
                       period, accuracy, continuation)  # fmt: skip
    chunks = [list(range(i, min(i + rows_per_chunk, yv.size)))
              for i in range(0, yv.size, rows_per_chunk)]  # fmt: skip
    folder = Path(output) if output is not None else None
    key = ""
    if folder is not None:
        spec = {"x": x.path, "y": y.path, "x_values": xv.tolist(), "y_values": yv.tolist(),
                "periods": periods, "keep": keep, "steps": steps_per_period, "line": line,
                "scale": scale, "continuation": continuation, "accuracy": accuracy,
                "period": period, "rows": rows_per_chunk, "model": fingerprint(base),
                "design": design.hash if design else None}  # fmt: skip
        key = open_run(folder, "regime_map_run.json", spec, "regime map run")
    results: dict[int, NDArray] = {}
    todo = []
    for i, rows in enumerate(chunks):  # finished chunks are checked before any new work
        f = None if folder is None else chunk_path(folder, i)
        if f is not None and f.exists():
            # stored row-first (one entry per y value of the chunk, as load_chunk checks)
            results[i] = load_chunk(f, key, i, yv[rows], ("rows",))["rows"].swapaxes(0, 1)
        else:
            todo.append(i)
    total = xv.size * yv.size
    done = sum(len(chunks[i]) for i in results) * xv.size
    if progress:
        progress(done, total)
    if todo:  # a divergent linear part at a corner fails at once
        corners = [(a, b) for a in np.unique(xv[[0, -1]]) for b in np.unique(yv[[0, -1]])]
        check_stability(
            [replace(members, fixed=(float(b),)).one(float(a)) for a, b in corners],
            [f"{x.path} = {a:.6g}, {y.path} = {b:.6g}" for a, b in corners],
        )

    def finish(i: int, rows: NDArray) -> None:
        nonlocal done
        results[i] = rows
        if folder is not None:
            save_chunk(chunk_path(folder, i), key, i, yv[chunks[i]], {"rows": rows.swapaxes(0, 1)})
        done += len(chunks[i]) * xv.size
        if progress:
            progress(done, total)

    if scheduler is not None and todo:
        from dask.distributed import as_completed

        with dask_client(scheduler, "regime_map") as client:
            futures = {client.submit(job, chunks[i], pure=False): i for i in todo}
            for fut in as_completed(futures):
                finish(futures[fut], fut.result())
    else:
        for i in todo:
            base_done = done

            def step(k: int, n: int, base_done: int = base_done) -> None:
                if progress:
                    progress(base_done + k, total)

            finish(i, job(chunks[i], step))
    rows = np.concatenate([results[i] for i in range(len(chunks))], axis=1)
    return _assemble(rows, design, model, x, y, xv, yv, job, base)


@dataclass
class _RegimeChunk:
    """Rows of a regime map (picklable for Dask): (branch, row, x value, column)."""

    members: Members
    x: NDArray
    y: NDArray
    x_path: str
    periods: int
    keep: int
    steps: int | None
    line: int
    scale: float
    period: float | None
    accuracy: float
    continuation: str | None

    @property
    def branches(self) -> list[str]:
        if self.continuation is None:
            return ["static"]
        return Continuation(self.continuation).directions

    def __call__(
        self, rows: list[int], progress: Callable[[int, int], None] | None = None
    ) -> NDArray:
        job = BifurcationChunk(self.members, self.x_path, self.periods, self.keep,
                                self.steps, self.line, self.scale, True, self.period,
                                self.accuracy)  # fmt: skip
        row_members = [replace(self.members, fixed=(float(self.y[j]),), fit=None)
                       for j in rows]  # fmt: skip
        nx = self.x.size
        if nx > 8:  # rows whose flat arrays are affine in x are interpolated, not rebuilt
            for m in row_members:
                m.probe(float(self.x.min()), float(self.x.max()))
        names = self.branches
        cols = self.keep + 1 + len(IMPACT_COLUMNS)
        out = np.full((len(names), len(rows), nx, cols), np.nan)
        if self.continuation is None:  # every point from static equilibrium
            systems = [s for m in row_members for s in m(self.x)]
            res = job.integrate(np.tile(self.x, len(rows)), systems)
            out[0] = res.reshape(len(rows), nx, cols)
            if progress:
                progress(len(rows) * nx, len(rows) * nx)
            return out
        order = np.argsort(self.x, kind="stable")
        sweeps = {"up": order, "down": order[::-1]}
        state: dict[tuple[int, int], NDArray | None] = {}
        for step in range(nx):
            idx, systems = [], []
            for m in row_members:
                for name in names:
                    k = int(sweeps[name][step])
                    idx.append(k)
                    systems.append(m(self.x[[k]])[0])
            y0 = static_states(systems)
            slots = list(itertools.product(range(len(rows)), range(len(names))))
            for q, (r, b) in enumerate(slots):
                prev = state.get((r, b))
                if prev is not None and np.all(np.isfinite(prev)):
                    y0[q] = prev
            res, ends = job.integrate(self.x[idx], systems, y0=y0, with_end=True)
            for q, (r, b) in enumerate(slots):
                out[b, r, idx[q]] = res[q]
                state[(r, b)] = ends[q]
            if progress:
                progress((step + 1) * len(rows), len(rows) * nx)
        return out


def _assemble(
    rows: NDArray,
    design: Design | None,
    model: Model,
    x: Axis,
    y: Axis,
    xv: NDArray,
    yv: NDArray,
    job: _RegimeChunk,
    base: NonlinearSystem,
) -> RegimeMapResult:
    keep = job.keep
    dims = ("branch", "p1", "p0")
    data = xr.Dataset(
        {
            "poincare": (
                (*dims, "point"),
                rows[..., :keep],
                {"units": length_unit(job.scale), "long_name": "mesh deflection"},
            ),
            "exponent": (
                dims,
                rows[..., keep],
                {"units": "1/s", "long_name": "largest Lyapunov exponent"},
            ),
        },
        coords={
            "branch": job.branches,
            "p0": ("p0", xv, axis_coord(design, x, xv, model)),
            "p1": ("p1", yv, axis_coord(design, y, yv, model)),
            "point": np.arange(keep),
        },
        attrs={
            "title": (design.name if design else model.name) or "regime map",
            "x": x.path,
            "y": y.path,
            "periods": job.periods,
            "keep": keep,
            "line": base.line_names[job.line],
            "continuation": str(job.continuation),
            "impact_classes": list(IMPACT_CLASSES),
            **provenance(model.metadata),
        },
    )
    for q, (name, unit) in enumerate(IMPACT_COLUMNS):
        data[name] = (dims, rows[..., keep + 1 + q], {"units": unit})
    result = RegimeMapResult(data)
    labels = result.labels()
    classes = motion_order(np.unique(labels).tolist())
    data["motion"] = (
        dims,
        np.vectorize(classes.index, otypes=[np.int64])(labels),
        {"units": "index into attrs motion_classes"},
    )
    data.attrs["motion_classes"] = classes
    return result


def motion_order(labels: list[str]) -> list[str]:
    """Motion classes in reading order: period-1, period-2, ..., quasi-periodic,
    chaotic, unsettled, diverged."""

    def key(k: str) -> tuple[int, int]:
        m = re.fullmatch(r"period-(\d+)", k)
        if m:
            return (0, int(m.group(1)))
        rank = ("quasi-periodic", "chaotic", "unsettled", "diverged")
        return (1, rank.index(k) if k in rank else len(rank))

    return sorted(set(labels), key=key)


class RegimeMapResult(Result):
    """Motion and impact classes over two parameters: (branch, p1, p0)."""

    kind: ClassVar[str] = "regime-map"

    def _forcing_hz(self) -> NDArray:
        """Forcing frequency of every point (Hz): omega-bar times the mesh mode."""
        ds = self.data
        return (ds["frequency_ratio"] * ds["mesh_mode_hz"]).values

    def labels(self) -> NDArray:
        """Motion class of every point (branch, p1, p0): ``period-n``,
        ``quasi-periodic``, ``chaotic`` (exponent above 1 % of the forcing frequency),
        ``unsettled`` or ``diverged`` (:func:`~reducerlab.analysis.motion.classify`;
        read from the stored ``motion`` once the result is assembled)."""
        ds = self.data
        if "motion" in ds:
            classes = np.atleast_1d(np.asarray(ds.attrs["motion_classes"], dtype=object))
            return classes[ds["motion"].values]
        pts = ds["poincare"].values
        lam = ds["exponent"].values
        f = self._forcing_hz()
        out = np.empty(lam.shape, dtype=object)
        for i in np.ndindex(lam.shape):
            row = pts[i]
            if not (np.all(np.isfinite(row)) and np.isfinite(lam[i])):
                out[i] = "diverged"
            else:
                out[i] = classify(row, float(lam[i]), float(f[i]) if np.isfinite(f[i]) else 0.0)
        return out

    def impacts(self) -> NDArray:
        """Impact class of every point (branch, p1, p0): ``no impact``,
        ``single-sided impact``, ``double-sided impact`` or ``diverged``."""
        ds = self.data
        names = list(ds.attrs["impact_classes"])
        c = ds["impact_class"].values
        out = np.empty(c.shape, dtype=object)
        for i in np.ndindex(c.shape):
            out[i] = names[int(c[i])] if np.isfinite(c[i]) else "diverged"
        return out

    def coexisting(self) -> NDArray[np.bool_]:
        """Points (p1, p0) where the ascending and descending sweeps hold different
        attractors (:func:`~reducerlab.analysis.motion.different_attractors`: other
        motion classes, or mean Poincaré deflections apart by more than 2 % of the map's
        largest Poincaré spread). All False with one branch."""
        ds = self.data
        if ds.sizes["branch"] < 2:
            return np.zeros((ds.sizes["p1"], ds.sizes["p0"]), bool)
        lab = self.labels()
        pts = ds["poincare"].values
        return different_attractors(pts[0], lab[0], pts[1], lab[1], attractor_scale(pts))

    def regions(self) -> list[dict[str, Any]]:
        """Where each class occurs: for every motion and impact class of every branch,
        its share of the map and the ranges of ``x`` and ``y`` (display units) it
        covers."""
        ds = self.data
        cx, cy = ds["p0"], ds["p1"]
        X, Y = shown_values(cx), shown_values(cy)
        out = []
        for what, lab in (("motion", self.labels()), ("teeth", self.impacts())):
            for b, branch in enumerate(ds["branch"].values.tolist()):
                grid = lab[b]
                order = motion_order(np.unique(grid).tolist()) if what == "motion" else [
                    k for k in (*IMPACT_CLASSES, "diverged") if k in set(grid.ravel())]  # fmt: skip
                for k in order:
                    where = grid == k
                    iy, ix = np.nonzero(where)
                    out.append({
                        "branch": branch, "kind": what, "class": k,
                        "share": float(where.mean()),
                        "x": [float(X[ix].min()), float(X[ix].max())],
                        "y": [float(Y[iy].min()), float(Y[iy].max())],
                    })  # fmt: skip
        return out

    def to_dict(self) -> dict[str, Any]:
        ds = self.data
        cx, cy = ds["p0"], ds["p1"]
        return {
            "x": ds.attrs["x"],
            "y": ds.attrs["y"],
            "x_values": cx.values.tolist(),
            "y_values": cy.values.tolist(),
            "x_unit": cx.attrs.get("display_unit", ""),
            "y_unit": cy.attrs.get("display_unit", ""),
            "branches": ds["branch"].values.tolist(),
            "motion": self.labels().tolist(),
            "impacts": self.impacts().tolist(),
            "coexisting": self.coexisting().tolist(),
            "regions": self.regions(),
        }

    def table(self) -> str:
        """The regions as text: class, share of the map and the x and y ranges."""
        ds = self.data
        cx, cy = ds["p0"], ds["p1"]
        ux = cx.attrs.get("display_unit", "") or ""
        uy = cy.attrs.get("display_unit", "") or ""
        t = Table([Column("branch", kind="text"), Column("kind", kind="text"),
                   Column("class", kind="text"), Column("share", "%", "percent"),
                   Column("x from", ux, "parameter"), Column("x to", ux, "parameter"),
                   Column("y from", uy, "parameter"), Column("y to", uy, "parameter")],
                  title=f"regime map: {ds.attrs.get('title', '')}  (x = {ds.attrs['x']}, "
                  f"y = {ds.attrs['y']})")  # fmt: skip
        for r in self.regions():
            t.add(r["branch"], r["kind"], r["class"], 100 * r["share"], *r["x"], *r["y"])
        lines = [t.text()]
        co = self.coexisting()
        if ds.sizes["branch"] > 1:
            share = fmt(100 * co.mean(), "percent")
            lines.append(f"coexisting attractors (up != down) at {share} % of points")
        return "\n".join(lines)

    def plot(self) -> Figure:
        """Motion-class and impact-class maps per branch (columns), points where the two
        sweeps found different attractors marked with a dot."""
        from ..plot.bifurcation import plot_regime_map

        return plot_regime_map(self)
