"""Benchmark: one junction of a real network checked from a cold start, as a user runs it.

``clearance check -n NET --junction ID`` for P, SU-30, CITY-BUS and WB-62 (the default
search, the default workers), each repeat a fresh process: the command's start, reading the
network and extracting the junction's curves, starting the workers and SUMO, the runs, the
verdicts. Prints each repeat's wall time and peak memory of all processes, then the median.

The default is DRT's (``tools/game/DRT`` of the eclipse-sumo wheel) largest junction,
``cluster_1293996765_1293996771_1298595250_1560223550`` (29 curves; 29 runs, the rest not
permitted for the vehicles' classes), and its 2-curve junction ``1292264805``.

Target (issue 31): at most 5 s from a cold start.

Run: ``python benchmarks/bench_junction.py [--repeats 5] [--net PATH --junction ID ...]``
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from measure import clearance_cmd, game_networks, run_measured  # noqa: E402

VEHICLES = ("P", "SU-30", "CITY-BUS", "WB-62")
JUNCTIONS = ("cluster_1293996765_1293996771_1298595250_1560223550", "1292264805")


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--net", type=Path, default=None)
    parser.add_argument("--junction", action="append")
    args = parser.parse_args()
    net = args.net or next(p for p in game_networks() if p.parent.name == "DRT")
    for junction in args.junction or JUNCTIONS:
        cmd = clearance_cmd("check", "-n", str(net), "--junction", junction)
        for v in VEHICLES:
            cmd += ["--design-vehicle", v]
        times, peaks = [], []
        for rep in range(args.repeats):
            m = run_measured(cmd)
            if m.returncode not in (0, 1):
                sys.exit(f"exit {m.returncode}: {m.stderr[-2000:]}")
            times.append(m.wall_s)
            peaks.append(m.peak_bytes / 1e6)
            print(f"  {junction}, repeat {rep + 1}: {m.wall_s:.2f} s, "
                  f"peak {m.peak_bytes / 1e6:.0f} MB", flush=True)
        print(f"{junction}: median {statistics.median(times):.2f} s over {args.repeats} "
              f"(min {min(times):.2f}, max {max(times):.2f}), peak {max(peaks):.0f} MB")


if __name__ == "__main__":
    main()
