"""Benchmark: 100 vehicles driven through a 90-degree turn, with envelopes and verdicts.

Prints the median over several repeats of: the batched simulation alone (vehicle-steps per
second), the per-run swept path and verdict, and complete runs per second (wall clock, and
by the process's CPU time, steadier on a shared machine). One process, one core (numpy's
threads are not used by these small arrays).

Run: ``python benchmarks/bench_kinematics.py [--vehicles 100] [--repeats 5]``
"""

from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np
import shapely

from clearance.analysis.clearance import Areas, evaluate
from clearance.analysis.polyline import prepare_path
from clearance.analysis.tracking import TrackingSettings, simulate_batch
from clearance.vehicles.vehicle import Trailer, Vehicle


def fleet(n: int) -> list[Vehicle]:
    """Cars, buses and tractor-semitrailers of graded sizes (every third has a trailer)."""
    out = []
    for i in range(n):
        f = i / max(n - 1, 1)
        kind = i % 3
        if kind == 0:
            out.append(Vehicle(f"car{i}", 2.5 + 0.5 * f, 1.5, 1.8, 0.9, 1.0,
                               math.radians(34.0), math.radians(38.0), 0.6))
        elif kind == 1:
            out.append(Vehicle(f"bus{i}", 5.0 + 2.0 * f, 2.1, 2.55, 2.0, 3.0,
                               math.radians(40.0), math.radians(45.0), 0.4))
        else:
            trailer = Trailer(-0.4, 9.0 + 3.0 * f, 2.55, 1.2, 2.8, math.radians(80.0))
            out.append(Vehicle(f"semi{i}", 3.8 + 0.4 * f, 2.0, 2.55, 1.4, 1.0,
                               math.radians(38.0), math.radians(42.0), 0.4, trailer=trailer))
    return out


def turn_90(radius_m: float = 15.0, straight_m: float = 15.0) -> np.ndarray:
    a = np.radians(np.arange(0.0, 90.01, 1.0))
    arc = np.c_[radius_m * np.sin(a), radius_m * (1.0 - np.cos(a))]
    return np.concatenate([[[-straight_m, 0.0]], arc, [[radius_m, radius_m + straight_m]]])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vehicles", type=int, default=100)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()

    vehicles = fleet(args.vehicles)
    points = turn_90()
    path = prepare_path(points, name="turn-90")
    centre = shapely.LineString(points)
    areas = Areas(shapely.buffer(centre, 3.5, cap_style="flat"),
                  shapely.buffer(centre, 8.0, cap_style="flat"))
    settings = TrackingSettings()

    sim_t, env_t, cpu_t, steps = [], [], [], 0
    verdicts: dict[str, int] = {}
    for _ in range(args.repeats):
        c0 = time.process_time()
        t0 = time.perf_counter()
        runs = simulate_batch(vehicles, [path], settings)
        t1 = time.perf_counter()
        results = [evaluate(r, areas, offset_m=0.3) for r in runs]
        t2 = time.perf_counter()
        cpu_t.append(time.process_time() - c0)
        sim_t.append(t1 - t0)
        env_t.append(t2 - t1)
        steps = sum(len(r.trajectory) - 1 for r in runs)
        verdicts = {}
        for r in results:
            verdicts[r.verdict] = verdicts.get(r.verdict, 0) + 1
    sim, env = statistics.median(sim_t), statistics.median(env_t)
    n = len(vehicles)
    print(f"{n} vehicles x 90-degree turn (R 15 m, {path.length_m:.1f} m), "
          f"dt {settings.dt_s} s, {settings.profile.speed_m_s[0]} m/s, "
          f"median of {args.repeats} repeats")
    print(f"  simulation (batched):     {sim * 1e3:8.1f} ms  {steps / sim:12,.0f} vehicle-steps/s "
          f"({steps} steps)")
    print(f"  envelopes + verdicts:     {env * 1e3:8.1f} ms  {env / n * 1e3:8.2f} ms per run")
    print(f"  complete runs:            {n / (sim + env):8.1f} runs/s "
          f"(by CPU time: {n / statistics.median(cpu_t):.1f} runs/s)")
    print(f"  verdicts: {verdicts}")


if __name__ == "__main__":
    main()
