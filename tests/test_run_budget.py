"""Integrations estimate their work (RK4 steps x trajectories) and memory before they
start (issue 26, item 2): a run beyond the documented bound
(``dynamics.runsize.MAX_WORK``) or the machine's free memory is refused at once, with the
estimate, the limit and the options to change, instead of running for days or being
killed by the kernel."""

from __future__ import annotations

import time

import numpy as np
import pytest
from typer.testing import CliRunner

from reducerlab.analysis.bifurcation import bifurcation
from reducerlab.analysis.frequency_response import frequency_response
from reducerlab.analysis.parameters import Axis
from reducerlab.analysis.regime_map import regime_map
from reducerlab.analysis.response import response
from reducerlab.budget import MEMORY_ENV
from reducerlab.cli import app
from reducerlab.drives import load_design
from reducerlab.dynamics.runsize import MAX_WORK, run_estimate
from reducerlab.errors import BudgetError
from reducerlab.examples import example_dir

GEAR_PAIR = example_dir() / "gear_pair.toml"


@pytest.fixture(scope="module")
def design():
    return load_design(GEAR_PAIR)


def test_the_estimate_counts_steps_times_trajectories():
    e = run_estimate("x", 10, 600, 64, 6, 1, 100, 10, exponents=True)
    assert e.work == 2 * 10 * 600 * 64
    assert e.work_limit == MAX_WORK
    # the history (every step of the last periods) dominates the memory
    assert (
        run_estimate("x", 1, 600, 64, 6, 1, 1, 100).memory
        > 50 * run_estimate("x", 1, 600, 64, 6, 1, 1, 0).memory
    )


def _refused_fast(call, *words):
    t0 = time.perf_counter()
    with pytest.raises(BudgetError) as info:
        call()
    # refused before any integration (the kernel's compile alone takes longer)
    assert time.perf_counter() - t0 < 30
    for w in words:
        assert w in str(info.value), str(info.value)
    return str(info.value)


def test_a_bifurcation_beyond_the_work_bound_is_refused_before_it_starts(design):
    values = np.linspace(0.9e8, 1.1e8, 100_000)
    msg = _refused_fast(
        lambda: bifurcation(design, Axis("mesh.stiffness", values), periods=1_000_000),
        "bifurcation",
        "at least",
        "RK4 steps",
        "--periods",
        f"{MAX_WORK:.3g}",
    )
    assert "3.2e+12" in msg  # 1e5 values x 1e6 periods x 32 steps (the lowest step count)


def test_a_regime_map_and_a_frequency_response_beyond_the_bound_are_refused(design):
    x = Axis("mesh.stiffness", np.linspace(0.9e8, 1.1e8, 400))
    y = Axis("mesh.damping", np.linspace(100.0, 200.0, 400))
    maps = _refused_fast(lambda: regime_map(design, x, y, periods=1_000_000), "regime-map", "RK4")
    response_msg = _refused_fast(
        lambda: frequency_response(design, x, periods=10_000_000, history=1),
        "frequency-response",
        "RK4",
    )
    for msg in (maps, response_msg):  # each names the bound it exceeds
        assert f"{MAX_WORK:.3g}" in msg


def test_a_history_beyond_the_free_memory_is_refused(design, monkeypatch):
    monkeypatch.setenv(MEMORY_ENV, "64M")
    msg = _refused_fast(
        lambda: response(design, periods=20_000, keep=10, history=20_000, steps_per_period=4000),
        "memory",
        "64 MiB",
        MEMORY_ENV,
    )
    assert "GiB" in msg


def test_the_command_line_names_the_estimate_and_exits_2():
    res = CliRunner().invoke(
        app,
        [
            "bifurcation", str(GEAR_PAIR), "--param", "mesh.stiffness",
            "--values", "lin:0.9e8:1.1e8:100000", "--periods", "1000000",
            "-o", "/nonexistent-never-written",
        ],
    )  # fmt: skip
    assert res.exit_code == 2, res.output
    assert "RK4 steps" in res.output and "Traceback" not in res.output


def test_a_sweep_beyond_the_free_memory_is_refused_before_any_eigen_solve(design, monkeypatch):
    from reducerlab.analysis.parameters import parse_values
    from reducerlab.analysis.sweep import sweep, sweep_estimate

    # two shape matrices per point dominate: 2 n^2 doubles
    assert sweep_estimate(1000, 10).memory >= 3 * 1000 * 8 * 2 * 100
    monkeypatch.setenv(MEMORY_ENV, "1M")
    _refused_fast(
        lambda: sweep(design, parse_values("mesh.stiffness", "lin:1e8:2e9:100000"), workers=1),
        "sweep",
        "1e+05 points",
        "1 MiB",
        "--values",
    )
