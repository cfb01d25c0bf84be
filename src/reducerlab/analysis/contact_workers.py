"""The loaded contact analysis on several processes (issue 28).

Two parts of ``contact_analysis`` run on one core for most of their time: the
finite-element tooth compliance of each gear (OpenCASCADE's boolean cut of the sector
solid and gmsh's quadratic nodes) and the loaded contact, position after position. With
``workers`` processes (the command's own and ``workers - 1`` worker processes, started
with ``spawn``: gmsh's global state and the OpenMP runtimes are not fork-safe):

* **the two gears' compliances at once**: the external gear's here, the internal gear's
  in a worker, when the memory estimate of both models together fits
  (``compliance_estimate(..., concurrent=True)``), otherwise one after the other here;
  the sector solids built by the worker join this process's cache
  (``fe.gear_mesh.stored_solids``) and the worker starts with that cache;
* **the positions in contiguous chunks**: the first here, the others in the workers.
  A chunk first recomputes the position before it (its *lead*, dropped) so that it
  starts from that position's contact grid (``s_max``) and active set as the run in one
  process does: every position is solved on the grid the single-process run would use,
  and its solution is the same exact complementarity solution, equal to rounding.

While processes run at once each gets ``cores // workers`` threads (OpenMP, MKL,
OpenBLAS, numba). Workers report their positions through a queue (the progress bar
counts all positions). A worker's error is raised here as soon as it is seen: a
:class:`~reducerlab.errors.ReducerlabError` as it was raised, any other error, or a
worker that died, as a ``ReducerlabError`` naming the part it computed. Workers never
outlive the command (``analysis.workers.worker_pool``).
"""

from __future__ import annotations

import contextlib
import os
import queue as queue_module
import sys
from collections.abc import Callable, Iterator, Sequence
from typing import Any

import numpy as np

from ..errors import ReducerlabError
from ..threads import cores, share_threads

__all__ = ["ContactPool", "contact_pool", "contact_processes", "tooth_compliances"]

Stage = Callable[[str], None]
Progress = Callable[[int, int], None]
#: what each process computes from its positions: a tuple of arrays along the positions
Post = Callable[[list], tuple]

#: the queue of this worker process (its initializer's), for the positions it solves
_QUEUE: Any = None
#: seconds between looks at the workers while waiting for them
_POLL = 0.2


def contact_processes(workers: int | None, *, rigid: bool, positions: int) -> int:
    """Number of processes for a contact analysis.

    Parameters
    ----------
    workers : int, optional
        As given: ``None`` chooses 2 where the machine has at least two cores and the
        teeth are elastic (finite-element models; ``rigid`` runs are quick), else 1.
    rigid : bool
        The analysis has no finite-element models.
    positions : int
        Mesh positions.

    Returns
    -------
    int
        At least 1; never more than ``positions`` (a chunk holds one position at least).
    """
    if workers is None:
        n = 1 if rigid else min(2, cores())
    elif isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise ReducerlabError(f"workers: must be an integer >= 1; got {workers!r}")
    else:
        n = workers
    return max(1, min(n, positions))


def _init_worker(progress: Any, threads: int) -> None:
    """Initializer of a contact worker: its progress queue and its thread share (the
    variables reach the libraries loaded from now on; ``share_threads`` the rest)."""
    global _QUEUE
    _QUEUE = progress
    for name in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
        os.environ[name] = str(threads)


def _warm() -> None:
    """A worker's first task: import what the contact analysis uses and start its
    thread pools (while this process still prepares)."""
    from ..contact import compliance, ltca  # noqa: F401
    from ..fe import gear_mesh  # noqa: F401

    with share_threads(1):
        pass


def _compliance_task(
    flank: Any, material: Any, tooth_size: float | None, solids: dict, threads: int,
    root_stress: bool = False,
) -> tuple[Any, dict]:  # fmt: skip
    """One gear's tooth compliance in a worker; also the sector solids it built."""
    from ..contact.compliance import fe_tooth_compliance
    from ..fe.gear_mesh import store_solids, stored_solids

    store_solids(solids)
    with share_threads(threads):
        comp = fe_tooth_compliance(flank, material=material, tooth_size=tooth_size,
                                   root_stress=root_stress)  # fmt: skip
    return comp, {k: v for k, v in stored_solids().items() if k not in solids}


def _positions_task(
    chunk: int, args: tuple, phis: Any, lead: int, kwargs: dict, post: Post, threads: int
) -> tuple[list, tuple]:
    """The loaded contact at ``phis`` in a worker, the first ``lead`` dropped, and
    ``post`` of the positions kept; each position done is put on the queue as
    ``(chunk, done)``."""
    from ..contact.ltca import loaded_contact

    def report(done: int, _total: int) -> None:
        if done > lead and _QUEUE is not None:
            _QUEUE.put((chunk, done - lead))

    with share_threads(threads):
        runs = loaded_contact(*args, phis, **kwargs, progress=report)[lead:]
        return runs, post(runs)


class ContactPool:
    """The worker processes of one contact analysis (:func:`contact_pool`).

    Attributes
    ----------
    processes : int
        This process and its workers.
    threads : int
        Threads of each process while they run at once.
    """

    def __init__(self, pool: Any, progress: Any, processes: int, threads: int) -> None:
        self.pool = pool
        self.queue = progress
        self.processes = processes
        self.threads = threads
        with _main_not_imported():  # the workers start now
            self.warm = [pool.submit(_warm) for _ in range(processes - 1)]

    def _result(self, future: Any, what: str) -> Any:
        """The result of ``future``, a worker's error raised as a ReducerlabError."""
        from concurrent.futures.process import BrokenProcessPool

        try:
            return future.result()
        except ReducerlabError:
            raise
        except BrokenProcessPool as exc:
            raise ReducerlabError(
                f"contact: the worker process computing {what} ended unexpectedly ({exc}); "
                "run it in one process (workers=1, --workers 1)"
            ) from None
        except Exception as exc:
            raise ReducerlabError(
                f"contact: the worker process computing {what} failed: {type(exc).__name__}: {exc}"
            ) from exc

    def _check(self, futures: dict) -> None:
        """Raise at once the error of any worker that has failed."""
        for future, what in futures.items():
            if future.done() and future.exception() is not None:
                self._result(future, what)

    def compliance(self, flanks: Sequence[Any], material: Any, tooth_size: float | None,
                   say: Stage, root_stress: bool = False) -> tuple[Any, Any]:  # fmt: skip
        """Both gears' tooth compliances at once: ``flanks[0]`` here, ``flanks[1]`` in a
        worker (``contact.compliance.fe_tooth_compliance``; ``root_stress``: with the
        fillet stress influence)."""
        from ..contact.compliance import fe_tooth_compliance
        from ..fe.gear_mesh import store_solids, stored_solids

        what = "the internal gear's tooth compliance"
        future = self.pool.submit(_compliance_task, flanks[1], material, tooth_size,
                                  stored_solids(), self.threads, root_stress)  # fmt: skip
        futures = {**dict.fromkeys(self.warm, "its start"), future: what}

        def stage(text: str) -> None:
            self._check(futures)
            say(f"{text} (external gear; internal gear in a worker process)")

        say("finite-element compliance of both gears' teeth (two processes)")
        with share_threads(self.threads):
            comp_a = fe_tooth_compliance(flanks[0], material=material, tooth_size=tooth_size,
                                         stage=stage, root_stress=root_stress)  # fmt: skip
        say("finite-element compliance of the internal gear's teeth (worker process)")
        comp_b, solids = self._result(future, what)
        store_solids(solids)
        return comp_a, comp_b

    def positions(self, args: tuple, phis: Any, kwargs: dict, progress: Progress | None,
                  post: Post) -> tuple[list, tuple]:  # fmt: skip
        """``loaded_contact(*args, phis, **kwargs)`` in contiguous chunks, the first
        here, each other one in a worker after its lead position; and ``post`` (picklable)
        of each chunk's positions, where they were computed, its arrays joined."""
        from concurrent.futures import FIRST_EXCEPTION, wait

        from ..contact.ltca import loaded_contact

        n, total = self.processes, len(phis)
        # a worker's chunk: its positions and its lead, the same work as the first's
        size = max(1, (total + n - 1) // n - 1)
        starts = [total - size * (n - k) for k in range(n)]
        starts[0] = 0
        bounds = [*starts, total]
        done = [0] * n
        futures = {}
        for k in range(1, n):
            s, e = bounds[k], bounds[k + 1]
            future = self.pool.submit(_positions_task, k, args, phis[s - 1 : e], 1, kwargs,
                                      post, self.threads)  # fmt: skip
            futures[future] = f"the loaded contact at positions {s + 1}-{e}"
        futures.update(dict.fromkeys(self.warm, "its start"))

        def drain() -> None:
            changed = False
            with contextlib.suppress(queue_module.Empty):
                while True:
                    chunk, count = self.queue.get_nowait()
                    done[chunk] = max(done[chunk], count)
                    changed = True
            if changed and progress is not None:
                progress(sum(done), total)

        def own(count: int, _total: int) -> None:
            self._check(futures)
            done[0] = count
            drain()
            if progress is not None:
                progress(sum(done), total)

        with share_threads(self.threads):
            runs = loaded_contact(*args, phis[: bounds[1]], **kwargs, progress=own)
            parts = [post(runs)]
        pending = set(futures)
        while pending:
            _, pending = wait(pending, timeout=_POLL, return_when=FIRST_EXCEPTION)
            drain()
            self._check(futures)
        for future, what in futures.items():
            if future not in self.warm:
                more, part = self._result(future, what)
                runs.extend(more)
                parts.append(part)
        return runs, tuple(np.concatenate(arrays) for arrays in zip(*parts, strict=True))


@contextlib.contextmanager
def _main_not_imported() -> Iterator[None]:
    """Within: workers started do not import the script that runs this process (their
    tasks live in this package; a script without an ``if __name__ == "__main__"``
    guard would otherwise run again in each worker)."""
    main = sys.modules.get("__main__")
    saved = {k: main.__dict__[k] for k in ("__spec__", "__file__") if k in vars(main)}
    try:
        main.__spec__ = None
        vars(main).pop("__file__", None)
        yield
    finally:
        vars(main).update(saved)


@contextlib.contextmanager
def contact_pool(processes: int) -> Iterator[ContactPool | None]:
    """The worker processes of a contact analysis on ``processes`` processes (this one
    included); ``None`` for one process. Workers start now (``spawn``) and end with the
    block, at once when it raises (``analysis.workers.worker_pool``)."""
    if processes <= 1:
        yield None
        return
    import multiprocessing

    from .workers import worker_pool

    ctx = multiprocessing.get_context("spawn")
    progress = ctx.Queue()
    threads = max(1, cores() // processes)
    try:
        with worker_pool(processes - 1, "spawn", _init_worker, (progress, threads)) as pool:
            yield ContactPool(pool, progress, processes, threads)
    finally:
        progress.close()
        progress.cancel_join_thread()


def tooth_compliances(
    pair: Any, material: Any, tooth_size: float | None, say: Stage, pool: ContactPool | None,
    root_stress: bool = False,
) -> tuple[Any, Any]:  # fmt: skip
    """The external and internal gears' tooth compliances of ``pair``
    (``contact.compliance.fe_tooth_compliance``; ``root_stress``: with the fillet
    stress influence): at once on ``pool`` where its memory estimate of both models
    together fits, else one after the other here."""
    from ..budget import memory_limit
    from ..contact.compliance import compliance_estimate, fe_tooth_compliance

    both = None if pool is None else compliance_estimate(pair, tooth_size, concurrent=True,
                                                         root_stress=root_stress)  # fmt: skip
    if both is not None and both.memory <= memory_limit():
        return pool.compliance((pair.flank_a, pair.flank_b), material, tooth_size, say,
                               root_stress)  # fmt: skip
    say("finite-element compliance of the external gear's teeth")
    comp_a = fe_tooth_compliance(pair.flank_a, material=material, tooth_size=tooth_size,
                                 stage=say, root_stress=root_stress)  # fmt: skip
    say("finite-element compliance of the internal gear's teeth")
    comp_b = fe_tooth_compliance(pair.flank_b, material=material, tooth_size=tooth_size,
                                 stage=say, root_stress=root_stress)  # fmt: skip
    return comp_a, comp_b
