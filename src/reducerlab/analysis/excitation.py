"""The excitation side of a Campbell diagram, shared by the undamped
(:mod:`.campbell`) and the complex (:mod:`.complex_modal`) diagrams and the resonance
verdict (:mod:`.resonance`): the operating speed range, the excitation orders, the speed
axis, the crossings of frequency branches with the excitation lines and the diagram's
dataset.

Excitation lines are the input rotation (1x) and the first harmonics of every mesh
frequency, as multiples ("orders") of the input rotation frequency: the line of order
``q`` is ``f = q * speed / 2 pi`` (Hz, speed in rad/s). Crossings are located by root
finding on the exact frequency-speed relation, not on the sampled grid.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np
import xarray as xr
from numpy.typing import NDArray
from scipy.optimize import brentq

from ..design import Design
from ..errors import ReducerlabError, names_source
from ..model import Model
from ..model.laws import flat_period
from ..results import provenance
from ..units import TWO_PI

__all__ = [
    "campbell_axes",
    "campbell_dataset",
    "excitation_orders",
    "find_crossings",
    "operating_range",
]

#: A crossing: (mode number, excitation name, speed in rad/s, frequency in Hz).
Crossing = tuple[int, str, float, float]


def operating_range(target: Design | Model) -> tuple[float, float]:
    """The operating speed range ``(min, max)`` of the input member (rad/s).

    A design's :meth:`~reducerlab.design.Design.operating_range` (its ``speed_range``,
    else its operating speed twice); a model's speed twice.
    """
    if isinstance(target, Design):
        lo, hi = target.operating_range()
        return float(lo), float(hi)
    if isinstance(target, Model):
        return float(target.speed), float(target.speed)
    raise ReducerlabError(
        f"operating range: target must be a Design or a Model, got {type(target).__name__}"
    )


@names_source
def excitation_orders(target: Design | Model, harmonics: int = 3) -> dict[str, float]:
    """Excitation frequencies as multiples ("orders") of the input rotation frequency.

    ``{"1x input": 1, "1x mesh": z, "2x mesh": 2z, ...}``. From the design's kinematics
    (:meth:`~reducerlab.design.Design.kinematics`) when it has them, otherwise from the
    periodic mesh-stiffness laws of the model (at the model's speed; none at rest).

    Parameters
    ----------
    target : Design or Model
    harmonics : int
        Mesh harmonics listed (1x .. ``harmonics`` x).

    Returns
    -------
    dict
        Excitation name -> order (multiple of the input rotation frequency).
    """
    orders = {"1x input": 1.0}
    meshes: dict[str, float] = {}
    kin = target.kinematics() if isinstance(target, Design) else None
    if kin is not None:
        f_unit = kin.mesh_frequencies(1.0)  # Hz at 1 rad/s input
        meshes = {name: f * TWO_PI for name, f in f_unit.items()}
    else:
        from ..drives import design_and_model

        _, model = design_and_model(target, "excitation orders")
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


def campbell_axes(
    target: Design | Model,
    model: Model,
    speeds: Sequence[float] | NDArray | None,
    orders: dict[str, float] | None,
    points: int,
    what: str,
) -> tuple[NDArray, float, float, dict[str, float]]:
    """The axes of a Campbell diagram, checked.

    Parameters
    ----------
    target : Design or Model
        Gives the operating range and the default orders.
    model : Model
        The target's model (its speed sets the default axis of a model at rest).
    speeds : array_like or None
        Input speeds (rad/s), >= 0, strictly increasing, at least two; None: ``points``
        speeds from 0 to 1.5x the top of the operating range.
    orders : dict or None
        Excitation name -> order (> 0); None: :func:`excitation_orders`.
    points : int
        Number of default speeds.
    what : str
        The analysis, named in the errors.

    Returns
    -------
    tuple
        ``(speeds, lo, hi, orders)``: the speeds (rad/s), the operating range (rad/s)
        and the orders.
    """
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
    at: Callable[[float], NDArray],
) -> list[Crossing]:
    """Crossings of frequency branches with the excitation lines ``order * speed / 2 pi``.

    A sign change of ``branch - line`` between two samples is refined by root finding
    (Brent) on ``at(speed)``, the frequencies of every branch at one speed, so a coarse
    grid still gives the exact crossing speed.

    Parameters
    ----------
    freq : ndarray
        Frequencies (Hz), shape (speed, mode); a branch never above 0 Hz (rigid or
        divergent throughout) has no crossing.
    speeds : ndarray
        The sampled input speeds (rad/s).
    orders : dict
        Excitation name -> order.
    at : callable
        ``at(speed)`` -> the frequencies (Hz) of every branch at ``speed`` (rad/s).

    Returns
    -------
    list of tuple
        ``(mode, excitation, speed (rad/s), frequency (Hz))``, sorted by speed; modes
        numbered from 1.
    """
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
    rows: Sequence[Crossing],
    modes: dict[str, tuple],
) -> xr.Dataset:
    """A Campbell diagram's dataset.

    Parameters
    ----------
    target : Design or Model
        Gives the title (its name, else the model's).
    model : Model
        Gives the provenance.
    speeds : ndarray
        Input speeds (rad/s).
    operating : tuple of float
        The operating range (rad/s), kept as attributes.
    orders : dict
        Excitation name -> order.
    rows : sequence of tuple
        Crossings, as :func:`find_crossings` gives them.
    modes : dict
        The per-mode variables over ``("speed", "mode")`` (xarray ``(dims, values,
        attrs)`` tuples), the first giving the number of modes.

    Returns
    -------
    xarray.Dataset
        ``modes``, ``excitation_frequency`` (speed, excitation; Hz), ``order`` and the
        crossings (``crossing_mode``, ``crossing_excitation``, ``crossing_speed`` in
        rad/s, ``crossing_frequency`` in Hz).
    """
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
            "title": target.name or model.name,
            "operating_min_rad_s": operating[0],
            "operating_max_rad_s": operating[1],
            **provenance(model.metadata),
        },
    )
