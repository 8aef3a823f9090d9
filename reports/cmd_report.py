"""``clearance report``: every vehicle × every curve of every network, with all outputs.

With no arguments it runs the default study: the bundled sample networks and vehicle
tables, output under ``reports/out/``. Everything is written into a fresh folder beside the
output folder and swapped in at the end in one atomic step (:mod:`reports.output_dir`), so
an interrupted or failing run leaves the previous report intact. An existing folder is
replaced only when it is a previous report (:data:`LAYOUT`); anything else is refused.
"""

from __future__ import annotations

import argparse
import logging
import time
from pathlib import Path

from networks.samples.build import SAMPLES, SAMPLES_DIR
from reports.atomic import write_text_atomic
from reports.document import build_sections, html_document, markdown
from reports.exports import EnvelopeRecord
from reports.options import (
    add_clearance_option,
    add_executor_options,
    add_lane_only_option,
    add_selection_options,
    add_table_option,
    add_vehicle_option,
    add_waivers_option,
    selection_of,
)
from reports.output_dir import Layout, output_folder
from reports.study import COLUMNS, METHODS, VERDICT_ORDER, Study, run_study
from reports.tables import clearance_csv, summary_json
from reports.waivers import Waived, read_waivers, study_waivers
from vehicles.table import bundled_table_paths, load_tables

log = logging.getLogger(__name__)

#: The default study's output folder, relative to where the command runs (the repository's
#: ``reports/`` folder when run from its root, as the README does).
DEFAULT_OUTPUT = Path("reports") / "out"

#: What a report writes into its folder (the folder it may replace holds nothing else).
LAYOUT = Layout(
    "report",
    files=frozenset({"clearance.csv", "summary.json", "report.md", "report.html",
                     "swept.geojson", "swept.add.xml", "swept.dxf"}),
    folders={"figures": (".png", ".svg"), "fcd": (".xml",)},
    signature=("clearance.csv", ",".join(COLUMNS[:4])),
)


def sample_networks() -> list[Path]:
    """The bundled sample networks."""
    return [SAMPLES_DIR / n / f"{n}.net.xml" for n in SAMPLES]


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "report",
        help="clearance report: every vehicle through every curve of every network",
        description="Every vehicle x every curve of every network: clearance.csv, "
                    "summary.json, report.html, report.md with figures, swept.geojson, "
                    "swept.add.xml (sumo-gui) and swept.dxf (CAD). Without arguments: the "
                    "bundled sample networks and vehicle tables, output under reports/out/.",
    )
    p.add_argument("-n", "--net", action="append", metavar="NET",
                   help="SUMO network .net.xml[.gz] (repeatable); default: the samples")
    add_table_option(p)
    add_vehicle_option(p)
    p.add_argument("-o", "--output", metavar="DIR", default=None,
                   help=f"output folder (default: {DEFAULT_OUTPUT})")
    p.add_argument("--method", choices=METHODS, default="simulate",
                   help="simulate: drive through libsumo with the kinematic model (default); "
                        "analytic: steady-state geometry")
    add_clearance_option(p)
    add_lane_only_option(p)
    add_executor_options(p)
    p.add_argument("--units", choices=("m", "ft"), default="m",
                   help="units of lengths shown in the report documents")
    p.add_argument("--fcd", action="store_true",
                   help="also write SUMO FCD output (replay with sumo-gui), simulate only")
    add_selection_options(p)
    add_waivers_option(p)
    p.set_defaults(run=run)


def envelope_records(study: Study) -> list[EnvelopeRecord]:
    return [EnvelopeRecord(r.network, r.vehicle, r.curve_id, r.kind, r.verdict, r.margin_m,
                           r.envelope)
            for r in study.records
            if r.verdict != "error" and r.envelope is not None and not r.envelope.is_empty]


def write_report(study: Study, folder: Path, tables: list[Path], units: str = "m",
                 waived: Waived | None = None) -> None:
    """Write every output of ``study`` into ``folder`` (which must be new or empty);
    ``waived`` runs are shown as such (:mod:`reports.waivers`)."""
    from reports.exports import write_dxf, write_geojson, write_sumo_additional

    write_text_atomic(folder / "clearance.csv", clearance_csv(study, waived))
    write_text_atomic(folder / "summary.json", summary_json(study, tables, waived))
    sections = build_sections(study, folder, units, waived)
    write_text_atomic(folder / "report.md", markdown(study, sections, folder, units))
    write_text_atomic(folder / "report.html", html_document(study, sections, units))
    records = envelope_records(study)
    locations = {n.name: n.network.location for n in study.networks}
    write_geojson(folder / "swept.geojson", records, locations)
    write_sumo_additional(folder / "swept.add.xml", records)
    write_dxf(folder / "swept.dxf", records)


def run(args: argparse.Namespace) -> int:
    t0 = time.perf_counter()
    nets = [Path(n) for n in args.net] if args.net else sample_networks()
    tables = [Path(t) for t in args.table] if args.table else bundled_table_paths()
    table = load_tables(tables, args.vehicle)
    selection = selection_of(args)
    waivers = None
    if args.waivers:  # a waiver may name any vehicle of the tables, not only those run
        names = load_tables(tables).names if args.vehicle else table.names
        waivers = read_waivers(Path(args.waivers), names)
    target = Path(args.output) if args.output else DEFAULT_OUTPUT
    with output_folder(target, LAYOUT) as staging:
        fcd = staging / "fcd" if args.fcd else None
        study = run_study(nets, table, args.method, args.clearance, fcd_dir=fcd,
                          workers=args.workers, scheduler=args.scheduler,
                          selection=selection, swing=not args.lane_only)
        waived = study_waivers(study.frame(), waivers) if waivers is not None else None
        write_report(study, staging, tables, args.units, waived)
    frame = study.frame()
    counts = frame.verdict.value_counts()
    print(f"{len(frame)} runs ({len(table)} vehicles, {len(nets)} networks, "
          f"{sum(len(n.curves) for n in study.networks)} curves, method {args.method}) "
          f"in {time.perf_counter() - t0:.1f} s")
    print("  " + ", ".join(f"{v}: {int(counts.get(v, 0))}"
                           for v in sorted(VERDICT_ORDER, key=VERDICT_ORDER.get)))
    if waived is not None:
        print(f"  waived: {len(waived)} runs")
        for w in waived.unused:
            log.warning("%s: waiver matches no run (curve %r, vehicle %r, network %r)",
                        w.where, w.curve_id, w.vehicle, w.network)
    print(f"report: {target / 'report.html'}")
    return 0
