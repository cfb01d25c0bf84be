"""Flat-array form of a model's nonlinear equations of motion.

:class:`NonlinearSystem` is what time integrators consume: plain float arrays, no
Python objects in the hot path. Its :meth:`~NonlinearSystem.rhs` is the plain-numpy
reference evaluation of the state derivative.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from .laws import TimeLaw, evaluate_flat

__all__ = ["NonlinearSystem", "pack_laws"]


def pack_laws(laws: Sequence[TimeLaw]) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """Kind codes ``(n,)`` and zero-padded parameter rows ``(n, p_max)`` of ``laws``."""
    flats = [law.flat() for law in laws]
    width = max((p.size for _, p in flats), default=1)
    kinds = np.array([k for k, _ in flats], dtype=np.int64)
    params = np.zeros((len(flats), width))
    for i, (_, p) in enumerate(flats):
        params[i, : p.size] = p
    return kinds, params


@dataclass(frozen=True)
class NonlinearSystem:
    """``M q'' + C q' + K q + G^T [k(t) f(G q - e(t)) + c (G q' - e'(t))] = F(t)``.

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
        Stiffness laws of the lines (see :func:`pack_laws`), N/m.
    line_damping : ndarray, shape (n_lines,)
        Mesh damping (N s/m).
    half_backlash : ndarray, shape (n_lines,)
        Dead-zone half widths (m).
    e_kind, e_params : ndarray
        Transmission error laws (m).
    load_dofs : ndarray of int
        DOF index of each load.
    f_kind, f_params : ndarray
        Load laws (N or N m).
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
    load_dofs: NDArray[np.intp]
    f_kind: NDArray[np.int64]
    f_params: NDArray[np.float64]

    @classmethod
    def from_laws(
        cls,
        *,
        stiffness_laws: Sequence[TimeLaw],
        error_laws: Sequence[TimeLaw],
        load_laws: Sequence[TimeLaw],
        **arrays: object,
    ) -> NonlinearSystem:
        """Build from law objects, packing each group with :func:`pack_laws`."""
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

    def mesh_forces(
        self, t: float, q: NDArray[np.float64], v: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        """Scalar mesh forces ``F_m = k_m(t) f(delta_m) + c_m d(delta_m)/dt`` (N)."""
        nl = self.G.shape[0]
        out = np.empty(nl)
        for m in range(nl):
            k, _ = evaluate_flat(int(self.k_kind[m]), self.k_params[m], t)
            e, de = evaluate_flat(int(self.e_kind[m]), self.e_params[m], t)
            delta = self.G[m] @ q - e
            h = self.half_backlash[m]
            f = delta - min(max(delta, -h), h)
            out[m] = k * f + self.line_damping[m] * (self.G[m] @ v - de)
        return out

    def external_forces(self, t: float) -> NDArray[np.float64]:
        """Generalised load vector ``F(t)``."""
        F = np.zeros(self.n)
        for j, dof in enumerate(self.load_dofs):
            F[dof] += evaluate_flat(int(self.f_kind[j]), self.f_params[j], t)[0]
        return F

    def rhs(self, t: float, y: NDArray[np.float64]) -> NDArray[np.float64]:
        """State derivative ``[q', q'']`` for ``y = [q, q']`` (plain numpy reference)."""
        n = self.n
        q, v = y[:n], y[n:]
        force = self.external_forces(t) - self.C @ v - self.K @ q
        force -= self.G.T @ self.mesh_forces(t, q, v)
        return np.concatenate([v, np.linalg.solve(self.M, force)])
