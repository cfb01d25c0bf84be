"""Time integration of a model's nonlinear equations of motion.

Two paths over the same :class:`~reducerlab.model.NonlinearSystem`:

* :func:`simulate_reference` — scipy ``solve_ivp`` (DOP853) restarted at every
  stiffness-law discontinuity and at every backlash boundary crossing (events on
  ``|delta| = b``), tolerances tight enough to serve as ground truth;
* :func:`simulate` / :func:`ensemble` — the compiled fixed-step RK4 kernel
  (:mod:`reducerlab.analysis.kernel`) for one system or an ensemble of systems that
  differ in parameter values, steps aligned with the law's discontinuities.

Models with rigid-body motion (a free drive train) are integrated in elastic
coordinates by default: ``q = S u`` with ``S`` the mass-normalised elastic modes of the
mean stiffness (the rigid motion, driven only by the net load, is removed, as paper
004 does with its relative coordinates).
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np
import scipy.integrate
import scipy.linalg
from numpy.typing import NDArray

from ..dynamics.steps import MAX_STEPS
from ..errors import DivergenceError, ModelError, ReducerlabError
from ..model import Model, NonlinearSystem
from ..model.laws import LAW_FOURIER, LAW_PIECEWISE, evaluate_flat, flat_peak, flat_period
from ..model.system import describe_dofs
from .modal import element_blocks

__all__ = [
    "BOUND_FACTOR",
    "MAX_STEPS",
    "Ensemble",
    "check_stability",
    "dimensionless",
    "ensemble",
    "forcing_period",
    "lyapunov",
    "seed_states",
    "simulate_reference",
    "state_bounds",
    "static_state",
    "static_states",
    "steps_for",
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


def at_rest(model: Model) -> NonlinearSystem | None:
    """The flat system of ``model`` at zero speed, or None when it runs at zero speed.

    Rigid-body motion is the motion that strains no element: the null space of the
    stiffness *without* speed-dependent terms. The centripetal and gyroscopic terms,
    linearised in a rotating frame, do not respect it (e.g. ``-m Omega^2`` on a
    tangential translation that is a pure phase shift of the rotating assembly), so
    they would turn a rigid mode into a slowly diverging one. As in
    :func:`reducerlab.analysis.modal.modal`, the rigid motion is taken from the model
    at rest and removed; the speed terms act on the elastic coordinates only.
    """
    if model.speed == 0.0:
        return None
    return model.with_speed(0.0).nonlinear()


def rigid_reduction(
    s: NonlinearSystem, blocks: Sequence[tuple[list[int], NDArray]] | None = None
) -> NDArray[np.float64] | None:
    """Rows ``T`` (n - r, n) of the relative coordinates ``u = T q`` that remove the rigid
    motion of ``s`` (the mass-weighted elastic modes of the mean stiffness), or None
    when ``s`` has no rigid motion. For a model at speed pass its system at rest
    (:func:`at_rest`). Any ``T`` with the same null space serves another
    system of the same topology (see :meth:`NonlinearSystem.reduced`).

    A mode is rigid when it strains no element (``blocks``: the model's
    :func:`~reducerlab.analysis.modal.element_blocks`, the test of ``modal``) or, without
    blocks, no stiffness beyond round-off (``|phi^T K phi| <= 1e-10 |phi|^T |K| |phi|``);
    an elastic mode below the eigen-solver's resolution is an error
    (:func:`~reducerlab.analysis.modal.check_resolved`)."""
    from .modal import RIGID_TOL, check_resolved, strain_ratio

    k_mean = s.mean_stiffness
    try:
        lam, V = scipy.linalg.eigh(k_mean, s.M)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ModelError(_mass_problem(s, exc)) from None
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


def _mass_problem(s: NonlinearSystem, exc: Exception | None = None) -> str:
    """Message for a mass matrix that the solvers cannot factorise, naming the DOF."""
    names, _, M = s.physical()
    d = np.diag(M)
    if np.any(~(d > 0)):
        bad = [names[i] for i in np.nonzero(~(d > 0))[0]]
        return (
            f"DOF(s) {bad} have no inertia, so the mass matrix is singular; add an "
            "Inertia element on each DOF (or remove the DOF)"
        )
    i, j = int(np.argmin(d)), int(np.argmax(d))
    return (
        f"the mass matrix is not positive definite to working precision ({exc}); the "
        f"inertias span {d[i]:.3g} ({names[i]}) to {d[j]:.3g} ({names[j]}) in SI: check "
        "for an extreme inertia value"
    )


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


def _member(labels: Sequence[str] | None, e: int, count: int) -> str:
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
                raise ModelError(_mass_problem(s, exc)) from None
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
    where = _member(labels, e, len(systems))
    rate = math.sqrt(-float(lam[e, j]))
    dofs = describe_dofs(s.dominant_dofs(phi[e, :, j]))
    raise DivergenceError(
        f"the linear part of the model is unstable{where}: a divergent mode "
        f"(negative stiffness, eigenvalue {lam[e, j]:.4g} rad^2/s^2: any disturbance grows "
        f"as exp({rate:.4g} t/s)) of the DOF(s) {dofs}; a response would be meaningless. "
        "Check the stiffness acting on those DOFs (e.g. centripetal terms larger than the "
        "support and mesh stiffness: lower the speed or stiffen the supports)"
    )


def static_state(s: NonlinearSystem) -> NDArray[np.float64]:
    """State ``[q, 0]`` of static equilibrium under the loads at t = 0 with the mean mesh
    stiffness (backlash offsets ignored): a start that shortens the transient."""
    return static_states([s])[0]


def forcing_period(s: NonlinearSystem) -> float:
    """Period (s) of the first time-varying mesh law (stiffness, then error), or of the
    first periodic load; the stroboscopic sampling period of Poincaré sections."""
    for kinds, params in ((s.k_kind, s.k_params), (s.e_kind, s.e_params), (s.f_kind, s.f_params)):
        for kind, p in zip(kinds, params, strict=True):
            period = flat_period(int(kind), p)
            if math.isfinite(period):
                return period
    raise ReducerlabError(
        "the model has no periodic law (constant mesh stiffness, no periodic error or "
        "load), so there is no forcing period to sample: give one (API: period=...; "
        "command line: --period '2 ms' or --frequency '500 Hz')"
    )


def _breaks(s: NonlinearSystem, T: float) -> NDArray[np.float64]:
    """Phases in [0, 1) of stiffness-law discontinuities within one forcing period."""
    out = [0.0]
    for kind, p in zip(s.k_kind, s.k_params, strict=True):
        if kind != LAW_PIECEWISE:
            continue
        P, t0, n = p[0], p[1], int(p[2])
        j = np.arange(math.floor(-t0 / P) - 1, math.ceil((T - t0) / P) + 1)
        times = (t0 + (j[:, None] + p[4 : 4 + n]) * P).ravel()
        out += list((times[(times >= 0) & (times < T)] / T).tolist())
    # exact phases (a rounded phase puts the step boundary beside the jump, and with
    # more than ~5000 steps per period the samples just inside a step then read the law
    # on the wrong side of it: a first-order error); phases closer than 1e-12 (the same
    # jump seen from two laws, or 1 - 1e-17 and 0) are one
    ph = np.sort(np.array(out))
    ph = ph[(ph >= 0) & (ph < 1 - 1e-12)]
    keep = np.concatenate([[True], np.diff(ph) > 1e-12])
    return ph[keep]


def _check_structure(systems: Sequence[NonlinearSystem]) -> None:
    if not systems:
        raise ReducerlabError("ensemble: no systems")
    s0 = systems[0]
    for s in systems[1:]:
        if (
            s.n != s0.n
            or s.G.shape != s0.G.shape
            or not np.array_equal(s.k_kind, s0.k_kind)
            or not np.array_equal(s.e_kind, s0.e_kind)
            or not np.array_equal(s.f_kind, s0.f_kind)
        ):
            raise ReducerlabError("ensemble: all members must have the same structure")


@dataclass(frozen=True)
class _Prepared:
    """Stacked kernel inputs of an ensemble (see :func:`kernel.rk4_ensemble`)."""

    arrays: tuple[NDArray, ...]
    period: NDArray[np.float64]  # (E,) s
    offs: NDArray[np.float64]  # (E, N) s, step starts from the period start
    dts: NDArray[np.float64]  # (E, N) s, step lengths
    periodic: bool  # every law repeats within the period
    steps: int


def _divides(P: float, T: float) -> bool:
    """A law of period ``P`` repeats within ``T`` (a whole number >= 1 of periods)."""
    ratio = T / P
    return abs(ratio - round(ratio)) <= 1e-9 * max(1.0, ratio) and round(ratio) >= 1


def _repeats_within(s: NonlinearSystem, T: float) -> bool:
    """Every law of ``s`` has a period that divides ``T`` (or is constant: a Fourier law
    whose amplitudes are all zero counts as constant)."""
    for kinds, params in ((s.k_kind, s.k_params), (s.e_kind, s.e_params), (s.f_kind, s.f_params)):
        for kind, p in zip(kinds, params, strict=True):
            if int(kind) == LAW_FOURIER and not np.any(p[3 : 3 + int(p[2])]):
                continue
            P = flat_period(int(kind), p)
            if math.isfinite(P) and not _divides(P, T):
                return False
    return True


def _prepare(
    systems: Sequence[NonlinearSystem],
    steps_per_period: int | None,
    period: float | None,
    labels: Sequence[str] | None = None,
) -> _Prepared:
    """Check an ensemble (structure, linear stability: :func:`check_stability`) and
    stack its arrays for the kernel (member axis first)."""
    _check_structure(systems)
    lam_max = check_stability(systems, labels)
    if period is not None and not (isinstance(period, int | float) and period > 0):
        raise ReducerlabError(f"period must be > 0 s, got {period!r}")
    E = len(systems)
    T = np.array([period if period is not None else forcing_period(s) for s in systems])
    Minv = np.linalg.inv(np.stack([s.M for s in systems]))  # M is positive definite (above)
    N = steps_per_period or _steps_batch(systems, T, lam_max=lam_max)
    if not (isinstance(N, int) and N >= 4):
        raise ReducerlabError(f"steps_per_period must be an integer >= 4, got {N!r}")
    if steps_per_period is None and N > MAX_STEPS:
        raise ReducerlabError(_too_many_steps(systems, T, N))
    for s, t in zip(systems, T, strict=True):
        _check_commensurate(s, t)
    offs, dts, N = _grid(systems, T, N)
    widths = {
        name: max(getattr(s, name).shape[1] if getattr(s, name).ndim == 2 else 1 for s in systems)
        for name in ("k_params", "e_params", "f_params")
    }

    def params(name: str) -> NDArray:
        out = np.zeros((E, getattr(systems[0], name).shape[0], widths[name]))
        for e, s in enumerate(systems):
            a = getattr(s, name)
            out[e, :, : a.shape[1]] = a
        return out

    s0 = systems[0]
    pad = np.stack
    arrays = (
        Minv, pad([s.C for s in systems]),
        pad([s.K for s in systems]), pad([s.G for s in systems]), s0.k_kind,
        params("k_params"), pad([s.line_damping for s in systems]),
        pad([s.half_backlash for s in systems]), pad([s.line_cubic for s in systems]),
        s0.e_kind, params("e_params"), pad([s.load_matrix for s in systems]), s0.f_kind,
        params("f_params"),
    )  # fmt: skip
    periodic = all(_repeats_within(s, t) for s, t in zip(systems, T, strict=True))
    return _Prepared(arrays, T, offs, dts, periodic, N)


def _grid(systems: Sequence[NonlinearSystem], T: NDArray, N: int) -> tuple[NDArray, NDArray, int]:
    """Step starts and lengths (E, N) (s, from each period's start), at least one step
    per law segment and aligned with the law jumps, and the step count."""
    from .kernel import step_grid

    brk = [_breaks(s, t) for s, t in zip(systems, T, strict=True)]
    N = max(N, max(len(b) for b in brk))
    edges = np.ones((len(systems), max(len(b) for b in brk) + 1))
    counts = np.empty(len(systems), np.int64)
    for e, b in enumerate(brk):
        edges[e, : len(b)] = b
        counts[e] = len(b) + 1
    offs, dts = step_grid(edges, counts, N)
    return offs * T[:, None], dts * T[:, None], N


def subset(prep: _Prepared, idx: NDArray[np.intp]) -> _Prepared:
    """The prepared kernel arrays of members ``idx``."""
    arrays = tuple(a if a.ndim == 1 else a[idx] for a in prep.arrays)
    return replace(prep, arrays=arrays, period=prep.period[idx], offs=prep.offs[idx],
                   dts=prep.dts[idx])  # fmt: skip


def _with_steps(prep: _Prepared, systems: Sequence[NonlinearSystem], N: int) -> _Prepared:
    """``prep`` with ``N`` steps per period (its checks and stacked arrays kept)."""
    if prep.steps == N:
        return prep
    offs, dts, N = _grid(systems, prep.period, N)
    return replace(prep, offs=offs, dts=dts, steps=N)


#: Most RK4 steps per forcing period chosen automatically (the command line's bound on
#: ``--steps`` too): more means a natural frequency over ~16000 x the forcing frequency,
#: i.e. a near-rigid part that makes the run stiff (hours of integration, gigabytes).


def _too_many_steps(systems: Sequence[NonlinearSystem], T: NDArray, N: int) -> str:
    """Message for a run whose highest natural frequency needs more than MAX_STEPS."""
    s = systems[0]
    lam, V = scipy.linalg.eigh(s.mean_stiffness, s.M)
    top = describe_dofs(s.dominant_dofs(V[:, -1]))
    f_top = math.sqrt(max(float(lam[-1]), 0.0)) / (2 * math.pi)
    return (
        f"the highest natural frequency, {f_top:.4g} Hz (a mode of {top}), is "
        f"{f_top * float(T[0]):.3g} times the forcing frequency {1 / float(T[0]):.4g} Hz: an "
        f"accurate explicit integration needs {N} steps per forcing period (at most "
        f"{MAX_STEPS}). Such a frequency comes from a near-zero inertia or a near-rigid "
        "stiffness on those DOFs: check their values (a rigid joint is better modelled by "
        "merging the DOFs), or give steps_per_period (--steps) explicitly"
    )


def _steps_batch(
    systems: Sequence[NonlinearSystem],
    T: NDArray,
    accuracy: float = 0.25,
    lam_max: NDArray[np.float64] | None = None,
) -> int:
    """:func:`steps_for` of every member at once (batched eigenvalues), the largest;
    ``lam_max``: the members' largest eigenvalues when already known
    (:func:`check_stability` returns them)."""
    lam = lam_max
    if lam is None:
        K = np.stack([s.mean_stiffness for s in systems])
        Lc = np.linalg.cholesky(np.stack([s.M for s in systems]))
        A = np.linalg.solve(Lc, np.swapaxes(np.linalg.solve(Lc, K), 1, 2))
        lam = np.linalg.eigvalsh(0.5 * (A + np.swapaxes(A, 1, 2))).max(axis=1)
    w = np.sqrt(np.maximum(lam, 0.0))
    return max(32, int(np.ceil(np.max(np.asarray(T) * w) / accuracy)))


def steps_for(s: NonlinearSystem, T: float, accuracy: float = 0.25) -> int:
    """Steps per forcing period: ``omega_max h <= accuracy`` for the highest natural
    frequency of the mean system (RK4 is stable to 2.8; 0.25 keeps its per-step
    relative phase error near 1e-6), at least 32."""
    return _steps_batch([s], np.array([T]), accuracy)


#: Default target error of Poincaré points, relative to the motion's scale.
ACCURACY = 1e-6

#: Periods integrated before the step count is checked (the state then lies on or near
#: the attractor, where the error is measured).
PILOT_PERIODS = 40

#: Error of the Poincaré points over the one-period error estimate (measured 2-4 on
#: the rattle oscillators of tests/test_accuracy.py: a stable orbit accumulates the
#: per-period error over a few periods).
PERIOD_ERROR_GAIN = 5.0

#: Initial (and renormalised) separation of the perturbed copies that measure Lyapunov
#: exponents, in state scales (:func:`lyapunov`, :func:`ensemble` with ``exponents``).
LYAPUNOV_D0 = 1e-9


def accurate_steps(
    prep: _Prepared,
    systems: Sequence[NonlinearSystem],
    Y0: NDArray[np.float64],
    bounds: NDArray[np.float64],
    accuracy: float = ACCURACY,
    pilot: int = PILOT_PERIODS,
) -> int:
    """Steps per forcing period that meet ``accuracy`` on the attractor.

    The members are integrated for ``pilot`` periods with the stability-based step
    count of ``prep`` (``omega_max h <= 0.25``, at least 32); from there one period is
    integrated with ``N`` and ``2 N`` steps, and the difference (the error of the
    ``N``-step period, Richardson) relative to each member's displacement scale
    (``bounds / BOUND_FACTOR``, velocities by that times the highest frequency) must be
    below ``accuracy / PERIOD_ERROR_GAIN``; otherwise ``N`` grows by the fourth root of
    the excess (RK4 is fourth order, kinks of the backlash included, since the kernel
    steps to each boundary crossing) and the check repeats. The largest over the
    members is returned, at most :data:`MAX_STEPS`. Members that diverge or have no
    scale are left to the main run.
    """
    from .kernel import block_width, rk4_ensemble

    if not (isinstance(accuracy, int | float) and 0 < accuracy < 1):
        raise ReducerlabError(f"accuracy must be a number in (0, 1), got {accuracy!r}")
    E = len(systems)
    T, N = prep.period, prep.steps
    bw = block_width(E)
    P, _, status, _ = rk4_ensemble(
        *prep.arrays, Y0, np.zeros(E), T, prep.offs, prep.dts, prep.periodic,
        pilot, 1, 0, bounds, bw, -1, 0.0,
    )  # fmt: skip
    Y = P[:, 1].copy()
    ok = (status[:, 0] == 0) & np.all(np.isfinite(Y), axis=1)
    if not np.any(ok):
        return N
    Y[~ok] = Y0[~ok]
    return refine_steps(prep, systems, Y, pilot * T, ok, bounds, accuracy)


def refine_steps(
    prep: _Prepared,
    systems: Sequence[NonlinearSystem],
    Y: NDArray[np.float64],
    start: NDArray[np.float64],
    ok: NDArray[np.bool_],
    bounds: NDArray[np.float64],
    accuracy: float,
) -> int:
    """The check of :func:`accurate_steps` from states ``Y`` at times ``start`` (s) on
    or near the attractor (members ``ok``): one period with ``N`` and ``2N`` steps, ``N``
    grown until their difference meets ``accuracy / PERIOD_ERROR_GAIN``."""
    from .kernel import block_width, rk4_ensemble

    E = len(systems)
    T, N = prep.period, prep.steps
    scale = bounds / BOUND_FACTOR
    scale[~np.isfinite(scale) | (scale <= 0)] = np.inf
    bw = block_width(E)
    ok = ok.copy()
    target = accuracy / PERIOD_ERROR_GAIN
    for _ in range(6):
        ends = []
        for steps in (N, 2 * N):
            p = _with_steps(prep, systems, steps)
            out, _, st, _ = rk4_ensemble(
                *p.arrays, Y, start, T, p.offs, p.dts, p.periodic, 1, 1, 0, bounds, bw, -1, 0.0,
            )  # fmt: skip
            ok &= st[:, 0] == 0
            ends.append(out[:, 1])
        err = np.abs(ends[0] - ends[1]) / scale
        est = float(np.nanmax(np.where(ok[:, None], err, 0.0)))
        if not est > target or N >= MAX_STEPS:
            return N
        grow = min(8.0, max(1.5, 1.2 * (est / target) ** 0.25))
        N = min(MAX_STEPS, math.ceil(N * grow))
    return N


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
    return np.concatenate([q, np.zeros_like(q)], axis=1)


@dataclass(frozen=True)
class Ensemble:
    """Result of :func:`ensemble`: Poincaré states (member, point, state), the history of
    the last periods (member, step, state), the mesh deflections at the Poincaré points
    (member, point, line), the period and the step times of the history."""

    poincare: NDArray[np.float64]
    history: NDArray[np.float64]
    delta_poincare: NDArray[np.float64]
    delta_history: NDArray[np.float64]
    period: NDArray[np.float64]
    history_time: NDArray[np.float64]  # (member, step), s
    systems: list[NonlinearSystem]
    steps_per_period: int = 0  # RK4 steps per period used
    diverged: NDArray[np.bool_] | None = None  # (member,), with on_divergence="mark"
    exponent: NDArray[np.float64] | None = None  # (member,), 1/s, with exponents=True
    mapped: NDArray[np.bool_] | None = None  # (member,): fast-forwarded by one-period maps


def ensemble(
    systems: Sequence[NonlinearSystem],
    *,
    periods: int = 600,
    keep: int = 100,
    history: int = 0,
    steps_per_period: int | None = None,
    y0: NDArray[np.float64] | None = None,
    limit: float | None = None,
    labels: Sequence[str] | None = None,
    period: float | None = None,
    accuracy: float = ACCURACY,
    on_divergence: str = "raise",
    exponents: bool = False,
    method: str = "auto",
) -> Ensemble:
    """Integrate systems of identical structure with the compiled RK4 kernel.

    Parameters
    ----------
    systems : sequence of NonlinearSystem
        Same DOFs, lines and law kinds; parameter values may differ.
    periods : int
        Forcing periods to integrate (transient included).
    keep : int
        Poincaré points kept: the states at the start of the last ``keep`` periods.
    history : int
        Periods at the end whose every step is returned (phase plots, spectra).
    steps_per_period : int, optional
        Overrides :func:`steps_for` (the largest over the members is used).
    y0 : array, optional
        Initial states (member, 2n) or (2n,); zeros by default.
    limit : float, optional
        |state component| above this counts as divergence (in the system's
        coordinates: after rigid-motion removal they are mass-weighted modal amplitudes,
        not metres); ``math.inf``: only a non-finite state (overflow, NaN) does. By
        default each member gets the bounds of :func:`state_bounds`: 1e6 times its
        displacement scale (static deflection under the peak loads, initial state,
        mesh clearances), and that times its highest frequency for velocities.
    labels : sequence of str
        Names of the members for error messages (parameter values).
    period : float, optional
        Sampling period (s) when the systems have no periodic law.
    accuracy : float
        Target error of the Poincaré points relative to each member's displacement
        scale (and that scale times its highest frequency for velocities), default
        1e-6: the step count is the smallest that meets it on the attractor
        (:func:`accurate_steps`); ignored when ``steps_per_period`` is given.
    on_divergence : {"raise", "mark"}
        A member that leaves its bounds during the run raises ``DivergenceError``
        (default), or with ``"mark"`` is flagged in :attr:`Ensemble.diverged` with NaN
        rows from the divergence on, and the other members' results are kept.
    exponents : bool
        Also the largest Lyapunov exponent of each member (1/s) over its last ``keep``
        periods, from the same trajectory as the points (:attr:`Ensemble.exponent`):
        every member runs beside a perturbed copy inside the compiled kernel
        (Benettin's renormalisation after every period, as :func:`lyapunov`), at twice
        the cost of the trajectory alone.
    method : {"auto", "rk4", "maps"}
        ``"rk4"`` integrates every period with the compiled RK4 kernel. ``"maps"``
        first tries the one-period map of the contact system (:mod:`.floquet`): exact
        while every line with backlash stays in contact, which it checks in every
        period (members whose teeth would separate are integrated by RK4 from the
        start); the last ``history`` periods are always RK4's. ``"auto"`` (default)
        takes the map where it pays: every law repeats within the period, no cubic
        line, and at least ``4 (2n + 1)`` periods.

    Raises
    ------
    DivergenceError
        Before integrating, when a member's linear part has a divergent mode
        (:func:`check_stability`); during it, when a state component leaves its bound
        or becomes non-finite: the message names the member (``labels``), the time and
        the physical DOFs that dominate the motion.
    """
    from .kernel import block_width, law_values, rk4_ensemble

    if not systems:
        raise ReducerlabError("ensemble: no systems")
    s0 = systems[0]
    if not (isinstance(periods, int) and isinstance(keep, int) and 1 <= keep <= periods):
        raise ReducerlabError(f"need 1 <= keep <= periods, got keep={keep}, periods={periods}")
    if not (isinstance(history, int) and 0 <= history <= periods):
        raise ReducerlabError(f"history must be in [0, periods], got {history!r}")
    E, n = len(systems), s0.n
    if labels is not None and len(labels) != E:
        raise ReducerlabError(f"labels: {len(labels)} names for {E} members")
    if y0 is not None:
        y0 = np.asarray(y0, float)
        if y0.shape not in ((2 * n,), (E, 2 * n)):
            raise ReducerlabError(
                f"y0 must have shape ({2 * n},) or ({E}, {2 * n}), got {y0.shape}"
            )
    if limit is not None and not (isinstance(limit, int | float) and limit > 0):
        raise ReducerlabError(f"limit must be a number > 0, got {limit!r}")
    if on_divergence not in ("raise", "mark"):
        raise ReducerlabError(f"on_divergence must be 'raise' or 'mark', got {on_divergence!r}")
    prep = _prepare(systems, steps_per_period, period, labels)
    T, N = prep.period, prep.steps
    Y0 = (
        np.zeros((E, 2 * n))
        if y0 is None
        else np.broadcast_to(np.asarray(y0, float), (E, 2 * n)).copy()
    )
    if not np.all(np.isfinite(Y0)):
        raise ReducerlabError("y0: the initial state must be finite")
    bounds = state_bounds(systems, Y0, T) if limit is None else np.full((E, 2 * n), float(limit))
    if method not in ("auto", "rk4", "maps"):
        raise ReducerlabError(f"method must be 'auto', 'rk4' or 'maps', got {method!r}")

    maps = None
    cache: dict = {}
    if prep.periodic and (method == "maps" or (method == "auto" and _maps_pay(n, periods))):
        from .floquet import contact_sides

        sides = contact_sides(prep.arrays, static_states(systems))
        if not np.any(prep.arrays[8]) and np.any(np.all(sides != 0, axis=1)):
            maps = sides
    if steps_per_period is None:
        if maps is not None:
            N = _map_steps(prep, systems, Y0, bounds, accuracy, min(periods, PILOT_PERIODS),
                           maps, cache)  # fmt: skip
        else:
            N = accurate_steps(prep, systems, Y0, bounds, accuracy, min(periods, PILOT_PERIODS))
        prep = _with_steps(prep, systems, N)
        N = prep.steps

    def rk4_run(idx: NDArray[np.intp], Ys: NDArray[np.float64]) -> tuple:
        """Poincaré states, history, status and exponents of members ``idx``."""
        sub = subset(prep, idx)
        Tk, bk, Ek = T[idx], bounds[idx], idx.size
        if not exponents:
            P, H, st, _ = rk4_ensemble(
                *sub.arrays, Ys, np.zeros(Ek), Tk, sub.offs, sub.dts, sub.periodic,
                periods, keep, history, bk, block_width(Ek), -1, 0.0,
            )  # fmt: skip
            return P, H, st, None
        # each member beside its perturbed copy: pairs in one kernel call
        two = subset(prep, np.repeat(idx, 2))
        P, H, st, logs = rk4_ensemble(
            *two.arrays, np.repeat(Ys, 2, axis=0), np.zeros(2 * Ek), np.repeat(Tk, 2),
            two.offs, two.dts, two.periodic, periods, keep, history,
            np.repeat(bk, 2, axis=0), block_width(2 * Ek), periods - keep, LYAPUNOV_D0,
        )  # fmt: skip
        P, H, st = P[0::2], H[0::2], st[0::2]
        lam = logs[0::2] / (keep * Tk)
        lam[st[:, 0] != 0] = np.nan
        return P, H, st, lam

    if maps is None:
        poincare, hist, status, exponent = rk4_run(np.arange(E), Y0)
        mapped = np.zeros(E, bool)
    else:
        poincare, hist, status, exponent, mapped = _map_run(
            prep, Y0, bounds, periods, keep, history, exponents, maps, rk4_run, cache
        )
    diverged = status[:, 0] != 0
    if on_divergence == "raise":
        _raise_diverged(systems, status, bounds, labels, N)
    G = prep.arrays[3]
    L = G.shape[1]
    # mesh deflections G q - e(t) at the Poincare times and along the history
    tP = (periods - keep + np.arange(keep + 1))[None, :] * T[:, None]
    start = periods - history
    ends = prep.offs + prep.dts  # (E, N): end of each step from the period start
    tH = (
        ((start + np.arange(history))[None, :, None] * T[:, None, None] + ends[:, None, :])
        .reshape(E, history * N)
    )  # fmt: skip
    width = tH.shape[1]
    e_kind, e_par = prep.arrays[9], prep.arrays[10]
    eP = law_values(e_kind, e_par, np.ascontiguousarray(tP * np.ones((E, 1))))
    dP = np.einsum("eln,epn->epl", G, poincare[:, :, :n]) - eP
    if history:
        hist = hist[:, :width]
        eH = law_values(e_kind, e_par, np.ascontiguousarray(tH))
        dH = np.einsum("eln,epn->epl", G, hist[:, :, :n]) - eH
    else:
        dH = np.empty((E, 0, L))
    times = tH
    return Ensemble(poincare, hist, dP, dH, T, times, list(systems), N, diverged, exponent,
                    mapped)  # fmt: skip


def _maps_pay(n: int, periods: int) -> bool:
    """Whether the one-period map is worth trying: it costs ``2n + 1`` periods."""
    return periods >= 4 * (2 * n + 1)


def _map_steps(
    prep: _Prepared,
    systems: Sequence[NonlinearSystem],
    Y0: NDArray[np.float64],
    bounds: NDArray[np.float64],
    accuracy: float,
    pilot: int,
    sides: NDArray[np.float64],
    cache: dict,
) -> int:
    """:func:`accurate_steps` with the pilot periods run through the one-period maps
    (members whose teeth separate in the pilot run them with the RK4 kernel); the maps
    stay in ``cache`` for the main run."""
    from .floquet import map_members
    from .kernel import block_width, rk4_ensemble

    P, failed, _ = map_members(prep, sides, Y0, bounds, pilot, 1, -1, 0.0, cache)
    Y = P[:, -1].copy()
    ok = np.ones(len(systems), bool)
    bad = np.flatnonzero(failed >= 0)
    if bad.size:  # teeth that separate: their pilot by the RK4 kernel
        sub = subset(prep, bad)
        P, _, st, _ = rk4_ensemble(
            *sub.arrays, Y0[bad], np.zeros(bad.size), sub.period, sub.offs, sub.dts,
            sub.periodic, pilot, 1, 0, bounds[bad], block_width(bad.size), -1, 0.0,
        )  # fmt: skip
        Y[bad] = np.where(np.isfinite(P[:, 1]), P[:, 1], Y0[bad])
        ok[bad] = st[:, 0] == 0
    if not np.any(ok):
        return prep.steps
    return refine_steps(prep, systems, Y, pilot * prep.period, ok, bounds, accuracy)


def _map_run(
    prep: _Prepared,
    Y0: NDArray[np.float64],
    bounds: NDArray[np.float64],
    periods: int,
    keep: int,
    history: int,
    exponents: bool,
    sides: NDArray[np.float64],
    rk4_run: Callable[[NDArray[np.intp], NDArray[np.float64]], tuple],
    cache: dict,
) -> tuple:
    """:func:`ensemble`'s outputs with the periods before the history taken by the
    one-period maps; members whose teeth separate (or that leave their bounds) in any
    period go to ``rk4_run`` from their start."""
    from .floquet import map_members

    E, n2 = Y0.shape
    N = prep.steps
    n_keep = max(keep, history)
    P, failed, logs = map_members(prep, sides, Y0, bounds, periods, n_keep,
                                     periods - keep if exponents else -1, LYAPUNOV_D0,
                                     cache)  # fmt: skip
    poincare = np.ascontiguousarray(P[:, n_keep - keep :])
    hist = np.full((E, history * N, n2), np.nan)
    status = np.zeros((E, 3 + n2))
    exponent = logs / (keep * prep.period) if exponents else None
    good = np.flatnonzero(failed < 0)
    if history and good.size:  # the last periods, every step: the full equations
        from .kernel import block_width, rk4_ensemble

        sub = subset(prep, good)
        start = P[good, n_keep - history]
        _, H, st, _ = rk4_ensemble(
            *sub.arrays, start, (periods - history) * sub.period, sub.period, sub.offs,
            sub.dts, sub.periodic, history, 1, history, bounds[good], block_width(good.size),
            -1, 0.0,
        )  # fmt: skip
        hist[good] = H
        status[good] = st
    bad = np.flatnonzero(failed >= 0)
    if bad.size:
        Pb, Hb, sb, lb = rk4_run(bad, Y0[bad])
        poincare[bad], hist[bad], status[bad] = Pb, Hb, sb
        if exponents:
            exponent[bad] = lb
    return poincare, hist, status, exponent, failed < 0


def _raise_diverged(
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
    where = _member(labels, e, len(systems))
    bound = float(bounds[e, i])
    why = (
        f"left its bound ({bound:.3g} in the system's coordinates, see "
        "reducerlab.analysis.response.state_bounds)"
        if math.isfinite(bound) and np.isfinite(y[i])
        else "became non-finite (overflow or NaN)"
    )
    raise DivergenceError(
        f"integration diverged{where} at t = {status[e, 1]:.6g} s: the {kind} of the "
        f"motion, dominated by {dofs}, {why}. The motion is unbounded (an instability of "
        f"the nonlinear or time-varying system) or the step too long: check the "
        f"parameters, or give steps_per_period > {steps}"
    )


def _check_commensurate(s: NonlinearSystem, T: float) -> None:
    """Every law with jumps (piecewise) must repeat within the sampling period T: the
    kernel aligns its steps with the jumps of one period and reuses that grid. Smooth
    laws (Fourier) may have any frequency."""
    for kinds, params in ((s.k_kind, s.k_params), (s.e_kind, s.e_params), (s.f_kind, s.f_params)):
        for kind, p in zip(kinds, params, strict=True):
            if kind != LAW_PIECEWISE:
                continue
            P = flat_period(int(kind), p)
            if not _divides(P, T):
                raise ReducerlabError(
                    f"a law of period {P:.6g} s does not repeat within the sampling period "
                    f"{T:.6g} s; give period= as a common multiple of all law periods"
                )


def _law_value(kind: int, params: NDArray, t: float) -> float:
    return evaluate_flat(int(kind), params, t)[0]


def simulate_reference(
    system: NonlinearSystem,
    t_eval: NDArray[np.float64],
    y0: NDArray[np.float64] | None = None,
    *,
    rtol: float = 1e-11,
    atol: float = 1e-16,
) -> NDArray[np.float64]:
    """Reference solution at the (increasing, > 0) times ``t_eval``: DOP853 restarted at
    every stiffness-law discontinuity and at every crossing of a backlash boundary
    (``|delta| = b``, located by events), so that no step straddles a kink.

    Returns the states, shape (len(t_eval), 2n).
    """
    t_eval = np.asarray(t_eval, dtype=float)
    if t_eval.ndim != 1 or t_eval.size == 0 or np.any(np.diff(t_eval) <= 0) or t_eval[0] <= 0:
        raise ReducerlabError("t_eval must be increasing times > 0")
    n = system.n
    y = np.zeros(2 * n) if y0 is None else np.asarray(y0, float).copy()
    if y.shape != (2 * n,):
        raise ReducerlabError(f"y0 must have shape ({2 * n},), got {y.shape}")
    t_end = float(t_eval[-1])
    try:
        T = forcing_period(system)
        k = np.arange(0, math.ceil(t_end / T) + 1)
        jumps = (k[:, None] + _breaks(system, T)).ravel() * T
    except ReducerlabError:
        T, jumps = t_end, np.empty(0)
    jumps = np.unique(np.append(jumps[(jumps > 0) & (jumps < t_end)], t_end))
    events = []
    for m in range(system.G.shape[0]):
        h = system.half_backlash[m]
        if h <= 0:
            continue
        for sgn in (1.0, -1.0):

            def ev(t: float, yy: NDArray, m: int = m, sgn: float = sgn, h: float = h) -> float:
                e = _law_value(system.e_kind[m], system.e_params[m], t)
                return float(system.G[m] @ yy[:n] - e - sgn * h)

            ev.terminal = True  # type: ignore[attr-defined]
            events.append(ev)
    out = np.full((t_eval.size, 2 * n), np.nan)
    t0 = 0.0
    tiny = 1e-9 * T
    t_seg = 0.0
    for t1 in jumps:
        lo, hi = t_seg + 1e-12 * T, t1 - 1e-12 * T
        t_seg = t1

        def rhs(t: float, yy: NDArray, lo: float = lo, hi: float = hi) -> NDArray:
            # laws are read just inside the segment: a jump at its ends is seen from
            # the correct side
            return system.rhs(min(max(t, lo), hi), yy)

        while t0 < t1:
            sol = scipy.integrate.solve_ivp(
                rhs, (t0, t1), y, method="DOP853", rtol=rtol, atol=atol,
                events=events or None, dense_output=True,
            )  # fmt: skip
            if not sol.success:
                raise ReducerlabError(f"reference integration failed after t = {t0:.6g} s")
            t_stop = float(sol.t[-1])
            if sol.status == 1 and t_stop - t0 < tiny:
                # an event at the restart point itself: step over it without events
                sol = scipy.integrate.solve_ivp(
                    rhs, (t0, min(t0 + tiny, t1)), y, method="DOP853", rtol=rtol,
                    atol=atol, dense_output=True,
                )  # fmt: skip
                t_stop = float(sol.t[-1])
            mask = (t_eval > t0) & (t_eval <= t_stop)
            if mask.any():
                out[mask] = sol.sol(t_eval[mask]).T
            y = sol.y[:, -1].copy()
            t0 = t_stop
    return out


def lyapunov(
    systems: Sequence[NonlinearSystem],
    *,
    periods: int = 600,
    transient: int = 200,
    steps_per_period: int | None = None,
    d0: float = LYAPUNOV_D0,
    y0: NDArray[np.float64] | None = None,
    period: float | None = None,
    accuracy: float = ACCURACY,
) -> NDArray[np.float64]:
    """Largest Lyapunov exponent (1/s) of each system, by two-trajectory renormalisation.

    A reference and a perturbed trajectory (initial separation ``d0`` in the first
    displacement) are integrated side by side in one call of the compiled kernel;
    after each period the separation is measured in a scaled state norm (displacements
    by their reference amplitude, velocities by amplitude x frequency), logged and reset
    to ``d0`` along the current separation direction (Benettin's method; it needs no
    linearisation, so it works with the non-smooth backlash). The first ``transient``
    periods are discarded. ``period`` (s) is the renormalisation period of systems
    without a periodic law (as in :func:`ensemble`).
    """
    from .kernel import block_width, rk4_ensemble

    if not (isinstance(periods, int) and isinstance(transient, int) and 0 <= transient < periods):
        raise ReducerlabError("lyapunov: need 0 <= transient < periods")
    pairs = [s for s in systems for _ in range(2)]
    labels = None if len(systems) == 1 else [f"member {i // 2}" for i in range(len(pairs))]
    prep = _prepare(pairs, steps_per_period, period, labels)
    T = prep.period
    bw = block_width(len(pairs))
    E2, n = len(pairs), systems[0].n
    if y0 is None:
        Y = np.zeros((E2, 2 * n))
    else:
        y0 = np.asarray(y0, float)
        if y0.shape == (2 * n,):
            Y = np.tile(y0, (E2, 1))
        elif y0.shape == (len(systems), 2 * n):
            Y = np.repeat(y0, 2, axis=0)
        else:
            raise ReducerlabError(
                f"y0 must have shape ({2 * n},) or ({len(systems)}, {2 * n}), got {y0.shape}"
            )
    if not np.all(np.isfinite(Y)):
        raise ReducerlabError("y0: the initial state must be finite")
    bounds = state_bounds(pairs, Y, T)
    if steps_per_period is None:  # the same accuracy-driven step count as ensemble
        N = accurate_steps(prep, pairs, Y, bounds, accuracy, min(periods, PILOT_PERIODS))
        prep = _with_steps(prep, pairs, N)
    # one compiled run: each pair separates at the end of the transient and is
    # renormalised after every later period inside the kernel
    _, _, status, logs = rk4_ensemble(
        *prep.arrays, Y, np.zeros(E2), T, prep.offs, prep.dts, prep.periodic, periods, 1,
        0, bounds, bw, transient, d0,
    )  # fmt: skip
    _raise_diverged(pairs, status, bounds, labels, prep.steps)
    return logs[0::2] / ((periods - transient) * T[0::2])


def _scale_law(kind: int, p: NDArray, value: float, omega_n: float) -> NDArray:
    """Flat law ``v(t)`` -> ``value * v(tau / omega_n)`` in dimensionless time."""
    q = p.copy()
    if kind == 0:
        q[0] *= value
    elif kind == LAW_FOURIER:
        n = int(p[2])
        q[0] *= value
        q[1] /= omega_n
        q[3 : 3 + n] *= value
    elif kind == LAW_PIECEWISE:
        n, m = int(p[2]), int(p[3])
        q[0] *= omega_n
        q[1] *= omega_n
        q[4 + n : 4 + n + n * m] *= value
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
        e_params=laws(s.e_kind, s.e_params, 1 / length),
        f_params=laws(s.f_kind, s.f_params, 1 / (w2 * length)),
    )
