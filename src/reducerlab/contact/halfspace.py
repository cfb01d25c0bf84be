"""The elastic half-space of a loaded tooth contact: surface compliance of rectangular
cells and the subsurface stress under them.

The contact surface of a tooth pair is divided into ``N`` small rectangular cells, each
carrying a uniform pressure. Both bodies are treated as elastic half-spaces (the cells
are small against the radii of curvature and the tooth size), so the normal approach of
the two surfaces at a point is the sum of the two half-space displacements, which only
depends on the combined (plane-strain) modulus ``E*``.

Sources:

* Boussinesq point force on a half-space, surface displacement ``u_z = P / (pi E* r)``
  and stresses: Johnson, *Contact Mechanics* (1985), §3.2, Eq. (3.3); Cartesian
  components: Timoshenko & Goodier, *Theory of Elasticity* (3rd ed. 1970), §138.
* Uniform pressure on a rectangle, surface displacement: Love (1929), Phil. Trans. R.
  Soc. A 228, 377-420; Johnson (1985) §3.3.
* Combined modulus ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2``: Johnson (1985) §4.2.

Everything is SI: lengths in m, forces in N, pressures and stresses in Pa. Stresses are
positive in tension (compression negative); the depth ``z`` is positive into the body.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import minimize_scalar

from ..errors import ReducerlabError

__all__ = [
    "combined_modulus",
    "influence_matrix",
    "max_subsurface_von_mises",
    "rectangle_influence",
    "subsurface_stress",
    "von_mises",
]

Array = NDArray[np.float64]

#: Beyond ``FAR_FIELD * max(a, b)`` from the centre of a rectangle, its influence is
#: taken from the multipole expansion of ``1/r`` to fourth order (relative error below
#: 6e-8 there, checked against the closed form in the tests); nearer, the closed form.
FAR_FIELD = 12.0

#: Kernel evaluations per block of the subsurface-stress sum: bounds the memory to a few
#: arrays of this many float64 values (1 MB each) and keeps them in cache.
_STRESS_BLOCK = 131_072


# --------------------------------------------------------------------------- checks
def _array(name: str, value: ArrayLike, *, ndim: int | None = None) -> Array:
    """``value`` as a finite float array, or a :class:`ReducerlabError` naming ``name``."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ReducerlabError(f"{name} must be numeric, got {value!r:.80}") from exc
    if ndim is not None and arr.ndim != ndim:
        raise ReducerlabError(f"{name} must be a {ndim}-D array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ReducerlabError(f"{name} must be finite (no NaN or inf)")
    return arr


def _positive(name: str, value: ArrayLike, *, ndim: int | None = None) -> Array:
    arr = _array(name, value, ndim=ndim)
    if not np.all(arr > 0):
        raise ReducerlabError(f"{name} must be > 0, got minimum {np.min(arr):.6g}")
    return arr


def _scalar(name: str, value: float) -> float:
    arr = _array(name, value)
    if arr.ndim != 0:
        raise ReducerlabError(f"{name} must be a scalar, got shape {arr.shape}")
    return float(arr)


def _poisson(nu: float) -> float:
    nu = _scalar("nu", nu)
    if not -1.0 < nu <= 0.5:
        raise ReducerlabError(f"Poisson's ratio nu must be in (-1, 0.5], got {nu!r}")
    return nu


def _shape(name: str, arr: Array, shape: tuple[int, ...]) -> None:
    if arr.shape != shape:
        raise ReducerlabError(f"{name} must have shape {shape}, got {arr.shape}")


# ------------------------------------------------------------------ surface compliance
def combined_modulus(E1: float, nu1: float, E2: float, nu2: float) -> float:
    """Combined (contact) modulus ``E*`` of two elastic bodies (Pa).

    ``1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2`` (Johnson, Contact Mechanics (1985), §4.2).

    Parameters
    ----------
    E1, E2 : float
        Young's moduli of the two bodies (Pa), > 0.
    nu1, nu2 : float
        Poisson's ratios, in (-1, 0.5].

    Returns
    -------
    float
        ``E*`` (Pa).
    """
    E1 = _scalar("E1", E1)
    E2 = _scalar("E2", E2)
    for name, E in (("E1", E1), ("E2", E2)):
        if not E > 0:
            raise ReducerlabError(f"{name} must be > 0 Pa, got {E!r}")
    for name, nu in (("nu1", nu1), ("nu2", nu2)):
        v = _scalar(name, nu)
        if not -1.0 < v <= 0.5:
            raise ReducerlabError(f"{name} must be in (-1, 0.5], got {v!r}")
    nu1, nu2 = float(nu1), float(nu2)
    return 1.0 / ((1.0 - nu1**2) / E1 + (1.0 - nu2**2) / E2)


def _rect_exact(dx: Array, dy: Array, a: Array, b: Array) -> Array:
    """Closed form ``int int dxi deta / r`` over ``|xi| <= a, |eta| <= b`` at (dx, dy).

    With the primitive ``G(x, y) = x asinh(y/|x|) + y asinh(x/|y|)`` of ``1/r``
    (``d2G/dxdy = 1/sqrt(x^2 + y^2)``, ``0 asinh(.../0) = 0``) the integral is
    ``G(x2, y2) - G(x1, y2) - G(x2, y1) + G(x1, y1)``, ``x1,2 = |dx| -+ a`` etc. (Love
    1929). ``asinh`` has no cancellation for either sign, so the self term and points on
    the extension of an edge are exact.
    """
    dx = np.abs(dx)
    dy = np.abs(dy)
    x2 = dx + a  # > 0
    y2 = dy + b  # > 0
    x1 = dx - a
    y1 = dy - b
    ix2 = 1.0 / x2
    iy2 = 1.0 / y2
    ax1 = np.abs(x1)
    ay1 = np.abs(y1)
    ix1 = np.divide(1.0, ax1, out=np.zeros_like(ax1), where=ax1 > 0)
    iy1 = np.divide(1.0, ay1, out=np.zeros_like(ay1), where=ay1 > 0)
    out = x2 * np.arcsinh(y2 * ix2) + y2 * np.arcsinh(x2 * iy2)
    out -= x1 * np.arcsinh(y2 * ix1) + y2 * np.arcsinh(x1 * iy2)
    out -= x2 * np.arcsinh(y1 * ix2) + y1 * np.arcsinh(x2 * iy1)
    out += x1 * np.arcsinh(y1 * ix1) + y1 * np.arcsinh(x1 * iy1)
    return out


def _multipole_coefficients(a: Array, b: Array) -> tuple[Array, ...]:
    """Coefficients of :func:`_rect_multipole` for half sides ``a, b``."""
    a2 = a * a
    b2 = b * b
    a4 = a2 * a2
    b4 = b2 * b2
    ab = a2 * b2
    return (
        4.0 * a * b,
        (2.0 * b2 - a2) / 6.0,
        0.5 * (a2 - b2),
        (1.8 * a4 - 8.0 * ab + 4.8 * b4) / 24.0,
        (-18.0 * a4 + 70.0 * ab - 24.0 * b4) / 24.0,
        (21.0 * a4 - 70.0 * ab + 21.0 * b4) / 24.0,
    )


def _rect_multipole(x2: Array, r2: Array, coef: tuple[Array, ...]) -> Array:
    """Fourth-order multipole expansion of ``int int dxi deta / r`` (far field).

    ``4ab [1/r + (<xi^2> d_xx + <eta^2> d_yy)(1/r)/2 + (<xi^4> d_xxxx + 6 <xi^2 eta^2>
    d_xxyy + <eta^4> d_yyyy)(1/r)/24]`` with the moments ``a^2/3, b^2/3, a^4/5, a^2b^2/9,
    b^4/5`` of the rectangle and the in-plane derivatives of ``1/r`` (z = 0), e.g.
    ``d_xx (1/r) = (3c - 1)/r^3``, ``d_xxxx (1/r) = 3 (35 c^2 - 30 c + 3)/r^5``,
    ``d_xxyy (1/r) = (105 c (1 - c) - 12)/r^5`` with ``c = x^2/r^2``; collected as
    ``4ab/r [1 + (b0 + b1 c)/r^2 + (a0 + a1 c + a2 c^2)/r^4]`` (``coef`` from
    :func:`_multipole_coefficients`). Arguments: ``x2 = dx^2``, ``r2 = dx^2 + dy^2``.
    """
    k, b0, b1, a0, a1, a2 = coef
    ir2 = 1.0 / r2
    c = x2 * ir2
    t4 = a2 * c
    t4 += a1
    t4 *= c
    t4 += a0
    t4 *= ir2
    t2 = b1 * c
    t2 += b0
    t4 += t2
    t4 *= ir2
    t4 += 1.0
    t4 *= np.sqrt(ir2)
    t4 *= k
    return t4


def _rect(dx: Array, dy: Array, a: Array, b: Array) -> Array:
    """Rectangle factor: closed form within ``FAR_FIELD max(a, b)``, multipole beyond.

    ``dx, dy`` of shape (m, n) or (n,), ``a, b`` of shape (n,) (one per column).
    """
    x2 = dx * dx
    r2 = dy * dy
    r2 += x2
    lim = FAR_FIELD * np.maximum(a, b)
    near = np.flatnonzero(r2 < lim * lim)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = _rect_multipole(x2, r2, _multipole_coefficients(a, b))
    if near.size:
        col = near % a.size
        out.flat[near] = _rect_exact(dx.flat[near], dy.flat[near], a[col], b[col])
    return out


def rectangle_influence(dx: ArrayLike, dy: ArrayLike, a: ArrayLike, b: ArrayLike) -> Array:
    """Surface displacement factor of a uniformly loaded rectangle on a half-space.

    A pressure ``p`` (Pa) uniform over ``|x| <= a, |y| <= b`` on a half-space of
    combined modulus ``E*`` displaces the surface point ``(dx, dy)`` normally by
    ``u = p f / (pi E*)`` with (Boussinesq's point force ``u = P/(pi E* r)``,
    Johnson 1985 §3.2, integrated over the rectangle: Love 1929; Johnson 1985 §3.3)

    ``f = int int dxi deta / sqrt((dx - xi)^2 + (dy - eta)^2)``
    ``  = sum over corners (x, y) of +-[x asinh(y/|x|) + y asinh(x/|y|)]``,

    ``x = dx +- a``, ``y = dy +- b``. At the centre ``f = 4 [a asinh(b/a) + b asinh(a/b)]``
    (a square of side ``2a``: ``8 a ln(1 + sqrt 2)``). Beyond ``12 max(a, b)`` the
    fourth-order multipole expansion is used (relative error < 6e-8; it avoids the
    cancellation of the four corner terms far away).

    Parameters
    ----------
    dx, dy : array_like
        Offsets of the field point from the centre of the rectangle (m), broadcastable.
    a, b : array_like
        Half sides along x and y (m), > 0, broadcastable with ``dx, dy``.

    Returns
    -------
    ndarray
        ``f`` (m), the broadcast shape of the inputs.
    """
    dx = _array("dx", dx)
    dy = _array("dy", dy)
    a = _positive("a", a)
    b = _positive("b", b)
    try:
        dx, dy, a, b = np.broadcast_arrays(dx, dy, a, b)
    except ValueError as exc:
        raise ReducerlabError(
            f"dx, dy, a, b must be broadcastable, got shapes {dx.shape}, {dy.shape}, "
            f"{a.shape}, {b.shape}"
        ) from exc
    shape = dx.shape
    out = _rect(*(np.ravel(v).astype(float) for v in (dx, dy, a, b)))
    return out.reshape(shape)


def influence_matrix(
    points: ArrayLike,
    axes_u: ArrayLike,
    axes_v: ArrayLike,
    half_u: ArrayLike,
    half_v: ArrayLike,
    E_star: float,
    same_body: ArrayLike | None = None,
) -> Array:
    """Compliance matrix of ``N`` rectangular cells on a half-space (m/N).

    Entry ``(i, j)`` is the normal approach at the centre of cell ``i`` per unit force
    (1 N) spread uniformly over cell ``j``:

    ``C_ij = f(dx_ij, dy_ij, a_j, b_j) / (pi E* 4 a_j b_j)``,

    ``f`` of :func:`rectangle_influence` (Love 1929), with ``(dx_ij, dy_ij)`` the
    projection of ``d = points[i] - points[j]`` on the axes of cell ``j``, stretched to
    the chord length ``|d|`` (exact for a plane grid, where the stretch is 1; on a gently
    curved surface of radius ``R`` the stretch is ``1 + O((|d|/R)^2)``, and it keeps
    a distant cell whose offset is mostly along the normal from being treated as a
    near one). The half-space idealisation itself is the approximation on a curved
    surface. The result is symmetrised, ``(C + C^T)/2``, since ``f`` is not exactly
    reciprocal between cells of unequal size.

    Parameters
    ----------
    points : array_like, shape (N, 3)
        Cell centres (m).
    axes_u, axes_v : array_like, shape (N, 3)
        Orthonormal in-plane axes of each cell (unit vectors, checked to 1e-6).
    half_u, half_v : array_like, shape (N,)
        Half sides of each cell along ``axes_u`` and ``axes_v`` (m), > 0.
    E_star : float
        Combined modulus ``E*`` (Pa), see :func:`combined_modulus`.
    same_body : array_like of int, shape (N,), optional
        Labels of the half-space each cell belongs to (e.g. the tooth pair): entries
        between cells of different labels are 0.

    Returns
    -------
    ndarray, shape (N, N)
        Symmetric compliance matrix (m/N), positive entries within a body.

    Notes
    -----
    Cost: ``N^2`` entries by a compiled kernel, in parallel over the rows
    (``contact.kernels.half_space_block``; the closed form only within ``12`` half
    sides, the multipole expansion beyond; entries between bodies are skipped).
    """
    P = _array("points", points, ndim=2)
    if P.shape[1:] != (3,) or P.shape[0] < 1:
        raise ReducerlabError(f"points must have shape (N, 3) with N >= 1, got {P.shape}")
    n = P.shape[0]
    U = _array("axes_u", axes_u)
    V = _array("axes_v", axes_v)
    _shape("axes_u", U, (n, 3))
    _shape("axes_v", V, (n, 3))
    hu = _positive("half_u", half_u)
    hv = _positive("half_v", half_v)
    _shape("half_u", hu, (n,))
    _shape("half_v", hv, (n,))
    E_star = _scalar("E_star", E_star)
    if not E_star > 0:
        raise ReducerlabError(f"E_star must be > 0 Pa, got {E_star!r}")
    for name, ax in (("axes_u", U), ("axes_v", V)):
        bad = np.abs(np.einsum("ij,ij->i", ax, ax) - 1.0) > 2e-6
        if bad.any():
            raise ReducerlabError(
                f"{name} must hold unit vectors; row {int(np.argmax(bad))} has length "
                f"{np.linalg.norm(ax[np.argmax(bad)]):.6g}"
            )
    ortho = np.abs(np.einsum("ij,ij->i", U, V)) > 1e-6
    if ortho.any():
        raise ReducerlabError(
            f"axes_u and axes_v must be orthogonal; row {int(np.argmax(ortho))} has "
            f"u.v = {float(U[np.argmax(ortho)] @ V[np.argmax(ortho)]):.3g}"
        )
    labels = None
    if same_body is not None:
        labels = np.asarray(same_body)
        if labels.shape != (n,):
            raise ReducerlabError(f"same_body must have shape ({n},), got {labels.shape}")
        if labels.dtype.kind not in "iub":
            raise ReducerlabError(f"same_body must hold integer labels, got dtype {labels.dtype}")

    from .kernels import half_space_block

    # centred to keep round-off small in dx_ij = p_i . u_j - p_j . u_j
    Pc = np.ascontiguousarray(P - P.mean(axis=0))
    scale = 1.0 / (math.pi * E_star * 4.0 * hu * hv)  # f -> m/N per column j
    body = np.zeros(n, np.int64) if labels is None else labels.astype(np.int64)
    C = half_space_block(
        Pc, np.ascontiguousarray(U), np.ascontiguousarray(V), hu, hv, scale, body, FAR_FIELD
    )
    return C


# ------------------------------------------------------------------ subsurface stress
def _point_force_sums(
    ex: Array, ey: Array, ez: Array, sx: Array, sy: Array, force: Array, nu: float
) -> Array:
    """Stress (Pa) at points ``(ex, ey, ez)`` (M,) from normal point forces ``force``
    (N, compressive positive) at surface points ``(sx, sy)`` (S,), shape (M, 3, 3).

    Boussinesq (Johnson 1985 §3.2, Eq. 3.3; Timoshenko & Goodier §138) in Cartesian
    components, with ``x, y`` the offsets from the force, ``rho^2 = x^2 + y^2 + z^2`` and
    forms free of ``1/r`` (``r^2 = x^2 + y^2``):

    ``sigma_x = P/(2 pi) [(1 - 2nu)(B + Q x^2) - 3 z x^2 / rho^5]`` (y alike),
    ``tau_xy = P/(2 pi) [(1 - 2nu) Q x y - 3 x y z / rho^5]``,
    ``sigma_z = -3 P z^3 / (2 pi rho^5)``, ``tau_xz = -3 P x z^2 / (2 pi rho^5)``,

    ``B = z/rho^3 - 1/(rho (rho + z))`` (``(1 - 2nu) B`` is the hoop term ``sigma_theta``
    and ``B + Q r^2`` the radial one), ``Q = (2 rho + z) / (rho^3 (rho + z)^2)``.

    Only the scalar kernels ``W = (1 - 2nu) Q - 3z/rho^5``, ``T = 3z/rho^5`` and ``B`` are
    formed per (point, force) pair; the polynomial factors ``x^2 = ex^2 - 2 ex sx + sx^2``
    etc. are applied through the force moments ``sum P sx^i sy^j`` (matrix products).
    """
    c = 1.0 - 2.0 * nu
    # centre the frame on the forces (keeps the moment expansion free of cancellation)
    x0, y0 = float(np.mean(sx)), float(np.mean(sy))
    sx = sx - x0
    sy = sy - y0
    ex = ex - x0
    ey = ey - y0
    w = force / (2.0 * math.pi)
    mom = np.column_stack([w, w * sx, w * sy, w * sx * sx, w * sy * sy, w * sx * sy])
    s2 = sx * sx + sy * sy
    S2 = np.column_stack([sx, sy])
    out = np.empty((ex.size, 3, 3))
    rows = max(1, _STRESS_BLOCK // max(1, sx.size))
    for i0 in range(0, ex.size, rows):
        i1 = min(ex.size, i0 + rows)
        bx, by, bz = ex[i0:i1], ey[i0:i1], ez[i0:i1]
        z = bz[:, None]
        # rho^2 = |e|^2 + |s|^2 - 2 e.s + z^2 (z > 0 dominates the round-off of r^2)
        rho2 = np.column_stack([bx, by]) @ S2.T
        rho2 *= -2.0
        rho2 += s2
        rho2 += (bx * bx + by * by + bz * bz)[:, None]
        np.maximum(rho2, z * z, out=rho2)  # r^2 >= 0 despite round-off
        rho = np.sqrt(rho2)
        irho3 = 1.0 / rho2
        irho3 /= rho  # 1/rho^3
        ipz = rho + z
        B = rho * ipz  # rho (rho + z)
        np.reciprocal(B, out=B)
        np.reciprocal(ipz, out=ipz)  # 1/(rho + z)
        T = irho3 / rho2
        T *= 3.0 * z  # 3 z/rho^5
        B = np.subtract(z * irho3, B, out=B)  # z/rho^3 - 1/(rho (rho + z))
        W = 2.0 * rho
        W += z
        W *= irho3
        W *= ipz
        W *= ipz
        W *= c
        W -= T  # (1 - 2nu) Q - 3 z/rho^5
        mw = W @ mom  # sums of W P sx^i sy^j
        mt = T @ mom[:, :3]
        mb = B @ w
        sxx = bx * bx * mw[:, 0] - 2.0 * bx * mw[:, 1] + mw[:, 3]
        syy = by * by * mw[:, 0] - 2.0 * by * mw[:, 2] + mw[:, 4]
        sxy = bx * by * mw[:, 0] - bx * mw[:, 2] - by * mw[:, 1] + mw[:, 5]
        blk = out[i0:i1]
        blk[:, 0, 0] = sxx + c * mb
        blk[:, 1, 1] = syy + c * mb
        blk[:, 2, 2] = -bz * bz * mt[:, 0]
        blk[:, 0, 1] = blk[:, 1, 0] = sxy
        blk[:, 0, 2] = blk[:, 2, 0] = -bz * (bx * mt[:, 0] - mt[:, 1])
        blk[:, 1, 2] = blk[:, 2, 1] = -bz * (by * mt[:, 0] - mt[:, 2])
    return out


def _cells(
    points_xy: ArrayLike, half_u: ArrayLike, half_v: ArrayLike, pressure: ArrayLike
) -> tuple[Array, Array, Array, Array]:
    C = _array("points_xy", points_xy, ndim=2)
    if C.shape[1:] != (2,) or C.shape[0] < 1:
        raise ReducerlabError(f"points_xy must have shape (N, 2) with N >= 1, got {C.shape}")
    n = C.shape[0]
    hu = _positive("half_u", half_u)
    hv = _positive("half_v", half_v)
    p = _array("pressure", pressure)
    _shape("half_u", hu, (n,))
    _shape("half_v", hv, (n,))
    _shape("pressure", p, (n,))
    return C, hu, hv, p


def _sources(C: Array, hu: Array, hv: Array, p: Array, quad: int) -> tuple[Array, Array, Array]:
    """Gauss points (x, y) and their forces (N) of the loaded cells."""
    keep = p != 0
    C, hu, hv, p = C[keep], hu[keep], hv[keep], p[keep]
    g, wg = np.polynomial.legendre.leggauss(quad)
    gx, gy = np.meshgrid(g, g, indexing="ij")
    ww = np.outer(wg, wg).ravel()
    sx = (C[:, 0:1] + hu[:, None] * gx.ravel()).ravel()
    sy = (C[:, 1:2] + hv[:, None] * gy.ravel()).ravel()
    f = ((p * hu * hv)[:, None] * ww).ravel()
    return sx, sy, f


def subsurface_stress(
    points_xy: ArrayLike,
    half_u: ArrayLike,
    half_v: ArrayLike,
    pressure: ArrayLike,
    eval_xyz: ArrayLike,
    nu: float,
    quad: int = 3,
) -> Array:
    """Stress tensor in a half-space under uniformly loaded rectangular cells (Pa).

    The half-space is ``z >= 0`` (depth ``z`` positive into the body); cell ``j`` is the
    axis-aligned rectangle of centre ``points_xy[j]`` and half sides ``half_u[j]`` (x),
    ``half_v[j]`` (y) carrying the uniform pressure ``pressure[j]`` (Pa, compressive
    positive). The Boussinesq point-force stresses (Johnson 1985 §3.2, Eq. 3.3; in
    Cartesian components Timoshenko & Goodier 1970 §138) are integrated over each cell
    with a ``quad x quad`` Gauss-Legendre rule.

    Accuracy: the rule integrates a kernel that varies on the scale of the depth ``z``,
    so its error falls fast with ``z`` over the cell size ``h = 2 max(half_u, half_v)``:
    with 3x3 points, about 2e-3 of the local stress at ``z = h`` and 4e-6 at ``z = 2h``,
    but 5 % at ``z = h/2`` and worse above (measured against the closed form under a
    uniformly loaded rectangle, see the tests). Nearer the surface than one cell size use
    a finer grid or a higher ``quad``.

    Parameters
    ----------
    points_xy : array_like, shape (N, 2)
        Cell centres (m).
    half_u, half_v : array_like, shape (N,)
        Half sides along x and y (m), > 0.
    pressure : array_like, shape (N,)
        Uniform pressure on each cell (Pa); cells with zero pressure are skipped.
    eval_xyz : array_like, shape (..., 3)
        Evaluation points ``(x, y, z)`` (m), ``z > 0``.
    nu : float
        Poisson's ratio of the body, in (-1, 0.5].
    quad : int, optional
        Gauss points per cell direction (default 3).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Stress tensors (Pa), tension positive.

    Notes
    -----
    The sum runs in blocks of about 1e6 kernel evaluations (memory ~10 arrays of that
    size); the cost is ``M N quad^2`` kernel evaluations.
    """
    C, hu, hv, p = _cells(points_xy, half_u, half_v, pressure)
    E = _array("eval_xyz", eval_xyz)
    if E.ndim < 1 or E.shape[-1] != 3:
        raise ReducerlabError(f"eval_xyz must have shape (..., 3), got {E.shape}")
    if not np.all(E[..., 2] > 0):
        raise ReducerlabError(
            "eval_xyz depths z (last column) must be > 0 m; the Gauss rule does not "
            "resolve the surface"
        )
    nu = _poisson(nu)
    if isinstance(quad, bool) or not isinstance(quad, int | np.integer) or quad < 1:
        raise ReducerlabError(f"quad must be an integer >= 1, got {quad!r}")
    shape = E.shape[:-1]
    E = E.reshape(-1, 3)
    sx, sy, f = _sources(C, hu, hv, p, int(quad))
    if sx.size == 0:
        return np.zeros((*shape, 3, 3))
    out = _point_force_sums(E[:, 0], E[:, 1], E[:, 2], sx, sy, f, nu)
    return out.reshape(*shape, 3, 3)


def von_mises(stress: ArrayLike) -> Array:
    """Von Mises equivalent stress of stress tensors (Pa).

    ``sigma_vM = sqrt(((s11 - s22)^2 + (s22 - s33)^2 + (s33 - s11)^2)/2
    + 3 (s12^2 + s23^2 + s13^2))``.

    Parameters
    ----------
    stress : array_like, shape (..., 3, 3)
        Stress tensors (Pa); only the upper triangle is read.

    Returns
    -------
    ndarray, shape (...)
        Equivalent stress (Pa), >= 0.
    """
    S = _array("stress", stress)
    if S.ndim < 2 or S.shape[-2:] != (3, 3):
        raise ReducerlabError(f"stress must have shape (..., 3, 3), got {S.shape}")
    s11, s22, s33 = S[..., 0, 0], S[..., 1, 1], S[..., 2, 2]
    s12, s23, s13 = S[..., 0, 1], S[..., 1, 2], S[..., 0, 2]
    return np.sqrt(
        0.5 * ((s11 - s22) ** 2 + (s22 - s33) ** 2 + (s33 - s11) ** 2)
        + 3.0 * (s12**2 + s23**2 + s13**2)
    )


def max_subsurface_von_mises(
    points_xy: ArrayLike,
    half_u: ArrayLike,
    half_v: ArrayLike,
    pressure: ArrayLike,
    nu: float,
    depths: ArrayLike | None = None,
) -> tuple[float, float, tuple[float, float]]:
    """Largest von Mises stress under a loaded area and where it is.

    The search evaluates :func:`subsurface_stress` (3x3 Gauss rule) under the centres of
    the cells that carry the largest pressures (``p >= 0.5 max p``, the 200 largest at
    most) at the given depths, then refines the depth of the best point with a bounded
    scalar minimisation (:func:`scipy.optimize.minimize_scalar`, between the
    neighbouring grid depths). The default depths are 40, evenly from
    ``max(0.05 r_eq, h)`` to ``max(1.5 r_eq, 2 max(0.05 r_eq, h))``, with the equivalent
    contact radius ``r_eq = sqrt(loaded area / pi)`` and the largest loaded cell size
    ``h``: the layer shallower than one cell is not searched because the Gauss rule does
    not resolve it. (Hertz maxima of frictionless contacts lie at 0.48 ``a`` for a circle
    and 0.70 ``b`` for a line contact, ``nu = 0.3``; Johnson 1985 §4.2-4.3.)

    Accuracy: the depth is converged to ``1e-6 r_eq`` and the value to round-off of the
    discretised field there (a smooth maximum). Laterally the maximum is sought only at
    cell centres, so its location is known to half a cell spacing and the value, being
    stationary, to second order in that offset. The stress field itself is that of the
    piecewise-uniform pressure with the Gauss-rule error of :func:`subsurface_stress`
    (about 2e-3 at one cell size deep, 4e-6 at two). For a Hertz contact with 6 to 14
    cells per semi-axis the value and depth agree with the closed form to 0.1 % (see
    the tests).

    Parameters
    ----------
    points_xy, half_u, half_v, pressure
        The loaded cells, as in :func:`subsurface_stress` (m, m, m, Pa).
    nu : float
        Poisson's ratio, in (-1, 0.5].
    depths : array_like, optional
        Depths of the search grid (m), > 0, increasing.

    Returns
    -------
    value : float
        Maximum von Mises stress (Pa).
    depth : float
        Its depth (m).
    location : tuple of float
        Its ``(x, y)`` (m): a cell centre.
    """
    C, hu, hv, p = _cells(points_xy, half_u, half_v, pressure)
    nu = _poisson(nu)
    loaded = p > 0
    if not loaded.any():
        raise ReducerlabError("pressure must have at least one positive entry (a loaded cell)")
    r_eq = math.sqrt(float(np.sum(4.0 * hu[loaded] * hv[loaded])) / math.pi)
    if depths is None:
        cell = 2.0 * float(np.max(np.maximum(hu[loaded], hv[loaded])))
        z_lo = max(0.05 * r_eq, cell)
        z = np.linspace(z_lo, max(1.5 * r_eq, 2.0 * z_lo), 40)
    else:
        z = _positive("depths", depths, ndim=1)
        if z.size < 1 or np.any(np.diff(z) <= 0):
            raise ReducerlabError("depths must be a non-empty increasing 1-D array")
    pmax = float(p.max())
    cand = np.flatnonzero(p >= 0.5 * pmax)
    cand = cand[np.argsort(-p[cand], kind="stable")[:200]]
    sx, sy, f = _sources(C, hu, hv, p, 3)
    ex = np.repeat(C[cand, 0], z.size)
    ey = np.repeat(C[cand, 1], z.size)
    ez = np.tile(z, cand.size)
    vm = von_mises(_point_force_sums(ex, ey, ez, sx, sy, f, nu)).reshape(cand.size, z.size)
    i, k = np.unravel_index(int(np.argmax(vm)), vm.shape)
    x0, y0 = float(C[cand[i], 0]), float(C[cand[i], 1])
    best, zbest = float(vm[i, k]), float(z[k])
    lo = z[k - 1] if k > 0 else z[k]
    hi = z[k + 1] if k < z.size - 1 else z[k]
    if hi > lo:

        def neg(zz: float) -> float:
            s = _point_force_sums(np.array([x0]), np.array([y0]), np.array([zz]), sx, sy, f, nu)
            return -float(von_mises(s)[0])

        res = minimize_scalar(
            neg, bounds=(lo, hi), method="bounded", options={"xatol": 1e-6 * r_eq}
        )
        if -res.fun > best:
            best, zbest = -float(res.fun), float(res.x)
    return best, zbest, (x0, y0)
