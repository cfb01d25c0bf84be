"""Monte-Carlo over tolerances (issue 31): the distribution of the lost motion and the
transmission error of a drive whose design fields are drawn from distributions.

``tolerances(design, {"mesh.backlash": "60..100 um", ...})`` draws every sample's field
values up front (:mod:`.tolerance_specs`: uniform or normal, a pitch-deviation list one
closed draw per tooth), each field from its own random stream seeded by the run's seed
and the field's path, so that the same seed gives the same samples whatever evaluates
them (this process, or a Dask cluster in any chunking) and adding a field leaves the
others' draws alone. Where an ``eccentricity`` is toleranced and its
``eccentricity_phase`` is not, the phase is drawn uniform on ``[0, 360) deg``: a gear's
runout direction is not controlled in assembly.

Each sample applies its values to the design's data (the ``--set`` paths of
:func:`reducerlab.design_files.apply_overrides`), validates it (a value that breaks a
field's rule fails the run naming the sample, the field and the rule), and runs:

* the torsion test with the input held (:func:`.torsion_test.torsion_test`) at the
  nominal design's rated torque: lost motion at +/-3 % of rated and the backlash;
* the rigid-kinematics transmission error over one output revolution
  (:func:`.transmission_accuracy.transmission_accuracy`), its peak to peak, where the
  drive has it (a drive it refuses for the nominal design is reported as such and the
  run gives the lost motion alone).

The statistics of each quantity ``x_1..x_n``: mean, sample standard deviation
(``n - 1``), and the 5th and 95th percentiles (linear interpolation between order
statistics, numpy's default: Hyndman and Fan 1996, definition 7), with the standard
error of the mean ``s / sqrt(n)``.

The samples run in chunks; each finished chunk is written to the run folder at once
(:mod:`.runfolder`, stamped with the run key and the chunk's drawn values), so an
interrupted run loses nothing computed and running it again into the same folder
computes only the missing chunks. Chunks run in this process, or on a Dask cluster
(``scheduler``), whose workers return their arrays to this process, which writes them.
"""

from __future__ import annotations

import copy
import json
import math
import shutil
import tempfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..budget import Estimate
from ..design_files import lookup, set_path
from ..errors import DesignError, ReducerlabError, names_source
from ..numformat import Column, Table, Value, fmt, unit_kind
from ..results import Result, provenance
from ..units import QUANTITIES as QUANTITY_KINDS
from .runfolder import chunk_path, load_chunk, open_run, save_chunk
from .tolerance_specs import Distribution, Tolerance, teeth_path, tolerance_items, unit_factor
from .workers import dask_client

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["MAX_SAMPLES", "TolerancesResult", "tolerance_estimate", "tolerances"]

Array = NDArray[np.float64]
ARCMIN = math.pi / (180.0 * 60.0)
ARCSEC = ARCMIN / 60.0
#: Most samples of one run.
MAX_SAMPLES = 100_000
#: Problems shown of a sample that is not a valid design.
SHOW_PROBLEMS = 4
#: Most static solves of one run (samples x the torsion test's solves).
MAX_SOLVES = 5e7
#: The quantities of a sample: (variable, label, display unit, radians per unit).
QUANTITIES = (
    ("lost_motion", "lost motion at +/-3 % rated", "arcmin", ARCMIN),
    ("backlash", "backlash", "arcmin", ARCMIN),
    ("te_peak_to_peak", "transmission error, peak to peak", "arcsec", ARCSEC),
)


class TolerancesResult(Result):
    """Per-sample lost motion, backlash and transmission error and their statistics.

    ``data`` has the dimension ``sample`` with ``lost_motion``, ``backlash`` and (where
    the drive has it) ``te_peak_to_peak`` (rad), the drawn scalar values ``value``
    (``sample`` x ``field``, SI) and the drawn pitch deviations ``pitch_deviation``
    (``sample`` x ``pitch_field`` x ``tooth``, m; NaN past a gear's teeth). Attributes:
    ``QUANTITY_mean``, ``_std``, ``_p5``, ``_p95``, ``_sem`` (rad), ``samples``,
    ``seed``, ``tolerances`` (JSON: path -> distribution text).
    """

    kind: ClassVar[str] = "tolerances"

    def quantities(self) -> list[tuple[str, str, str, float]]:
        """The quantities this result holds (:data:`QUANTITIES` rows)."""
        return [q for q in QUANTITIES if q[0] in self.data]

    def values(self, name: str) -> Array:
        """Per-sample values of ``name`` (rad)."""
        return np.asarray(self.data[name].values, float)

    def statistics(self) -> dict[str, dict[str, float]]:
        """Mean, std, p5, p95 and standard error of each quantity in its display unit."""
        a = self.data.attrs
        return {
            f"{name}_{unit}": {s: float(a[f"{name}_{s}"]) / per for s in _STATS}
            for name, _, unit, per in self.quantities()
        }

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: the run's settings, the statistics and the samples."""
        a = self.data.attrs
        out: dict[str, Any] = {k: (v.item() if hasattr(v, "item") else v)
                               for k, v in a.items() if k != "design"}  # fmt: skip
        out["tolerances"] = json.loads(a["tolerances"])
        out["statistics"] = self.statistics()
        out["samples_values"] = {
            f"{name}_{unit}": (self.values(name) / per).tolist()
            for name, _, unit, per in self.quantities()
        }
        out["drawn"] = {str(f): self.data["value"].sel(field=f).values.tolist()
                        for f in self.data["field"].values}  # fmt: skip
        return out

    def table(self) -> str:
        """Plain-text summary."""
        a = self.data.attrs
        lines = [
            f"Monte-Carlo over tolerances: {a['samples']} samples, seed {a['seed']}; torsion "
            f"test at {fmt(a['rated_torque'], 'torque')} N m ({a['steps']} steps)",
            "tolerances:",
        ]
        lines += [f"  {p} ~ {t}" for p, t in json.loads(a["tolerances"]).items()]
        if "te_peak_to_peak" not in self.data:
            lines.append(f"transmission error: {a['transmission_accuracy']}")
        t = Table([Column("quantity", kind="text"), *(Column(s) for s in ("mean", "std", "p5",
                   "p95")), Column("unit", kind="text")])  # fmt: skip
        for name, label, unit, per in self.quantities():
            v = [float(a[f"{name}_{s}"]) / per for s in ("mean", "std", "p5", "p95")]
            t.add(label, *(Value(x, unit_kind(unit)) for x in v), unit)
        lines.append(t.text())
        return "\n".join(lines)

    def figure(self) -> Figure:
        """Histograms and empirical CDFs with the mean and p95 marked."""
        from ..plot.tolerances import plot_tolerances

        return plot_tolerances(self)

    plot = figure


_STATS = ("mean", "std", "p5", "p95", "sem")


def statistics(x: Array) -> dict[str, float]:
    """Mean, sample standard deviation (``n - 1``), 5th and 95th percentiles (numpy's
    linear interpolation) and the standard error of the mean ``s / sqrt(n)``."""
    s = float(np.std(x, ddof=1))
    return {"mean": float(np.mean(x)), "std": s, "p5": float(np.percentile(x, 5)),
            "p95": float(np.percentile(x, 95)), "sem": s / math.sqrt(len(x))}  # fmt: skip


def tolerance_estimate(samples: int, steps: int, numbers: int) -> Estimate:
    """Work (static solves: each sample's torsion test solves four branches of
    ``steps + 5`` torques) and memory (the drawn values and results, three copies) of a
    run; at most :data:`MAX_SOLVES` solves."""
    solves = float(samples) * 4 * (steps + 5)
    memory = 8.0 * 3 * samples * (numbers + len(QUANTITIES))
    return Estimate(
        f"Monte-Carlo over tolerances: {samples} samples of a torsion test "
        f"({4 * (steps + 5)} static solves each) and a transmission error", memory, solves,
        "static solves", MAX_SOLVES, "the samples or the torsion test's steps",
    )  # fmt: skip


@dataclass(frozen=True)
class _Job:
    """What a chunk needs (picklable): the design's data, the fields and their columns
    in a row of drawn values, and the analyses' settings."""

    base: dict[str, Any]
    fields: tuple[tuple[str, int, int, bool], ...]  # path, first column, width, per tooth
    source: str
    rated: float
    steps: int
    te_samples: int
    te: bool
    mu: float | None = None

    def design(self, row: Array, index: int) -> Any:
        """The sample's validated design."""
        from ..drives import design_from_dict

        data = copy.deepcopy(self.base)
        for path, start, width, per_tooth in self.fields:
            v = row[start : start + width]
            set_path(data, path, [float(x) for x in v] if per_tooth else float(v[0]), path)
        try:
            return design_from_dict(data, f"{self.source} (sample {index})")
        except DesignError as exc:
            lines = exc.problems[:SHOW_PROBLEMS]
            more = len(exc.problems) - len(lines)
            lines += [f"... and {more} more"] if more > 0 else []
            raise ReducerlabError(
                f"tolerances: sample {index} is not a valid design "
                "(a distribution reaches values its field refuses):\n  " + "\n  ".join(lines)
            ) from None

    def evaluate(self, row: Array, index: int) -> tuple[float, float, float]:
        """Lost motion at +/-3 %, backlash and TE peak to peak (rad) of one sample."""
        from .torsion_test import torsion_test
        from .transmission_accuracy import transmission_accuracy

        d = self.design(row, index)
        n = torsion_test(d, rated=self.rated, steps=self.steps, mu=self.mu).numbers
        te = math.nan
        if self.te:
            te = transmission_accuracy(d, samples=self.te_samples).peak_to_peak * ARCSEC
        return n.lost_motion_3, n.backlash, te


def run_chunk(job: _Job, rows: Array, first: int) -> dict[str, Array]:
    """The results of the samples ``rows`` (drawn values, one row each; the first is
    sample ``first``): ``lost_motion``, ``backlash``, ``te_peak_to_peak`` (rad)."""
    out = np.array([job.evaluate(r, first + i) for i, r in enumerate(rows)]).reshape(-1, 3)
    return {name: out[:, k].copy() for k, (name, *_) in enumerate(QUANTITIES)}


def _resolve(base: dict[str, Any], items: list, dump: dict[str, Any]) -> list:
    """The tolerances with their unit factors and teeth, the automatic eccentricity
    phases added; each distribution's bounds checked against the field's rules."""
    from ..drives import design_from_dict

    tols: list[Tolerance] = []
    paths = {p for p, _, _ in items}
    for path, dist, label in items:
        factor = unit_factor(dist.unit, label)
        teeth = 0
        tp = teeth_path(path)
        if path.rsplit(".", 1)[-1] == "pitch_deviations":
            z = lookup(dump, tp) if tp is not None else None
            if isinstance(z, bool) or not isinstance(z, int) or z < 1:
                raise ReducerlabError(f"{label}: cannot tell the number of teeth of the gear "
                                      f"of {path} (looked for {tp})")  # fmt: skip
            if dist.centre != 0:
                raise ReducerlabError(f"{label}: pitch deviations are drawn per tooth and "
                                      "closed (sum zero): the distribution must be centred "
                                      "on 0, e.g. '0 +- 2 um' or '-3..3 um'")  # fmt: skip
            teeth = z
        tols.append(Tolerance(path, dist, label, factor, teeth))
        phase = path.removesuffix("eccentricity") + "eccentricity_phase"
        if path.endswith(".eccentricity") and phase not in paths:
            auto = Distribution("uniform", 0.0, 360.0, "deg", "0..360 deg")
            tols.append(Tolerance(phase, auto, f"{phase} (drawn: {path} is toleranced)",
                                  math.pi / 180.0))  # fmt: skip
    tols = [replace(t, floor=_floor(base, t)) for t in tols]
    for t in tols:  # each bound as the design file would give it, the others nominal
        for v in sorted(set(t.dist.bounds)):
            text = f"{v!r} {t.dist.unit}".strip() if t.dist.unit else v
            data = copy.deepcopy(base)
            set_path(data, t.path, _probe_list(v, t) if t.per_tooth else text, t.option)
            try:
                probe = design_from_dict(data, f"{t.option}, at {v:g} {t.dist.unit}".strip())
            except DesignError as exc:
                raise ReducerlabError(f"tolerances: {exc}") from None
            got = lookup(probe.model_dump(), t.path)
            got = got[0] if t.per_tooth and got else got
            if isinstance(got, int | float) and not math.isclose(
                float(got), t.factor * v, rel_tol=1e-9, abs_tol=1e-300
            ):
                raise ReducerlabError(f"{t.option}: the unit {t.dist.unit!r} reads as "
                                      f"{got!r} SI for {v:g}, not {t.factor * v!r}")  # fmt: skip
    return tols


#: Candidate smallest nonzero magnitudes of a field (SI): the kinds' ``lo``.
_FLOORS = sorted({k.lo for k in QUANTITY_KINDS.values()})


def _floor(base: dict[str, Any], t: Tolerance) -> float:
    """The smallest nonzero magnitude the field ``t.path`` takes (SI): the least of the
    quantity kinds' floors (:data:`reducerlab.units.QUANTITIES`) that its rules accept,
    tried on the side of zero the distribution reaches; 0 when none is accepted."""
    from ..drives import design_from_dict

    sign = 1.0 if t.dist.bounds[1] > 0 or t.per_tooth else -1.0
    for lo in _FLOORS:
        data = copy.deepcopy(base)
        v = sign * lo
        set_path(data, t.path, _probe_list(v, t, si=True) if t.per_tooth else v, t.option)
        try:
            design_from_dict(data)
        except DesignError:
            continue
        return lo
    return 0.0


def _probe_list(v: float, t: Tolerance, si: bool = False) -> list[Any]:
    """A closed list of pitch deviations ``v, -v, v, ...`` (0 last for an odd count) in
    the distribution's unit (its bound as a design file gives it), or in SI."""
    signs = [(-1.0) ** k for k in range(t.teeth - t.teeth % 2)] + [0.0] * (t.teeth % 2)
    if si or not t.dist.unit:
        return [s * v for s in signs]
    return [f"{s * v!r} {t.dist.unit}" for s in signs]


def _draw(tols: list[Tolerance], samples: int, seed: int) -> tuple[Array, list[tuple]]:
    """All samples' values (samples x columns, SI) and each field's columns; each field
    from its own stream ``SeedSequence(seed, spawn_key=path bytes)``."""
    cols, fields, start = [], [], 0
    for t in tols:
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=tuple(t.path.encode())))
        v = t.draw(rng, samples).reshape(samples, -1)
        cols.append(v)
        fields.append((t.path, start, v.shape[1], t.per_tooth))
        start += v.shape[1]
    return np.concatenate(cols, axis=1), fields


@names_source
def tolerances(
    design: Any,
    tols: Mapping[str, str | Distribution] | Sequence[str],
    *,
    samples: int = 1000,
    seed: int = 0,
    steps: int = 4,
    rated: float | None = None,
    mu: float | None = None,
    te_samples: int = 4096,
    chunk_size: int = 50,
    output: str | Path | None = None,
    scheduler: Any = None,
    progress: Callable[[int, int], None] | None = None,
) -> TolerancesResult:
    """Monte-Carlo over tolerance fields: distributions of lost motion, backlash and
    transmission error (module docstring).

    Parameters
    ----------
    design : Design
        The nominal design (``reducerlab.drives.load_design``).
    tols : mapping or sequence
        ``{path: "60..100 um" | "80 +- 5 um" | Distribution}``, or ``"PATH=DIST"`` and
        ``(path, DIST, label)`` items (:func:`.tolerance_specs.tolerance_items`).
    samples : int
        Number of samples, 2 .. :data:`MAX_SAMPLES`.
    seed : int
        Seed (>= 0) of the draws; the same seed gives the same samples.
    steps : int
        Torque steps of each torsion test (>= 3; the lost motion is read at a solved
        point whatever the steps).
    rated : float, optional
        Rated output torque (N m); default the nominal design's output torque.
    mu : float, optional
        Coulomb coefficient of the torsion test's sliding contacts (``torsion_test``'s
        ``mu``; 0: frictionless); default the design's.
    te_samples : int
        Steps over the output revolution of each transmission error (64 .. 2**20).
    chunk_size : int
        Samples per chunk (written to the run folder when finished).
    output : path, optional
        Run folder (the manifest ``tolerances-run.json`` and ``chunks/``; resumable): a
        run into it again computes only the chunks it lacks. A temporary one without it.
    scheduler : str or dask.distributed.Client, optional
        Run the chunks on a Dask cluster.
    progress : callable, optional
        ``progress(done, total)`` samples after each chunk.

    Returns
    -------
    TolerancesResult
    """
    from ..drives import design_from_dict

    for name, value, lo, hi in (("samples", samples, 2, MAX_SAMPLES), ("seed", seed, 0, 2**63 - 1),
                                ("steps", steps, 3, 10000), ("te_samples", te_samples, 64, 2**20),
                                ("chunk_size", chunk_size, 1, MAX_SAMPLES)):  # fmt: skip
        if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
            raise ReducerlabError(f"tolerances: {name} must be an integer in {lo} .. {hi}; "
                                  f"got {value!r}")  # fmt: skip
    items = tolerance_items(tols, "tolerance" if isinstance(tols, Mapping) else "--tol")
    if not items:
        raise ReducerlabError("tolerances: give at least one toleranced field")
    source = getattr(design, "_source", None) or "<design>"
    base = design.model_dump(exclude_unset=True)
    if design_from_dict(copy.deepcopy(base), source) != design:  # pragma: no cover
        raise ReducerlabError("tolerances: the design does not read back from its own data")
    dump = design.model_dump()
    if rated is None:
        rated = float(design.operating_point().output_torque)
    if not (isinstance(rated, int | float) and math.isfinite(rated) and rated > 0):
        raise ReducerlabError(f"tolerances: the rated torque must be > 0 N m; got {rated!r}")
    tol_list = _resolve(base, items, dump)
    numbers = sum(t.teeth or 1 for t in tol_list)
    tolerance_estimate(samples, steps, numbers).check()
    te, te_note = _te_support(design, te_samples)
    values, fields = _draw(tol_list, samples, seed)
    job = _Job(base, tuple(fields), source, float(rated), steps, te_samples, te, mu)
    for i, row in enumerate(values):  # every sample valid before any work (~0.1 ms each)
        job.design(row, i)
    spec = {"design": design.hash, "tolerances": {t.path: t.dist.text for t in tol_list},
            "samples": samples, "seed": seed, "steps": steps, "rated": float(rated), "mu": mu,
            "te_samples": te_samples, "chunk_size": chunk_size}  # fmt: skip
    temporary = output is None
    folder = Path(output) if output is not None else Path(tempfile.mkdtemp(prefix="rl-tol-"))
    try:
        key = open_run(folder, "tolerances-run.json", spec, "Monte-Carlo run")
        chunks = [(i, s) for i, s in enumerate(range(0, samples, chunk_size))]
        rows = {i: values[s : s + chunk_size] for i, s in chunks}
        todo = [(i, s) for i, s in chunks if not chunk_path(folder, i).exists()]
        for i, _ in chunks:
            if chunk_path(folder, i).exists():
                load_chunk(chunk_path(folder, i), key, i, rows[i])  # stamp checked
        done = samples - sum(len(rows[i]) for i, _ in todo)
        if progress:
            progress(done, samples)

        def finish(i: int, arrays: dict[str, Array]) -> None:
            nonlocal done
            save_chunk(chunk_path(folder, i), key, i, rows[i], arrays)
            done += len(rows[i])
            if progress:
                progress(done, samples)

        _run_all(job, todo, rows, scheduler, finish)
        names = [q[0] for q in QUANTITIES]
        parts = [load_chunk(chunk_path(folder, i), key, i, rows[i], names) for i, _ in chunks]
        out = {n: np.concatenate([p[n] for p in parts]) for n in names}
        result = _assemble(design, tol_list, fields, values, out, te_note, job, seed)
        return result
    finally:
        if temporary:
            shutil.rmtree(folder, ignore_errors=True)


def _te_support(design: Any, te_samples: int) -> tuple[bool, str]:
    """Whether the transmission error is computed for this drive (tried on the nominal
    design: a drive it is not written for raises), and the note for the result."""
    from .transmission_accuracy import transmission_accuracy

    try:
        transmission_accuracy(design, samples=64)
    except ReducerlabError as exc:
        return False, f"not computed ({exc})"
    return True, f"rigid kinematics, {te_samples} steps over one output revolution"


def _run_all(job: _Job, todo: list, rows: dict, scheduler: Any, finish: Callable) -> None:
    """Run the chunks still to do, here or on Dask, calling ``finish`` (which writes the
    chunk) as each one ends."""
    if not todo:
        return
    if scheduler is None:
        for i, s in todo:
            finish(i, run_chunk(job, rows[i], s))
        return
    from dask.distributed import as_completed

    with dask_client(scheduler, "tolerances") as client:
        [job_f] = client.scatter([job], broadcast=True)
        futures = {client.submit(run_chunk, job_f, rows[i], s, pure=False): i for i, s in todo}
        for f in as_completed(list(futures)):
            finish(futures[f], f.result())


def _assemble(
    design: Any,
    tols: list[Tolerance],
    fields: list,
    values: Array,
    out: dict[str, Array],
    te_note: str,
    job: _Job,
    seed: int,
) -> TolerancesResult:
    n = values.shape[0]
    scalar = [(p, s) for p, s, _, per in fields if not per]
    pitch = [(p, s, w) for p, s, w, per in fields if per]
    width = max((w for *_, w in pitch), default=0)
    pd = np.full((n, len(pitch), width), np.nan)
    for k, (_, s, w) in enumerate(pitch):
        pd[:, k, :w] = values[:, s : s + w]
    dvars: dict[str, Any] = {
        "value": (("sample", "field"), values[:, [s for _, s in scalar]].reshape(n, len(scalar))),
        "pitch_deviation": (("sample", "pitch_field", "tooth"), pd, {"units": "m"}),
    }
    stats: dict[str, float] = {}
    for name, label, *_ in QUANTITIES:
        if name == "te_peak_to_peak" and not job.te:
            continue
        dvars[name] = ("sample", out[name], {"units": "rad", "long_name": label})
        stats.update({f"{name}_{k}": v for k, v in statistics(out[name]).items()})
    ds = xr.Dataset(
        dvars,
        coords={"sample": np.arange(n), "field": [p for p, _ in scalar],
                "pitch_field": [p for p, *_ in pitch], "tooth": np.arange(width)},
        attrs={"title": "Monte-Carlo over tolerances", **provenance(design.provenance)},
    )  # fmt: skip
    ds.attrs.update(
        samples=n, seed=seed, steps=job.steps, rated_torque=job.rated,
        te_samples=job.te_samples, transmission_accuracy=te_note,
        tolerances=json.dumps({t.path: t.dist.text for t in tols}),
        phase_rule="an eccentricity toleranced without its phase: phase uniform 0..360 deg",
        pitch_rule="pitch deviations: drawn per tooth, then each gear's mean subtracted",
        **stats,
    )  # fmt: skip
    return TolerancesResult(ds)
