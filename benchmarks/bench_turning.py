"""Benchmark: full-lock turning metrics for one million vehicle rows on one core.

Target (issue 2): under one second. Prints the median of several repeats, for the lock
resolution (inner-wheel lock to bicycle angle and outer wheel, vectorised) plus
:func:`clearance.analysis.turning.full_lock_metrics`.

Run: ``python benchmarks/bench_turning.py [ROWS]``
"""

from __future__ import annotations

import os
import statistics
import sys
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from clearance.analysis.turning import full_lock_metrics  # noqa: E402
from clearance.vehicles.steering import bicycle_from_inner, ideal_outer_from_inner  # noqa: E402


def make_frame(n: int, seed: int = 1) -> pd.DataFrame:
    rng = np.random.default_rng(seed)
    l = rng.uniform(1.8, 7.5, n)  # noqa: E741
    B = rng.uniform(1.5, 2.6, n)
    return pd.DataFrame({
        "wheelbase_m": l, "track_m": B * 0.85, "width_m": B,
        "front_overhang_m": rng.uniform(0.5, 2.0, n), "rear_overhang_m": rng.uniform(0.5, 3, n),
        "max_inner_steer_rad": np.radians(rng.uniform(30, 50, n)),
    })


def run(frame: pd.DataFrame) -> pd.DataFrame:
    inner = frame["max_inner_steer_rad"].to_numpy()
    l, w = frame["wheelbase_m"].to_numpy(), frame["track_m"].to_numpy()  # noqa: E741
    frame = frame.assign(max_steer_rad=bicycle_from_inner(inner, l, w),
                         max_outer_steer_rad=ideal_outer_from_inner(inner, l, w))
    return full_lock_metrics(frame)


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    frame = make_frame(n)
    run(frame.head(1000))  # warm up
    times = []
    for _ in range(7):
        t0 = time.perf_counter()
        out = run(frame)
        times.append(time.perf_counter() - t0)
    med = statistics.median(times)
    print(f"rows: {n:,}")
    print(f"full-lock metrics: median {med:.3f} s over {len(times)} runs "
          f"(min {min(times):.3f} s, max {max(times):.3f} s); {n / med / 1e6:.2f} M rows/s")
    print(f"target < 1 s: {'met' if med < 1.0 else 'NOT met'}")
    print(f"check: mean swept width {out['swept_width_m'].mean():.3f} m")


if __name__ == "__main__":
    main()
