"""Batched generalised symmetric eigenproblems ``K phi = lambda M phi``.

One call solves a whole stack of small problems with numpy's batched LAPACK drivers:
``M = L L^T`` (batched Cholesky), ``A = L^-1 K L^-T`` (batched triangular solves),
``A y = lambda y`` (batched ``eigh``), ``phi = L^-T y``. The eigenvectors ``y`` are
orthonormal in the Euclidean sense, i.e. the shapes ``phi`` are mass-normalised, and
``y`` itself is the mass-weighted shape used for mode tracking.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError

__all__ = ["eigh_batch"]


def eigh_batch(
    M: NDArray[np.float64], K: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Solve ``K phi = lambda M phi`` for stacks of matrices.

    Parameters
    ----------
    M, K : ndarray, shape (..., n, n)
        Symmetric mass (positive definite) and stiffness matrices; broadcast together.

    Returns
    -------
    lam : ndarray, shape (..., n)
        Eigenvalues, ascending (rad^2/s^2).
    phi : ndarray, shape (..., n, n)
        Mass-normalised shapes in columns.
    y : ndarray, shape (..., n, n)
        Mass-weighted shapes ``L^T phi`` (orthonormal columns).
    """
    M, K = np.broadcast_arrays(np.asarray(M, float), np.asarray(K, float))
    try:
        L = np.linalg.cholesky(0.5 * (M + np.swapaxes(M, -1, -2)))
    except np.linalg.LinAlgError:
        raise ModelError("a mass matrix of the batch is not positive definite") from None
    Ksym = 0.5 * (K + np.swapaxes(K, -1, -2))
    X = np.linalg.solve(L, Ksym)  # L^-1 K
    A = np.linalg.solve(L, np.swapaxes(X, -1, -2))  # L^-1 (L^-1 K)^T = L^-1 K L^-T
    A = 0.5 * (A + np.swapaxes(A, -1, -2))
    lam, y = np.linalg.eigh(A)
    phi = np.linalg.solve(np.swapaxes(L, -1, -2), y)
    return lam, phi, y
