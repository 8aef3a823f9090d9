"""``clearance report``: every vehicle × every curve of every network, with all outputs.

With no arguments it runs the default study: the bundled sample networks and vehicle
tables, output under ``reports/out/``. The study is :func:`clearance.reports.study.run.run_study`;
its folder is written by :func:`clearance.reports.documents.writer.write_report` into a fresh
folder swapped in at the end (:mod:`clearance.reports.output.output_dir`), so an interrupted or
failing run leaves the previous report intact.
"""

from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

from clearance.networks.samples.build import sample_networks
from clearance.reports.cli.options import (
    add_clearance_option,
    add_executor_options,
    add_grade_option,
    add_lane_only_option,
    add_net_option,
    add_output_option,
    add_route_options,
    add_selection_options,
    add_sheet_options,
    add_table_option,
    add_vehicle_option,
    add_waivers_option,
    announcer,
    route_study,
    selection_of,
    sheet_settings_of,
)
from clearance.reports.documents.writer import LAYOUT, write_report
from clearance.reports.exports.geojson import parse_origin
from clearance.reports.output.output_dir import output_folder
from clearance.reports.results.text_table import counted
from clearance.reports.results.waivers import read_waivers, study_waivers
from clearance.reports.study.executor import (
    make_executor,
)
from clearance.reports.study.run import (
    METHODS,
    VERDICT_ORDER,
    run_study,
)
from clearance.vehicles.table import bundled_table_paths, load_tables

__all__ = ["DEFAULT_OUTPUT", "add_parser", "run"]

log = logging.getLogger(__name__)

#: The default study's output folder, relative to where the command runs (the repository's
#: ``reports/`` folder when run from its root, as the README does).
DEFAULT_OUTPUT = Path("reports") / "out"


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "report",
        help="clearance report: every vehicle through every curve of every network",
        description="Every vehicle x every curve of every network: clearance.csv, "
                    "summary.json, report.html, report.md with figures, sheets/<network>.pdf "
                    "(A3 swept-path sheets: an index, then a sheet per vehicle not clear on "
                    "a curve, worst first), and per network "
                    "under exports/: NET.add.xml (sumo-gui -n NET -a NET.add.xml), NET.dxf "
                    "(CAD) and NET.geojson (GIS). Without arguments: the bundled sample "
                    "networks and vehicle tables, output under reports/out/.",
    )
    add_net_option(p, repeatable=True,
                   help="SUMO network .net.xml[.gz] (repeatable); default: the samples")
    add_table_option(p)
    add_vehicle_option(p)
    add_output_option(p, folder=True, metavar="DIR", default=None,
                      help=f"output folder (default: {DEFAULT_OUTPUT})")
    p.add_argument("--method", choices=METHODS, default="simulate",
                   help="simulate: drive through libsumo with the kinematic model (default); "
                        "analytic: steady-state geometry")
    add_clearance_option(p)
    add_grade_option(p)
    add_lane_only_option(p)
    add_executor_options(p)
    p.add_argument("--units", choices=("m", "ft"), default="m",
                   help="units of lengths in clearance.csv, the report documents, sheets "
                        "and figures (the exports stay in the network's metres)")
    p.add_argument("--fcd", action="store_true",
                   help="also write SUMO FCD output (replay with sumo-gui), simulate only")
    p.add_argument("--origin", metavar="LAT,LON", default=None,
                   help="latitude,longitude of the 0,0 point of networks without a "
                        "projection: their GeoJSON in WGS84 (default: local metres)")
    add_selection_options(p)
    add_waivers_option(p)
    add_route_options(p)
    add_sheet_options(p)
    p.add_argument("--svg", action="store_true",
                   help="also write every figure as SVG (vector) beside its PNG under "
                        "figures/ (the sheets under sheets/ are vector PDFs either way)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    t0 = time.perf_counter()
    nets = [Path(n) for n in args.net] if args.net else sample_networks()
    tables = [Path(t) for t in args.table] if args.table else bundled_table_paths()
    table = load_tables(tables, args.vehicle)
    selection = selection_of(args)
    waivers = None
    if args.waivers:  # a waiver may name any vehicle of the tables, not only those run
        names = load_tables(tables, warn=False).names if args.vehicle else table.names
        waivers = read_waivers(Path(args.waivers), names)
    origin = parse_origin(args.origin) if args.origin else None
    sheets = sheet_settings_of(args, table.names)
    target = Path(args.output) if args.output else DEFAULT_OUTPUT
    with output_folder(target, LAYOUT) as staging, \
            make_executor(args.workers, args.scheduler) as executor:
        fcd = staging / "fcd" if args.fcd else None
        options = dict(method=args.method, clearance_m=args.clearance, fcd_dir=fcd,
                       announce=announcer("report"), executor=executor, selection=selection,
                       swing=not args.lane_only, max_grade_pct=args.max_grade_pct)
        routes = route_study(args, nets, table, options)
        study = routes.study if routes is not None else run_study(nets, table, **options)
        log.info("study: %d runs in %.1f s", len(study.records), time.perf_counter() - t0)
        waived = study_waivers(study.frame(), waivers) if waivers is not None else None
        t1 = time.perf_counter()
        write_report(study, staging, tables, args.units, waived, origin, executor, routes,
                     sheets, svg=args.svg)
        log.info("report, figures, sheets and exports written in %.1f s",
                 time.perf_counter() - t1)
    frame = study.frame()
    counts = frame.verdict.value_counts()
    curves = sum(len(n.curves) for n in study.networks)
    print(f"{counted(len(frame), 'run')} ({counted(len(table), 'vehicle')}, "
          f"{counted(len(nets), 'network')}, {counted(curves, 'curve')}, method {args.method}) "
          f"in {time.perf_counter() - t0:.1f} s")
    print("  " + ", ".join(f"{v}: {int(counts.get(v, 0))}"
                           for v in sorted(VERDICT_ORDER, key=VERDICT_ORDER.__getitem__)))
    if study.not_permitted:
        print(f"  not run: {counted(len(study.not_permitted), 'curve')} whose lanes do not "
              "admit the vehicle's SUMO class (per vehicle in the report)")
    if waived is not None:
        print(f"  waived: {counted(len(waived), 'run')}")
        for w in waived.unused:
            log.warning("%s: waiver matches no run (curve %r, vehicle %r, network %r)",
                        w.where, w.curve_id, w.vehicle, w.network)
    print(f"report: {target / 'report.html'}")
    return 0

