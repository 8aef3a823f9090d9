"""A cheap bound on how far a run's envelope leaves the paved area, for screening candidates.

A search that judges hundreds of candidate lines per run (:mod:`clearance.networks.driving.swing`)
needs each one's exact clearance only where it could be the best; a line that provably
leaves the pavement further than one already judged need not be. The bound here is read
off the body's corners at the judged samples, without building the envelope:

- points round each body's outline, its corners and every :data:`OUTLINE_STEP_M` along its
  sides, at the judged samples where a corner is outside the pavement and the samples
  either side (at every judged sample with a clearance offset): fewer points only weaken
  the bound;
- the envelope :func:`clearance.analysis.clearance.judge` measures is the union of the
  bodies' hulls between *key* samples (:func:`clearance.analysis.envelope.sweep`); every
  sample's body lies within ``tolerance_m`` of it, so a point ``p`` outside the paved area
  by ``d(p)`` puts a point of the envelope at least ``d(p) - tolerance_m`` beyond it
  (the distance to an area is 1-Lipschitz);
- the exact overreach is found by branch and bound short of the true one by at most
  half of :data:`~clearance.analysis.margins.DEFAULT_DENSIFY_M`;
- the envelope is trimmed at the path's ends (:func:`~clearance.analysis.clearance.end_boxes`),
  so points within :data:`~clearance.analysis.clearance.END_SLACK_M` plus the tolerance
  of those boxes do not count; a clearance offset grows every depth by itself (and the
  distance kept from the boxes), points inside the pavement then counting too.

So the judged paved margin is at most ``-(max d(p) + offset - tolerance - densify / 2)``
(:func:`paved_reach_bound_m` returns that reach). Where it is at least
:data:`~clearance.analysis.margins.PRECISION_M`, the verdict is ``fails`` or worse and the
paved margin no better than minus it. Runs on networks with levels are not bounded (their
storeys are judged apart).
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from clearance.analysis.clearance import END_SLACK_M, Areas
from clearance.analysis.envelope import DEFAULT_TOLERANCE_M, body_points
from clearance.analysis.feature import feature_mask
from clearance.analysis.kernels import segments_distance
from clearance.analysis.margins import DEFAULT_DENSIFY_M
from clearance.analysis.polyline import Path
from clearance.analysis.tracking import TrackingRun

__all__ = ["OUTLINE_STEP_M", "paved_reach_bound_m"]

OUTLINE_STEP_M = 0.5
"""Points of a body's outline are read this far apart at most (m)."""


def paved_reach_bound_m(run: TrackingRun, areas: Areas, offset_m: float = 0.0,
                        feature_m: tuple[float, float] | None = None,
                        tolerance_m: float = DEFAULT_TOLERANCE_M) -> float:
    """How far the judged envelope of ``run`` leaves the paved area at least (m; ``-inf``:
    no bound, none of its outline's points is outside, or the areas have levels).

    The judged paved margin (:func:`clearance.analysis.clearance.judge` with the same
    offset, window and tolerance) is at most minus this (see the module docstring).

    Examples
    --------
    A car 1.8 m wide driven 0.75 m from the edge of a strip of pavement: its right side
    reaches 0.15 m beyond; less the sweep's tolerance (0.02 m) and half the search's step
    (0.025 m), the bound is 0.105 m, and the judged margin is no better than minus it.

    >>> from clearance.analysis.clearance import judge
    >>> from clearance.analysis.tracking import simulate
    >>> from clearance.vehicles.vehicle import Vehicle
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate(car, [(0.0, 0.75), (30.0, 0.75)])
    >>> strip = shapely.box(-10, 0, 40, 3.5)
    >>> areas = Areas(strip, strip)
    >>> bound = paved_reach_bound_m(run, areas)
    >>> round(bound, 3), judge(run, areas).paved_margin_m <= -bound
    (0.105, True)

    On the pavement (the degenerate case) there is nothing to bound:

    >>> paved_reach_bound_m(simulate(car, [(0.0, 1.75), (30.0, 1.75)]), areas)
    -inf
    """
    if areas.levels:
        return -math.inf
    v, tr = run.vehicle, run.trajectory
    keep = slice(None)
    if feature_m is not None:  # the judged samples (judged_part): one either side
        inside = np.flatnonzero(feature_mask(run, feature_m))
        if len(inside):
            keep = slice(max(int(inside[0]) - 1, 0), int(inside[-1]) + 2)
    parts = [(tr.x_m, tr.y_m, tr.theta_rad, v.wheelbase_m + v.front_overhang_m,
              v.rear_overhang_m, v.width_m)]
    if (v.trailer is not None and tr.xt_m is not None and tr.yt_m is not None
            and tr.theta_t_rad is not None):
        t = v.trailer
        parts.append((tr.xt_m, tr.yt_m, tr.theta_t_rad, t.wheelbase_m + t.front_overhang_m,
                      t.rear_overhang_m, t.width_m))
    xs, ys = [], []
    for x, y, th, ahead, behind, width in parts:
        x, y, th = x[keep], y[keep], th[keep]
        poses = np.ones(len(x), dtype=bool)
        if offset_m <= 0:  # the outline only where a corner is out, and a pose either side
            cx, cy = body_points(x, y, th, np.array([-behind, ahead, ahead, -behind]),
                                 np.array([-0.5, -0.5, 0.5, 0.5]) * width)
            paved_c: np.ndarray = np.asarray(shapely.contains_xy(areas.paved, cx, cy))
            out_c = np.logical_not(np.all(paved_c, axis=1))
            poses = out_c | np.r_[out_c[1:], False] | np.r_[False, out_c[:-1]]
        along, across = _outline(ahead, behind, width)
        px, py = body_points(x[poses], y[poses], th[poses], along, across)
        xs.append(px.ravel())
        ys.append(py.ravel())
    px, py = np.concatenate(xs), np.concatenate(ys)
    if not len(px):
        return -math.inf
    out = ~shapely.contains_xy(areas.paved, px, py)
    if offset_m <= 0:  # only points outside can reach out (with an offset, all may)
        if not out.any():
            return -math.inf
        px, py, out = px[out], py[out], out[out]
    # points in (or near) the end boxes may lie in what the trim cuts away
    reach = v.overall_length_m + max(v.width_m, v.trailer.width_m if v.trailer else 0.0)
    keep_pt = ~_near_end_boxes(run.path, reach + offset_m + 1.0,
                               END_SLACK_M + tolerance_m + offset_m, px, py)
    if not keep_pt.any():
        return -math.inf
    xy = np.ascontiguousarray(np.stack([px[keep_pt], py[keep_pt]], axis=1))
    gap = segments_distance(xy, np.ascontiguousarray(areas.segments("paved")))
    depth = float(np.where(out[keep_pt], gap, -gap).max())
    return depth + offset_m - tolerance_m - 0.5 * DEFAULT_DENSIFY_M


def _outline(ahead_m: float, behind_m: float, width_m: float
             ) -> tuple[np.ndarray, np.ndarray]:
    """Points round a body's rectangle, at most :data:`OUTLINE_STEP_M` apart, corners
    included (along and across, from the reference point): the deepest point of a side
    that spans a curved edge lies between its corners."""
    n_long = max(1, math.ceil((ahead_m + behind_m) / OUTLINE_STEP_M))
    n_wide = max(1, math.ceil(width_m / OUTLINE_STEP_M))
    along = np.linspace(-behind_m, ahead_m, n_long + 1)
    across = np.linspace(-0.5 * width_m, 0.5 * width_m, n_wide + 1)
    a = np.concatenate([along, along, np.full(n_wide - 1, -behind_m),
                        np.full(n_wide - 1, ahead_m)])
    c = np.concatenate([np.full(n_long + 1, -0.5 * width_m), np.full(n_long + 1, 0.5 * width_m),
                        across[1:-1], across[1:-1]])
    return a, c


def _near_end_boxes(path: Path, reach_m: float, slack_m: float, px: np.ndarray,
                    py: np.ndarray) -> np.ndarray:
    """Whether each point lies in :func:`~clearance.analysis.clearance.end_boxes`'s boxes
    grown by ``slack_m`` (each box: ``reach_m`` beyond an end along its heading, ``reach_m``
    either side)."""
    near = np.zeros(len(px), dtype=bool)
    for i, sign in ((0, -1.0), (-1, 1.0)):
        ux, uy = sign * math.cos(path.heading_rad[i]), sign * math.sin(path.heading_rad[i])
        dx, dy = px - path.xy[i, 0], py - path.xy[i, 1]
        along, across = dx * ux + dy * uy, dx * -uy + dy * ux
        near |= ((along >= -slack_m) & (along <= reach_m + slack_m)
                 & (np.abs(across) <= reach_m + slack_m))
    return near
