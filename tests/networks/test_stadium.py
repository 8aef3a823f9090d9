"""Round-capped segment buffers built in numpy equal GEOS's."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from networks.areas import lane_polygons
from networks.reader import Lane, Location, Network
from networks.stadium import segment_buffers, stadium_rings


def _geos(p0, p1, r, quad_segs=4):
    lines = shapely.linestrings(np.stack([p0, p1], axis=1))
    return shapely.buffer(lines, r, cap_style="round", join_style="round", quad_segs=quad_segs)


@pytest.mark.parametrize("quad_segs", [4, 8])
def test_stadiums_equal_geos_buffers(quad_segs):
    rng = np.random.default_rng(7)
    n = 5000
    p0 = rng.uniform(-20000, 20000, (n, 2))
    p1 = p0 + rng.uniform(-150, 150, (n, 2))
    p1[:50, 0] = p0[:50, 0]  # vertical, horizontal, both directions
    p1[50:100, 1] = p0[50:100, 1]
    r = rng.uniform(0.2, 3.0, n)
    ours = stadium_rings(p0, p1, r, quad_segs)
    theirs = shapely.get_coordinates(_geos(p0, p1, r, quad_segs)).reshape(ours.shape)
    exact = (ours == theirs).all(axis=(1, 2))
    assert exact.mean() > 0.95  # the same formulas in the same order
    scale = np.maximum(np.abs(theirs), 1.0)
    assert (np.abs(ours - theirs) <= 4 * np.finfo(float).eps * scale).all()
    polys = segment_buffers(p0, p1, r, quad_segs)
    assert shapely.is_valid(polys).all()
    assert np.allclose(shapely.area(polys), shapely.area(_geos(p0, p1, r, quad_segs)), rtol=1e-13)


def test_lane_polygons_keep_geos_for_bent_and_degenerate_lanes():
    def lane(k, pts):
        shape = np.array([[x, y, 0.0] for x, y in pts])
        return Lane(k, "e", 0, 3.0, "normal", frozenset(), shape, 10.0, 13.9)

    lanes = {
        "straight": lane("straight", [(0, 0), (10, 0)]),
        "bent": lane("bent", [(0, 10), (10, 10), (10, 20)]),
        "point": lane("point", [(5, 5), (5, 5)]),
    }
    net = Network(None, lanes, {}, [], {}, [], Location())
    ids = list(lanes)
    ours = lane_polygons(net, ids, "round", grow_m=1e-3)
    lines = [shapely.LineString(lanes[k].shape[:, :2]) for k in ids]
    theirs = shapely.buffer(lines, 1.501, cap_style="round", join_style="round", quad_segs=4)
    assert shapely.equals_exact(ours, theirs, 1e-12).all()
    assert shapely.to_wkb(ours[1]) == shapely.to_wkb(theirs[1])  # GEOS's own
    assert shapely.to_wkb(ours[2]) == shapely.to_wkb(theirs[2])
    flat = lane_polygons(net, ids)  # flat ends: all by GEOS
    assert shapely.equals_exact(flat, shapely.buffer(lines, 1.5, cap_style="flat",
                                                      join_style="round", quad_segs=4), 0).all()
