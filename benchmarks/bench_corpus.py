"""Benchmark: `clearance report` for P and WB-62 on every network of the real corpus.

The corpus is every network in ``../shared/realnets/`` and the road networks the
eclipse-sumo wheel ships under ``tools/game/``. For each network it runs the report as a
user would (a subprocess, default workers) and prints one row: file size, junctions,
curves by kind, wall time, peak memory of all processes together, runs per second, and per
vehicle the verdict counts (``ct`` cannot-turn, ``f`` fails, ``e`` encroaches, ``c`` clear,
``err`` error), with the share of ``fails`` + ``cannot-turn`` on curves other than
``uturn`` (the issue's acceptance figure). A network whose report does not complete is
printed with its exit status and the last line of its error output.

With ``--lane-too`` each network gets a second row, the same report with ``--lane-only``
(no swung paths): the time the search of swung paths costs, and the verdicts without it.
The reports run with ``-v``, and ``study s`` is the time their log gives for the study
(the runs, without reading and the documents); the last lines add the times up over the
corpus and give the ratio of the search's totals to those of the lane alone.

Run: ``python benchmarks/bench_corpus.py [--vehicle NAME ...] [--workers N] [--only TEXT]
[--lane-too]``
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import tempfile
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from measure import clearance_cmd, corpus, run_measured, verdict_counts  # noqa: E402

SHORT = {"cannot-turn": "ct", "fails": "f", "encroaches": "e", "clear": "c", "error": "err"}


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--vehicle", action="append", help="vehicles (default P and WB-62)")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--only", action="append", help="networks whose path contains TEXT")
    parser.add_argument("--lane-too", action="store_true",
                        help="also run each report with --lane-only (no swung paths) and "
                             "print it as a second row: what the search costs")
    args = parser.parse_args()
    vehicles = args.vehicle or ["P", "WB-62"]
    nets = [p for p in corpus() if not args.only or any(t in str(p) for t in args.only)]
    print(f"{len(nets)} networks x {', '.join(vehicles)}")
    header = ("| network | MB | junctions | curves by kind | time s | study s | peak MB | runs/s | "
              + " | ".join(f"{v} ct/f/e/c/err (bad %)" for v in vehicles) + " |")
    print(header)
    print("|" + "---|" * (header.count("|") - 1))
    totals = {"search": [0.0, 0.0], "lane": [0.0, 0.0]}  # wall s, study s
    for net in nets:
        for mode, extra in [("search", []), ("lane", ["--lane-only"])]:
            if mode == "lane" and not args.lane_too:
                continue
            wall, study = _one(net, vehicles, args.workers, extra)
            totals[mode][0] += wall
            totals[mode][1] += study
    print(f"total with the search: {totals['search'][0]:.0f} s, study {totals['search'][1]:.0f} s")
    if args.lane_too:
        lane_wall, lane_study = totals["lane"]
        print(f"total on the lanes alone: {lane_wall:.0f} s, study {lane_study:.0f} s")
        if lane_wall and lane_study:
            print(f"search / lane: {totals['search'][0] / lane_wall:.2f} x whole reports, "
                  f"{totals['search'][1] / lane_study:.2f} x studies")


def _one(net: Path, vehicles: list[str], workers: int | None,
         extra: list[str]) -> tuple[float, float]:
    """One row: the report of ``net`` (with the ``extra`` options); its wall and study s."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "report"
        cmd = clearance_cmd("report", "-v", "-n", str(net), "-o", str(out), *extra)
        for v in vehicles:
            cmd += ["--vehicle", v]
        if workers:
            cmd += ["--workers", str(workers)]
        m = run_measured(cmd)
        name = f"{net.parent.name}/{net.name}" + (" (lane only)" if extra else "")
        size = net.stat().st_size / 1e6
        if m.returncode != 0 or not (out / "clearance.csv").is_file():
            last = (m.stderr.strip().splitlines() or ["(no message)"])[-1]
            print(f"| {name} | {size:.1f} | | | {m.wall_s:.0f} | | {m.peak_bytes / 1e6:.0f} "
                  f"| | exit {m.returncode}: {last[:120]} |")
            return m.wall_s, 0.0
        logged = re.search(r"study: \d+ runs in ([0-9.]+) s", m.stderr)
        study_s = float(logged.group(1)) if logged else 0.0
        summary = json.loads((out / "summary.json").read_text())
        counts, n = verdict_counts(out / "clearance.csv")
        kinds: Counter[str] = Counter()
        for (v, kind, _), c in counts.items():
            if v == vehicles[0]:
                kinds[kind] += c
        cells = []
        for v in vehicles:
            by = Counter()
            bad = total = 0
            for (vv, kind, verdict), c in counts.items():
                if vv != v:
                    continue
                by[verdict] += c
                if kind != "uturn" and verdict != "not-permitted":
                    total += c
                    bad += c if verdict in ("fails", "cannot-turn") else 0
            share = 100.0 * bad / total if total else 0.0
            cells.append("/".join(str(by[k]) for k in SHORT) + f" ({share:.1f} %)")
        nets_in = summary.get("inputs", {}).get("networks", [{}])
        junctions = nets_in[0].get("junctions", "") if nets_in else ""
        kind_text = ", ".join(f"{k} {c}" for k, c in sorted(kinds.items()))
        print(f"| {name} | {size:.1f} | {junctions} | {kind_text} | {m.wall_s:.0f} | "
              f"{study_s:.1f} | {m.peak_bytes / 1e6:.0f} | {n / m.wall_s:.0f} | "
              + " | ".join(cells) + " |", flush=True)
        return m.wall_s, study_s


if __name__ == "__main__":
    main()
