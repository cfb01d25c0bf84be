"""Coordinates of the integrated system: rigid motion removed (elastic coordinates),
static equilibrium states, and paper 004's dimensionless form.

Models with rigid-body motion (a free drive train) are integrated in elastic
coordinates by default: ``q = S u`` with ``S`` the mass-normalised elastic modes of the
mean stiffness (the rigid motion, driven only by the net load, is removed, as paper
004 does with its relative coordinates).
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from ..errors import ModelError, ReducerlabError
from ..model import Model, NonlinearSystem, layout
from ..model.layout import LAW_FOURIER, LAW_PIECEWISE
from ..model.rigid import RIGID_TOL, check_resolved, element_blocks, strain_ratio
from .systems import at_rest, mass_problem

__all__ = [
    "dimensionless",
    "elastic_names",
    "rigid_reduction",
    "static_state",
    "static_states",
    "to_system",
]


def to_system(
    model: Model | NonlinearSystem,
    reduce_rigid: bool = True,
    *,
    flat: NonlinearSystem | None = None,
) -> NonlinearSystem:
    """The flat system to integrate, rigid motion removed unless ``reduce_rigid=False``.

    ``flat`` is ``model.nonlinear()`` when the caller has built it already."""
    s = model if not isinstance(model, Model) else flat or model.nonlinear()
    if not reduce_rigid:
        return s
    rest = at_rest(model) if isinstance(model, Model) else None
    blocks = element_blocks(model) if isinstance(model, Model) else None
    T = rigid_reduction(rest if rest is not None else s, blocks)
    if T is None:
        return s
    if T.shape[0] == 0:
        raise ReducerlabError(
            f"the model's DOFs {s.dof_names} move only as rigid bodies (no support, "
            "coupling or mesh resists any motion): there is no vibration to integrate"
        )
    # T is made of the model's own rigid modes: no need to test them (see reduced)
    return s.reduced(T, elastic_names(T), check=False)[0]


def rigid_reduction(
    s: NonlinearSystem, blocks: Sequence[tuple[list[int], NDArray]] | None = None
) -> NDArray[np.float64] | None:
    """Rows ``T`` (n - r, n) of the relative coordinates ``u = T q`` that remove the rigid
    motion of ``s`` (the mass-weighted elastic modes of the mean stiffness), or None
    when ``s`` has no rigid motion. For a model at speed pass its system at rest
    (:func:`at_rest`). Any ``T`` with the same null space serves another
    system of the same topology (see :meth:`NonlinearSystem.reduced`).

    A mode is rigid when it strains no element (``blocks``: the model's
    :func:`~reducerlab.model.rigid.element_blocks`, the test of ``modal``) or, without
    blocks, no stiffness beyond round-off (``|phi^T K phi| <= 1e-10 |phi|^T |K| |phi|``);
    an elastic mode below the eigen-solver's resolution is an error
    (:func:`~reducerlab.model.rigid.check_resolved`)."""
    k_mean = s.mean_stiffness
    try:
        lam, V = scipy.linalg.eigh(k_mean, s.M)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ModelError(mass_problem(s, exc)) from None
    if blocks is not None:
        rigid = strain_ratio(blocks, s.M, V) <= RIGID_TOL
    else:
        num = np.abs(np.einsum("im,ij,jm->m", V, k_mean, V))
        rigid = num <= RIGID_TOL * np.einsum("im,ij,jm->m", np.abs(V), np.abs(k_mean), np.abs(V))
    check_resolved(lam, rigid, s.M, k_mean, s.dof_names, "nonlinear run")
    if not rigid.any():
        return None
    return V[:, ~rigid].T @ s.M


def elastic_names(T: NDArray[np.float64]) -> list[str]:
    """Coordinate names of a reduction ``T``."""
    return [f"elastic_{i + 1}" for i in range(T.shape[0])]


def static_state(s: NonlinearSystem) -> NDArray[np.float64]:
    """State ``[q, 0]`` of static equilibrium under the loads at t = 0 with the mean mesh
    stiffness (backlash offsets ignored; power-law lines at their own law, beyond their
    backlash: :func:`_power_equilibrium`): a start that shortens the transient."""
    return static_states([s])[0]


def static_states(systems: Sequence[NonlinearSystem]) -> NDArray[np.float64]:
    """:func:`static_state` of every member (one batched solve), shape (E, 2n); a member
    whose mean stiffness is singular starts at rest."""
    if not systems:
        return np.empty((0, 0))
    K = np.stack([s.mean_stiffness for s in systems])
    F = np.stack([s.external_forces(0.0) for s in systems])
    try:
        q = np.linalg.solve(K, F[..., None])[..., 0]
    except np.linalg.LinAlgError:
        q = np.zeros_like(F)
        for e in range(len(systems)):
            with contextlib.suppress(np.linalg.LinAlgError):
                q[e] = np.linalg.solve(K[e], F[e])
    for e, s in enumerate(systems):
        if np.any(s.line_power[:, 0] != 1.0) and np.all(np.isfinite(q[e])):
            q[e] = _power_equilibrium(s, K[e], F[e], q[e])
    return np.concatenate([q, np.zeros_like(q)], axis=1)


def _power_equilibrium(s: NonlinearSystem, K: NDArray, F: NDArray, q: NDArray) -> NDArray:
    """Static equilibrium (m or rad) of a system with power-law lines
    (``model.system.power_force``, each line's mean stiffness law, beyond its backlash
    on the side the linear solution ``q`` loads) by damped Newton iteration from the
    lines' secant stiffness at their reference deflection; ``q`` itself where the
    iteration does not converge (it is only a start)."""
    from ..model.laws import flat_mean
    from ..model.system import power_force

    power = s.line_power[:, 0] != 1.0
    G = s.G[power]
    k = np.array([flat_mean(int(kd), p) for kd, p in zip(s.k_kind[power], s.k_params[power],
                                                         strict=True)])  # fmt: skip
    p, d = s.line_power[power, 0], s.line_power[power, 1]
    h = s.half_backlash[power]
    K_rest = K - G.T @ (G * k[:, None])  # the linear part without the power lines
    side = np.where(G @ q >= 0.0, 1.0, -1.0)

    def residual(x: NDArray) -> tuple[NDArray, NDArray]:
        f = G @ x - side * h
        f = np.where(f * side > 0.0, f, 0.0)  # apart: no force
        force = np.array([power_force(*a) for a in zip(k, f, p, d, strict=True)])
        slope = np.where(f != 0.0, k * (np.abs(f) / d) ** (p - 1.0), 0.0)
        return K_rest @ x + G.T @ force - F, np.maximum(slope, 1e-6 * k)

    # first guess: the lines at their secant stiffness at the reference deflection
    # (k / p) beyond their backlash, exact where the loads meet the reference
    k_sec = k / p
    try:
        x = np.linalg.solve(K_rest + G.T @ (G * k_sec[:, None]), F + G.T @ (k_sec * side * h))
    except np.linalg.LinAlgError:
        return q
    r, slope = residual(x)
    scale = np.abs(F).max() or 1.0
    for _ in range(50):
        if np.abs(r).max() <= 1e-12 * scale:
            return x
        try:
            dx = np.linalg.solve(K_rest + G.T @ (G * slope[:, None]), -r)
        except np.linalg.LinAlgError:
            return q
        t = 1.0
        while t > 1e-4:
            r_new, slope_new = residual(x + t * dx)
            if np.linalg.norm(r_new) < np.linalg.norm(r):
                break
            t *= 0.5
        else:
            return q
        x, r, slope = x + t * dx, r_new, slope_new
    return x if np.abs(r).max() <= 1e-8 * scale else q


def _scale_law(kind: int, p: NDArray, value: float, omega_n: float) -> NDArray:
    """Flat law ``v(t)`` -> ``value * v(tau / omega_n)`` in dimensionless time."""
    q = p.copy()
    if kind == layout.LAW_CONSTANT:
        q[layout.CONSTANT_VALUE] *= value
    elif kind == LAW_FOURIER:
        q[layout.FOURIER_MEAN] *= value
        q[layout.FOURIER_OMEGA] /= omega_n
        layout.amplitudes(q)[:] *= value
    elif kind == LAW_PIECEWISE:
        q[layout.PIECE_PERIOD] *= omega_n
        q[layout.PIECE_T0] *= omega_n
        layout.coefficients(q)[:] *= value
    return q


def dimensionless(
    s: NonlinearSystem, omega_n: float, length: float, mass: float
) -> NonlinearSystem:
    """The equations in paper 004's dimensionless form (Eq. 13-16).

    ``tau = omega_n t``, ``X = X / b_c`` (``length`` = b_c), masses by ``mass`` (paper
    004: ``M_VH``, with ``omega_n = sqrt(k_mean / M_VH)``): ``M/mass``,
    ``C/(mass omega_n)``, ``K/(mass omega_n^2)``, mesh stiffness ``k/(mass omega_n^2)``,
    mesh damping ``c/(mass omega_n)``, backlash and error ``/b_c``, loads
    ``F/(mass b_c omega_n^2)``, cubic line stiffness ``k3 b_c^2/(mass omega_n^2)``; law
    frequencies become ``omega/omega_n``. The solution is
    the dimensional one at ``t = tau / omega_n`` divided by ``b_c``.
    """
    for name, v in (("omega_n", omega_n), ("length", length), ("mass", mass)):
        if not (isinstance(v, int | float) and math.isfinite(v) and v > 0):
            raise ReducerlabError(f"dimensionless: {name} must be > 0, got {v!r}")
    w2 = mass * omega_n**2

    def laws(kinds: NDArray, params: NDArray, value: float) -> NDArray:
        rows = [_scale_law(k, p, value, omega_n) for k, p in zip(kinds, params, strict=True)]
        return np.array(rows).reshape(params.shape)

    return replace(
        s,
        M=s.M / mass,
        C=s.C / (mass * omega_n),
        K=s.K / w2,
        k_params=laws(s.k_kind, s.k_params, 1 / w2),
        line_damping=s.line_damping / (mass * omega_n),
        half_backlash=s.half_backlash / length,
        line_cubic=s.line_cubic * length**2 / w2,
        line_power=s.line_power * np.array([1.0, 1.0 / length]),
        e_params=laws(s.e_kind, s.e_params, 1 / length),
        f_params=laws(s.f_kind, s.f_params, 1 / (w2 * length)),
    )
