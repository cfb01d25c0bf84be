"""Flat-array form of a model's nonlinear equations of motion.

:class:`NonlinearSystem` is what time integrators consume: plain float arrays, no
Python objects in the hot path. Its :meth:`~NonlinearSystem.rhs` is the plain-numpy
reference evaluation of the state derivative.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import ClassVar

import numpy as np
from numpy.typing import NDArray

from ..errors import ReducerlabError
from .laws import TimeLaw, evaluate_flat, flat_mean
from .layout import pack_laws

__all__ = ["NonlinearSystem", "Origin", "power_force"]


@dataclass(frozen=True)
class Origin:
    """The physical coordinates behind a system in other (relative, modal) coordinates.

    ``q = S u``: the physical DOF motions ``q`` (named ``dof_names``) of a motion ``u`` of
    the system's coordinates; ``M`` is the physical mass matrix, used to rank DOFs by
    their share of kinetic energy (as :func:`reducerlab.analysis.modal.modal` labels
    modes). Error messages use it to name physical DOFs instead of ``elastic_1``.
    """

    dof_names: list[str]
    S: NDArray[np.float64]
    M: NDArray[np.float64]


def dominant_dofs(
    names: Sequence[str], M: NDArray[np.float64], q: NDArray[np.float64], count: int = 3
) -> list[tuple[str, float]]:
    """The DOFs with the largest share of the kinetic-energy norm ``q^T M q`` of a motion
    ``q`` (at most ``count``, those with at least 10 % or the largest), with their
    shares (fractions)."""
    q = np.asarray(q, float)
    bad = ~np.isfinite(q)
    if bad.any() or not np.any(q):
        i = int(np.argmax(bad)) if bad.any() else 0
        return [(names[i], 1.0)]
    scale = np.abs(q).max()
    qs = q / scale
    share = qs * (M @ qs)
    total = float(np.sum(share))
    share = share / total if total > 0 else np.abs(qs) / np.abs(qs).sum()
    order = np.argsort(-share, kind="stable")
    out = [(names[int(i)], float(share[i])) for i in order[:count] if share[i] >= 0.1]
    return out or [(names[int(order[0])], float(share[order[0]]))]


def describe_dofs(parts: Sequence[tuple[str, float]]) -> str:
    """``"wheel.x (90 %), pinion.x (10 %)"``."""
    return ", ".join(f"{name} ({100 * share:.0f} %)" for name, share in parts)


def power_force(k: float, f: float, exponent: float, reference: float) -> float:
    """Elastic force (N) of a line of tangent stiffness ``k`` (N/m) at the reference
    deflection ``reference`` (m) under the deflection ``f`` (m) beyond its backlash:
    ``k f`` for ``exponent = 1``, else ``k (d / p) sgn(f) (|f| / d)^p`` (``p``: the
    exponent, ``d``: the reference), whose slope is ``k`` at ``|f| = d`` (Hertz's
    point contact: ``p = 1.5``). The reference of the compiled kernel
    (``dynamics.kernel_step``)."""
    if exponent == 1.0 or f == 0.0:
        return k * f
    a = abs(f) / reference
    return math.copysign(k * reference / exponent * a**exponent, f)


def _require_finite(owner: str, what: str, a: NDArray, rows: Sequence[str]) -> None:
    """Raise naming the row (DOF or line) of the first non-finite entry of ``a``."""
    a = np.asarray(a, dtype=float)
    if a.size and not np.all(np.isfinite(a)):
        r = int(np.argwhere(~np.isfinite(a))[0][0]) if a.ndim else 0
        where = f" at {rows[r]!r}" if r < len(rows) else ""
        raise ReducerlabError(
            f"{owner}: the {what} is not finite{where} (an extreme parameter value "
            "overflowed, or NaN was given); check the values of that DOF's elements"
        )


@dataclass(frozen=True)
class NonlinearSystem:
    """``M q'' + C q' + K q + G^T [k(t) f + k3 f^3 + c (G q' - e'(t))] = F(t)``, with
    ``f = f(G q - e(t))`` the dead-zone (backlash) function of the line deflections;
    a line with a load exponent ``p != 1`` (``line_power``) has
    ``k(t) (delta_ref / p) sgn(f) (|f| / delta_ref)^p`` in place of ``k(t) f``
    (:class:`~reducerlab.model.elements.Mesh`).

    Attributes
    ----------
    dof_names : list of str
        Coordinate names in array order (``n`` of them).
    M, C, K : ndarray, shape (n, n)
        Linear mass, damping and stiffness (meshes excluded).
    G : ndarray, shape (n_lines, n)
        Projection coefficients of each mesh line of action.
    line_names : list of str
        Name of each line.
    k_kind, k_params : ndarray
        Stiffness laws of the lines (see :func:`~reducerlab.model.layout.pack_laws`), N/m.
    line_damping : ndarray, shape (n_lines,)
        Mesh damping (N s/m).
    half_backlash : ndarray, shape (n_lines,)
        Dead-zone half widths (m).
    e_kind, e_params : ndarray
        Transmission error laws (m).
    load_matrix : ndarray, shape (n, n_loads)
        Generalised force of each load per unit law value (a unit column for a load on
        one DOF; a distribution after a change of coordinates).
    f_kind, f_params : ndarray
        Load laws (N or N m).
    line_cubic : ndarray, shape (n_lines,)
        Cubic stiffness ``k3`` of each line (N/m^3): the line force gains
        ``k3 f(delta)^3`` (a Duffing-type spring); zeros by default.
    line_power : ndarray, shape (n_lines, 2)
        Load exponent ``p`` and reference deflection ``delta_ref`` (m) of each line's
        elastic force; ``(1, 0)`` (linear) by default.
    """

    dof_names: list[str]
    M: NDArray[np.float64]
    C: NDArray[np.float64]
    K: NDArray[np.float64]
    G: NDArray[np.float64]
    line_names: list[str]
    k_kind: NDArray[np.int64]
    k_params: NDArray[np.float64]
    line_damping: NDArray[np.float64]
    half_backlash: NDArray[np.float64]
    e_kind: NDArray[np.int64]
    e_params: NDArray[np.float64]
    load_matrix: NDArray[np.float64]
    f_kind: NDArray[np.int64]
    f_params: NDArray[np.float64]
    line_cubic: NDArray[np.float64] = field(default=None)  # type: ignore[assignment]
    line_power: NDArray[np.float64] = field(default=None)  # type: ignore[assignment]
    #: Physical DOFs behind relative coordinates (set by :meth:`reduced`); None when
    #: the coordinates are the physical DOFs themselves.
    origin: Origin | None = field(default=None, compare=False)

    #: The float arrays that parameter values change (not the law kinds or names).
    ARRAYS: ClassVar[tuple[str, ...]] = (
        "M", "C", "K", "G", "k_params", "e_params", "f_params", "load_matrix",
        "line_damping", "half_backlash", "line_cubic", "line_power",
    )  # fmt: skip

    def __post_init__(self) -> None:
        n_lines = self.G.shape[0]
        cubic = np.zeros(n_lines) if self.line_cubic is None else np.asarray(self.line_cubic, float)
        if cubic.shape != (n_lines,):
            raise ReducerlabError(f"line_cubic must have shape ({n_lines},), got {cubic.shape}")
        object.__setattr__(self, "line_cubic", cubic)
        power = (np.tile([1.0, 0.0], (n_lines, 1)) if self.line_power is None
                 else np.asarray(self.line_power, float))  # fmt: skip
        if power.shape != (n_lines, 2):
            raise ReducerlabError(f"line_power must have shape ({n_lines}, 2), got {power.shape}")
        object.__setattr__(self, "line_power", power)
        dofs, lines = list(self.dof_names), list(self.line_names)
        loads = [f"load {j + 1}" for j in range(np.shape(self.f_params)[0])]
        for what, a, rows in (
            ("mass matrix", self.M, dofs), ("damping matrix", self.C, dofs),
            ("stiffness matrix", self.K, dofs), ("line of action of a mesh", self.G, lines),
            ("stiffness law of a mesh", self.k_params, lines),
            ("damping of a mesh", self.line_damping, lines),
            ("backlash of a mesh", self.half_backlash, lines),
            ("transmission error law of a mesh", self.e_params, lines),
            ("cubic stiffness of a mesh", cubic, lines),
            ("load exponent of a mesh", power, lines),
            ("load distribution", self.load_matrix, dofs), ("load law", self.f_params, loads),
        ):  # fmt: skip
            _require_finite("model", what, a, rows)

    def physical(self) -> tuple[list[str], NDArray[np.float64], NDArray[np.float64]]:
        """Physical DOF names, the map ``S`` (``q = S u``) from this system's coordinates
        and the physical mass matrix (identity map when no reduction was applied)."""
        if self.origin is None:
            return list(self.dof_names), np.eye(self.n), self.M
        o = self.origin
        return list(o.dof_names), o.S, o.M

    def dominant_dofs(self, u: NDArray[np.float64], count: int = 3) -> list[tuple[str, float]]:
        """Physical DOFs that dominate a motion ``u`` of this system's coordinates, with
        their shares of its kinetic-energy norm (see :func:`dominant_dofs`)."""
        names, S, M = self.physical()
        return dominant_dofs(names, M, S @ np.asarray(u, float), count)

    @classmethod
    def from_laws(
        cls,
        *,
        stiffness_laws: Sequence[TimeLaw],
        error_laws: Sequence[TimeLaw],
        load_laws: Sequence[TimeLaw],
        **arrays: object,
    ) -> NonlinearSystem:
        """Build from law objects, packing each group with
        :func:`~reducerlab.model.layout.pack_laws`."""
        k_kind, k_params = pack_laws(stiffness_laws)
        e_kind, e_params = pack_laws(error_laws)
        f_kind, f_params = pack_laws(load_laws)
        return cls(
            k_kind=k_kind,
            k_params=k_params,
            e_kind=e_kind,
            e_params=e_params,
            f_kind=f_kind,
            f_params=f_params,
            **arrays,  # type: ignore[arg-type]
        )

    @property
    def n(self) -> int:
        """Number of DOFs."""
        return len(self.dof_names)

    @cached_property
    def mean_stiffness(self) -> NDArray[np.float64]:
        """``K + G^T diag(k_mean) G`` (N/m): every line at the time average of its
        stiffness law (the system's arrays are not changed after construction)."""
        k = np.array([flat_mean(int(kd), p) for kd, p in zip(self.k_kind, self.k_params,
                                                            strict=True)])  # fmt: skip
        return self.K + self.G.T @ (self.G * k[:, None])

    def mesh_forces(
        self, t: float, q: NDArray[np.float64], v: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Scalar mesh forces ``F_m = k_m(t) f(delta_m) + c_m d(delta_m)/dt`` (N)."""
        elastic, damping = self.mesh_force_parts(t, q, v)
        return elastic + damping

    def mesh_force_parts(
        self, t: float, q: NDArray[np.float64], v: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """The two parts of each mesh force (N): the elastic (tooth) force
        ``k_m(t) f(delta_m) + k3_m f^3`` (a power law in place of ``k_m f`` where the
        line's exponent is not 1: :func:`power_force`), zero while the teeth are apart
        (``f``: the dead zone of half width ``b_m``), and the viscous force
        ``c_m d(delta_m)/dt``, which the model applies across the gap too (paper 004's
        line damping)."""
        nl = self.G.shape[0]
        elastic = np.empty(nl)
        damping = np.empty(nl)
        for m in range(nl):
            k, _ = evaluate_flat(int(self.k_kind[m]), self.k_params[m], t)
            e, de = evaluate_flat(int(self.e_kind[m]), self.e_params[m], t)
            delta = self.G[m] @ q - e
            h = self.half_backlash[m]
            f = delta - min(max(delta, -h), h)
            k3 = self.line_cubic[m]
            cubic = k3 * f * f * f if k3 != 0.0 else 0.0  # no 0 * inf for a huge f
            elastic[m] = power_force(k, f, *self.line_power[m]) + cubic
            damping[m] = self.line_damping[m] * (self.G[m] @ v - de)
        return elastic, damping

    def external_forces(self, t: float) -> NDArray[np.float64]:
        """Generalised load vector ``F(t)``."""
        values = np.array(
            [
                evaluate_flat(int(k), p, t)[0]
                for k, p in zip(self.f_kind, self.f_params, strict=True)
            ]
        )
        return self.load_matrix @ values if values.size else np.zeros(self.n)

    def reduced(
        self,
        T: NDArray[np.float64],
        names: list[str],
        *,
        rest_stiffness: NDArray[np.float64] | None = None,
        check: bool = True,
    ) -> tuple[NonlinearSystem, NDArray[np.float64]]:
        """The same equations in relative coordinates ``u = T q`` without rigid motion.

        ``T`` (n - r, n) must annihilate the rigid-body modes ``R`` (``K R = 0``,
        ``C R = 0``, ``G R = 0``; r = n - rank). With ``S = M^-1 T^T (T M^-1 T^T)^-1``,
        ``q = R eta + S u`` splits the motion into the free rigid part ``eta`` and the
        elastic part ``u``, mass-orthogonally, and the Galerkin projection gives
        ``S^T M S u'' + S^T C S u' + S^T K S u + (G S)^T [k f(G S u - e) + c(...)]
        = S^T F``: paper 004's Eq. 3-6 for any model (its relative coordinates
        ``X_DH, X_VH, X_VL`` are one choice of ``T``). Returns the reduced system and
        ``S``.

        ``rest_stiffness``, for a system at speed, is its linear stiffness at zero speed:
        the rigid modes must carry none of it, while the speed terms' action on them is
        dropped (see :func:`reducerlab.dynamics.systems.at_rest`). ``check=False`` skips
        the test that the rigid modes carry no stiffness, damping or mesh: for a ``T``
        made from the system's own rigid modes (``rigid_reduction``), where the test
        would only measure the eigen-solver's round-off (large when stiffness values
        span many decades).
        """
        T = np.asarray(T, dtype=float)
        if T.ndim != 2 or T.shape[1] != self.n or len(names) != T.shape[0]:
            raise ReducerlabError(
                f"reduced: T must be (n_relative, {self.n}) with one name per row, got "
                f"{T.shape} and {len(names)} names"
            )
        names0, S0, M0 = self.physical()
        Minv_Tt = np.linalg.solve(self.M, T.T)
        W = np.linalg.inv(T @ Minv_Tt)
        S = Minv_Tt @ W
        if check:
            self._check_rigid_free(T, names, rest_stiffness)
        red = replace(
            self,
            dof_names=list(names),
            M=S.T @ self.M @ S,
            C=S.T @ self.C @ S,
            K=S.T @ self.K @ S,
            G=self.G @ S,
            load_matrix=S.T @ self.load_matrix,
            origin=Origin(names0, S0 @ S, M0),
        )
        return red, S

    def _check_rigid_free(
        self,
        T: NDArray[np.float64],
        names: list[str],
        rest_stiffness: NDArray[np.float64] | None,
    ) -> None:
        """Raise when a rigid mode of ``T`` (its null space) carries stiffness, damping
        or a mesh line: the relative coordinates leave an elastic motion undescribed."""
        # rigid modes: null space of T; they must carry no stiffness, damping or mesh
        _, sv, vt = np.linalg.svd(T)
        R = vt[np.sum(sv > 1e-12 * sv.max()) :].T
        K = self.K if rest_stiffness is None else np.asarray(rest_stiffness, float)
        for what, A, rows in (
            ("the stiffness (supports, couplings) at", K, self.dof_names),
            ("the damping (supports, couplings) at", self.C, self.dof_names),
            ("the mesh line(s)", self.G, self.line_names),
        ):
            if not (R.size and A.size):
                continue
            AR = np.abs(A @ R)
            if AR.max() > 1e-9 * max(np.abs(A).max(), 1e-300):
                resist = [rows[i] for i in np.nonzero(AR.max(axis=1) > 1e-9 * AR.max())[0]]
                free = np.abs(R).max(axis=1)
                moving = [self.dof_names[i] for i in np.nonzero(free > 1e-6 * free.max())[0]]
                raise ReducerlabError(
                    f"reduced: the relative coordinates {list(names)} leave a motion of "
                    f"{moving} free, but {what} {resist} resist(s) it; add a relative "
                    "coordinate that measures that motion (every elastic deformation "
                    "must be described), or remove the stiffness that holds it"
                )

    def rhs(self, t: float, y: NDArray[np.float64]) -> NDArray[np.float64]:
        """State derivative ``[q', q'']`` for ``y = [q, q']`` (plain numpy reference)."""
        n = self.n
        q, v = y[:n], y[n:]
        force = self.external_forces(t) - self.C @ v - self.K @ q
        force -= self.G.T @ self.mesh_forces(t, q, v)
        return np.concatenate([v, np.linalg.solve(self.M, force)])
