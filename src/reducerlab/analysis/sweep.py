"""Parameter sweeps of modal analysis: any design field or model parameter, over a list,
a linear or logarithmic range, relative to the design value, or a grid of two (the
paths, their values and the model at a point: :mod:`.parameters`).

Points are evaluated in chunks. Each finished chunk is written to the run folder at
once (``chunks/chunk_NNNNN.npz``, written atomically and stamped with the run key, its
index and its parameter values, see :mod:`.runfolder`), so an interrupted run loses
nothing: running the same sweep into the same folder again checks the finished chunks
and computes only the missing ones. Chunks run in worker processes by default (see
:mod:`.workers`), or on a Dask cluster when a scheduler address is given. Where ``M``
and ``K`` are affine in the swept parameters (``K = K0 + p K1``), a chunk is one
batched eigenproblem with no Python loop per point.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import shutil
from collections.abc import Callable, Sequence
from concurrent.futures import as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..budget import Estimate
from ..design import Design
from ..errors import ReducerlabError, names_source
from ..model import Model
from ..model.rigid import RIGID_TOL, check_resolved, element_blocks, rest_stiffness, strain_ratio
from ..numformat import Column, Table, fmt
from ..results import Result, provenance
from ..units import TWO_PI, display_unit
from .batch import eigh_batch
from .parameters import Axis, Evaluator, Target, axis_targets, parameter_kind
from .runfolder import chunk_path, load_chunk, open_run, save_chunk
from .tracking import find_events, track_modes
from .workers import check_workers, dask_client, worker_pool

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["Axis", "PointModes", "SweepResult", "sweep"]


# ----------------------------------------------------------------------------- points
@dataclass
class _Points:
    """``M`` and ``K`` of sweep points: each point's model, or, when they are affine in
    the swept values (:func:`_affine`), one batched expression; picklable for worker
    processes."""

    ev: Evaluator
    affine: tuple[NDArray, NDArray, NDArray, NDArray] | None = None  # M0, K0, dM, dK
    anchor: NDArray | None = None
    affine_rest: tuple[NDArray, NDArray] | None = None  # stiffness at rest: K0, dK
    affine_blocks: list[tuple[list[int], NDArray, NDArray]] | None = None  # idx, Ke0, dKe

    def matrices(self, points: NDArray) -> PointModes:
        """``M, K`` (n_points, n, n) at parameter rows ``points`` (n_points, n_axes), the
        stiffness at rest (speed terms left out) where the points run at a speed, and
        the element stiffness blocks that decide rigidity (as in
        :func:`reducerlab.analysis.modal.modal`)."""
        if self.affine is not None:
            M0, K0, dM, dK = self.affine
            t = points - self.anchor  # (n_pts, n_axes)
            K = K0 + np.einsum("pa,aij->pij", t, dK)
            rest = None
            if self.affine_rest is not None:
                rest = self.affine_rest[0] + np.einsum("pa,aij->pij", t, self.affine_rest[1])
            blocks = [  # elements the parameters do not touch keep one block
                (idx, Ke + np.einsum("pa,aij->pij", t, dKe) if np.any(dKe) else Ke)
                for idx, Ke, dKe in self.affine_blocks or []
            ]
            M = M0 if not np.any(dM) else M0 + np.einsum("pa,aij->pij", t, dM)
            return PointModes(M, K, rest, blocks, self.ev.model.dof_names)  # one M: factorised once
        Ms, Ks, Rs, Bs = [], [], [], []
        for row in points:
            model = self.ev.model_at(list(row))
            mats = model.matrices()
            Ms.append(mats.M)
            Ks.append(mats.K)
            Rs.append(rest_stiffness(model))
            Bs.append(element_blocks(model))
        rest = None
        if any(r is not None for r in Rs):
            rest = np.array([k if r is None else r for k, r in zip(Ks, Rs, strict=True)])
        return PointModes(np.array(Ms), np.array(Ks), rest, Bs, self.ev.model.dof_names)

    def solve(self, points: NDArray) -> tuple[NDArray, NDArray, NDArray]:
        """Eigenvalues (rigid modes exactly 0), shapes and weighted shapes."""
        return self.matrices(points).solve()


@dataclass
class PointModes:
    """Modes of a stack of points (sweep points, Campbell speeds): their matrices and
    what decides their rigid modes, solved as :func:`reducerlab.analysis.modal.modal`
    would solve each point."""

    M: NDArray  # (n, n) shared, or (P, n, n)
    K: NDArray  # (P, n, n)
    rest: NDArray | None  # stiffness at rest (P, n, n), when the points run at a speed
    blocks: list  # stacked element blocks [(idx, (P, ne, ne))], or per point [[(idx, Ke)]]
    names: list[str]  # DOF names, for messages
    what: str = "sweep"  # the analysis, for messages

    def ratio(self, phi: NDArray) -> NDArray:
        """Largest element strain ratio of each mode (P, n)."""
        stacked = not self.blocks or isinstance(self.blocks[0], tuple)
        if stacked:
            return strain_ratio(self.blocks, self.M, phi)
        M = np.broadcast_to(self.M, phi.shape)
        return np.stack(
            [strain_ratio(b, m, f) for b, m, f in zip(self.blocks, M, phi, strict=True)]
        )

    def solve(self, rigid_tol: float = RIGID_TOL) -> tuple[NDArray, NDArray, NDArray]:
        """``K phi = lambda M phi`` with rigid modes (no element strained) at exactly 0.

        At a speed, the rigid modes are those of the stiffness at rest and the elastic
        modes are solved on their mass-orthogonal complement, as in
        :func:`reducerlab.analysis.modal.modal` (the speed terms, linearised in a
        rotating frame, would make a rigid mode drift).
        """
        lam, phi, y = self._solve(rigid_tol)
        # rigid modes are exactly 0 (no elastic eigenvalue is); the others must lie
        # above the eigen-solver's resolution at their point
        check_resolved(lam, lam == 0.0, self.M, self.K, self.names, self.what)
        return lam, phi, y

    def _solve(self, rigid_tol: float) -> tuple[NDArray, NDArray, NDArray]:
        lam, phi, y = eigh_batch(self.M, self.K)
        if self.rest is None or np.array_equal(self.rest, self.K):  # no speed term in K
            return np.where(self.ratio(phi) <= rigid_tol, 0.0, lam), phi, y
        _, phi0, y0 = eigh_batch(self.M, self.rest)
        null = self.ratio(phi0) <= rigid_tol  # (P, n)
        L = np.linalg.cholesky(0.5 * (self.M + np.swapaxes(self.M, -1, -2)))
        L = np.broadcast_to(L, self.K.shape)
        same = np.all(self.rest == self.K, axis=(-2, -1))  # points without speed terms
        if same.any():
            lam = np.where(same[:, None] & (self.ratio(phi) <= rigid_tol), 0.0, lam)
        for p in np.nonzero(null.any(axis=1) & ~same)[0]:
            N, V = y0[p][:, null[p]], y0[p][:, ~null[p]]  # orthonormal (mass-weighted)
            A = np.linalg.solve(L[p], np.linalg.solve(L[p], self.K[p]).T)  # L^-1 K L^-T
            lam_e, z = np.linalg.eigh(0.5 * (V.T @ A @ V + (V.T @ A @ V).T))
            lam_p = np.concatenate([np.zeros(N.shape[1]), lam_e])
            y_p = np.concatenate([N, V @ z], axis=1)
            order = np.argsort(lam_p, kind="stable")
            lam[p], y[p] = lam_p[order], y_p[:, order]
            phi[p] = np.linalg.solve(L[p].T, y[p])
        return lam, phi, y


def _affine(points: _Points, lows: NDArray, highs: NDArray) -> bool:
    """Detect ``M, K`` affine in the swept values; store the batch form if so."""
    n_ax = len(lows)
    base_model = points.ev.model_at(list(lows))
    base = base_model.matrices()
    base_rest = rest_stiffness(base_model)
    dM, dK, dR = [], [], []
    ends: list[Model] = []
    for a in range(n_ax):
        p = lows.copy()
        span = highs[a] - lows[a]
        if span == 0:
            return False
        p[a] = highs[a]
        model = points.ev.model_at(list(p))
        ends.append(model)
        m = model.matrices()
        dM.append((m.M - base.M) / span)
        dK.append((m.K - base.K) / span)
        rest = rest_stiffness(model)
        if (rest is None) != (base_rest is None):
            return False  # the speed itself is swept through zero
        if rest is not None:
            dR.append((rest - base_rest) / span)
    dM_, dK_ = np.array(dM), np.array(dK)
    # probe: an interior point off the axes must be predicted exactly
    probe = lows + (highs - lows) * np.linspace(0.37, 0.61, n_ax)
    model = points.ev.model_at(list(probe))
    m = model.matrices()
    t = probe - lows
    pM = base.M + np.einsum("a,aij->ij", t, dM_)
    pK = base.K + np.einsum("a,aij->ij", t, dK_)
    scale_M = max(np.abs(base.M).max(), 1e-300)
    scale_K = max(np.abs(base.K).max(), np.abs(pK).max(), 1e-300)
    if np.abs(m.M - pM).max() > 1e-10 * scale_M or np.abs(m.K - pK).max() > 1e-10 * scale_K:
        return False
    blocks = _affine_blocks(base_model, ends, lows, highs, model, probe)
    if blocks is None:
        return False
    if base_rest is not None:
        rest = rest_stiffness(model)
        pR = base_rest + np.einsum("a,aij->ij", t, np.array(dR))
        if rest is None or np.abs(rest - pR).max() > 1e-10 * scale_K:
            return False
        points.affine_rest = (base_rest, np.array(dR))
    points.affine_blocks = blocks  # set with the rest, once every probe passed
    points.affine = (base.M, base.K, dM_, dK_)
    points.anchor = lows.astype(float)
    return True


def _affine_blocks(
    base: Model,
    ends: list[Model],
    lows: NDArray,
    highs: NDArray,
    probe_model: Model,
    probe: NDArray,
) -> list[tuple[list[int], NDArray, NDArray]] | None:
    """Element blocks ``K_e = K_e0 + t dK_e`` of an affine sweep (the rigid-mode test of
    every point), checked at the probe point; None when they are not affine."""
    b0 = element_blocks(base)
    per_axis = [element_blocks(m) for m in ends]
    bp = element_blocks(probe_model)
    if any(len(b) != len(b0) for b in (*per_axis, bp)):
        return None
    out = []
    for k, (idx, K0) in enumerate(b0):
        if any(b[k][0] != idx for b in (*per_axis, bp)):
            return None
        dK = np.array(
            [(b[k][1] - K0) / (h - lo) for b, h, lo in zip(per_axis, highs, lows, strict=True)]
        )
        want = K0 + np.einsum("a,aij->ij", probe - lows, dK)
        if np.abs(bp[k][1] - want).max() > 1e-10 * max(np.abs(K0).max(), np.abs(want).max()):
            return None
        out.append((idx, K0, dK))
    return out


# ----------------------------------------------------------------------------- running
_ARRAYS = ("lam", "phi", "y")


def _solve_chunk(ev: _Points, points: NDArray, path: str, key: str, index: int) -> str:
    lam, phi, y = ev.solve(points)
    save_chunk(path, key, index, points, {"lam": lam, "phi": phi, "y": y})
    return path


@dataclass
class _Run:
    folder: Path
    key: str
    chunks: list[tuple[int, NDArray]] = field(default_factory=list)

    def chunk_path(self, i: int) -> Path:
        return chunk_path(self.folder, i)

    def missing(self) -> list[tuple[int, NDArray]]:
        """Chunks still to compute; the stamps of the finished ones are checked."""
        todo = []
        for i, pts in self.chunks:
            path = self.chunk_path(i)
            if path.exists():
                load_chunk(path, self.key, i, pts)
            else:
                todo.append((i, pts))
        return todo

    def load(self, i: int, pts: NDArray) -> dict[str, NDArray]:
        return load_chunk(self.chunk_path(i), self.key, i, pts, _ARRAYS, finite=True)


def _submit_all(
    ev: _Points,
    jobs: list[tuple[int, NDArray]],
    run: _Run,
    workers: int | None,
    scheduler: Any,
    progress: Callable[[int], None] | None,
) -> None:
    if not jobs:
        return
    args = [(ev, pts, str(run.chunk_path(i)), run.key, i) for i, pts in jobs]
    if scheduler is not None:
        from dask.distributed import as_completed as dask_completed

        with dask_client(scheduler, "sweep") as client:
            futures = [client.submit(_solve_chunk, *a, pure=False) for a in args]
            for f in dask_completed(futures):
                f.result()
                if progress:
                    progress(1)
        return
    n_workers = workers if workers is not None else (os.cpu_count() or 1)
    if n_workers <= 1 or len(jobs) == 1:
        for a in args:
            _solve_chunk(*a)
            if progress:
                progress(1)
        return
    # on any exception (Ctrl-C, SIGTERM, an error) the pool ends its workers at once;
    # the chunks already written stay, and a re-run resumes from them
    with worker_pool(min(n_workers, len(jobs))) as pool:
        for f in as_completed([pool.submit(_solve_chunk, *a) for a in args]):
            f.result()
            if progress:
                progress(1)


@names_source
def sweep(
    target: Design | Model,
    axes: Axis | Sequence[Axis],
    *,
    output: str | Path | None = None,
    chunk_size: int = 2000,
    workers: int | None = None,
    scheduler: Any = None,
    track: bool = True,
    progress: Callable[[int, int], None] | None = None,
) -> SweepResult:
    """Modal analysis over one parameter or a grid of two.

    Parameters
    ----------
    target : Design or Model
        A validated design (design fields and model parameters can be swept) or a
        model (model parameters only).
    axes : Axis or sequence of one or two Axis
    output : path, optional
        Run folder: chunks are written here as they finish and a re-run resumes.
        Without it, a temporary folder is used and removed.
    chunk_size : int
        Points per chunk.
    workers : int, optional
        Worker processes (default: all cores; at most 4 per core); 1 runs in this
        process. Workers end with this process, whatever ends it.
    scheduler : str or dask.distributed.Client, optional
        Run the chunks on a Dask cluster (``"tcp://HOST:PORT"``) instead.
    track : bool
        Track modes by shape along a 1-D sweep and detect crossings and veerings.
    progress : callable, optional
        ``progress(done, total)`` after each chunk.

    Returns
    -------
    SweepResult
    """
    from ..drives import design_and_model

    axes = [axes] if isinstance(axes, Axis) else list(axes)
    if not 1 <= len(axes) <= 2 or not all(isinstance(a, Axis) for a in axes):
        raise ReducerlabError("sweep: give one Axis, or two for a grid")
    if len({a.path for a in axes}) != len(axes):
        raise ReducerlabError("sweep: the two grid axes must be different parameters")
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, int) or chunk_size < 1:
        raise ReducerlabError(f"sweep: chunk_size must be a positive integer, got {chunk_size!r}")
    if workers is not None:
        check_workers(workers, "sweep")
    design, model = design_and_model(target, "sweep")
    groups, columns = [], []
    for i, a in enumerate(axes):
        group, col = axis_targets(design, model, a, i, "sweep")
        groups.append(group)
        columns.append(col)
    targets = tuple(t for group in groups for t in group)
    firsts = tuple(group[0] for group in groups)
    n_points = math.prod(len(c) for c in columns)
    sweep_estimate(n_points, model.n).check()
    grid = np.meshgrid(*columns, indexing="ij")
    points = np.stack([g.ravel() for g in grid], axis=-1)  # (n_points, n_axes)
    ev = _Points(Evaluator(design, model, targets))
    lows = np.array([c.min() for c in columns])
    highs = np.array([c.max() for c in columns])
    vectorised = points.shape[0] > 2 and _affine(ev, lows, highs)
    spec = {
        "axes": [[a.path, [float(x) for x in c]] for a, c in zip(axes, columns, strict=True)],
        "design": design.hash if design is not None else None,
        "model": hashlib.sha256(
            model.matrices().M.tobytes() + model.matrices().K.tobytes()
        ).hexdigest(),
        "chunk_size": chunk_size,
    }
    temporary = output is None
    folder = Path(output) if output is not None else Path(_tempdir())
    try:
        run = _Run(folder, open_run(folder, "sweep.json", spec, "sweep"))
        run.chunks = [
            (i, points[s : s + chunk_size]) for i, s in enumerate(range(0, len(points), chunk_size))
        ]
        jobs = run.missing()
        total, done = len(run.chunks), len(run.chunks) - len(jobs)
        if progress:
            progress(done, total)

        def tick(k: int) -> None:
            nonlocal done
            done += k
            if progress:
                progress(done, total)

        _submit_all(ev, jobs, run, workers, scheduler, tick)
        parts = [run.load(i, pts) for i, pts in run.chunks]
        lam = np.concatenate([p["lam"] for p in parts])
        phi = np.concatenate([p["phi"] for p in parts])
        y = np.concatenate([p["y"] for p in parts])
        result = _assemble(axes, columns, firsts, lam, phi, y, model, design, vectorised)
        if track and len(axes) == 1 and len(columns[0]) > 1:
            _add_tracking(result, ev, columns[0])
        if not temporary:
            result.save(folder / "sweep.nc")  # atomic
        return result
    finally:
        if temporary:
            shutil.rmtree(folder, ignore_errors=True)


def sweep_estimate(points: int, n: int) -> Estimate:
    """Memory of a sweep of ``points`` parameter points of an ``n``-DOF model: per point
    the eigenvalues and two ``n x n`` shape matrices (``shape``, ``weighted_shape``),
    held three times at the end (the chunks, their concatenation and the result; the
    tracking of a 1-D sweep works on a copy), in bytes."""
    per_point = 8.0 * (2 * n * n + 2 * n + 2)
    return Estimate(
        "sweep", 3.0 * per_point * points, float(points), "points",
        control="the number of values (--values, --grid)",
    )  # fmt: skip


def _tempdir() -> str:
    import tempfile

    return tempfile.mkdtemp(prefix="reducerlab-sweep-")


def _assemble(
    axes: list[Axis],
    columns: list[NDArray],
    targets: tuple[Target, ...],
    lam: NDArray,
    phi: NDArray,
    y: NDArray,
    model: Model,
    design: Design | None,
    vectorised: bool,
) -> SweepResult:
    freq = np.sign(lam) * np.sqrt(np.abs(lam)) / TWO_PI
    dims = [f"p{i}" for i in range(len(axes))]
    shape = tuple(len(c) for c in columns)
    n = model.n
    coords: dict[str, Any] = {
        d: (
            d,
            c,
            {"path": a.path, "design_value": t.base, "scale": a.scale}
            | _display(design, model, a.path, c),
        )
        for d, c, a, t in zip(dims, columns, axes, targets, strict=True)
    }
    coords.update(mode=np.arange(1, n + 1), dof=model.dof_names)
    data = xr.Dataset(
        {
            "frequency": ((*dims, "mode"), freq.reshape(*shape, n), {"units": "Hz"}),
            "eigenvalue": ((*dims, "mode"), lam.reshape(*shape, n), {"units": "rad^2/s^2"}),
            "shape": ((*dims, "dof", "mode"), phi.reshape(*shape, n, n)),
            "weighted_shape": ((*dims, "dof", "mode"), y.reshape(*shape, n, n)),
        },
        coords=coords,
        attrs={
            "title": (design.name if design is not None else model.name) or "modal sweep",
            "parameters": json.dumps([a.path for a in axes]),
            "relative": json.dumps([a.relative for a in axes]),
            "vectorised": int(vectorised),
            **provenance(model.metadata),
        },
    )
    return SweepResult(data)


def _display(design: Design | None, model: Model, path: str, values: NDArray) -> dict[str, Any]:
    """The unit figures show a parameter in (``display_unit``, ``display_factor``: N/m for
    a stiffness, kg m^2 for an inertia, rpm for a speed; ``""`` for a plain number)."""
    unit, factor = display_unit(parameter_kind(design, model, path), values)
    return {"display_unit": unit, "display_factor": factor}


def _add_tracking(result: SweepResult, ev: _Points, params: NDArray) -> None:
    ds = result.data
    y = ds["weighted_shape"].values
    freq = ds["frequency"].values

    def evaluate(p: float) -> tuple[NDArray, NDArray]:
        lam_p, _, y_p = ev.solve(np.array([[p]]))
        return lam_p[0], y_p[0]

    tr = track_modes(params, ds["eigenvalue"].values, y, evaluate)
    events = find_events(params, freq, tr.y, tr)
    tf = np.take_along_axis(freq, tr.order, axis=1)
    result.data = ds.assign(
        tracked_frequency=(("p0", "track"), tf, {"units": "Hz"}),
        track_order=(("p0", "track"), tr.order + 1, {"long_name": "sorted mode number"}),
        step_mac=(("step",), tr.min_mac, {"long_name": "min MAC between neighbours"}),
        event_kind=(("event",), np.array([e.kind for e in events], dtype=object)),
        event_param=(("event",), np.array([e.param for e in events], dtype=float)),
        event_modes=(("event", "pair"), np.array([e.modes for e in events]).reshape(-1, 2)),
        event_gap_hz=(("event",), np.array([e.gap_hz for e in events], dtype=float)),
        weighted_shape=(ds["weighted_shape"].dims, tr.y),
    ).assign_coords(track=np.arange(1, freq.shape[1] + 1))
    result.data.attrs["refined_points"] = tr.refined


class SweepResult(Result):
    """Natural frequencies over one or two swept parameters (dims ``p0``, ``p1``).

    Variables: ``frequency`` (sorted), ``eigenvalue``, ``shape``, ``weighted_shape``;
    for 1-D sweeps also ``tracked_frequency`` (p0, track), ``track_order`` and the
    crossing/veering events (``event_kind``, ``event_param``, ``event_modes``,
    ``event_gap_hz``).
    """

    kind: ClassVar[str] = "sweep"

    @property
    def parameters(self) -> list[str]:
        """Swept parameter paths."""
        return json.loads(self.data.attrs["parameters"])

    def events(self) -> list[dict[str, Any]]:
        """Crossings and veerings as dictionaries."""
        ds = self.data
        if "event_kind" not in ds:
            return []
        return [
            {
                "kind": str(k),
                "param": float(p),
                "modes": [int(m) for m in mm],
                "gap_hz": float(g),
            }
            for k, p, mm, g in zip(
                ds["event_kind"].values,
                ds["event_param"].values,
                ds["event_modes"].values,
                ds["event_gap_hz"].values,
                strict=True,
            )
        ]

    def table(self) -> str:
        """Frequencies at the first, middle and last point, and the events."""
        ds = self.data
        lines = [f"{ds.attrs.get('title', '')}: sweep of {', '.join(self.parameters)}"]
        if len(self.parameters) == 1:
            p = ds["p0"].values
            idx = sorted({0, len(p) // 2, len(p) - 1})
            var = "tracked_frequency" if "tracked_frequency" in ds else "frequency"
            f = ds[var].values
            cols = [Column(f"at {fmt(p[i], 'parameter')}", "Hz", "frequency") for i in idx]
            t = Table([Column("mode", kind="count"), *cols])
            for j in range(f.shape[1]):
                t.add(j + 1, *(f[i, j] for i in idx))
            lines.append(t.text())
            ev = self.events()
            lines.append(f"events: {len(ev)}")
            if ev:
                t = Table([Column("event", kind="text"), Column("at", kind="parameter"),
                           Column("modes", kind="text"),
                           Column("gap", "Hz", "frequency")])  # fmt: skip
                for e in ev:
                    t.add(
                        e["kind"], e["param"], f"{e['modes'][0]} and {e['modes'][1]}", e["gap_hz"]
                    )
                lines.append(t.text(indent="  "))
        else:
            lines.append(f"grid {ds.sizes['p0']} x {ds.sizes['p1']} points")
        return "\n".join(lines)

    def plot(self) -> Figure:
        """Tracked frequencies against the parameter, veerings and crossings marked."""
        from ..plot.sweep import plot_sweep

        return plot_sweep(self)
