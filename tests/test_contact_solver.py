"""The load-distribution solver (contact/complementarity.py): exact KKT conditions,
agreement with a general-purpose QP solver, warm starts, and errors."""

from __future__ import annotations

import numpy as np
import pytest

from reducerlab.contact.complementarity import ContactError, solve_contact


def _problem(n: int, seed: int):
    rng = np.random.default_rng(seed)
    x = np.sort(rng.uniform(0, 1, n))
    # a smooth SPD kernel (like Boussinesq + bending) plus a diagonal
    C = 1.0 / (1.0 + 30 * np.abs(x[:, None] - x[None, :])) + 0.5 * np.eye(n)
    C *= 1e-9
    g = 1e-6 * (x - 0.4) ** 2 * 40 + 1e-7 * rng.uniform(0, 1, n)
    lam = 0.03 + 0.01 * rng.uniform(0, 1, n)
    return C, g, lam


@pytest.mark.parametrize("seed", range(6))
def test_kkt_conditions_hold_to_round_off(seed):
    C, g, lam = _problem(40, seed)
    sol = solve_contact(C, g, lam, 20.0)
    F, s = sol.force, sol.gap
    assert np.all(F >= 0)
    # gaps: zero on the contact set, non-negative elsewhere (1e-12 of the approach)
    scale = np.max(lam * sol.approach)
    assert np.all(s >= -1e-9 * scale)
    assert np.max(np.abs(F * s)) <= 1e-9 * scale * F.max()
    assert lam @ F == pytest.approx(20.0, rel=1e-12)
    # the gap is recomputed from its definition, not taken from the solver's bookkeeping
    s2 = C @ F + g - lam * sol.approach
    assert np.allclose(s2[sol.active], 0.0, atol=1e-9 * scale)


@pytest.mark.parametrize("seed", range(4))
def test_agrees_with_enumeration_of_all_contact_sets(seed):
    """Oracle: the KKT point found by trying every one of the 2^n - 1 contact sets
    (independent of the active-set path; exact for a strictly convex QP, whose KKT
    point is unique)."""
    from itertools import combinations

    n = 9
    C, g, lam = _problem(n, seed)
    T = 5.0
    sol = solve_contact(C, g, lam, T)
    found = []
    for k in range(1, n + 1):
        for A in combinations(range(n), k):
            A = list(A)
            M = np.block([[C[np.ix_(A, A)], -lam[A, None]], [lam[None, A], np.zeros((1, 1))]])
            x = np.linalg.solve(M, np.concatenate([-g[A], [T]]))
            F = np.zeros(n)
            F[A] = x[:-1]
            s = C @ F + g - lam * x[-1]
            if np.all(F >= 0) and np.all(s >= -1e-12 * np.abs(lam * x[-1]).max()):
                found.append(F)
    assert len(found) == 1
    assert np.allclose(sol.force, found[0], rtol=1e-9, atol=1e-12 * T / lam.min())


def test_warm_start_gives_the_same_solution_in_fewer_steps():
    C, g, lam = _problem(60, 7)
    cold = solve_contact(C, g, lam, 30.0)
    warm = solve_contact(C, g, lam, 30.0, start=cold.active)
    assert np.allclose(warm.force, cold.force, rtol=1e-10, atol=1e-12 * cold.force.max())
    assert warm.iterations == 1 <= cold.iterations
    # a poor warm start (every point) still ends at the solution
    poor = solve_contact(C, g, lam, 30.0, start=np.ones(60, bool))
    assert np.allclose(poor.force, cold.force, rtol=1e-9, atol=1e-12 * cold.force.max())


def test_single_point_and_rigid_limit():
    """Two points, one closer: a small load stays on the first point
    (F = T / lam, psi = (C F + g) / lam); a large load shares."""
    C = np.diag([1e-9, 1e-9])
    g = np.array([0.0, 1e-6])
    lam = np.array([0.02, 0.02])
    small = solve_contact(C, g, lam, 0.2)  # F = 10 N -> deflection 1e-8 < 1e-6
    assert small.force == pytest.approx([10.0, 0.0])
    assert small.approach == pytest.approx(1e-8 / 0.02)
    big = solve_contact(C, g, lam, 40.0)  # F_total = 2000 N
    # equal deflection: 1e-9 F1 = 1e-9 F2 + 1e-6 -> F1 - F2 = 1000
    assert big.force == pytest.approx([1500.0, 500.0])


def test_bad_input_is_named():
    C, g, lam = _problem(5, 0)
    with pytest.raises(ContactError, match="compliance: must have shape"):
        solve_contact(C[:4], g, lam, 1.0)
    with pytest.raises(ContactError, match="gap: must be finite"):
        solve_contact(C, np.where(np.arange(5) == 2, np.nan, g), lam, 1.0)
    with pytest.raises(ContactError, match="load: must be a finite number > 0"):
        solve_contact(C, g, lam, -1.0)
    with pytest.raises(ContactError, match="no contact"):
        solve_contact(C, g, -lam, 1.0)
    with pytest.raises(ContactError, match="did not settle"):
        solve_contact(*_problem(40, 0), 1e3, max_iter=1, start=[0])
    with pytest.raises(ContactError, match="not positive definite"):
        solve_contact(np.zeros((5, 5)), g, lam, 1.0, start=np.ones(5, bool))
