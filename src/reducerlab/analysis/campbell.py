"""Campbell diagram and resonance check.

Natural frequencies are computed at each input speed with the speed-dependent terms
(centripetal, ...) rebuilt (``Model.with_speed``). Excitation lines are the input
rotation (1x) and the first three harmonics of every mesh frequency; their orders come
from the drive's kinematics, or, for designs without kinematics, from the mesh
stiffness laws of the model. Crossings of natural frequencies with excitation lines are
located by root finding on the exact frequency-speed relation.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray
from scipy.optimize import brentq

from ..design import Design
from ..errors import ModelError, ReducerlabError, names_source
from ..model import Model
from ..model.laws import flat_period
from ..results import Result, provenance
from .modal import RIGID_TOL, element_blocks, rest_stiffness

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = [
    "CampbellResult",
    "campbell",
    "excitation_orders",
    "format_check",
    "operating_range",
    "resonance_check",
]

TWO_PI = 2.0 * math.pi
RPM = 60.0 / TWO_PI


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
    lo, hi = operating_range(target)
    if speeds is None:
        top = 1.5 * hi if hi > 0 else 1.5 * max(model.speed, 1.0)
        speeds = np.linspace(0.0, top, points)
    speeds = np.asarray(speeds, dtype=float)
    if speeds.ndim != 1 or speeds.size < 2:
        raise ReducerlabError("campbell: give at least two speeds")
    if not np.all(np.isfinite(speeds)) or np.any(speeds < 0) or np.any(np.diff(speeds) <= 0):
        raise ReducerlabError("campbell: speeds must be finite, >= 0 and strictly increasing")
    orders = orders if orders is not None else excitation_orders(target)
    if not orders or any(not (o > 0 and math.isfinite(o)) for o in orders.values()):
        raise ReducerlabError(f"campbell: excitation orders must be positive, got {orders}")
    freq = _frequencies(model, speeds)
    exc = np.outer(speeds / TWO_PI, list(orders.values()))
    rows = []
    for j in range(freq.shape[1]):
        if np.all(freq[:, j] <= 0):
            continue  # rigid or divergent throughout
        for k, (name, order) in enumerate(orders.items()):
            g = freq[:, j] - exc[:, k]
            for i in np.nonzero((np.sign(g[:-1]) * np.sign(g[1:]) < 0) & (freq[:-1, j] > 0))[0]:

                def h(w: float, j: int = j, order: float = order) -> float:
                    return float(_frequencies(model, np.array([w]))[0, j] - order * w / TWO_PI)

                w = brentq(h, speeds[i], speeds[i + 1], xtol=1e-12 * speeds[-1], rtol=1e-12)
                rows.append((j + 1, name, w, order * w / TWO_PI))
    rows.sort(key=lambda r: r[2])
    data = xr.Dataset(
        {
            "frequency": (("speed", "mode"), freq, {"units": "Hz"}),
            "excitation_frequency": (("speed", "excitation"), exc, {"units": "Hz"}),
            "order": ("excitation", list(orders.values())),
            "crossing_mode": ("crossing", np.array([r[0] for r in rows], dtype=int)),
            "crossing_excitation": ("crossing", np.array([r[1] for r in rows], dtype=object)),
            "crossing_speed": ("crossing", np.array([r[2] for r in rows]), {"units": "rad/s"}),
            "crossing_frequency": ("crossing", np.array([r[3] for r in rows]), {"units": "Hz"}),
        },
        coords={
            "speed": ("speed", speeds, {"units": "rad/s"}),
            "mode": np.arange(1, freq.shape[1] + 1),
            "excitation": list(orders),
        },
        attrs={
            "title": getattr(target, "name", "") or model.name,
            "operating_min_rad_s": lo,
            "operating_max_rad_s": hi,
            **provenance(model.metadata),
        },
    )
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

    def plot(self) -> Figure:
        """Campbell diagram."""
        from ..plot.sweep import plot_campbell

        return plot_campbell(self)


@names_source
def resonance_check(
    target: Design | Model,
    *,
    margin: float = 0.10,
    speed_range: tuple[float, float] | None = None,
    points: int = 101,
) -> dict[str, Any]:
    """Resonance verdict over the operating speed range (paper 000's closing check).

    Lists every crossing of a natural frequency with an excitation inside the range,
    and every (mode, excitation) pair whose frequencies come within ``margin``
    (relative to the excitation) somewhere in the range, with the closest approach.

    Returns
    -------
    dict
        ``{"ok": bool, "margin": ..., "speed_range_rpm": [...], "crossings": [...],
        "near": [...]}``.
    """
    if not (isinstance(margin, int | float) and 0 < margin < 1):
        raise ReducerlabError(f"margin must be a fraction in (0, 1), got {margin!r}")
    lo, hi = speed_range if speed_range is not None else operating_range(target)
    if not (0 <= lo <= hi) or not math.isfinite(hi):
        raise ReducerlabError(f"speed range must satisfy 0 <= min <= max, got ({lo}, {hi})")
    if hi == 0:
        raise ReducerlabError("the design has no operating speed: give a speed range")
    speeds = np.linspace(lo, hi, points) if hi > lo else np.array([lo])
    grid = np.unique(np.concatenate([speeds, np.linspace(0.0, 1.5 * hi, 201)]))
    res = campbell(target, grid)
    ds = res.data
    orders = dict(zip([str(e) for e in ds["excitation"].values], ds["order"].values, strict=True))
    freq = _frequencies(_model_of(target), speeds)
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
                )
    crossings = [c for c in res.crossings() if lo <= c["speed_rad_s"] <= hi]
    near.sort(key=lambda r: r["distance"])
    return {
        "ok": not crossings and not near,
        "margin": margin,
        "speed_range_rpm": [lo * RPM, hi * RPM],
        "crossings": crossings,
        "near": near,
        "title": ds.attrs.get("title", ""),
    }


def format_check(report: dict[str, Any]) -> str:
    """Human-readable verdict of :func:`resonance_check`."""
    lo, hi = report["speed_range_rpm"]
    rng = f"{lo:.6g} rpm" if lo == hi else f"{lo:.6g}-{hi:.6g} rpm"
    m = 100 * report["margin"]
    lines = [f"Resonance check: {report['title']} over {rng}, margin {m:g} %"]
    for c in report["crossings"]:
        lines.append(
            f"  CROSSING  mode {c['mode']} with {c['excitation']} at {c['speed_rpm']:.5g} rpm "
            f"({c['frequency_hz']:.5g} Hz)"
        )
    for r in report["near"]:
        lines.append(
            f"  NEAR      mode {r['mode']} ({r['natural_hz']:.5g} Hz) within "
            f"{100 * r['distance']:.2f} % of {r['excitation']} ({r['excitation_hz']:.5g} Hz) "
            f"at {r['speed_rpm']:.5g} rpm"
        )
    lines.append(
        "verdict: no resonance risk" if report["ok"] else "verdict: RESONANCE RISK (see above)"
    )
    return "\n".join(lines)
