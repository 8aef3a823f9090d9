"""The figures, sheets and exports of a report, drawn in the study's worker processes.

Each :class:`Drawing` is one task a worker draws and sends back as files (bytes by their
paths relative to the report); :class:`Drawings` submits them while the report's process
builds the documents, draws again alone those whose worker died
(:func:`clearance.reports.study.executor.run_isolated`), and says in the documents what a
drawing lost for good was to show."""

from __future__ import annotations

import logging
import pickle
import tempfile
from collections.abc import Callable
from concurrent.futures import Future
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Literal

from clearance.networks.curves import Curve
from clearance.reports.documents.figures import (
    CurveFigure,
    draw_curve_figure,
    scratch_files,
    worst_by_curve,
)
from clearance.reports.documents.html_images import COMPACT_MADE, compact_key, compact_png
from clearance.reports.documents.plotting import PNG
from clearance.reports.documents.report import Section
from clearance.reports.documents.sheet_settings import DEFAULT_SHEETS, SheetSettings
from clearance.reports.exports.study import (
    DRAWN_RUNS,
    drawn_geometry,
    envelope_records,
    export_names,
    georeferenced,
    write_network_exports,
)
from clearance.reports.output.atomic import write_bytes_atomic
from clearance.reports.output.file_names import file_name
from clearance.reports.results.records import RunRecord
from clearance.reports.study.batch import bare, with_areas, worker_network
from clearance.reports.study.executor import (
    Executor,
    SharedFile,
    WorkerLost,
    run_isolated,
)
from clearance.reports.study.run import (
    NetworkCurves,
    Study,
    progress_bar,
)

__all__ = ["COMPACT", "SHEETS_PER_TASK", "SHEET_PART", "Drawing", "Drawings", "NetworkTask",
           "SheetsTask", "curve_figure_files", "draw", "network_exports", "network_sheets_pdf",
           "network_tasks"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class NetworkTask:
    """One network's part of a report, to write in a worker: its records, the curves the
    part draws (without their areas, :func:`clearance.reports.study.batch.bare`), what else it
    needs."""

    network: str
    path: str
    curves: tuple[Curve, ...]
    records: tuple[RunRecord, ...]
    study: Study  # table, method, clearance (no records, no networks)
    tables: tuple[str, ...] = ()
    units: str = "m"
    names: tuple[tuple[str, str], ...] = ()
    origin: tuple[float, float] | None = None
    sheets: SheetSettings = DEFAULT_SHEETS
    #: The report's folder when the worker writes there itself (an executor that
    #: :attr:`~clearance.reports.study.executor.Executor.shares_disk`): the exports are
    #: then written in place rather than sent back as bytes.
    into: str | None = None

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
    """One network's exports (:func:`write_exports`): written into the report's folder
    where the task says so (:attr:`NetworkTask.into`; then none are returned), else
    returned as files relative to the report."""
    study = task.local(shared)
    names = dict(task.names)
    recs = envelope_records(study, drawn_geometry(study))

    def write(root: Path) -> None:
        write_network_exports(root / "exports", recs, study.networks[0], names, task.origin)

    if task.into is None:
        return scratch_files(write)
    write(Path(task.into))
    return {}


#: Sheets a sheets task draws at most (a curve's runs kept together): a town's hundreds of
#: sheets spread over the workers, their parts joined into one PDF per network.
SHEETS_PER_TASK = 12
#: The name under which a task's files carry a part of a network's sheets
#: (:class:`SheetsTask`): this prefix, the part's number and the network.
SHEET_PART = "sheets-part:"


@dataclass(frozen=True)
class SheetsTask:
    """A part of a network's sheets to draw in a worker: the runs (vehicle, curve) it
    draws, numbered from ``first`` of ``total``, in the network task's records (which hold
    the ghost's runs on their curves too)."""

    task: NetworkTask
    runs: tuple[tuple[str, str], ...]
    first: int
    total: int
    part: int


def network_sheets_pdf(sheets: SheetsTask, shared: SharedFile) -> dict[str, bytes]:
    """A part of one network's sheets
    (:func:`clearance.reports.documents.sheets.sheet_part`): its PDF and index lines,
    pickled under :data:`SHEET_PART`, which :class:`Drawings` joins
    (:meth:`Drawings.write_sheets`)."""
    from clearance.reports.documents.sheets import sheet_part

    task = sheets.task
    study = task.local(shared)
    by_key = {(r.vehicle, r.curve_id): r for r in study.records}
    runs = [by_key[k] for k in sheets.runs]
    part = sheet_part(study, study.networks[0], [Path(t) for t in task.tables], task.units,
                      task.sheets, runs, sheets.first, sheets.total)
    return {f"{SHEET_PART}{sheets.part:05d}:{task.network}": pickle.dumps((*part, sheets.total))}


#: The name under which a task's files carry the compact copy of a PNG for the HTML
#: (:func:`clearance.reports.documents.html_images.compact_png`): this prefix and the copy's key.
COMPACT = "compact:"


def curve_figure_files(task: CurveFigure, shared: SharedFile) -> dict[str, bytes]:
    """A curve figure's files (:func:`clearance.reports.documents.figures.draw_curve_figure`) and
    the compact
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
    are drawn again through :func:`clearance.reports.study.executor.run_isolated`; one that kills
    its worker even alone is lost: warned about, listed in :attr:`lost`, and said in the
    documents by :meth:`mark_lost`."""

    def __init__(self, executor: Executor, folder: Path) -> None:
        self.executor, self.folder = executor, folder
        self._pending: list[tuple[Drawing, str, Future[dict[str, bytes]] | None]] = []
        self._shared: dict[str, SharedFile] = {}
        #: The parts of each network's sheets drawn (:data:`SHEET_PART`), by part number.
        self._sheet_parts: dict[str, dict[int, bytes]] = {}
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

    def curve_figure(self, study: Study, units: str, formats: tuple[str, ...] = PNG
                     ) -> Callable[[NetworkCurves, Curve, list[RunRecord], Path], Path]:
        """A ``draw`` for :func:`clearance.reports.documents.report.build_sections` (the
        files of ``formats``, PNG first)."""
        def draw_figure(nc: NetworkCurves, curve: Curve, records: list[RunRecord],
                        stem: Path) -> Path:
            rel = stem.relative_to(self.folder).as_posix()
            task = CurveFigure(nc.name, str(nc.path), bare(curve), tuple(records), rel,
                               study.table, units, formats)
            kinds = ", ".join(f".{f}" for f in formats[1:])
            self.submit(Drawing(curve_figure_files, task, nc.name, "figure",
                                f"figure of curve {curve.curve_id} ({rel}.png"
                                + (f", {kinds})" if kinds else ")"), curve.curve_id), nc.path)
            return Path(f"{stem}.png")
        return draw_figure

    def finish(self) -> None:
        """Wait for every drawing and write its files; draw those whose worker died again
        (:func:`clearance.reports.study.executor.run_isolated`), and give up those that kill it
        alone. On a terminal a progress bar counts them (the phase after the study's bar:
        figures, sheets and exports), as the study's bar counts its runs."""
        again: dict[str, list[Drawing]] = {}
        done = progress_bar(len(self._pending), "drawing figures, sheets, exports", "drawing")
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
                done(1)
        self._pending.clear()
        for key, drawings in again.items():
            for _, files in run_isolated(self.executor, draw, drawings, _cannot_split,
                                         self._lose, self._shared[key]):
                self._write(files)
                done(1)

    def _write(self, files: dict[str, bytes]) -> None:
        for rel, data in files.items():
            if rel.startswith(COMPACT):
                COMPACT_MADE[rel.removeprefix(COMPACT)] = data
            elif rel.startswith(SHEET_PART):
                part, network = rel.removeprefix(SHEET_PART).split(":", 1)
                self._sheet_parts.setdefault(network, {})[int(part)] = data
            else:
                write_bytes_atomic(self.folder / rel, data)

    def write_sheets(self, study: Study, tables: list[Path], settings: SheetSettings) -> None:
        """Join each network's sheet parts drawn by the workers into ``sheets/NET.pdf``,
        after an index of them drawn here
        (:func:`clearance.reports.documents.sheets.index_pdf`)."""
        from clearance.reports.documents.sheets import index_pdf, join_pdfs, left_out, title_rows

        for nc in study.networks:
            parts = self._sheet_parts.pop(nc.name, {})
            if not parts:
                continue
            pdfs, rows, total = [], [], 0
            for k in sorted(parts):
                pdf, lines, total = pickle.loads(parts[k])
                pdfs.append(pdf)
                rows += lines
            records = [r for r in study.records if r.network == nc.name]
            index = index_pdf(nc, rows, title_rows(nc, tables), settings.project, total,
                              left_out(records, settings))
            write_bytes_atomic(self.folder / "sheets" / file_name([nc.name], ".pdf"),
                               join_pdfs([index, *pdfs]))

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
                # a worker writing in place may have written some before it died
                for name in exports.pop(drawing.network, {}).values():
                    (self.folder / "exports" / name).unlink(missing_ok=True)


def _lost_words(what: str, reason: str) -> str:
    """A lost drawing in words.

    >>> _lost_words("Figure", "killed")
    'Figure not drawn: the worker process died, also when it drew nothing else (killed).'
    """
    return (f"{what} not drawn: the worker process died, also when it drew nothing else "
            f"({reason}).")


def network_tasks(study: Study, tables: list[Path], units: str,
                  origin: tuple[float, float] | None,
                  sheets_asked: SheetSettings = DEFAULT_SHEETS,
                  into: Path | None = None) -> list[tuple[Drawing, Path]]:
    """The sheets and exports drawing of every network, with the network's file: each
    with the network's records and the curves it draws (those of
    :func:`clearance.reports.documents.sheets.pick_sheets` and of :func:`drawn_geometry`);
    ``into``: the report's folder, where the exports' workers write them
    (:attr:`NetworkTask.into`)."""
    from clearance.reports.documents.sheets import pick_sheets

    frame = study.frame()
    head = Study([], [], study.table, study.method, study.clearance_m)
    out: list[tuple[Drawing, Path]] = []
    for nc in study.networks:
        records = tuple(r for r in study.records if r.network == nc.name)
        by_id = {c.curve_id: c for c in nc.curves}
        picked = pick_sheets(records, sheets_asked.which, sheets_asked.limit)
        f = frame[(frame.network == nc.name) & (frame.verdict != "error")]
        drawn = (worst_by_curve(f).head(DRAWN_RUNS) if study.method == "simulate"
                 and not f.empty else f.iloc[:0])
        drawn_ids = dict.fromkeys(drawn.curve_id)
        # the exports drive only their drawn runs again: the others' swung lines (tens of
        # kB each) stay here
        runs = set(zip(drawn.vehicle, drawn.curve_id, strict=True))
        exported = tuple(r if r.line is None or (r.vehicle, r.curve_id) in runs
                         else replace(r, line=None) for r in records)
        names = tuple(export_names(nc.name, georeferenced(nc, origin)).items())
        base = NetworkTask(nc.name, str(nc.path), (), records, head, tuple(map(str, tables)),
                           units, names, origin, sheets_asked)
        exports = NetworkTask(**{**base.__dict__, "records": exported,
                                 "curves": tuple(bare(by_id[c]) for c in drawn_ids),
                                 "into": None if into is None else str(into)})
        out += [(d, nc.path) for d in _sheet_drawings(base, records, picked, by_id)]
        out.append((Drawing(network_exports, exports, nc.name, "exports", "exports ("
                            + ", ".join(f"exports/{n}" for _, n in names) + ")"), nc.path))
    return out


def _sheet_drawings(base: NetworkTask, records: tuple[RunRecord, ...],
                    picked: list[RunRecord], by_id: dict[str, Curve]) -> list[Drawing]:
    """The sheets of one network in parts of about :data:`SHEETS_PER_TASK` runs, a curve's
    runs in one part: each part with its curves and its runs, the ghost's runs on those
    curves, and the number of its first sheet."""
    groups: list[list[RunRecord]] = []
    for r in picked:
        if groups and groups[-1][-1].curve_id == r.curve_id:
            groups[-1].append(r)
        else:
            groups.append([r])
    parts: list[list[RunRecord]] = [[]]
    for g in groups:
        if parts[-1] and len(parts[-1]) + len(g) > SHEETS_PER_TASK:
            parts.append([])
        parts[-1].extend(g)
    ghost = base.sheets.ghost
    out, first = [], 1
    name = file_name([base.network], ".pdf")
    for k, runs in enumerate(p for p in parts if p):
        ids = dict.fromkeys(r.curve_id for r in runs)
        mine = tuple(runs) + tuple(r for r in records if ghost and r.vehicle == ghost
                                   and r.curve_id in ids and all(r is not p for p in runs))
        task = replace(base, records=mine, curves=tuple(bare(by_id[c]) for c in ids))
        sheets = SheetsTask(task, tuple((r.vehicle, r.curve_id) for r in runs), first,
                            len(picked), k)
        last = first + len(runs) - 1
        out.append(Drawing(network_sheets_pdf, sheets, base.network, "sheets",
                           f"sheets {first} to {last} (sheets/{name})"))
        first = last + 1
    return out
