"""The life of a run's processes: every one ends when the command is stopped, however.

A command stopped by Ctrl-C (``SIGINT``), ``kill`` (``SIGTERM``) or a closed terminal
(``SIGHUP``) unwinds like an error (:func:`stop_on_signals` turns the last two into
:class:`Stopped`, as Python turns the first into :class:`KeyboardInterrupt`): its executor
kills its workers at once (:meth:`clearance.reports.study.executor.Executor.abort`), its output
folder's staging folder and lock are removed and the previous output stays as it was
(:mod:`clearance.reports.output.output_dir`), and it exits with ``128 + signal``.

A command killed outright (``SIGKILL``, which no process can catch) leaves its workers to
notice: each watches the command's process from a thread of its own and exits within
:data:`WATCH_S` of its end (:func:`worker_start`). A worker's parent is the fork server,
which lives as long as any worker holds its pipe, so the kernel's parent-death signal alone
would never come; once the workers are gone the fork server and the resource tracker end
by themselves. The next run into the same folder takes over the lock, which the kernel
released, and removes the staging folder left behind.

Example
-------
>>> import os, signal
>>> with stop_on_signals():
...     try:
...         os.kill(os.getpid(), signal.SIGTERM)
...     except Stopped as exc:
...         print(exc.signal_name, exc.exit_status)
SIGTERM 143
"""

from __future__ import annotations

import ctypes
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

__all__ = ["STOP_SIGNALS", "Stopped", "WATCH_S", "die_with_parent", "in_worker",
           "stop_on_signals", "watch_command", "worker_start"]

#: The signals that stop a command cleanly, besides Ctrl-C's ``SIGINT``.
STOP_SIGNALS = (signal.SIGTERM, signal.SIGHUP)

_PR_SET_PDEATHSIG = 1


class Stopped(BaseException):
    """The command was told to stop (``SIGTERM``, ``SIGHUP``): unwound like Ctrl-C, not
    caught by ``except Exception``."""

    def __init__(self, signum: int):
        super().__init__(f"stopped by {signal.Signals(signum).name}")
        self.signum = signum

    @property
    def signal_name(self) -> str:
        """``SIGTERM``, ``SIGHUP``."""
        return signal.Signals(self.signum).name

    @property
    def exit_status(self) -> int:
        """``128 + signal``, as a shell reports a process the signal stopped."""
        return 128 + self.signum


def _raise(signum: int, frame: FrameType | None) -> None:
    raise Stopped(signum)


@contextmanager
def stop_on_signals() -> Iterator[None]:
    """Inside the block, :data:`STOP_SIGNALS` raise :class:`Stopped` in the main thread
    (the handlers before are put back after). Outside the main thread, nothing changes."""
    if sys.platform == "win32" or not _main_thread():  # pragma: no cover
        yield
        return
    before = {s: signal.signal(s, _raise) for s in STOP_SIGNALS}
    try:
        yield
    finally:
        for s, handler in before.items():
            signal.signal(s, handler)


def _main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def die_with_parent(sig: int = signal.SIGKILL) -> bool:
    """Ask the kernel to send ``sig`` to this process when its parent dies (Linux); True
    when it was arranged. A parent that is already gone is answered at once."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        ok = libc.prctl(_PR_SET_PDEATHSIG, int(sig), 0, 0, 0) == 0
    except (OSError, AttributeError):  # pragma: no cover - not Linux
        return False
    if ok and os.getppid() == 1:  # the parent died before the request: too late for it
        os.kill(os.getpid(), sig)
    return ok


#: How often a worker looks whether its command still runs (s).
WATCH_S = 0.5


def watch_command(pid: int, every_s: float = WATCH_S) -> threading.Thread:
    """A daemon thread that ends this process (``os._exit``) once process ``pid`` is gone.

    >>> watch_command(os.getpid(), 0.01).daemon  # this process runs: nothing happens
    True
    """
    def watch() -> None:
        while True:
            time.sleep(every_s)
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                os._exit(1)
            except PermissionError:  # pragma: no cover - another user's process now
                os._exit(1)

    thread = threading.Thread(target=watch, name="watch-command", daemon=True)
    thread.start()
    return thread


_WORKER = False


def in_worker() -> bool:
    """Whether this process is a local worker (started by :func:`worker_start`): one that
    lives for its command's work alone, not the command's own process or a test's."""
    return _WORKER


def worker_start(command_pid: int | None = None) -> None:
    """What a worker process does first: Ctrl-C is its command's to handle (the command
    kills it), and it ends with its command (``command_pid``; see the module's text)."""
    global _WORKER
    _WORKER = True
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for s in STOP_SIGNALS:
        signal.signal(s, signal.SIG_DFL)
    die_with_parent()
    if command_pid is not None:
        watch_command(command_pid)
