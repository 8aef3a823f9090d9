"""Swept path of a run: body envelopes, wheel tracks, offtracking and swept width.

Definitions
-----------
Body rectangles
    The towing unit spans ``-a_r .. l + a_f`` along its centre line from the rear-axle centre
    and ``+-B/2`` across; a trailer spans ``-a_r,t .. l_t + a_f,t`` from its axle centre
    (its nose ``a_f,t`` ahead of the hitch) and ``+-B_t/2``.
Swept envelope
    The body is cut at its unsteered axle (the rear axle; the front axle of a rear-steered
    vehicle; a trailer's axle) into a front and a rear part. Between consecutive *key*
    samples each part's sweep is taken as the convex hull of its two positions; the
    envelope is the union of these hulls. The instantaneous centre of rotation of a unit
    lies on its axle line, so each part's point nearest to it is an axle-line corner, whose
    arc the hull replaces by a chord; every other boundary point too lies on an arc the
    hull replaces by its chord. A vertex's path of length ``L`` that turns by ``A`` between
    two key samples strays from its chord by at most ``L A / 4`` (the worst case being a
    kink half-way; a circular arc strays ``L A / 8``), and edge points stray no more than
    their vertices. Key samples are chosen greedily, from the sampled vertex paths, so that
    this bound stays under ``tolerance_m``, both ways (hull short of the sweep, or beyond
    it); in straight driving the hull is exact and samples are skipped freely. (A vertex
    path turns with the body and also when the steering changes, which moves the centre of
    rotation: both count.) The hull of the uncut body would not do: on the inside of
    a turn its side rotates about a point between its ends, and the hull of two positions
    cuts the corner between the rear of one and the front of the other by
    ``dtheta a b / (a + b)`` (``a`` behind, ``b`` ahead of the axle), a first-order error.
    The result has no gaps between steps.
Wheel tracks
    Contact paths of the wheels as line strings: front and rear wheels at ``+-w/2`` from the
    axle centres (the rear track is taken equal to the steered track ``w``); trailer wheels at
    ``+-min(w, B_t)/2`` from the trailer axle centre (the table gives no trailer track).
Offtracking
    At each sample, the distance from the rear-axle centre (or the trailer-axle centre) to
    the path traced so far by the front-axle centre, looking back along that path by twice
    their current distance (so a later lap of a spiral does not count). The front-axle path
    is extended straight back from its start, because a run starts aligned and straight.
    The maximum over the run is reported; in a steady turn it equals ``CTR - rho``. (A
    rear-steered vehicle's rear axle runs outside the front axle's path: the distance is
    then outward, ``sqrt(R^2 + l^2) - R`` in a steady turn of front-axle radius ``R``.)
Swept width
    At stations every ``width_step_m`` along the centre line (up to the front axle's last
    station), the length of the piece of the normal line through the centre-line point that
    lies inside the envelope and contains that point. The maximum over the stations is
    reported; in a steady turn it equals ``sqrt((rho + B/2)^2 + (l + a_f)^2) - (rho - B/2)``
    (docs/design.md §4). Where the envelope overlaps itself across a normal (a path that comes back
    near itself), the overlapping part counts too; near the path's end the parts of the body that
    trail the front axle have not swept yet, so the widths there are partial.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import cast

import numpy as np
import shapely
from numpy.typing import NDArray
from shapely.geometry.base import BaseGeometry

from clearance.analysis.kernels import (
    greedy_keys,
    look_back_distance,
    normal_widths,
    pair_hulls,
    vertex_path_bounds,
)
from clearance.analysis.tracking import TrackingRun, Trajectory
from clearance.vehicles.vehicle import Vehicle

__all__ = ["DEFAULT_TOLERANCE_M", "DEFAULT_WIDTH_STEP_M", "SweptPath", "body_corners",
           "body_points", "interval_hulls", "key_samples", "ring_segments", "sweep",
           "sweep_poses", "swept_envelope", "swept_path", "swept_widths", "wheel_tracks"]

FloatArray = NDArray[np.float64]

DEFAULT_TOLERANCE_M = 0.02
"""Default bound on the distance between the true swept area's boundary and the polygon's (m)."""

DEFAULT_WIDTH_STEP_M = 0.5
"""Default distance between the stations where the swept width is measured (m)."""


@dataclass(frozen=True)
class SweptPath:
    """Geometry swept by one run.

    Attributes
    ----------
    envelope
        Union of every unit's swept area (Polygon, or MultiPolygon when a drawbar leaves a
        gap between the units).
    tractor, trailer
        Swept area of the towing unit and of the trailer (``None`` without trailer).
    wheel_tracks
        Wheel contact paths by name: ``front_left``, ``front_right``, ``rear_left``,
        ``rear_right`` and, with a trailer, ``trailer_left``, ``trailer_right``.
    offtracking_m
        Offtracking of the rear-axle centre at each sample (m).
    max_offtracking_m, max_offtracking_station_m
        Its maximum and the front axle's station when it occurred.
    trailer_offtracking_m, max_trailer_offtracking_m
        The same for the trailer-axle centre (``None`` without trailer).
    swept_width_m
        ``(K, 2)`` array of (station m, swept width m) along the centre line.
    max_swept_width_m, max_swept_width_station_m
        Largest swept width and its station.
    """

    envelope: BaseGeometry
    tractor: BaseGeometry
    trailer: BaseGeometry | None
    wheel_tracks: dict[str, shapely.LineString]
    offtracking_m: FloatArray
    max_offtracking_m: float
    max_offtracking_station_m: float
    trailer_offtracking_m: FloatArray | None
    max_trailer_offtracking_m: float | None
    swept_width_m: FloatArray
    max_swept_width_m: float
    max_swept_width_station_m: float


def body_points(
    x_m: FloatArray, y_m: FloatArray, theta_rad: FloatArray, along_m: FloatArray,
    across_m: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """Points fixed to a moving body, ``(n, m)`` x and y: ``along_m`` ahead of the reference
    point on the heading and ``across_m`` to its left, at each of ``n`` poses.

    Examples
    --------
    A point 2 m ahead and 1 m to the left, at heading 0 (straight ahead) and at +90 degrees:

    >>> px, py = body_points(np.zeros(2), np.zeros(2), np.array([0.0, np.pi / 2]),
    ...                      np.array([2.0]), np.array([1.0]))
    >>> np.round(px, 9).ravel().tolist(), np.round(py, 9).ravel().tolist()
    ([2.0, -1.0], [1.0, 2.0])
    """
    c, s = np.cos(theta_rad)[:, None], np.sin(theta_rad)[:, None]
    return x_m[:, None] + along_m * c - across_m * s, y_m[:, None] + along_m * s + across_m * c


def body_corners(
    x_m: FloatArray,
    y_m: FloatArray,
    theta_rad: FloatArray,
    ahead_m: float,
    behind_m: float,
    width_m: float,
) -> FloatArray:
    """Corners of a body rectangle about reference points, ``(n, 4, 2)``, counter-clockwise.

    The rectangle spans ``-behind_m .. ahead_m`` along the heading from the reference point
    and ``+-width_m / 2`` across; corners are rear-right, front-right, front-left, rear-left.

    Examples
    --------
    Heading +x (straight ahead):

    >>> body_corners(np.array([0.0]), np.array([0.0]), np.array([0.0]), 4.0, 1.0, 2.0)[0]
    array([[-1., -1.],
           [ 4., -1.],
           [ 4.,  1.],
           [-1.,  1.]])
    """
    along = np.array([-behind_m, ahead_m, ahead_m, -behind_m])
    across = np.array([-0.5, -0.5, 0.5, 0.5]) * width_m
    return np.stack(body_points(x_m, y_m, theta_rad, along, across), axis=-1)


def key_samples(
    px_m: FloatArray, py_m: FloatArray, tolerance_m: float = DEFAULT_TOLERANCE_M
) -> NDArray[np.intp]:
    """Indices of the samples whose consecutive hulls approximate the sweep within tolerance.

    Parameters
    ----------
    px_m, py_m
        ``(n, m)`` paths of the ``m`` vertices of the moving shape, ``n`` samples.
    tolerance_m
        Bound on how far any vertex's path strays from its chord between key samples.

    Greedy: from a key sample ``i``, the next is the farthest ``j`` with
    ``L_ij A_ij / 4 <= tolerance_m``, where ``L_ij`` sums over the steps between them the
    longest step of any vertex and ``A_ij`` the largest turning of any vertex's path at each
    sample. Each vertex's own path length and turning are no larger, and a path of length
    ``L`` turning by ``A`` strays at most ``L A / 4`` from its chord, so every vertex stays
    within the tolerance (in a steady turn every vertex turns alike and the bound is tight).
    Points of the edges stray no more than their end points (they move as fixed blends of
    them). The first and last samples are always included, and so is every sample after a
    single step however much it turns (the sampling then decides the accuracy).

    Examples
    --------
    Straight driving needs only the ends:

    >>> x = np.linspace(0.0, 50.0, 501)[:, None] + np.array([[0.0, 1.0]])
    >>> key_samples(x, 0 * x).tolist()
    [0, 500]

    A point going round a circle of radius 10 m (50 samples a turn): a quarter turn of
    15.7 m strays 3.9 m from its chord by the bound, so the keys come every ``A`` with
    ``10 A^2 / 4 <= 0.02``, about 0.09 rad (one sample of 0.126 rad is the least step):

    >>> a = np.linspace(0.0, 2 * np.pi, 51)
    >>> len(key_samples(10 * np.cos(a)[:, None], 10 * np.sin(a)[:, None]))
    51
    """
    n = px_m.shape[0]
    if n <= 2:
        return np.arange(n)
    # length[k]: the longest vertex steps summed up to sample k; turn[k]: the largest
    # vertex turnings up to and including the bend at sample k - 1 (a little conservative)
    length, turn = vertex_path_bounds(np.ascontiguousarray(px_m, dtype=float),
                                      np.ascontiguousarray(py_m, dtype=float))
    return greedy_keys(length, turn, 4.0 * tolerance_m).astype(np.intp)


def interval_hulls(corners: FloatArray) -> NDArray[np.object_]:
    """Convex hulls of a quadrilateral's consecutive positions, ``(n, 4, 2)`` -> ``n - 1``.

    Compiled (:func:`clearance.analysis.kernels.pair_hulls`); where a hull has no area (a body of no
    width moving along itself) GEOS's convex hull takes over, which gives line strings.

    Examples
    --------
    >>> sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> hulls = interval_hulls(np.stack([sq, sq + [1.0, 0.0], sq + [1.0, 1.0]]))
    >>> shapely.area(hulls).tolist()
    [2.0, 2.0]
    >>> bar = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 0.0]])
    >>> interval_hulls(np.stack([bar, bar + [1.0, 0.0]]))[0].wkt
    'LINESTRING (0 0, 2 0)'
    """
    coords, offsets = pair_hulls(np.ascontiguousarray(corners, dtype=float))
    if len(offsets) == len(corners) or len(corners) < 2:
        return shapely.from_ragged_array(shapely.GeometryType.POLYGON, coords,
                                         (offsets, np.arange(len(offsets))))
    pairs = np.concatenate([corners[:-1], corners[1:]], axis=1)
    # an (N, 8, 2) array of coordinates gives an array of N hulls
    return cast("NDArray[np.object_]", shapely.convex_hull(shapely.multipoints(pairs)))


def sweep_poses(
    x_m: FloatArray,
    y_m: FloatArray,
    theta_rad: FloatArray,
    ahead_m: float,
    behind_m: float,
    width_m: float,
    tolerance_m: float = DEFAULT_TOLERANCE_M,
    axle_m: float = 0.0,
) -> tuple[FloatArray, FloatArray, FloatArray, list[tuple[float, float]]]:
    """The key poses :func:`sweep` unites and the parts of the body it sweeps.

    Returns the key poses' ``x``, ``y`` and heading, and the parts as ``(ahead, behind)``
    about the reference point, the longer first, each of some length: the body is cut at
    ``axle_m`` (see :func:`sweep`), and the longer part's sweep covers most of the shorter
    one's hulls.

    Examples
    --------
    A body 4 m ahead of and 1 m behind its rear axle, standing still: its first and last
    poses; the part ahead of the axle first:

    >>> xs, ys, ths, parts = sweep_poses(np.zeros(3), np.zeros(3), np.zeros(3), 4.0, 1.0, 2.0)
    >>> len(xs), parts
    (2, [(4.0, -0.0), (0.0, 1.0)])

    Cut at its rear end (no part behind the axle), only the part ahead is swept:

    >>> sweep_poses(np.zeros(1), np.zeros(1), np.zeros(1), 4.0, 0.0, 2.0)[3]
    [(4.0, -0.0)]
    """
    # vertices of both parts: the body's corners and the two ends of its axle line
    along = np.array([-behind_m, ahead_m, ahead_m, -behind_m, axle_m, axle_m])
    across = np.array([-0.5, -0.5, 0.5, 0.5, -0.5, 0.5]) * width_m
    px, py = body_points(x_m, y_m, theta_rad, along, across)
    keys = key_samples(px, py, tolerance_m)
    # the longer part first: the shorter part's hulls that its sweep covers (most of them,
    # away from where the turning starts) add nothing and are left out of the union
    parts = sorted(((ahead_m, -axle_m), (axle_m, behind_m)), key=lambda p: -(p[0] + p[1]))
    return (x_m[keys], y_m[keys], theta_rad[keys],
            [(a, b) for a, b in parts if a + b > 0])


def sweep(
    x_m: FloatArray,
    y_m: FloatArray,
    theta_rad: FloatArray,
    ahead_m: float,
    behind_m: float,
    width_m: float,
    tolerance_m: float = DEFAULT_TOLERANCE_M,
    axle_m: float = 0.0,
) -> BaseGeometry:
    """Area swept by a rectangle carried along sampled poses (see the module docstring).

    The rectangle spans ``-behind_m .. ahead_m`` along the heading from the reference point
    ``(x_m, y_m)`` and is cut at ``axle_m`` (the unsteered axle, on whose line the centre of
    rotation lies: 0 for the rear axle of a front-steered unit, the wheelbase for a
    rear-steered one).

    Examples
    --------
    Standing still sweeps the rectangle itself; driving straight 10 m adds 10 m:

    >>> sweep(np.zeros(1), np.zeros(1), np.zeros(1), 4.0, 1.0, 2.0).area
    10.0
    >>> x = np.linspace(0.0, 10.0, 101)
    >>> round(sweep(x, 0 * x, 0 * x, 4.0, 1.0, 2.0).area, 9)
    30.0

    A 3 m bar turning on the spot by a half turn sweeps a disc of radius 1.5 m (the polygon
    is inscribed in it, short of it by at most the tolerance):

    >>> th = np.linspace(0.0, np.pi, 721)
    >>> a = sweep(0 * th, 0 * th, th, 1.5, 1.5, 0.0)
    >>> bool(np.pi * (1.5 - 0.02) ** 2 < a.area < np.pi * 1.5 ** 2)
    True
    """
    xs, ys, ths, parts = sweep_poses(x_m, y_m, theta_rad, ahead_m, behind_m, width_m,
                                     tolerance_m, axle_m)
    if len(xs) == 1:
        body: BaseGeometry = shapely.polygons(
            body_corners(xs, ys, ths, ahead_m, behind_m, width_m)[0])
        return body
    swept: BaseGeometry | None = None
    for ahead, behind in parts:
        hulls = interval_hulls(body_corners(xs, ys, ths, ahead, behind, width_m))
        if swept is None:
            swept = shapely.union_all(hulls)
            shapely.prepare(swept)
            continue
        hulls = hulls[~shapely.covers(swept, hulls)]
        if len(hulls):
            swept = shapely.union_all(np.concatenate([[swept], hulls]))
    if swept is None:  # both parts of no length: ahead_m + behind_m <= 0
        raise ValueError(f"sweep: a body of no length (ahead {ahead_m} m, behind {behind_m} m)")
    return swept


def _offtracking(
    fx: FloatArray, fy: FloatArray, qx: FloatArray, qy: FloatArray, theta0: float
) -> FloatArray:
    """Distance from each point q_i to the front path up to sample i, looking back locally.

    The front path is extended straight back from its start; the window of sample ``i`` is
    the path's segments from ``2 |f_i - q_i| + 1`` metres of arc behind its point ``i`` up
    to that point, every one of them searched
    (:func:`clearance.analysis.kernels.look_back_distance`).
    """
    gap = np.hypot(fx - qx, fy - qy)
    back = float(gap.max()) * 2.0 + 1.0
    # the front path, extended straight back from its start by `back`
    px = np.concatenate([[fx[0] - back * math.cos(theta0)], fx])
    py = np.concatenate([[fy[0] - back * math.sin(theta0)], fy])
    # sample i is point i + 1 of the extended path
    return look_back_distance(px, py, qx, qy, 2.0 * gap + 1.0)


def wheel_tracks(vehicle: Vehicle, traj: Trajectory) -> dict[str, shapely.LineString]:
    """Wheel contact paths of a run (see the module docstring for the tracks used).

    Examples
    --------
    >>> from clearance.analysis.tracking import simulate
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate(car, [(0.0, 0.0), (10.0, 0.0)])
    >>> tracks = wheel_tracks(car, run.trajectory)
    >>> round(tracks["front_left"].length, 9), tracks["rear_right"].coords[0]
    (10.0, (-2.7, -0.75))
    """
    names = ["front_left", "front_right", "rear_left", "rear_right"]
    half = vehicle.track_m / 2
    cx, cy = [traj.xf_m, traj.xf_m, traj.x_m, traj.x_m], [traj.yf_m, traj.yf_m, traj.y_m, traj.y_m]
    side = [half, -half, half, -half]
    heading = [traj.theta_rad] * 4
    if (vehicle.trailer is not None and traj.theta_t_rad is not None
            and traj.xt_m is not None and traj.yt_m is not None):
        ht = min(vehicle.track_m, vehicle.trailer.width_m) / 2
        names += ["trailer_left", "trailer_right"]
        cx += [traj.xt_m] * 2
        cy += [traj.yt_m] * 2
        side += [ht, -ht]
        heading += [traj.theta_t_rad] * 2
    th = np.array(heading)
    off = np.array(side)[:, None]
    # each wheel at +-its half track along the unit's left normal (-sin, cos)
    coords = np.empty((len(names), th.shape[1], 2))
    coords[:, :, 0] = np.array(cx) + off * -np.sin(th)
    coords[:, :, 1] = np.array(cy) + off * np.cos(th)
    if coords.shape[1] == 1:
        coords = np.concatenate([coords, coords], axis=1)
    # an (N, M, 2) array of coordinates gives an array of N lines
    lines = cast("NDArray[np.object_]", shapely.linestrings(coords))
    return dict(zip(names, lines, strict=True))


def ring_segments(geom: BaseGeometry) -> tuple[FloatArray, FloatArray]:
    """Start and end points, ``(k, 2)`` each, of every boundary segment of a (multi)polygon.

    Examples
    --------
    >>> a, b = ring_segments(shapely.box(0, 0, 2, 1))
    >>> len(a), float(np.hypot(*(b - a).T).sum())
    (4, 6.0)
    >>> [x.shape for x in ring_segments(shapely.Polygon())]
    [(0, 2), (0, 2)]
    """
    coords, ring = shapely.get_coordinates(shapely.get_rings(shapely.get_parts(geom)),
                                           return_index=True)
    same = ring[1:] == ring[:-1]
    return coords[:-1][same], coords[1:][same]


def swept_widths(
    envelope: BaseGeometry,
    run: TrackingRun,
    width_step_m: float = DEFAULT_WIDTH_STEP_M,
    stations_m: tuple[float, float] | None = None,
) -> FloatArray:
    """Swept width along the centre line, ``(K, 2)`` rows of (station m, width m).

    With ``stations_m`` (e.g. the feature's ``core_start_m``, ``core_end_m``) only the
    stations between those two count (at least the one nearest to them, when none lies
    between: the widths are never empty).

    Each station's normal line is cut with every boundary segment of the envelope; the
    nearest crossings on either side of the centre-line point bound the piece that contains
    it (zero when the point lies outside the envelope: an odd number of crossings on one
    side means inside).

    Examples
    --------
    >>> from clearance.analysis.tracking import simulate
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> run = simulate(car, [(0.0, 0.0), (10.0, 0.0)])
    >>> env = shapely.box(-4.0, -0.5, 11.0, 1.5)
    >>> np.round(swept_widths(env, run, width_step_m=5.0), 9).tolist()
    [[0.0, 2.0], [5.0, 2.0], [10.0, 2.0]]
    """
    path = run.path
    last = float(min(path.length_m, np.max(run.trajectory.s_m)))
    k = max(2, math.ceil(last / width_step_m - 1e-9) + 1)
    stations = np.linspace(0.0, last, k)
    if stations_m is not None:
        inside = (stations >= stations_m[0] - 1e-9) & (stations <= stations_m[1] + 1e-9)
        mid = 0.5 * (stations_m[0] + stations_m[1])
        stations = stations[inside] if inside.any() else stations[[np.argmin(
            np.abs(stations - mid))]]
    p = path.point_at(stations)
    h = path.heading_at(stations)
    a, b = ring_segments(envelope)
    d = b - a
    widths = normal_widths(p[:, 0], p[:, 1], -np.sin(h), np.cos(h), a[:, 0], a[:, 1], d[:, 0],
                           d[:, 1])
    return np.stack([stations, widths], axis=1)


def swept_envelope(run: TrackingRun, tolerance_m: float = DEFAULT_TOLERANCE_M
                   ) -> tuple[BaseGeometry, BaseGeometry, BaseGeometry | None]:
    """The area a run's bodies sweep: ``(envelope, tractor's, trailer's or None)``.

    The envelope alone, for judging a path (:func:`clearance.analysis.clearance.judge`):
    :func:`swept_path` adds the wheel tracks, offtracking and swept widths.

    Examples
    --------
    Straight ahead 10 m, a car without trailer: the body stretched by the distance.

    >>> from clearance.analysis.tracking import simulate
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> env, tractor, trailer = swept_envelope(simulate(car, [(0.0, 0.0), (10.0, 0.0)]))
    >>> round(env.area, 6), env.equals(tractor), trailer is None
    (26.28, True, True)

    Standing still (one sample) sweeps the body itself:

    >>> from clearance.analysis.feature import slice_run
    >>> one = slice_run(simulate(car, [(0.0, 0.0), (10.0, 0.0)]), np.array([0]))
    >>> round(swept_envelope(one)[0].area, 6)
    8.28
    """
    v, tr = run.vehicle, run.trajectory
    wb = v.wheelbase_m
    tractor = sweep(tr.x_m, tr.y_m, tr.theta_rad, wb + v.front_overhang_m, v.rear_overhang_m,
                    v.width_m, tolerance_m, axle_m=wb if v.steered_axle == "rear" else 0.0)
    if (v.trailer is None or tr.theta_t_rad is None or tr.xt_m is None
            or tr.yt_m is None):
        return tractor, tractor, None
    t = v.trailer
    trailer_area = sweep(tr.xt_m, tr.yt_m, tr.theta_t_rad, t.wheelbase_m + t.front_overhang_m,
                         t.rear_overhang_m, t.width_m, tolerance_m)
    return shapely.union(tractor, trailer_area), tractor, trailer_area


def swept_path(
    run: TrackingRun,
    tolerance_m: float = DEFAULT_TOLERANCE_M,
    width_step_m: float = DEFAULT_WIDTH_STEP_M,
    stations_m: tuple[float, float] | None = None,
) -> SweptPath:
    """Envelope, wheel tracks, offtracking and swept width of one run.

    Parameters
    ----------
    run
        A run from :func:`clearance.analysis.tracking.simulate_batch`.
    tolerance_m
        Largest gap between the true swept area and the envelope polygon (m).
    width_step_m
        Distance between the stations where the swept width is measured (m).
    stations_m
        Only the stations between these two (m) are measured (:func:`swept_widths`).

    Examples
    --------
    Straight ahead: the envelope is the body stretched by the distance driven, the swept
    width is the body width and nothing offtracks.

    >>> from clearance.analysis.tracking import simulate
    >>> car = Vehicle("car", 2.7, 1.5, 1.8, 0.9, 1.0, 0.6, 0.65, 0.5)
    >>> sp = swept_path(simulate(car, [(0.0, 0.0), (10.0, 0.0)]))
    >>> round(sp.envelope.area, 6), round(sp.max_swept_width_m, 9)
    (26.28, 1.8)
    >>> round(sp.max_offtracking_m, 12)
    0.0
    """
    v, tr = run.vehicle, run.trajectory
    envelope, tractor, trailer_area = swept_envelope(run, tolerance_m)
    theta0 = float(tr.theta_rad[0])
    off = _offtracking(tr.xf_m, tr.yf_m, tr.x_m, tr.y_m, theta0)
    i_off = int(np.argmax(off))
    off_t = None
    if trailer_area is not None and tr.xt_m is not None and tr.yt_m is not None:
        off_t = _offtracking(tr.xf_m, tr.yf_m, tr.xt_m, tr.yt_m, theta0)
    widths = swept_widths(envelope, run, width_step_m, stations_m)
    i_w = int(np.argmax(widths[:, 1]))
    return SweptPath(
        envelope=envelope,
        tractor=tractor,
        trailer=trailer_area,
        wheel_tracks=wheel_tracks(v, tr),
        offtracking_m=off,
        max_offtracking_m=float(off[i_off]),
        max_offtracking_station_m=float(tr.s_m[i_off]),
        trailer_offtracking_m=off_t,
        max_trailer_offtracking_m=None if off_t is None else float(off_t.max()),
        swept_width_m=widths,
        max_swept_width_m=float(widths[i_w, 1]),
        max_swept_width_station_m=float(widths[i_w, 0]),
    )
