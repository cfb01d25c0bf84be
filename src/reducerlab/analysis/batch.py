"""Batched generalised symmetric eigenproblems ``K phi = lambda M phi``.

One call solves a whole stack of small problems with numpy's batched LAPACK drivers:
``M = L L^T`` (Cholesky, once when ``M`` is shared by the stack), ``A = L^-1 K L^-T``,
``A y = lambda y`` (batched ``eigh``, split over threads for large stacks: numpy's
linear-algebra loops release the GIL), ``phi = L^-T y``. The eigenvectors ``y`` are
orthonormal, i.e. the shapes ``phi`` are mass-normalised, and ``y`` is the
mass-weighted shape used for mode tracking.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from numpy.typing import NDArray

from ..errors import ModelError

__all__ = ["eigh_batch"]

#: Stacks at least this large are split over threads.
THREAD_MIN = 2000


def _sym(a: NDArray) -> NDArray:
    return 0.5 * (a + np.swapaxes(a, -1, -2))


def _eigh(A: NDArray) -> tuple[NDArray, NDArray]:
    n_threads = min(os.cpu_count() or 1, 8)
    if A.ndim < 3 or A.shape[0] < THREAD_MIN or n_threads < 2:
        return np.linalg.eigh(A)
    parts = np.array_split(A, n_threads)
    with ThreadPoolExecutor(n_threads) as pool:
        out = list(pool.map(np.linalg.eigh, parts))
    return np.concatenate([o[0] for o in out]), np.concatenate([o[1] for o in out])


def eigh_batch(
    M: NDArray[np.float64], K: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Solve ``K phi = lambda M phi`` for stacks of matrices.

    Parameters
    ----------
    M, K : ndarray, shape (..., n, n)
        Symmetric mass (positive definite) and stiffness matrices; broadcast together.
        A single ``M`` (n, n) for a stack of ``K`` is factorised once.

    Returns
    -------
    lam : ndarray, shape (..., n)
        Eigenvalues, ascending (rad^2/s^2).
    phi : ndarray, shape (..., n, n)
        Mass-normalised shapes in columns.
    y : ndarray, shape (..., n, n)
        Mass-weighted shapes ``L^T phi`` (orthonormal columns).
    """
    M = np.asarray(M, float)
    K = _sym(np.asarray(K, float))
    try:
        L = np.linalg.cholesky(_sym(M))
    except np.linalg.LinAlgError:
        raise ModelError("a mass matrix of the batch is not positive definite") from None
    if M.ndim == 2:
        Linv = np.linalg.inv(L)
        A = Linv @ K @ Linv.T
        lam, y = _eigh(_sym(A))
        return lam, Linv.T @ y, y
    L, K = np.broadcast_arrays(L, K)
    X = np.linalg.solve(L, K)  # L^-1 K
    A = np.linalg.solve(L, np.swapaxes(X, -1, -2))  # L^-1 K L^-T
    lam, y = _eigh(_sym(A))
    phi = np.linalg.solve(np.swapaxes(L, -1, -2), y)
    return lam, phi, y
