"""Worker processes and Dask clients of the chunked runs (sweep, bifurcation).

Worker processes never outlive the run that started them:

* every worker asks Linux to kill it when its parent dies (``prctl(PR_SET_PDEATHSIG,
  SIGKILL)``), and runs a daemon watchdog thread that exits the worker when its parent
  process changes (the fallback on other systems, and a second guard on Linux: the
  death signal follows the *thread* that created the worker);
* workers ignore ``SIGINT`` and take the default action on ``SIGTERM``: the parent
  decides, and on any exception (Ctrl-C, a ``SIGTERM`` turned into ``SystemExit`` by the
  command line, an error) :func:`worker_pool` cancels the queued chunks and terminates
  the workers at once instead of waiting for the running chunks.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

from ..errors import ReducerlabError

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor

__all__ = ["check_workers", "dask_client", "max_workers", "worker_pool"]

_PR_SET_PDEATHSIG = 1
_WATCHDOG_INTERVAL = 0.25  # s between checks of the parent process


def max_workers() -> int:
    """Largest number of worker processes accepted: 4 per core."""
    return 4 * (os.cpu_count() or 1)


def check_workers(workers: Any, what: str) -> None:
    """Refuse a worker count that is not an integer in ``1..max_workers()``.

    Parameters
    ----------
    workers : Any
        The value given by the user (``None`` is not checked here).
    what : str
        The command, for the message (``"sweep"``, ``"bifurcation"``).
    """
    limit = max_workers()
    if isinstance(workers, bool) or not isinstance(workers, int) or not 1 <= workers <= limit:
        raise ReducerlabError(
            f"{what}: workers must be a positive integer of at most {limit} (4 per core), "
            f"got {workers!r}"
        )


def _set_pdeathsig() -> bool:
    """Ask Linux to SIGKILL this process when its parent (thread) exits."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def _watch_parent(parent: int) -> None:
    """Exit this process at once when its parent process is gone (re-parented)."""
    while True:
        time.sleep(_WATCHDOG_INTERVAL)
        if os.getppid() != parent:
            os._exit(1)


def _guard_worker(
    parent: int, direct: bool, then: Callable[..., None] | None = None, args: tuple = ()
) -> None:
    """Initializer of every worker process (see the module docstring).

    ``parent`` is the pid of the process that made the pool; ``direct`` tells whether
    it is also the worker's parent process (not so under a fork server, which then is
    the process watched: it exits when the pool's process does). ``then(*args)`` runs
    last, when given (the pool's own initializer).
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _set_pdeathsig()
    ppid = os.getppid()
    if ppid == 1 or (direct and ppid != parent):  # gone before the signal was armed
        os._exit(1)
    threading.Thread(target=_watch_parent, args=(ppid,), daemon=True).start()
    if then is not None:
        then(*args)


def _terminate(pool: ProcessPoolExecutor) -> None:
    """Cancel the queued tasks and end the pool's processes now (running tasks are
    lost: their chunks were not written and are computed by the next run)."""
    procs = list((getattr(pool, "_processes", None) or {}).values())
    manager = getattr(pool, "_executor_manager_thread", None)
    pool.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        with contextlib.suppress(Exception):
            p.terminate()
    for p in procs:
        with contextlib.suppress(Exception):
            p.join(2.0)
            if p.is_alive():
                p.kill()
                p.join(1.0)
    if manager is not None:
        # let the pool's manager thread see its dead workers and close its pipes now:
        # left running, it races the interpreter's exit hook of concurrent.futures
        # ("OSError: Bad file descriptor" printed at exit)
        manager.join(5.0)


@contextlib.contextmanager
def worker_pool(
    workers: int,
    context: str | None = None,
    initializer: Callable[..., None] | None = None,
    initargs: tuple = (),
) -> Iterator[ProcessPoolExecutor]:
    """A process pool whose workers cannot outlive this process.

    Create it from the thread that runs the computation (normally the main thread):
    the Linux death signal fires when the creating thread exits; the watchdog thread
    covers the rest within 0.25 s.

    Parameters
    ----------
    workers : int
        Number of processes.
    context : str, optional
        Multiprocessing start method (``"fork"``, ``"spawn"``, ...); default: the
        platform's.
    initializer, initargs : optional
        ``initializer(*initargs)`` in each worker after its guards (objects a process
        may only inherit, such as a ``multiprocessing`` queue, travel in ``initargs``).

    Yields
    ------
    concurrent.futures.ProcessPoolExecutor
        Shut down normally (waiting for its tasks) when the block ends, terminated at
        once when the block raises (including ``KeyboardInterrupt`` and ``SystemExit``).
    """
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    ctx = multiprocessing.get_context(context)
    direct = ctx.get_start_method() != "forkserver"
    pool = ProcessPoolExecutor(
        workers,
        mp_context=ctx,
        initializer=_guard_worker,
        initargs=(os.getpid(), direct, initializer, initargs),
    )
    try:
        yield pool
        pool.shutdown(wait=True)
    except BaseException:
        _terminate(pool)
        raise


@contextlib.contextmanager
def dask_client(scheduler: Any, what: str) -> Iterator[Any]:
    """A ``dask.distributed.Client`` for ``scheduler`` (an address or a client).

    A client passed in is used as is and left open; one made here from an address is
    closed at the end. Failing to import Dask or to connect raises
    :class:`~reducerlab.errors.ReducerlabError` naming the scheduler.

    Parameters
    ----------
    scheduler : str or dask.distributed.Client
    what : str
        The command, for the message.
    """
    try:
        from dask.distributed import Client
    except ImportError as exc:
        raise ReducerlabError(
            f"{what}: running on a Dask scheduler needs dask.distributed "
            f"(pip install 'dask[distributed]'): {exc}"
        ) from None
    if isinstance(scheduler, Client):
        yield scheduler
        return
    try:
        client = Client(scheduler)
    except Exception as exc:  # connection, address and timeout errors
        raise ReducerlabError(
            f"{what}: cannot connect to the Dask scheduler {scheduler!r}: "
            f"{type(exc).__name__}: {exc}"
        ) from None
    try:
        yield client
    finally:
        client.close()
