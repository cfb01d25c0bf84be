"""The compliance matrix of the contact cells at one mesh position, computed on demand.

``C = C_hs + W_A K_A W_A^T + W_B K_B W_B^T`` (m/N) over the ``n`` candidate cells of a
position: the half-space influence between cells of the same tooth pair
(``contact.halfspace.influence_matrix``) and the finite-element bending compliance of
each gear interpolated from its load points (``contact.compliance.ToothCompliance``).
The load-distribution solver (``contact.complementarity.solve_contact``) needs only
``C_AA`` and ``C F`` with ``F`` zero off the contact set ``A``, that is the columns of
the cells that carry load (about a third of the candidates on a gear flank), so the
columns are made when first asked for (``contact.kernels.fill_columns``) and kept.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from .halfspace import FAR_FIELD

__all__ = ["CellCompliance"]

Array = NDArray[np.float64]


class CellCompliance:
    """Compliance between contact cells (m/N), made column by column.

    Parameters
    ----------
    points : ndarray (n, 3)
        Cell centres (m).
    axes_u, axes_v : ndarray (n, 3)
        Orthonormal in-plane axes of the cells.
    half_u, half_v : ndarray (n,)
        Half sides of the cells along the axes (m).
    E_star : float
        Combined modulus of the two bodies (Pa).
    body : ndarray of int (n,)
        Tooth pair of each cell: the half-space acts only within a tooth pair.
    bending : sequence of (ToothCompliance, tooth, u, v)
        The bending compliance of each gear with its flank parameters of the cells.
    """

    def __init__(
        self,
        points: Array,
        axes_u: Array,
        axes_v: Array,
        half_u: Array,
        half_v: Array,
        E_star: float,
        body: NDArray[np.int64],
        bending: Sequence = (),
    ) -> None:
        from .kernels import cell_tables, stencil_product

        n = len(points)
        self.shape = (n, n)
        self._P = np.ascontiguousarray(points - points.mean(axis=0))
        self._U = np.ascontiguousarray(axes_u, dtype=float)
        self._V = np.ascontiguousarray(axes_v, dtype=float)
        self._hu = np.ascontiguousarray(half_u, dtype=float)
        self._hv = np.ascontiguousarray(half_v, dtype=float)
        self._scale = 1.0 / (math.pi * E_star * 4.0 * self._hu * self._hv)
        self._body = np.ascontiguousarray(body, dtype=np.int64)
        self._tables = cell_tables(self._P, self._U, self._V, self._hu, self._hv, FAR_FIELD)
        WKs, cols, ws, offset = [], [], [], 0
        for comp, tooth, u, v in bending:
            c, w = comp.stencil(tooth, u, v)
            WKs.append(stencil_product(c, w, np.ascontiguousarray(comp.matrix)))
            cols.append(c + offset)
            ws.append(w)
            offset += comp.matrix.shape[0]
        if WKs:
            self._WK = np.ascontiguousarray(np.hstack(WKs))
            self._cols = np.ascontiguousarray(np.hstack(cols), dtype=np.int64)
            self._w = np.ascontiguousarray(np.hstack(ws))
        else:
            self._WK = np.zeros((n, 1))
            self._cols = np.zeros((n, 0), dtype=np.int64)
            self._w = np.zeros((n, 0))
        self._C = np.zeros((n, n), order="F")  # columns not yet made are zero
        self._made = np.zeros(n, dtype=bool)

    def _make(self, idx: NDArray[np.int64]) -> None:
        from .kernels import fill_columns

        new = np.unique(idx[~self._made[idx]])
        if new.size:
            W, cu, cv, cw, coef, lim2 = self._tables
            fill_columns(
                self._C, new, self._P, self._U, self._V, W, cu, cv, cw, self._hu,
                self._hv, coef, lim2, self._scale, self._body, self._WK, self._cols, self._w,
            )  # fmt: skip
            self._made[new] = True

    @property
    def columns_made(self) -> int:
        """How many columns have been computed."""
        return int(self._made.sum())

    def diagonal(self) -> Array:
        """``C_ii`` (m/N): the self terms, made without the rest of the columns."""
        from .kernels import diagonal_entries

        W, cu, cv, cw, coef, lim2 = self._tables
        return diagonal_entries(
            self._P, self._U, self._V, W, cu, cv, cw, self._hu, self._hv, coef, lim2,
            self._scale, self._WK, self._cols, self._w,
        )  # fmt: skip

    def block(self, A: NDArray[np.int64]) -> Array:
        """``C_AA`` (m/N)."""
        self._make(A)
        # gathered through the transpose (C order, rows contiguous): C_AA^T, which is
        # C_AA; the solver's Cholesky factor reads one triangle of it
        return self._C.T[np.ix_(A, A)]

    def apply(self, F: Array, A: NDArray[np.int64]) -> Array:
        """``C F`` (m) for forces ``F`` (N) that are zero off ``A``."""
        self._make(A)
        return self._C @ F

    def dense(self) -> Array:
        """The whole matrix (all columns made)."""
        self._make(np.arange(self.shape[0]))
        return np.array(self._C)
