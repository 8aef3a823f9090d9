"""Printable swept-path sheets: one PDF per network, one sheet per vehicle and curve.

Each sheet is A3 landscape (420 x 297 mm) at a stated scale: the first of
:data:`SCALES` (1:200, 1:250, 1:500, then 1:1000 for a large ramp or roundabout) at which
the curve's feature and the vehicle's envelope fit the drawing frame (:func:`fit_scale`).
Beside the drawing (:func:`clearance.reports.documents.drawing.draw_curve`, one vehicle) stand a
title block (network, curve, junction, date, tool version, input hashes), a vehicle data block
(dimensions, lock, CTR, steering speed, source), a verdict block and the legend.

One vehicle a sheet keeps the drawing legible (bodies at intervals, wheel paths and
dimensions of one vehicle) and gives the vehicle block one vehicle to describe. A network
gets at most :data:`MAX_SHEETS` sheets, worst first (:func:`pick_sheets`): the worst run of
each curve in the order of the curves' worst runs, then the next runs of those curves.
``clearance report`` writes them as ``sheets/<network>.pdf``.
"""

from __future__ import annotations

import datetime as dt
import io
import math
import textwrap
from collections.abc import Sequence
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import shapely
from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from clearance.analysis.turning import centre_line_radius
from clearance.networks.curves import Curve
from clearance.networks.geometry import cut_polyline
from clearance.reports.documents.drawing import (
    BADGE,
    Shown,
    angle_text,
    draw_curve,
    length_text,
    path_words,
    rerun,
    stop_words,
)
from clearance.reports.documents.plotting import STYLE, vehicle_colours
from clearance.reports.output.atomic import write_bytes_atomic
from clearance.reports.output.file_names import file_name
from clearance.reports.results.records import VERDICT_ORDER, RunRecord
from clearance.reports.results.tables import _version, sha256_of
from clearance.reports.results.units import text_in_units
from clearance.reports.study.run import NetworkCurves, Study
from clearance.vehicles.vehicle import Vehicle

__all__ = ["BLOCKS_MM", "FRAME_MM", "MAX_SHEETS", "MM", "PAPER_MM", "SCALES", "fit_scale",
           "network_sheets", "pick_sheets", "sheet_view", "title_rows", "vehicle_rows",
           "verdict_rows", "write_sheets"]

#: Drawing scales tried in order (1:N); the first at which the drawing fits is used.
SCALES = (100, 200, 250, 500, 1000)
#: A sheet shows the swept path this far (m) around the feature: the manoeuvre, not the
#: lead-in and run-out (a bus length either side of the junction).
MANOEUVRE_REACH_M = 12.0
#: Paper: A3 landscape, millimetres.
PAPER_MM = (420.0, 297.0)
#: Sheets per network at most (worst first).
MAX_SHEETS = 12
MM = 1 / 25.4
#: The drawing frame on the sheet (x, y, width, height, mm from the lower-left corner):
#: the axes of the plan, inside the border, left of the blocks.
FRAME_MM = (22.0, 18.0, 272.0, 267.0)
#: The column of blocks at the right (x, width, mm).
BLOCKS_MM = (304.0, 106.0)


def fit_scale(width_m: float, height_m: float, frame_mm: tuple[float, float] = FRAME_MM[2:],
              scales: Sequence[int] = SCALES) -> int:
    """The first scale ``1:N`` of ``scales`` at which ``width_m x height_m`` fits a frame
    of ``frame_mm`` (width, height); the last one when none does.

    Examples
    --------
    >>> fit_scale(50.0, 40.0)        # 50 m at 1:200 is 250 mm: fits 272 x 267 mm
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


def pick_sheets(records: Sequence[RunRecord], limit: int = MAX_SHEETS) -> list[RunRecord]:
    """The runs of one network that get a sheet, worst first, at most ``limit``.

    The worst run of every curve comes first (curves in the order of their worst runs),
    then the other runs worst first; ``error`` runs (nothing to draw) get none.

    Examples
    --------
    >>> from types import SimpleNamespace as R
    >>> rs = [R(curve_id=c, vehicle=v, verdict=x, margin_m=m) for c, v, x, m in
    ...       [("a", "P", "clear", 0.5), ("a", "T", "fails", -1.0), ("b", "P", "encroaches",
    ...        -0.1), ("b", "T", "fails", -0.5), ("c", "P", "error", math.nan)]]
    >>> [(r.curve_id, r.vehicle) for r in pick_sheets(rs)]
    [('a', 'T'), ('b', 'T'), ('b', 'P'), ('a', 'P')]
    >>> [(r.curve_id, r.vehicle) for r in pick_sheets(rs, 1)]
    [('a', 'T')]
    """
    runs = [r for r in records if r.verdict != "error"]
    runs.sort(key=lambda r: (VERDICT_ORDER[r.verdict], r.margin_m, r.curve_id, r.vehicle))
    firsts, seen = [], set()
    for r in runs:
        if r.curve_id not in seen:
            seen.add(r.curve_id)
            firsts.append(r)
    rest = [r for r in runs if all(r is not f for f in firsts)]
    return (firsts + rest)[:limit]


def vehicle_rows(v: Vehicle, units: str) -> list[tuple[str, str]]:
    """The vehicle data block: dimensions, lock, CTR, steering speed, trailer, source."""
    L = lambda x: length_text(x, units)  # noqa: E731
    ctr = float(centre_line_radius(v.min_radius_m, v.wheelbase_m))
    rows = [("vehicle", v.name), ("category", v.category or "-"),
            ("overall length", L(v.overall_length_m)), ("width", L(v.width_m)),
            ("wheelbase", L(v.wheelbase_m)), ("front / rear overhang",
                                              f"{L(v.front_overhang_m)} / {L(v.rear_overhang_m)}"),
            ("track (steered axle)", L(v.track_m)), ("steered axle", v.steered_axle),
            ("lock (inner wheel)", f"{math.degrees(v.max_inner_steer_rad):.1f}°"),
            ("lock (bicycle angle)", f"{math.degrees(v.max_steer_rad):.1f}°"),
            ("CTR at full lock", L(ctr)),
            ("steering speed", f"{math.degrees(v.max_steer_rate_rad_s):.1f}°/s (road wheel)")]
    t = v.trailer
    if t is not None:
        rows += [("trailer: kingpin behind axle", L(t.hitch_offset_m)),
                 ("trailer wheelbase", L(t.wheelbase_m)), ("trailer width", L(t.width_m)),
                 ("trailer front / rear overhang",
                  f"{L(t.front_overhang_m)} / {L(t.rear_overhang_m)}"),
                 ("max articulation", f"{math.degrees(t.max_articulation_rad):.0f}°")]
    rows.append(("source", v.source or "-"))
    return rows


def verdict_rows(s: Shown, units: str) -> list[tuple[str, str]]:
    """The verdict block's rows (the badge is drawn above them)."""
    r = s.record
    L = lambda x: length_text(x, units)  # noqa: E731
    rows = [("margin to its own lanes", L(r.margin_m)),
            ("margin to the pavement", L(r.paved_margin_m)),
            ("largest swept width", L(r.swept_width_m)),
            ("lane width (narrowest)", L(r.available_width_m)),
            ("largest offtracking", L(r.max_offtracking_m)),
            *([("largest trailer offtracking", L(r.trailer_offtracking_m))]
              if math.isfinite(getattr(r, "trailer_offtracking_m", math.nan)) else []),
            ("largest tracking error", L(r.max_tracking_error_m)),
            ("clearance offset", L(r.clearance_m)), ("method", r.method)]
    rows.append(("path", path_words(s, units).split(": ", 1)[1]))
    run = s.run
    why = (stop_words(run, units) if run is not None and run.reason
           else text_in_units(r.reason, units))
    rows.append(("why", why or "-"))
    extra = getattr(r, "extra_width_m", math.nan)
    if math.isfinite(extra):
        beyond = "the pavement" if r.verdict == "fails" else "its own lanes"
        rows.append(("worst overreach", f"station {L(r.overreach_station_m)} (x "
                     f"{r.overreach_x:.2f}, y {r.overreach_y:.2f}): {beyond} needs {L(extra)} "
                     "more width there"))
    served = getattr(r, "serves_up_to", "")
    rows.append(("curve serves up to", f"{served or 'no vehicle of the study'} (clear), "
                 f"{getattr(r, 'serves_encroaching_up_to', '') or 'none'} (stays paved)"))
    return rows


def _block(fig: Figure, x: float, top: float, w: float, title: str,
           rows: Sequence[tuple[str, str]], wrap: int = 44, max_lines: int = 4) -> float:
    """A ruled block of ``rows`` (label, value) under ``title``, top edge at ``top`` (mm);
    returns the bottom edge (mm). Long values wrap at ``wrap`` characters."""
    W, H = PAPER_MM
    line = 3.3
    lines: list[tuple[str, str]] = []
    for label, value in rows:
        parts = textwrap.wrap(str(value), wrap) or ["-"]
        if len(parts) > max_lines:
            parts = parts[:max_lines]
            parts[-1] = parts[-1][: wrap - 1] + "…"
        lines += [(label, parts[0])] + [("", p) for p in parts[1:]]
    h = 6.0 + line * len(lines) + 1.5
    y0 = top - h
    fig.add_artist(Rectangle((x / W, y0 / H), w / W, h / H,
                             transform=fig.transFigure, fc="white", ec="black", lw=0.8))
    fig.add_artist(Rectangle((x / W, (top - 5.5) / H), w / W, 5.5 / H,
                             transform=fig.transFigure, fc="#e8e8e8", ec="black", lw=0.8))
    fig.text((x + 2) / W, (top - 2.75) / H, title, fontsize=7.5, fontweight="bold",
             va="center")
    y = top - 5.5 - line * 0.8
    for label, value in lines:
        fig.text((x + 2) / W, y / H, label, fontsize=6.2, va="center", color="#333333")
        fig.text((x + 42) / W, y / H, value, fontsize=6.2, va="center")
        y -= line
    return y0


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


def _sheet(nc: NetworkCurves, s: Shown, units: str, title_rows: list[tuple[str, str]],
           number: int, total: int, vehicles: dict[str, Vehicle]) -> Figure:
    W, H = PAPER_MM
    with plt.rc_context(STYLE):
        fig = plt.figure(figsize=(W * MM, H * MM))
    fig.add_artist(Rectangle((5 / W, 5 / H), (W - 10) / W, (H - 10) / H,
                             transform=fig.transFigure, fc="none", ec="black", lw=1.2))
    curve = {c.curve_id: c for c in nc.curves}[s.record.curve_id]
    fx, fy, fw, fh = FRAME_MM
    bounds, n = sheet_view(curve, s)
    ax = fig.add_axes((fx / W, fy / H, fw / W, fh / H))
    handles = draw_curve(ax, nc, curve, [s], units, bounds, bodies=9, badges=False)
    ax.set_title(f"{s.record.vehicle} on {curve.curve_id}  ({curve.kind}, "
                 f"{angle_text(curve.turn_angle_deg)})   scale 1:{n} on A3", fontsize=9,
                 loc="left")
    bx, bw = BLOCKS_MM
    top = H - 10.0
    rows = [("network", nc.name), ("curve", curve.curve_id), ("kind", curve.kind),
            ("junction", curve.junction or "-"), ("scale", f"1:{n} (A3 landscape)"),
            ("units", "feet" if units == "ft" else "metres")] + title_rows + [
            ("sheet", f"{number} of {total}")]
    top = _block(fig, bx, top, bw, "SWEPT-PATH SHEET", rows) - 3.0
    r = s.record
    badge_h = 9.0
    fig.add_artist(Rectangle((bx / W, (top - badge_h) / H), bw / W, badge_h / H,
                             transform=fig.transFigure, fc=BADGE.get(r.verdict, "black"),
                             ec="black", lw=0.8))
    fig.text((bx + bw / 2) / W, (top - badge_h / 2) / H, f"VERDICT: {r.verdict.upper()}",
             fontsize=11, fontweight="bold", color="white", ha="center", va="center")
    top = _block(fig, bx, top - badge_h, bw, "VERDICT", verdict_rows(s, units)) - 3.0
    vehicle = s.driven.vehicle if s.driven is not None else vehicles.get(r.vehicle)
    if vehicle is not None:
        top = _block(fig, bx, top, bw, "VEHICLE", vehicle_rows(vehicle, units),
                     max_lines=3) - 3.0
    legend = fig.legend(handles=handles, loc="upper left", fontsize=5.8, ncol=2,
                        bbox_to_anchor=(bx / W, top / H), frameon=True, handlelength=3.0,
                        title="LEGEND", title_fontsize=7, borderaxespad=0.0)
    legend.get_frame().set_edgecolor("black")
    legend.get_frame().set_linewidth(0.8)
    return fig


def title_rows(nc: NetworkCurves, tables: Sequence[Path], date: str | None = None
               ) -> list[tuple[str, str]]:
    """Date, tool version and input hashes of a network's sheets."""
    rows = [("date", date or dt.datetime.now(dt.UTC).date().isoformat()),
            ("tool", f"sumo-clearance {_version('sumo-clearance')}, "
                     f"SUMO {_version('eclipse-sumo')}"),
            ("network file", f"{nc.path.name}  sha256 {sha256_of(nc.path)[:16]}")]
    rows += [("vehicle table", f"{Path(t).name}  sha256 {sha256_of(t)[:16]}") for t in tables]
    return rows


def network_sheets(study: Study, nc: NetworkCurves, tables: Sequence[Path],
                   units: str = "m", limit: int = MAX_SHEETS) -> list[Figure]:
    """The sheets of one network as figures (the caller closes them)."""
    records = [r for r in study.records if r.network == nc.name]
    chosen = pick_sheets(records, limit)
    colours = vehicle_colours(study.table.names)
    by_name = {v.name: v for v in study.table.vehicles()}
    by_curve = {c.curve_id: c for c in nc.curves}
    shown = [Shown(r, colours[r.vehicle]) for r in chosen]
    for cid in dict.fromkeys(r.curve_id for r in chosen):
        group = [s for s in shown if s.record.curve_id == cid and s.record.method == "simulate"]
        if not group:  # analytic runs: drawn by their envelopes alone
            continue
        runs = rerun(nc, by_curve[cid], [by_name[s.record.vehicle] for s in group],
                     [s.record for s in group], study.clearance_m)
        for s, d in zip(group, runs, strict=True):
            s.driven = d
    head = title_rows(nc, tables)
    return [_sheet(nc, s, units, head, i, len(shown), by_name)
            for i, s in enumerate(shown, start=1)]


def write_sheets(study: Study, folder: Path, tables: Sequence[Path], units: str = "m",
                 limit: int = MAX_SHEETS) -> list[Path]:
    """``folder/<network>.pdf`` for every network with a run to draw; the paths written."""
    written = []
    for nc in study.networks:
        figs = network_sheets(study, nc, tables, units, limit)
        if not figs:
            continue
        buf = io.BytesIO()
        with PdfPages(buf, metadata={"Creator": "sumo-clearance", "CreationDate": None}) as pdf:
            for fig in figs:
                pdf.savefig(fig)
                plt.close(fig)
        written.append(write_bytes_atomic(folder / file_name([nc.name], ".pdf"),
                                          buf.getvalue()))
    return written
