"""``clearance simulate``: drive vehicles through a network's curves in SUMO and judge them.

Each vehicle x curve run follows the curve's centre line with its kinematic model, is
replayed in libsumo (:mod:`networks.sumo.driver`), and gets an envelope and a verdict. With
``-o DIR`` it writes, byte-identically for identical inputs, into a fresh folder swapped in
for ``DIR`` in one atomic step when everything is written (:mod:`reports.output_dir`: a
failing or interrupted run leaves the previous output as it was, and an existing ``DIR``
is replaced only when it is an earlier simulate output, :data:`LAYOUT`):

``DIR/results.csv``
    One row per run (:data:`RESULT_COLUMNS`), lengths in metres: the run's measures, its
    verdict beside the lane's, and the design feedback of ``clearance report``'s
    ``clearance.csv`` (the largest vehicle of the run's vehicles that the curve serves, a
    run's worst overreach and the extra width there), filled by the same definitions
    (:func:`run_records`, :mod:`reports.feedback`), so that the two files agree.
``DIR/envelopes.geojson``
    One feature per run: the swept envelope, in longitude/latitude where the network has a
    projection, in its local plane coordinates (metres) otherwise, as the file says
    (:func:`reports.export_geojson.write_geojson`).
``DIR/trajectories/<vehicle>__<curve>.csv``
    The model's states of each run (:data:`TRAJECTORY_COLUMNS`), named by
    :func:`reports.file_names.file_name` (letters, digits, ``.``, ``-`` and ``_``; a short
    hash of the ids when anything else was replaced or the name would be too long).
``DIR/fcd.xml``, ``DIR/replay.sumocfg`` and ``DIR/replay.sh`` (with ``--fcd``)
    SUMO's FCD output, a configuration and a script to replay it in sumo-gui (the command,
    with SUMO_HOME set to the installed package, is printed).
"""

from __future__ import annotations

import argparse
import csv
import io
import math
import os
import shlex
import sys
from collections.abc import Iterable, Sequence
from contextlib import nullcontext
from dataclasses import replace
from pathlib import Path

import numpy as np

from analysis.tracking import TrackingSettings
from networks.curves import DEFAULT_KINDS, Curve, CurveOptions
from networks.integrity import not_at_road_scale
from networks.loading import load_network
from networks.model import ROAD_VCLASSES, Network
from networks.permissions import permits
from networks.selection import check_junctions, load_selected
from networks.sumo.driver import (
    DrivenRun,
    DriveOptions,
    replay_config,
    select_curves,
)
from networks.sumo.tools import sumo_home
from reports.atomic import current_umask, write_text_atomic
from reports.batch import DriveTask, detached, driven_record, lost_drive, run_drive, split_drive
from reports.executor import Executor, LocalExecutor, run_isolated
from reports.export_geojson import write_geojson
from reports.exports import EnvelopeRecord
from reports.feedback import set_serves_up_to
from reports.file_names import file_name
from reports.options import (
    add_clearance_option,
    add_lane_only_option,
    add_net_option,
    add_output_option,
    add_selection_options,
    add_table_option,
    add_vehicle_option,
    selection_of,
)
from reports.output_dir import Layout, output_folder
from reports.records import RunRecord
from reports.study import APPROACH_M, network_name
from reports.text_table import format_table
from vehicles.errors import InputError
from vehicles.table import VehicleTable, load_tables
from vehicles.vehicle import Vehicle

__all__ = ["LAYOUT", "RESULT_COLUMNS", "TRAILER_COLUMNS", "TRAJECTORY_COLUMNS", "add_parser",
           "csv_text", "drive_in_workers", "envelope_records", "print_summary", "replay_command",
           "replay_script", "result_row", "run", "run_records", "trajectory_csv",
           "trajectory_files", "write_outputs"]

#: Columns of ``results.csv``.
RESULT_COLUMNS = (
    "vehicle",
    "curve_id",
    "kind",
    "verdict",
    "margin_m",
    "paved_margin_m",
    "max_offtracking_m",
    "max_tracking_error_m",
    "swept_width_m",
    "sumo_max_deviation_m",
    "sumo_steps",
    "lane_verdict",
    "lane_margin_m",
    "path",
    "encroaches_on",
    "reason",
    "serves_up_to",
    "serves_encroaching_up_to",
    "overreach_station_m",
    "overreach_x",
    "overreach_y",
    "extra_width_m",
)

#: Columns of a trajectory CSV (the trailer's only for a vehicle with one).
TRAJECTORY_COLUMNS = ("t_s", "s_m", "x_m", "y_m", "theta_rad", "phi_rad", "xf_m", "yf_m",
                      "error_m", "speed_m_s")
TRAILER_COLUMNS = ("xt_m", "yt_m", "theta_t_rad", "psi_rad")

#: What simulate writes into its output folder (the folder it may replace holds nothing else).
LAYOUT = Layout(
    "simulate",
    files=frozenset({"results.csv", "envelopes.geojson", "fcd.xml", "replay.sumocfg",
                     "replay.sh"}),
    folders={"trajectories": (".csv",)},
    signature=("results.csv", ",".join(RESULT_COLUMNS[:4])),
)


def add_parser(subparsers: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """Register ``simulate`` with the ``clearance`` command."""
    p = subparsers.add_parser(
        "simulate",
        help="drive vehicles through a network's curves in SUMO and judge the clearance",
        description=(
            "Drive each vehicle along each curve's centre line with its kinematic model, "
            "replay it in SUMO (libsumo) and check SUMO's positions, then measure the swept "
            "envelope against the curve's lanes and paved area: clear, encroaches, fails "
            "or cannot-turn. Lengths in metres."
        ),
    )
    add_net_option(p, required=True, type=Path)
    add_table_option(p)
    add_vehicle_option(p, required=True, help="vehicle to drive (repeatable)")
    p.add_argument("--curve", action="append", metavar="ID",
                   help="only this curve (repeatable; ids as `clearance curves` lists them)")
    add_selection_options(p, kinds_default="all but uturn")
    add_output_option(p, folder=True, metavar="DIR", type=Path,
                      help="write results.csv, envelopes.geojson and trajectories/ here")
    add_clearance_option(p)
    add_lane_only_option(p)
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes that drive the runs (default: one per core)")
    p.add_argument("--fcd", action="store_true",
                   help="also write SUMO's FCD output (DIR/fcd.xml) for sumo-gui")
    p.add_argument("--no-sumo", action="store_true",
                   help="compute the runs without SUMO (model, envelopes and verdicts only)")
    p.add_argument("--sumo-step", type=float, default=DriveOptions.sumo_step_s, metavar="S",
                   help="SUMO's step length in seconds, a whole multiple of the model's "
                        f"{TrackingSettings.dt_s:g} s step (default %(default)s; the model "
                        "and the verdicts do not depend on it)")
    p.add_argument("--batch", type=int, default=DriveOptions.batch_size, metavar="N",
                   help="vehicles in flight in SUMO at once (default %(default)s)")
    p.add_argument("--limit", type=int, default=60, metavar="N",
                   help="print at most N rows (default %(default)s)")
    p.set_defaults(run=run)
    return p


def run(args: argparse.Namespace) -> int:
    """Load, drive, print the summary, write the outputs."""
    if not (math.isfinite(args.clearance) and args.clearance >= 0):
        raise InputError(f"--clearance must be a length >= 0 m, not {args.clearance}")
    if args.batch < 1:
        raise InputError(f"--batch must be >= 1, not {args.batch}")
    if args.fcd and args.output is None:
        raise InputError("--fcd needs an output folder (-o DIR)")
    if args.fcd and args.no_sumo:
        raise InputError("--fcd needs SUMO; drop --no-sumo")
    table = load_tables(args.table, list(dict.fromkeys(args.vehicle)))
    vehicles = [table.vehicle(n) for n in dict.fromkeys(args.vehicle)]
    settings = TrackingSettings()
    options = DriveOptions(batch_size=args.batch, offset_m=args.clearance,
                           use_sumo=not args.no_sumo, sumo_step_s=args.sumo_step,
                           swing=not args.lane_only)
    options.samples_per_step(settings.dt_s)  # a step that does not fit: exit 2 before work
    # the output folder is checked and locked before the network is read
    folder = output_folder(args.output, LAYOUT) if args.output is not None else nullcontext()
    with folder as staging:
        net = load_network(args.net)
        if why := not_at_road_scale(net.lanes, ROAD_VCLASSES):
            raise InputError(f"{args.net}: {why}")
        kinds = tuple(dict.fromkeys(args.kind or DEFAULT_KINDS))
        selection = replace(selection_of(args), kinds=kinds)
        if selection.junctions:
            check_junctions(selection.junctions, [net])
        # the study's lead-ins, so that a run here is the run `clearance report` makes
        curves = select_curves(load_selected(net, selection,
                                             CurveOptions(approach_length_m=APPROACH_M)),
                               args.curve)
        if not curves:
            raise InputError(f"{args.net}: no curve passes the selection "
                             f"({selection.describe()})")
        if staging is not None and args.fcd:
            options = replace(options, fcd_output=staging / "fcd.xml")
        # as in a study: a vehicle drives only the curves whose lanes admit its SUMO class
        pairs = [(v, c) for v in vehicles for c in curves]
        allowed = [(v, c) for v, c in pairs if permits(net, c, v.vclass)]
        if not allowed:
            raise InputError(f"{args.net}: no selected curve admits the vehicle(s)' SUMO "
                             f"class ({', '.join(sorted({v.vclass for v in vehicles}))}); "
                             f"nothing to drive")
        if len(allowed) < len(pairs):
            print(f"{len(pairs) - len(allowed)} run(s) not permitted (the curve's lanes do not "
                  f"admit the vehicle's SUMO class) and not driven")
        runs = drive_in_workers(net, allowed, settings, options, args.workers)
        records = run_records(runs, table, options.offset_m, network_name(Path(net.path)))
        rows = [result_row(r, rec) for r, rec in zip(runs, records, strict=True)]
        print_summary(rows, args.limit)
        if staging is not None:
            write_outputs(staging, runs, rows, net)
            if args.fcd:
                write_text_atomic(staging / "replay.sumocfg",
                                  replay_config(Path(net.path).resolve(),
                                                options.samples_per_step(settings.dt_s)
                                                * settings.dt_s))
                write_text_atomic(staging / "replay.sh", replay_script())
                os.chmod(staging / "replay.sh", 0o777 & ~current_umask())
    if args.output is not None:
        if args.fcd:
            print("replay in sumo-gui: " + replay_command(args.output / "replay.sumocfg",
                                                          args.output / "fcd.xml"))
            print(f"  (or: sh {shlex.quote(str(args.output / 'replay.sh'))})")
        print(f"wrote {len(rows)} run(s) to {args.output}")
    return 0


def drive_in_workers(net: Network, pairs: Sequence[tuple[Vehicle, Curve]],
                     settings: TrackingSettings, options: DriveOptions,
                     workers: int | None = None,
                     executor: Executor | None = None) -> list[DrivenRun]:
    """:func:`networks.sumo.driver.drive` in worker processes, so that a crash of SUMO costs only
    the runs that cause it (they come back failed, with the reason; see
    :func:`reports.executor.run_isolated`). With FCD output the runs go to one worker
    (one SUMO session writes one FCD file); otherwise they are shared between the workers.
    ``executor`` replaces the local workers (and is closed).
    """
    detached_curves = {c.curve_id: detached(c) for _, c in pairs}
    pairs = [(v, detached_curves[c.curve_id]) for v, c in pairs]
    with executor or LocalExecutor(workers) as ex:
        n = 1 if options.fcd_output is not None else ex.workers
        size = max(1, -(-len(pairs) // n))
        tasks = [DriveTask(tuple(pairs[k:k + size]), settings, options)
                 for k in range(0, len(pairs), size)]
        finished = [runs for _, runs in run_isolated(ex, run_drive, tasks, split_drive,
                                                     lost_drive, ex.share(net.path))]
    done = {(d.vehicle.name, d.curve.curve_id): d for runs in finished for d in runs}
    return [done[(v.name, c.curve_id)] for v, c in pairs]


# ------------------------------------------------------------------------------- replay


def replay_command(config: Path, fcd: Path) -> str:
    """The shell command that replays ``fcd`` in sumo-gui with SUMO's ``fcdReplay.py``: it
    sets ``SUMO_HOME`` to the installed eclipse-sumo package (a pip install sets none) and
    runs the script with this Python, which has sumolib and traci.

    >>> cmd = replay_command(Path("out/replay.sumocfg"), Path("out/fcd.xml"))
    >>> cmd.startswith("SUMO_HOME=") and cmd.endswith("-k out/replay.sumocfg -f out/fcd.xml")
    True
    """
    home = sumo_home()
    return (f"SUMO_HOME={shlex.quote(str(home))} {shlex.quote(sys.executable)} "
            f"{shlex.quote(str(home / 'tools' / 'fcdReplay.py'))} "
            f"-k {shlex.quote(str(config))} -f {shlex.quote(str(fcd))}")


def replay_script() -> str:
    """``replay.sh``: the replay of :func:`replay_command`, from the folder it lies in."""
    home = sumo_home()
    return ("#!/bin/sh\n# Replays fcd.xml in sumo-gui (written by clearance simulate --fcd).\n"
            'cd "$(dirname "$0")" || exit 1\n'
            f"SUMO_HOME={shlex.quote(str(home))} exec {shlex.quote(sys.executable)} "
            f"{shlex.quote(str(home / 'tools' / 'fcdReplay.py'))} "
            '-k replay.sumocfg -f fcd.xml "$@"\n')


# ------------------------------------------------------------------------------- rows


def _num(value: float | None, digits: int = 3) -> str:
    """A fixed-point number; ``nan``/``None`` is empty, ``-0.000`` is ``0.000``."""
    if value is None or not math.isfinite(value):
        return "" if value is None or math.isnan(value) else str(value)
    text = f"{value:.{digits}f}"
    return text[1:] if text.startswith("-") and float(text) == 0 else text


def run_records(runs: Sequence[DrivenRun], table: VehicleTable, clearance_m: float,
                network: str = "") -> list[RunRecord]:
    """The runs as ``clearance report`` records them (:func:`reports.batch.driven_record`):
    each run's worst overreach (said in its reason) and, per curve over ``table``'s vehicles
    run on it, the largest it serves (:func:`reports.feedback.set_serves_up_to`)."""
    records = [driven_record(network, r, clearance_m, conflict=False) for r in runs]
    set_serves_up_to(records, table)
    return records


def result_row(r: DrivenRun, rec: RunRecord) -> dict[str, str]:
    """One ``results.csv`` row (metres to the millimetre): the run's measures, and its
    record's (:func:`run_records`) reason and design feedback."""
    res = r.result
    return {
        "vehicle": r.vehicle.name,
        "curve_id": r.curve.curve_id,
        "kind": r.curve.kind,
        "verdict": r.verdict,
        "margin_m": _num(res.clearance.margin_m if res else None),
        "paved_margin_m": _num(res.clearance.paved_margin_m if res else None),
        "max_offtracking_m": _num(res.swept.max_offtracking_m if res else None),
        "max_tracking_error_m": _num(r.run.max_error_m if r.run else None),
        "swept_width_m": _num(res.swept.max_swept_width_m if res else None),
        "sumo_max_deviation_m": _num(r.sumo_max_deviation_m, 4),
        "sumo_steps": str(r.sumo_steps),
        "lane_verdict": r.lane_verdict,
        "lane_margin_m": _num(r.lane_margin_m),
        "path": r.path,
        "encroaches_on": r.encroaches_on,
        "reason": rec.reason,
        "serves_up_to": rec.serves_up_to,
        "serves_encroaching_up_to": rec.serves_encroaching_up_to,
        "overreach_station_m": _num(rec.overreach_station_m),
        "overreach_x": _num(rec.overreach_x),
        "overreach_y": _num(rec.overreach_y),
        "extra_width_m": _num(rec.extra_width_m),
    }


def csv_text(rows: Iterable[dict[str, str]], columns: Sequence[str]) -> str:
    """CSV with ``\\n`` line ends."""
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(columns), lineterminator="\n")
    w.writeheader()
    w.writerows(rows)
    return buf.getvalue()


def trajectory_files(runs: Sequence[DrivenRun]) -> list[str]:
    """``<vehicle>__<curve>.csv`` for each run (:func:`reports.file_names.file_name`)."""
    return [file_name([r.vehicle.name, r.curve.curve_id], ".csv") for r in runs]


def trajectory_csv(r: DrivenRun) -> str:
    """The model's states of one run as CSV (4 decimals)."""
    tr = r.run.trajectory if r.run is not None else None
    assert tr is not None
    cols = list(TRAJECTORY_COLUMNS)
    if tr.xt_m is not None:
        cols += TRAILER_COLUMNS
    data = np.column_stack([getattr(tr, c) for c in cols])
    data = np.round(data, 4) + 0.0  # + 0.0 turns -0.0 into 0.0
    lines = [",".join(cols)]
    lines += [",".join(f"{v:.4f}" for v in row) for row in data]
    return "\n".join(lines) + "\n"


def envelope_records(runs: Sequence[DrivenRun], network: str) -> list[EnvelopeRecord]:
    """The runs' swept envelopes as export records (runs SUMO failed are left out)."""
    return [EnvelopeRecord(network, r.vehicle.name, r.curve.curve_id, r.curve.kind,
                           r.result.verdict, r.result.margin_m, r.result.swept.envelope)
            for r in runs if r.result is not None and not r.error]


def write_outputs(out_dir: Path, runs: Sequence[DrivenRun], rows: Sequence[dict[str, str]],
                  net: Network) -> None:
    """results.csv, envelopes.geojson and one trajectory CSV per run, each atomically."""
    for r, name in zip(runs, trajectory_files(runs), strict=True):
        if r.run is None:
            continue
        write_text_atomic(out_dir / "trajectories" / name, trajectory_csv(r))
    name = network_name(Path(net.path))
    write_geojson(out_dir / "envelopes.geojson", envelope_records(runs, name),
                  {name: net.location})
    write_text_atomic(out_dir / "results.csv", csv_text(rows, RESULT_COLUMNS))


# ---------------------------------------------------------------------------- summary


def print_summary(rows: Sequence[dict[str, str]], limit: int) -> None:
    """Counts per verdict and an aligned table, worst first."""
    order = {"error": 0, "cannot-turn": 1, "fails": 2, "encroaches": 3, "clear": 4}
    counts = {v: sum(1 for r in rows if r["verdict"] == v) for v in order}
    print(f"{len(rows)} run(s): " + ", ".join(f"{n} {v}" for v, n in counts.items() if n))
    if not rows:
        return
    shown = sorted(rows, key=lambda r: (order.get(r["verdict"], 9),
                                        float(r["margin_m"] or "inf"), r["vehicle"],
                                        r["curve_id"]))
    shown = shown[: max(limit, 0)]
    cols = ("vehicle", "curve_id", "verdict", "margin_m", "max_offtracking_m",
            "swept_width_m", "sumo_max_deviation_m")
    heads = ("vehicle", "curve", "verdict", "margin [m]", "offtracking [m]", "swept [m]",
             "SUMO dev [m]")
    print("\n".join(format_table(shown, cols, heads, 3)))
    if len(rows) > len(shown):
        print(f"... {len(rows) - len(shown)} more (worst first; see results.csv)")

