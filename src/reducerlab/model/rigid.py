"""The rigid-mode test: which motions of a model strain no element.

A rigid-body mode is a motion that strains no element (:func:`strain_ratio` at most
:data:`RIGID_TOL`), the null space of the stiffness at rest by the model's connectivity,
whatever the spread of stiffness and mass values. Modal analysis, sweeps, Campbell
diagrams and the nonlinear engine (which integrates in elastic coordinates) all use
this one test; it lives below them, with the model.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from ..errors import ModelError
from ..units import TWO_PI
from .assembly import Model

__all__ = [
    "MOTION_TOL",
    "RESOLUTION",
    "RIGID_TOL",
    "check_resolved",
    "element_blocks",
    "rest_stiffness",
    "rigid_and_elastic",
    "solve_modes",
    "strain_ratio",
]


def solve_modes(M: NDArray, K: NDArray, model: Model) -> tuple[NDArray, NDArray]:
    """Eigenvalues and mass-normalised shapes of ``K phi = lambda M phi`` (symmetric
    parts), ``lambda`` in rad^2/s^2; a DOF without inertia, a failing or non-finite
    solve raise :class:`ModelError` naming ``model``'s DOFs."""
    M = 0.5 * (M + M.T)
    K = 0.5 * (K + K.T)
    massless = [model.dof_names[i] for i in range(model.n) if not M[i, i] > 0]
    if massless:
        raise ModelError(
            f"DOF(s) {massless} have no inertia, so M is singular; add an Inertia element "
            "on each DOF (or remove the DOF)"
        )
    try:
        lam, phi = scipy.linalg.eigh(K, M)
    except (np.linalg.LinAlgError, ValueError) as exc:
        d = np.diag(M)
        i, j = int(np.argmin(d)), int(np.argmax(d))
        raise ModelError(
            f"model {model.name!r}: the eigen-solver failed ({exc}); the inertias span "
            f"{d[i]:.3g} ({model.dof_names[i]}) to {d[j]:.3g} ({model.dof_names[j]}) in SI: "
            "check for an extreme inertia or stiffness value"
        ) from None
    if not (np.all(np.isfinite(lam)) and np.all(np.isfinite(phi))):
        raise ModelError(
            f"model {model.name!r}: the eigen-solver returned non-finite values; check for "
            "an extreme inertia or stiffness value"
        )
    return lam, phi


#: Mass-weighted amplitude, relative to the mode's largest, below which an element
#: is not moved by a mode (round-off of the eigen-solver is ~1e-16).
MOTION_TOL = 1e-6


#: Largest element strain ratio of a rigid-body mode (the default ``rigid_tol`` of every
#: analysis that tells rigid from elastic modes).
RIGID_TOL = 1e-10


def rest_stiffness(model: Model) -> NDArray[np.float64] | None:
    """``K`` of ``model`` at zero speed (speed terms left out), or None when it runs at
    zero speed: rigid-body modes are those of the model at rest."""
    return None if model.speed == 0.0 else model.with_speed(0.0).matrices().K


def element_blocks(model: Model) -> list[tuple[list[int], NDArray[np.float64]]]:
    """``(dof indices, K_e)`` of every element with stiffness, at zero speed (mean mesh
    stiffness included): what :func:`strain_ratio` tests a mode against."""
    out = []
    for e in model.elements:
        idx, em = model.element_matrices(e, 0.0)
        Ke = np.real(em.K)
        if np.any(Ke):
            out.append((list(idx), Ke))
    return out


def strain_ratio(
    model: Model | Sequence[tuple[list[int], NDArray]], M: NDArray, phi: NDArray
) -> NDArray[np.float64]:
    """Largest element strain ratio of each mode, for shapes ``phi`` (..., n, modes).

    ``model`` is a model or its :func:`element_blocks`; a block's ``K_e`` may be a
    stack (..., n_e, n_e) matching the leading axes of ``phi`` (a sweep's points).

    For every element ``e`` with stiffness (at zero speed, mean mesh stiffness
    included) that the mode moves (mass-weighted amplitude ``sqrt(M_ii) |phi_i|`` of
    one of its DOFs above ``1e-6`` of the mode's largest), the ratio
    ``|phi_e^T K_e phi_e| / (|phi_e|^T |K_e| |phi_e|)``; the largest over the
    elements. It is 0 (round-off) for a motion that strains no element: a rigid-body
    motion, the null space of ``K`` by the model's connectivity, whatever the spread of
    stiffness and mass values; it is of order one for a motion that strains an
    element (a support that the mode moves gives 1). Unlike an eigenvalue compared
    with the largest eigenvalue, it does not depend on the other modes.
    """
    phi = np.asarray(phi)
    w = np.abs(phi) * np.sqrt(np.abs(np.diagonal(M, axis1=-2, axis2=-1)))[..., :, None]
    wmax = w.max(axis=-2)
    ratio = np.zeros(phi.shape[:-2] + phi.shape[-1:])
    blocks = element_blocks(model) if isinstance(model, Model) else model
    for idx, Ke in blocks:
        pe = phi[..., idx, :]
        u = np.abs(np.einsum("...im,...ij,...jm->...m", pe, Ke, pe))
        a = np.einsum("...im,...ij,...jm->...m", np.abs(pe), np.abs(Ke), np.abs(pe))
        moved = (w[..., idx, :].max(axis=-2) > MOTION_TOL * wmax) & (a > 0)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.maximum(ratio, np.where(moved, u / np.where(moved, a, 1.0), 0.0))
    return ratio


#: An elastic eigenvalue within ``RESOLUTION`` units of round-off of the largest one
#: (``|lambda| < RESOLUTION * eps * max|lambda|``, about 2.2e-12 of it) is below what a
#: symmetric eigen-solver resolves: its absolute error is ``~ n eps max|lambda|``, so
#: such a frequency would be wrong by more than ~1e-4 n relative, or its sign arbitrary.
RESOLUTION = 1e4


def check_resolved(
    lam: NDArray, rigid: NDArray, M: NDArray, K: NDArray, names: Sequence[str], what: str
) -> None:
    """Raise :class:`ModelError` when an elastic mode lies below the eigen-solver's
    resolution (:data:`RESOLUTION`): the stiffness and inertia values span more than
    double precision can hold, and the low frequencies would be round-off (a stable
    model reported "divergent", a rigid mode reported elastic). The message names the
    DOF whose stiffness / inertia sets the highest frequency.

    ``lam`` (..., n), ``rigid`` (..., n), ``M`` and ``K`` (..., n, n) may be stacks.
    """
    lam = np.asarray(lam, float)
    top = np.max(np.abs(lam), axis=-1, keepdims=True)
    floor = RESOLUTION * np.finfo(float).eps * top
    bad = ~np.asarray(rigid, bool) & (np.abs(lam) < floor)
    if not bad.any():
        return
    at = np.unravel_index(int(np.argmax(bad.reshape(-1, lam.shape[-1]).any(axis=1))),
                          lam.shape[:-1])  # fmt: skip
    Mp = np.broadcast_to(M, lam.shape[:-1] + M.shape[-2:])[at]
    Kp = np.broadcast_to(K, lam.shape[:-1] + K.shape[-2:])[at]
    ratio = np.abs(np.diag(Kp)) / np.abs(np.diag(Mp))
    i = int(np.argmax(ratio))
    f_top = math.sqrt(float(top[at][0])) / TWO_PI
    f_floor = math.sqrt(float(floor[at][0])) / TWO_PI
    low = [f"{math.copysign(math.sqrt(abs(v)), v) / TWO_PI:.3g} Hz" for v in lam[at][bad[at]]]
    raise ModelError(
        f"{what}: the stiffness and inertia values span more than double precision "
        f"resolves: the highest natural frequency is {f_top:.4g} Hz (set by {names[i]}: "
        f"stiffness / inertia = {ratio[i]:.3g} 1/s^2), so no frequency below "
        f"{f_floor:.3g} Hz can be computed, yet {len(low)} mode(s) lie there "
        f"({', '.join(low)}: round-off, not results). Check the inertia of {names[i]} and "
        "the stiffness acting on it for an extreme value (e.g. a near-zero inertia or a "
        "near-rigid stiffness: a rigid joint is better modelled by merging the DOFs)"
    )


def rigid_and_elastic(
    model: Model, M: NDArray, K: NDArray, rigid_tol: float
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Eigenvalues, shapes, rigid flags, and the speed-term eigenvalues of rigid modes.

    Rigid-body modes are the motions that strain no element: the null space of the
    stiffness without speed-dependent terms (``K`` at zero speed). Speed terms are
    linearised in a rotating frame and do not respect its symmetries (e.g. the
    centripetal ``-m Omega^2`` on a tangential translation that is a pure phase shift
    of the rotating assembly), so rigid modes are kept at exactly 0 Hz and the elastic
    modes are solved on their mass-orthogonal complement; what the speed terms would
    do to each rigid mode (``phi^T K phi``) is returned as ``drift`` (rad^2/s^2).
    """
    lam, phi = solve_modes(M, K, model)
    blocks = element_blocks(model)  # once: both strain tests below use them
    K0 = rest_stiffness(model)
    if K0 is None:
        rigid = strain_ratio(blocks, M, phi) <= rigid_tol
        return np.where(rigid, 0.0, lam), phi, rigid, np.zeros(int(rigid.sum()))
    _, phi0 = solve_modes(M, K0, model)
    null = strain_ratio(blocks, M, phi0) <= rigid_tol
    if not null.any() or np.array_equal(K0, K):
        rigid = (
            strain_ratio(blocks, M, phi) <= rigid_tol if null.any() else np.zeros(lam.size, bool)
        )
        return np.where(rigid, 0.0, lam), phi, rigid, np.zeros(int(rigid.sum()))
    N, V = phi0[:, null], phi0[:, ~null]  # M-orthonormal bases
    drift = np.einsum("im,ij,jm->m", N, K, N)
    lam_e, z = np.linalg.eigh(0.5 * (V.T @ K @ V + (V.T @ K @ V).T))
    lam_all = np.concatenate([np.zeros(N.shape[1]), lam_e])
    phi_all = np.concatenate([N, V @ z], axis=1)
    order = np.argsort(lam_all, kind="stable")
    rigid = np.concatenate([np.ones(N.shape[1], bool), np.zeros(lam_e.size, bool)])[order]
    return lam_all[order], phi_all[:, order], rigid, drift
