"""Guards of every nonlinear run: the linear stability check before integrating, the
state bounds that stop a diverging member while integrating (and the message naming
the DOFs that diverged), and random starts around the static equilibrium."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..errors import DivergenceError, ModelError
from ..model import NonlinearSystem
from ..model.laws import flat_peak
from ..model.system import describe_dofs
from .coordinates import static_states
from .systems import mass_problem

__all__ = [
    "BOUND_FACTOR",
    "SEED_SPREAD",
    "STRAIN_TOL",
    "check_stability",
    "member_label",
    "raise_diverged",
    "seed_states",
    "state_bounds",
]


#: Default state bound of :func:`ensemble`: a state component beyond ``BOUND_FACTOR``
#: times the displacement scale of its member (see :func:`state_bounds`) stops the run.
BOUND_FACTOR = 1e6


def state_bounds(
    systems: Sequence[NonlinearSystem],
    y0: NDArray[np.float64] | None,
    period: NDArray[np.float64],
    factor: float = BOUND_FACTOR,
) -> NDArray[np.float64]:
    """Default bounds ``(E, 2n)`` of the state components, the rule of :func:`ensemble`.

    For each member the displacement scale ``d`` (in the system's coordinates: metres
    or radians, or mass-weighted modal amplitudes after rigid-motion removal) is the
    largest of

    * the static deflection under the peak loads with the mean mesh stiffness,
      ``max_i sum_j |(K_mean^-1 B)_ij| F_peak_j`` (``F_peak``: an upper bound of each
      load law's magnitude);
    * the largest initial displacement ``max_i |q0_i|``;
    * the clearance of each mesh line, ``(b_m + e_peak_m) / max_i |G_mi|`` (half backlash
      plus peak transmission error, over the line's largest projection coefficient);

    a displacement component beyond ``factor * d`` (default ``1e6 d``), or a velocity
    component beyond ``factor * d * w`` with ``w`` the larger of the highest natural
    frequency (rad/s) of the mean system and the forcing frequency ``2 pi / T``, is a
    divergence. A member with ``d = 0`` (no load, no clearance, at rest) is bounded only
    by overflow (inf).
    """
    E, n = len(systems), systems[0].n
    K = np.stack([s.mean_stiffness for s in systems])
    B = np.stack([s.load_matrix for s in systems])
    out = np.full((E, 2 * n), math.inf)
    for e, s in enumerate(systems):
        f_peak = np.array([flat_peak(int(k), p) for k, p in zip(s.f_kind, s.f_params,
                                                                  strict=True)])  # fmt: skip
        d = 0.0
        if f_peak.size and np.any(f_peak):
            KiB = np.linalg.pinv(K[e]) @ B[e]
            d = float(np.max(np.abs(KiB) @ f_peak))
        if y0 is not None:
            d = max(d, float(np.max(np.abs(y0[e, :n]))))
        for m in range(s.G.shape[0]):
            g = float(np.abs(s.G[m]).max())
            if g > 0:
                clear = s.half_backlash[m] + flat_peak(int(s.e_kind[m]), s.e_params[m])
                d = max(d, float(clear) / g)
        if not (d > 0 and math.isfinite(d)):
            continue
        Lc = np.linalg.cholesky(s.M)
        A = np.linalg.solve(Lc, np.linalg.solve(Lc, K[e]).T)
        w = max(math.sqrt(max(float(np.linalg.eigvalsh(0.5 * (A + A.T)).max()), 0.0)),
                2 * math.pi / float(period[e]))  # fmt: skip
        out[e, :n] = factor * d
        out[e, n:] = factor * d * w
    return out


#: Spread of the random starts of :func:`seed_states`, in displacement scales.
SEED_SPREAD = 1.0


def seed_states(
    systems: Sequence[NonlinearSystem],
    period: NDArray[np.float64],
    rngs: Sequence[np.random.Generator],
) -> NDArray[np.float64]:
    """Random initial states ``(E, 2n)`` around each member's static equilibrium, to
    look for coexisting attractors: displacements uniform within ``+-SEED_SPREAD d``
    (``d`` the displacement scale of :func:`state_bounds`: static deflection under the
    peak loads, or the mesh clearance), velocities within ``+-SEED_SPREAD d W`` (``W``
    the forcing frequency ``2 pi / period``); member ``e`` draws from ``rngs[e]``."""
    n = systems[0].n
    Y = static_states(systems)
    d = state_bounds(systems, None, period, factor=1.0)[:, :1]  # (E, 1)
    d = np.where(np.isfinite(d), d, 0.0)
    w = (2 * math.pi / np.asarray(period, float))[:, None]
    for e, rng in enumerate(rngs):
        u = rng.uniform(-1.0, 1.0, 2 * n)
        Y[e, :n] += SEED_SPREAD * d[e] * u[:n]
        Y[e, n:] += SEED_SPREAD * d[e] * w[e] * u[n:]
    return Y


#: Relative size of ``phi^T K phi`` against ``|phi|^T |K| |phi|`` below which a negative
#: eigenvalue is round-off of a rigid-body mode, not a divergent mode.
STRAIN_TOL = 1e-9


def member_label(labels: Sequence[str] | None, e: int, count: int) -> str:
    """`` for LABEL`` naming member ``e`` in a message (its label, else its index when
    there are several members, else nothing)."""
    label = labels[e] if labels is not None else (f"member {e}" if count > 1 else "")
    return f" for {label}" if label else ""


def check_stability(
    systems: Sequence[NonlinearSystem], labels: Sequence[str] | None = None
) -> NDArray[np.float64]:
    """Raise :class:`DivergenceError` when the linear part of a member has a divergent
    mode: a negative eigenvalue of ``K_mean phi = lambda M phi`` (mean mesh stiffness)
    whose strain energy is not round-off (``|phi^T K phi| > 1e-9 |phi|^T |K| |phi|``,
    robust to rigid-body modes) and that no hardening cubic line confines
    (``sum_m k3_m (G_m phi)^4 > 0``, the double well of a Duffing oscillator). The message
    names the member, the eigenvalue and the physical DOFs that dominate the mode.
    Members are checked together (batched Cholesky and ``eigh``). Returns the largest
    eigenvalue of each member (rad^2/s^2), from which the step is chosen.
    """
    if not systems:
        return np.empty(0)
    K = np.stack([s.mean_stiffness for s in systems])
    M = np.stack([s.M for s in systems])
    try:
        Lc = np.linalg.cholesky(0.5 * (M + np.swapaxes(M, 1, 2)))
    except np.linalg.LinAlgError:
        for s in systems:
            try:
                np.linalg.cholesky(s.M)
            except np.linalg.LinAlgError as exc:
                raise ModelError(mass_problem(s, exc)) from None
        raise
    A = np.linalg.solve(Lc, np.swapaxes(np.linalg.solve(Lc, K), 1, 2))
    lam, Y = np.linalg.eigh(0.5 * (A + np.swapaxes(A, 1, 2)))
    if not np.any(lam < 0):
        return lam[:, -1]
    phi = np.linalg.solve(np.swapaxes(Lc, 1, 2), Y)
    num = np.einsum("eim,eij,ejm->em", phi, K, phi)
    den = np.einsum("eim,eij,ejm->em", np.abs(phi), np.abs(K), np.abs(phi))
    k3 = np.stack([s.line_cubic for s in systems])  # (E, L)
    G = np.stack([s.G for s in systems])  # (E, L, n)
    Gp = np.einsum("eli,eim->elm", G, phi)
    quartic = np.einsum("el,elm->em", k3, Gp**4)
    quartic_abs = np.einsum("el,elm->em", np.abs(k3),
                            np.einsum("eli,eim->elm", np.abs(G), np.abs(phi)) ** 4)  # fmt: skip
    divergent = (lam < 0) & (np.abs(num) > STRAIN_TOL * den) & ~(quartic > 1e-9 * quartic_abs)
    bad = np.nonzero(divergent.any(axis=1))[0]
    if not bad.size:
        return lam[:, -1]
    e = int(bad[0])
    j = int(np.argmin(np.where(divergent[e], lam[e], np.inf)))
    s = systems[e]
    where = member_label(labels, e, len(systems))
    rate = math.sqrt(-float(lam[e, j]))
    dofs = describe_dofs(s.dominant_dofs(phi[e, :, j]))
    raise DivergenceError(
        f"the linear part of the model is unstable{where}: a divergent mode "
        f"(negative stiffness, eigenvalue {lam[e, j]:.4g} rad^2/s^2: any disturbance grows "
        f"as exp({rate:.4g} t/s)) of the DOF(s) {dofs}; a response would be meaningless. "
        "Check the stiffness acting on those DOFs (e.g. centripetal terms larger than the "
        "support and mesh stiffness: lower the speed or stiffen the supports)"
    )


def raise_diverged(
    systems: Sequence[NonlinearSystem],
    status: NDArray[np.float64],
    bounds: NDArray[np.float64],
    labels: Sequence[str] | None,
    steps: int,
) -> None:
    """Raise :class:`DivergenceError` for the first member the kernel stopped, naming
    the physical DOFs that dominate its motion at the time it left its bound."""
    bad = np.nonzero(status[:, 0])[0]
    if not bad.size:
        return
    e = int(bad[0])
    s = systems[e]
    n = s.n
    i = int(status[e, 2])
    y = status[e, 3 : 3 + 2 * n]
    part = y[:n] if i < n else y[n:]
    if not np.all(np.isfinite(part)) or not np.any(part):
        part = np.eye(n)[i % n]  # the coordinate that failed
    dofs = describe_dofs(s.dominant_dofs(part))
    kind = "displacement" if i < n else "velocity"
    where = member_label(labels, e, len(systems))
    bound = float(bounds[e, i])
    why = (
        f"left its bound ({bound:.3g} in the system's coordinates, see "
        "reducerlab.dynamics.guards.state_bounds)"
        if math.isfinite(bound) and np.isfinite(y[i])
        else "became non-finite (overflow or NaN)"
    )
    raise DivergenceError(
        f"integration diverged{where} at t = {status[e, 1]:.6g} s: the {kind} of the "
        f"motion, dominated by {dofs}, {why}. The motion is unbounded (an instability of "
        f"the nonlinear or time-varying system) or the step too long: check the "
        f"parameters, or give steps_per_period > {steps}"
    )
