"""``clearance simulate``: drive vehicles through a network's curves in SUMO and judge them.

Each vehicle x curve run follows the curve's centre line with its kinematic model, is
replayed in libsumo (:mod:`clearance.networks.driving.drive`), and gets an envelope and a verdict.
With ``-o DIR`` it writes, byte-identically for identical inputs, into a fresh folder swapped in
for ``DIR`` in one atomic step when everything is written
(:mod:`clearance.reports.output.output_dir`: a
failing or interrupted run leaves the previous output as it was, and an existing ``DIR``
is replaced only when it is an earlier simulate output, :data:`LAYOUT`):

``DIR/results.csv``
    One row per run (:data:`RESULT_COLUMNS`), lengths in metres: the run's measures, its
    verdict beside the lane's, and the design feedback of ``clearance report``'s
    ``clearance.csv`` (the largest vehicle of the run's vehicles that the curve serves, a
    run's worst overreach and the extra width there), filled by the same definitions
    (:func:`run_records`, :mod:`clearance.reports.results.feedback`), so that the two files agree.
``DIR/envelopes.geojson``
    One feature per run: the swept envelope, in longitude/latitude where the network has a
    projection, in its local plane coordinates (metres) otherwise, as the file says
    (:func:`clearance.reports.exports.geojson.write_geojson`).
``DIR/trajectories/<vehicle>__<curve>.csv``
    The model's states of each run (:data:`TRAJECTORY_COLUMNS`), named by
    :func:`clearance.reports.output.file_names.file_name` (letters, digits, ``.``, ``-`` and ``_``;
    a short hash of the ids when anything else was replaced or the name would be too long).
``DIR/fcd.xml``, ``DIR/paths.add.xml``, ``DIR/replay.sumocfg``, ``DIR/replay.sh`` (``--fcd``)
    SUMO's FCD output, each run placed along the path its verdict rests on (the swung path
    where one was taken, the lane's otherwise:
    :attr:`~clearance.networks.driving.runs.DrivenRun.chosen_run`); those paths drawn as
    lines for sumo-gui, the front-bumper centre's, coloured by verdict
    (:func:`~clearance.reports.results.simulate_files.paths_additional`); a configuration
    that loads the network and the paths, and a script to replay the FCD output in sumo-gui
    (the command, with SUMO_HOME set to the installed package, is printed).
"""

from __future__ import annotations

import argparse
import math
import os
import shlex
from collections.abc import Sequence
from contextlib import nullcontext
from dataclasses import replace
from pathlib import Path

from clearance.analysis.tracking import TrackingSettings
from clearance.networks.curves import DEFAULT_KINDS, KINDS, CurveOptions
from clearance.networks.driving.drive import (
    DrivenRun,
    DriveOptions,
    replay_config,
    select_curves,
)
from clearance.networks.integrity import not_at_road_scale
from clearance.networks.loading import load_network
from clearance.networks.model import ROAD_VCLASSES
from clearance.networks.permissions import permits
from clearance.networks.selection import check_junctions, load_selected
from clearance.networks.sumo.placement import replay_command, replay_script
from clearance.reports.cli.options import (
    add_clearance_option,
    add_lane_only_option,
    add_net_option,
    add_output_option,
    add_route_options,
    add_selection_options,
    add_table_option,
    add_vehicle_option,
    route_selection_of,
    selection_of,
)
from clearance.reports.output.atomic import current_umask, write_text_atomic
from clearance.reports.output.output_dir import output_folder
from clearance.reports.results.records import VERDICT_ORDER
from clearance.reports.results.simulate_files import (
    LAYOUT,
    PATHS_FILE,
    result_row,
    run_records,
    write_outputs,
    write_paths,
)
from clearance.reports.results.text_table import format_table
from clearance.reports.study.drives import drive_in_workers
from clearance.reports.study.routes import route_curve_ids, selected_routes
from clearance.reports.study.run import APPROACH_M, network_name
from clearance.vehicles.errors import NetworkError, OptionError
from clearance.vehicles.table import load_tables

__all__ = ["add_parser", "print_summary", "run"]


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
    add_route_options(p, baseline=False)
    add_selection_options(p, kinds_default="all but uturn")
    add_output_option(p, folder=True, metavar="DIR", type=Path,
                      help="write results.csv, envelopes.geojson and trajectories/ here")
    add_clearance_option(p)
    add_lane_only_option(p)
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes that drive the runs (default: one per core)")
    p.add_argument("--fcd", action="store_true",
                   help="also write SUMO's FCD output (DIR/fcd.xml: each run along the "
                        "path its verdict rests on) and those paths (DIR/paths.add.xml) for "
                        "sumo-gui")
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
        raise OptionError(f"--clearance must be a length >= 0 m, not {args.clearance}")
    if args.batch < 1:
        raise OptionError(f"--batch must be >= 1, not {args.batch}")
    if args.fcd and args.output is None:
        raise OptionError("--fcd needs an output folder (-o DIR)")
    if args.fcd and args.no_sumo:
        raise OptionError("--fcd needs SUMO; drop --no-sumo")
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
            raise NetworkError(f"{args.net}: {why}")
        kinds = tuple(dict.fromkeys(args.kind or DEFAULT_KINDS))
        selection = replace(selection_of(args), kinds=kinds)
        if args.routes:  # the passages of the routes only, every kind (U-turns too)
            routes = selected_routes(net, args.routes, args.additional or (),
                                     route_selection_of(args))
            selection = replace(selection, kinds=KINDS, curve_ids=route_curve_ids(net, routes))
        if selection.junctions:
            check_junctions(selection.junctions, [net])
        # the study's lead-ins, so that a run here is the run `clearance report` makes
        curves = select_curves(load_selected(net, selection,
                                             CurveOptions(approach_length_m=APPROACH_M)),
                               args.curve)
        if not curves:
            raise OptionError(f"{args.net}: no curve passes the selection "
                             f"({selection.describe()})")
        if staging is not None and args.fcd:
            options = replace(options, fcd_output=staging / "fcd.xml")
        # as in a study: a vehicle drives only the curves whose lanes admit its SUMO class
        pairs = [(v, c) for v in vehicles for c in curves]
        allowed = [(v, c) for v, c in pairs if permits(net, c, v.vclass)]
        if not allowed:
            raise OptionError(f"{args.net}: no selected curve admits the vehicle(s)' SUMO "
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
                _write_replay(staging, runs, net.path,
                              options.samples_per_step(settings.dt_s) * settings.dt_s)
    if args.output is not None:
        if args.fcd:
            print("replay in sumo-gui: " + replay_command(args.output / "replay.sumocfg",
                                                          args.output / "fcd.xml"))
            print(f"  (or: sh {shlex.quote(str(args.output / 'replay.sh'))})")
        print(f"wrote {len(rows)} run(s) to {args.output}")
    return 0


# ------------------------------------------------------------------------------- replay


def _write_replay(folder: Path, runs: Sequence[DrivenRun], net_path: str | os.PathLike[str],
                  step_s: float) -> None:
    """The chosen paths (``paths.add.xml``), the replay's configuration (the network and
    those paths) and ``replay.sh``, beside ``fcd.xml``."""
    write_paths(folder / PATHS_FILE, runs, network_name(Path(net_path)))
    write_text_atomic(folder / "replay.sumocfg",
                      replay_config(Path(net_path).resolve(), step_s, [PATHS_FILE]))
    write_text_atomic(folder / "replay.sh", replay_script())
    os.chmod(folder / "replay.sh", 0o777 & ~current_umask())


# ------------------------------------------------------------------------------- rows


# ---------------------------------------------------------------------------- summary


def print_summary(rows: Sequence[dict[str, str]], limit: int) -> None:
    """Counts per verdict and an aligned table, worst first."""
    order = VERDICT_ORDER  # worst first
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

