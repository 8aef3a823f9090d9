"""The swept-path drawing of one curve, as a designer lays it on a plan.

For each vehicle drawn (:func:`draw_curve`):

- the body (tractor and trailer, with its wheels) at regular intervals along the run, the
  first and last positions drawn bold, and an arrow for the direction of travel;
- the paths of the wheels that bound the sweep (the outer front wheel, the inner rear
  wheel, the trailer's inner wheel) and of the trailer-axle centre; the path followed (the
  steered-axle centre);
- the body envelope, and the clearance envelope (grown by the clearance offset) when there
  is one; the verdict by the envelope's line style and a badge, never by a fill colour;
- the conflict: the envelope outside its own lanes hatched ``///``, outside the pavement
  hatched ``xxx``; the worst overreach and the largest offtracking dimensioned with their
  values; where a run stops, a cross and the reason in words.

Every vehicle keeps its colour (:func:`clearance.reports.documents.plotting.vehicle_colours`);
lengths are in the report's units. The drawing needs each run's trajectory, which a study's records
do not keep (their runs happen in worker processes, :mod:`clearance.reports.study.batch`):
:func:`rerun`
drives
the few runs a figure shows again in this process with the model alone, each on the path
its record says it took: its lane (:func:`clearance.networks.driving.drive.drive` with
``DriveOptions(use_sumo=False, swing=False)``) or the swung line the study chose
(:attr:`RunRecord.line <clearance.reports.results.records.RunRecord.line>`,
:func:`clearance.networks.driving.runs.drive_lines`), without searching it again. The model is
deterministic and SUMO only replays it, so the envelope and the verdict are the study's.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from typing import cast

import numpy as np
import shapely
from matplotlib.axes import Axes
from matplotlib.lines import Line2D
from matplotlib.patches import Patch, Polygon
from shapely.geometry.base import BaseGeometry

from clearance.analysis.envelope import body_corners
from clearance.analysis.overreach import worst_overreach
from clearance.analysis.tracking import TrackingRun, Trajectory
from clearance.analysis.trailer import hitch_point
from clearance.networks.curves import Curve
from clearance.networks.driving.drive import DrivenRun, DriveOptions, drive
from clearance.networks.driving.runs import drive_lines
from clearance.networks.plot import EDGE_OF_PAVEMENT, fill_geometry, plot_plan
from clearance.reports.documents.colours import VERDICT_COLOURS
from clearance.reports.documents.plotting import add_north_arrow, add_scale_bar, plan_axes
from clearance.reports.results.records import RunRecord
from clearance.reports.results.units import length_scale
from clearance.reports.study.run import NetworkCurves
from clearance.vehicles.vehicle import Vehicle

__all__ = ["BADGE", "GHOST", "HATCH_ALPHA", "HATCH_ZORDER", "LANE_CENTRE", "MIN_CONFLICT_M2",
           "OUTSIDE_LANES", "OUTSIDE_PAVEMENT", "OWN_LANES", "PATH_TAKEN", "Shown",
           "VERDICT_STYLE", "angle_text", "badge_text", "conflict_areas", "dimension",
           "draw_bodies", "draw_conflicts", "draw_curve", "draw_ghost", "draw_run",
           "ghost_handle", "is_swung",
           "legend_handles", "length_text", "overreach", "path_words", "rerun", "run_geometry",
           "stop_point", "stop_words", "view_bounds"]

#: Envelope outline by verdict (the verdict is told by line style and badge, not fill).
VERDICT_STYLE = {"clear": ("-", 1.1), "encroaches": ((0, (5, 2)), 1.4),
                 "fails": ((0, (7, 2, 1.5, 2)), 1.8), "cannot-turn": ((0, (1.5, 1.5)), 1.8),
                 "error": ((0, (1, 3)), 1.0)}
#: Badge colours of the verdicts (as the report's plans use them).
BADGE = VERDICT_COLOURS
#: Hatches and colours of the conflict.
OUTSIDE_LANES = ("////", VERDICT_COLOURS["encroaches"])
OUTSIDE_PAVEMENT = ("xxxx", VERDICT_COLOURS["fails"])
OWN_LANES = "#2471a3"
#: Conflict pieces smaller than this (m²) are slivers of the polygon arithmetic.
MIN_CONFLICT_M2 = 0.005
#: A swung run: the path its steered axle took (line width; solid, in the vehicle's colour
#: with a dark core), and the lane's centre line it left (colour, width, dashes).
PATH_TAKEN = 2.2
LANE_CENTRE = ("#5d6d7e", 1.0, (0, (5, 3)))


@dataclass
class Shown:
    """One run a drawing shows: the study's record, its colour, its re-run (or None)."""

    record: RunRecord
    colour: str
    driven: DrivenRun | None = None

    @property
    def run(self) -> TrackingRun | None:
        d = self.driven
        return None if d is None or d.result is None else d.result.run


def is_swung(s: Shown) -> bool:
    """Whether a shown run's drawing is of a swung path
    (:mod:`clearance.networks.driving.swing`)."""
    return s.driven is not None and s.driven.result is not None and s.driven.path == "swung"


def path_words(s: Shown, units: str = "m") -> str:
    """The path a shown run took (its steered axle's), for a legend or a sheet.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> rec = NS(vehicle="CITY-BUS", path="swung")
    >>> path_words(Shown(rec, "k", NS(result=1, path="swung", swing_m=1.5)))
    'CITY-BUS: path taken, swung 1.50 m out'
    >>> path_words(Shown(NS(vehicle="P", path="lane"), "k"))
    'P: on the lane centre line'
    """
    d = s.driven
    if d is not None and is_swung(s):
        return f"{s.record.vehicle}: path taken, swung {length_text(d.swing_m, units)} out"
    if s.record.path == "swung":
        return f"{s.record.vehicle}: swung wide (not drawn again)"
    return f"{s.record.vehicle}: on the lane centre line"


def rerun(nc: NetworkCurves, curve: Curve, vehicles: Sequence[Vehicle],
          records: Sequence[RunRecord], clearance_m: float) -> list[DrivenRun]:
    """The runs of ``records`` on ``curve`` again (``vehicles[i]`` the vehicle of
    ``records[i]``), model only, each on the path the study took: the lane's centre line,
    or the swung line the record keeps (:attr:`RunRecord.line
    <clearance.reports.results.records.RunRecord.line>`), driven and judged as the search judged
    it. The trajectory, envelope, verdict and margins are the study's; neither SUMO nor the search
    of swung paths runs again. A swung record without its line (made without it) is
    searched again, as the study searched it."""
    if len(vehicles) != len(records):
        raise ValueError(f"rerun: {len(vehicles)} vehicles for {len(records)} records")
    out: dict[int, DrivenRun] = {}
    searched = {i for i, r in enumerate(records) if r.path == "swung" and r.line is None}
    for swing in (False, True):
        which = [i for i in range(len(records)) if (i in searched) == swing]
        if which:
            runs = drive(nc.network, [(vehicles[i], curve) for i in which],
                         options=DriveOptions(use_sumo=False, offset_m=clearance_m,
                                              swing=swing))
            out.update(zip(which, runs, strict=True))
    lined = [(out[i], line) for i, r in enumerate(records)
             if r.path == "swung" and (line := r.line) is not None]
    drive_lines([d for d, _ in lined], [line for _, line in lined], clearance_m)
    return [out[i] for i in range(len(records))]


def angle_text(turn_deg: float) -> str:
    """A curve's signed turn in whole degrees (left positive), never ``-0°``.

    Examples
    --------
    >>> angle_text(-90.2), angle_text(-0.3), angle_text(45.5), angle_text(0.4)
    ('-90°', '0°', '+46°', '0°')
    """
    whole = round(turn_deg)
    return "0°" if whole == 0 else f"{whole:+d}°"


def length_text(value_m: float, units: str, digits: int = 2) -> str:
    """A length in the report's units, ``"n/a"`` when it is not a number.

    Examples
    --------
    >>> length_text(0.3048, "ft"), length_text(1.234, "m", 1), length_text(math.nan, "m")
    ('1.00 ft', '1.2 m', 'n/a')
    """
    if not math.isfinite(value_m):
        return "n/a"
    return f"{value_m / length_scale(units):.{digits}f} {units}"


def stop_words(run: TrackingRun, units: str = "m") -> str:
    """Why a run could not be driven as asked, in words a designer reads (empty when it
    could); :func:`stop_point` is where.

    Examples
    --------
    >>> from clearance.analysis.tracking import simulate
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> stop_words(simulate(car, [(0.0, 0.0), (10.0, 0.0)]))
    ''
    """
    if not run.reason:
        return ""
    tr = run.trajectory
    worst = int(np.argmax(np.abs(tr.error_m))) if len(tr) else 0
    off = length_text(run.max_error_m, units, 1)
    tol = length_text(run.settings.tolerance_m, units, 1)
    where = length_text(float(tr.s_m[worst]) if len(tr) else 0.0, units, 0)
    if run.jackknife_time_s is not None and run.vehicle.trailer is not None:
        return (f"the trailer jackknifes here (articulation beyond its "
                f"{math.degrees(run.vehicle.trailer.max_articulation_rad):.0f}° limit)")
    if run.max_error_m > run.settings.tolerance_m:
        lock = (" with the wheels at full lock" if run.steps_at_lock
                else " at its steering rate" if run.steps_rate_limited else "")
        verb = "cannot hold the path" if run.reached_end else "stops: cannot follow the path"
        return (f"{verb}{lock}, {off} off it at station {where} (allowed {tol}); "
                "needs a wider turn or reversing")
    return "stops: did not reach the end of the path"


def stop_point(run: TrackingRun) -> tuple[float, float]:
    """Where :func:`stop_words` applies: the last position of a run that stopped, else
    the steered axle where it was farthest off the path."""
    tr = run.trajectory
    i = len(tr) - 1
    if run.reached_end and run.jackknife_time_s is None and len(tr):
        i = int(np.argmax(np.abs(tr.error_m)))
    return float(tr.xf_m[i]), float(tr.yf_m[i])


def overreach(measured: BaseGeometry, area: BaseGeometry
              ) -> tuple[np.ndarray, np.ndarray, float] | None:
    """The point of ``measured`` farthest outside ``area`` (the worst overreach of
    :func:`clearance.analysis.overreach.worst_overreach`, the point ``clearance.csv`` gives), the
    nearest point of ``area`` to it and their distance; ``None`` when nothing lies outside
    (or only slivers under :data:`MIN_CONFLICT_M2`).

    Examples
    --------
    >>> p, q, d = overreach(shapely.box(0, 0, 4, 3), shapely.box(0, 0, 4, 2))
    >>> round(d, 6), round(float(p[1]), 6), round(float(q[1]), 6)
    (1.0, 3.0, 2.0)
    >>> overreach(shapely.box(0, 0, 1, 1), shapely.box(-1, -1, 2, 2)) is None
    True
    """
    o = worst_overreach(measured, area, min_area_m2=MIN_CONFLICT_M2)
    if o is None:
        return None
    line = shapely.shortest_line(shapely.Point(o.x, o.y), area.boundary)
    a, b = np.asarray(line.coords)
    return a, b, o.distance_m


def view_bounds(curve: Curve, shown: Sequence[Shown], pad_m: float = 6.0,
                aspect: float = 1.0) -> tuple[float, float, float, float]:
    """A view (x0, x1, y0, y1) around the curve's feature and the drawn envelopes, of
    width / height ``aspect`` (only the envelopes when every run drawn is ``cannot-turn``:
    the feature beyond where they stop would shrink the drawing)."""
    pts = np.asarray(curve.centerline)[:, :2]
    station = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    core = (station >= curve.core_start_m - 1e-6) & (station <= curve.core_end_m + 1e-6)
    if core.sum() >= 2:
        pts = pts[core]
    # the whole feature, unless every run drawn stopped short of it (then its envelope)
    stopped = bool(shown) and all(s.record.verdict == "cannot-turn" and s.record.envelope
                                  is not None and not s.record.envelope.is_empty
                                  for s in shown)
    boxes = [] if stopped else [pts.min(axis=0).tolist() + pts.max(axis=0).tolist()]
    for s in shown:
        env = s.record.envelope
        if env is not None and not env.is_empty:
            boxes.append(list(env.bounds))
    b = np.array(boxes)
    x0, y0 = b[:, 0].min() - pad_m, b[:, 1].min() - pad_m
    x1, y1 = b[:, 2].max() + pad_m, b[:, 3].max() + pad_m
    w, h = x1 - x0, y1 - y0
    if w / h < aspect:
        w = h * aspect
    else:
        h = w / aspect
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    return cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2


def _outline(ax: Axes, geom: BaseGeometry, **kw) -> None:
    for poly in getattr(geom, "geoms", [geom]):
        if poly.is_empty or poly.geom_type != "Polygon":
            continue
        for ring in [poly.exterior, *poly.interiors]:
            xy = np.asarray(ring.coords)
            ax.plot(xy[:, 0], xy[:, 1], **kw)


def _poses(run: TrackingRun, count: int) -> list[int]:
    """Sample indices of ``count`` positions evenly spaced along the front axle's path."""
    tr = run.trajectory
    if len(tr) < 2:
        return [0]
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(tr.xf_m), np.diff(tr.yf_m)))])
    marks = np.linspace(0.0, s[-1], max(2, count))
    return sorted(set(np.searchsorted(s, marks).clip(0, len(tr) - 1).tolist()))


def _wheels(ax: Axes, v: Vehicle, x: float, y: float, th: float, phi: float, colour: str,
            lw: float, trailer_axle: bool = False) -> None:
    """Wheels as small rectangles: front ones turned by the steering angle."""
    size, thick = 0.9, 0.32
    half = v.track_m / 2
    axles = [(0.0, 0.0)] if trailer_axle else [(0.0, 0.0), (v.wheelbase_m, phi)]
    if not trailer_axle and v.steered_axle == "rear":
        axles = [(0.0, phi), (v.wheelbase_m, 0.0)]
    c, s_ = math.cos(th), math.sin(th)
    for along, steer in axles:
        for side in (half, -half):
            wx, wy = x + along * c - side * s_, y + along * s_ + side * c
            corners = body_corners(np.array([wx]), np.array([wy]), np.array([th + steer]),
                                   size / 2, size / 2, thick)[0]
            ax.add_patch(Polygon(corners, closed=True, fc=colour, ec=colour, lw=lw * 0.5,
                                 zorder=9))


def draw_bodies(ax: Axes, run: TrackingRun, colour: str, count: int) -> None:
    """The vehicle at ``count`` positions; first and last bold, an arrow of travel."""
    v, tr = run.vehicle, run.trajectory
    idx = _poses(run, count)
    t = v.trailer
    for n, i in enumerate(idx):
        ends = n in (0, len(idx) - 1)
        lw = 1.3 if ends else 0.55
        fc = (*_rgb(colour), 0.18 if ends else 0.0)
        x, y, th = float(tr.x_m[i]), float(tr.y_m[i]), float(tr.theta_rad[i])
        corners = body_corners(np.array([x]), np.array([y]), np.array([th]),
                               v.wheelbase_m + v.front_overhang_m, v.rear_overhang_m,
                               v.width_m)[0]
        ax.add_patch(Polygon(corners, closed=True, fc=fc, ec=colour, lw=lw, zorder=8))
        _wheels(ax, v, x, y, th, float(tr.phi_rad[i]), colour, lw)
        if (t is not None and tr.theta_t_rad is not None and tr.xt_m is not None
                and tr.yt_m is not None):
            xt, yt, tt = float(tr.xt_m[i]), float(tr.yt_m[i]), float(tr.theta_t_rad[i])
            tc = body_corners(np.array([xt]), np.array([yt]), np.array([tt]),
                              t.wheelbase_m + t.front_overhang_m, t.rear_overhang_m,
                              t.width_m)[0]
            ax.add_patch(Polygon(tc, closed=True, fc=fc, ec=colour, lw=lw, zorder=8))
            _wheels(ax, v, xt, yt, tt, 0.0, colour, lw, trailer_axle=True)
            hx, hy = hitch_point(x, y, th, t.hitch_offset_m)
            ax.plot([float(hx)], [float(hy)], marker="o", ms=2.5 if ends else 1.5,
                    color=colour, zorder=9)
    # the direction of travel: an arrow on the path followed, a third of the way along
    k = max(1, len(tr) // 3)
    j = min(len(tr) - 1, k + max(1, len(tr) // 25))
    if j > k:
        ax.annotate("", xy=(tr.xf_m[j], tr.yf_m[j]), xytext=(tr.xf_m[k], tr.yf_m[k]),
                    arrowprops=dict(arrowstyle="-|>,head_width=0.4,head_length=0.9",
                                    color=colour, lw=1.6), zorder=11)


def _rgb(colour: str) -> tuple[float, float, float]:
    from matplotlib.colors import to_rgb

    return to_rgb(colour)


def dimension(ax: Axes, a: np.ndarray, b: np.ndarray, text: str, colour: str,
               offset: tuple[float, float] = (8, 8)) -> None:
    """A dimension line from ``a`` to ``b`` with arrow heads and its value, the label
    ``offset`` points away."""
    ax.annotate("", xy=tuple(b), xytext=tuple(a),
                arrowprops=dict(arrowstyle="<|-|>,head_width=0.2,head_length=0.5",
                                color=colour, lw=0.9, shrinkA=0, shrinkB=0), zorder=14)
    mid = (np.asarray(a) + np.asarray(b)) / 2
    ax.annotate(text, xy=tuple(mid), xytext=offset, textcoords="offset points",
                fontsize=6.5, color="black", zorder=15, ha="left",
                va="bottom" if offset[1] >= 0 else "top",
                # a dimension whose anchor lies outside the drawing is left out, not drawn
                # beside it (it would stretch the saved figure)
                annotation_clip=True,
                bbox=dict(boxstyle="round,pad=0.2", fc="white", ec=colour, lw=0.6),
                arrowprops=dict(arrowstyle="-", color=colour, lw=0.5))


def _wheel_names(curve: Curve, run: TrackingRun) -> tuple[str, str, str]:
    """Outer front, inner rear and inner trailer wheel of the turn's direction."""
    tr = run.trajectory
    left = float(tr.theta_rad[-1] - tr.theta_rad[0]) >= 0 if len(tr) > 1 else (
        curve.turn_angle_deg >= 0)
    inner, outer = ("left", "right") if left else ("right", "left")
    return f"front_{outer}", f"rear_{inner}", f"trailer_{inner}"


#: The conflict hatches: drawn under the envelopes' outlines, the bodies and the wheel paths,
#: their lines this opaque so that the vehicle reads through them.
HATCH_ZORDER, HATCH_ALPHA = 6, 0.55


def conflict_areas(curve: Curve, envelopes: Sequence[BaseGeometry]
                   ) -> list[tuple[BaseGeometry, tuple[str, str]]]:
    """The envelopes' parts beyond their own lanes (but paved) and beyond the pavement, each
    merged over every envelope given (one hatch per kind, never two overlapping).

    Examples
    --------
    >>> from types import SimpleNamespace as C
    >>> lanes, paved = shapely.box(0, 0, 10, 3), shapely.box(0, -3, 10, 3)
    >>> a, b = shapely.box(1, 1, 4, 5), shapely.box(3, 1, 6, 5)  # overlapping, both out
    >>> [(round(g.area, 3), k[0]) for g, k in conflict_areas(C(own_lanes=lanes, paved=paved),
    ...                                                    [a, b])]
    [(10.0, 'xxxx')]
    >>> conflict_areas(C(own_lanes=None, paved=None), [a])
    []
    """
    out: list[tuple[BaseGeometry, tuple[str, str]]] = []
    whole = shapely.union_all([e for e in envelopes if e is not None and not e.is_empty])
    if whole.is_empty:
        return out
    if curve.own_lanes is not None:
        beyond = shapely.difference(whole, curve.own_lanes)
        if curve.paved is not None:
            beyond = shapely.intersection(beyond, curve.paved)
        out.append((beyond, OUTSIDE_LANES))
    if curve.paved is not None:
        out.append((shapely.difference(whole, curve.paved), OUTSIDE_PAVEMENT))
    return [(g, kind) for g, kind in out if not g.is_empty and g.area >= MIN_CONFLICT_M2]


def draw_conflicts(ax: Axes, curve: Curve, envelopes: Sequence[BaseGeometry]) -> None:
    """Hatch the merged conflict areas of ``envelopes`` (:func:`conflict_areas`), light and
    under the vehicles."""
    for geom, (hatch, colour) in conflict_areas(curve, envelopes):
        fill_geometry(ax, geom, fc="none", ec=(*_rgb(colour), HATCH_ALPHA), hatch=hatch,
                      lw=0.5, zorder=HATCH_ZORDER)


def draw_run(ax: Axes, curve: Curve, s: Shown, units: str, bodies: int = 7,
             dimensions: bool = True, envelope_fill: bool = False, words: bool = True,
             hatches: bool = True) -> None:
    """One vehicle's swept path on a plan (see the module docstring); ``words``: the reason
    of a stop in full (else the vehicle's name only); ``hatches``: its conflict hatched
    (:func:`draw_conflicts`; a figure of several runs hatches them together instead)."""
    rec, colour = s.record, s.colour
    ls, lw = VERDICT_STYLE.get(rec.verdict, VERDICT_STYLE["error"])
    res = None if s.driven is None else s.driven.result
    if res is None:
        if rec.envelope is not None and not rec.envelope.is_empty:
            _outline(ax, rec.envelope, color=colour, ls=ls, lw=lw, zorder=7)
        return
    run, swept = res.run, res.swept
    if envelope_fill:
        fill_geometry(ax, swept.envelope, fc=(*_rgb(colour), 0.10), ec="none", zorder=4)
    _outline(ax, swept.envelope, color=colour, ls=ls, lw=lw, zorder=7)
    if res.clearance.offset_m > 0:
        _outline(ax, res.measured, color=colour, ls=(0, (1, 1.5)), lw=0.7, zorder=7)
    if hatches:
        draw_conflicts(ax, curve, [res.measured])
    tr = run.trajectory
    names = _wheel_names(curve, run)
    styles = {names[0]: "-", names[1]: (0, (3, 1.5)), names[2]: (0, (1, 1))}
    for name, style in styles.items():
        track = swept.wheel_tracks.get(name)
        if track is not None:
            xy = np.asarray(track.coords)
            ax.plot(xy[:, 0], xy[:, 1], color=colour, lw=0.7, ls=style, zorder=9)
    if tr.xt_m is not None and tr.yt_m is not None:
        ax.plot(tr.xt_m, tr.yt_m, color=colour, lw=0.7, ls=(0, (6, 1.5, 1, 1.5)), zorder=9)
    if is_swung(s):
        # the path taken, and the lane's centre line it left, dashed beside it
        ax.plot(tr.xf_m, tr.yf_m, color=colour, lw=PATH_TAKEN, ls="-", zorder=9,
                solid_capstyle="butt", gid="path-taken")
        ax.plot(tr.xf_m, tr.yf_m, color="black", lw=0.5, ls="-", zorder=9)
        lane = np.asarray(curve.centerline)[:, :2]
        ax.plot(lane[:, 0], lane[:, 1], color=LANE_CENTRE[0], lw=LANE_CENTRE[1],
                ls=LANE_CENTRE[2], zorder=11, gid="lane-centre-line")
    else:
        ax.plot(tr.xf_m, tr.yf_m, color="black", lw=0.6, ls=(0, (8, 2)), zorder=9,
                gid="path-followed")
    draw_bodies(ax, run, colour, bodies)
    if dimensions:
        _dimensions(ax, curve, s, units)
    if run.reason:
        x, y = stop_point(run)
        ax.plot([x], [y], marker="X", ms=10, mfc=colour, mec="black", mew=0.8, zorder=16)
        said = stop_words(run, units)
        text = (textwrap.fill(f"{rec.vehicle} {said}", 38) if words
                else f"{rec.vehicle} {said.split(':')[0].split(',')[0]}")
        x0, x1 = ax.get_xlim()
        right = x > (x0 + x1) / 2  # the words toward the middle of the drawing
        ax.annotate(text, xy=(x, y), annotation_clip=False, va="top",
                    ha="right" if right else "left", xytext=(-12 if right else 12, -12),
                    textcoords="offset points", fontsize=6.5, zorder=16,
                    bbox=dict(boxstyle="round,pad=0.25", fc="#fff8dc",
                                         ec="black", lw=0.6),
                    arrowprops=dict(arrowstyle="-", lw=0.6))


#: A ghost: a second vehicle shown faintly for comparison (a route study's baseline):
#: its colour, its envelope line's width and dashes.
GHOST = ("#7f7f7f", 1.0, (0, (6, 2, 1, 2, 1, 2)))


def draw_ghost(ax: Axes, curve: Curve, s: Shown) -> None:
    """A second vehicle shown for comparison, under the vehicle of the drawing: its
    envelope outline (grey, dash-dot-dot) and the paths of its outer front and inner rear
    wheels (thin grey); no bodies, no hatches, no dimensions. A run not driven again shows
    its recorded envelope alone."""
    colour, lw, ls = GHOST
    res = None if s.driven is None else s.driven.result
    env = res.swept.envelope if res is not None else s.record.envelope
    if env is not None and not env.is_empty:
        _outline(ax, env, color=colour, ls=ls, lw=lw, zorder=6, gid="ghost-envelope")
    if res is None:
        return
    for name in _wheel_names(curve, res.run)[:2]:
        track = res.swept.wheel_tracks.get(name)
        if track is not None:
            xy = np.asarray(track.coords)
            ax.plot(xy[:, 0], xy[:, 1], color=colour, lw=0.5, ls="-", zorder=6)


def ghost_handle(s: Shown, units: str) -> Line2D:
    """The legend's line of a ghost (:func:`draw_ghost`): whose, and its verdict."""
    colour, lw, ls = GHOST
    return Line2D([], [], color=colour, ls=ls, lw=lw,
                  label=f"{s.record.vehicle} for comparison: envelope, {s.record.verdict} "
                        f"({length_text(s.record.margin_m, units)})")


def _dimensions(ax: Axes, curve: Curve, s: Shown, units: str) -> None:
    res = None if s.driven is None else s.driven.result
    if res is None:  # draw_run dimensions only a run driven again
        return
    run, swept = res.run, res.swept
    hit = None
    if curve.paved is not None and res.clearance.paved_margin_m < 0:
        hit = overreach(res.measured, curve.paved)
        words, colour = "beyond the pavement", OUTSIDE_PAVEMENT[1]
    elif curve.own_lanes is not None and res.clearance.margin_m < 0:
        hit = overreach(res.measured, curve.own_lanes)
        words, colour = "beyond its lanes", OUTSIDE_LANES[1]
    if hit is not None:
        a, b, d = hit
        dimension(ax, a, b, f"{s.record.vehicle}: {length_text(d, units)} {words}", colour)
    tr = run.trajectory
    if len(tr) > 1 and swept.max_offtracking_m > 0.05:
        _offtracking_dimension(ax, tr, swept.offtracking_m, (tr.x_m, tr.y_m),
                               f"offtracking {length_text(swept.max_offtracking_m, units)}",
                               s.colour, (-14, -18))
    off_t, xt, yt = swept.trailer_offtracking_m, tr.xt_m, tr.yt_m
    if len(tr) > 1 and off_t is not None and xt is not None and yt is not None \
            and float(off_t.max()) > 0.05:
        _offtracking_dimension(ax, tr, off_t, (xt, yt),
                               f"trailer offtracking {length_text(float(off_t.max()), units)}",
                               s.colour, (-14, -30))


def _offtracking_dimension(ax: Axes, tr: Trajectory, off: np.ndarray,
                           axle: tuple[np.ndarray, np.ndarray], label: str, colour: str,
                           offset: tuple[float, float]) -> None:
    """Dimension the largest offtracking: from the axle (the tractor's rear axle or the
    trailer's) at its worst sample to the steered axle's path."""
    i = int(np.argmax(off))
    q = shapely.Point(float(axle[0][i]), float(axle[1][i]))
    line = shapely.shortest_line(q, shapely.LineString(np.column_stack([tr.xf_m, tr.yf_m])))
    a, b = np.asarray(line.coords)
    dimension(ax, a, b, label, colour, offset=offset)


def badge_text(rec: RunRecord, units: str) -> str:
    """``WB-67  FAILS  −6.45 m`` (the margin to its own lanes; ``, swung`` on a swung path).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> badge_text(NS(vehicle="P", verdict="encroaches", margin_m=-0.8, path="swung"), "m")
    'P  ENCROACHES  -0.80 m, swung'
    """
    m = rec.margin_m
    margin = "" if not math.isfinite(m) else f"  {m / length_scale(units):+.2f} {units}"
    swung = ", swung" if getattr(rec, "path", "lane") == "swung" else ""
    return f"{rec.vehicle}  {rec.verdict.upper()}{margin}{swung}"


def draw_curve(ax: Axes, nc: NetworkCurves, curve: Curve, shown: Sequence[Shown],
               units: str = "m", bounds: tuple[float, float, float, float] | None = None,
               bodies: int = 7, badges: bool = True, ghost: Shown | None = None) -> list:
    """The base plan, the curve's own lanes and every shown run; returns the legend handles.

    The axes get ticks in ``units``, a scale bar and a north arrow; ``ghost``, a second
    vehicle for comparison, is drawn faintly under the others (:func:`draw_ghost`).
    """
    bounds = bounds or view_bounds(curve, shown)
    plot_plan(nc.network, ax, None, bounds, decorate=False)
    if curve.own_lanes is not None:
        _outline(ax, curve.own_lanes, color=OWN_LANES, lw=0.9, ls=(0, (4, 2)), zorder=5)
    if ghost is not None:
        draw_ghost(ax, curve, ghost)
    order = {"error": -1, "cannot-turn": 0, "fails": 1, "encroaches": 2, "clear": 3}
    shown = sorted(shown, key=lambda s: (order.get(s.record.verdict, 9),
                                         s.record.margin_m if math.isfinite(s.record.margin_m)
                                         else -math.inf))
    single = len(shown) == 1
    # several vehicles: the worst one (first) in full, the others by envelope, wheel paths
    # and where they stop, so that the drawing stays legible
    for k, s in enumerate(shown):
        draw_run(ax, curve, s, units, bodies if k == 0 or len(shown) <= 2 else 2,
                 dimensions=k == 0, envelope_fill=single, words=k == 0 or single,
                 hatches=False)
    # every run's conflict in one hatch per kind, under the vehicles
    draw_conflicts(ax, curve, [s.driven.result.measured for s in shown
                               if s.driven is not None and s.driven.result is not None])
    ax.set_xlim(bounds[0], bounds[1])
    ax.set_ylim(bounds[2], bounds[3])
    plan_axes(ax, units)
    add_scale_bar(ax, units)
    add_north_arrow(ax)
    if badges:
        for k, s in enumerate(shown):
            ax.text(0.015, 0.985 - 0.055 * k, badge_text(s.record, units),
                    transform=ax.transAxes, ha="left", va="top", fontsize=7,
                    fontweight="bold", color="white", zorder=22,
                    bbox=dict(boxstyle="round,pad=0.3", fc=BADGE.get(s.record.verdict, "k"),
                              ec=s.colour, lw=2.0))
    handles = legend_handles(shown, units, any(s.run is not None and s.run.vehicle.trailer
                                               for s in shown))
    if ghost is not None:
        handles.insert(len(shown), ghost_handle(ghost, units))
    return handles


def legend_handles(shown: Sequence[Shown], units: str, trailer: bool) -> list:
    """Every line, fill and hatch of the drawing, explained."""
    h: list = []
    for s in shown:
        ls, lw = VERDICT_STYLE.get(s.record.verdict, VERDICT_STYLE["error"])
        h.append(Line2D([], [], color=s.colour, ls=ls, lw=lw,
                        label=f"{s.record.vehicle}: envelope, {s.record.verdict}"))
    grey = "#444444"
    h += [Patch(fc="none", ec=grey, lw=1.3, label="vehicle at start and end (bold)"),
          Patch(fc="none", ec=grey, lw=0.5, label="vehicle at intervals"),
          Line2D([], [], color=grey, lw=0.7, label="outer front wheel path"),
          Line2D([], [], color=grey, lw=0.7, ls=(0, (3, 1.5)), label="inner rear wheel path")]
    if trailer:
        h += [Line2D([], [], color=grey, lw=0.7, ls=(0, (1, 1)),
                     label="inner trailer wheel path"),
              Line2D([], [], color=grey, lw=0.7, ls=(0, (6, 1.5, 1, 1.5)),
                     label="trailer axle path")]
    swung = [s for s in shown if is_swung(s)]
    if len(swung) < len([s for s in shown if s.run is not None]) or not swung:
        h.append(Line2D([], [], color="black", lw=0.6, ls=(0, (8, 2)),
                        label="path followed (steered axle)"))
    for s in swung:
        h.append(Line2D([], [], color=s.colour, lw=PATH_TAKEN, ls="-",
                        label=path_words(s, units)))
    if swung:
        h.append(Line2D([], [], color=LANE_CENTRE[0], lw=LANE_CENTRE[1], ls=LANE_CENTRE[2],
                        label="lane centre line (not taken)"))
    offsets = {s.record.clearance_m for s in shown if s.record.clearance_m > 0}
    if offsets:
        h.append(Line2D([], [], color=grey, lw=0.7, ls=(0, (1, 1.5)),
                        label=f"clearance envelope (+{length_text(max(offsets), units)})"))
    h += [Patch(fc="none", ec=OUTSIDE_LANES[1], hatch=OUTSIDE_LANES[0],
                label="outside its own lanes (paved)"),
          Patch(fc="none", ec=OUTSIDE_PAVEMENT[1], hatch=OUTSIDE_PAVEMENT[0],
                label="outside the pavement"),
          Line2D([], [], color=OWN_LANES, lw=0.9, ls=(0, (4, 2)), label="own lanes"),
          Line2D([], [], color=EDGE_OF_PAVEMENT, lw=1.1, label="edge of pavement"),
          Patch(fc="#d5d5d5", ec="none", label="pavement (white dashes: lane lines)")]
    for v in ("clear", "encroaches", "fails", "cannot-turn"):
        h.append(Line2D([], [], color=grey, ls=VERDICT_STYLE[v][0], lw=VERDICT_STYLE[v][1],
                        label=f"envelope line: {v}"))
    if any(s.run is not None and s.run.reason for s in shown):
        h.append(Line2D([], [], marker="X", ms=7, color="none", mfc=grey, mec="black",
                        label="cannot follow the path here (why beside)"))
    return h


def run_geometry(curve: Curve, driven: DrivenRun, count: int = 7
                 ) -> tuple[tuple[shapely.Polygon, ...], tuple[shapely.LineString, ...]]:
    """A re-driven run's body outlines at ``count`` positions along its path (tractor, and
    trailer where there is one) and the paths of the wheels that bound its sweep (outer
    front, inner rear, inner trailer wheel) and of the trailer axle: what the CAD export
    draws on a vehicle's body and wheel-path layers. ``((), ())`` for a run without a
    result.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> run_geometry(None, NS(result=None))
    ((), ())
    """
    res = driven.result
    if res is None:
        return (), ()
    run, swept = res.run, res.swept
    v, tr = run.vehicle, run.trajectory
    idx = _poses(run, count)
    outlines = list(cast("np.ndarray", shapely.polygons(body_corners(
        tr.x_m[idx], tr.y_m[idx], tr.theta_rad[idx], v.wheelbase_m + v.front_overhang_m,
        v.rear_overhang_m, v.width_m))))
    t = v.trailer
    if (t is not None and tr.theta_t_rad is not None and tr.xt_m is not None
            and tr.yt_m is not None):
        outlines += list(cast("np.ndarray", shapely.polygons(body_corners(
            tr.xt_m[idx], tr.yt_m[idx], tr.theta_t_rad[idx], t.wheelbase_m + t.front_overhang_m,
            t.rear_overhang_m, t.width_m))))
    paths = [swept.wheel_tracks[n] for n in _wheel_names(curve, run) if n in swept.wheel_tracks]
    if tr.xt_m is not None and tr.yt_m is not None and len(tr) > 1:
        paths.append(shapely.LineString(np.column_stack([tr.xt_m, tr.yt_m])))
    return tuple(outlines), tuple(paths)
