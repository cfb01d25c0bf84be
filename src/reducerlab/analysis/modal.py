"""Modal analysis of any :class:`~reducerlab.model.Model`.

Undamped generalised symmetric eigenproblem ``K phi = lambda M phi`` with the mean
stiffness (paper 000 Eq. 9, paper 003 Eq. 12), ``lambda = (2 pi f)^2``.

Conventions (``docs/conventions.md``):

* rigid-body modes (motions that strain no element: ``model.rigid.strain_ratio`` at most
  ``rigid_tol``) are reported as exactly 0 Hz;
* a negative eigenvalue, which speed-dependent (centripetal) terms can produce, is a
  static divergence; it is kept, and its frequency is reported with a minus sign,
  ``f = -sqrt(-lambda) / 2 pi``, and flagged ``unstable``;
* shapes are mass-normalised (``phi^T M phi = 1``, ``shape``) and max-normalised
  (largest component +1, ``shape_max``); the sign makes the largest component positive.
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from ..errors import ReducerlabError, names_source
from ..model import Model
from ..model.rigid import RIGID_TOL, check_resolved, rigid_and_elastic
from ..numformat import Column, Table
from ..results import Result, provenance
from ..units import TWO_PI

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..drives.places import DriveLayout

__all__ = [
    "SHOWN",
    "MapCells",
    "ModalResult",
    "SensitivityResult",
    "eigenvalue_derivatives",
    "frequency_sensitivity",
    "mac",
    "modal",
]

#: The smallest relative sensitivity ``|(p/f) df/dp|`` the maps write (two decimals): a
#: parameter below it on every elastic mode is left out of the maps and named.
SHOWN = 0.005

#: Relative gap below which two eigenvalues are treated as one repeated eigenvalue.
DEGENERACY_TOL = 1e-7


def _skew(A: NDArray) -> bool:
    """Whether ``A`` has a skew-symmetric part beyond round-off."""
    return bool(np.any(np.abs(0.5 * (A - A.T)) > 1e-12 * max(float(np.abs(A).max()), 1e-300)))


def has_skew_terms(model: Model) -> bool:
    """Whether ``model`` has, at its speed, skew velocity terms (gyroscopic, Coriolis) or
    skew stiffness (circulatory): what the undamped modes leave out and complex modes
    (:mod:`.complex_modal`) include."""
    mats = model.matrices()
    return _skew(mats.C) or _skew(mats.K)


def _pretty(body: str) -> str:
    return body.replace("_", " ")


def _energy_labels(
    model: Model, kinetic: NDArray, rigid: NDArray, unstable: NDArray
) -> tuple[list[str], list[str], list[str]]:
    """Classification string, dominant family and dominant body of each mode."""
    bodies = [d.body for d in model.dofs]
    families = [d.family for d in model.dofs]
    cells = sorted({(b, f) for b, f in zip(bodies, families, strict=True)})
    labels, fam_out, body_out = [], [], []
    for j in range(kinetic.shape[1]):
        share = {c: 0.0 for c in cells}
        for i in range(model.n):
            share[(bodies[i], families[i])] += kinetic[i, j]
        fam_share: dict[str, float] = {}
        for (_, f), s in share.items():
            fam_share[f] = fam_share.get(f, 0.0) + s
        fam = max(fam_share, key=lambda k: fam_share[k])
        (body, family), s = max(share.items(), key=lambda kv: kv[1])
        text = f"{family} — {_pretty(body)} {100 * s:.0f} %"
        if rigid[j]:
            text = f"rigid body ({fam})"
        elif unstable[j]:
            text = f"divergent — {text}"
        labels.append(text)
        fam_out.append(fam)
        body_out.append(body)
    return labels, fam_out, body_out


@names_source
def modal(model: Model, *, rigid_tol: float = RIGID_TOL) -> ModalResult:
    """Natural frequencies, mode shapes and energy classification of a model.

    Parameters
    ----------
    model : Model
        Any lumped-parameter model (mesh stiffness at its mean).
    rigid_tol : float
        A mode is a rigid-body mode (reported as exactly 0 Hz) when it strains no
        element: its largest element strain ratio (:func:`~reducerlab.model.rigid.strain_ratio`,
        ``|phi_e^T K_e phi_e| / (|phi_e|^T |K_e| |phi_e|)``, 0 for a rigid motion, of
        order one for an elastic one) is at most ``rigid_tol``. The test is
        structural: it does not compare eigenvalues with the largest one, so a very
        light or very stiff body does not turn elastic modes into rigid ones. With speed-dependent
        terms, rigid modes are the null space of the stiffness at zero speed (see
        ``model.rigid.rigid_and_elastic``); the attribute ``rigid_speed_eigenvalues`` records
        what the speed terms would make of them.

    Returns
    -------
    ModalResult
    """
    if not (isinstance(rigid_tol, int | float) and 0 <= rigid_tol < 1):
        raise ReducerlabError(f"rigid_tol must be a number in [0, 1), got {rigid_tol!r}")
    mats = model.matrices()
    # gyroscopic / Coriolis (skew) velocity terms and circulatory (skew) stiffness are
    # outside K phi = lambda M phi: they are flagged in the result
    # (complex_modal.complex_modes includes them)
    skew_terms = int(_skew(mats.C) or _skew(mats.K))  # has_skew_terms, matrices at hand
    lam, phi, rigid, drift = rigid_and_elastic(model, mats.M, mats.K, rigid_tol)
    check_resolved(lam, rigid, mats.M, mats.K, model.dof_names, f"modal of {model.name!r}")
    unstable = lam < 0
    freq = np.sign(lam) * np.sqrt(np.abs(lam)) / TWO_PI
    # sign: largest component positive
    imax = np.argmax(np.abs(phi), axis=0)
    cols = np.arange(phi.shape[1])
    phi = phi * np.sign(phi[imax, cols])
    shape_max = phi / phi[imax, cols]
    kinetic = phi * (mats.M @ phi)
    with np.errstate(divide="ignore", invalid="ignore"):
        strain = np.where(rigid, np.nan, phi * (mats.K @ phi) / np.where(rigid, 1.0, lam))
    # strain energy per element (mean mesh stiffness included)
    enames, eshare = [], []
    for e in model.elements:
        idx, em = model.element_matrices(e)
        if not np.any(em.K):
            continue
        pe = phi[idx]
        u = np.einsum("im,ij,jm->m", pe, em.K, pe)
        with np.errstate(divide="ignore", invalid="ignore"):
            eshare.append(np.where(rigid, np.nan, u / np.where(rigid, 1.0, lam)))
        enames.append(e.name)
    labels, fams, bodies = _energy_labels(model, kinetic, rigid, unstable)
    n = model.n
    dofs = model.dofs
    coords = {
        "mode": ("mode", np.arange(1, n + 1)),
        "dof": ("dof", model.dof_names),
        "body": ("dof", [d.body for d in dofs]),
        "kind": ("dof", [d.kind for d in dofs]),
        "family": ("dof", [d.family for d in dofs]),
        "unit": ("dof", [d.unit for d in dofs]),
        "element": ("element", enames),
    }
    data = xr.Dataset(
        {
            "frequency": ("mode", freq, {"units": "Hz", "long_name": "natural frequency"}),
            "eigenvalue": ("mode", lam, {"units": "rad^2/s^2", "long_name": "lambda = omega^2"}),
            "shape": (
                ("dof", "mode"),
                phi,
                {"long_name": "mass-normalised mode shape", "units": "dof unit / sqrt(kg)"},
            ),
            "shape_max": (("dof", "mode"), shape_max, {"long_name": "max-normalised shape"}),
            "kinetic_energy": (
                ("mode", "dof"),
                kinetic.T,
                {"units": "1", "long_name": "share of kinetic energy"},
            ),
            "strain_energy": (
                ("mode", "dof"),
                strain.T,
                {"units": "1", "long_name": "share of strain energy by DOF"},
            ),
            "element_energy": (
                ("mode", "element"),
                np.array(eshare).reshape(len(enames), n).T,
                {"units": "1", "long_name": "share of strain energy by element"},
            ),
            "classification": ("mode", np.array(labels, dtype=object)),
            "dominant_family": ("mode", np.array(fams, dtype=object)),
            "dominant_body": ("mode", np.array(bodies, dtype=object)),
            "rigid": ("mode", rigid.astype(np.int8), {"long_name": "rigid-body mode (1)"}),
            "unstable": ("mode", unstable.astype(np.int8), {"long_name": "divergent mode (1)"}),
        },
        coords=coords,
        attrs={
            "title": model.name or "modal analysis",
            "speed_rad_s": model.speed,
            "rigid_tol": rigid_tol,
            "rigid_speed_eigenvalues": json.dumps([float(x) for x in drift]),
            "skew_velocity_terms": skew_terms,
            **provenance(model.metadata),
        },
    )
    return ModalResult(data)


class ModalResult(Result):
    """Natural frequencies and modes of a model (xarray Dataset in ``.data``).

    Variables: ``frequency`` (mode, Hz), ``eigenvalue`` (mode, rad^2/s^2), ``shape``
    and ``shape_max`` (dof, mode), ``kinetic_energy`` and ``strain_energy`` shares
    (mode, dof), ``element_energy`` (mode, element), ``classification`` (mode),
    ``rigid`` and ``unstable`` flags.
    """

    kind: ClassVar[str] = "modal"

    @property
    def frequencies(self) -> NDArray[np.float64]:
        """Natural frequencies (Hz), ascending; 0 for rigid-body modes."""
        return self.data["frequency"].values

    @property
    def shapes(self) -> NDArray[np.float64]:
        """Mass-normalised mode shapes, shape (n_dof, n_mode)."""
        return self.data["shape"].values

    @property
    def dof_names(self) -> list[str]:
        """DOF names in row order of :attr:`shapes`."""
        return [str(x) for x in self.data["dof"].values]

    @property
    def classifications(self) -> list[str]:
        """One label per mode, e.g. ``"torsional — gear 71 %"``."""
        return [str(x) for x in self.data["classification"].values]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary: ``frequencies_hz`` and ``modes``."""
        ds = self.data
        modes = [
            {
                "mode": int(m),
                "frequency_hz": float(f),
                "classification": str(c),
                "rigid": bool(r),
                "unstable": bool(u),
            }
            for m, f, c, r, u in zip(
                ds["mode"].values,
                ds["frequency"].values,
                ds["classification"].values,
                ds["rigid"].values,
                ds["unstable"].values,
                strict=True,
            )
        ]
        return {
            "title": ds.attrs.get("title", ""),
            "design_hash": ds.attrs.get("design_hash"),
            "reducerlab_version": ds.attrs.get("reducerlab_version"),
            "frequencies_hz": [float(f) for f in ds["frequency"].values],
            "modes": modes,
        }

    def to_json(self) -> str:
        """:meth:`to_dict` as a JSON string."""
        return json.dumps(self.to_dict(), indent=2)

    def table_data(self) -> Table:
        """The modes as a :class:`~reducerlab.numformat.Table` (mode, frequency in Hz,
        classification): the text, the command line and the report show its cells."""
        t = Table([Column("mode", kind="count"), Column("frequency", "Hz", "frequency"),
                   Column("classification", kind="text")])  # fmt: skip
        for m, f, c in zip(self.data["mode"].values, self.frequencies, self.classifications,
                           strict=True):  # fmt: skip
            t.add(int(m), float(f), str(c))
        return t

    def table(self) -> str:
        """Plain-text table of frequencies and classifications."""
        return self.table_data().text()

    def __repr__(self) -> str:
        return f"ModalResult({self.data.attrs.get('title', '')!r}, {self.data.sizes['mode']} modes)"

    def plot_shapes(self, modes: Sequence[int] | None = None, *, scale: str = "mass") -> Figure:
        """Bar charts of the mode shapes, one panel per mode, translations (m) and
        rotations (rad) on separate axes; ``scale``: ``"mass"`` (the mass-normalised
        shape), ``"energy"`` or ``"max"`` (see :func:`reducerlab.plot.modal.plot_mode_shapes`)."""
        from ..plot.modal import plot_mode_shapes

        return plot_mode_shapes(self, modes, scale=scale)

    def plot_drive(
        self,
        layout: DriveLayout,
        modes: Sequence[int] | None = None,
        *,
        fraction: float = 0.15,
        panel: float = 3.4,
    ) -> Figure:
        """The mode shapes as the drive's bodies moving, one 3-D panel per mode (every
        elastic mode by default; see :func:`reducerlab.plot.drive_shape.plot_drive_shapes`).

        Parameters
        ----------
        layout : DriveLayout
            Where the bodies sit: :func:`reducerlab.drives.drive_layout` of the design.
        modes : sequence of int, optional
            1-based modes.
        fraction : float
            Largest drawn displacement over the drive's size.
        panel : float
            Width of one panel (in).
        """
        from ..plot.drive_shape import plot_drive_shapes

        return plot_drive_shapes(self, layout, modes, fraction=fraction, panel=panel)

    def plot_energy(self) -> Figure:
        """Map of kinetic and strain energy shares per mode."""
        from ..plot.modal import plot_energy

        return plot_energy(self)


def eigenvalue_derivatives(
    lam: NDArray, phi: NDArray, dK: NDArray, dM: NDArray, *, tol: float = DEGENERACY_TOL
) -> NDArray[np.float64]:
    """Derivatives of the eigenvalues of ``K phi = lambda M phi`` for ``dK, dM``.

    For a simple eigenvalue ``d lambda = phi^T (dK - lambda dM) phi`` with mass-normalised
    ``phi``. For a repeated eigenvalue the derivatives are the eigenvalues of
    ``Phi^T (dK - lambda dM) Phi`` over its eigenspace ``Phi`` (they are the one-sided
    derivatives of the sorted branches), returned in ascending order.
    """
    n = lam.size
    out = np.empty(n)
    scale = max(float(np.max(np.abs(lam))), np.finfo(float).tiny)
    i = 0
    while i < n:
        j = i + 1
        while j < n and abs(lam[j] - lam[i]) <= tol * max(abs(lam[i]), scale * 1e-12):
            j += 1
        P = phi[:, i:j]
        lam_c = float(np.mean(lam[i:j]))
        D = P.T @ (dK - lam_c * dM) @ P
        out[i:j] = np.linalg.eigvalsh(0.5 * (D + D.T)) if j - i > 1 else np.diag(D)
        i = j
    return out


@names_source
def frequency_sensitivity(
    model: Model, parameters: Sequence[str], result: ModalResult | None = None
) -> SensitivityResult:
    """Sensitivity of every natural frequency to model parameters.

    ``df/dp = (phi^T (dK/dp - lambda dM/dp) phi) / (8 pi^2 |f|)`` with the exact matrix
    derivatives of :meth:`Model.derivative`.

    Parameters
    ----------
    model : Model
    parameters : sequence of str
        Parameter paths (``"speed"``, ``"mesh.stiffness"``, ``"support:gear.x.stiffness"``).
    result : ModalResult, optional
        A modal result of ``model`` to reuse.

    Returns
    -------
    SensitivityResult
        ``dfdp`` (mode, parameter) in Hz per SI unit of the parameter, ``relative``
        ``(p / f) df/dp`` (dimensionless: % change of f per % change of p),
        ``dlambda`` (mode, parameter). Rigid-body modes get NaN.
    """
    if isinstance(parameters, str):
        parameters = [parameters]
    if not parameters:
        raise ReducerlabError("frequency_sensitivity: give at least one parameter path")
    res = result if result is not None else modal(model)
    lam = res.data["eigenvalue"].values
    phi = res.shapes
    f = res.frequencies
    rigid = res.data["rigid"].values.astype(bool)
    dlam, dfdp, rel, values = [], [], [], []
    for p in parameters:
        d = model.derivative(p)
        dl = eigenvalue_derivatives(lam, phi, d.K, d.M)
        with np.errstate(divide="ignore", invalid="ignore"):
            df = np.where(rigid, np.nan, dl / (2 * TWO_PI**2 * np.abs(f)))
            value = float(np.real(model.parameter(p)))
            r = np.where(rigid, np.nan, value * df / f)
        dlam.append(dl)
        dfdp.append(df)
        rel.append(r)
        values.append(value)
    data = xr.Dataset(
        {
            "dfdp": (("mode", "parameter"), np.array(dfdp).T, {"units": "Hz per SI unit"}),
            "relative": (
                ("mode", "parameter"),
                np.array(rel).T,
                {"units": "1", "long_name": "(p/f) df/dp"},
            ),
            "dlambda": (("mode", "parameter"), np.array(dlam).T),
            "value": ("parameter", np.array(values), {"long_name": "parameter value (SI)"}),
            "frequency": res.data["frequency"],
        },
        coords={"mode": res.data["mode"].values, "parameter": list(parameters)},
        attrs=dict(res.data.attrs),
    )
    return SensitivityResult(data)


@dataclass(frozen=True)
class MapCells:
    """The rows and columns a sensitivity map draws, and what it leaves out."""

    #: Row indices: the elastic modes (a rigid-body mode has no frequency to move).
    modes: list[int]
    #: Column indices: the parameters of at least :data:`SHOWN` on some elastic mode.
    parameters: list[int]
    #: Mode numbers of the rigid-body modes left out.
    rigid: list[int]
    #: Parameters under :data:`SHOWN` on every elastic mode, and the largest of them.
    negligible: list[str]
    largest: float
    #: Parameters of value 0: their relative sensitivity is 0 by definition.
    at_zero: list[str]

    def note(self) -> str:
        """What the map leaves out, in words ("" when nothing)."""
        out = []
        if self.rigid:
            modes = ", ".join(str(m) for m in self.rigid)
            out.append(f"rigid-body modes left out (0 Hz): {modes}.")
        if self.negligible:
            out.append(
                f"No effect on any mode (|(p/f) df/dp| < {SHOWN:g} on every mode, at most "
                f"{self.largest:.2g}): {', '.join(self.negligible)}."
            )
        if self.at_zero:
            out.append(
                "Parameters of value 0 (relative sensitivity 0 by definition; see df/dp): "
                f"{', '.join(self.at_zero)}."
            )
        text = " ".join(out)
        return text[:1].upper() + text[1:]


class SensitivityResult(Result):
    """Frequency sensitivities (``dfdp``, ``relative``) per mode and parameter."""

    kind: ClassVar[str] = "sensitivity"

    def map_cells(self) -> MapCells:
        """The cells of the sensitivity maps: the elastic modes against the parameters
        that move one of them by at least :data:`SHOWN` (relative); the rest named."""
        ds = self.data
        rel = ds["relative"].values
        rigid = ~np.all(np.isfinite(rel), axis=1) | (ds["frequency"].values == 0.0)
        rows = [i for i in range(rel.shape[0]) if not rigid[i]]
        params = [str(p) for p in ds["parameter"].values]
        values = ds["value"].values
        big = np.max(np.abs(rel[rows]), axis=0) if rows else np.zeros(len(params))
        cols = [j for j in range(len(params)) if big[j] >= SHOWN]
        zero = [j for j in range(len(params)) if big[j] < SHOWN and values[j] == 0.0]
        small = [j for j in range(len(params)) if big[j] < SHOWN and values[j] != 0.0]
        return MapCells(
            modes=rows,
            parameters=cols,
            rigid=[int(m) for m, r in zip(ds["mode"].values, rigid, strict=True) if r],
            negligible=[params[j] for j in small],
            largest=float(max((big[j] for j in small), default=0.0)),
            at_zero=[params[j] for j in zero],
        )

    def table(self) -> str:
        """Relative sensitivities ``(p/f) df/dp`` as plain text, one column a parameter
        (headers whole)."""
        params = [str(p) for p in self.data["parameter"].values]
        t = Table([Column("mode", kind="count"), Column("f", "Hz", "frequency"),
                   *(Column(p, kind="share") for p in params)])  # fmt: skip
        rel = self.data["relative"].values
        for i, (m, f) in enumerate(
            zip(self.data["mode"].values, self.data["frequency"].values, strict=True)
        ):
            t.add(int(m), float(f), *(float(v) for v in rel[i]))
        return t.text()

    def plot(self) -> Figure:
        """Heat map of the relative sensitivities."""
        from ..plot.modal import plot_sensitivity

        return plot_sensitivity(self)


def _shape_matrix(x: ModalResult | NDArray) -> tuple[NDArray, list[str] | None]:
    if isinstance(x, ModalResult):
        return x.shapes, x.dof_names
    arr = np.asarray(x, dtype=float)
    if arr.ndim != 2:
        raise ReducerlabError(f"mac: mode sets must be 2-D (dof, mode) arrays, got {arr.shape}")
    return arr, None


def mac(
    a: ModalResult | NDArray, b: ModalResult | NDArray, weight: NDArray | None = None
) -> xr.DataArray:
    """Modal assurance criterion between two mode sets.

    ``MAC_ij = |a_i^T W b_j|^2 / ((a_i^T W a_i)(b_j^T W b_j))`` with ``W`` the identity
    (classic MAC) or a weighting matrix such as the mass matrix (then modes of one
    model are mutually orthogonal: MAC is the identity). Results are matched by DOF
    name when both are :class:`ModalResult`; arrays must share the row order (and the
    order of ``weight``, which follows ``a``).

    Returns
    -------
    xarray.DataArray
        Dims ``(mode_a, mode_b)``, values in [0, 1].
    """
    A, na = _shape_matrix(a)
    B, nb = _shape_matrix(b)
    if na is not None and nb is not None:
        if set(na) != set(nb):
            raise ReducerlabError(
                f"mac: the two results have different DOFs: {sorted(set(na) ^ set(nb))}"
            )
        B = B[[nb.index(d) for d in na]]
    if A.shape[0] != B.shape[0]:
        raise ReducerlabError(f"mac: {A.shape[0]} DOFs against {B.shape[0]} DOFs")
    W = np.eye(A.shape[0]) if weight is None else np.asarray(weight, dtype=float)
    if W.shape != (A.shape[0], A.shape[0]):
        raise ReducerlabError(f"mac: weight must be {A.shape[0]}x{A.shape[0]}, got {W.shape}")
    num = (A.T @ W @ B) ** 2
    den = np.outer(np.sum(A * (W @ A), axis=0), np.sum(B * (W @ B), axis=0))
    return xr.DataArray(
        num / den,
        dims=("mode_a", "mode_b"),
        coords={"mode_a": np.arange(1, A.shape[1] + 1), "mode_b": np.arange(1, B.shape[1] + 1)},
        name="MAC",
    )
