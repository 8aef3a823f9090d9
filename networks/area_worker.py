"""A second process that builds area geometry (:func:`networks.areas.run_job`).

Threads of one Python process share the GIL: the grouping of curves (Python) and the
Python side of each shapely call keep two threads building areas at about 1.5 times the
speed of one on two cores. A second process has its own interpreter: while this process
groups a large batch's curves and builds the geometry of one part of them, the worker
builds the other part's (:func:`build_in_two`, :data:`PROCESS_SHARE` of the curves). It gets
a :class:`~networks.areas.Job` (plain arrays and index rows, no network) and sends back
the areas as WKB, which is exact: the geometry is the same as if this process had built
it. When the caller says which curves come next (an
:class:`~networks.area_book.AreaBook` read in order), their part is queued behind the
current one, so that the worker goes straight on with it.

The worker is started on first use (``python -m networks.area_worker``, with one thread:
``CLEARANCE_THREADS=1``), kept for later batches, and told to stop when this process
exits (or it stops by itself when this process's end of the pipe closes). Messages are
pickles, each after its length in eight bytes. Anything that goes wrong with it (it
cannot start, dies, answers nonsense) makes :func:`worker` give None from then on, and
the caller builds that part itself: a failure costs time, never an area.
"""

from __future__ import annotations

import atexit
import os
import pickle
import struct
import subprocess
import sys
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import IO, TYPE_CHECKING, NamedTuple

import numpy as np
import shapely

from networks import areas
from networks.area_groups import AreaIndex, BatchPlan
from networks.areas import Job, run_job

if TYPE_CHECKING:
    from networks.curves import Curve

#: Each message: these four bytes, its length in eight, then a pickle. A message that does
#: not start with them (something else wrote to the pipe) ends the exchange.
_MAGIC = b"CAW1"
_HEAD = struct.Struct("<4sQ")

#: Seconds a worker is given to stop when asked, before it is killed.
STOP_TIMEOUT_S = 5.0


class AreaWorker:
    """A running worker process: :meth:`send` a job, then :meth:`receive` its areas."""

    def __init__(self, proc: subprocess.Popen):
        self.proc = proc
        #: The part whose job was queued behind the last one (kept by :func:`build_in_two`).
        self.pending: _Part | None = None
        self._writer: threading.Thread | None = None
        self._sent = True
        self._waiting = 0  # jobs sent (or being sent) whose answers are not read yet

    @classmethod
    def start(cls) -> AreaWorker | None:
        """Start a worker process; None when it cannot be started."""
        env = dict(os.environ)
        root = str(Path(__file__).resolve().parents[1])
        env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
        env["CLEARANCE_THREADS"] = "1"  # the other core is this process's
        try:
            proc = subprocess.Popen(
                [sys.executable, "-m", "networks.area_worker"],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL,
                env=env,
            )
        except OSError:
            return None
        return cls(proc)

    def send(self, job: Job) -> bool:
        """Give the worker a job (it starts at once); False when it cannot take it."""
        if not self._join():
            return False
        try:
            _write(self.proc.stdin, pickle.dumps(job, protocol=pickle.HIGHEST_PROTOCOL))
        except (OSError, ValueError, pickle.PicklingError):
            return False
        self._waiting += 1
        return True

    def send_behind(self, job: Job) -> None:
        """Queue a job behind the one the worker is on, without waiting: a thread writes
        it while this one reads the current answer (the worker reads its next job only
        once it has written its answer, which may not fit in the pipe)."""
        if not self._join():
            return
        data = pickle.dumps(job, protocol=pickle.HIGHEST_PROTOCOL)
        self._sent = False
        self._waiting += 1

        def write() -> None:
            try:
                _write(self.proc.stdin, data)
                self._sent = True
            except (OSError, ValueError):
                pass

        self._writer = threading.Thread(target=write, name="area-worker-send", daemon=True)
        self._writer.start()

    def _join(self) -> bool:
        """Wait for a job being written (True when it was, or none was)."""
        if self._writer is not None:
            self._writer.join()
            self._writer = None
        return self._sent

    def receive(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """The areas of the oldest job not answered yet (as :func:`networks.areas.run_job`
        gives them); None when the worker failed (it is then of no more use)."""
        if self._waiting == 0:
            return None
        self._waiting -= 1
        try:
            # the only job left may still be being written: it must be read to be answered
            if self._waiting == 0 and not self._join():
                return None
            data = _read(self.proc.stdout)
            if not data:
                return None
            own, roadway, paved = pickle.loads(data)  # noqa: S301 - our own child process
            return shapely.from_wkb(own), shapely.from_wkb(roadway), shapely.from_wkb(paved)
        except Exception:  # noqa: BLE001 - whatever came back, the caller builds it itself
            return None

    def stop(self) -> None:
        """Ask the worker to stop (its input closes) and wait for it. One with a job or an
        answer still in flight (nobody will read that answer, and it would wait to write
        it) is killed at once, which also frees a thread still writing a job to it."""
        if self._waiting or self._writer is not None:
            self.proc.kill()
        try:
            if self.proc.stdin is not None:
                self.proc.stdin.close()
        except OSError:
            pass
        try:
            self.proc.wait(timeout=STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        if self._writer is not None:
            self._writer.join()
            self._writer = None
        self._waiting = 0


_WORKER: tuple[int, AreaWorker | None] | None = None


def worker() -> AreaWorker | None:
    """This process's worker (started on first use); None when it could not be started
    or has failed before."""
    global _WORKER
    if _WORKER is None or _WORKER[0] != os.getpid():  # a forked child makes its own
        started = AreaWorker.start()
        _WORKER = (os.getpid(), started)
        if started is not None:
            atexit.register(started.stop)
    return _WORKER[1]


def give_up() -> None:
    """Stop using this process's worker (after it failed): the caller builds everything."""
    global _WORKER
    if _WORKER is not None and _WORKER[1] is not None and _WORKER[0] == os.getpid():
        _WORKER[1].stop()
    _WORKER = (os.getpid(), None)


def stop() -> None:
    """Stop this process's worker now (a later :func:`worker` starts a new one)."""
    global _WORKER
    if _WORKER is not None and _WORKER[1] is not None and _WORKER[0] == os.getpid():
        _WORKER[1].stop()
    _WORKER = None


def build_in_two(
    index: AreaIndex, curves: Sequence[Curve], ahead: Sequence[Curve] | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The areas of a large run of curves (as :func:`networks.areas.build_areas` gives
    them), :data:`PROCESS_SHARE` of them built by the worker process while this thread
    groups all of them and builds the rest; ``ahead`` (the curves likely asked for next):
    their worker part is queued behind this one's. None when no worker is to be used
    (``CLEARANCE_PROCESS=0``, none can be started or it failed, or the curves are all at
    one junction, or another thread is using the worker): the caller builds them itself.
    """
    if not use_process():
        return None
    if not _LOCK.acquire(blocking=False):  # another thread is using the worker
        return None
    try:
        helper = worker()
        cut = areas._halfway(curves, 1.0 - PROCESS_SHARE)
        if helper is None or not cut:
            return None
        return _build_with(helper, index, curves, cut, ahead)
    finally:
        _LOCK.release()


#: Held while a thread exchanges jobs and answers with the worker (one at a time: the
#: answers come back in the order the jobs went out).
_LOCK = threading.Lock()


class _Part(NamedTuple):
    """The part of a run of curves given to the worker process."""

    curves: Sequence[Curve]
    cut: int
    of: np.ndarray
    job: Job


def _worker_part(index: AreaIndex, curves: Sequence[Curve], cut: int) -> _Part:
    """Group the curves from ``cut`` on and make their job (the worker's part)."""
    plan = BatchPlan(index)
    of = np.array([plan.add(c) for c in curves[cut:]], dtype=np.intp)
    return _Part(curves, cut, of, areas.make_job(plan, curves[cut:]))


def _build_with(
    helper: AreaWorker,
    index: AreaIndex,
    curves: Sequence[Curve],
    cut: int,
    ahead: Sequence[Curve] | None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """:func:`~networks.areas.build_areas` with the curves from ``cut`` on built by the
    worker process; None when the worker failed before it got them."""
    part = helper.pending
    helper.pending = None
    if part is None or part.curves is not curves:
        if part is not None and helper.receive() is None:  # another run's: dropped
            give_up()
            return None
        part = _worker_part(index, curves, cut)
        if not helper.send(part.job):
            give_up()
            return None
    first = areas.build_alone(index, curves[: part.cut])  # the other core is the worker's
    nxt = (
        areas._halfway(ahead, 1.0 - PROCESS_SHARE)
        if ahead and len(ahead) >= areas.HALVES_MIN else 0
    )
    if nxt:  # queued now, so that the worker goes straight on with it
        helper.pending = _worker_part(index, ahead, nxt)
        helper.send_behind(helper.pending.job)
    got = helper.receive()
    if got is None:  # the worker failed: this part is built here, and later ones too
        give_up()
        got = run_job(part.job)
    own, roadway, paved = got
    second = own, roadway[part.of[:, 0]], paved[part.of[:, 1]]
    own, roadway, paved = (np.concatenate(p) for p in zip(first, second, strict=True))
    return own, roadway, paved


def use_process() -> bool:
    """Whether large batches use a worker process (not when the environment variable
    ``CLEARANCE_PROCESS`` is ``0``)."""
    return os.environ.get("CLEARANCE_PROCESS", "1").strip() != "0"


#: The share of a large batch's curves a worker process builds (this process also groups
#: the worker's curves and reads back its areas).
PROCESS_SHARE = 0.65


def _write(stream: IO[bytes] | None, data: bytes) -> None:
    if stream is None:
        raise OSError("no pipe")
    stream.write(_HEAD.pack(_MAGIC, len(data)))
    stream.write(data)
    stream.flush()


def _read(stream: IO[bytes] | None) -> bytes | None:
    """One message; None at the end of the stream or when what comes is not a message.

    Examples
    --------
    >>> import io
    >>> pipe = io.BytesIO()
    >>> _write(pipe, b"abc"); _write(pipe, b"")
    >>> _ = pipe.seek(0)
    >>> _read(pipe), _read(pipe), _read(pipe)
    (b'abc', b'', None)
    >>> _read(io.BytesIO(b"hello, world: not a message"))  # e.g. a stray print
    """
    if stream is None:
        return None
    head = stream.read(_HEAD.size)
    if len(head) < _HEAD.size:
        return None
    magic, n = _HEAD.unpack(head)
    if magic != _MAGIC:
        return None
    data = stream.read(n)
    return data if len(data) == n else None


def serve(inp: IO[bytes], out: IO[bytes]) -> int:
    """The worker's loop: build each job read from ``inp``, write its areas as WKB to
    ``out`` (an empty message when a job fails); return at the end of ``inp``."""
    while (data := _read(inp)) is not None:
        try:
            own, roadway, paved = run_job(pickle.loads(data))  # noqa: S301 - from our parent
            reply = pickle.dumps(
                (shapely.to_wkb(own), shapely.to_wkb(roadway), shapely.to_wkb(paved)),
                protocol=pickle.HIGHEST_PROTOCOL,
            )
        except Exception:  # noqa: BLE001 - the parent builds it and sees the error itself
            reply = b""
        _write(out, reply)
    return 0


def main() -> int:
    """The worker process: :func:`serve` standard input, answering on standard output."""
    import gc

    gc.disable()  # jobs make no reference cycles; everything is freed by reference counts
    # the answers go to a copy of the pipe; whatever else writes to standard output (a
    # library's print, at Python or C level) goes to standard error instead
    answers = os.fdopen(os.dup(sys.stdout.fileno()), "wb")
    sys.stdout.flush()
    os.dup2(sys.stderr.fileno(), sys.stdout.fileno())
    return serve(sys.stdin.buffer, answers)


if __name__ == "__main__":
    raise SystemExit(main())
