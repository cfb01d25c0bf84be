"""Campbell diagram of the undamped natural frequencies.

Natural frequencies are computed at each input speed with the speed-dependent terms
(centripetal, ...) rebuilt (``Model.with_speed``). The excitation lines, their orders
(from the drive's kinematics, or for designs without kinematics from the mesh stiffness
laws of the model) and the crossings, located by root finding on the exact
frequency-speed relation, come from :mod:`.excitation`; the damped, whirl-split diagram
is :func:`.complex_modal.complex_campbell`, the resonance verdict
:func:`.resonance.resonance_check`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from ..design import Design
from ..errors import ModelError, ReducerlabError, names_source
from ..model import Model
from ..model.rigid import RIGID_TOL, element_blocks, rest_stiffness
from ..numformat import Column, Table
from ..results import Result
from ..units import RPM, TWO_PI
from .excitation import campbell_axes, campbell_dataset, find_crossings
from .tracking import branch_of, renumber, track_modes

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .components import ComponentModes

__all__ = [
    "CampbellResult",
    "campbell",
    "frequencies_over",
    "reference_index",
    "tracked_rows",
    "undamped_modes_over",
]

#: Public names that lived here before the resonance verdict got its own module
#: (issue 25) and stay importable from here, as the README's
#: ``from reducerlab.analysis.campbell import campbell, resonance_check`` does.
MOVED = {"resonance_check": "resonance", "format_check": "resonance"}


def __getattr__(name: str) -> Any:
    """A name in :data:`MOVED`, from its module (PEP 562: looked up on first use, so
    this module does not import the verdict that imports it)."""
    if name in MOVED:
        from . import resonance

        return getattr(resonance, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def frequencies_over(model: Model, speeds: NDArray, rigid_tol: float = RIGID_TOL) -> NDArray:
    """Undamped natural frequencies of ``model`` at each input speed.

    Each speed is solved as :func:`~reducerlab.analysis.modal.modal` would: rigid-body
    modes (no element strained at rest, see
    :func:`~reducerlab.model.rigid.strain_ratio`) at exactly 0 Hz, the elastic modes
    on their complement where speed terms act.

    Parameters
    ----------
    model : Model
    speeds : ndarray
        Input speeds (rad/s).
    rigid_tol : float
        As in :func:`~reducerlab.analysis.modal.modal`.

    Returns
    -------
    ndarray
        Frequencies (Hz), shape (speed, mode); a divergent mode is negative.
    """
    return undamped_modes_over(model, speeds, rigid_tol)[0]


def undamped_modes_over(
    model: Model, speeds: NDArray, rigid_tol: float = RIGID_TOL
) -> tuple[NDArray, NDArray]:
    """:func:`frequencies_over` with the mode shapes: frequencies (Hz), shape (speed,
    mode), and mass-normalised shapes, shape (speed, dof, mode), in the same order."""
    lam, phi, _ = _eigen_over(model, speeds, rigid_tol)
    return np.sign(lam) * np.sqrt(np.abs(lam)) / TWO_PI, phi


def _eigen_over(model: Model, speeds: NDArray, rigid_tol: float) -> tuple[NDArray, ...]:
    """Sorted eigenvalues (rad^2/s^2), mass-normalised and mass-weighted shapes at
    each speed."""
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
        lam, phi, y = modes.solve(rigid_tol)
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
    return lam, phi, y


def reference_index(target: Design | Model, model: Model, speeds: NDArray) -> int:
    """The sample nearest the operating speed (a design's ``operating_speed``, a
    model's speed): tracked modes are numbered by their order there, as the modal
    analysis at the operating point numbers them."""
    op = target.operating_speed if isinstance(target, Design) else model.speed
    return int(np.argmin(np.abs(speeds - float(op))))


def tracked_rows(
    rows: Sequence[tuple[int, str, float, float]],
    speeds: NDArray,
    tracked: NDArray,
    order: NDArray,
) -> list[tuple[int, str, float, float, int]]:
    """Crossings found on sorted branches (:func:`~.excitation.find_crossings`) named by
    their tracked mode: ``(tracked mode, excitation, speed, frequency, sorted mode)``,
    modes numbered from 1."""
    return [
        (branch_of(j, w, f, speeds, tracked, order) + 1, name, w, f, j) for j, name, w, f in rows
    ]


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
        :func:`~reducerlab.analysis.excitation.excitation_orders`.
    points : int
        Number of default speeds.

    Returns
    -------
    CampbellResult
        ``frequency`` (speed, mode; Hz) along each mode tracked by shape (MAC,
        :func:`~.tracking.track_modes`, refined where neighbouring speeds disagree), so
        that a line follows one mode through crossings and veerings; modes are numbered
        by their order at the operating speed (``sorted_mode``: the sorted number of
        each tracked mode at each speed). The excitation lines and their crossings
        (``crossing_mode`` the tracked mode, ``crossing_sorted_mode`` its sorted number
        at the crossing speed).
    """
    from ..drives import design_and_model

    _, model = design_and_model(target, "campbell")
    speeds, lo, hi, orders = campbell_axes(target, model, speeds, orders, points, "campbell")
    lam, _, y = _eigen_over(model, speeds, RIGID_TOL)

    def evaluate(w: float) -> tuple[NDArray, NDArray]:
        lw, _, yw = _eigen_over(model, np.array([w]), RIGID_TOL)
        return lw[0], yw[0]

    order = renumber(track_modes(speeds, lam, y, evaluate).order,
                     reference_index(target, model, speeds))  # fmt: skip
    freq = np.sign(lam) * np.sqrt(np.abs(lam)) / TWO_PI
    tracked = np.take_along_axis(freq, order, axis=1)
    found = find_crossings(freq, speeds, orders,
                           lambda w: frequencies_over(model, np.array([w]))[0])  # fmt: skip
    rows = tracked_rows(found, speeds, tracked, order)
    modes = {
        "frequency": (("speed", "mode"), tracked, {"units": "Hz"}),
        "sorted_mode": (("speed", "mode"), order + 1, {"long_name": "sorted mode number"}),
    }
    data = campbell_dataset(target, model, speeds, (lo, hi), orders, [r[:4] for r in rows],
                            modes)  # fmt: skip
    data["crossing_sorted_mode"] = ("crossing", np.array([r[4] for r in rows], dtype=int))
    return CampbellResult(data)


class CampbellResult(Result):
    """Frequencies (speed x mode), excitation lines (speed x excitation), crossings."""

    kind: ClassVar[str] = "campbell"

    def crossings(self) -> list[dict[str, Any]]:
        """Crossings of natural frequencies with excitation lines: ``mode`` the tracked
        mode (the line of the diagram), ``sorted_mode`` its number in frequency order
        at the crossing speed."""
        ds = self.data
        sorted_ = (ds["crossing_sorted_mode"].values if "crossing_sorted_mode" in ds
                   else ds["crossing_mode"].values)  # fmt: skip
        return [
            {
                "mode": int(m),
                "sorted_mode": int(s),
                "excitation": str(e),
                "speed_rad_s": float(w),
                "speed_rpm": float(w) * RPM,
                "frequency_hz": float(f),
            }
            for m, s, e, w, f in zip(
                ds["crossing_mode"].values,
                sorted_,
                ds["crossing_excitation"].values,
                ds["crossing_speed"].values,
                ds["crossing_frequency"].values,
                strict=True,
            )
        ]

    def table_data(self) -> Table:
        """The crossings as a :class:`~reducerlab.numformat.Table` (mode, excitation,
        speed in rpm, frequency in Hz)."""
        t = Table([Column("mode", kind="count"), Column("excitation", kind="text"),
                   Column("speed", "rpm", "speed"),
                   Column("frequency", "Hz", "frequency")])  # fmt: skip
        for c in self.crossings():
            t.add(c["mode"], c["excitation"], c["speed_rpm"], c["frequency_hz"])
        return t

    def table(self) -> str:
        """Crossings as text."""
        t = self.table_data()
        return "\n".join([f"Campbell diagram: {self.data.attrs.get('title', '')}",
                          f"{len(t.rows)} crossing(s) of natural frequencies with excitations:",
                          t.text(indent="  ")])  # fmt: skip

    def plot(self, components: Sequence[ComponentModes] = ()) -> Figure:
        """Campbell diagram; ``components``: body modes drawn as horizontal lines."""
        from ..plot.campbell import plot_campbell

        return plot_campbell(self, components=components)
