"""Benchmark: a route study against the whole-network study of the same network.

Runs ``clearance report`` as a user would (a subprocess) on each shared bus network of
``../shared/realnets/`` twice, alternating over the repeats: once along its road bus lines
(``--routes``, ``--route-vclass bus``, baseline CITY-BUS) and once over the whole network,
both with CITY-BUS and A-BUS and the default search, and prints per network the wall times
(medians), the runs and the ratio whole / routes. A route study costs its passages, not
the network (issue 29).

Run: ``python benchmarks/bench_routes.py [--repeats 1] [--net wildau|tavf_hamburg|doerpfeldstr ...]
[--lane-only]``
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from measure import REALNETS, clearance_cmd, run_measured  # noqa: E402

#: Network, its route files, its additional files (types kept apart).
BUS_NETWORKS = {
    "wildau": ("wildau.net.xml.gz", ["wildau.bus.rou.xml"], []),
    "tavf_hamburg": ("tavf_hamburg.net.xml.gz", ["tavf_hamburg.bus.rou.xml"],
                     ["tavf_hamburg.vtypes.xml"]),
    "doerpfeldstr": ("doerpfeldstr.net.xml.gz", ["doerpfeldstr.pt_lines.rou.xml"],
                     ["doerpfeldstr.vtypes.xml"]),
}
VEHICLES = ("CITY-BUS", "A-BUS")


def _runs(folder: Path) -> int:
    return int(json.loads((folder / "summary.json").read_text())["runs"])


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--net", action="append", choices=sorted(BUS_NETWORKS))
    parser.add_argument("--lane-only", action="store_true")
    args = parser.parse_args()
    common = [a for v in VEHICLES for a in ("--vehicle", v)]
    common += ["--lane-only"] if args.lane_only else []
    for name in args.net or sorted(BUS_NETWORKS):
        net, routes, additional = BUS_NETWORKS[name]
        base = ["report", "-n", str(REALNETS / net), *common]
        along = [*base, "--route-vclass", "bus", "--baseline", "CITY-BUS"]
        along += [a for f in routes for a in ("--routes", str(REALNETS / f))]
        along += [a for f in additional for a in ("--additional", str(REALNETS / f))]
        times: dict[str, list[float]] = {"routes": [], "network": []}
        runs: dict[str, int] = {}
        for _ in range(args.repeats):
            for kind, argv in (("routes", along), ("network", base)):
                with tempfile.TemporaryDirectory() as tmp:
                    out = Path(tmp) / "out"
                    m = run_measured(clearance_cmd(*argv, "-o", str(out)))
                    if m.returncode != 0:
                        raise SystemExit(f"{name} {kind}: exit {m.returncode}\n{m.stderr}")
                    times[kind].append(m.wall_s)
                    runs[kind] = _runs(out)
        r, w = statistics.median(times["routes"]), statistics.median(times["network"])
        print(f"{name}: routes {r:.1f} s ({runs['routes']} runs), whole network {w:.1f} s "
              f"({runs['network']} runs): {w / r:.1f}x", flush=True)


if __name__ == "__main__":
    main()
