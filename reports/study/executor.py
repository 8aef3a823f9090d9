"""One executor for a study's parallel work: local worker processes, or a Dask cluster.

A study's cost is its runs, so runs are what goes out: in batches (tasks), each a picklable
call ``fn(task, shared)`` run in a worker process. Two engines sit behind one small
interface (:class:`Executor`):

:class:`LocalExecutor`
    :class:`concurrent.futures.ProcessPoolExecutor` on this machine (``--workers N``,
    default the number of cores this process may use, :func:`cores`). Workers start from a
    fork server that has imported the study's modules once, so a new worker costs
    milliseconds, not an import of numpy, shapely and numba.
:class:`DaskExecutor`
    A ``dask.distributed`` cluster (``--scheduler tcp://HOST:8786``, or a ``Client`` from
    Python). Tasks are submitted as impure (a retry is run again, not served from Dask's
    cache); files the workers need are sent once to every worker (:meth:`Executor.share`).

Crash isolation (:func:`run_isolated`)
--------------------------------------
libsumo can crash the process it runs in (a segmentation fault). A worker that dies costs
only the tasks it had: every task that was in flight when a worker died is *suspect*
(a local pool cannot say which of its workers died, and all its tasks fail together). When
nothing else is in flight, each suspect runs alone; one that kills its worker when alone is
guilty and is split in halves (``split``), each run alone in turn, down to the single items
that crash, which are reported through ``lost`` with the reason. The other tasks go on in
parallel as before. Results never depend on which worker ran a task.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import logging
import multiprocessing
import os
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any, TypeVar

from clearance.reports.study.lifetime import worker_start
from clearance.vehicles.errors import OptionError

__all__ = ["DaskExecutor", "Executor", "LocalExecutor", "SharedFile", "WorkerLost", "cores",
           "make_executor", "run_isolated", "trim_memory", "trimmed"]

log = logging.getLogger(__name__)

T = TypeVar("T")
R = TypeVar("R")

#: Modules the fork server imports once, so that each worker starts with them loaded.
PRELOAD = ["clearance.reports.study.batch"]


def cores() -> int:
    """The number of cores this process may run on (at least 1).

    ``CLEARANCE_WORKERS`` overrides it when set to a positive integer.

    Examples
    --------
    >>> cores() >= 1
    True
    """
    env = os.environ.get("CLEARANCE_WORKERS", "").strip()
    if env.isdigit() and int(env) >= 1:
        return int(env)
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def trim_memory() -> None:
    """Give the heap's free pages back to the system (glibc's ``malloc_trim``; nothing
    elsewhere).

    A run's envelopes and margins allocate and free many small GEOS geometries; glibc keeps
    the freed pages, and a worker's resident set grew by some 200 MB over a town's batches
    (Brunswick) that it never used again. Trimmed after each task, it stays near what the
    worker holds.

    Examples
    --------
    >>> trim_memory()  # never fails; nothing to see but the resident set
    """
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        libc.malloc_trim(0)
    except (OSError, AttributeError):  # pragma: no cover - not glibc
        pass


def trimmed(fn: Callable[..., R], *args: Any) -> R:
    """``fn(*args)``, then :func:`trim_memory` (what a local worker runs for a task)."""
    try:
        return fn(*args)
    finally:
        trim_memory()


class WorkerLost(RuntimeError):
    """The worker process running a task died (a crash in SUMO, out of memory, a kill)."""


#: A file every worker needs: ``(path here, its bytes or None)``. On a cluster the bytes
#: are a future of data sent once to every worker; a plain tuple, so that Dask hands the
#: task the bytes in its place.
SharedFile = tuple[str, Any]


class Executor(ABC):
    """Runs picklable calls in worker processes; see the module docstring."""

    workers: int
    #: The workers write to this machine's file system, so that a task may write its
    #: files where they go instead of sending them back (a town's exports: 150 MB).
    shares_disk: bool = False

    @abstractmethod
    def submit(self, fn: Callable[..., R], *args: Any) -> Future[R]:
        """Start ``fn(*args)`` in a worker."""

    def wait_any(self, futures: Iterable[Any]) -> set[Any]:
        """The futures of ``futures`` that are done, once at least one is."""
        done, _ = wait(list(futures), return_when=FIRST_COMPLETED)
        return set(done)

    def outcome(self, future: Future[R]) -> R:
        """The result of a finished task; :class:`WorkerLost` when its worker died."""
        try:
            return future.result()
        except BrokenProcessPool as exc:
            raise WorkerLost(f"a worker process died ({exc})") from None

    def recover(self) -> None:
        """Make the executor usable again after a worker died (default: nothing to do)."""
        return None

    def release(self) -> None:
        """Let the workers drop what their finished tasks left them (a study's network, its
        areas, SUMO's copy of it) before different work (the drawings) comes: local workers
        are stopped, and the next task starts fresh ones (default: nothing to do)."""
        return None

    def share(self, path: str | Path) -> SharedFile:
        """Make the file at ``path`` available to every worker (default: by its path)."""
        return (str(path), None)

    @abstractmethod
    def close(self) -> None:
        """Stop the workers once their tasks are done."""

    def abort(self) -> None:
        """Stop the workers now, their tasks with them (the command was stopped or failed:
        :mod:`clearance.reports.study.lifetime`); default: :meth:`close`."""
        self.close()

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, kind: type[BaseException] | None, *exc: object) -> None:
        if kind is None:
            self.close()
        else:
            self.abort()


class LocalExecutor(Executor):
    """Worker processes on this machine (:class:`~concurrent.futures.ProcessPoolExecutor`)."""

    shares_disk = True

    def __init__(self, workers: int | None = None) -> None:
        n = cores() if workers is None else workers
        if not (isinstance(n, int) and n >= 1):
            raise OptionError(f"--workers must be a whole number >= 1, not {workers!r}")
        self.workers = n
        self._context = multiprocessing.get_context("forkserver")
        self._context.set_forkserver_preload(PRELOAD)
        self._pool: ProcessPoolExecutor | None = None

    def _get(self) -> ProcessPoolExecutor:
        if self._pool is None:
            self._pool = ProcessPoolExecutor(self.workers, mp_context=self._context,
                                             initializer=worker_start,
                                             initargs=(os.getpid(),))
        return self._pool

    def submit(self, fn: Callable[..., R], *args: Any) -> Future[R]:
        return self._get().submit(trimmed, fn, *args)

    def recover(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def release(self) -> None:
        self.recover()

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None

    def abort(self) -> None:
        """Kill the workers and forget the pool (``ProcessPoolExecutor`` has no public way
        to stop a running task before Python 3.14: its ``_processes`` are killed)."""
        pool, self._pool = self._pool, None
        if pool is None:
            return
        procs = list(getattr(pool, "_processes", {}).values())
        for proc in procs:
            proc.kill()
        pool.shutdown(wait=False, cancel_futures=True)
        for proc in procs:
            proc.join(timeout=5)


class DaskExecutor(Executor):
    """Workers of a ``dask.distributed`` cluster, through a ``Client``."""

    def __init__(self, client: Any, own: bool = False) -> None:
        self.client = client
        self._own = own
        n = len(client.scheduler_info().get("workers", {}))
        self.workers = max(1, n)
        self._shared: dict[str, SharedFile] = {}

    @classmethod
    def connect(cls, address: str) -> DaskExecutor:
        """A client of the scheduler at ``address`` (``tcp://HOST:PORT``)."""
        try:
            from distributed import Client
        except ImportError:
            raise OptionError("--scheduler needs dask.distributed: pip install "
                             "'sumo-clearance[cluster]'") from None
        try:
            client = Client(address, timeout="20s")
        except (OSError, TimeoutError) as exc:
            raise OptionError(f"--scheduler {address}: cannot connect: {exc}") from None
        return cls(client, own=True)

    def submit(self, fn: Callable[..., R], *args: Any) -> Future[R]:
        return self.client.submit(fn, *args, pure=False)

    def wait_any(self, futures: Iterable[Any]) -> set[Any]:
        from distributed import wait as dask_wait

        done, _ = dask_wait(list(futures), return_when="FIRST_COMPLETED")
        return set(done)

    def outcome(self, future: Any) -> Any:
        from distributed import KilledWorker

        try:
            return future.result()
        except KilledWorker as exc:
            raise WorkerLost(f"the task's worker died ({exc})") from None

    def share(self, path: str | Path) -> SharedFile:
        key = str(path)
        if key not in self._shared:
            data = Path(path).read_bytes()
            [fut] = self.client.scatter([data], broadcast=True, hash=False)
            self._shared[key] = (key, fut)
        return self._shared[key]

    def close(self) -> None:
        self._shared.clear()
        if self._own:
            self.client.close()


def make_executor(workers: int | None = None, scheduler: str | None = None,
                  client: Any = None) -> Executor:
    """The executor a study asked for: a Dask ``client``, a ``scheduler`` address, or local
    worker processes (``workers``, default :func:`cores`)."""
    if client is not None:
        return DaskExecutor(client)
    if scheduler:
        return DaskExecutor.connect(scheduler)
    return LocalExecutor(workers)


def run_isolated(
    executor: Executor,
    fn: Callable[[T, Any], R],
    tasks: Iterable[T],
    split: Callable[[T], Sequence[T]],
    lost: Callable[[T, str], R],
    shared: Any = None,
    window: int | None = None,
) -> Iterator[tuple[T, R]]:
    """``fn(task, shared)`` for every task in worker processes, as they finish.

    A task whose worker dies is retried alone; one that still kills its worker is cut by
    ``split`` (two or more smaller tasks; a task it cannot cut, ``len < 2``, is given up)
    and each part retried alone, until the parts that crash are single items, for which
    ``lost(task, reason)`` is yielded instead of a result.

    ``window`` bounds the tasks in flight (default: twice the workers).

    Examples
    --------
    >>> with LocalExecutor(1) as ex:   # doctest: +SKIP
    ...     list(run_isolated(ex, pow_task, [[1, 2]], halves, lost))
    """
    window = window or 2 * executor.workers
    queue: deque[T] = deque(tasks)
    suspects: deque[T] = deque()
    flying: dict[Future[Any], T] = {}
    broken = False
    while queue or suspects or flying:
        if not flying and broken:
            executor.recover()
            broken = False
        if suspects and not flying:
            task = suspects.popleft()
            future = executor.submit(fn, task, shared)
            executor.wait_any([future])
            try:
                yield task, executor.outcome(future)
            except WorkerLost as exc:
                executor.recover()
                parts = split(task)
                if len(parts) < 2:
                    log.warning("a task crashed its worker when run alone: %s", exc)
                    yield task, lost(task, str(exc))
                else:
                    suspects.extendleft(reversed(list(parts)))
            continue
        while queue and len(flying) < window and not broken:
            task = queue.popleft()
            try:
                flying[executor.submit(fn, task, shared)] = task
            except BrokenProcessPool:  # a worker died since the last look
                queue.appendleft(task)
                broken = True
        if not flying:
            continue
        for future in executor.wait_any(flying):
            task = flying.pop(future)
            try:
                yield task, executor.outcome(future)
            except WorkerLost as exc:
                log.info("a worker died with a task in flight (%s); it is retried alone", exc)
                suspects.append(task)
                broken = True
