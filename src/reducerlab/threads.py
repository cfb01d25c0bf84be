"""One threading policy for the process (issue 28).

Three thread pools can be loaded at once: OpenBLAS's (scipy's and numpy's dense LAPACK,
POSIX threads), libgomp's (the OpenMP runtime of numba's parallel kernels, whose
threading layer resolves to ``omp`` here, and of MKL's PARDISO, built with GNU
threading) and, where installed, TBB's. Left alone, OpenBLAS and libgomp each start one
thread per core and keep them spinning after every call: on two cores, the contact
analysis, which alternates numba kernels with ~1000x1000 Cholesky factorisations,
factorised at 0.5 GFLOP/s where the same factorisation alone runs at 40-60 GFLOP/s
(``benchmarks/threads.py``).

The policy: inside the package's heavy analyses (:func:`compute_threads`, used by the
loaded contact, the FE tooth compliance, the gear-body modes and ``reducerlab run``),
OpenBLAS runs on one thread and libgomp keeps every core: numba's kernels and PARDISO
share the one OpenMP pool, and the dense factorisations, which are small (a contact
step's active set, ARPACK's Lanczos vectors), run where they were called. Outside
them every pool is as the user left it. ``REDUCERLAB_THREADS=off`` disables the policy
(the pools as loaded: the comparison of the benchmark).
"""

from __future__ import annotations

import contextlib
import functools
import os
from collections.abc import Callable, Iterator
from typing import Any, TypeVar

__all__ = [
    "THREADS_ENV",
    "compute_threads",
    "cores",
    "policy_active",
    "pools",
    "share_threads",
    "with_compute_threads",
]

#: Environment variable: ``off`` leaves every thread pool as loaded.
THREADS_ENV = "REDUCERLAB_THREADS"

F = TypeVar("F", bound=Callable[..., Any])


def policy_active() -> bool:
    """Whether the policy applies (``REDUCERLAB_THREADS`` is not ``off``/``0``)."""
    return os.environ.get(THREADS_ENV, "").strip().lower() not in ("off", "0", "no", "false")


def pools() -> list[dict[str, Any]]:
    """The thread pools loaded in the process now: ``{"api", "library", "threads"}`` each
    (threadpoolctl's view)."""
    from threadpoolctl import threadpool_info

    return [
        {
            "api": p["internal_api"],
            "library": os.path.basename(p["filepath"]),
            "threads": int(p["num_threads"]),
        }
        for p in threadpool_info()
    ]


@contextlib.contextmanager
def compute_threads() -> Iterator[None]:
    """Within: OpenBLAS on one thread, every other pool as it was; restored on exit
    (also on an exception). Re-entrant: an inner use changes nothing."""
    if not policy_active():
        yield
        return
    from threadpoolctl import ThreadpoolController

    # a controller made now: it sees the libraries loaded so far (PARDISO's MKL may
    # have been loaded since the last call)
    openblas = ThreadpoolController().select(internal_api="openblas")
    with openblas.limit(limits=1):
        yield


def with_compute_threads(func: F) -> F:
    """Decorator: run ``func`` under :func:`compute_threads`."""

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        with compute_threads():
            return func(*args, **kwargs)

    wrapper.compute_threads = True  # type: ignore[attr-defined]
    return wrapper  # type: ignore[return-value]


def cores() -> int:
    """Cores this process may run on (its affinity mask where the system has one)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return os.cpu_count() or 1


@contextlib.contextmanager
def share_threads(threads: int) -> Iterator[None]:
    """Within: at most ``threads`` threads in every thread pool of this process
    (OpenMP, MKL, OpenBLAS through threadpoolctl; numba's), restored on exit.

    MKL (PARDISO) and numba's OpenMP pool are loaded first, so that the limit reaches
    them too."""
    from threadpoolctl import threadpool_limits

    from .fe.elasticity import import_pypardiso

    import_pypardiso()
    try:
        import numba
    except ImportError:  # pragma: no cover - numba is a dependency
        numba = None
    old = numba.get_num_threads() if numba is not None else None
    if numba is not None:
        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    try:
        with threadpool_limits(limits=threads):
            yield
    finally:
        if numba is not None:
            numba.set_num_threads(old)
