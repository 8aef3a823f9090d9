"""The blocks of text beside a sheet's drawing: ruled blocks of rows, the vehicle data, the
verdict, and the title block a firm signs.

Every block is drawn in paper millimetres on an A3 landscape figure
(:data:`PAPER_MM`); a long value wraps onto as many lines as it needs: nothing is cut
short. The title block (:func:`title_block`) sits at the foot of the column of blocks, as
on a drawing office's sheet: the project, the drawing's title, its number and revision,
the scale, the sheet's number, and who drew, checked and approved it, with blank boxes
where they sign and date.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence

import matplotlib.pyplot as plt
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from clearance.analysis.turning import centre_line_radius
from clearance.reports.documents.drawing import Shown, length_text, path_words, stop_words
from clearance.reports.documents.plotting import STYLE
from clearance.reports.documents.sheet_settings import Project
from clearance.reports.results.units import text_in_units
from clearance.vehicles.vehicle import Vehicle

__all__ = ["LINE_MM", "MM", "PAPER_MM", "PDF_METADATA", "ROW_MM", "block", "block_height",
           "sheet_figure", "title_block", "vehicle_rows", "verdict_rows", "wrapped_rows"]

#: Paper: A3 landscape, millimetres.
PAPER_MM = (420.0, 297.0)
MM = 1 / 25.4
#: Height of one line of a block's text (mm).
LINE_MM = 3.3
#: A title block row's height (mm): number, revision, scale, sheet, the signatures.
ROW_MM = 8.0
#: What every PDF of sheets says of itself (no creation date: the same inputs give the same
#: file).
PDF_METADATA = {"Creator": "sumo-clearance", "CreationDate": None}


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


def verdict_rows(s: Shown, units: str, ghost: Shown | None = None) -> list[tuple[str, str]]:
    """The verdict block's rows (the badge is drawn above them); with ``ghost``, the
    vehicle shown beside it for comparison and its verdict on the same curve."""
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
    if ghost is not None:
        g = ghost.record
        rows.append(("compared with", f"{g.vehicle} (grey): {g.verdict}, margin to its "
                     f"own lanes {L(g.margin_m)}, to the pavement {L(g.paved_margin_m)}"))
    return rows


def wrapped_rows(rows: Sequence[tuple[str, str]], wrap: int) -> list[tuple[str, str]]:
    """``rows`` (label, value) as lines: each value wrapped at ``wrap`` characters onto as
    many lines as it needs, the label on its first.

    >>> wrapped_rows([("curve", "a" * 10), ("kind", "")], 4)
    [('curve', 'aaaa'), ('', 'aaaa'), ('', 'aa'), ('kind', '-')]
    """
    lines: list[tuple[str, str]] = []
    for label, value in rows:
        parts = textwrap.wrap(str(value), wrap, break_on_hyphens=False) or ["-"]
        lines += [(label, parts[0])] + [("", p) for p in parts[1:]]
    return lines


def sheet_figure() -> Figure:
    """An empty A3 landscape sheet (:data:`PAPER_MM`) in the report's style, with its border
    5 mm inside the paper's edge (the caller closes it)."""
    W, H = PAPER_MM
    with plt.rc_context(STYLE):
        fig = plt.figure(figsize=(W * MM, H * MM))
    fig.add_artist(Rectangle((5 / W, 5 / H), (W - 10) / W, (H - 10) / H,
                             transform=fig.transFigure, fc="none", ec="black", lw=1.2))
    return fig


def block_height(rows: Sequence[tuple[str, str]], wrap: int = 44, scale: float = 1.0
                 ) -> float:
    """The height (mm) :func:`block` gives ``rows`` (``scale``: its text set smaller).

    >>> block_height([("a", "b")]), block_height([("a", "b")], scale=0.5)
    (10.8, 5.4)
    """
    return round((6.0 + LINE_MM * len(wrapped_rows(rows, wrap)) + 1.5) * scale, 6)


def block(fig: Figure, x: float, top: float, w: float, title: str,
          rows: Sequence[tuple[str, str]], wrap: int = 44, scale: float = 1.0) -> float:
    """A ruled block of ``rows`` (label, value) under ``title``, top edge at ``top`` (mm
    from the foot of the paper); returns the bottom edge (mm). Long values wrap at ``wrap``
    characters, whole; ``scale`` sets the whole block smaller (where the paper is short)."""
    W, H = PAPER_MM
    lines = wrapped_rows(rows, wrap)
    h = block_height(rows, wrap, scale)
    head, line = 5.5 * scale, LINE_MM * scale
    y0 = top - h
    fig.add_artist(Rectangle((x / W, y0 / H), w / W, h / H,
                             transform=fig.transFigure, fc="white", ec="black", lw=0.8))
    fig.add_artist(Rectangle((x / W, (top - head) / H), w / W, head / H,
                             transform=fig.transFigure, fc="#e8e8e8", ec="black", lw=0.8))
    fig.text((x + 2) / W, (top - head / 2) / H, title, fontsize=7.5 * scale,
             fontweight="bold", va="center")
    y = top - head - line * 0.8
    for label, value in lines:
        fig.text((x + 2) / W, y / H, label, fontsize=6.2 * scale, va="center",
                 color="#333333")
        fig.text((x + 42) / W, y / H, value, fontsize=6.2 * scale, va="center")
        y -= line
    return y0


def _cell(fig: Figure, x: float, y: float, w: float, h: float, label: str,
          value: str = "", wrap: int = 60, size: float = 7.0) -> None:
    """One box of the title block: a small label at its top left, the value under it
    (wrapped at ``wrap`` characters, whole)."""
    W, H = PAPER_MM
    fig.add_artist(Rectangle((x / W, y / H), w / W, h / H, transform=fig.transFigure,
                             fc="white", ec="black", lw=0.6))
    fig.text((x + 1.2) / W, (y + h - 1.0) / H, label, fontsize=4.6, va="top",
             color="#555555")
    lines = textwrap.wrap(value, wrap, break_on_hyphens=False)
    for i, line in enumerate(lines):
        fig.text((x + 1.2) / W, (y + h - 4.2 - i * LINE_MM) / H, line, fontsize=size,
                 va="top")


def _value_lines(value: str, wrap: int) -> int:
    return max(1, len(textwrap.wrap(value, wrap, break_on_hyphens=False)))


def _wrap_at(w: float) -> int:
    """Characters of 7-point text a box ``w`` mm wide holds."""
    return max(8, int(w / 1.4))


def _row_heights(project: Project, title: str, number: str, w: float) -> list[float]:
    """The title block's rows' heights (mm), top to bottom: each at least :data:`ROW_MM`
    (the project and the title one line), grown by the lines its longest value wraps onto."""
    def tall(*cells: tuple[str, float]) -> float:
        lines = max(_value_lines(v, _wrap_at(cw)) for v, cw in cells)
        return max(ROW_MM, 4.5 + LINE_MM * lines)

    half, name_w = w / 2, w * 0.36
    return [4.5 + LINE_MM * _value_lines(project.name, _wrap_at(w)),
            4.5 + LINE_MM * _value_lines(title, _wrap_at(w)),
            tall((number, half), (project.revision, half)), ROW_MM,
            tall((project.drawn, name_w), (project.date, w * 0.26)),
            tall((project.checked, name_w)), ROW_MM]


def title_block(fig: Figure, x: float, y: float, w: float, project: Project, title: str,
                number: str, scale: str, sheet: str) -> float:
    """The title block, its foot at ``y`` (mm), ``w`` wide; returns its top (mm).

    Rows, from the top: the project; the drawing's title; drawing number and revision;
    scale and sheet; drawn, checked and approved, each with the name, a blank box to sign
    and the date (the project's date beside "drawn"). Nothing is cut short: a long value
    wraps and its row grows."""
    W, H = PAPER_MM
    heights = _row_heights(project, title, number, w)
    top = y + sum(heights)
    half, name_w, sign_w = w / 2, w * 0.36, w * 0.38
    date_w = w - name_w - sign_w
    rows: list[list[tuple[float, float, str, str]]] = [
        [(0.0, w, "PROJECT", project.name)], [(0.0, w, "DRAWING TITLE", title)],
        [(0.0, half, "DRAWING No.", number), (half, half, "REVISION", project.revision)],
        [(0.0, half, "SCALE", scale), (half, half, "SHEET", sheet)]]
    for role, name, date in (("DRAWN", project.drawn, project.date),
                             ("CHECKED", project.checked, ""), ("APPROVED", "", "")):
        rows.append([(0.0, name_w, role, name), (name_w, sign_w, "SIGNATURE", ""),
                     (name_w + sign_w, date_w, "DATE", date)])
    yy = top
    for h, cells in zip(heights, rows, strict=True):
        yy -= h
        for dx, cw, label, value in cells:
            _cell(fig, x + dx, yy, cw, h, label, value, _wrap_at(cw))
    fig.add_artist(Rectangle((x / W, y / H), w / W, (top - y) / H, transform=fig.transFigure,
                             fc="none", ec="black", lw=1.0))
    return top
