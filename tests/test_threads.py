"""The process's threading policy (issue 28, ``reducerlab.threads``): inside the heavy
analyses OpenBLAS runs on one thread and every other pool keeps its threads; outside,
and with ``REDUCERLAB_THREADS=off``, every pool is as loaded. The rate it buys is
measured in ``benchmarks/threads.py`` (``benchmarks/RESULTS.md``)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg  # loads scipy's OpenBLAS

from reducerlab.threads import THREADS_ENV, compute_threads, pools, with_compute_threads


def _threads(api: str) -> list[int]:
    return [p["threads"] for p in pools() if p["api"] == api]


@pytest.fixture
def two_blas_threads():
    """OpenBLAS on two threads for the test (the CI machine may have set one)."""
    from threadpoolctl import threadpool_limits

    if not _threads("openblas"):
        pytest.skip("no OpenBLAS loaded (numpy and scipy built against another BLAS)")
    with threadpool_limits(limits=2, user_api="blas"):
        yield


def test_openblas_on_one_thread_inside_and_restored(two_blas_threads, monkeypatch):
    monkeypatch.delenv(THREADS_ENV, raising=False)
    before = pools()
    with compute_threads():
        assert set(_threads("openblas")) == {1}
        with compute_threads():  # re-entrant
            assert set(_threads("openblas")) == {1}
        assert set(_threads("openblas")) == {1}
        # every other pool untouched
        others = [(p["api"], p["library"], p["threads"]) for p in pools() if p["api"] != "openblas"]
        assert others == [
            (p["api"], p["library"], p["threads"]) for p in before if p["api"] != "openblas"
        ]
    assert pools() == before


def test_restored_after_an_exception(two_blas_threads, monkeypatch):
    monkeypatch.delenv(THREADS_ENV, raising=False)
    before = pools()

    @with_compute_threads
    def fails() -> None:
        assert set(_threads("openblas")) == {1}
        raise ValueError("inside")

    with pytest.raises(ValueError, match="inside"):
        fails()
    assert pools() == before


@pytest.mark.parametrize("value", ["off", "0", "OFF"])
def test_off_leaves_every_pool(two_blas_threads, monkeypatch, value):
    monkeypatch.setenv(THREADS_ENV, value)
    before = pools()
    with compute_threads():
        assert pools() == before


def test_the_heavy_analyses_run_under_the_policy():
    """The entry points of the loaded contact, the FE tooth compliance, the gear-body
    modes and the whole chain are wrapped (their docstrings and signatures kept)."""
    from reducerlab.analysis.body_modal import body_modal
    from reducerlab.analysis.contact import contact_analysis
    from reducerlab.contact.compliance import fe_tooth_compliance
    from reducerlab.pipeline import run

    for f in (body_modal, contact_analysis, fe_tooth_compliance, run):
        chain = []
        g = f
        while g is not None:
            chain.append(g)
            g = getattr(g, "__wrapped__", None)
        assert any(getattr(c, "compute_threads", False) for c in chain), f
        assert f.__doc__ and "Parameters" in f.__doc__


def test_results_equal_with_and_without(monkeypatch):
    """The policy changes threads, not numbers: a factorisation inside equals one
    outside to round-off."""
    rng = np.random.default_rng(1)
    B = rng.standard_normal((300, 300))
    A = B @ B.T + 300 * np.eye(300)
    monkeypatch.delenv(THREADS_ENV, raising=False)
    outside = scipy.linalg.cholesky(A, lower=True)
    with compute_threads():
        inside = scipy.linalg.cholesky(A, lower=True)
    np.testing.assert_allclose(inside, outside, rtol=1e-12, atol=1e-12 * np.abs(A).max())
