"""Does SUMO load this network? SUMO itself is asked, once per file, before any run.

The tool reads exactly the networks SUMO loads (docs/design.md §7): what ``sumo -n NET``
refuses is bad input, named in SUMO's own words; what it loads is read, the elements no
vehicle can be judged on left out with a note (:mod:`clearance.networks.integrity`). The check runs
``sumo`` of the ``eclipse-sumo`` package in a process of its own
(:class:`SumoLoadCheck`), beside the reader, so that it costs no time where two cores are
free, and a SUMO that crashes on a file costs only that process. The answer is kept per
file (path, size and modification time) for the life of the process.

Example
-------
>>> check = SumoLoadCheck("networks/samples/intersection/intersection.net.xml")
>>> check.refusal() is None
True
"""

from __future__ import annotations

import os
import signal
import subprocess
import tempfile
from pathlib import Path

from clearance.networks.sumo.tools import find_sumo_binary, sumo_home

__all__ = ["LOAD_TIMEOUT_S", "SumoLoadCheck", "refusal_message"]

#: SUMO loads the 10,000-junction grid of the benchmarks (132 MB) in well under a minute; a
#: load that takes longer than this is stopped and taken as an internal failure.
LOAD_TIMEOUT_S = 900.0

#: Answers by (real path, size, modification time): None (loads) or SUMO's reason.
_KNOWN: dict[tuple[str, int, int], str | None] = {}

#: The error lines of SUMO's output quoted at most.
_QUOTED_ERRORS = 3


def _key(path: Path) -> tuple[str, int, int]:
    st = path.stat()
    return (os.path.realpath(path), st.st_size, st.st_mtime_ns)


class SumoLoadCheck:
    """``sumo -n NET --end 1`` in a process of its own, started at once; :meth:`refusal`
    waits for its answer.

    Parameters
    ----------
    path
        The network file (already found to be a regular file of XML: SUMO is never started
        on a FIFO or a device).
    """

    def __init__(self, path: str | os.PathLike[str]):
        self.path = Path(path)
        self.key = _key(self.path)
        self._answer: str | None = _KNOWN.get(self.key)
        self._known = self.key in _KNOWN
        self._proc: subprocess.Popen[bytes] | None = None
        self._log: tempfile._TemporaryFileWrapper[bytes] | None = None
        if not self._known:
            self._start()

    def _start(self) -> None:
        exe = find_sumo_binary("sumo")
        env = dict(os.environ, SUMO_HOME=str(sumo_home()))
        self._log = tempfile.NamedTemporaryFile(prefix="clearance-sumo-", suffix=".log")
        # --end 1: load the network and take one step (what SUMO checks on loading);
        # no warnings (a city network has thousands), errors only
        self._proc = subprocess.Popen(
            [str(exe), "-n", str(self.path), "--end", "1", "--no-step-log", "--no-warnings",
             "--duration-log.disable", "--xml-validation", "never"],
            stdin=subprocess.DEVNULL, stdout=self._log, stderr=subprocess.STDOUT, env=env,
            start_new_session=False)

    def refusal(self, timeout_s: float = LOAD_TIMEOUT_S) -> str | None:
        """None when SUMO loads the network, else SUMO's reason (its first error lines).

        Raises
        ------
        RuntimeError
            SUMO did not answer within ``timeout_s`` (an internal failure, not a verdict on
            the file).
        """
        if self._known:
            return self._answer
        assert self._proc is not None and self._log is not None
        try:
            code = self._proc.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            self.cancel()
            raise RuntimeError(f"{self.path}: SUMO did not finish loading the network within "
                               f"{timeout_s:g} s") from None
        self._log.seek(0)
        text = self._log.read().decode("utf-8", "replace")
        self._log.close()
        self._answer = refusal_message(code, text)
        self._known = True
        _KNOWN[self.key] = self._answer
        return self._answer

    def cancel(self) -> None:
        """Stop SUMO (the command stopped before it needed the answer)."""
        if self._proc is not None and self._proc.poll() is None:
            self._proc.kill()
            self._proc.wait()
        if self._log is not None:
            self._log.close()


def refusal_message(code: int, output: str) -> str | None:
    """SUMO's reason for refusing a network, from its exit status and output (None: it
    loaded it).

    Examples
    --------
    >>> refusal_message(0, "Step #1.00")
    >>> refusal_message(1, "Error: Attribute length of lane 'a_0' is invalid (nan)\\n"
    ...                    "Error: Unknown from-node 'T' for edge ':T_0'.\\nQuitting (on error).")
    "Attribute length of lane 'a_0' is invalid (nan); Unknown from-node 'T' for edge ':T_0'."
    >>> refusal_message(-11, "")
    'SUMO crashed loading it (signal SIGSEGV)'
    """
    if code == 0:
        return None
    errors = [line.removeprefix("Error:").strip() for line in output.splitlines()
              if line.startswith("Error:")]
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = str(-code)
        errors.append(f"SUMO crashed loading it (signal {name})")
    if not errors:
        errors = [line.strip() for line in output.splitlines() if line.strip()][-1:] or [
            f"SUMO exited with status {code}"]
    more = len(errors) - _QUOTED_ERRORS
    text = "; ".join(errors[:_QUOTED_ERRORS])
    return text + (f" (and {more} more error(s))" if more > 0 else "")
