"""A second process that builds area geometry (:func:`networks.areas.run_job`).

Threads of one Python process share the GIL: the grouping of curves (Python) and the
Python side of each shapely call keep two threads building areas at about 1.5 times the
speed of one on two cores. A second process has its own interpreter: while this process
groups one part of a batch and builds its geometry, the worker builds the other part's
(:func:`networks.areas.build_areas`). It gets a :class:`~networks.areas.Job` (plain arrays
and index rows, no network) and sends back the areas as WKB, which is exact: the geometry
is the same as if this process had built it.

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
from pathlib import Path
from typing import IO

import numpy as np
import shapely

from networks.areas import Job, run_job

_LENGTH = struct.Struct("<Q")

#: Seconds a worker is given to stop when asked, before it is killed.
STOP_TIMEOUT_S = 5.0


class AreaWorker:
    """A running worker process: :meth:`send` a job, then :meth:`receive` its areas."""

    def __init__(self, proc: subprocess.Popen):
        self.proc = proc
        #: What the job queued last is for (kept by :func:`networks.areas.build_areas`).
        self.pending: object | None = None
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


def _write(stream: IO[bytes] | None, data: bytes) -> None:
    if stream is None:
        raise OSError("no pipe")
    stream.write(_LENGTH.pack(len(data)))
    stream.write(data)
    stream.flush()


def _read(stream: IO[bytes] | None) -> bytes | None:
    """One message; None at the end of the stream."""
    if stream is None:
        return None
    head = stream.read(_LENGTH.size)
    if len(head) < _LENGTH.size:
        return None
    (n,) = _LENGTH.unpack(head)
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


if __name__ == "__main__":
    import gc  # noqa: I001

    gc.disable()  # jobs make no reference cycles; everything is freed by reference counts
    raise SystemExit(serve(sys.stdin.buffer, sys.stdout.buffer))
