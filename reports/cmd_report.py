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
from reports.export_geojson import lonlat_transformer, parse_origin
from reports.exports import EnvelopeRecord, conflict_parts
from reports.file_names import file_name
from reports.options import (
    add_clearance_option,
    add_executor_options,
    add_grade_option,
    add_lane_only_option,
    add_net_option,
    add_output_option,
    add_selection_options,
    add_table_option,
    add_vehicle_option,
    add_waivers_option,
    selection_of,
)
from reports.output_dir import Layout, output_folder
from reports.study import COLUMNS, METHODS, VERDICT_ORDER, Study, run_study
from reports.tables import clearance_csv, summary_json
from reports.text_table import counted
from reports.waivers import Waived, read_waivers, study_waivers
from vehicles.table import bundled_table_paths, load_tables

__all__ = ["DEFAULT_OUTPUT", "DRAWN_RUNS", "LAYOUT", "add_parser", "drawn_geometry",
           "envelope_records", "export_names", "run", "sample_networks", "write_exports",
           "write_report"]

log = logging.getLogger(__name__)

#: The default study's output folder, relative to where the command runs (the repository's
#: ``reports/`` folder when run from its root, as the README does).
DEFAULT_OUTPUT = Path("reports") / "out"

#: What a report writes into its folder (the folder it may replace holds nothing else).
LAYOUT = Layout(
    "report",
    # swept.*: the single export files of earlier versions, replaced by exports/
    files=frozenset({"clearance.csv", "summary.json", "report.md", "report.html",
                     "swept.geojson", "swept.add.xml", "swept.dxf"}),
    folders={"figures": (".png", ".svg", ".jpg"), "fcd": (".xml",),
             "exports": (".add.xml", ".dxf", ".geojson"), "sheets": (".pdf",)},
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
                    "summary.json, report.html, report.md with figures, sheets/<network>.pdf "
                    "(A3 swept-path sheets, worst runs first), and per network "
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
                   help="units of lengths shown in the report documents")
    p.add_argument("--fcd", action="store_true",
                   help="also write SUMO FCD output (replay with sumo-gui), simulate only")
    p.add_argument("--origin", metavar="LAT,LON", default=None,
                   help="latitude,longitude of the 0,0 point of networks without a "
                        "projection: their GeoJSON in WGS84 (default: local metres)")
    add_selection_options(p)
    add_waivers_option(p)
    p.set_defaults(run=run)


#: Runs whose vehicle bodies and wheel paths the CAD export draws, per network: the worst
#: run of each of the worst curves, as many as the report draws (they are driven again).
DRAWN_RUNS = 60


def drawn_geometry(study: Study, limit: int = DRAWN_RUNS
                   ) -> dict[tuple[str, str, str], tuple[tuple, tuple]]:
    """Body outlines and wheel paths of the worst run of each of the ``limit`` worst curves
    of every network (not clear ones first; see :func:`reports.drawing.run_geometry`), by
    (network, vehicle, curve id). The runs are driven again without SUMO (the same model,
    so the same paths)."""
    from reports.drawing import rerun, run_geometry
    from reports.figures import worst_by_curve

    out: dict[tuple[str, str, str], tuple[tuple, tuple]] = {}
    if study.method != "simulate":
        return out
    frame = study.frame()
    vehicles = {v.name: v for v in study.table.vehicles()}
    for nc in study.networks:
        f = frame[(frame.network == nc.name) & (frame.verdict != "error")]
        if f.empty:
            continue
        by_id = {c.curve_id: c for c in nc.curves}
        for row in worst_by_curve(f).head(limit).itertuples():
            curve = by_id[row.curve_id]
            [driven] = rerun(nc, curve, [vehicles[row.vehicle]], study.clearance_m)
            out[(nc.name, row.vehicle, row.curve_id)] = run_geometry(curve, driven)
    return out


def envelope_records(study: Study,
                     drawn: dict[tuple[str, str, str], tuple[tuple, tuple]] | None = None
                     ) -> list[EnvelopeRecord]:
    """The exportable runs of ``study``: envelope, offset, conflict with the curve's areas,
    and the body outlines and wheel paths of the runs in ``drawn``
    (:func:`drawn_geometry`)."""
    curves = {(n.name, c.curve_id): c for n in study.networks for c in n.curves}
    drawn = drawn or {}
    out = []
    for r in study.records:
        if r.verdict == "error" or r.envelope is None or r.envelope.is_empty:
            continue
        curve = curves.get((r.network, r.curve_id))
        lanes, paved = (curve.own_lanes, curve.paved) if curve is not None else (None, None)
        outside_lanes, outside_pavement = conflict_parts(r.envelope, lanes, paved)
        out.append(EnvelopeRecord(
            r.network, r.vehicle, r.curve_id, r.kind, r.verdict, r.margin_m, r.envelope,
            offset_m=r.clearance_m, outside_lanes=outside_lanes,
            outside_pavement=outside_pavement,
            body_outlines=drawn.get((r.network, r.vehicle, r.curve_id), ((), ()))[0],
            wheel_paths=drawn.get((r.network, r.vehicle, r.curve_id), ((), ()))[1]))
    return out


def export_names(network: str, georeferenced: bool) -> dict[str, str]:
    """The export files of one network under ``exports/``: sumo-gui, DXF, GeoJSON.

    >>> export_names("roundabout", False)["geojson"]
    'roundabout.local-metres.geojson'
    """
    return {"sumo": file_name([network], ".add.xml"), "dxf": file_name([network], ".dxf"),
            "geojson": file_name([network], ".geojson" if georeferenced
                                 else ".local-metres.geojson")}


def write_exports(study: Study, folder: Path, origin: tuple[float, float] | None = None
                  ) -> dict[str, dict[str, str]]:
    """Each network's sumo-gui additional file, DXF and GeoJSON under ``folder/exports``
    (:func:`export_names`); returns the names written by network."""
    from reports.export_dxf import write_dxf
    from reports.export_geojson import write_geojson
    from reports.export_sumo import write_sumo_additional
    from reports.exports import by_network

    groups = by_network(envelope_records(study, drawn_geometry(study)))
    written = {}
    for nc in study.networks:
        records = groups.get(nc.name, [])
        location = nc.network.location
        georef = origin is not None or lonlat_transformer(nc.name, location) is not None
        names = export_names(nc.name, georef)
        out = folder / "exports"
        write_sumo_additional(out / names["sumo"], records)
        write_dxf(out / names["dxf"], records, nc.network)
        write_geojson(out / names["geojson"], records, {nc.name: location}, origin)
        written[nc.name] = names
    return written


def write_report(study: Study, folder: Path, tables: list[Path], units: str = "m",
                 waived: Waived | None = None, origin: tuple[float, float] | None = None
                 ) -> None:
    """Write every output of ``study`` into ``folder`` (which must be new or empty);
    ``waived`` runs are shown as such (:mod:`reports.waivers`); ``origin`` (lat, lon)
    places the networks without a projection in the GeoJSON exports."""
    from reports.sheets import write_sheets

    write_text_atomic(folder / "clearance.csv", clearance_csv(study, waived))
    write_text_atomic(folder / "summary.json", summary_json(study, tables, waived))
    exports = write_exports(study, folder, origin)
    sections = build_sections(study, folder, units, waived)
    write_text_atomic(folder / "report.md", markdown(study, sections, folder, units))
    write_text_atomic(folder / "report.html", html_document(study, sections, units, exports))
    write_sheets(study, folder / "sheets", tables, units)


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
    target = Path(args.output) if args.output else DEFAULT_OUTPUT
    with output_folder(target, LAYOUT) as staging:
        fcd = staging / "fcd" if args.fcd else None
        study = run_study(nets, table, args.method, args.clearance, fcd_dir=fcd,
                          workers=args.workers, scheduler=args.scheduler,
                          selection=selection, swing=not args.lane_only,
                          max_grade_pct=args.max_grade_pct)
        waived = study_waivers(study.frame(), waivers) if waivers is not None else None
        write_report(study, staging, tables, args.units, waived, origin)
    frame = study.frame()
    counts = frame.verdict.value_counts()
    curves = sum(len(n.curves) for n in study.networks)
    print(f"{counted(len(frame), 'run')} ({counted(len(table), 'vehicle')}, "
          f"{counted(len(nets), 'network')}, {counted(curves, 'curve')}, method {args.method}) "
          f"in {time.perf_counter() - t0:.1f} s")
    print("  " + ", ".join(f"{v}: {int(counts.get(v, 0))}"
                           for v in sorted(VERDICT_ORDER, key=VERDICT_ORDER.__getitem__)))
    if waived is not None:
        print(f"  waived: {counted(len(waived), 'run')}")
        for w in waived.unused:
            log.warning("%s: waiver matches no run (curve %r, vehicle %r, network %r)",
                        w.where, w.curve_id, w.vehicle, w.network)
    print(f"report: {target / 'report.html'}")
    return 0
