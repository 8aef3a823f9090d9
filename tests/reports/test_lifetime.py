"""A stopped command takes all its processes with it and leaves the previous output as it was."""

from __future__ import annotations

import doctest
import hashlib
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest

import clearance.reports.study.lifetime
from clearance.networks.samples.sources import SAMPLES_DIR
from tests.cli import CLI

REPO = Path(__file__).resolve().parents[2]
INTERSECTION = SAMPLES_DIR / "intersection" / "intersection.net.xml"
BOLOGNA = REPO.parent / "shared" / "realnets" / "bologna_joined.net.xml.gz"


def test_doctests():
    assert doctest.testmod(clearance.reports.study.lifetime).failed == 0


def _session(sid: int) -> list[int]:
    """The processes of session ``sid`` still alive (zombies left out)."""
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == sid and fields[0] != "Z":
            out.append(int(stat.parent.name))
    return out


def _digest(folder: Path) -> str:
    h = hashlib.sha256()
    for p in sorted(folder.rglob("*")):
        if p.is_file():
            h.update(p.relative_to(folder).as_posix().encode() + p.read_bytes())
    return h.hexdigest()


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("made") / "out"
    subprocess.run([*CLI, "report", "-n", str(INTERSECTION),
                    "--vehicle", "P", "--workers", "1", "-o", str(out)], cwd=REPO,
                   check=True, capture_output=True, timeout=120)
    return out


@pytest.fixture()
def previous(made: Path, tmp_path: Path) -> Path:
    """A previous report in a folder of its own."""
    import shutil

    return Path(shutil.copytree(made, tmp_path / "out"))


def _start(out: Path) -> subprocess.Popen[bytes]:
    """A report into ``out`` with two workers, in a session of its own, once it runs."""
    net = BOLOGNA if BOLOGNA.is_file() else INTERSECTION
    proc = subprocess.Popen(
        [*CLI, "report", "-n", str(net), "--vehicle", "P",
         "--vehicle", "CITY-BUS", "--vehicle", "WB-62", "--workers", "2", "-o", str(out)],
        cwd=REPO, start_new_session=True, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    deadline = time.monotonic() + 60
    while len(_session(proc.pid)) < 5:  # the command, its tracker, fork server, 2 workers
        assert proc.poll() is None and time.monotonic() < deadline, "the study did not start"
        time.sleep(0.2)
    time.sleep(1.0)  # in the middle of its batches
    return proc


def _gone_within(sid: int, seconds: float) -> bool:
    deadline = time.monotonic() + seconds
    while _session(sid):
        if time.monotonic() > deadline:
            return False
        time.sleep(0.2)
    return True


def _leftovers(out: Path) -> list[str]:
    return sorted(p.name for p in out.parent.iterdir() if p.name.startswith(f".{out.name}."))


@pytest.mark.parametrize("sig, to_group, status", [
    (signal.SIGTERM, False, 143),  # kill PID
    (signal.SIGHUP, False, 129),   # the terminal closed
    (signal.SIGINT, True, 130),    # Ctrl-C: the terminal signals the whole group
])
def test_a_stopped_report_ends_every_process_and_leaves_no_trace(previous, sig, to_group,
                                                                 status):
    before = _digest(previous)
    proc = _start(previous)
    if to_group:
        os.killpg(proc.pid, sig)
    else:
        os.kill(proc.pid, sig)
    assert proc.wait(timeout=15) == status, proc.stderr.read() if proc.stderr else ""
    assert _gone_within(proc.pid, 10), _session(proc.pid)
    assert _leftovers(previous) == []  # no lock, no staging folder
    assert _digest(previous) == before  # the previous report, untouched
    err = proc.stderr.read().decode() if proc.stderr else ""
    assert "Traceback" not in err, err


def test_after_sigkill_the_workers_end_and_the_next_run_takes_over(previous):
    before = _digest(previous)
    proc = _start(previous)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait(timeout=15)
    assert _gone_within(proc.pid, 10), _session(proc.pid)  # the workers saw it go
    assert _digest(previous) == before
    left = _leftovers(previous)
    assert any(n.endswith(".lock") for n in left) and any(".new-" in n for n in left)
    again = subprocess.run([*CLI, "report", "-n",
                            str(INTERSECTION), "--vehicle", "SU-30", "--workers", "1", "-o",
                            str(previous)], cwd=REPO, capture_output=True, text=True,
                           timeout=120)
    assert again.returncode == 0, again.stderr  # the stale lock is taken over
    assert _leftovers(previous) == []  # and what the killed run left is cleared
    assert "SU-30" in (previous / "clearance.csv").read_text()
