"""Speed and memory of reading a large network and extracting its curves.

A 10,000-junction grid (``netgenerate --grid --grid.number 100``, two lanes, about 130 MB)
is generated once into a cache directory outside the repository, then:

1. our reader (:func:`clearance.networks.reader.read_network`) is timed ``--repeat`` times, each in
a
   fresh process (so that peak memory is per run); the median is compared with the target;
2. ``sumolib.net.readNet(..., withInternal=True)`` is timed once in its own process, for the
   ratio; the extraction is also given against it at the end (on these shared machines
   sumolib's read of the grid took 19-33 s in different spells: the ratios tell how our
   steps did whatever the machine's speed);
3. in a fresh process (``--extract-repeat`` times, median): the network is read, every
   curve extracted (:func:`clearance.networks.curves.extract_curves`, which gives the curves their
   areas to be built on demand, :mod:`clearance.networks.area_book`), then the three areas
   (``own_lanes``, ``roadway``, ``paved``) of EVERY curve are read and checked to be
   non-empty polygons, in curve order: each batch of curves has its areas built when its
   first curve is read, and the oldest batch is released when more than
   :data:`~clearance.networks.area_book.MAX_BATCHES` would be kept. The extraction figure is curves
   plus building every area. Held at once: the network, every curve (centre line,
   profile, lanes) and the areas of at most that many batches, never all areas. Peak
   memory is that process's ``ru_maxrss`` (read, curves and areas together). Reading and
   the areas run on one core (a study's parallel work is its runs, docs/design.md §8).

Targets on a 2-core machine: reading ≤ 5 s, extracting every curve ≤ 30 s, peak memory
≤ 1.5 GB. Run::

    python benchmarks/bench_network.py                 # cache: ~/.cache/sumo-clearance
    python benchmarks/bench_network.py --grid 30       # a smaller grid, for a quick look
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

TARGET_READ_S = 5.0
TARGET_EXTRACT_S = 30.0
TARGET_PEAK_MB = 1536.0

_CHILD = r"""
import json, os, resource, sys, time
what, path = sys.argv[1], sys.argv[2]
POLYGONAL = ("Polygon", "MultiPolygon")


def rss_mb():
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return float("nan")


t0, c0 = time.perf_counter(), time.process_time()
out = {}
if what == "ours":
    from clearance.networks.reader import read_network
    net = read_network(path)
    out["read_s"], out["read_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
    out["lanes"] = len(net.lanes) out["junctions"] = sum(1 for j in net.junctions.values() if
    j.type != "internal")
elif what == "sumolib":
    import sumolib
    net = sumolib.net.readNet(path, withInternal=True)
    out["read_s"], out["read_cpu_s"] = time.perf_counter() - t0, time.process_time() - c0
elif what == "extract":
    from clearance.networks.area_book import BATCH_CURVES, MAX_BATCHES
    from clearance.networks.curves import extract_curves
    from clearance.networks.reader import read_network
    net = read_network(path)
    out["read_s"] = time.perf_counter() - t0
    out["read_peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    t1, c1 = time.perf_counter(), time.process_time()
    # areas=True: every curve gets its areas, built on demand
    curves = extract_curves(net)
    t2, c2 = time.perf_counter(), time.process_time()
    out["curves_rss_mb"] = rss_mb()
    # build and check the three areas of EVERY curve, in curve order: each batch is built
    # when its first curve is read; the book keeps at most MAX_BATCHES batches at once
    bad = 0 for c in curves:
        for area in (c.own_lanes, c.roadway, c.paved):
            if area is None or area.is_empty or area.geom_type not in POLYGONAL:
                bad += 1
    t3, c3 = time.perf_counter(), time.process_time()
    if bad:
        raise SystemExit(f"{bad} areas missing, empty or not polygons")
    book = curves[0].area_book if curves else None
    out["batches"] = len(book.batches) if book else 0
    out["batches_built"] = book.built if book else 0
    out["batch_curves"], out["max_batches"] = BATCH_CURVES, MAX_BATCHES
    out.update(curves_s=t2 - t1, areas_s=t3 - t2, curves_cpu_s=c2 - c1, areas_cpu_s=c3 - c2)
    out["curves"] = len(curves) kinds = {}
    for c in curves:
        kinds[c.kind] = kinds.get(c.kind, 0) + 1
    out["kinds"] = kinds
out["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps(out))
"""


def cache_dir() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "sumo-clearance"


def grid_network(n: int, directory: Path) -> Path:
    """Generate (once) an n × n grid with two lanes per direction."""
    from clearance.networks.sumo.tools import run_sumo_tool

    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f"grid{n}x{n}_2lanes.net.xml"
    if not path.exists():
        print(f"generating {path} (netgenerate, once) ...", flush=True)
        tmp = path.with_suffix(".tmp.xml")
        args = ["--grid", "--grid.number", str(n), "--default.lanenumber", "2", "-o", str(tmp)]
        run_sumo_tool("netgenerate", args, timeout_s=1800)
        tmp.replace(path)
    return path


def child(what: str, path: Path, extra: str = "-") -> dict:
    env = dict(os.environ)
    repo = str(Path(__file__).resolve().parents[1])
    env["PYTHONPATH"] = repo + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.run(
        [sys.executable, "-c", _CHILD, what, str(path), extra],
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )
    if proc.returncode != 0:
        raise SystemExit(f"{what} failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def verdict(value: float, target: float) -> str:
    return "ok" if value <= target else "OVER TARGET"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").split("\n")[0])
    parser.add_argument("--grid", type=int, default=100, help="junctions per side (default 100)")
    parser.add_argument("--repeat", type=int, default=3, help="reads of our reader (median)")
    parser.add_argument("--cache", type=Path, default=None, help="where the grid is kept")
    parser.add_argument("--extract-repeat", type=int, default=1, help="extraction runs (median)")
    parser.add_argument("--no-sumolib", action="store_true", help="skip the sumolib comparison")
    args = parser.parse_args(argv)
    path = grid_network(args.grid, args.cache or cache_dir())
    size_mb = path.stat().st_size / 1e6
    print(f"network: {path} ({size_mb:.0f} MB)")

    ours = [child("ours", path) for _ in range(max(args.repeat, 1))]
    read_s = statistics.median(r["read_s"] for r in ours)
    read_peak = max(r["peak_mb"] for r in ours)
    read_cpu = statistics.median(r["read_cpu_s"] for r in ours)
    runs = ", ".join(f"{r['read_s']:.2f}" for r in ours)
    print(
        f"our reader: median {read_s:.2f} s over {len(ours)} run(s) "
        f"({runs}; CPU {read_cpu:.2f} s), "
        f"peak {read_peak:.0f} MB, "
        f"{ours[0]['junctions']} junctions, {ours[0]['lanes']} lanes "
        f"[target {TARGET_READ_S:.0f} s: {verdict(read_s, TARGET_READ_S)}]"
    )
    ref = None
    if not args.no_sumolib:
        ref = child("sumolib", path)
        print(
            f"sumolib.net.readNet(withInternal=True): {ref['read_s']:.2f} s "
            f"(CPU {ref['read_cpu_s']:.2f} s), peak "
            f"{ref['peak_mb']:.0f} MB; ratio ours/sumolib = {read_s / ref['read_s']:.2f} "
            f"({ref['read_s'] / read_s:.1f}x faster)"
        )
    runs = [child("extract", path) for _ in range(max(args.extract_repeat, 1))]
    ext = sorted(runs, key=lambda r: r["curves_s"] + r["areas_s"])[len(runs) // 2]
    total = ext["curves_s"] + ext["areas_s"]
    cpu = ext["curves_cpu_s"] + ext["areas_cpu_s"]
    peak = max(r["peak_mb"] for r in runs)
    print(
        f"extracting every curve with its three areas ({ext['curves']}: {ext['kinds']}): "
        f"{total:.2f} s (curves {ext['curves_s']:.2f} s + own lanes, roadway and paved "
        f"areas of every curve built and checked {ext['areas_s']:.2f} s; CPU {cpu:.2f} s = "
        f"{ext['curves_cpu_s']:.2f} + {ext['areas_cpu_s']:.2f}), median of {len(runs)} "
        f"[target {TARGET_EXTRACT_S:.0f} s: {verdict(total, TARGET_EXTRACT_S)}]"
    )
    if ref is not None:  # how fast the machine ran: sumolib's read is the yardstick
        print(
            f"against sumolib's read in this run: reading {read_s / ref['read_s']:.2f}, "
            f"extracting every curve with its areas {total / ref['read_s']:.2f} (sumolib's read "
            f"as the measure of how fast the machine ran)"
        )
    print(
        f"areas built on demand in {ext['batches']} batches of >= {ext['batch_curves']} "
        f"curves ({ext['batches_built']} built, one core); held at once: "
        f"the network, every curve (geometry, profiles) and the areas of at most "
        f"{ext['max_batches']} batches"
    )
    print(
        f"peak memory of that process (read + extract + areas of every curve): {peak:.0f} MB "
        f"(after reading {ext['read_peak_mb']:.0f} MB, with the curves {ext['curves_rss_mb']:.0f}"
        f" MB) [target {TARGET_PEAK_MB:.0f} MB: {verdict(peak, TARGET_PEAK_MB)}]"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
