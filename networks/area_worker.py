"""A second process that builds area geometry (:func:`networks.areas.run_job`).

Threads of one Python process share the GIL: the grouping of curves (Python) and the
Python side of each shapely call keep two threads building areas at about 1.5 times the
speed of one on two cores. A second process has its own interpreter: while this process
groups a large batch's curves and builds the geometry of one part of them, the worker
builds the other part's (:func:`build_in_two`). It gets a :class:`~networks.areas.Job`
(plain arrays and index rows, no network) and sends back the areas as WKB, which is
exact: the geometry is the same as if this process had built it.

Jobs are queued: a thread writes them and another reads the answers as they come, so
the worker goes from one job to the next while this process does something else. When
the caller says which curves come next (an :class:`~networks.area_book.AreaBook` read
in order), their parts are queued behind the current one; while the curves are still
being extracted, the first batches' parts are sent as soon as they are complete
(:func:`send_ahead`, from an :class:`~networks.area_book.AreaFeed`). The share of each
batch the worker builds starts at :data:`PROCESS_SHARE` and then follows the measured
cost of each side's work, so that neither waits for the other (:func:`next_share`).

The worker is started on first use (``python -m networks.area_worker``, with one thread:
``CLEARANCE_THREADS=1``), kept for later batches, and told to stop when this process
exits (or it stops by itself when this process's end of the pipe closes). Messages are
pickles, each after a marker and its length. Anything that goes wrong with it (it
cannot start, dies, answers nonsense) makes :func:`worker` give None from then on, and
the caller builds that part itself: a failure costs time, never an area.
"""

from __future__ import annotations

import atexit
import operator
import os
import pickle
import queue
import struct
import subprocess
import sys
import threading
import time
from collections import deque
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

__all__ = ["AreaWorker", "MAX_INFLIGHT", "PROCESS_SHARE", "QUEUED_PARTS", "SHARE_GAIN",
           "SHARE_HORIZON", "SHARE_RANGE", "STOP_TIMEOUT_S", "build_in_two", "give_up", "main",
           "next_share", "send_ahead", "serve", "share", "stop", "use_process", "worker"]

#: Each message: these four bytes, its length in eight, then a pickle. A message that does
#: not start with them (something else wrote to the pipe) ends the exchange.
_MAGIC = b"CAW1"
_HEAD = struct.Struct("<4sQ")

#: Seconds a worker is given to stop when asked, before it is killed.
STOP_TIMEOUT_S = 5.0


class AreaWorker:
    """A running worker process: :meth:`send` it jobs, :meth:`receive` their areas in the
    order the jobs went out.

    A thread writes the jobs and another reads the answers as they come, so that
    :meth:`send` never waits and the worker never waits to write an answer: jobs can be
    queued while this process does something else, and the worker goes from one to the
    next. The parts of runs of curves whose answers are not read yet are kept in
    :attr:`inflight` (by :func:`build_in_two` and :func:`send_ahead`).
    """

    def __init__(self, proc: subprocess.Popen):
        self.proc = proc
        #: Parts whose jobs were sent and whose answers are not read yet, oldest first.
        self.inflight: deque[_Part] = deque()
        #: (worker's seconds building, seconds it waited for the job) of the last answer read
        self.last_stats: tuple[float, float] = (0.0, 0.0)
        #: Seconds :meth:`receive` waited for the last answer read (negative: how long
        #: that answer had been there, waiting to be read).
        self.last_wait_s = 0.0
        self._jobs: queue.SimpleQueue[bytes | None] = queue.SimpleQueue()
        self._answers: queue.SimpleQueue[tuple[bytes | None, float]] = queue.SimpleQueue()
        self._sent = 0  # jobs sent
        self._taken = 0  # answers read by receive()
        self._arrived = 0  # answers read from the pipe (by the reader thread)
        self._broken = False
        self._threads = [
            threading.Thread(target=self._write_loop, name="area-worker-send", daemon=True),
            threading.Thread(target=self._read_loop, name="area-worker-read", daemon=True),
        ]
        for t in self._threads:
            t.start()

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
        """Queue a job (the worker starts on it when done with those before it); False
        when the worker cannot take it (it failed)."""
        if self._broken or self.proc.poll() is not None:
            return False
        try:
            data = pickle.dumps(job, protocol=pickle.HIGHEST_PROTOCOL)
        except (pickle.PicklingError, TypeError, AttributeError):
            return False
        self._sent += 1
        self._jobs.put(data)
        return True

    @property
    def sent(self) -> int:
        """Jobs sent so far."""
        return self._sent

    def backlog(self) -> int:
        """Jobs sent that the worker has not answered yet (the one it is on included)."""
        return self._sent - self._arrived

    def receive(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """The areas of the oldest job whose answer is not read yet (as
        :func:`networks.areas.run_job` gives them); None when the worker failed (it is
        then of no more use) or no answer is due."""
        if self._taken == self._sent:
            return None
        self._taken += 1
        if self._broken and self._answers.empty():
            return None
        asked = time.perf_counter()
        data, arrived = self._answers.get()
        self.last_wait_s = arrived - asked
        if not data:
            return None
        try:
            own, roadway, paved, stats = pickle.loads(data)  # noqa: S301 - our own child
            self.last_stats = (float(stats[0]), float(stats[1]))
            return shapely.from_wkb(own), shapely.from_wkb(roadway), shapely.from_wkb(paved)
        except Exception:  # noqa: BLE001 - whatever came back, the caller builds it itself
            return None

    def _write_loop(self) -> None:
        while (data := self._jobs.get()) is not None:
            try:
                _write(self.proc.stdin, data)
            except (OSError, ValueError):
                self._broken = True
                return

    def _read_loop(self) -> None:
        while True:
            try:
                data = _read(self.proc.stdout)
            except (OSError, ValueError):
                data = None
            if data is None:
                self._broken = True
                self._answers.put((None, time.perf_counter()))
                return
            self._arrived += 1
            self._answers.put((data, time.perf_counter()))

    def stop(self) -> None:
        """Ask the worker to stop (its input closes) and wait for it. One with a job or an
        answer still in flight (nobody will read that answer) is killed at once."""
        if self._taken != self._sent:
            self.proc.kill()
        self._jobs.put(None)
        self._threads[0].join(STOP_TIMEOUT_S)
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
        self._threads[1].join(STOP_TIMEOUT_S)
        self._broken = True
        self._taken = self._sent
        self.inflight.clear()


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
    """Stop this process's worker now (a later :func:`worker` starts a new one, at the
    first share)."""
    global _WORKER, _BALANCE
    _BALANCE = _Balance()
    if _WORKER is not None and _WORKER[1] is not None and _WORKER[0] == os.getpid():
        _WORKER[1].stop()
    _WORKER = None


def build_in_two(
    index: AreaIndex,
    curves: Sequence[Curve],
    ahead: Sequence[Sequence[Curve]] = (),
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The areas of a large run of curves (as :func:`networks.areas.build_areas` gives
    them), :func:`share` of them built by the worker process while this thread groups
    all of them and builds the rest. ``ahead``: the runs likely asked for next, in order;
    their worker parts are queued behind this one's (up to :data:`QUEUED_PARTS` unanswered
    jobs). None when no worker is to be used (``CLEARANCE_PROCESS=0``, none can be
    started or it failed, or the curves are all at one junction, or another thread is
    using the worker): the caller builds them itself.
    """
    if not use_process():
        return None
    if not _LOCK.acquire(blocking=False):  # another thread is using the worker
        return None
    try:
        helper = worker()
        if helper is None:
            return None
        return _build_with(helper, index, curves, ahead)
    finally:
        _LOCK.release()


def send_ahead(index: AreaIndex, curves: Sequence[Curve]) -> bool:
    """Give the worker its part of a run of curves now, to be read later by
    :func:`build_in_two` (e.g. while the rest of the curves are still being extracted:
    :class:`networks.area_book.AreaFeed`). False when it is not sent: no worker is to be
    used, it already has :data:`QUEUED_PARTS` jobs to answer or :data:`MAX_INFLIGHT`
    answers to be read (offer it again later), or the run is too small to be built in
    two."""
    if len(curves) < areas.HALVES_MIN or not areas._may_split() or not use_process():
        return False
    if not _LOCK.acquire(blocking=False):
        return False
    try:
        helper = worker()
        if helper is None or helper.backlog() >= QUEUED_PARTS:
            return False
        if len(helper.inflight) >= MAX_INFLIGHT:
            return False
        return _queue(helper, index, curves)
    finally:
        _LOCK.release()


#: Held while a thread exchanges jobs and answers with the worker (one at a time: the
#: answers come back in the order the jobs went out).
_LOCK = threading.Lock()

#: Jobs queued for the worker (the one it is on included) beyond which no more is sent
#: ahead: enough that it goes straight from one to the next.
QUEUED_PARTS = 2

#: Parts sent whose answers are not read yet beyond which no more is sent ahead (the
#: answers wait in memory, about 10 MB each for a batch of 8192 curves).
MAX_INFLIGHT = 8


class _Part(NamedTuple):
    """The part of a run of curves given to the worker process."""

    curves: Sequence[Curve]
    cut: int  # the worker builds ``curves[cut:]``
    of: np.ndarray  # the roadway and paved group of each of those curves
    job: Job
    ahead: bool  # queued by a read in order: the worker's wait for it was ours


def _same(a: Sequence[Curve], b: Sequence[Curve]) -> bool:
    """Whether two runs are the same curves (the same objects, in the same order)."""
    return a is b or (len(a) == len(b) and all(map(operator.is_, a, b)))


def _queue(
    helper: AreaWorker, index: AreaIndex, curves: Sequence[Curve], ahead: bool = False
) -> bool:
    """Group the worker's part of a run of curves (from where :func:`share` cuts it),
    make its job and send it; False when it is not sent (no cut, or the worker failed)."""
    cut = areas._halfway(curves, 1.0 - share())
    if not cut:
        return False
    t0 = time.perf_counter()
    plan = BatchPlan(index)
    of = np.array([plan.add(c) for c in curves[cut:]], dtype=np.intp)
    part = _Part(curves, cut, of, areas.make_job(plan, curves[cut:]), ahead)
    if not helper.send(part.job):
        return False
    _BALANCE.measured("plan", time.perf_counter() - t0, len(curves) - cut)
    helper.inflight.append(part)
    return True


def _build_with(
    helper: AreaWorker,
    index: AreaIndex,
    curves: Sequence[Curve],
    ahead: Sequence[Sequence[Curve]],
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """:func:`~networks.areas.build_areas` with part of the curves built by the worker
    process (sent now, or earlier); None when the worker failed before it got them or
    there is no cut."""
    if not any(_same(p.curves, curves) for p in helper.inflight):
        # others' answers come first: read and dropped (work lost, never a wrong area)
        while helper.inflight:
            helper.inflight.popleft()
            if helper.receive() is None:
                give_up()
                return None
        if not _queue(helper, index, curves):
            if helper.proc.poll() is not None or helper._broken:
                give_up()
            return None
    while not _same(helper.inflight[0].curves, curves):  # runs skipped over: dropped
        helper.inflight.popleft()
        if helper.receive() is None:
            give_up()
            return None
    part = helper.inflight.popleft()
    t0 = time.perf_counter()
    first = areas.build_alone(index, curves[: part.cut])  # the other core is the worker's
    _BALANCE.measured("own", time.perf_counter() - t0, part.cut)
    for nxt in ahead:  # queued now, so that the worker goes straight on with them
        if helper.backlog() >= QUEUED_PARTS or len(helper.inflight) >= MAX_INFLIGHT:
            break
        if any(_same(p.curves, nxt) for p in helper.inflight):
            continue
        if len(nxt) < areas.HALVES_MIN or not _queue(helper, index, nxt, ahead=True):
            break
    got = helper.receive()
    if got is None:  # the worker failed: this part is built here, and later ones too
        give_up()
        got = run_job(part.job)
    else:
        _BALANCE.answered(part, helper.last_wait_s, *helper.last_stats)
    own, roadway, paved = got
    second = own, roadway[part.of[:, 0]], paved[part.of[:, 1]]
    own, roadway, paved = (np.concatenate(p) for p in zip(first, second, strict=True))
    return own, roadway, paved


def use_process() -> bool:
    """Whether large batches use a worker process (not when the environment variable
    ``CLEARANCE_PROCESS`` is ``0``)."""
    return os.environ.get("CLEARANCE_PROCESS", "1").strip() != "0"


#: The share of a large batch's curves a worker process builds at first (this process
#: also groups the worker's curves and reads back its areas); then it follows what each
#: side's work is measured to cost (:func:`next_share`).
PROCESS_SHARE = 0.65

#: The range the share is kept in.
SHARE_RANGE = (0.3, 0.9)

#: How far the share moves towards the balance each time (0: it stays at
#: :data:`PROCESS_SHARE`; 1: all the way).
SHARE_GAIN = 0.5

#: Batches over which one side's lead on the other is to be made up.
SHARE_HORIZON = 8


def next_share(
    at: float, lead_s: float, curves: int, own: float, plan: float, run: float
) -> float:
    """The share after an answer, from the share ``at`` used now and what the work is
    measured to cost, in seconds per curve: ``own`` this process building its part,
    ``plan`` this process grouping the worker's part and sending it, ``run`` the worker
    building it. For a batch of ``curves`` curves cut at share ``s`` this process then
    spends ``curves * (s * plan + (1 - s) * own)`` and the worker ``curves * s * run``;
    the balance is the share at which the worker spends ``lead_s / SHARE_HORIZON`` more
    (``lead_s``: how far the worker was ahead on the last answer: it waited for its job,
    or its answer waited to be read; negative: this process waited for the answer). The
    share moves :data:`SHARE_GAIN` of the way there, within :data:`SHARE_RANGE`.

    Examples
    --------
    >>> next_share(0.6, 0.0, 8192, 150e-6, 40e-6, 170e-6)  # balance: 150 / 280 = 0.536
    0.568
    >>> next_share(0.6, 4.0, 8192, 150e-6, 40e-6, 170e-6)  # the worker 4 s ahead: 0.754
    0.677
    >>> next_share(0.6, 0.0, 8192, 0.0, 0.0, 0.0)  # nothing measured yet
    0.6
    """
    if min(own, run) <= 0.0 or curves <= 0 or own + run - plan <= 0.0:
        return at
    balance = (own + lead_s / (SHARE_HORIZON * curves)) / (own + run - plan)
    low, high = SHARE_RANGE
    return round(min(max(at + SHARE_GAIN * (balance - at), low), high), 3)


class _Balance:
    """The share of large batches the worker builds (:func:`share`), from the cost of
    each side's work per curve (averaged over the last measures)."""

    def __init__(self) -> None:
        self.share = PROCESS_SHARE
        self.cost = {"own": 0.0, "plan": 0.0, "run": 0.0}

    def measured(self, what: str, seconds: float, curves: int) -> None:
        if curves > 0:
            per = seconds / curves
            self.cost[what] = per if not self.cost[what] else 0.5 * (self.cost[what] + per)

    def answered(self, part: _Part, wait_s: float, run_s: float, idle_s: float) -> None:
        """After a part's answer was read, this process having waited ``wait_s`` for it
        (negative: the answer waited) and the worker having built it in ``run_s`` after
        waiting ``idle_s`` for the job (counted only when the job was queued ahead by a
        read in order: this process was late with it; otherwise the worker waited for a
        caller to ask at all)."""
        self.measured("run", run_s, len(part.curves) - part.cut)
        lead = (idle_s if part.ahead else 0.0) - wait_s
        cost = self.cost
        self.share = next_share(
            self.share, lead, len(part.curves), cost["own"], cost["plan"], cost["run"]
        )


_BALANCE = _Balance()


def share() -> float:
    """The share of a run of curves the worker builds now."""
    return _BALANCE.share


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
    ``out`` with (seconds building it, seconds waiting for it); an empty message when a
    job fails. Return at the end of ``inp``."""
    idle_from = time.perf_counter()
    while (data := _read(inp)) is not None:
        start = time.perf_counter()
        try:
            own, roadway, paved = run_job(pickle.loads(data))  # noqa: S301 - from our parent
            stats = (time.perf_counter() - start, start - idle_from)
            reply = pickle.dumps(
                (shapely.to_wkb(own), shapely.to_wkb(roadway), shapely.to_wkb(paved), stats),
                protocol=pickle.HIGHEST_PROTOCOL,
            )
        except Exception:  # noqa: BLE001 - the parent builds it and sees the error itself
            reply = b""
        _write(out, reply)
        idle_from = time.perf_counter()
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
