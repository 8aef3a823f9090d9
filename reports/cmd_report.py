"""``clearance report``: every vehicle × every curve of every network, with all outputs.

With no arguments it runs the default study: the bundled sample networks and vehicle
tables, output under ``reports/out/``. Everything is written into a fresh folder beside the
output folder and swapped in at the end in one atomic step (:mod:`reports.output_dir`), so
an interrupted or failing run leaves the previous report intact. An existing folder is
replaced only when it is a previous report (:data:`LAYOUT`); anything else is refused.

The study's executor stays open for the report: the curve figures, each network's sheets
and each network's exports are drawn in its workers (:class:`Drawings`), which send the
files back as bytes, while this process draws the network plans and writes the tables;
the files are the same whichever process draws them (``tests/reports/test_report.py``).
A drawing whose worker dies is drawn again alone (:func:`reports.executor.run_isolated`);
one that kills its worker even then is lost, and the report says so where it would be.
"""

from __future__ import annotations

import argparse
import logging
import tempfile
import time
from collections.abc import Callable
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Literal

from networks.curves import Curve
from networks.samples.build import SAMPLES, SAMPLES_DIR
from reports.atomic import write_bytes_atomic, write_text_atomic
from reports.batch import bare, with_areas, worker_network
from reports.document import Section, build_sections, html_document
from reports.executor import Executor, SharedFile, WorkerLost, make_executor, run_isolated
from reports.export_geojson import lonlat_transformer, parse_origin
from reports.exports import EnvelopeRecord, conflict_parts
from reports.feedback import overreach_point
from reports.figures import CurveFigure, draw_curve_figure, scratch_files, worst_by_curve
from reports.file_names import file_name
from reports.html_images import COMPACT_MADE, compact_key, compact_png
from reports.markdown import markdown
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
    announcer,
    selection_of,
)
from reports.output_dir import Layout, output_folder
from reports.records import RunRecord
from reports.study import COLUMNS, METHODS, VERDICT_ORDER, NetworkCurves, Study, run_study
from reports.tables import clearance_csv, summary_json
from reports.text_table import counted
from reports.waivers import Waived, read_waivers, study_waivers
from vehicles.table import bundled_table_paths, load_tables

__all__ = ["COMPACT", "DEFAULT_OUTPUT", "DRAWN_RUNS", "LAYOUT", "Drawing", "Drawings",
           "NetworkTask", "add_parser", "curve_figure_files", "draw", "drawn_geometry",
           "envelope_records", "export_names", "network_exports", "network_sheets_pdf", "run",
           "sample_networks", "write_exports", "write_report"]

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
                   help="units of lengths in clearance.csv, the report documents, sheets "
                        "and figures (the exports stay in the network's metres)")
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
        records = {(r.vehicle, r.curve_id): r for r in study.records if r.network == nc.name}
        for row in worst_by_curve(f).head(limit).itertuples():
            curve = by_id[row.curve_id]
            [driven] = rerun(nc, curve, [vehicles[row.vehicle]],
                             [records[(row.vehicle, row.curve_id)]], study.clearance_m)
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
        if r.conflict is not None:  # measured by the worker that ran it
            outside_lanes, outside_pavement = r.conflict
        else:
            curve = curves.get((r.network, r.curve_id))
            lanes, paved = (curve.own_lanes, curve.paved) if curve is not None else (None, None)
            outside_lanes, outside_pavement = conflict_parts(r.envelope, lanes, paved)
        out.append(EnvelopeRecord(
            r.network, r.vehicle, r.curve_id, r.kind, r.verdict, r.margin_m, r.envelope,
            offset_m=r.clearance_m, outside_lanes=outside_lanes,
            outside_pavement=outside_pavement,
            body_outlines=drawn.get((r.network, r.vehicle, r.curve_id), ((), ()))[0],
            wheel_paths=drawn.get((r.network, r.vehicle, r.curve_id), ((), ()))[1],
            overreach=overreach_point(r)))
    return out


def export_names(network: str, georeferenced: bool) -> dict[str, str]:
    """The export files of one network under ``exports/``: sumo-gui, DXF, GeoJSON.

    >>> export_names("roundabout", False)["geojson"]
    'roundabout.local-metres.geojson'
    """
    return {"sumo": file_name([network], ".add.xml"), "dxf": file_name([network], ".dxf"),
            "geojson": file_name([network], ".geojson" if georeferenced
                                 else ".local-metres.geojson")}


def _georeferenced(nc: NetworkCurves, origin: tuple[float, float] | None) -> bool:
    return origin is not None or lonlat_transformer(nc.name, nc.network.location) is not None


def _write_network_exports(out: Path, records: list[EnvelopeRecord], nc: NetworkCurves,
                           names: dict[str, str], origin: tuple[float, float] | None) -> None:
    from reports.export_dxf import write_dxf
    from reports.export_geojson import write_geojson
    from reports.export_sumo import write_sumo_additional

    write_sumo_additional(out / names["sumo"], records)
    write_dxf(out / names["dxf"], records, nc.network)
    write_geojson(out / names["geojson"], records, {nc.name: nc.network.location}, origin)


def write_exports(study: Study, folder: Path, origin: tuple[float, float] | None = None
                  ) -> dict[str, dict[str, str]]:
    """Each network's sumo-gui additional file, DXF and GeoJSON under ``folder/exports``
    (:func:`export_names`); returns the names written by network."""
    from reports.exports import by_network

    groups = by_network(envelope_records(study, drawn_geometry(study)))
    written = {}
    for nc in study.networks:
        names = export_names(nc.name, _georeferenced(nc, origin))
        _write_network_exports(folder / "exports", groups.get(nc.name, []), nc, names, origin)
        written[nc.name] = names
    return written


@dataclass(frozen=True)
class NetworkTask:
    """One network's part of a report, to write in a worker: its records, the curves the
    part draws (without their areas, :func:`reports.batch.bare`), what else it needs."""

    network: str
    path: str
    curves: tuple[Curve, ...]
    records: tuple[RunRecord, ...]
    study: Study  # table, method, clearance (no records, no networks)
    tables: tuple[str, ...] = ()
    units: str = "m"
    names: tuple[tuple[str, str], ...] = ()
    origin: tuple[float, float] | None = None

    def local(self, shared: SharedFile) -> Study:
        """The task's study in this process: its records, its network and curves (with
        their areas built here)."""
        net = worker_network(shared)
        curves = list(self.curves)
        with_areas(net, curves)
        # the file as this worker has it (on a cluster maybe a copy under another folder)
        nc = NetworkCurves(self.network, Path(net.path), net, curves)
        return Study(list(self.records), [nc], self.study.table, self.study.method,
                     self.study.clearance_m)


def network_exports(task: NetworkTask, shared: SharedFile) -> dict[str, bytes]:
    """One network's exports (:func:`write_exports`), as files relative to the report."""
    study = task.local(shared)
    names = dict(task.names)
    recs = envelope_records(study, drawn_geometry(study))
    return scratch_files(lambda root: _write_network_exports(
        root / "exports", recs, study.networks[0], names, task.origin))


def network_sheets_pdf(task: NetworkTask, shared: SharedFile) -> dict[str, bytes]:
    """One network's sheets (:func:`reports.sheets.write_sheets`), as files relative to
    the report."""
    from reports.sheets import write_sheets

    study = task.local(shared)
    return scratch_files(lambda root: write_sheets(study, root / "sheets",
                                                   [Path(t) for t in task.tables], task.units))


#: The name under which a task's files carry the compact copy of a PNG for the HTML
#: (:func:`reports.html_images.compact_png`): this prefix and the copy's key.
COMPACT = "compact:"


def curve_figure_files(task: CurveFigure, shared: SharedFile) -> dict[str, bytes]:
    """A curve figure's files (:func:`reports.figures.draw_curve_figure`) and the compact
    copy of its PNG that report.html embeds (made here, where the PNG is)."""
    files = draw_curve_figure(task, shared)
    for rel in [r for r in files if r.endswith(".png")]:
        key = compact_key(files[rel])
        with tempfile.TemporaryDirectory(prefix="clearance-compact-") as tmp:
            png = Path(tmp) / "figure.png"
            png.write_bytes(files[rel])
            files[COMPACT + key] = compact_png(png)
    return files


@dataclass(frozen=True)
class Drawing:
    """One drawing task of a report: ``fn(task, shared)`` in a worker returns its files by
    their paths relative to the report (:func:`draw`). ``part`` and ``what`` say what the
    report lacks when it is lost: a curve's figure (``curve_id``), a network's sheets or
    its exports."""

    fn: Callable[[Any, SharedFile], dict[str, bytes]]
    task: Any
    network: str
    part: Literal["figure", "sheets", "exports"]
    what: str  # e.g. "sheets (sheets/NET.pdf)"
    curve_id: str = ""


def draw(drawing: Drawing, shared: SharedFile) -> dict[str, bytes]:
    """Draw ``drawing`` in this process: its files by their paths relative to the report."""
    return drawing.fn(drawing.task, shared)


def _cannot_split(drawing: Drawing) -> tuple[Drawing, ...]:
    return ()  # a drawing is one task: one that crashes its worker alone is lost


class Drawings:
    """The figures, sheets and exports of a report drawn in the executor's workers.

    Each :class:`Drawing` is submitted as soon as it is known, so the workers draw while
    the report's process builds the sections; :meth:`finish` waits for them and writes
    their files under ``folder``. The drawings whose worker died (a crash, out of memory)
    are drawn again through :func:`reports.executor.run_isolated`; one that kills its
    worker even alone is lost: warned about, listed in :attr:`lost`, and said in the
    documents by :meth:`mark_lost`."""

    def __init__(self, executor: Executor, folder: Path) -> None:
        self.executor, self.folder = executor, folder
        self._pending: list[tuple[Drawing, str, Future[dict[str, bytes]] | None]] = []
        self._shared: dict[str, SharedFile] = {}
        #: The drawings lost, with the reason.
        self.lost: list[tuple[Drawing, str]] = []

    def submit(self, drawing: Drawing, path: Path) -> None:
        """Start ``drawing`` in a worker, on its copy of the network at ``path``."""
        key = str(path)
        if key not in self._shared:
            self._shared[key] = self.executor.share(path)
        try:
            future = self.executor.submit(draw, drawing, self._shared[key])
        except BrokenProcessPool:  # a worker died: drawn again by finish
            future = None
        self._pending.append((drawing, key, future))

    def curve_figure(self, study: Study, units: str
                     ) -> Callable[[NetworkCurves, Curve, list[RunRecord], Path], Path]:
        """A ``draw`` for :func:`reports.document.build_sections`."""
        def draw_figure(nc: NetworkCurves, curve: Curve, records: list[RunRecord],
                        stem: Path) -> Path:
            rel = stem.relative_to(self.folder).as_posix()
            task = CurveFigure(nc.name, str(nc.path), bare(curve), tuple(records), rel,
                               study.table, units)
            self.submit(Drawing(curve_figure_files, task, nc.name, "figure",
                                f"figure of curve {curve.curve_id} ({rel}.png, .svg)",
                                curve.curve_id), nc.path)
            return Path(f"{stem}.png")
        return draw_figure

    def finish(self) -> None:
        """Wait for every drawing and write its files; draw those whose worker died again
        (:func:`reports.executor.run_isolated`), and give up those that kill it alone."""
        again: dict[str, list[Drawing]] = {}
        for drawing, key, future in self._pending:
            try:
                files = None if future is None else self.executor.outcome(future)
            except WorkerLost as exc:
                log.info("%s: %s: its worker died (%s); drawn again", drawing.network,
                         drawing.what, exc)
                files = None
            if files is None:
                again.setdefault(key, []).append(drawing)
            else:
                self._write(files)
        self._pending.clear()
        for key, drawings in again.items():
            for _, files in run_isolated(self.executor, draw, drawings, _cannot_split,
                                         self._lose, self._shared[key]):
                self._write(files)

    def _write(self, files: dict[str, bytes]) -> None:
        for rel, data in files.items():
            if rel.startswith(COMPACT):
                COMPACT_MADE[rel.removeprefix(COMPACT)] = data
            else:
                write_bytes_atomic(self.folder / rel, data)

    def _lose(self, drawing: Drawing, reason: str) -> dict[str, bytes]:
        self.lost.append((drawing, reason))
        log.warning("%s: %s", drawing.network, _lost_words(drawing.what, reason))
        return {}

    def mark_lost(self, sections: list[Section], exports: dict[str, dict[str, str]]
                  ) -> None:
        """Say in ``sections`` what the lost drawings were to show: a lost figure's curve
        says so in place of it, a network's lost sheets or exports in a line of the
        network's part; the lost exports leave ``exports`` (the files report.html lists)."""
        by_name = {s.name: s for s in sections}
        for drawing, reason in self.lost:
            section = by_name[drawing.network]
            if drawing.part == "figure":
                for c in section.curves:
                    if c.curve_id == drawing.curve_id:
                        c.figure, c.drawn = None, []
                        c.missing = _lost_words("Figure", reason)
                continue
            words = _lost_words(drawing.what, reason)
            section.lost.append(words[:1].upper() + words[1:])
            if drawing.part == "exports":
                exports.pop(drawing.network, None)


def _lost_words(what: str, reason: str) -> str:
    """A lost drawing in words.

    >>> _lost_words("Figure", "killed")
    'Figure not drawn: the worker process died, also when it drew nothing else (killed).'
    """
    return (f"{what} not drawn: the worker process died, also when it drew nothing else "
            f"({reason}).")


def _network_tasks(study: Study, tables: list[Path], units: str,
                   origin: tuple[float, float] | None) -> list[tuple[Drawing, Path]]:
    """The sheets and exports drawing of every network, with the network's file: each
    with the network's records and the curves it draws (those of
    :func:`reports.sheets.pick_sheets` and of :func:`drawn_geometry`)."""
    from reports.sheets import MAX_SHEETS, pick_sheets

    frame = study.frame()
    head = Study([], [], study.table, study.method, study.clearance_m)
    out: list[tuple[Drawing, Path]] = []
    for nc in study.networks:
        records = tuple(r for r in study.records if r.network == nc.name)
        by_id = {c.curve_id: c for c in nc.curves}
        # the sheets' runs pick themselves again from themselves (the worst of each curve
        # first, then the rest worst first), so they are all the sheets task is sent
        sheeted = tuple(pick_sheets(records, MAX_SHEETS))
        sheet_ids = dict.fromkeys(r.curve_id for r in sheeted)
        f = frame[(frame.network == nc.name) & (frame.verdict != "error")]
        drawn = (worst_by_curve(f).head(DRAWN_RUNS) if study.method == "simulate"
                 and not f.empty else f.iloc[:0])
        drawn_ids = dict.fromkeys(drawn.curve_id)
        # the exports drive only their drawn runs again: the others' swung lines (tens of
        # kB each) stay here
        runs = set(zip(drawn.vehicle, drawn.curve_id, strict=True))
        exported = tuple(r if r.line is None or (r.vehicle, r.curve_id) in runs
                         else replace(r, line=None) for r in records)
        names = tuple(export_names(nc.name, _georeferenced(nc, origin)).items())
        base = NetworkTask(nc.name, str(nc.path), (), records, head, tuple(map(str, tables)),
                           units, names, origin)
        sheets = NetworkTask(**{**base.__dict__, "records": sheeted,
                                "curves": tuple(bare(by_id[c]) for c in sheet_ids)})
        exports = NetworkTask(**{**base.__dict__, "records": exported,
                                 "curves": tuple(bare(by_id[c]) for c in drawn_ids)})
        out.append((Drawing(network_sheets_pdf, sheets, nc.name, "sheets",
                            f"sheets (sheets/{file_name([nc.name], '.pdf')})"), nc.path))
        out.append((Drawing(network_exports, exports, nc.name, "exports", "exports ("
                            + ", ".join(f"exports/{n}" for _, n in names) + ")"), nc.path))
    return out


def write_report(study: Study, folder: Path, tables: list[Path], units: str = "m",
                 waived: Waived | None = None, origin: tuple[float, float] | None = None,
                 executor: Executor | None = None) -> None:
    """Write every output of ``study`` into ``folder`` (which must be new or empty);
    ``waived`` runs are shown as such (:mod:`reports.waivers`); ``origin`` (lat, lon)
    places the networks without a projection in the GeoJSON exports. With ``executor``
    the curve figures, sheets and exports are drawn in its workers (:class:`Drawings`)."""
    from reports.sheets import write_sheets

    write_text_atomic(folder / "clearance.csv", clearance_csv(study, waived, units))
    write_text_atomic(folder / "summary.json", summary_json(study, tables, waived))
    if executor is None:
        exports = write_exports(study, folder, origin)
        sections = build_sections(study, folder, units, waived)
        write_sheets(study, folder / "sheets", tables, units)
    else:
        drawings = Drawings(executor, folder)
        for drawing, path in _network_tasks(study, tables, units, origin):
            drawings.submit(drawing, path)
        exports = {nc.name: export_names(nc.name, _georeferenced(nc, origin))
                   for nc in study.networks}
        sections = build_sections(study, folder, units, waived,
                                  draw=drawings.curve_figure(study, units))
        drawings.finish()
        drawings.mark_lost(sections, exports)
    write_text_atomic(folder / "report.md", markdown(study, sections, folder, units))
    write_text_atomic(folder / "report.html", html_document(study, sections, units, exports))


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
    with output_folder(target, LAYOUT) as staging, \
            make_executor(args.workers, args.scheduler) as executor:
        fcd = staging / "fcd" if args.fcd else None
        study = run_study(nets, table, args.method, args.clearance, fcd_dir=fcd,
                          announce=announcer("report"),
                          executor=executor, selection=selection, swing=not args.lane_only,
                          max_grade_pct=args.max_grade_pct)
        log.info("study: %d runs in %.1f s", len(study.records), time.perf_counter() - t0)
        waived = study_waivers(study.frame(), waivers) if waivers is not None else None
        t1 = time.perf_counter()
        write_report(study, staging, tables, args.units, waived, origin, executor)
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
