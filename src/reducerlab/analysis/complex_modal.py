"""Complex modes of models with damping and gyroscopic terms (issue 17).

The quadratic eigenproblem ``(lambda^2 M + lambda C + K) phi = 0`` of a model whose
velocity matrix ``C`` holds damping (symmetric) and gyroscopic or Coriolis terms (skew:
:class:`~reducerlab.model.Gyroscopic`, :class:`~reducerlab.model.Coriolis`, at the model
speed) is solved by its first-order (state-space) form

    ``A = [[0, I], [-M^-1 K, -M^-1 C]]``,  ``A [phi; lambda phi] = lambda [phi; lambda phi]``

(Friswell et al., *Dynamics of Rotating Machines*, 2010, Sec. 2.5). Each oscillatory mode
is one eigenvalue ``lambda = -zeta omega_n + i omega_d`` of a conjugate pair: damped
frequency ``omega_d / 2 pi`` (Hz), natural frequency ``|lambda| / 2 pi``, damping ratio
``zeta = -Re(lambda) / |lambda|``, logarithmic decrement ``2 pi zeta / sqrt(1 - zeta^2)``.
A mode with ``Re(lambda) > 0`` grows: it is reported as *unstable*, never as a normal
frequency. Rigid-body motions (the model's rigid modes, as :func:`.modal.modal` finds
them) are reported at 0 Hz. Whirl: for the body pair ``(x, y)`` or ``(rx, ry)`` that
carries most of a mode's kinetic energy (``M_ii |phi_i|^2``, so translations and
rotations compare in one unit), its orbit turns with the body's spin (*forward*), against it
(*backward*), or not at all (*planar*, an orbit narrower than 5 % of its length).
Without damping and gyroscopic terms the damped frequencies are the undamped ones of
:func:`.modal.modal`.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..errors import ModelError, ReducerlabError, names_source
from ..model import Coriolis, Gyroscopic, Model, Nutating
from ..model.rigid import RIGID_TOL, rigid_and_elastic
from ..numformat import Column, Table, fmt
from ..results import Result, provenance
from ..units import RPM, TWO_PI
from .campbell import reference_index, tracked_rows
from .excitation import campbell_axes, campbell_dataset, find_crossings
from .modal import has_skew_terms
from .tracking import renumber, track_complex

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from .components import ComponentModes

__all__ = [
    "ComplexCampbellResult",
    "ComplexModalResult",
    "complex_campbell",
    "complex_modes",
    "log_decrement",
    "spin_signs",
    "steady_whirl",
]

#: An orbit whose minor axis is below this share of its major axis is planar (no whirl).
PLANAR = 0.05

#: A mode grows (unstable) when Re(lambda) exceeds this share of |lambda|: round-off of
#: an undamped mode stays far below it.
UNSTABLE_TOL = 1e-9


def spin_signs(model: Model) -> dict[tuple[str, str], float]:
    """Spin sense per ``(body, pair)`` (pair ``"xy"`` or ``"rxry"``): of the frame a
    Coriolis element turns with, of the spin of a Gyroscopic or Nutating body."""
    out: dict[tuple[str, str], float] = {}
    for e in model.elements:
        if isinstance(e, Gyroscopic):
            ratio, body, pair = e.spin_ratio, e.pair[0].split(".")[0], "rxry"
        elif isinstance(e, Nutating):
            ratio, body, pair = e.axial_spin_ratio(), e.triple[0].split(".")[0], "rxry"
        elif isinstance(e, Coriolis):
            ratio, body, pair = e.ratio, e.pair[0].split(".")[0], "xy"
        else:
            continue
        out[(body, pair)] = float(np.sign(ratio * model.speed))
    return out


def _whirl(
    model: Model, phi: NDArray[np.complex128], spins: dict[tuple[str, str], float], mass: NDArray
) -> str:
    """Whirl of one complex mode shape (see the module docstring); ``mass`` is the
    diagonal of M."""
    best, label = 0.0, "none"
    default = float(np.sign(model.speed))
    for body in {d.body for d in model.dofs}:
        for a, b in (("x", "y"), ("rx", "ry")):
            ia, ib = model.index.get(f"{body}.{a}"), model.index.get(f"{body}.{b}")
            if ia is None or ib is None:
                continue
            u, v = phi[ia], phi[ib]
            weight = mass[ia] * abs(u) ** 2 + mass[ib] * abs(v) ** 2
            if weight <= best:
                continue
            best = weight
            # orbit (Re u e^{iwt}, Re v e^{iwt}): counterclockwise about +z when
            # Im(conj(u) v) < 0; its minor / major axis ratio from the singular values
            sense = -np.imag(np.conj(u) * v)
            m = np.array([[u.real, -u.imag], [v.real, -v.imag]])
            sv = np.linalg.svd(m, compute_uv=False)
            spin = spins.get((body, a + b), default)
            if sv[0] == 0 or sv[1] / sv[0] < PLANAR:
                label = "planar"
            elif spin == 0:
                label = "ccw" if sense > 0 else "cw"
            else:
                label = "forward" if sense * spin > 0 else "backward"
    return label


@names_source
def complex_modes(model: Model, *, rigid_tol: float = RIGID_TOL) -> ComplexModalResult:
    """Complex modes of ``model`` at its speed: damping and gyroscopic terms included.

    Parameters
    ----------
    model : Model
        Any model; its velocity matrix ``C`` (damping, mesh damping, gyroscopic and
        Coriolis blocks at the model speed) and stiffness ``K`` (speed terms included)
        enter the quadratic eigenproblem.
    rigid_tol : float
        As in :func:`.modal.modal`: decides the rigid-body modes (reported at 0 Hz).

    Returns
    -------
    ComplexModalResult
        Per mode: ``frequency`` (damped, Hz), ``natural_frequency`` (|lambda| / 2 pi, Hz),
        ``damping_ratio``, ``log_decrement``, ``growth_rate`` (Re lambda, 1/s), ``whirl``,
        ``stable``; complex shapes (largest component 1) as ``shape_real`` and
        ``shape_imag`` (dof, mode).
    """
    if not (isinstance(rigid_tol, int | float) and 0 <= rigid_tol < 1):
        raise ReducerlabError(f"rigid_tol must be a number in [0, 1), got {rigid_tol!r}")
    mats = model.matrices()
    M, C, K = mats.M, mats.C, mats.K
    n = model.n
    _, phi_real, rigid, _ = rigid_and_elastic(model, M, K, rigid_tol)
    n_rigid = int(np.count_nonzero(rigid))
    try:
        Minv = np.linalg.inv(M)
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
        lam, vec = np.linalg.eig(A)
    except np.linalg.LinAlgError as exc:
        raise ModelError(
            f"complex modes of {model.name!r}: the eigen-solver failed ({exc})"
        ) from None
    if not np.all(np.isfinite(lam)):
        raise ModelError(f"complex modes of {model.name!r}: non-finite eigenvalues")
    order = np.argsort(np.abs(lam))
    lam, vec = lam[order], vec[:, order]
    # the rigid motions: the 2 n_rigid eigenvalues nearest zero (a double root each)
    lam_e, vec_e = lam[2 * n_rigid :], vec[:, 2 * n_rigid :]
    scale = float(np.max(np.abs(lam_e))) if lam_e.size else 1.0
    keep = (lam_e.imag > 1e-12 * scale) | (np.abs(lam_e.imag) <= 1e-12 * scale)
    lam_e, vec_e = lam_e[keep], vec_e[:, keep]
    spins = spin_signs(model)
    mass = np.diag(M)
    rows = []
    for k in range(lam_e.size):
        lk = lam_e[k]
        phi = vec_e[:n, k]
        i = int(np.argmax(np.abs(phi)))
        phi = phi / phi[i]
        mag = abs(lk)
        # round-off of an undamped mode (|Re| below the stability tolerance) is no damping
        undamped = mag == 0 or abs(lk.real) <= UNSTABLE_TOL * mag
        zeta = 0.0 if undamped else -lk.real / mag
        rows.append((lk, phi, zeta, _whirl(model, phi, spins, mass)))
    rows.sort(key=lambda r: (abs(r[0].imag), abs(r[0])))
    m_total = n_rigid + len(rows)
    freq = np.zeros(m_total)
    natural = np.zeros(m_total)
    zeta = np.zeros(m_total)
    growth = np.zeros(m_total)
    whirl = ["rigid"] * n_rigid + [r[3] for r in rows]
    shapes = np.zeros((n, m_total), complex)
    if n_rigid:  # rigid shapes: the null space of the stiffness, largest component 1
        R = phi_real[:, rigid]
        shapes[:, :n_rigid] = R / R[np.argmax(np.abs(R), axis=0), np.arange(n_rigid)]
    for j, (lk, phi, z, _) in enumerate(rows, start=n_rigid):
        freq[j] = abs(lk.imag) / TWO_PI
        natural[j] = abs(lk) / TWO_PI
        zeta[j] = z
        growth[j] = lk.real
        shapes[:, j] = phi
    logdec = log_decrement(zeta)
    stable = growth <= UNSTABLE_TOL * np.maximum(natural * TWO_PI, 1e-300)
    data = xr.Dataset(
        {
            "frequency": ("mode", freq, {"units": "Hz", "long_name": "damped natural frequency"}),
            "natural_frequency": ("mode", natural, {"units": "Hz", "long_name": "|lambda| / 2 pi"}),
            "damping_ratio": ("mode", zeta, {"units": "1"}),
            "log_decrement": ("mode", logdec, {"units": "1"}),
            "growth_rate": ("mode", growth, {"units": "1/s", "long_name": "Re(lambda)"}),
            "whirl": ("mode", np.array(whirl, dtype=object).astype(str)),
            "stable": ("mode", stable),
            "shape_real": (("dof", "mode"), shapes.real),
            "shape_imag": (("dof", "mode"), shapes.imag),
        },
        coords={"mode": np.arange(1, m_total + 1), "dof": model.dof_names},
        attrs={
            "title": model.name or "complex modes",
            "speed_rad_s": model.speed,
            "rigid_modes": n_rigid,
            # gyroscopic, Coriolis or circulatory (skew) terms present (0 or 1)
            "gyroscopic": int(has_skew_terms(model)),
            **provenance(model.metadata),
        },
    )
    return ComplexModalResult(data)


class ComplexModalResult(Result):
    """Complex modes: damped frequencies, damping ratios, whirl and stability."""

    kind: ClassVar[str] = "complex-modal"

    @property
    def frequencies(self) -> NDArray[np.float64]:
        """Damped natural frequencies (Hz), rigid modes 0."""
        return self.data["frequency"].values

    def to_dict(self) -> dict[str, Any]:
        ds = self.data
        return {
            "speed_rad_s": ds.attrs["speed_rad_s"],
            "frequencies_hz": ds["frequency"].values.tolist(),
            "damping_ratios": ds["damping_ratio"].values.tolist(),
            "whirl": ds["whirl"].values.tolist(),
            "stable": ds["stable"].values.tolist(),
        }

    def table_data(self) -> Table:
        """The modes as a :class:`~reducerlab.numformat.Table` (mode, damped frequency in
        Hz, damping ratio, whirl, stability)."""
        ds = self.data
        rpm = ds.attrs["speed_rad_s"] * RPM
        title = f"complex modes: {ds.attrs.get('title', '')} at {fmt(rpm, 'speed')} rpm"
        t = Table([Column("mode", kind="count"), Column("frequency", "Hz", "frequency"),
                   Column("damping ratio", kind="value"), Column("whirl", kind="text"),
                   Column("stability", kind="text")], title=title)  # fmt: skip
        for m, f, z, w, s in zip(ds["mode"].values, ds["frequency"].values,
                                 ds["damping_ratio"].values, ds["whirl"].values,
                                 ds["stable"].values, strict=True):  # fmt: skip
            t.add(int(m), float(f), float(z), str(w), "stable" if s else "UNSTABLE (grows)")
        return t

    def table(self) -> str:
        """The modes as plain text."""
        return self.table_data().text()

    def plot(self) -> Figure:
        """Damped frequencies (marker by whirl) and damping ratios of every mode."""
        from ..plot.modal import plot_complex_modes

        return plot_complex_modes(self)


def modes_over(model: Model, speeds: NDArray, rigid_tol: float = RIGID_TOL) -> list[xr.Dataset]:
    """The complex modes' dataset (:func:`complex_modes`) at each speed (rad/s)."""
    return [complex_modes(model.with_speed(float(w)), rigid_tol=rigid_tol).data for w in speeds]


def stack_branches(rows: list[xr.Dataset]) -> tuple[NDArray, ...]:
    """Damped frequencies, damping ratios, whirl and stability (speed, mode) of
    :func:`modes_over` rows, the modes sorted by frequency at each speed."""
    width = max(r.sizes["mode"] for r in rows)

    def stack(name: str, fill: Any, dtype: Any) -> NDArray:
        out = np.full((len(rows), width), fill, dtype=dtype)
        for i, r in enumerate(rows):
            out[i, : r.sizes["mode"]] = r[name].values
        return out

    return (stack("frequency", np.nan, float), stack("damping_ratio", np.nan, float),
            stack("whirl", "", object), stack("stable", True, bool))  # fmt: skip


def _branches(model: Model, speeds: NDArray, rigid_tol: float) -> tuple[NDArray, ...]:
    return stack_branches(modes_over(model, speeds, rigid_tol))


def _shapes(rows: list[xr.Dataset], width: int) -> NDArray[np.complex128]:
    """Complex shapes (speed, dof, mode) of :func:`modes_over` rows, zero where a
    speed has fewer modes."""
    n = rows[0].sizes["dof"]
    out = np.zeros((len(rows), n, width), complex)
    for i, r in enumerate(rows):
        out[i, :, : r.sizes["mode"]] = r["shape_real"].values + 1j * r["shape_imag"].values
    return out


def log_decrement(zeta: NDArray) -> NDArray:
    """Logarithmic decrement ``2 pi zeta / sqrt(1 - zeta^2)`` of damping ratios (inf
    from critical damping on, NaN kept)."""
    z = np.asarray(zeta, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.abs(z) < 1, TWO_PI * z / np.sqrt(1 - z**2), np.copysign(np.inf, z))


#: Whirl labels that only say the orbit's sense about +z (no spin to compare with: a
#: model at rest).
UNREFERENCED = ("cw", "ccw")


def steady_whirl(labels: Sequence[str], min_run: int | None = None) -> NDArray:
    """The whirl along one tracked branch, without flicker.

    At rest there is no spin to compare an orbit with (``cw``/``ccw``): those samples
    take the whirl the branch has once it spins. A run of one label shorter than
    ``min_run`` samples (default ``max(3, n / 50)``) between others is a decision at its
    threshold (an orbit near the planar limit, a repeated eigenvalue whose basis the
    solver picks), not a change of whirl: it takes its neighbours' label. Where the
    label still changes more than twice, the branch has no whirl of its own (a repeated
    eigenvalue throughout): it takes its most frequent label.

    Parameters
    ----------
    labels : sequence of str
        Whirl of the branch at each speed, as :func:`complex_modes` gives it ("" where
        the branch is missing).
    min_run : int, optional

    Returns
    -------
    ndarray of str
    """
    lab = np.array([str(v) for v in labels], dtype=object)
    n = lab.size
    if n == 0:
        return lab.astype(str)
    known = np.nonzero(~np.isin(lab, UNREFERENCED) & (lab != ""))[0]
    if known.size:
        for i in np.nonzero(np.isin(lab, UNREFERENCED))[0]:
            lab[i] = lab[known[np.argmin(np.abs(known - i))]]
    min_run = max(3, n // 50) if min_run is None else int(min_run)
    while True:
        starts = np.concatenate([[0], np.nonzero(lab[1:] != lab[:-1])[0] + 1, [n]])
        runs = list(pairwise(starts.tolist()))
        short = [k for k, (a, b) in enumerate(runs) if b - a < min_run and len(runs) > 1]
        if not short:
            break
        k = min(short, key=lambda q: runs[q][1] - runs[q][0])
        a, b = runs[k]
        lab[a:b] = lab[runs[k - 1][0]] if k > 0 else lab[runs[k + 1][0]]
    if np.count_nonzero(lab[1:] != lab[:-1]) > 2:
        values, counts = np.unique(lab[lab != ""], return_counts=True)
        if values.size:
            lab[lab != ""] = values[np.argmax(counts)]
    return lab.astype(str)


@names_source
def complex_campbell(
    target: Any,
    speeds: Any = None,
    *,
    orders: dict[str, float] | None = None,
    points: int = 121,
    rigid_tol: float = RIGID_TOL,
) -> ComplexCampbellResult:
    """Campbell diagram of the complex modes: damped frequencies against input speed,
    split into forward and backward whirl by gyroscopic and Coriolis terms, with
    excitation lines, their crossings and the speeds where a mode grows (unstable).

    Parameters
    ----------
    target : Design or Model
    speeds : array_like, optional
        Input speeds (rad/s), ascending, >= 0; default 0 to 1.5x the top of the operating
        range (``points`` values).
    orders : dict, optional
        Excitation name -> order (multiple of the input rotation frequency); default
        :func:`~reducerlab.analysis.excitation.excitation_orders`.

    Returns
    -------
    ComplexCampbellResult
        ``frequency``, ``damping_ratio``, ``log_decrement``, ``whirl``, ``stable`` over
        (speed, mode), each mode tracked across speed by its shape (complex MAC,
        :func:`~.tracking.track_complex`) so that a line follows one mode, and numbered
        by its frequency order at the operating speed (``sorted_mode``: its number in
        frequency order at each speed); ``whirl`` decided along each tracked branch
        (:func:`steady_whirl`: no flicker, the sense at rest from the spinning branch);
        excitation lines; crossings found between samples on the frequency-ordered
        modes, refined by root finding and named by their tracked mode
        (``crossing_mode``; ``crossing_sorted_mode``, ``crossing_whirl``).
    """
    from ..drives import design_and_model

    _, model = design_and_model(target, "complex campbell")
    speeds, lo, hi, orders = campbell_axes(target, model, speeds, orders, points,
                                           "complex campbell")  # fmt: skip
    at = modes_over(model, speeds, rigid_tol)
    freq, zeta, whirl, stable = stack_branches(at)
    shapes = _shapes(at, freq.shape[1])
    order = renumber(track_complex(freq, shapes, model.matrices().M),
                     reference_index(target, model, speeds))  # fmt: skip

    def take(a: NDArray) -> NDArray:
        return np.take_along_axis(a, order, axis=1)

    tracked, zeta = take(freq), take(zeta)
    whirl = np.stack([steady_whirl(c) for c in take(whirl).T], axis=1).astype(str)
    found = find_crossings(
        freq, speeds, orders, lambda w: _branches(model, np.array([w]), rigid_tol)[0][0]
    )
    rows = tracked_rows(found, speeds, tracked, order)
    near = [int(np.argmin(np.abs(speeds - r[2]))) for r in rows]  # whirl of the nearest
    modes = {
        "frequency": (("speed", "mode"), tracked, {"units": "Hz"}),
        "damping_ratio": (("speed", "mode"), zeta, {"units": "1"}),
        "log_decrement": (("speed", "mode"), log_decrement(zeta), {"units": "1"}),
        "whirl": (("speed", "mode"), whirl),
        "stable": (("speed", "mode"), take(stable)),
        "sorted_mode": (("speed", "mode"), order + 1, {"long_name": "sorted mode number"}),
    }
    data = campbell_dataset(target, model, speeds, (lo, hi), orders,
                            [r[:4] for r in rows], modes)  # fmt: skip
    data["crossing_whirl"] = (
        "crossing", np.array([whirl[k, r[0] - 1] for k, r in zip(near, rows, strict=True)],
                             dtype=str),
    )  # fmt: skip
    data["crossing_sorted_mode"] = ("crossing", np.array([r[4] for r in rows], dtype=int))
    return ComplexCampbellResult(data)


class ComplexCampbellResult(Result):
    """Complex-mode Campbell diagram: (speed, mode) frequencies, whirl and stability."""

    kind: ClassVar[str] = "complex-campbell"

    def crossings(self) -> list[dict[str, Any]]:
        """Crossings: ``mode`` the tracked mode (the line of the diagram),
        ``sorted_mode`` its number in frequency order at the crossing speed, its whirl."""
        ds = self.data
        sorted_ = (ds["crossing_sorted_mode"].values if "crossing_sorted_mode" in ds
                   else ds["crossing_mode"].values)  # fmt: skip
        return [
            {"mode": int(m), "sorted_mode": int(s), "excitation": str(e),
             "speed_rad_s": float(w), "speed_rpm": float(w) * RPM, "frequency_hz": float(f),
             "whirl": str(h)}
            for m, s, e, w, f, h in zip(ds["crossing_mode"].values, sorted_,
                                        ds["crossing_excitation"].values,
                                        ds["crossing_speed"].values,
                                        ds["crossing_frequency"].values,
                                        ds["crossing_whirl"].values, strict=True)
        ]  # fmt: skip

    def unstable_speeds(self) -> list[float]:
        """Input speeds (rpm) at which some mode grows."""
        ds = self.data
        bad = ~np.all(ds["stable"].values, axis=1)
        return (ds["speed"].values[bad] * RPM).tolist()

    def to_dict(self) -> dict[str, Any]:
        return {"crossings": self.crossings(), "unstable_speeds_rpm": self.unstable_speeds()}

    def table_data(self) -> Table:
        """The crossings as a :class:`~reducerlab.numformat.Table` (mode, whirl,
        excitation, speed in rpm, damped frequency in Hz)."""
        t = Table([Column("mode", kind="count"), Column("whirl", kind="text"),
                   Column("excitation", kind="text"), Column("speed", "rpm", "speed"),
                   Column("frequency", "Hz", "frequency")])  # fmt: skip
        for c in self.crossings():
            t.add(c["mode"], c["whirl"], c["excitation"], c["speed_rpm"], c["frequency_hz"])
        return t

    def table(self) -> str:
        """Crossings, then the stability over the speeds, as text."""
        t = self.table_data()
        lines = [
            f"complex Campbell diagram: {self.data.attrs.get('title', '')}",
            f"{len(t.rows)} crossing(s) of damped natural frequencies with excitations:",
            t.text(indent="  "),
        ]
        bad = self.unstable_speeds()
        if bad:
            lines.append(f"UNSTABLE (a mode grows) from {fmt(min(bad), 'speed')} to "
                         f"{fmt(max(bad), 'speed')} rpm")  # fmt: skip
        else:
            lines.append("every mode is stable over the speeds computed")
        return "\n".join(lines)

    def plot(
        self, components: Sequence[ComponentModes] = (), *, fmax: float | None = None
    ) -> Figure:
        """Damped frequencies against speed: each tracked mode coloured by its log
        decrement, its whirl marked (up-triangles forward, down-triangles backward),
        unstable points as red crosses; excitation lines; crossings; ``components``:
        body modes drawn as horizontal lines (see
        :func:`~reducerlab.plot.campbell.plot_complex_campbell`)."""
        from ..plot.campbell import plot_complex_campbell

        return plot_complex_campbell(self, components, fmax=fmax)
