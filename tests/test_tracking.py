"""Mode tracking: the compiled steps of long sweeps take the Python steps' decisions
(issue 28): the same track order, refinements and events, shapes and MACs equal to
round-off, on the 10,000-point benchmark sweep and on crossings, veerings and repeated
eigenvalues."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
from numpy.typing import NDArray

from reducerlab.analysis import tracking
from reducerlab.analysis.parameters import Axis
from reducerlab.analysis.sweep import sweep
from reducerlab.analysis.tracking import Tracking, find_events, track_modes
from reducerlab.model import Coupling, Dof, Inertia, Model, Support

BENCHMARK = Path(__file__).resolve().parents[1] / "benchmarks" / "modal_sweep.py"


def both(monkeypatch, *args, **kw) -> tuple[Tracking, Tracking]:
    """``track_modes`` by the Python steps alone and by the compiled kernel."""
    with monkeypatch.context() as m:
        m.setattr(tracking, "_COMPILED_FROM", 10**9)
        python = track_modes(*args, **kw)
    with monkeypatch.context() as m:
        m.setattr(tracking, "_COMPILED_FROM", 1)
        compiled = track_modes(*args, **kw)
    return python, compiled


def same(a: Tracking, b: Tracking) -> None:
    np.testing.assert_array_equal(a.order, b.order)
    assert a.refined == b.refined
    np.testing.assert_allclose(a.min_mac, b.min_mac, rtol=0, atol=1e-12)
    np.testing.assert_allclose(a.y, b.y, rtol=0, atol=1e-11)


def two_dof(k1: NDArray, k2: float, kc: float) -> tuple[NDArray, NDArray]:
    """Unit masses on springs k1 (swept), k2, coupled by kc: eigenvalues and shapes."""
    lam, y = [], []
    for k in np.atleast_1d(k1):
        w, v = np.linalg.eigh(np.array([[k + kc, -kc], [-kc, k2 + kc]]))
        lam.append(w)
        y.append(v)
    return np.array(lam), np.array(y)


def test_benchmark_sweep_tracks_as_the_python_steps(monkeypatch):
    # the 10,000-point 12-DOF sweep of benchmarks/modal_sweep.py: two double
    # frequencies at every point, so every step aligns two eigenspaces
    spec = importlib.util.spec_from_file_location("modal_sweep_benchmark", BENCHMARK)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    k = np.linspace(0.5e8, 1.0e9, bench.N_POINTS)
    res = sweep(bench.twelve_dof(), Axis("mesh1.stiffness", tuple(k)), workers=1, track=False)
    lam, y = res.data["eigenvalue"].values, res.data["weighted_shape"].values
    python, compiled = both(monkeypatch, k, lam, y)
    same(python, compiled)
    freq = res.data["frequency"].values
    assert find_events(k, freq, python.y, python) == find_events(k, freq, compiled.y, compiled)


@pytest.mark.parametrize("n", [101, 11])
def test_veering_with_refinement(monkeypatch, n):
    # a sharp veering (kc << k): the shapes turn within a step or two, which are
    # bisected through evaluate()
    k2, kc = 1e6, 2e3
    k1 = np.linspace(0.5e6, 1.5e6, n)
    lam, y = two_dof(k1, k2, kc)

    def evaluate(p: float) -> tuple[NDArray, NDArray]:
        lp, yp = two_dof(p, k2, kc)
        return lp[0], yp[0]

    python, compiled = both(monkeypatch, k1, lam, y, evaluate)
    same(python, compiled)
    assert python.refined > 0
    assert np.all(python.order == python.order[0])  # the sorted order through a veering
    freq = np.sqrt(lam) / (2 * math.pi)
    events = find_events(k1, freq, compiled.y, compiled)
    assert events == find_events(k1, freq, python.y, python)
    assert [e.kind for e in events] == ["veering"]


def test_crossings_and_repeated_eigenvalues(monkeypatch):
    # 8 modes in a slowly turning basis: a triple eigenvalue throughout (aligned by SVD),
    # a double one, and straight lines crossing on and between grid points (a double
    # eigenvalue that appears at one point only)
    n, rng = 8, np.random.default_rng(3)
    p = np.linspace(0.0, 1.0, 201)
    A = rng.standard_normal((n, n))
    S = 0.3 * (A - A.T)  # the basis turns by exp(p S)
    Q0 = np.linalg.qr(rng.standard_normal((n, n)))[0]
    lines = np.stack(
        [1.0 + 0 * p, 1.0 + 0 * p, 1.0 + 0 * p, 2.0 + 0 * p, 2.0 + 0 * p,
         1.5 + 2.0 * (p - 0.5), 2.5 - 2.0 * p, 0.5 + 3.0 * p],
        axis=1,
    )  # fmt: skip
    lam, y = [], []
    for pi, d in zip(p, lines, strict=True):
        R = scipy.linalg.expm(pi * S) @ Q0
        w, v = np.linalg.eigh(R @ np.diag(d) @ R.T)
        lam.append(w)
        y.append(v)
    lam, y = np.array(lam), np.array(y)
    python, compiled = both(monkeypatch, p, lam, y)
    same(python, compiled)
    freq = np.sqrt(lam) / (2 * math.pi)
    events = find_events(p, freq, compiled.y, compiled)
    assert events == find_events(p, freq, python.y, python)
    assert sum(e.kind == "crossing" for e in events) >= 4


def test_tracked_sweep_is_the_same_with_the_kernel(monkeypatch):
    # through sweep(): three unit masses, the first two uncoupled and crossing on a grid
    # point (a double eigenvalue there), the third coupled to the second (a veering)
    model = Model(
        [Dof("a", "x"), Dof("b", "x"), Dof("c", "x")],
        [Inertia("a.x", 1.0), Inertia("b.x", 1.0), Inertia("c.x", 1.0),
         Support("a.x", 1e6, name="ka"), Support("b.x", 1.2e6, name="kb"),
         Support("c.x", 2e6, name="kc"), Coupling({"b.x": 1.0, "c.x": -1.0}, 2e4)],
    )  # fmt: skip
    axis = Axis.linspace("ka.stiffness", 0.5e6, 3.0e6, 26)
    runs = []
    for start in (10**9, 1):
        with monkeypatch.context() as m:
            m.setattr(tracking, "_COMPILED_FROM", start)
            runs.append(sweep(model, axis, workers=1).data)
    python, compiled = runs
    np.testing.assert_array_equal(python["track_order"].values, compiled["track_order"].values)
    assert python.attrs["refined_points"] == compiled.attrs["refined_points"]
    for var in ("event_kind", "event_modes"):
        np.testing.assert_array_equal(python[var].values, compiled[var].values)
    np.testing.assert_allclose(python["event_param"].values, compiled["event_param"].values,
                               rtol=1e-12)  # fmt: skip
    np.testing.assert_allclose(python["step_mac"].values, compiled["step_mac"].values,
                               rtol=0, atol=1e-12)  # fmt: skip


def test_unclear_steps_are_left_to_the_python_step(monkeypatch):
    # two modes turned by 45 degrees: every MAC is 1/2, the Hungarian algorithm decides
    lam = np.array([[1.0, 2.0, 3.0]] * 2)
    c = math.sqrt(0.5)
    turned = np.array([[c, -c, 0.0], [c, c, 0.0], [0.0, 0.0, 1.0]])
    y = np.stack([np.eye(3), turned])
    # a double eigenvalue spanning e0 and (e1 + e2)/sqrt(2): modes 1 and 2 of the first
    # point overlap it equally, argpartition picks the one it aligns onto
    lam2 = np.array([[1.0, 2.0, 3.0], [1.0, 1.0, 3.0]])
    y2 = np.stack([np.eye(3), np.array([[1.0, 0.0, 0.0], [0.0, c, -c], [0.0, c, c]])])
    for lam_, y_ in ((lam, y), (lam2, y2)):
        order = np.zeros((2, 3), dtype=np.intp)
        order[0] = np.arange(3)
        repeated = np.array([False, lam_[1, 0] == lam_[1, 1]])
        left = tracking._kernel()(lam_, y_.copy(), repeated, order, np.ones(1), 0, 0.8, False)
        assert left == 0  # nothing decided in the kernel
        same(*both(monkeypatch, np.arange(2.0), lam_, y_))
