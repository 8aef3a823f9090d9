"""Floors under what judging a run finds beyond its areas, without uniting its sweep.

:func:`clearance.analysis.clearance.judge` unites the convex hulls of a run's key poses
(:func:`clearance.analysis.envelope.sweep`), trims the union at the path's ends and measures,
for each area, how far the union's boundary reaches beyond it
(:func:`clearance.analysis.margins.signed_margin_m`): the farthest of the boundary's vertices
beyond the area, exactly, and the points between them by branch and bound. The union is
most of that cost. A search that only needs to know that a candidate cannot beat one
already judged can do with a floor under those reaches, found from the hulls alone:

- a body corner of a key pose is a vertex of the hulls about it; where those hulls cover
  one angle about it, short of the full turn, and no other hull comes within
  :data:`NEAR_RING_M` of it, it is on the union's boundary
  (:func:`clearance.analysis.kernels.corner_vertices`), so a vertex of the union as GEOS
  computes it (an overlay keeps its input's vertices on the boundary, collinear ones
  too);
- corners within :data:`AWAY_M` of the boxes the envelope is trimmed by are left out, so
  the corner is a vertex of the trimmed envelope's boundary too, outside the region where
  the areas' boundaries do not count;
- beyond an area by at least :data:`~clearance.analysis.margins.PRECISION_M`, that vertex
  is one the judging measures, with the same distance to the area's boundary segments.
  (The hulls about it cover at least :data:`MIN_ANGLE_RAD` there, so the envelope's part
  beyond the area is far larger than the square millimetre under which the judging takes
  it for noise.)

So the reach judged beyond an area is at least the farthest such corner's distance from
it (less :data:`SLACK_M` for floating point); where that is at least ``PRECISION_M`` the
judged margin is at most minus it. ``tests/analysis/test_screen.py`` holds the floors
under the judged reaches of a corpus of swung paths.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from clearance.analysis.clearance import END_SLACK_M, Areas, judged_part
from clearance.analysis.envelope import DEFAULT_TOLERANCE_M, body_corners, sweep_poses
from clearance.analysis.kernels import corner_vertices, pair_hulls, segments_distance
from clearance.analysis.margins import PRECISION_M
from clearance.analysis.tracking import TrackingRun

__all__ = ["AREAS", "AWAY_M", "MIN_ANGLE_RAD", "NEAR_RING_M", "SLACK_M", "boundary_corners",
           "reach_floors"]

NEAR_RING_M = 1e-9
"""A hull this close to a corner is about it (m): the corner is its vertex or on its edge."""

MIN_ANGLE_RAD = math.pi / 8
"""The hulls about a corner must cover at least this, and leave at least this open (rad)."""

AREAS = ("paved", "roadway", "own_lanes")
"""The areas a floor is sought beyond, the outermost first."""

SLACK_M = 1e-6
"""Taken off a corner's distance, for the floating point of the overlay (m)."""

AWAY_M = END_SLACK_M + 2 * PRECISION_M
"""Corners this close to the boxes the envelope is trimmed by give no floor (m)."""


def _bodies(run: TrackingRun) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, float, float,
                                             float, float]]:
    """The bodies :func:`clearance.analysis.envelope.swept_envelope` sweeps: pose arrays,
    ahead, behind, width and axle, the tractor's and the trailer's (if any)."""
    v, tr = run.vehicle, run.trajectory
    wb = v.wheelbase_m
    out = [(tr.x_m, tr.y_m, tr.theta_rad, wb + v.front_overhang_m, v.rear_overhang_m,
            v.width_m, wb if v.steered_axle == "rear" else 0.0)]
    if (v.trailer is not None and tr.theta_t_rad is not None and tr.xt_m is not None
            and tr.yt_m is not None):
        t = v.trailer
        out.append((tr.xt_m, tr.yt_m, tr.theta_t_rad, t.wheelbase_m + t.front_overhang_m,
                    t.rear_overhang_m, t.width_m, 0.0))
    return out


def _sweep_rings(run: TrackingRun, tolerance_m: float
                 ) -> tuple[list[np.ndarray], list[tuple[np.ndarray, np.ndarray]]]:
    """The body corners of each part's key poses, ``(n, 4, 2)``, and the hulls
    :func:`clearance.analysis.envelope.sweep` unites for them, as rings (coordinates and
    offsets, :func:`clearance.analysis.kernels.pair_hulls`); none when a hull has no area."""
    corners, rings = [], []
    for x, y, th, ahead_m, behind_m, width_m, axle_m in _bodies(run):
        xs, ys, ths, parts = sweep_poses(x, y, th, ahead_m, behind_m, width_m, tolerance_m,
                                         axle_m)
        if len(xs) == 1:  # the sweep is the body itself
            c = body_corners(xs, ys, ths, ahead_m, behind_m, width_m)
            corners.append(c)
            rings.append((np.concatenate([c[0], c[:1, 0]]), np.array([0, 5])))
            continue
        for ahead, behind in parts:
            c = body_corners(xs, ys, ths, ahead, behind, width_m)
            coords, offsets = pair_hulls(np.ascontiguousarray(c))
            if len(offsets) != len(c):  # a hull of no area: no floor from this run
                return [], []
            corners.append(c)
            rings.append((coords, offsets))
    return corners, rings


class _Corners:
    """The body corners of a run's key poses, ``(n, 2)``, and which of them are
    corners of the sweep's boundary (tested when asked: a test is a scan of every
    hull)."""

    def __init__(self, run: TrackingRun, feature_m: tuple[float, float] | None,
                 tolerance_m: float) -> None:
        _, judged, _ = judged_part(run, feature_m)
        corners, rings = _sweep_rings(judged, tolerance_m)
        self.points: np.ndarray = np.empty((0, 2))
        if not corners:
            return
        self._coords = np.concatenate([r[0] for r in rings])
        starts = np.cumsum([0] + [len(r[0]) for r in rings[:-1]])
        self._offsets = np.concatenate(
            [[0]] + [r[1][1:] + k for r, k in zip(rings, starts, strict=True)]
        ).astype(np.int64)
        points = np.concatenate(corners).reshape(-1, 2)
        # away from the trimmed ends only: ahead of the start line and short of the end
        # line by AWAY_M (the boxes lie beyond those lines: end_boxes)
        ends, heading = run.path.xy[[0, -1]], run.path.heading_rad[[0, -1]]
        u = np.stack([np.cos(heading), np.sin(heading)], axis=1)
        ahead = (points - ends[0]) @ u[0]
        short = (ends[1] - points) @ u[1]
        self.points = points[(ahead >= AWAY_M) & (short >= AWAY_M)]
        self._tested: dict[int, bool] = {}

    def on_boundary(self, which: np.ndarray) -> np.ndarray:
        """Whether each of ``self.points[which]`` is a corner of the sweep's boundary."""
        todo = [int(i) for i in which if int(i) not in self._tested]
        if todo:
            hits = corner_vertices(np.ascontiguousarray(self.points[todo]), self._coords,
                                   self._offsets, NEAR_RING_M, MIN_ANGLE_RAD)
            for i, hit in zip(todo, hits, strict=True):
                self._tested[i] = bool(hit)
        return np.array([self._tested[int(i)] for i in which], dtype=bool)


def boundary_corners(run: TrackingRun, feature_m: tuple[float, float] | None = None,
                     tolerance_m: float = DEFAULT_TOLERANCE_M) -> np.ndarray:
    """Body corners of a run that are corners of the boundary of the envelope
    :func:`~clearance.analysis.clearance.judge` measures, away from its trimmed ends,
    ``(k, 2)`` (see the module docstring).

    Examples
    --------
    A car driving straight 30 m (its rear axle from -2.7 m to 27.3 m): its ends are
    trimmed, and its sides are straight edges of the sweep whose only vertices are where
    the body's two parts (ahead of and behind the rear axle) meet at the last pose;
    turning a quarter circle of 12 m radius, its corners turn the boundary at every key
    pose:

    >>> from clearance.analysis.tracking import simulate
    >>> from clearance.vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> np.unique(boundary_corners(simulate(car, [(0.0, 0.0), (30.0, 0.0)])).round(6),
    ...           axis=0).tolist()
    [[27.3, -0.9], [27.3, 0.9]]
    >>> a = np.linspace(0.0, np.pi / 2, 30)
    >>> bend = [(-20.0, 0.0), *zip(12 * np.sin(a), 12 - 12 * np.cos(a)), (12.0, 32.0)]
    >>> len(boundary_corners(simulate(car, bend))) > 10
    True
    """
    c = _Corners(run, feature_m, tolerance_m)
    kept: np.ndarray = c.points[c.on_boundary(np.arange(len(c.points)))]
    return kept


#: Corners tested for the boundary at a time, farthest from an area first.
_CHUNK = 8


def reach_floors(run: TrackingRun, areas: Areas, offset_m: float = 0.0,
                 feature_m: tuple[float, float] | None = None,
                 tolerance_m: float = DEFAULT_TOLERANCE_M,
                 names: tuple[str, ...] = AREAS) -> dict[str, float]:
    """A floor under the reach beyond an area that :func:`~clearance.analysis.clearance.judge`
    finds for ``run`` with the same arguments, by the area's name: that of the first of
    ``names`` (:data:`AREAS`, the outermost first) that has one of at least
    :data:`~clearance.analysis.margins.PRECISION_M` (the judged margin to that area is
    then at most minus the floor); none with a clearance offset or levels.

    The corners beyond an area are tried farthest first: the first that is a corner of
    the envelope's boundary (:func:`boundary_corners`) gives the floor.

    Examples
    --------
    A car on a quarter circle of 12 m radius, its lane from 11 m to 12.6 m: its outer
    front corner reaches beyond the lane, and the floor is the judged reach (to the
    floating point), the pavement 0.5 m wider not left:

    >>> from clearance.analysis.clearance import judge
    >>> from clearance.analysis.tracking import simulate
    >>> from clearance.vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> a = np.linspace(0.0, np.pi / 2, 30)
    >>> run = simulate(car, [(-20.0, 0.0), *zip(12 * np.sin(a), 12 - 12 * np.cos(a)),
    ...                      (12.0, 32.0)])
    >>> ring = shapely.Point(0, 12).buffer(12.6, 256).difference(
    ...     shapely.Point(0, 12).buffer(11.0, 256)).intersection(shapely.box(0, -5, 20, 12))
    >>> lane = shapely.union_all([ring, shapely.box(-25, -0.6, 0, 1.0),
    ...                           shapely.box(11.0, 12, 12.6, 40)])
    >>> areas = Areas(lane, lane.buffer(0.5))
    >>> floors = reach_floors(run, areas)
    >>> sorted(floors), round(floors["own_lanes"], 4), round(-judge(run, areas).margin_m, 4)
    (['own_lanes'], 0.4939, 0.4939)

    Straight in its lane, no floor (the degenerate case):

    >>> straight = Areas(shapely.box(-10, 0, 40, 3.5), shapely.box(-10, -3.5, 40, 7.0))
    >>> reach_floors(simulate(car, [(0.0, 1.75), (30.0, 1.75)]), straight)
    {}
    """
    if offset_m > 0 or areas.levels:
        return {}
    corners = _Corners(run, feature_m, tolerance_m)
    points = corners.points
    floors: dict[str, float] = {}
    if not len(points):
        return floors
    for name in names:
        if floors:
            break
        area = getattr(areas, name)
        if area is None:
            continue
        beyond = np.flatnonzero(~shapely.contains_xy(area, points[:, 0], points[:, 1]))
        if not len(beyond):
            continue
        d = segments_distance(np.ascontiguousarray(points[beyond]), areas.segments(name))
        order = np.argsort(-d, kind="stable")
        order = order[d[order] - SLACK_M >= PRECISION_M]  # only those that could give a floor
        for lo in range(0, len(order), _CHUNK):
            part = order[lo:lo + _CHUNK]
            hit = corners.on_boundary(beyond[part])
            if hit.any():
                floors[name] = float(d[part[int(np.argmax(hit))]]) - SLACK_M
                break
    return floors
