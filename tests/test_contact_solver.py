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


def test_cold_start_never_factorises_far_more_than_the_contact_set(monkeypatch):
    # A smooth surface under load: about a third of 1500 candidates carry load. A cold
    # start from the single first point would give that point the whole load and bring
    # every candidate into the next step's factorisation; the Winkler (diagonal) start
    # and the capped growth keep every factorisation within a few times the final set
    # (measured: 386 points for 163 in contact, the Winkler set being the largest).
    import reducerlab.contact.complementarity as cp

    sizes = []
    orig = cp._subproblem

    def spy(C, g, lam, A, load):
        sizes.append(A.size)
        return orig(C, g, lam, A, load)

    monkeypatch.setattr(cp, "_subproblem", spy)
    C, g, lam = _problem(1500, 3)
    sol = solve_contact(C, g, lam, 2000.0)
    n_active = int(sol.active.sum())
    assert 100 < n_active < 1400
    assert max(sizes) <= 3 * n_active
    # the same KKT point as the monotone method alone from the first point
    monkeypatch.setattr(cp, "PDAS_STEPS", 0)
    ref = solve_contact(C, g, lam, 2000.0, start=[int(np.argmin(g / lam))])
    np.testing.assert_allclose(sol.force, ref.force, rtol=1e-8, atol=1e-10 * ref.force.max())


def test_a_contact_set_too_large_to_factorise_is_an_error(monkeypatch):
    import reducerlab.contact.complementarity as cp

    monkeypatch.setattr(cp, "MAX_SET", 10)
    C, g, lam = _problem(200, 1)
    with pytest.raises(ContactError, match="coarsen the contact grid"):
        solve_contact(C, g, lam, 2000.0)
