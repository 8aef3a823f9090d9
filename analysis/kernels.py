"""Compiled inner loops of the swept-path measures (numba).

Each function is a plain loop over points and segments, compiled by numba on first use and
cached beside this file, so the envelope of a run costs no per-element Python work. They
are the hot path of :mod:`clearance.analysis.envelope` and :mod:`clearance.analysis.clearance`; the
definitions (what is measured) live there, these only compute.

All lengths are in metres; arrays are float64 unless said otherwise.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["corner_vertices", "farthest_from_segments", "greedy_keys", "look_back_distance",
           "normal_widths", "pair_hulls", "project_near", "segments_distance",
           "vertex_path_bounds", "windowed_distance"]


@njit(cache=True)
def _point_segment_d2(qx: float, qy: float, ax: float, ay: float, bx: float,
                      by: float) -> float:  # pragma: no cover - compiled
    dx, dy = bx - ax, by - ay
    rx, ry = qx - ax, qy - ay
    dd = dx * dx + dy * dy
    t = 0.0
    if dd > 0.0:
        t = (rx * dx + ry * dy) / dd
        if t < 0.0:
            t = 0.0
        elif t > 1.0:
            t = 1.0
    ex, ey = rx - t * dx, ry - t * dy
    return ex * ex + ey * ey


@njit(cache=True)
def windowed_distance(px: np.ndarray, py: np.ndarray, qx: np.ndarray, qy: np.ndarray,
                      lo: np.ndarray, hi: np.ndarray) -> np.ndarray:  # pragma: no cover
    """Distance from each point ``q_i`` to the polyline's segments ``lo[i] .. hi[i] - 1``.

    Segment ``j`` joins points ``j`` and ``j + 1`` of ``(px, py)``; ``inf`` where the
    window is empty.

    Every segment of the window counts, but not every one is measured: the search starts at
    the previous point's nearest segment and goes both ways along the polyline, and a point
    of the polyline at distance ``d`` from ``q_i`` rules out every segment within ``d - best``
    of it along the polyline (a path of that length cannot come nearer than ``best``). The
    segments left out could not be nearer, so the minimum is the one over the whole window.

    Examples
    --------
    A straight path along x; a point 2 m beside it, another beyond its last segment:

    >>> px, py = np.arange(5.0), np.zeros(5)
    >>> d = windowed_distance(px, py, np.array([1.5, 7.0]), np.array([2.0, 0.0]),
    ...                       np.array([0, 0]), np.array([4, 4]))
    >>> d.tolist()
    [2.0, 3.0]

    Only the segments in the window count (the window of the second point is empty):

    >>> windowed_distance(px, py, np.array([0.0, 0.0]), np.array([0.0, 0.0]),
    ...                   np.array([2, 1]), np.array([4, 1])).tolist()
    [2.0, inf]
    """
    return _nearest_in_windows(px, py, _arc_lengths(px, py), qx, qy, lo, hi)


@njit(cache=True)
def look_back_distance(px: np.ndarray, py: np.ndarray, qx: np.ndarray, qy: np.ndarray,
                       reach: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    """Distance from each point ``q_i`` to the polyline from point ``i + 1`` back ``reach_i``.

    The window of ``q_i`` (:func:`windowed_distance`) is the segments from the last point
    more than ``reach_i`` metres of arc behind point ``i + 1`` (the first point if none is),
    up to point ``i + 1``.

    Examples
    --------
    A straight path along x; each point 2 m behind point ``i + 1`` and 1 m to its left. Its
    window reaching far back holds the point beside it (the first point has nothing behind
    it); a window of 0.5 m holds only the last segment:

    >>> px, py = np.arange(6.0), np.zeros(6)
    >>> qx, qy = np.arange(5.0) - 1.0, np.ones(5)
    >>> np.round(look_back_distance(px, py, qx, qy, np.full(5, 9.0)), 3).tolist()
    [1.414, 1.0, 1.0, 1.0, 1.0]
    >>> np.round(look_back_distance(px, py, qx, qy, np.full(5, 0.5)), 3).tolist()
    [1.414, 1.414, 1.414, 1.414, 1.414]
    """
    arc = _arc_lengths(px, py)
    n = qx.shape[0]
    lo = np.empty(n, dtype=np.int64)
    hi = np.empty(n, dtype=np.int64)
    for i in range(n):
        hi[i] = i + 1
        j = np.searchsorted(arc, arc[i + 1] - reach[i], side="right") - 1
        lo[i] = min(max(j, 0), i)
    return _nearest_in_windows(px, py, arc, qx, qy, lo, hi)


@njit(cache=True)
def _arc_lengths(px: np.ndarray, py: np.ndarray) -> np.ndarray:  # pragma: no cover
    m = px.shape[0]
    arc = np.zeros(m)
    for k in range(m - 1):
        arc[k + 1] = arc[k] + math.hypot(px[k + 1] - px[k], py[k + 1] - py[k])
    return arc


@njit(cache=True)
def _nearest_in_windows(px: np.ndarray, py: np.ndarray, arc: np.ndarray, qx: np.ndarray,
                        qy: np.ndarray, lo: np.ndarray,
                        hi: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    n = qx.shape[0]
    out = np.empty(n)
    start = -1
    for i in range(n):
        a, b = lo[i], hi[i]
        if b <= a:
            out[i] = np.inf
            continue
        x, y = qx[i], qy[i]
        j0 = start if a <= start < b else b - 1
        best2 = _point_segment_d2(x, y, px[j0], py[j0], px[j0 + 1], py[j0 + 1])
        best = math.sqrt(best2)
        nearest = j0
        j = j0 - 1
        while j >= a:  # back along the polyline, ruling out from each segment's end point
            ex, ey = x - px[j + 1], y - py[j + 1]
            slack = math.sqrt(ex * ex + ey * ey) - best - 1e-9
            if slack > 0.0 and arc[j] > arc[j + 1] - slack:
                lim = arc[j + 1] - slack
                while j >= a and arc[j] > lim:
                    j -= 1
                continue
            d2 = _point_segment_d2(x, y, px[j], py[j], px[j + 1], py[j + 1])
            if d2 < best2:
                best2, best, nearest = d2, math.sqrt(d2), j
            j -= 1
        j = j0 + 1
        while j < b:  # and ahead, ruling out from each segment's start point
            ex, ey = x - px[j], y - py[j]
            slack = math.sqrt(ex * ex + ey * ey) - best - 1e-9
            if slack > 0.0 and arc[j + 1] < arc[j] + slack:
                lim = arc[j] + slack
                while j < b and arc[j + 1] < lim:
                    j += 1
                continue
            d2 = _point_segment_d2(x, y, px[j], py[j], px[j + 1], py[j + 1])
            if d2 < best2:
                best2, best, nearest = d2, math.sqrt(d2), j
            j += 1
        out[i] = best
        start = nearest
    return out


@njit(cache=True)
def segments_distance(xy: np.ndarray, segs: np.ndarray) -> np.ndarray:  # pragma: no cover
    """Distance from each point ``(k, 2)`` to the nearest segment ``(m, 2, 2)`` (``inf``: none).

    Examples
    --------
    >>> segs = np.array([[[0.0, 0.0], [10.0, 0.0]], [[10.0, 0.0], [10.0, 5.0]]])
    >>> segments_distance(np.array([[5.0, 2.0], [13.0, 9.0], [5.0, 0.0]]), segs).tolist()
    [2.0, 5.0, 0.0]
    >>> segments_distance(np.array([[1.0, 1.0]]), np.empty((0, 2, 2))).tolist()
    [inf]
    """
    k = xy.shape[0]
    m = segs.shape[0]
    out = np.empty(k)
    for i in range(k):
        best = np.inf
        for j in range(m):
            d2 = _point_segment_d2(xy[i, 0], xy[i, 1], segs[j, 0, 0], segs[j, 0, 1],
                                   segs[j, 1, 0], segs[j, 1, 1])
            if d2 < best:
                best = d2
        out[i] = math.sqrt(best)
    return out


@njit(cache=True)
def farthest_from_segments(coords: np.ndarray, joined: np.ndarray, segs: np.ndarray,
                           tolerance_m: float,
                           reach_m: float) -> float:  # pragma: no cover - compiled
    """Largest distance to segments ``(m, 2, 2)`` over lines, by branch and bound.

    The lines are the points ``coords`` ``(k, 2)``, point ``i`` joined to point ``i + 1``
    where ``joined[i]``. The same search, in the same rounds, as
    :func:`clearance.analysis.margins.farthest_on_lines` with :func:`segments_distance` as the
    distance (short of the maximum by at most ``tolerance_m``). Returns ``nan`` as soon as a
    probed point lies farther than ``reach_m`` from every segment: the caller then needs a
    distance the segments cannot give.

    Examples
    --------
    The distance from the x axis along a roof line peaks half-way, at 3 m; a probe beyond
    the reach gives ``nan``:

    >>> roof = np.array([[0.0, 0.0], [4.0, 3.0], [8.0, 0.0]])
    >>> axis = np.array([[[-10.0, 0.0], [10.0, 0.0]]])
    >>> farthest_from_segments(roof, np.array([True, True]), axis, 0.01, 5.0)
    3.0
    >>> farthest_from_segments(roof, np.array([True, True]), axis, 0.01, 2.0)
    nan
    """
    k = coords.shape[0]
    if k == 0:
        return 0.0
    d = segments_distance(coords, segs)
    best = -np.inf
    for i in range(k):
        if not d[i] <= reach_m:
            return np.nan
        if d[i] > best:
            best = d[i]
    count = 0
    for i in range(k - 1):
        if joined[i]:
            count += 1
    a = np.empty((count, 2))
    b = np.empty((count, 2))
    da = np.empty(count)
    db = np.empty(count)
    c = 0
    for i in range(k - 1):
        if joined[i]:
            a[c], b[c], da[c], db[c] = coords[i], coords[i + 1], d[i], d[i + 1]
            c += 1
    while count:
        keep = np.empty(count, dtype=np.bool_)
        n_open = 0
        for i in range(count):  # what each segment could hold at most
            bound = 0.5 * (da[i] + db[i] + math.hypot(b[i, 0] - a[i, 0], b[i, 1] - a[i, 1]))
            keep[i] = bound > best + tolerance_m
            n_open += keep[i]
        if n_open == 0:
            break
        oa = a[keep]
        ob = b[keep]
        oda = da[keep]
        odb = db[keep]
        mid = 0.5 * (oa + ob)
        dm = segments_distance(mid, segs)
        for i in range(n_open):
            if not dm[i] <= reach_m:
                return np.nan
            if dm[i] > best:
                best = dm[i]
        a = np.concatenate((oa, mid))
        b = np.concatenate((mid, ob))
        da = np.concatenate((oda, dm))
        db = np.concatenate((dm, odb))
        count = 2 * n_open
    return best


@njit(cache=True)
def normal_widths(px: np.ndarray, py: np.ndarray, nx: np.ndarray, ny: np.ndarray,
                  ax: np.ndarray, ay: np.ndarray, dx: np.ndarray,
                  dy: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    """Length of the piece of each normal line inside a polygon, through its own point.

    The line through ``(px_i, py_i)`` along ``(nx_i, ny_i)`` is cut with every boundary
    segment ``a_j .. a_j + d_j`` (half-open); the nearest crossings on either side bound the
    piece containing the point, which is inside when the crossings on one side are odd in
    number (0 when it is outside).

    Examples
    --------
    The unit square's boundary, a vertical line through its middle, and one outside it:

    >>> ax = np.array([0.0, 1.0, 1.0, 0.0]); ay = np.array([0.0, 0.0, 1.0, 1.0])
    >>> dx = np.array([1.0, 0.0, -1.0, 0.0]); dy = np.array([0.0, 1.0, 0.0, -1.0])
    >>> normal_widths(np.array([0.5, 3.0]), np.array([0.5, 0.5]), np.zeros(2), np.ones(2),
    ...               ax, ay, dx, dy).tolist()
    [1.0, 0.0]
    """
    k = px.shape[0]
    m = ax.shape[0]
    out = np.zeros(k)
    for i in range(k):
        t_pos = np.inf
        t_neg = -np.inf
        count = 0
        for j in range(m):
            denom = nx[i] * dy[j] - ny[i] * dx[j]
            if abs(denom) <= 1e-12:
                continue
            wx, wy = ax[j] - px[i], ay[j] - py[i]
            t = (wx * dy[j] - wy * dx[j]) / denom
            u = (wx * ny[i] - wy * nx[i]) / denom
            if u < 0.0 or u >= 1.0:
                continue
            if t > 0.0:
                count += 1
                if t < t_pos:
                    t_pos = t
            elif t > t_neg:
                t_neg = t
        if count % 2 == 1 and t_pos < np.inf and t_neg > -np.inf:
            out[i] = t_pos - t_neg
    return out


@njit(cache=True)
def vertex_path_bounds(px: np.ndarray,
                       py: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover
    """Cumulative longest step and largest turning over the paths of ``m`` vertices.

    ``px, py`` are ``(n, m)``. ``length[k]`` sums, over the steps up to sample ``k``, the
    longest step any vertex makes; ``turn[k]`` sums, over the samples up to ``k - 1``, the
    largest turning of any vertex's path there (a vertex standing still turns by 0).

    Examples
    --------
    One vertex going 1 m east, then 1 m north (a quarter turn at sample 1):

    >>> length, turn = vertex_path_bounds(np.array([[0.0], [1.0], [1.0]]),
    ...                                   np.array([[0.0], [0.0], [1.0]]))
    >>> length.tolist(), [round(float(t), 6) for t in turn]
    ([0.0, 1.0, 2.0], [0.0, 0.0, 1.570796])
    """
    n, m = px.shape
    length = np.zeros(n)
    turn = np.zeros(n)
    prev_dx = np.zeros(m)
    prev_dy = np.zeros(m)
    prev_moving = np.zeros(m, dtype=np.bool_)
    for k in range(n - 1):
        longest2 = 0.0
        sharpest = 0.0
        for v in range(m):
            dx = px[k + 1, v] - px[k, v]
            dy = py[k + 1, v] - py[k, v]
            chord2 = dx * dx + dy * dy
            if chord2 > longest2:
                longest2 = chord2
            moving = chord2 > 1e-24  # a step over 1e-12 m
            if k > 0 and moving and prev_moving[v]:
                # the angle between this step and the previous one (0 .. pi)
                bend = math.atan2(abs(prev_dx[v] * dy - prev_dy[v] * dx),
                                  prev_dx[v] * dx + prev_dy[v] * dy)
                if bend > sharpest:
                    sharpest = bend
            prev_dx[v], prev_dy[v] = dx, dy
            prev_moving[v] = moving
        length[k + 1] = length[k] + math.sqrt(longest2)
        if k > 0:
            turn[k + 1] = turn[k] + sharpest
    return length, turn


@njit(cache=True)
def greedy_keys(length: np.ndarray, turn: np.ndarray,
                budget: float) -> np.ndarray:  # pragma: no cover - compiled
    """Greedy key samples: from each key, the farthest ``j`` with ``dL dT <= budget``.

    ``length`` and ``turn`` are non-decreasing; ``dL dT`` is measured from the current key.
    A single step is always accepted. The first and last samples are keys.

    Examples
    --------
    >>> greedy_keys(np.arange(6.0), np.array([0.0, 0, 0, 1, 2, 2]), 1.0).tolist()
    [0, 2, 3, 4, 5]
    >>> greedy_keys(np.arange(3.0), np.zeros(3), 1.0).tolist()
    [0, 2]
    """
    n = length.shape[0]
    keys = np.empty(n, dtype=np.int64)
    keys[0] = 0
    count = 1
    i = 0
    last = n - 1
    while i < last:
        a, b = length[i], turn[i]
        if (length[last] - a) * (turn[last] - b) <= budget:
            keys[count] = last
            count += 1
            break
        j, step = i + 1, 1
        while j + step < last and (length[j + step] - a) * (turn[j + step] - b) <= budget:
            j += step
            step *= 2
        hi = min(j + step, last)
        while hi - j > 1:
            mid = (j + hi) // 2
            if (length[mid] - a) * (turn[mid] - b) <= budget:
                j = mid
            else:
                hi = mid
        keys[count] = j
        count += 1
        i = j
    return keys[:count]


@njit(cache=True)
def _cross(ox: float, oy: float, ax: float, ay: float, bx: float,
           by: float) -> float:  # pragma: no cover - compiled
    return (ax - ox) * (by - oy) - (ay - oy) * (bx - ox)


@njit(cache=True)
def pair_hulls(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover
    """Convex hulls of consecutive quadrilaterals: hull ``i`` of ``corners[i]`` and ``[i + 1]``.

    ``corners`` is ``(n, 4, 2)``. Returns the hulls' closed rings, counter-clockwise, as
    ``(k, 2)`` coordinates and ``(n, )`` offsets (ring ``i`` is rows ``offsets[i]`` to
    ``offsets[i + 1] - 1``, its first point repeated last; Andrew's monotone chain, collinear
    points dropped), ready for ``shapely.from_ragged_array``. A hull with no area (all eight
    points on one line) makes the whole answer empty (one offset, no rows): the caller must
    then use another way.

    Examples
    --------
    A unit square moved 1 m right sweeps a 2 x 1 rectangle:

    >>> sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> coords, offsets = pair_hulls(np.stack([sq, sq + [1.0, 0.0]]))
    >>> coords.tolist(), offsets.tolist()
    ([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0], [0.0, 0.0]], [0, 5])

    Flat quadrilaterals (a bar of no width) moved along their own line have no hull area:

    >>> bar = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 0.0]])
    >>> [x.shape for x in pair_hulls(np.stack([bar, bar + [1.0, 0.0]]))]
    [(0, 2), (1,)]
    """
    n = corners.shape[0] - 1
    out = np.empty((max(n, 0) * 9, 2))
    offsets = np.zeros(max(n, 0) + 1, dtype=np.int64)
    px = np.empty(8)
    py = np.empty(8)
    hx = np.empty(17)
    hy = np.empty(17)
    pos = 0
    for i in range(n):
        for k in range(8):  # the eight corners, sorted by x then y (insertion sort)
            x, y = corners[i + k // 4, k % 4, 0], corners[i + k // 4, k % 4, 1]
            b = k - 1
            while b >= 0 and (px[b] > x or (px[b] == x and py[b] > y)):
                px[b + 1], py[b + 1] = px[b], py[b]
                b -= 1
            px[b + 1], py[b + 1] = x, y
        m = 0
        for a in range(8):  # lower chain, left to right
            while m >= 2 and _cross(hx[m - 2], hy[m - 2], hx[m - 1], hy[m - 1], px[a],
                                    py[a]) <= 0.0:
                m -= 1
            hx[m], hy[m] = px[a], py[a]
            m += 1
        lower = m + 1
        for a in range(6, -1, -1):  # upper chain, right to left, back to the first point
            while m >= lower and _cross(hx[m - 2], hy[m - 2], hx[m - 1], hy[m - 1], px[a],
                                        py[a]) <= 0.0:
                m -= 1
            hx[m], hy[m] = px[a], py[a]
            m += 1
        if m < 4:  # fewer than three distinct vertices: no area
            return out[:0], offsets[:1]
        for a in range(m):
            out[pos, 0], out[pos, 1] = hx[a], hy[a]
            pos += 1
        offsets[i + 1] = pos
    return out[:pos], offsets


@njit(cache=True)
def project_near(px: np.ndarray, py: np.ndarray, path_xy: np.ndarray, n_points: np.ndarray,
                 segment: np.ndarray, window: int
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # pragma: no cover
    """Project point ``i`` onto path ``i``, searching segments ``segment[i] - 1`` onward.

    The body of :func:`clearance.analysis.polyline.project_window` (its docstring says what it
    returns): the ``window + 2`` segments from one behind the previous match are searched,
    the first and last segments extended beyond the path's ends.

    Examples
    --------
    >>> xy = np.array([[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]])
    >>> seg, along, lat = project_near(np.array([1.5]), np.array([-0.2]), xy,
    ...                                np.array([3]), np.array([0]), 2)
    >>> int(seg[0]), float(along[0]), float(lat[0])
    (1, 0.5, -0.2)
    """
    n = px.shape[0]
    seg_out = np.empty(n, dtype=np.int64)
    along = np.empty(n)
    lateral = np.empty(n)
    for i in range(n):
        last = n_points[i] - 2
        best_d2 = np.inf
        best_c = 0
        best_t = 0.0
        best_len = 0.0
        best_cross = 0.0
        for w in range(-1, window + 1):
            c = segment[i] + w
            if c < 0:
                c = 0
            elif c > last:
                c = last
            ax, ay = path_xy[i, c, 0], path_xy[i, c, 1]
            dx, dy = path_xy[i, c + 1, 0] - ax, path_xy[i, c + 1, 1] - ay
            rx, ry = px[i] - ax, py[i] - ay
            dd = dx * dx + dy * dy
            t = (rx * dx + ry * dy) / dd if dd > 0.0 else 0.0
            if t < 0.0 and c != 0:
                t = 0.0
            elif t > 1.0 and c != last:
                t = 1.0
            ex, ey = rx - t * dx, ry - t * dy
            d2 = ex * ex + ey * ey
            if d2 < best_d2:
                best_d2, best_c, best_t = d2, c, t
                best_len = math.sqrt(dd)
                best_cross = dx * ry - dy * rx
        seg_out[i] = best_c
        along[i] = best_t * best_len
        lateral[i] = math.copysign(math.sqrt(best_d2), best_cross)
    return seg_out, along, lateral


@njit(cache=True)
def _sector(qx: float, qy: float, coords: np.ndarray, lo: int, hi: int,
            margin_m: float) -> tuple[int, float, float]:  # pragma: no cover - compiled
    """The angle about ``(qx, qy)`` a convex ring (rows ``lo`` to ``hi``, ``hi`` its first
    point repeated) covers: ``(kind, start, length)``, kind 0 far from it, 1 a vertex of it,
    2 on one edge, 3 inside it or near two edges without being a vertex (no clear angle)."""
    near = 0
    edge = -1
    for e in range(lo, hi):
        ax, ay = coords[e, 0], coords[e, 1]
        ex, ey = coords[e + 1, 0] - ax, coords[e + 1, 1] - ay
        length = math.sqrt(ex * ex + ey * ey)
        if length == 0.0:
            continue
        side = (ex * (qy - ay) - ey * (qx - ax)) / length
        if side < -margin_m:
            return 0, 0.0, 0.0
        if side <= margin_m:
            near += 1
            edge = e
    for e in range(lo, hi):
        if abs(coords[e, 0] - qx) <= 1e-12 and abs(coords[e, 1] - qy) <= 1e-12:
            prv = e - 1 if e > lo else hi - 1
            a0 = math.atan2(coords[e + 1, 1] - qy, coords[e + 1, 0] - qx)
            a1 = math.atan2(coords[prv, 1] - qy, coords[prv, 0] - qx)
            return 1, a0 % (2.0 * math.pi), (a1 - a0) % (2.0 * math.pi)
    if near == 1:
        a = math.atan2(coords[edge + 1, 1] - coords[edge, 1],
                       coords[edge + 1, 0] - coords[edge, 0])
        return 2, a % (2.0 * math.pi), math.pi
    return 3, 0.0, 0.0


@njit(cache=True)
def _covered(a: float, starts: np.ndarray, lengths: np.ndarray,
             n: int) -> bool:  # pragma: no cover - compiled
    for j in range(n):
        if (a - starts[j]) % (2.0 * math.pi) < lengths[j]:
            return True
    return False


@njit(cache=True)
def _joined_angle(starts: np.ndarray, lengths: np.ndarray,
                  n: int) -> float:  # pragma: no cover - compiled
    """The angle the ``n`` arcs (start, length) cover when they join into one; -1 when they
    leave two gaps or more, or none."""
    tau = 2.0 * math.pi
    gap = -1.0  # an angle no arc covers: just past the end of one of them
    for j in range(n):
        a = (starts[j] + lengths[j] + 1e-9) % tau
        if not _covered(a, starts, lengths, n):
            gap = a
            break
    if gap < 0.0:
        return -1.0
    rel = np.empty(n)
    for j in range(n):
        rel[j] = (starts[j] - gap) % tau
    order = np.argsort(rel)
    first = rel[order[0]]
    end = first + lengths[order[0]]
    for m in range(1, n):
        j = order[m]
        if rel[j] > end + 1e-12:
            return -1.0
        end = max(end, rel[j] + lengths[j])
    return float(end - first)


@njit(cache=True)
def corner_vertices(xy: np.ndarray, coords: np.ndarray, offsets: np.ndarray,
                    margin_m: float, min_angle_rad: float) -> np.ndarray:  # pragma: no cover
    """Whether each point ``(k, 2)`` is a vertex of the boundary of the union of convex
    rings: a vertex of one of them at least; the rings about it (within ``margin_m``:
    each having it as a vertex, or on an edge) cover one contiguous angle about it, at
    least ``min_angle_rad`` and short of the full turn by that much; no ring holds it
    inside.

    The rings are counter-clockwise and closed, as :func:`pair_hulls` gives them (ring
    ``i`` is rows ``offsets[i]`` to ``offsets[i + 1] - 1`` of ``coords``). A point near two
    edges of a ring without being its vertex, or about which the rings leave two gaps, is
    not taken for a corner.

    Examples
    --------
    Two unit squares side by side and a third on top of the first, an L: its outer
    corners, the point where two meet along its bottom edge and the inner corner where all
    three meet are vertices of the union; a point inside one square, or off them all, is
    not:

    >>> sq = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]])
    >>> rings = np.concatenate([sq, sq + [1.0, 0.0], sq + [0.0, 1.0]])
    >>> pts = np.array([[0.0, 0.0], [2.0, 1.0], [1.0, 0.0], [1.0, 1.0], [0.5, 0.5],
    ...                 [5.0, 5.0]])
    >>> corner_vertices(pts, rings, np.array([0, 5, 10, 15]), 1e-9, 0.1).tolist()
    [True, True, True, True, False, False]
    """
    out = np.zeros(xy.shape[0], dtype=np.bool_)
    nr = offsets.shape[0] - 1
    starts = np.empty(nr + 1)
    lengths = np.empty(nr + 1)
    for i in range(xy.shape[0]):
        n = 0
        vertices = 0
        clear = True
        for r in range(nr):
            kind, start, length = _sector(xy[i, 0], xy[i, 1], coords, offsets[r],
                                          offsets[r + 1] - 1, margin_m)
            if kind == 3:
                clear = False
                break
            if kind > 0:
                starts[n], lengths[n] = start, length
                vertices += kind == 1
                n += 1
        if not clear or vertices == 0:
            continue
        angle = _joined_angle(starts, lengths, n)
        out[i] = min_angle_rad <= angle <= 2.0 * math.pi - min_angle_rad
    return out
