"""Shared by the study benchmarks: run a command and measure its wall time and the peak
memory of its whole process tree (the command and every worker it starts), and find the
corpus of real networks.

The peak is sampled: every ``interval_s`` the resident set sizes of the process and all its
descendants (``/proc/PID/task/*/children``) are added up; the largest sum is the peak. A
spike shorter than the interval can be missed, so the figure is a lower bound within a few
per cent for processes that grow steadily, as a study's do.

A sum of resident sets counts the pages the processes share (the worker processes fork
from one server that has imported numpy, shapely and libsumo once) once per process; the
proportional set sizes (``Pss`` of ``/proc/PID/smaps_rollup``: each shared page divided
among its sharers) add up to the memory the tree really holds, which is also sampled
(``peak_pss_bytes``).
"""

from __future__ import annotations

import csv
import subprocess
import sys
import threading
import time
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
REALNETS = REPO.parent / "shared" / "realnets"


def _children(pid: int) -> list[int]:
    out: list[int] = []
    for task in Path(f"/proc/{pid}/task").glob("*"):
        try:
            out += [int(c) for c in (task / "children").read_text().split()]
        except OSError:
            pass
    return out


def _rss_bytes(pid: int) -> int:
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def _pss_bytes(pid: int) -> int:
    try:
        for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
            if line.startswith("Pss:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def _tree(pid: int) -> list[int]:
    out, todo, seen = [], [pid], set()
    while todo:
        p = todo.pop()
        if p in seen:
            continue
        seen.add(p)
        out.append(p)
        todo += _children(p)
    return out


def tree_rss_bytes(pid: int) -> int:
    """Resident memory of ``pid`` and all its descendants, now (shared pages counted in
    every process that maps them)."""
    return sum(_rss_bytes(p) for p in _tree(pid))


def tree_pss_bytes(pid: int) -> int:
    """Proportional memory of ``pid`` and all its descendants, now (shared pages divided
    among the processes that share them)."""
    return sum(_pss_bytes(p) for p in _tree(pid))


@dataclass
class Measured:
    """What one command cost."""

    wall_s: float
    peak_bytes: int
    returncode: int
    stderr: str
    peak_pss_bytes: int = 0


def run_measured(cmd: list[str], interval_s: float = 0.1, cwd: Path | None = None) -> Measured:
    """Run ``cmd`` to its end; its wall time and the peak memory of its process tree."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            cwd=cwd)
    peak = peak_pss = 0
    done = threading.Event()

    def sample() -> None:
        nonlocal peak, peak_pss
        while not done.is_set():
            pids = _tree(proc.pid)
            peak = max(peak, sum(_rss_bytes(p) for p in pids))
            peak_pss = max(peak_pss, sum(_pss_bytes(p) for p in pids))
            done.wait(interval_s)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    _, err = proc.communicate()
    wall = time.perf_counter() - t0
    done.set()
    sampler.join()
    return Measured(wall, peak, proc.returncode, err, peak_pss)


def game_networks() -> list[Path]:
    """The road networks the eclipse-sumo wheel ships under ``tools/game``."""
    try:
        import sumo

        game = Path(sumo.SUMO_HOME) / "tools" / "game"
    except ImportError:  # pragma: no cover
        return []
    return sorted(p for p in game.glob("*/*.net.xml*"))


def corpus() -> list[Path]:
    """Every network of the corpus: ``../shared/realnets/`` and the wheel's game networks."""
    return sorted(REALNETS.glob("*.net.xml*")) + game_networks()


def verdict_counts(csv_path: Path) -> tuple[Counter[tuple[str, str, str]], int]:
    """``(vehicle, kind, verdict)`` counts of a ``clearance.csv``, and its number of rows."""
    counts: Counter[tuple[str, str, str]] = Counter()
    n = 0
    with open(csv_path, newline="") as fh:
        for row in csv.DictReader(fh):
            counts[(row["vehicle"], row["kind"], row["verdict"])] += 1
            n += 1
    return counts, n


def against_baseline(csv_path: Path, baseline: Path) -> str:
    """How a ``clearance.csv``'s verdicts compare with a baseline's (``.csv`` or
    ``.csv.gz``), run by run: the same, better, worse, and the runs either lacks; and the
    baseline's and the study's counts per verdict (in the project's verdict order)."""
    import gzip

    from clearance.reports.results.records import VERDICT_ORDER  # higher is better

    def rows(path: Path) -> dict[tuple[str, str, str], str]:
        opener = gzip.open if path.suffix == ".gz" else open
        with opener(path, "rt", newline="") as fh:
            return {(r["network"], r["vehicle"], r["curve_id"]): r["verdict"]
                    for r in csv.DictReader(fh)}

    old, new = rows(baseline), rows(csv_path)
    common = old.keys() & new.keys()
    better = sum(VERDICT_ORDER[new[k]] > VERDICT_ORDER[old[k]] for k in common)
    worse = sum(VERDICT_ORDER[new[k]] < VERDICT_ORDER[old[k]] for k in common)

    def counts(v: dict[tuple[str, str, str], str]) -> str:
        c = Counter(v.values())
        best_first = sorted(VERDICT_ORDER, key=VERDICT_ORDER.__getitem__, reverse=True)
        return ", ".join(f"{c[x]:,} {x}" for x in best_first if c[x])

    return (f"against {baseline.name}: {len(common) - better - worse:,} the same, {better:,} "
            f"better, {worse:,} worse, {len(old.keys() - new.keys()):,} missing, "
            f"{len(new.keys() - old.keys()):,} new\n    baseline: {counts(old)}\n"
            f"    this run: {counts(new)}")


def clearance_cmd(*args: str) -> list[str]:
    """The ``clearance`` command of this interpreter's environment."""
    return [sys.executable, "-m", "clearance.reports.cli.main", *args]
