"""Refined swung paths: the knot profile, the compass moves, the lattice, the offset line."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clearance.analysis.polyline import prepare_path
from clearance.networks.driving.refine import (
    Knots,
    RefineSearch,
    compass_moves,
    knot_profile,
    lattice_knots,
    refined_candidate,
)

offsets = st.floats(-3.0, 6.0, allow_nan=False)
ramps = st.floats(2.0, 24.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(ramps, offsets, offsets, offsets, ramps, st.floats(0.15, 0.85))
def test_knot_profile_passes_its_knots_smoothly_and_is_zero_beyond_its_ramps(
        ramp_in, start, apex, end, ramp_out, at):
    s = np.arange(0.0, 100.01, 0.05)
    f0, f1 = 40.0, 52.0
    k = Knots(ramp_in, start, apex, end, ramp_out, at)
    d = knot_profile(s, (f0, f1), k)
    xs = [f0 - ramp_in, f0, f0 + at * (f1 - f0), f1, f1 + ramp_out]
    ys = [0.0, start, apex, end, 0.0]
    for x, y in zip(xs, ys, strict=True):  # through every knot
        assert d[int(round(x / 0.05))] == pytest.approx(y, abs=2e-3)
    assert np.all(d[s < xs[0] - 1e-9] == 0) and np.all(d[s > xs[-1] + 1e-9] == 0)
    # a half cosine from y0 to y1 over L rises at most (pi / 2) |y1 - y0| / L: no jump
    steepest = max(math.pi / 2 * abs(b - a) / (x1 - x0)
                   for a, b, x0, x1 in zip(ys, ys[1:], xs, xs[1:], strict=False))
    assert np.max(np.abs(np.diff(d))) <= steepest * 0.05 + 1e-9
    # between two knots it stays between their values
    for a, b, x0, x1 in zip(ys, ys[1:], xs, xs[1:], strict=False):
        seg = d[(s >= x0) & (s <= x1)]
        assert seg.min() >= min(a, b) - 1e-9 and seg.max() <= max(a, b) + 1e-9


def test_a_refined_line_on_an_arc_lies_at_its_offset_from_the_circle():
    # a right turn round a 20 m circle about the origin: the outside is away from the
    # centre, so a point offset by d lies at 20 + d from it (d < 0: inside)
    a = np.radians(np.linspace(90.0, 0.0, 91))
    arc = np.c_[20 * np.cos(a), 20 * np.sin(a)]
    p = prepare_path(np.vstack([[(-40.0, 20.0)], arc, [(20.0, -40.0)]]), spacing_m=0.25,
                     smooth=True)
    feature = (40.0, 40.0 + 10 * math.pi)  # the arc: 31.4 m
    k = Knots(8.0, 1.2, -0.8, 0.5, 8.0, 0.5)
    c = refined_candidate(p, feature, -90.0, k)
    assert c is not None and c.shape == "refined"
    mid = feature[0] + 0.5 * (feature[1] - feature[0])
    for station, d in ((feature[0] + 2.0, None), (mid, -0.8), (feature[1] - 2.0, None)):
        i = int(np.argmin(np.abs(p.station_m - station)))
        want = knot_profile(p.station_m, feature, k)[i] if d is None else d
        # the outside of a right turn is the left: along the left normal
        moved = p.xy[i] + want * np.array([-np.sin(p.heading_rad[i]), np.cos(p.heading_rad[i])])
        # the offset line passes through that point, and that point is 20 + d from the centre
        assert np.min(np.hypot(*(c.path.xy - moved).T)) < 0.15
        assert math.hypot(*moved) == pytest.approx(20.0 + want, abs=0.05)
    assert c.offset_m.min() == pytest.approx(-0.8, abs=1e-3)
    assert c.offset_m.max() == pytest.approx(1.2, abs=1e-3)


def test_a_line_folding_over_itself_is_left_out():
    a = np.radians(np.linspace(90.0, 0.0, 46))
    arc = np.c_[3 * np.cos(a), 3 * np.sin(a)]
    p = prepare_path(np.vstack([[(-30.0, 3.0)], arc, [(3.0, -30.0)]]), smooth=True)
    feature = (30.0, 30.0 + 1.5 * math.pi)
    # 3 m toward the inside of a 3 m corner puts the line through the corner's centre
    assert refined_candidate(p, feature, -90.0, Knots(6.0, 0.0, -3.0, 0.0, 6.0, 0.5)) is None
    assert refined_candidate(p, feature, -90.0, Knots(6.0, 0.0, 2.0, 0.0, 6.0, 0.5)) is not None


def test_compass_moves_change_one_number_by_one_step_within_the_bounds():
    r = RefineSearch()
    step = np.array(r.step.values()) / 2
    k = Knots(10.0, 5.8, 0.0, -2.9, 23.0, 0.8)
    moves = compass_moves(k, step, r)
    lo, hi = np.array(r.lower.values()), np.array(r.upper.values())
    assert len(moves) == len(set(moves)) == 12  # all inside the bounds: none cancelled
    for m in moves:
        delta = np.array(m.values()) - np.array(k.values())
        changed = np.flatnonzero(np.abs(delta) > 1e-12)
        assert len(changed) == 1
        j = int(changed[0])
        assert abs(delta[j]) <= step[j] + 1e-9
        assert np.all(np.array(m.values()) >= lo - 1e-12)
        assert np.all(np.array(m.values()) <= hi + 1e-12)
    # the moves past a bound are clipped to it (start 5.8 + 0.4 -> 6.0)
    assert Knots(10.0, 6.0, 0.0, -2.9, 23.0, 0.8) in moves


def test_the_lattice_follows_the_room_at_each_knot():
    r = RefineSearch()
    ks = lattice_knots((3.0, 0.1, 8.0), r)  # no room at the apex, more than the bound after
    assert len(ks) == 9
    assert {k.apex_m for k in ks} == {0.0}
    assert {k.start_m for k in ks} == {0.0, 1.5, 3.0}
    assert {k.end_m for k in ks} == {0.0, 3.0, 6.0}  # the bound, 6 m
    assert all(k.ramp_in_m == max(6.0, 4 * max(k.start_m, k.end_m)) for k in ks)


@pytest.mark.parametrize("bad", [dict(rounds=0), dict(starts=0),
                                 dict(step=Knots(4.0, 0.0, 0.8, 0.8, 4.0, 0.1))])
def test_a_refine_search_with_bad_bounds_is_refused(bad):
    with pytest.raises(ValueError, match="refine search"):
        RefineSearch(**bad)
