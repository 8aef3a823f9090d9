"""Benchmark: a full study of a real city network with 1 and 2 worker processes.

Runs ``clearance report`` as a user would (a subprocess) on the DRT network the
eclipse-sumo wheel ships (``tools/game/DRT/osm.net.xml``, a few thousand junctions) for P,
SU-30, CITY-BUS and WB-62, alternating 1 and 2 workers over the repeats, and prints per
run and as medians: wall time, runs per second, peak memory of all processes together
(the sum of resident sets, and of proportional sets, which counts the pages the workers
share once: :mod:`measure`), and the speed-up of 2 workers over 1 (the ratio of the
medians).

Targets (issue 18): 2 workers at least 1.8 times one; the study in at most 3 minutes on a
2-core machine; at most 2 GB in all processes together.

With ``--workers 2`` only the 2-worker study is run (issue 31's figure); with
``--baseline CSV.gz`` each run's verdicts are compared with a recorded study's, run by run
(``benchmarks/baselines/``: DRT's and Brunswick's x those four, before issue 31's work).

Targets (issue 31): DRT x 4 with 2 workers at most 180 s, Brunswick
(``../shared/realnets/port_brunswick.net.xml.gz``) x 4 at most 600 s, each at most 2 GB in all
processes together, every verdict the same as the baseline's or better.

Run: ``python benchmarks/bench_study.py [--repeats 2] [--net PATH] [--vehicle NAME ...]
[--workers 2] [--baseline CSV.gz]``
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from measure import (  # noqa: E402
    against_baseline,
    clearance_cmd,
    game_networks,
    run_measured,
    verdict_counts,
)

VEHICLES = ("P", "SU-30", "CITY-BUS", "WB-62")


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--net", type=Path, default=None)
    parser.add_argument("--vehicle", action="append")
    parser.add_argument("--workers", type=int, choices=(1, 2), action="append",
                        help="only these worker counts (repeatable; default 1 and 2)")
    parser.add_argument("--baseline", type=Path, default=None)
    args = parser.parse_args()
    counts = tuple(args.workers or (1, 2))
    net = args.net or next(p for p in game_networks() if p.parent.name == "DRT")
    vehicles = args.vehicle or list(VEHICLES)
    times: dict[int, list[float]] = {1: [], 2: []}
    peaks: dict[int, list[float]] = {1: [], 2: []}
    pss: dict[int, list[float]] = {1: [], 2: []}
    runs = 0
    print(f"{net} x {', '.join(vehicles)}")
    for rep in range(args.repeats):
        for workers in counts if rep % 2 == 0 else counts[::-1]:
            with tempfile.TemporaryDirectory() as tmp:
                out = Path(tmp) / "report"
                cmd = clearance_cmd("report", "-n", str(net), "-o", str(out),
                                    "--workers", str(workers))
                for v in vehicles:
                    cmd += ["--vehicle", v]
                m = run_measured(cmd)
                if m.returncode != 0:
                    sys.exit(f"exit {m.returncode}: {m.stderr[-2000:]}")
                _, runs = verdict_counts(out / "clearance.csv")
                if args.baseline is not None:
                    print("  " + against_baseline(out / "clearance.csv", args.baseline))
            times[workers].append(m.wall_s)
            peaks[workers].append(m.peak_bytes / 1e9)
            pss[workers].append(m.peak_pss_bytes / 1e9)
            print(f"  repeat {rep + 1}, {workers} worker(s): {m.wall_s:.1f} s, "
                  f"{runs / m.wall_s:.1f} runs/s, peak {m.peak_bytes / 1e9:.2f} GB "
                  f"(PSS {m.peak_pss_bytes / 1e9:.2f} GB)", flush=True)
    if len(counts) == 1:
        w = counts[0]
        t = statistics.median(times[w])
        print(f"{runs} runs. Median {w} worker(s): {t:.1f} s ({runs / t:.1f} runs/s, peak "
              f"{max(peaks[w]):.2f} GB, PSS {max(pss[w]):.2f} GB)")
        return
    t1, t2 = statistics.median(times[1]), statistics.median(times[2])
    print(f"{runs} runs. Medians: 1 worker {t1:.1f} s ({runs / t1:.1f} runs/s, peak "
          f"{max(peaks[1]):.2f} GB, PSS {max(pss[1]):.2f} GB); 2 workers {t2:.1f} s "
          f"({runs / t2:.1f} runs/s, peak {max(peaks[2]):.2f} GB, PSS {max(pss[2]):.2f} GB); "
          f"speed-up {t1 / t2:.2f}x")


if __name__ == "__main__":
    main()
