"""Benchmark: vehicle x curve runs driven through libsumo, 100 vehicles in flight.

The runs are every vehicle of a table (default: the AASHTO design vehicles) on every turn of
the ``intersection`` sample (5 x 20 = 100 runs by default, all in flight at once). Each
repeat times the same runs twice in the same process: through SUMO (model, SUMO placement
and read-back of every vehicle at every step, envelopes, verdicts) and without SUMO (model,
envelopes, verdicts). Prints medians over the repeats:

- SUMO vehicle-steps per second (placements and read-backs / time in the SUMO session,
  the model excluded; target >= 20,000 on one core);
- complete runs per second through SUMO (target >= 100 on one core);
- the ratio of the two wall-clock times (target: through SUMO at most twice as long).

SUMO steps at the driver's default (0.2 s, every second sample of the model's 0.1 s);
``--sumo-step 0.1`` shows every model sample in SUMO.

Run: ``python benchmarks/bench_simulate.py [--repeats 5] [--vehicle NAME ...] [--batch 100]
[--sumo-step S]``
"""

from __future__ import annotations

import argparse
import statistics
import time

from clearance.networks.curves import extract_curves
from clearance.networks.driving.drive import DriveOptions, DriveStats, curve_areas, drive
from clearance.networks.reader import read_network
from clearance.networks.samples import build as samples
from clearance.vehicles.table import bundled_table, load_tables

DEFAULT_VEHICLES = ("P", "SU-30", "CITY-BUS", "WB-40", "WB-62")


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--vehicle", action="append", help="vehicle names (repeatable)")
    parser.add_argument("--batch", type=int, default=100, help="vehicles in flight")
    parser.add_argument("--sample", default="intersection", choices=samples.SAMPLES)
    parser.add_argument("--sumo-step", type=float, default=DriveOptions.sumo_step_s,
                        help="SUMO step length (s; default %(default)s)")
    args = parser.parse_args()

    names = args.vehicle or list(DEFAULT_VEHICLES)
    table = load_tables([bundled_table("aashto_green_book"), bundled_table("paper_table1")],
                        names)
    vehicles = [table.vehicle(n) for n in names]
    net = read_network(samples.SAMPLES_DIR / args.sample / f"{args.sample}.net.xml")
    curves = extract_curves(net)
    # The areas are built on first use, on a thread pool (clearance.networks.area_book): build them
    # now, so that the timed runs measure one core and no area building
    for c in curves:
        curve_areas(c)
    pairs = [(v, c) for v in vehicles for c in curves]

    with_t: list[float] = []
    with_cpu: list[float] = []
    without_t: list[float] = []
    without_cpu: list[float] = []
    rates: list[float] = []
    cpu_rates: list[float] = []
    sumo_s: list[float] = []
    model_s: list[float] = []
    eval_s: list[float] = []
    steps = vsteps = 0
    verdicts: dict[str, int] = {}
    max_dev = 0.0
    for _ in range(args.repeats):
        st = DriveStats()
        c0, t0 = time.process_time(), time.perf_counter()
        runs = drive(net, pairs, options=DriveOptions(batch_size=args.batch,
                                                      sumo_step_s=args.sumo_step), stats=st)
        with_t.append(time.perf_counter() - t0)
        with_cpu.append(time.process_time() - c0)
        c0, t0 = time.process_time(), time.perf_counter()
        plain = drive(net, pairs, options=DriveOptions(batch_size=args.batch, use_sumo=False))
        without_t.append(time.perf_counter() - t0)
        without_cpu.append(time.process_time() - c0)
        rates.append(st.vehicle_steps / st.sumo_s)
        cpu_rates.append(st.vehicle_steps / st.sumo_cpu_s)
        sumo_s.append(st.sumo_s)
        model_s.append(st.model_s)
        eval_s.append(st.evaluate_s)
        steps, vsteps = st.sumo_steps, st.vehicle_steps
        verdicts = {}
        for r in runs:
            verdicts[r.verdict] = verdicts.get(r.verdict, 0) + 1
        max_dev = max(r.sumo_max_deviation_m for r in runs)
        assert [r.verdict for r in plain] == [r.verdict for r in runs]

    n = len(pairs)
    w, wo = statistics.median(with_t), statistics.median(without_t)
    print(f"{len(vehicles)} vehicles x {len(curves)} curves of '{args.sample}' = {n} runs, "
          f"{min(args.batch, n)} in flight, SUMO step {args.sumo_step} s, "
          f"median of {args.repeats} repeats")
    print(f"  SUMO session:        {statistics.median(sumo_s):7.3f} s  {vsteps} vehicle-steps "
          f"in {steps} steps: {statistics.median(rates):,.0f} vehicle-steps/s "
          f"(by CPU time {statistics.median(cpu_rates):,.0f})")
    print(f"  model:               {statistics.median(model_s):7.3f} s")
    print(f"  envelopes+verdicts:  {statistics.median(eval_s):7.3f} s")
    print(f"  through SUMO:        {w:7.3f} s  {n / w:7.1f} runs/s "
          f"(by CPU time {n / statistics.median(with_cpu):.1f} runs/s)")
    wo_cpu = statistics.median(without_cpu)
    print(f"  without SUMO:        {wo:7.3f} s  {n / wo:7.1f} runs/s "
          f"(by CPU time {n / wo_cpu:.1f} runs/s)")
    print(f"  ratio with/without:  {w / wo:7.2f}  (by CPU time "
          f"{statistics.median(with_cpu) / wo_cpu:.2f}; target <= 2)")
    print(f"  largest SUMO deviation from the model: {max_dev:.2e} m; verdicts {verdicts}")


if __name__ == "__main__":
    main()
