"""Campbell diagram and resonance check.

Natural frequencies are computed at each input speed with the speed-dependent terms
(centripetal, ...) rebuilt (``Model.with_speed``). Excitation lines are the input
rotation (1x) and the first three harmonics of every mesh frequency; their orders come
from the drive's kinematics, or, for designs without kinematics, from the mesh
stiffness laws of the model. Crossings of natural frequencies with excitation lines are
located by root finding on the exact frequency-speed relation.

The resonance check can also take the finite-element modes of the gear bodies
(:class:`ComponentModes`, paper 000 §4): each body frequency is checked against every
excitation line (a constant frequency meets ``order * speed / 2 pi`` at exactly
``speed = 2 pi f / order``) and against the system natural frequencies (paper 000's
Table 5 comparison).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray
from scipy.optimize import brentq

from ..design import Design
from ..errors import ModelError, ReducerlabError, names_source
from ..model import Model
from ..model.laws import flat_period
from ..model.rigid import RIGID_TOL, element_blocks, rest_stiffness
from ..results import Result, provenance
from .modal import has_skew_terms

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "CampbellResult",
    "ComponentModes",
    "campbell",
    "excitation_orders",
    "format_check",
    "operating_range",
    "resonance_check",
]

TWO_PI = 2.0 * math.pi
RPM = 60.0 / TWO_PI


@dataclass(frozen=True)
class ComponentModes:
    """Natural frequencies of one component (a gear body), computed elsewhere (FE).

    Parameters
    ----------
    label : str
        Name of the component in reports and figures, e.g. ``"gear 1"``.
    frequencies : sequence of float
        Natural frequencies (Hz), ascending (repeated roots allowed), finite, > 0; the
        k-th is mode k (1-based).
    types : sequence of str, optional
        Mode type of each frequency (paper 000's names, e.g. ``"torsional"``), same
        length as ``frequencies``; empty strings where unknown. Default: all empty.
    source : str, optional
        Where the frequencies come from (a file, "ANSYS", "paper 000 Table 4", ...).
    """

    label: str
    frequencies: tuple[float, ...]
    types: tuple[str, ...] = ()
    source: str = ""

    def __post_init__(self) -> None:
        label = self.label
        if not isinstance(label, str) or not label.strip():
            raise ReducerlabError(f"ComponentModes.label must be a non-empty string, got {label!r}")
        where = f"ComponentModes {label!r}"
        raw = self.frequencies
        if isinstance(raw, str | bytes) or not isinstance(raw, Iterable):
            raise ReducerlabError(
                f"{where}: frequencies must be a sequence of numbers (Hz), got {raw!r}"
            )
        if isinstance(raw, np.ndarray) and raw.ndim != 1:
            raise ReducerlabError(
                f"{where}: frequencies must be one-dimensional, got shape {raw.shape}"
            )
        freqs = []
        for i, f in enumerate(raw):
            if isinstance(f, bool | np.bool_) or not isinstance(f, int | float | np.number):
                raise ReducerlabError(f"{where}: frequencies[{i}] must be a number (Hz), got {f!r}")
            freqs.append(float(f))
        if not freqs:
            raise ReducerlabError(f"{where}: frequencies must hold at least one frequency")
        for i, f in enumerate(freqs):
            if not (math.isfinite(f) and f > 0):
                raise ReducerlabError(
                    f"{where}: frequencies must be finite and > 0 Hz, frequencies[{i}] = {f!r}"
                )
        for i in range(1, len(freqs)):
            if freqs[i] < freqs[i - 1]:
                raise ReducerlabError(
                    f"{where}: frequencies must be ascending (mode k is the k-th "
                    f"frequency), frequencies[{i}] = {freqs[i]!r} < frequencies[{i - 1}] = "
                    f"{freqs[i - 1]!r}"
                )
        types = self.types
        if isinstance(types, str) or not isinstance(types, Iterable):
            raise ReducerlabError(
                f"{where}: types must be a sequence of strings (one a frequency), got {types!r}"
            )
        types = tuple(types)
        if not types:
            types = ("",) * len(freqs)
        bad = [t for t in types if not isinstance(t, str)]
        if bad:
            raise ReducerlabError(f"{where}: types must be strings, got {bad[0]!r}")
        if len(types) != len(freqs):
            raise ReducerlabError(
                f"{where}: types must have the same length as frequencies "
                f"({len(freqs)}), got {len(types)}"
            )
        if not isinstance(self.source, str):
            raise ReducerlabError(f"{where}: source must be a string, got {self.source!r}")
        object.__setattr__(self, "frequencies", tuple(freqs))
        object.__setattr__(self, "types", tuple(t.strip() for t in types))

    @classmethod
    def from_body_modal(
        cls, result: Any, label: str | None = None, source: str | None = None
    ) -> ComponentModes:
        """From a :class:`~reducerlab.analysis.body_modal.BodyModalResult` (or anything
        with ``frequencies`` and ``types``); label ``"gear N"`` from its attributes."""
        attrs = getattr(getattr(result, "data", None), "attrs", {}) or {}
        if label is None:
            gear = attrs.get("gear")
            label = f"gear {gear}" if gear is not None else "body"
        if source is None:
            boundary = attrs.get("boundary")
            source = "FE body modes" + (f" ({boundary})" if boundary else "")
        return cls(label, tuple(result.frequencies), tuple(result.types), source)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form."""
        return {
            "label": self.label,
            "frequencies": list(self.frequencies),
            "types": list(self.types),
            "source": self.source,
        }


@names_source
def excitation_orders(target: Design | Model, harmonics: int = 3) -> dict[str, float]:
    """Excitation frequencies as multiples ("orders") of the input rotation frequency.

    ``{"1x input": 1, "1x mesh": z, "2x mesh": 2z, ...}``. From the design's kinematics
    when it has them, otherwise from the periodic mesh-stiffness laws of the model.
    """
    orders = {"1x input": 1.0}
    meshes: dict[str, float] = {}
    kin = getattr(target, "kinematics", None)
    if kin is not None:
        f_unit = kin().mesh_frequencies(1.0)  # Hz at 1 rad/s input
        meshes = {name: f * TWO_PI for name, f in f_unit.items()}
    else:
        model = target if isinstance(target, Model) else None
        if model is None:
            from ..drives import build_model

            model = build_model(target)
        if model.speed > 0:
            s = model.nonlinear()
            for name, kind, params in zip(s.line_names, s.k_kind, s.k_params, strict=True):
                period = flat_period(int(kind), params)
                if math.isfinite(period):
                    meshes[name] = TWO_PI / period / model.speed
    for name, order in meshes.items():
        label = "mesh" if len(meshes) == 1 else name
        for h in range(1, harmonics + 1):
            orders[f"{h}x {label}"] = h * order
    return orders


def _model_of(target: Design | Model) -> Model:
    if isinstance(target, Model):
        return target
    if isinstance(target, Design):
        from ..drives import build_model

        return build_model(target)
    raise ReducerlabError(f"campbell: target must be a Design or a Model, got {type(target)}")


def _frequencies(model: Model, speeds: NDArray, rigid_tol: float = RIGID_TOL) -> NDArray:
    """Frequencies (Hz, speed, mode), each speed solved as ``modal`` would: rigid-body
    modes (no element strained at rest, see
    :func:`~reducerlab.analysis.modal.strain_ratio`) at exactly 0 Hz, the elastic modes
    on their complement where speed terms act."""
    from .sweep import PointModes

    Ms, Ks = [], []
    for w in speeds:
        m = model.with_speed(float(w)).matrices()  # checked: finite, in solver range
        Ms.append(m.M)
        Ks.append(m.K)
    K = np.array(Ks)
    rest = rest_stiffness(model)
    rest = np.broadcast_to(K[0] if rest is None else rest, K.shape)
    modes = PointModes(np.array(Ms), K, rest, element_blocks(model), model.dof_names,
                       f"campbell of {model.name!r}")  # fmt: skip
    try:
        lam, _, _ = modes.solve(rigid_tol)
    except (np.linalg.LinAlgError, ValueError) as exc:
        if isinstance(exc, ReducerlabError):
            raise
        raise ModelError(
            f"campbell: the eigen-solver failed for model {model.name!r} ({exc}); check "
            "for an extreme inertia or stiffness value"
        ) from None
    if not np.all(np.isfinite(lam)):
        raise ModelError(
            f"campbell: non-finite natural frequencies for model {model.name!r}; check for "
            "an extreme inertia or stiffness value"
        )
    return np.sign(lam) * np.sqrt(np.abs(lam)) / TWO_PI


def operating_range(target: Design | Model) -> tuple[float, float]:
    """The design's operating speed range (rad/s): ``speed_range`` if given, else the
    single operating speed."""
    rng = getattr(getattr(target, "operating", None), "speed_range", None) or getattr(
        target, "speed_range", None
    )
    if rng:
        return float(rng[0]), float(rng[1])
    speed = getattr(target, "input_speed", None)
    if speed is None:
        speed = getattr(target, "speed", None)
    if speed is None and isinstance(target, Model):
        speed = target.speed
    return float(speed or 0.0), float(speed or 0.0)


def campbell_axes(
    target: Design | Model,
    model: Model,
    speeds: Sequence[float] | NDArray | None,
    orders: dict[str, float] | None,
    points: int,
    what: str,
) -> tuple[NDArray, float, float, dict[str, float]]:
    """Checked speeds (rad/s; default 0 to 1.5x the top of the operating range), the
    operating range and the excitation orders of a Campbell diagram."""
    lo, hi = operating_range(target)
    if speeds is None:
        top = 1.5 * hi if hi > 0 else 1.5 * max(model.speed, 1.0)
        speeds = np.linspace(0.0, top, points)
    speeds = np.asarray(speeds, dtype=float)
    if speeds.ndim != 1 or speeds.size < 2:
        raise ReducerlabError(f"{what}: give at least two speeds")
    if not np.all(np.isfinite(speeds)) or np.any(speeds < 0) or np.any(np.diff(speeds) <= 0):
        raise ReducerlabError(f"{what}: speeds must be finite, >= 0 and strictly increasing")
    orders = orders if orders is not None else excitation_orders(target)
    if not orders or any(not (o > 0 and math.isfinite(o)) for o in orders.values()):
        raise ReducerlabError(f"{what}: excitation orders must be positive, got {orders}")
    return speeds, lo, hi, orders


def find_crossings(
    freq: NDArray,
    speeds: NDArray,
    orders: dict[str, float],
    at: Any,
) -> list[tuple[int, str, float, float]]:
    """Crossings ``(mode, excitation, speed, frequency)`` of the frequencies
    ``freq`` (speed, mode; Hz) with the excitation lines ``order * speed / 2 pi``,
    found between samples and refined by root finding on ``at(speed)`` (the
    frequencies of every mode at one speed), sorted by speed."""
    exc = np.outer(speeds / TWO_PI, list(orders.values()))
    rows = []
    for j in range(freq.shape[1]):
        if not np.any(freq[:, j] > 0):
            continue  # rigid or divergent throughout
        for k, (name, order) in enumerate(orders.items()):
            g = freq[:, j] - exc[:, k]
            for i in np.nonzero((np.sign(g[:-1]) * np.sign(g[1:]) < 0) & (freq[:-1, j] > 0))[0]:

                def h(w: float, j: int = j, order: float = order) -> float:
                    return float(at(w)[j] - order * w / TWO_PI)

                w = brentq(h, speeds[i], speeds[i + 1], xtol=1e-12 * speeds[-1], rtol=1e-12)
                rows.append((j + 1, name, w, order * w / TWO_PI))
    rows.sort(key=lambda r: r[2])
    return rows


def campbell_dataset(
    target: Design | Model,
    model: Model,
    speeds: NDArray,
    operating: tuple[float, float],
    orders: dict[str, float],
    rows: list[tuple[int, str, float, float]],
    modes: dict[str, Any],
) -> xr.Dataset:
    """A Campbell diagram's dataset: the per-mode variables ``modes`` over (speed,
    mode), the excitation lines and the crossings ``rows`` of :func:`find_crossings`."""
    width = next(iter(modes.values()))[1].shape[1]
    exc = np.outer(speeds / TWO_PI, list(orders.values()))
    return xr.Dataset(
        {
            **modes,
            "excitation_frequency": (("speed", "excitation"), exc, {"units": "Hz"}),
            "order": ("excitation", list(orders.values())),
            "crossing_mode": ("crossing", np.array([r[0] for r in rows], dtype=int)),
            "crossing_excitation": ("crossing", np.array([r[1] for r in rows], dtype=object)),
            "crossing_speed": (
                "crossing",
                np.array([r[2] for r in rows], dtype=float),
                {"units": "rad/s"},
            ),
            "crossing_frequency": (
                "crossing",
                np.array([r[3] for r in rows], dtype=float),
                {"units": "Hz"},
            ),
        },
        coords={
            "speed": ("speed", speeds, {"units": "rad/s"}),
            "mode": np.arange(1, width + 1),
            "excitation": list(orders),
        },
        attrs={
            "title": getattr(target, "name", "") or model.name,
            "operating_min_rad_s": operating[0],
            "operating_max_rad_s": operating[1],
            **provenance(model.metadata),
        },
    )


@names_source
def campbell(
    target: Design | Model,
    speeds: Sequence[float] | NDArray | None = None,
    *,
    orders: dict[str, float] | None = None,
    points: int = 201,
) -> CampbellResult:
    """Natural frequencies against input speed with excitation lines and crossings.

    Parameters
    ----------
    target : Design or Model
    speeds : array_like, optional
        Input speeds (rad/s), ascending, >= 0. Default: 0 to 1.5 x the top of the
        operating range (``points`` values).
    orders : dict, optional
        Excitation name -> order (multiple of the input rotation frequency); default
        :func:`excitation_orders`.
    """
    model = _model_of(target)
    speeds, lo, hi, orders = campbell_axes(target, model, speeds, orders, points, "campbell")
    freq = _frequencies(model, speeds)
    rows = find_crossings(freq, speeds, orders, lambda w: _frequencies(model, np.array([w]))[0])
    data = campbell_dataset(target, model, speeds, (lo, hi), orders, rows,
                            {"frequency": (("speed", "mode"), freq, {"units": "Hz"})})  # fmt: skip
    return CampbellResult(data)


class CampbellResult(Result):
    """Frequencies (speed x mode), excitation lines (speed x excitation), crossings."""

    kind: ClassVar[str] = "campbell"

    def crossings(self) -> list[dict[str, Any]]:
        """Crossings of natural frequencies with excitation lines."""
        ds = self.data
        return [
            {
                "mode": int(m),
                "excitation": str(e),
                "speed_rad_s": float(w),
                "speed_rpm": float(w) * RPM,
                "frequency_hz": float(f),
            }
            for m, e, w, f in zip(
                ds["crossing_mode"].values,
                ds["crossing_excitation"].values,
                ds["crossing_speed"].values,
                ds["crossing_frequency"].values,
                strict=True,
            )
        ]

    def table(self) -> str:
        """Crossings as text."""
        lines = [f"Campbell diagram: {self.data.attrs.get('title', '')}"]
        cr = self.crossings()
        lines.append(f"{len(cr)} crossing(s) of natural frequencies with excitations:")
        for c in cr:
            lines.append(
                f"  mode {c['mode']:>2} x {c['excitation']:<14} at {c['speed_rpm']:10.5g} rpm, "
                f"{c['frequency_hz']:10.5g} Hz"
            )
        return "\n".join(lines)

    def plot(self, components: Sequence[ComponentModes] = ()) -> Figure:
        """Campbell diagram; ``components``: body modes drawn as horizontal lines."""
        from ..plot.sweep import plot_campbell

        return plot_campbell(self, components=components)


def _components(components: Any) -> tuple[ComponentModes, ...]:
    """The ``components`` argument of :func:`resonance_check`, checked."""
    if isinstance(components, ComponentModes):
        return (components,)
    if components is None:
        return ()
    if isinstance(components, str | bytes | dict) or not isinstance(components, Iterable):
        raise ReducerlabError(
            f"components must be a sequence of ComponentModes, got {type(components).__name__}"
        )
    out = tuple(components)
    for c in out:
        if not isinstance(c, ComponentModes):
            raise ReducerlabError(
                f"components must be a sequence of ComponentModes, got an item of type "
                f"{type(c).__name__}"
            )
    labels = [c.label for c in out]
    dup = sorted({lab for lab in labels if labels.count(lab) > 1})
    if dup:
        raise ReducerlabError(f"components: labels must be unique, {dup[0]!r} is repeated")
    return out


def _component_check(
    components: tuple[ComponentModes, ...],
    orders: dict[str, float],
    speeds: NDArray,
    freq: NDArray,
    lo: float,
    hi: float,
    margin: float,
) -> dict[str, Any]:
    """Body modes against excitation lines (exact) and system natural frequencies."""
    crossings, near, coincidences, summary = [], [], [], []
    for comp in components:
        best_exc: dict[str, Any] | None = None
        best_sys: dict[str, Any] | None = None
        for k, (f, kind) in enumerate(zip(comp.frequencies, comp.types, strict=True), 1):
            head = {"component": comp.label, "mode": k, "type": kind}
            for name, order in orders.items():
                w_star = TWO_PI * f / order  # f = order w / 2 pi: exact for a constant f
                if lo <= w_star <= hi:
                    crossings.append(
                        {
                            **head,
                            "excitation": name,
                            "speed_rad_s": w_star,
                            "speed_rpm": w_star * RPM,
                            "frequency_hz": f,
                        }
                    )
                # |f - fe| / fe = |f / fe - 1| is monotone on either side of w*: the
                # closest approach in the range is at w* clipped to it
                w = min(max(w_star, lo), hi)
                fe = order * w / TWO_PI
                row = {
                    **head,
                    "excitation": name,
                    "speed_rpm": w * RPM,
                    "natural_hz": f,
                    "excitation_hz": fe,
                    "distance": abs(f - fe) / fe,
                }
                if row["distance"] <= margin:
                    near.append(row)
                if best_exc is None or row["distance"] < best_exc["distance"]:
                    best_exc = row
            for j in range(freq.shape[1]):
                fn = freq[:, j]
                if np.all(fn <= 0):
                    continue  # rigid (0 Hz) or divergent throughout
                with np.errstate(divide="ignore", invalid="ignore"):
                    rel = np.where(fn > 0, np.abs(f - fn) / fn, np.inf)
                i = int(np.argmin(rel))
                row = {
                    **head,
                    "system_mode": j + 1,
                    "speed_rpm": float(speeds[i] * RPM),
                    "natural_hz": f,
                    "system_hz": float(fn[i]),
                    "distance": float(rel[i]),
                }
                if row["distance"] <= margin:
                    coincidences.append(row)
                if best_sys is None or row["distance"] < best_sys["distance"]:
                    best_sys = row
        strip = ("component",)
        summary.append(
            {
                **comp.to_dict(),
                "closest": {
                    "excitation": None
                    if best_exc is None
                    else {k: v for k, v in best_exc.items() if k not in strip},
                    "system_mode": None
                    if best_sys is None
                    else {k: v for k, v in best_sys.items() if k not in strip},
                },
            }
        )
    crossings.sort(key=lambda r: r["speed_rad_s"])
    near.sort(key=lambda r: r["distance"])
    coincidences.sort(key=lambda r: r["distance"])
    return {
        "component_crossings": crossings,
        "component_near": near,
        "coincidences": coincidences,
        "components": summary,
        "system": {
            "speed_rpm": [float(speeds[0] * RPM), float(speeds[-1] * RPM)],
            "frequencies_hz": [float(v) for v in freq[-1]],
            "min_hz": [float(v) for v in freq.min(axis=0)],
            "max_hz": [float(v) for v in freq.max(axis=0)],
        },
    }


@names_source
def resonance_check(
    target: Design | Model,
    *,
    margin: float = 0.10,
    speed_range: tuple[float, float] | None = None,
    points: int = 101,
    components: Sequence[ComponentModes] | ComponentModes = (),
) -> dict[str, Any]:
    """Resonance verdict over the operating speed range (paper 000's closing check).

    Lists every crossing of a natural frequency with an excitation inside the range,
    and every (mode, excitation) pair whose frequencies come within ``margin``
    (relative to the excitation) somewhere in the range, with the closest approach.

    With ``components`` (finite-element modes of the gear bodies, paper 000 §4), each
    body mode is also checked against

    * every excitation line: a constant body frequency ``f`` meets the line
      ``order * speed / 2 pi`` at exactly ``speed = 2 pi f / order``
      (``component_crossings`` when inside the range); ``component_near`` lists the
      (body mode, excitation) pairs within ``margin`` (relative to the excitation) at
      their exact closest approach in the range;
    * every elastic system natural frequency at the speeds of the range
      (``coincidences`` when within ``margin``, relative to the system frequency):
      paper 000's Table 5 comparison.

    Returns
    -------
    dict
        ``{"ok": bool, "margin": ..., "speed_range_rpm": [...], "crossings": [...],
        "near": [...], "title": ...}``; with components also ``"component_crossings"``,
        ``"component_near"``, ``"coincidences"``, ``"components"`` (per body: label,
        frequencies, types, source and its ``closest`` approach to an excitation and
        to a system mode) and ``"system"`` (the system natural frequencies over the
        range: ``frequencies_hz`` at its top speed, ``min_hz``, ``max_hz``). ``ok`` is
        False if any list of findings is non-empty.
    """
    if not (isinstance(margin, int | float) and 0 < margin < 1):
        raise ReducerlabError(f"margin must be a fraction in (0, 1), got {margin!r}")
    comps = _components(components)
    lo, hi = speed_range if speed_range is not None else operating_range(target)
    if not (0 <= lo <= hi) or not math.isfinite(hi):
        raise ReducerlabError(f"speed range must satisfy 0 <= min <= max, got ({lo}, {hi})")
    if hi == 0:
        raise ReducerlabError("the design has no operating speed: give a speed range")
    speeds = np.linspace(lo, hi, points) if hi > lo else np.array([lo])
    grid = np.unique(np.concatenate([speeds, np.linspace(0.0, 1.5 * hi, 201)]))
    model = _model_of(target)
    # gyroscopic, Coriolis or circulatory terms: check the damped, whirl-split branches
    from .complex_modal import complex_campbell, modes_over, stack_branches

    rows = modes_over(model, speeds)  # complex modes at each speed: stability and branches
    gyroscopic = has_skew_terms(model.with_speed(float(hi)))
    if gyroscopic:
        res: Any = complex_campbell(target, grid)
        freq, _, whirl, _ = stack_branches(rows)
        freq = np.where(np.isnan(freq), 0.0, freq)
    else:
        res = campbell(target, grid)
        freq, whirl = _frequencies(model, speeds), None
    ds = res.data
    orders = dict(zip([str(e) for e in ds["excitation"].values], ds["order"].values, strict=True))
    near = []
    for name, order in orders.items():
        fe = order * speeds / TWO_PI
        for j in range(freq.shape[1]):
            fn = freq[:, j]
            if np.all(fn <= 0):
                continue
            with np.errstate(divide="ignore", invalid="ignore"):
                rel = np.where(fe > 0, np.abs(fn - fe) / fe, np.inf)
            i = int(np.argmin(rel))
            if rel[i] <= margin:
                near.append(
                    {
                        "mode": j + 1,
                        "excitation": name,
                        "speed_rpm": float(speeds[i] * RPM),
                        "natural_hz": float(fn[i]),
                        "excitation_hz": float(fe[i]),
                        "distance": float(rel[i]),
                    }
                    | ({"whirl": str(whirl[i, j])} if whirl is not None else {})
                )
    crossings = [c for c in res.crossings() if lo <= c["speed_rad_s"] <= hi]
    near.sort(key=lambda r: r["distance"])
    stability = _stability(rows, speeds)
    report: dict[str, Any] = {
        "ok": not crossings and not near and not stability["unstable"],
        "margin": margin,
        "frequencies": "complex (damped, whirl-split)" if gyroscopic else "undamped",
        "speed_range_rpm": [lo * RPM, hi * RPM],
        "crossings": crossings,
        "near": near,
        "stability": stability,
        "title": ds.attrs.get("title", ""),
    }
    if comps:
        plain = {name: float(order) for name, order in orders.items()}
        report.update(_component_check(comps, plain, speeds, freq, float(lo), float(hi), margin))
        report["ok"] = report["ok"] and not (
            report["component_crossings"] or report["component_near"] or report["coincidences"]
        )
    return report


def _stability(rows: list[xr.Dataset], speeds: NDArray) -> dict[str, Any]:
    """From the complex modes at each speed (damping, gyroscopic and Coriolis terms): the
    modes that grow (``unstable``) and the smallest damping ratio of an elastic mode."""
    unstable, least = [], None
    for w, ds in zip(speeds, rows, strict=True):
        elastic = ds["whirl"].values != "rigid"
        for m, f, z, g, ok in zip(ds["mode"].values[elastic], ds["frequency"].values[elastic],
                                  ds["damping_ratio"].values[elastic],
                                  ds["growth_rate"].values[elastic],
                                  ds["stable"].values[elastic], strict=True):  # fmt: skip
            if not ok:
                unstable.append({"mode": int(m), "speed_rpm": float(w * RPM),
                                 "frequency_hz": float(f), "growth_rate": float(g)})  # fmt: skip
            if least is None or z < least["damping_ratio"]:
                least = {"mode": int(m), "speed_rpm": float(w * RPM), "frequency_hz": float(f),
                         "damping_ratio": float(z)}  # fmt: skip
    return {"unstable": unstable, "least_damped": least}


def format_check(report: dict[str, Any]) -> str:
    """Human-readable verdict of :func:`resonance_check`."""
    lo, hi = report["speed_range_rpm"]
    rng = f"{lo:.6g} rpm" if lo == hi else f"{lo:.6g}-{hi:.6g} rpm"
    m = 100 * report["margin"]
    lines = [f"Resonance check: {report['title']} over {rng}, margin {m:g} %"]
    if report.get("frequencies", "undamped") != "undamped":
        lines.append(f"  frequencies: {report['frequencies']}")
    for c in report["crossings"]:
        whirl = f", {c['whirl']} whirl" if c.get("whirl") else ""
        lines.append(
            f"  CROSSING  mode {c['mode']} with {c['excitation']} at {c['speed_rpm']:.5g} rpm "
            f"({c['frequency_hz']:.5g} Hz{whirl})"
        )
    for r in report["near"]:
        lines.append(
            f"  NEAR      mode {r['mode']} ({r['natural_hz']:.5g} Hz"
            + (f", {r['whirl']} whirl" if r.get("whirl") else "")
            + ") within "
            f"{100 * r['distance']:.2f} % of {r['excitation']} ({r['excitation_hz']:.5g} Hz) "
            f"at {r['speed_rpm']:.5g} rpm"
        )
    for c in report.get("component_crossings", ()):
        lines.append(
            f"  CROSSING  {_body_mode(c)} with {c['excitation']} at {c['speed_rpm']:.5g} rpm "
            f"({c['frequency_hz']:.5g} Hz)"
        )
    for r in report.get("component_near", ()):
        lines.append(
            f"  NEAR      {_body_mode(r)} ({r['natural_hz']:.5g} Hz) within "
            f"{100 * r['distance']:.2f} % of {r['excitation']} ({r['excitation_hz']:.5g} Hz) "
            f"at {r['speed_rpm']:.5g} rpm"
        )
    for r in report.get("coincidences", ()):
        lines.append(
            f"  COINCIDE  {_body_mode(r)} ({r['natural_hz']:.5g} Hz) within "
            f"{100 * r['distance']:.2f} % of system mode {r['system_mode']} "
            f"({r['system_hz']:.5g} Hz) at {r['speed_rpm']:.5g} rpm"
        )
    for comp in report.get("components", ()):
        f = comp["frequencies"]
        parts = [f"  BODY      {comp['label']}: {len(f)} mode(s) {f[0]:.5g}-{f[-1]:.5g} Hz"]
        ex, sy = comp["closest"]["excitation"], comp["closest"]["system_mode"]
        if ex is not None:
            parts.append(
                f"closest excitation {100 * ex['distance']:.2f} % (mode {ex['mode']} x "
                f"{ex['excitation']})"
            )
        if sy is not None:
            parts.append(
                f"closest system mode {100 * sy['distance']:.2f} % (mode {sy['mode']} ~ "
                f"system mode {sy['system_mode']})"
            )
        lines.append(", ".join(parts))
    st = report.get("stability")
    if st is not None:
        for u in st["unstable"][:10]:
            lines.append(
                f"  UNSTABLE  mode {u['mode']} ({u['frequency_hz']:.5g} Hz) grows at "
                f"{u['growth_rate']:.4g} 1/s at {u['speed_rpm']:.5g} rpm"
            )
        if len(st["unstable"]) > 10:
            lines.append(f"  ... {len(st['unstable']) - 10} more unstable (mode, speed) pairs")
        z = st["least_damped"]
        if z is not None:
            lines.append(
                f"  DAMPING   least damped: mode {z['mode']} ({z['frequency_hz']:.5g} Hz), "
                f"damping ratio {z['damping_ratio']:.4g} at {z['speed_rpm']:.5g} rpm"
            )
    lines.append(
        "verdict: no resonance risk" if report["ok"] else "verdict: RESONANCE RISK (see above)"
    )
    return "\n".join(lines)


def _body_mode(row: dict[str, Any]) -> str:
    """``"gear 1 mode 3 (folding)"`` of a component row."""
    kind = f" ({row['type']})" if row.get("type") else ""
    return f"{row['component']} mode {row['mode']}{kind}"
