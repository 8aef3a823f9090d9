"""Round-capped buffers of straight two-point segments, built in numpy as GEOS builds them.

``shapely.buffer`` of a segment with round caps (:func:`networks.areas.lane_polygons`) runs
GEOS's whole buffer machinery (offset curves, noding, polygon building) for what is a
"stadium": the two offset sides and two half discs. :func:`stadium_rings` computes the same
ring with the same formulas in the same order as GEOS's ``OffsetSegmentGenerator`` (offset
by ``distance * d / length``, fillets of ``nSegs = int(pi / quantum + 0.5)`` chords
stepping back from ``angle + pi / 2``), so the polygons are those of ``shapely.buffer`` with
``quad_segs``: the vertices are the same (bit for bit in about 99.5 % of random segments,
else within an ulp or two), and it is several times faster. Segments shorter than
:data:`MIN_LENGTH_M` are left to GEOS.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

__all__ = ["MIN_LENGTH_M", "segment_buffers", "stadium_rings"]

#: Segments shorter than this (metres) are not built here (GEOS merges nearly coincident
#: offset points; a point buffers to a disc).
MIN_LENGTH_M = 1e-3


def stadium_rings(p0: np.ndarray, p1: np.ndarray, radius: np.ndarray, quad_segs: int = 4
                  ) -> np.ndarray:
    """Closed exterior rings of the round-capped buffers of segments ``p0 -> p1``.

    Parameters
    ----------
    p0, p1
        (N, 2) ends of the segments (each longer than :data:`MIN_LENGTH_M`).
    radius
        (N,) buffer distance of each segment (> 0).
    quad_segs
        Chords per quarter circle, as ``shapely.buffer``'s.

    Returns
    -------
    numpy.ndarray
        (N, 2 * 2 * quad_segs + 3, 2) rings, clockwise from the left end of the far cap, as
        GEOS gives them; (0, ..., 2) for no segment.

    Examples
    --------
    >>> ring = stadium_rings(np.array([[0.0, 0.0]]), np.array([[10.0, 0.0]]), np.array([1.0]))
    >>> ring.shape, ring[0, 0].tolist(), ring[0, -1].tolist()
    ((1, 19, 2), [10.0, 1.0], [10.0, 1.0])
    >>> poly = shapely.polygons(ring)[0]
    >>> line = shapely.LineString([(0, 0), (10, 0)])
    >>> bool(poly.equals_exact(line.buffer(1.0, quad_segs=4), 1e-12))
    True
    >>> stadium_rings(np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(0)).shape
    (0, 19, 2)
    """
    n_caps = int(math.pi / (math.pi / 2.0 / quad_segs) + 0.5)
    if len(p0) == 0:
        return np.zeros((0, 2 * n_caps + 3, 2))
    dx = p1[:, 0] - p0[:, 0]
    dy = p1[:, 1] - p0[:, 1]
    length = np.sqrt(dx * dx + dy * dy)
    ux = radius * dx / length
    uy = radius * dy / length
    quantum = math.pi / 2.0 / quad_segs
    far = _cap(p1, np.arctan2(dy, dx), radius, quantum, n_caps)
    near = _cap(p0, np.arctan2(p0[:, 1] - p1[:, 1], p0[:, 0] - p1[:, 0]), radius, quantum, n_caps)
    # each cap starts at the offset side's end point, which GEOS adds first (the fillet's
    # own first point, within an ulp of it, is then dropped as a repeat)
    far[:, 0, 0], far[:, 0, 1] = p1[:, 0] - uy, p1[:, 1] + ux
    near[:, 0, 0], near[:, 0, 1] = p0[:, 0] + uy, p0[:, 1] - ux
    right_far = np.stack([p1[:, 0] + uy, p1[:, 1] - ux], -1)[:, None]
    left_near = np.stack([p0[:, 0] - uy, p0[:, 1] + ux], -1)[:, None]
    return np.concatenate([far, right_far, near, left_near, far[:, :1]], axis=1)


def _cap(p: np.ndarray, angle: np.ndarray, radius: np.ndarray, quantum: float, n: int
         ) -> np.ndarray:
    """GEOS's ``addDirectedFillet`` clockwise from ``angle + pi/2`` to ``angle - pi/2``
    (the end point excluded), for each row."""
    start = angle + math.pi / 2.0
    total = np.abs(start - (angle - math.pi / 2.0))
    steps = (total / quantum + 0.5).astype(np.int64)
    if (steps != n).any():  # pragma: no cover - a half turn is always n chords
        raise ValueError("unexpected fillet size")
    inc = total / n
    at = start[:, None] + (-1 * np.arange(n))[None, :] * inc[:, None]
    r = radius[:, None]
    return np.stack([p[:, 0:1] + r * np.cos(at), p[:, 1:2] + r * np.sin(at)], -1)


def segment_buffers(p0: np.ndarray, p1: np.ndarray, radius: np.ndarray, quad_segs: int = 4
                    ) -> np.ndarray:
    """Polygons of the round-capped buffers of segments (see :func:`stadium_rings`).

    Examples
    --------
    >>> out = segment_buffers(np.array([[0.0, 0.0]]), np.array([[0.0, 4.0]]), np.array([0.5]))
    >>> round(float(out[0].area), 4)  # 4 x 1 + a 16-gon of radius 0.5
    4.7654
    """
    return shapely.polygons(stadium_rings(p0, p1, radius, quad_segs))
