"""Printable swept-path sheets: one PDF per network, a sheet per vehicle and curve.

Each sheet is A3 landscape (420 x 297 mm) at a stated scale: the first of :data:`SCALES`
(1:100, 1:200, 1:250, 1:500, then 1:1000 for a large ramp or roundabout) at which the
manoeuvre (the curve's feature and the swept path near it, :func:`manoeuvre_box`) fits the
drawing frame (:func:`fit_scale`). Beside the drawing
(:func:`clearance.reports.documents.drawing.draw_curve`, one vehicle) stand a block of what
the sheet shows (network, curve, tool version, input hashes), the verdict, the vehicle's
data, and at the foot the title block a firm signs
(:func:`clearance.reports.documents.sheet_blocks.title_block`, its fields from
:class:`clearance.reports.documents.sheet_settings.Project`); under the drawing, the legend.

Which runs get a sheet (:func:`pick_sheets`, ``--sheets``): by default every vehicle that
is not clear on a curve, each its own sheet, so that the design vehicle a designer must
show gets one beside a larger vehicle that fails worse; ``all`` every run, ``none`` none.
A second vehicle may stand on each sheet as a grey ghost for comparison (a route study's
baseline, :attr:`SheetSettings.ghost`). A run that passes over itself (a helix) gets a
sheet per storey (:mod:`clearance.reports.documents.storeys`). The PDF opens with an index
of its sheets (:func:`index_pages`). ``clearance report`` writes it as
``sheets/<network>.pdf``.
"""

from __future__ import annotations

import datetime as dt
import io
import textwrap
from collections.abc import Sequence
from dataclasses import astuple, dataclass
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import shapely
from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from clearance.networks.curves import Curve
from clearance.networks.geometry import cut_polyline
from clearance.reports.documents.drawing import (
    BADGE,
    GHOST,
    Shown,
    angle_text,
    draw_curve,
    length_text,
)
from clearance.reports.documents.figures import shown_runs
from clearance.reports.documents.sheet_blocks import (
    LINE_MM,
    PAPER_MM,
    PDF_METADATA,
    block,
    block_height,
    sheet_figure,
    title_block,
    vehicle_rows,
    verdict_rows,
)
from clearance.reports.documents.sheet_settings import DEFAULT_SHEETS, Project, SheetSettings
from clearance.reports.documents.storeys import storey_heights, storey_shown, storey_stretches
from clearance.reports.output.atomic import write_bytes_atomic
from clearance.reports.output.file_names import file_name
from clearance.reports.results.records import VERDICT_ORDER, RunRecord
from clearance.reports.results.tables import _version, sha256_of
from clearance.reports.study.run import NetworkCurves, Study

__all__ = ["BLOCKS_MM", "FRAME_MM", "INDEX_ROWS_MM", "IndexRow", "LEGEND_MM",
           "MANOEUVRE_REACH_M", "SCALES", "SheetPage", "fit_scale", "index_pdf", "join_pdfs",
           "left_out", "manoeuvre_box", "network_sheets_bytes", "pick_sheets", "sheet_pages",
           "sheet_part", "sheet_view", "title_rows", "write_sheets"]

#: Drawing scales tried in order (1:N); the first at which the drawing fits is used.
SCALES = (100, 200, 250, 500, 1000)
#: A sheet shows the swept path this far (m) around the feature: the manoeuvre, not the
#: lead-in and run-out (a bus length either side of the junction).
MANOEUVRE_REACH_M = 12.0
#: The drawing frame on the sheet (x, y, width, height, mm from the lower-left corner):
#: the axes of the plan, inside the border, left of the blocks, above the legend.
FRAME_MM = (22.0, 52.0, 272.0, 233.0)
#: The legend's strip under the drawing (x, top, width, mm).
LEGEND_MM = (22.0, 40.0, 272.0)
#: The column of blocks at the right (x, width, mm), and the foot of its title block (mm).
BLOCKS_MM = (304.0, 106.0)
BLOCKS_FOOT_MM = 8.0
#: The index's table on its sheet (top, foot, mm).
INDEX_ROWS_MM = (272.0, 12.0)


def fit_scale(width_m: float, height_m: float, frame_mm: tuple[float, float] = FRAME_MM[2:],
              scales: Sequence[int] = SCALES) -> int:
    """The first scale ``1:N`` of ``scales`` at which ``width_m x height_m`` fits a frame
    of ``frame_mm`` (width, height); the last one when none does.

    Examples
    --------
    >>> fit_scale(50.0, 40.0)        # 50 m at 1:200 is 250 mm: fits 272 x 233 mm
    200
    >>> fit_scale(60.0, 40.0)        # 300 mm at 1:200, 240 mm at 1:250
    250
    >>> fit_scale(900.0, 10.0)       # too large for every scale: the coarsest
    1000
    """
    for n in scales:
        # (a micrometre of slack: a drawing of exactly the frame's size fits)
        if (width_m * 1000.0 / n <= frame_mm[0] + 1e-3
                and height_m * 1000.0 / n <= frame_mm[1] + 1e-3):
            return n
    return scales[-1]


def pick_sheets(records: Sequence[RunRecord], which: str = "not-clear",
                limit: int | None = None) -> list[RunRecord]:
    """The runs of one network that get a sheet, at most ``limit``, grouped by curve: the
    curves in the order of their worst runs, each curve's runs worst first.

    ``which``: ``not-clear`` every run that is not clear, ``all`` every run, ``none`` none;
    ``error`` runs (nothing to draw) get none. A subset of ``records`` holding the runs
    picked picks them again, in the same order.

    Examples
    --------
    >>> from types import SimpleNamespace as R
    >>> rs = [R(curve_id=c, vehicle=v, verdict=x, margin_m=m) for c, v, x, m in
    ...       [("a", "P", "clear", 0.5), ("a", "T", "fails", -1.0), ("b", "P", "encroaches",
    ...        -0.1), ("b", "T", "fails", -0.5), ("c", "P", "error", float("nan"))]]
    >>> [(r.curve_id, r.vehicle) for r in pick_sheets(rs)]
    [('a', 'T'), ('b', 'T'), ('b', 'P')]
    >>> [(r.curve_id, r.vehicle) for r in pick_sheets(rs, "all")]
    [('a', 'T'), ('a', 'P'), ('b', 'T'), ('b', 'P')]
    >>> [(r.curve_id, r.vehicle) for r in pick_sheets(rs, "all", 1)], pick_sheets(rs, "none")
    ([('a', 'T')], [])
    """
    if which == "none":
        return []
    runs = [r for r in records if r.verdict != "error"
            and (which == "all" or r.verdict != "clear")]
    key = {id(r): (VERDICT_ORDER[r.verdict], r.margin_m, r.vehicle) for r in runs}
    worst: dict[str, tuple] = {}
    for r in runs:
        k = (*key[id(r)][:2], r.curve_id)
        worst[r.curve_id] = min(worst.get(r.curve_id, k), k)
    runs.sort(key=lambda r: (worst[r.curve_id], key[id(r)]))
    return runs if limit is None else runs[:limit]


def manoeuvre_box(curve: Curve, s: Shown, reach_m: float = MANOEUVRE_REACH_M
                  ) -> tuple[float, float, float, float]:
    """What a sheet must show (x0, y0, x1, y1, m): the feature and the envelope within
    ``reach_m`` of it (the manoeuvre; the lead-in and run-out beyond are left to the edge of
    the paper). The envelope alone where the feature has no length.

    Examples
    --------
    >>> import numpy as np, shapely
    >>> from types import SimpleNamespace as S
    >>> line = np.array([[-100.0, 0, 0], [0, 0, 0], [0, 100, 0]])
    >>> c = S(centerline=line, core_start_m=95.0, core_end_m=105.0)
    >>> env = shapely.LineString(line[:, :2]).buffer(1.5)  # 200 m of swept path
    >>> [round(v) for v in manoeuvre_box(c, S(record=S(envelope=env)), 12.0)]
    [-17, -2, 2, 17]
    """
    line = np.asarray(curve.centerline, dtype=float)
    core = cut_polyline(line, curve.core_start_m, curve.core_end_m)[:, :2]
    env = s.record.envelope
    if len(core) < 2 or curve.core_end_m <= curve.core_start_m:
        b = (env.bounds if env is not None and not env.is_empty
             else (*line[:, :2].min(axis=0), *line[:, :2].max(axis=0)))
        return float(b[0]), float(b[1]), float(b[2]), float(b[3])
    x0, y0 = core.min(axis=0)
    x1, y1 = core.max(axis=0)
    if env is not None and not env.is_empty:
        near = shapely.clip_by_rect(env, x0 - reach_m, y0 - reach_m, x1 + reach_m,
                                    y1 + reach_m)
        if not near.is_empty:
            b = near.bounds
            x0, y0, x1, y1 = min(x0, b[0]), min(y0, b[1]), max(x1, b[2]), max(y1, b[3])
    return float(x0), float(y0), float(x1), float(y1)


def sheet_view(curve: Curve, s: Shown) -> tuple[tuple[float, float, float, float], int]:
    """The drawing's bounds (x0, x1, y0, y1, m) and scale ``1:N``: the manoeuvre
    (:func:`manoeuvre_box`) with 3 m around it, at the first scale of :data:`SCALES` that
    fits :data:`FRAME_MM`; the bounds fill the frame exactly at that scale, centred on it."""
    fw, fh = FRAME_MM[2:]
    bx0, by0, bx1, by1 = manoeuvre_box(curve, s)
    pad = 3.0
    x0, x1, y0, y1 = bx0 - pad, bx1 + pad, by0 - pad, by1 + pad
    n = fit_scale(x1 - x0, y1 - y0)
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    half_w, half_h = fw * n / 2000.0, fh * n / 2000.0
    return (cx - half_w, cx + half_w, cy - half_h, cy + half_h), n


@dataclass
class SheetPage:
    """One swept-path sheet: the run shown, the ghost beside it (or None), its run's number
    (a run's storeys share it), and on a run drawn one storey per view
    (:mod:`~clearance.reports.documents.storeys`) which storey: ``(k, count, z_lo_m,
    z_hi_m)``; its scale ``1:N``."""

    shown: Shown
    curve: Curve
    ghost: Shown | None = None
    number: int = 0
    storey: tuple[int, int, float, float] | None = None
    scale: int = 0

    def title(self) -> str:
        """The drawing's title in the title block.

        >>> from types import SimpleNamespace as S
        >>> page = SheetPage(Shown(S(vehicle="CITY-BUS"), "k"), S(kind="ramp", junction="H0",
        ...                  turn_angle_deg=1080.0), storey=(2, 3, 3.2, 6.4))
        >>> page.title()
        'Swept path: CITY-BUS, ramp at junction H0 (+1080°), storey 2 of 3 (3.2 to 6.4 m)'
        """
        c = self.curve
        where = f"{c.kind} at junction {c.junction}" if c.junction else c.kind
        text = (f"Swept path: {self.shown.record.vehicle}, {where} "
                f"({angle_text(c.turn_angle_deg)})")
        if self.storey is not None:
            k, count, lo, hi = self.storey
            text += f", storey {k} of {count} ({lo:.1f} to {hi:.1f} m)"
        return text

    def drawing_number(self, project: Project) -> str:
        """The sheet's drawing number: the project's for its run, ``.k`` for storey k.

        >>> from types import SimpleNamespace as S
        >>> SheetPage(None, None, number=7, storey=(2, 3, 0, 3)).drawing_number(
        ...     Project(drawing_number="HR"))
        'HR-007.2'
        """
        base = project.sheet_number(self.number)
        return base if self.storey is None else f"{base}.{self.storey[0]}"

    def sheet_words(self, total: int) -> str:
        """``7 of 23``, with the storey on a storey's sheet."""
        words = f"{self.number} of {total}"
        return words if self.storey is None else (
            f"{words}, storey {self.storey[0]} of {self.storey[1]}")


def _column(fig: Figure, page: SheetPage, nc: NetworkCurves, units: str,
            head: list[tuple[str, str]], total: int, project: Project,
            vehicles: dict) -> None:
    """The column of blocks right of the drawing: what the sheet shows, the verdict, the
    vehicle, and at its foot the title block. Blocks that would reach into the title block
    are set smaller (never cut short)."""
    W, H = PAPER_MM
    bx, bw = BLOCKS_MM
    s, r, curve = page.shown, page.shown.record, page.curve
    foot = title_block(fig, bx, BLOCKS_FOOT_MM, bw, project, page.title(),
                       page.drawing_number(project), f"1:{page.scale} on A3",
                       page.sheet_words(total))
    rows = [("network", nc.name), ("curve", curve.curve_id), ("kind", curve.kind),
            ("junction", curve.junction or "-"),
            ("units", "feet" if units == "ft" else "metres")] + head
    vehicle = s.driven.vehicle if s.driven is not None else vehicles.get(r.vehicle)
    blocks = [("SWEPT-PATH SHEET", rows),
              ("VERDICT", verdict_rows(s, units, page.ghost)),
              *([("VEHICLE", vehicle_rows(vehicle, units))] if vehicle is not None else [])]
    badge_h, gap = 9.0, 3.0
    room = (H - 10.0) - foot - gap
    need = sum(block_height(rows_) for _, rows_ in blocks) + badge_h + gap * len(blocks)
    k = min(1.0, room / need)
    top = H - 10.0
    for title_, rows_ in blocks:
        if title_ == "VERDICT":
            fig.add_artist(Rectangle((bx / W, (top - badge_h * k) / H), bw / W,
                                     badge_h * k / H, transform=fig.transFigure,
                                     fc=BADGE.get(r.verdict, "black"), ec="black", lw=0.8))
            fig.text((bx + bw / 2) / W, (top - badge_h * k / 2) / H,
                     f"VERDICT: {r.verdict.upper()}", fontsize=11 * k, fontweight="bold",
                     color="white", ha="center", va="center")
            top -= badge_h * k
        top = block(fig, bx, top, bw, title_, rows_, scale=k) - gap * k


def _sheet(nc: NetworkCurves, page: SheetPage, units: str, head: list[tuple[str, str]],
           total: int, project: Project, vehicles: dict) -> Figure:
    W, H = PAPER_MM
    fig = sheet_figure()
    s, curve = page.shown, page.curve
    fx, fy, fw, fh = FRAME_MM
    bounds, page.scale = sheet_view(curve, s)
    ax = fig.add_axes((fx / W, fy / H, fw / W, fh / H))
    handles = draw_curve(ax, nc, curve, [s], units, bounds, bodies=9, badges=False,
                         ghost=page.ghost)
    storey = "" if page.storey is None else (f"   storey {page.storey[0]} of "
                                              f"{page.storey[1]}")
    ax.set_title(f"{s.record.vehicle} on {curve.curve_id}  ({curve.kind}, "
                 f"{angle_text(curve.turn_angle_deg)}){storey}   scale 1:{page.scale} on A3",
                 fontsize=9, loc="left", wrap=True)
    _column(fig, page, nc, units, head, total, project, vehicles)
    lx, ltop, lw = LEGEND_MM
    legend = fig.legend(handles=handles, loc="upper left", fontsize=5.8, ncol=4,
                        bbox_to_anchor=(lx / W, ltop / H, lw / W, 0), frameon=True,
                        handlelength=3.0, title="LEGEND", title_fontsize=7,
                        borderaxespad=0.0, mode="expand")
    legend.get_frame().set_edgecolor("black")
    legend.get_frame().set_linewidth(0.8)
    return fig


def title_rows(nc: NetworkCurves, tables: Sequence[Path], date: str | None = None
               ) -> list[tuple[str, str]]:
    """Date, tool version and input hashes of a network's sheets."""
    rows = [("run on", date or dt.datetime.now(dt.UTC).date().isoformat()),
            ("tool", f"sumo-clearance {_version('sumo-clearance')}, "
                     f"SUMO {_version('eclipse-sumo')}"),
            ("network file", f"{nc.path.name}  sha256 {sha256_of(nc.path)[:16]}")]
    rows += [("vehicle table", f"{Path(t).name}  sha256 {sha256_of(t)[:16]}") for t in tables]
    return rows


def _storey_pages(s: Shown, curve: Curve, ghost: Shown | None, offset_m: float
                  ) -> list[SheetPage]:
    """The pages of one run: one, or one per storey of a run that passes over itself (the
    ghost cut likewise where it turns as many times, else whole on each)."""
    run = s.run
    if run is None:
        return [SheetPage(s, curve, ghost)]
    tr = run.trajectory
    stretches = storey_stretches(curve, tr.theta_rad, tr.s_m)
    if len(stretches) == 1:
        return [SheetPage(s, curve, ghost)]
    g_run = ghost.run if ghost is not None else None
    g_stretches = (storey_stretches(curve, g_run.trajectory.theta_rad, g_run.trajectory.s_m)
                   if g_run is not None else [])
    pages = []
    for k, stretch in enumerate(stretches):
        g = ghost
        if ghost is not None and len(g_stretches) == len(stretches):
            g = storey_shown(ghost, g_stretches[k], offset_m)
        lo, hi = storey_heights(curve, tr.s_m, stretch)
        pages.append(SheetPage(storey_shown(s, stretch, offset_m), curve, g,
                               storey=(k + 1, len(stretches), lo, hi)))
    return pages


def sheet_pages(study: Study, nc: NetworkCurves, settings: SheetSettings = DEFAULT_SHEETS,
                runs: Sequence[RunRecord] | None = None, first: int = 1) -> list[SheetPage]:
    """The sheets of ``runs`` of one network (default: :func:`pick_sheets`), each run driven
    again for its drawing, with its ghost (:attr:`SheetSettings.ghost`'s run on the same
    curve, on every other vehicle's sheet); the runs numbered from ``first`` in their
    order, a run's storeys sharing its number."""
    records = [r for r in study.records if r.network == nc.name]
    if runs is None:
        runs = pick_sheets(records, settings.which, settings.limit)
    numbers = {id(r): first + i for i, r in enumerate(runs)}
    ghosts = {r.curve_id: r for r in records
              if settings.ghost and r.vehicle == settings.ghost and r.verdict != "error"}
    by_curve = {c.curve_id: c for c in nc.curves}
    pages: list[SheetPage] = []
    for cid in dict.fromkeys(r.curve_id for r in runs):
        mine = [r for r in runs if r.curve_id == cid]
        g = ghosts.get(cid)
        extra = [g] if g is not None and any(r.vehicle != g.vehicle for r in mine) else []
        shown = shown_runs(nc, by_curve[cid], mine + extra, study.table)
        ghost = shown[-1] if extra else None
        if ghost is not None:
            ghost.colour = GHOST[0]
        for s in shown[:len(mine)]:
            beside = (ghost if ghost is not None and s.record.vehicle != ghost.record.vehicle
                      else None)
            for page in _storey_pages(s, by_curve[cid], beside, s.record.clearance_m):
                page.number = numbers[id(s.record)]
                pages.append(page)
    pages.sort(key=lambda p: (p.number, p.storey[0] if p.storey else 0))
    return pages


@dataclass(frozen=True)
class IndexRow:
    """One line of a network's sheet index (:func:`index_pdf`), as a part of the sheets
    reports it (:func:`sheet_part`)."""

    number: str
    curve: str
    kind: str
    junction: str
    vehicle: str
    verdict: str
    margins: str
    scale: str

    @classmethod
    def of(cls, page: SheetPage, project: Project, units: str) -> IndexRow:
        """The index line of a drawn ``page`` (its scale set)."""
        r, c = page.shown.record, page.curve
        storey = "" if page.storey is None else f" (storey {page.storey[0]}/{page.storey[1]})"
        return cls(page.drawing_number(project), c.curve_id + storey, c.kind,
                   c.junction or "-", r.vehicle, r.verdict,
                   f"{length_text(r.margin_m, units)} / {length_text(r.paved_margin_m, units)}",
                   f"1:{page.scale}")


def sheet_part(study: Study, nc: NetworkCurves, tables: Sequence[Path], units: str,
               settings: SheetSettings, runs: Sequence[RunRecord], first: int, total: int
               ) -> tuple[bytes, list[IndexRow]]:
    """The sheets of ``runs`` (numbered from ``first`` of ``total``) as one PDF, each sheet
    drawn, saved and closed in turn (a town's hundreds of A3 figures never all in memory),
    and their index lines."""
    pages = sheet_pages(study, nc, settings, runs, first)
    head = title_rows(nc, tables)
    vehicles = {v.name: v for v in study.table.vehicles()}
    rows = []
    buf = io.BytesIO()
    with PdfPages(buf, metadata=PDF_METADATA) as pdf:
        for page in pages:
            fig = _sheet(nc, page, units, head, total, settings.project, vehicles)
            pdf.savefig(fig)
            plt.close(fig)
            rows.append(IndexRow.of(page, settings.project, units))
    return buf.getvalue(), rows


#: The index's columns: heading, x (mm from the frame's left), width (mm).
_INDEX_COLUMNS = (("sheet", 0.0, 28.0), ("curve", 28.0, 92.0), ("kind", 120.0, 16.0),
                  ("junction", 136.0, 30.0), ("vehicle", 166.0, 24.0),
                  ("verdict", 190.0, 18.0), ("margin: lanes / pavement", 208.0, 46.0),
                  ("scale", 254.0, 18.0))


def _index_chunks(rows: Sequence[IndexRow]) -> list[list[list[list[str]]]]:
    """The index's lines wrapped into their columns, in as many sheets as they need."""
    top_mm, foot_mm = INDEX_ROWS_MM
    chunks: list[list[list[list[str]]]] = [[]]
    y = top_mm
    for row in rows:
        cells = [textwrap.wrap(v, max(6, int(w / 1.25)), break_on_hyphens=False) or ["-"]
                 for v, (_, _, w) in zip(astuple(row), _INDEX_COLUMNS, strict=True)]
        h = LINE_MM * max(len(c) for c in cells) + 0.8
        if y - h < foot_mm and chunks[-1]:
            chunks.append([])
            y = top_mm
        chunks[-1].append(cells)
        y -= h
    return chunks


def index_pdf(nc: NetworkCurves, rows: Sequence[IndexRow], head: list[tuple[str, str]],
              project: Project, total: int, left_out: int = 0) -> bytes:
    """The index of a network's sheets, first in its PDF: per sheet its drawing number,
    curve (whole), kind, junction, vehicle, verdict, margins and scale, on as many index
    sheets as the lines need, each with the study's block and the title block;
    ``left_out`` runs that would have had a sheet but for the limit are said there."""
    W, H = PAPER_MM
    fx = FRAME_MM[0]
    chunks = _index_chunks(rows)
    buf = io.BytesIO()
    with PdfPages(buf, metadata=PDF_METADATA) as pdf:
        for n, chunk in enumerate(chunks, start=1):
            fig = sheet_figure()
            fig.text(fx / W, (H - 12) / H, f"Swept-path sheets of {nc.name}: index"
                     + (f" ({n} of {len(chunks)})" if len(chunks) > 1 else ""),
                     fontsize=12, fontweight="bold", va="top")
            y = INDEX_ROWS_MM[0]
            for head_text, x, _ in _INDEX_COLUMNS:
                fig.text((fx + x) / W, y / H, head_text, fontsize=6.5, fontweight="bold")
            y -= 2.0
            fig.add_artist(Rectangle((fx / W, y / H), 272 / W, 0.0,
                                     transform=fig.transFigure, ec="black", lw=0.6))
            for cells in chunk:
                y -= LINE_MM
                for lines, (_, x, _) in zip(cells, _INDEX_COLUMNS, strict=True):
                    for i, line in enumerate(lines):
                        fig.text((fx + x) / W, (y - i * LINE_MM) / H, line, fontsize=6.2)
                y -= LINE_MM * (max(len(c) for c in cells) - 1) + 0.8
            bx, bw = BLOCKS_MM
            title_block(fig, bx, BLOCKS_FOOT_MM, bw, project,
                        f"Swept-path sheets of {nc.name}: index", project.sheet_number(0),
                        "-", f"index {n} of {len(chunks)}")
            more = ([("not drawn", f"{left_out} more runs, past the limit of sheets "
                      "(--max-sheets N, 0 for all): report.html has them")] if left_out else [])
            block(fig, bx, H - 10.0, bw, "STUDY",
                  [("network", nc.name), *head, ("sheets", str(total)), *more])
            pdf.savefig(fig)
            plt.close(fig)
    return buf.getvalue()


def join_pdfs(parts: Sequence[bytes]) -> bytes:
    """One PDF of the pages of ``parts`` in order (pypdf).

    >>> import io
    >>> from pypdf import PdfWriter
    >>> def blank(n):
    ...     w = PdfWriter()
    ...     for _ in range(n):
    ...         w.add_blank_page(100, 100)
    ...     b = io.BytesIO(); w.write(b); return b.getvalue()
    >>> from pypdf import PdfReader
    >>> len(PdfReader(io.BytesIO(join_pdfs([blank(1), blank(2)]))).pages)
    3
    """
    from pypdf import PdfReader, PdfWriter

    writer = PdfWriter()
    for part in parts:
        writer.append(PdfReader(io.BytesIO(part)))
    writer.add_metadata({"/Creator": "sumo-clearance"})
    buf = io.BytesIO()
    writer.write(buf)
    return buf.getvalue()


def network_sheets_bytes(study: Study, nc: NetworkCurves, tables: Sequence[Path],
                         units: str = "m", settings: SheetSettings = DEFAULT_SHEETS
                         ) -> bytes | None:
    """One network's sheets PDF in this process: the index, then every sheet; None when no
    run gets a sheet."""
    records = [r for r in study.records if r.network == nc.name]
    runs = pick_sheets(records, settings.which, settings.limit)
    if not runs:
        return None
    part, rows = sheet_part(study, nc, tables, units, settings, runs, 1, len(runs))
    index = index_pdf(nc, rows, title_rows(nc, tables), settings.project, len(runs),
                      left_out(records, settings))
    return join_pdfs([index, part])


def left_out(records: Sequence[RunRecord], settings: SheetSettings) -> int:
    """How many runs of ``records`` (one network) would have a sheet but for the limit.

    >>> from types import SimpleNamespace as R
    >>> rs = [R(curve_id=c, vehicle="T", verdict="fails", margin_m=-1.0) for c in "abc"]
    >>> left_out(rs, SheetSettings(limit=1)), left_out(rs, SheetSettings(limit=None))
    (2, 0)
    """
    if settings.limit is None:
        return 0
    return max(0, len(pick_sheets(records, settings.which, None)) - settings.limit)


def write_sheets(study: Study, folder: Path, tables: Sequence[Path], units: str = "m",
                 settings: SheetSettings = DEFAULT_SHEETS) -> list[Path]:
    """``folder/<network>.pdf`` for every network with a run to draw; the paths written."""
    written = []
    for nc in study.networks:
        data = network_sheets_bytes(study, nc, tables, units, settings)
        if data is not None:
            written.append(write_bytes_atomic(folder / file_name([nc.name], ".pdf"), data))
    return written
