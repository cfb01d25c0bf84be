"""The loaded contact analysis on two processes (analysis/contact_workers.py, issue 28):
the same results as on one process (the positions in chunks, the two gears' tooth
compliances at once), progress over all positions, and a worker's error raised here
as a clear ReducerlabError."""

from __future__ import annotations

import os

import numpy as np
import pytest

from reducerlab.analysis.contact import contact_analysis, contact_pair
from reducerlab.analysis.contact_workers import (
    contact_pool,
    contact_processes,
    tooth_compliances,
)
from reducerlab.contact.complementarity import ContactError
from reducerlab.contact.halfspace import combined_modulus
from reducerlab.contact.ltca import ContactGrid
from reducerlab.drives import load_design
from reducerlab.errors import ReducerlabError
from reducerlab.fe import Material

E_STAR = combined_modulus(2.06e11, 0.3, 2.06e11, 0.3)
#: the test process: the failing post-processing below fails in workers alone
PARENT_ENV = "REDUCERLAB_TEST_PARENT_PID"


@pytest.fixture(scope="module")
def design():
    return load_design("examples/nutation_surface.toml")


def _same(a, b) -> None:
    """Every variable of two contact results equal, to rounding."""
    assert set(a.data.data_vars) == set(b.data.data_vars)
    for name in a.data.data_vars:
        x, y = a.data[name].values, b.data[name].values
        assert x.shape == y.shape, name
        if x.dtype.kind == "f":
            np.testing.assert_allclose(y, x, rtol=1e-9, atol=1e-12 * np.nanmax(np.abs(x)))
        else:
            np.testing.assert_array_equal(y, x)


def test_positions_in_two_processes_are_those_of_one(design):
    """Rigid teeth (quick): the positions in two chunks, the second after its lead
    position, give the cells and numbers of the run in one process; the progress
    counts the positions of both processes."""
    seen = []
    one = contact_analysis(design, 1, torque=19.1, positions=7, order=2, rigid=True, workers=1)
    two = contact_analysis(
        design, 1, torque=19.1, positions=7, order=2, rigid=True, workers=2,
        progress=lambda done, total: seen.append((done, total)),
    )  # fmt: skip
    _same(one, two)
    assert seen[-1] == (7, 7)
    assert all(t == 7 for _, t in seen)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)


def test_both_compliances_at_once_are_those_one_after_the_other(design):
    """Coarse tooth models (elements of 0.4 m_n): the internal gear's in a worker, the
    external gear's here, equal to the two built in this process."""
    mp = contact_pair(design, 1)
    material = Material(2.06e11, 0.3, 7850.0)
    size = 0.4 * mp.crown.profile.module
    texts = []
    with contact_pool(2) as pool:
        two = tooth_compliances(mp, material, size, texts.append, pool)
    one = tooth_compliances(mp, material, size, lambda _s: None, None)
    assert any("worker process" in t for t in texts)
    for a, b in zip(one, two, strict=True):
        assert a.dofs == b.dofs
        assert a.teeth == b.teeth
        scale = np.abs(a.matrix).max()
        assert np.abs(a.matrix - b.matrix).max() <= 1e-12 * scale


def _fail_in_worker(runs):
    """Post-processing that fails in a worker only (the way its environment says)."""
    if os.getpid() != int(os.environ[PARENT_ENV]):
        how = os.environ["REDUCERLAB_TEST_FAILURE"]
        if how == "contact":
            raise ContactError("no contact: made up in the worker")
        if how == "bug":
            raise KeyError("made up")
        os._exit(3)
    return (np.zeros(len(runs)),)


@pytest.mark.parametrize(
    ("how", "kind", "text"),
    [
        ("contact", ContactError, "made up in the worker"),
        ("bug", ReducerlabError, "positions 5-6 failed: KeyError"),
        ("exit", ReducerlabError, "positions 5-6 ended unexpectedly"),
    ],
)
def test_a_workers_error_is_raised_here(design, monkeypatch, how, kind, text):
    """A ReducerlabError of a worker arrives as it was raised; any other error, and a
    worker that died, as a ReducerlabError naming the positions; no hang."""
    monkeypatch.setenv(PARENT_ENV, str(os.getpid()))
    monkeypatch.setenv("REDUCERLAB_TEST_FAILURE", how)
    mp = contact_pair(design, 1)
    phis = 2 * np.pi / mp.external.teeth * np.arange(6) / 6
    kwargs = {"grid": ContactGrid(1e-4), "E_star": E_STAR}
    with pytest.raises(kind, match=text), contact_pool(2) as pool:
        pool.positions((mp, 19.1), phis, kwargs, None, _fail_in_worker)


def test_process_count():
    assert contact_processes(1, rigid=False, positions=24) == 1
    assert contact_processes(3, rigid=True, positions=2) == 2
    assert contact_processes(None, rigid=True, positions=24) == 1
    assert contact_processes(None, rigid=False, positions=24) in (1, 2)
    for bad in (0, 1.5, True, "2"):
        with pytest.raises(ReducerlabError, match="workers"):
            contact_processes(bad, rigid=False, positions=24)
