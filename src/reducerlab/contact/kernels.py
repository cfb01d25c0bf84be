"""Compiled (numba) kernels of the contact compliance matrix.

The loaded tooth contact analysis needs, at every mesh position, the compliance between
a few thousand contact cells: the half-space influence of every cell on every other cell
of the same tooth (``contact.halfspace.influence_matrix``) plus the finite-element
bending compliance interpolated to the cells (``contact.compliance.ToothCompliance``).
Written with numpy, each of the ``N^2`` entries passes through a dozen temporary arrays;
these kernels compute each entry once, in parallel, with the same formulas: the whole
symmetric matrix (:func:`half_space_block`) or the columns the solver asks for
(:func:`fill_columns`, ``contact.cellmatrix``). ``tests/test_contact_kernels.py``
compares them with the numpy definitions.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

__all__ = [
    "cell_tables",
    "diagonal_entries",
    "fill_columns",
    "half_space_block",
    "stencil_product",
]


@nb.njit(cache=True, inline="always")
def _corner(x: float, y: float) -> float:
    """``x asinh(y/|x|) + y asinh(x/|y|)`` with ``0 asinh(./0) = 0`` (Love 1929)."""
    out = 0.0
    ax = abs(x)
    ay = abs(y)
    if ax > 0.0:
        out += x * math.asinh(y / ax)
    if ay > 0.0:
        out += y * math.asinh(x / ay)
    return out


@nb.njit(cache=True, inline="always")
def _rect_entry(dx: float, dy: float, a: float, b: float, coef: np.ndarray, lim2: float) -> float:
    """``int int dxi deta / r`` over the rectangle ``|xi| <= a, |eta| <= b`` at
    ``(dx, dy)``: the closed form within ``lim2 = (far max(a, b))^2``, the fourth-order
    multipole expansion with the coefficients ``coef`` beyond
    (``contact.halfspace._rect_exact``, ``_rect_multipole`` and
    ``_multipole_coefficients``)."""
    x2 = dx * dx
    r2 = x2 + dy * dy
    if r2 < lim2:
        dx = abs(dx)
        dy = abs(dy)
        return (
            _corner(dx + a, dy + b)
            - _corner(dx - a, dy + b)
            - _corner(dx + a, dy - b)
            + _corner(dx - a, dy - b)
        )
    ir2 = 1.0 / r2
    c = x2 * ir2
    t4 = ((coef[5] * c + coef[4]) * c + coef[3]) * ir2 + (coef[2] * c + coef[1])
    return coef[0] * math.sqrt(ir2) * (1.0 + t4 * ir2)


@nb.njit(cache=True, inline="always")
def _entry(P, i, j, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale) -> float:
    """Approach of cell ``i`` per unit force on cell ``j`` (m/N), unsymmetrised."""
    px, py, pz = P[i, 0], P[i, 1], P[i, 2]
    dx = px * U[j, 0] + py * U[j, 1] + pz * U[j, 2] - cu[j]
    dy = px * V[j, 0] + py * V[j, 1] + pz * V[j, 2] - cv[j]
    dz = px * W[j, 0] + py * W[j, 1] + pz * W[j, 2] - cw[j]
    r2p = dx * dx + dy * dy
    z2 = dz * dz
    if r2p > 0.0:  # stretch the in-plane offset to the chord length
        stretch = math.sqrt(1.0 + z2 / r2p)
        dx *= stretch
        dy *= stretch
    elif z2 > 0.0:  # straight above the cell centre: any in-plane direction
        dx = abs(dz)
    return _rect_entry(dx, dy, hu[j], hv[j], coef[j], lim2[j]) * scale[j]


@nb.njit(cache=True, inline="always")
def _far(du: float, dv: float, ir2: float, coef: np.ndarray) -> float:
    """The multipole branch of :func:`_rect_entry` from the in-plane offset ``(du, dv)``
    in the cell's axes (its direction only: ``c = du^2 / (du^2 + dv^2)``, 1 on the
    normal) and ``ir2 = 1 / r^2`` of the chord."""
    p2 = du * du + dv * dv
    c = du * du / p2 if p2 > 0.0 else 1.0
    t4 = ((coef[5] * c + coef[4]) * c + coef[3]) * ir2 + (coef[2] * c + coef[1])
    return coef[0] * math.sqrt(ir2) * (1.0 + t4 * ir2)


@nb.njit(cache=True, inline="always")
def _pair(P, i, j, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale) -> float:
    """Symmetrised entry ``(C_ij + C_ji) / 2`` (m/N). Far from both cells (the usual
    case) the two directions share the chord: the stretched offset has the chord's
    length, so only its direction in each cell's axes differs."""
    if i == j:
        return _entry(P, i, j, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale)
    dx = P[i, 0] - P[j, 0]
    dy = P[i, 1] - P[j, 1]
    dz = P[i, 2] - P[j, 2]
    r2 = dx * dx + dy * dy + dz * dz
    if r2 >= lim2[i] and r2 >= lim2[j]:
        ir2 = 1.0 / r2
        uj = dx * U[j, 0] + dy * U[j, 1] + dz * U[j, 2]
        vj = dx * V[j, 0] + dy * V[j, 1] + dz * V[j, 2]
        ui = dx * U[i, 0] + dy * U[i, 1] + dz * U[i, 2]
        vi = dx * V[i, 0] + dy * V[i, 1] + dz * V[i, 2]
        return 0.5 * (_far(uj, vj, ir2, coef[j]) * scale[j] + _far(ui, vi, ir2, coef[i]) * scale[i])
    e = _entry(P, i, j, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale)
    return 0.5 * (e + _entry(P, j, i, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale))


@nb.njit(cache=True)
def _fill_row(C, i, P, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale, labels) -> None:
    """Entries ``(i, j)`` and ``(j, i)``, ``j <= i``, symmetrised."""
    for j in range(i + 1):
        if labels[i] != labels[j]:
            continue
        e = _pair(P, i, j, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale)
        C[i, j] = e
        C[j, i] = e


@nb.njit(cache=True)
def cell_tables(P: np.ndarray, U: np.ndarray, V: np.ndarray, hu: np.ndarray, hv: np.ndarray,
                far: float):  # fmt: skip
    """Per-cell constants of the half-space entries: normals ``W``, the projections
    ``P_j . U_j`` etc., the multipole coefficients (``contact.halfspace.
    _multipole_coefficients``) and the squared far-field radius."""
    n = P.shape[0]
    W = np.empty((n, 3))
    cu = np.empty(n)
    cv = np.empty(n)
    cw = np.empty(n)
    coef = np.empty((n, 6))
    lim2 = np.empty(n)
    for j in range(n):
        W[j, 0] = U[j, 1] * V[j, 2] - U[j, 2] * V[j, 1]
        W[j, 1] = U[j, 2] * V[j, 0] - U[j, 0] * V[j, 2]
        W[j, 2] = U[j, 0] * V[j, 1] - U[j, 1] * V[j, 0]
        cu[j] = P[j, 0] * U[j, 0] + P[j, 1] * U[j, 1] + P[j, 2] * U[j, 2]
        cv[j] = P[j, 0] * V[j, 0] + P[j, 1] * V[j, 1] + P[j, 2] * V[j, 2]
        cw[j] = P[j, 0] * W[j, 0] + P[j, 1] * W[j, 1] + P[j, 2] * W[j, 2]
        a, b = hu[j], hv[j]
        a2, b2 = a * a, b * b
        a4, b4, ab = a2 * a2, b2 * b2, a2 * b2
        coef[j, 0] = 4.0 * a * b
        coef[j, 1] = (2.0 * b2 - a2) / 6.0
        coef[j, 2] = 0.5 * (a2 - b2)
        coef[j, 3] = (1.8 * a4 - 8.0 * ab + 4.8 * b4) / 24.0
        coef[j, 4] = (-18.0 * a4 + 70.0 * ab - 24.0 * b4) / 24.0
        coef[j, 5] = (21.0 * a4 - 70.0 * ab + 21.0 * b4) / 24.0
        lim = far * max(a, b)
        lim2[j] = lim * lim
    return W, cu, cv, cw, coef, lim2


@nb.njit(cache=True, parallel=True)
def fill_columns(Cf, js, P, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale, labels, WK, cols, w):
    """Columns ``js`` of the cell compliance into ``Cf`` (n, n), Fortran order (m/N):
    the symmetrised half-space entries between cells of the same ``labels`` plus the
    interpolated bending compliance ``sum_b w[j, b] WK[:, cols[j, b]]`` (``WK = W K``
    of :func:`stencil_product`, both gears side by side)."""
    n = P.shape[0]
    k = cols.shape[1]
    for jj in nb.prange(js.shape[0]):
        j = js[jj]
        for i in range(n):
            acc = 0.0
            for b in range(k):
                acc += w[j, b] * WK[i, cols[j, b]]
            if labels[i] == labels[j]:
                acc += _pair(P, i, j, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale)
            Cf[i, j] = acc


@nb.njit(cache=True)
def diagonal_entries(P, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale, WK, cols, w):
    """The diagonal of :func:`fill_columns`' matrix (m/N): self terms only."""
    n = P.shape[0]
    k = cols.shape[1]
    d = np.empty(n)
    for j in range(n):
        acc = 0.0
        for b in range(k):
            acc += w[j, b] * WK[j, cols[j, b]]
        d[j] = acc + _entry(P, j, j, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale)
    return d


@nb.njit(cache=True, parallel=True)
def stencil_product(cols: np.ndarray, w: np.ndarray, K: np.ndarray) -> np.ndarray:
    """``W K`` (n, L) for the sparse interpolation ``W`` (weights ``w[i]`` in columns
    ``cols[i]``) and the load-point compliance ``K`` (L, L)."""
    n, k = cols.shape
    L = K.shape[0]
    WK = np.zeros((n, L))
    for i in nb.prange(n):
        for a in range(k):
            c = cols[i, a]
            wa = w[i, a]
            if wa == 0.0:
                continue
            for m in range(L):
                WK[i, m] += wa * K[c, m]
    return WK


@nb.njit(cache=True, parallel=True)
def half_space_block(
    P: np.ndarray,
    U: np.ndarray,
    V: np.ndarray,
    hu: np.ndarray,
    hv: np.ndarray,
    scale: np.ndarray,
    labels: np.ndarray,
    far: float,
) -> np.ndarray:
    """Symmetric half-space compliance between cells (m/N).

    Entry ``(i, j)`` before symmetrisation: ``f(dx, dy, hu_j, hv_j) scale_j`` with
    ``(dx, dy)`` the offset ``P_i - P_j`` in the axes ``U_j, V_j`` of cell ``j``
    stretched to the chord length (``contact.halfspace.influence_matrix``), 0 between
    cells of different ``labels``; the result is ``(C + C^T) / 2``.

    Parameters
    ----------
    P : ndarray (n, 3)
        Cell centres (m), best centred on their mean.
    U, V : ndarray (n, 3)
        Orthonormal in-plane axes of the cells.
    hu, hv : ndarray (n,)
        Half sides along ``U`` and ``V`` (m).
    scale : ndarray (n,)
        ``1 / (pi E* 4 hu hv)`` per cell (1/(Pa m^2)).
    labels : ndarray of int64 (n,)
        Body of each cell.
    far : float
        Far-field radius in half sides (``contact.halfspace.FAR_FIELD``).
    """
    n = P.shape[0]
    C = np.zeros((n, n))
    W, cu, cv, cw, coef, lim2 = cell_tables(P, U, V, hu, hv, far)
    # rows t and n - 1 - t together: every task has the same share of the triangle
    for t in nb.prange((n + 1) // 2):
        _fill_row(C, t, P, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale, labels)
        if n - 1 - t != t:
            _fill_row(C, n - 1 - t, P, U, V, W, cu, cv, cw, hu, hv, coef, lim2, scale, labels)
    return C
