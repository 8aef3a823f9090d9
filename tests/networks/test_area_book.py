"""Areas built on demand per batch of curves, with a bound on the batches kept."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from clearance.networks.area_book import AreaBook, _batches
from clearance.networks.areas import attach_areas
from clearance.networks.curves import extract_curves
from clearance.networks.reader import read_network
from clearance.networks.samples.sources import SAMPLES_DIR


def _net(name: str):
    return read_network(SAMPLES_DIR / name / f"{name}.net.xml")


def _same(a, b) -> bool:
    return shapely.symmetric_difference(a, b).area <= 1e-9


def test_no_area_is_built_before_it_is_read():
    curves = extract_curves(_net("intersection"))
    book = curves[0].area_book
    assert book is not None and book.built == 0 and book.held() == []
    assert all(c.area_book is book for c in curves)
    assert curves[-1].roadway is not None and book.built == 1


def test_lazy_areas_equal_the_areas_built_at_once():
    net = _net("roundabout")
    lazy = extract_curves(net)
    eager = extract_curves(net, areas=False)
    attach_areas(net, eager)
    assert all(c.area_book is None for c in eager)
    for a, b in zip(lazy, eager, strict=True):
        assert a.curve_id == b.curve_id
        assert _same(a.own_lanes, b.own_lanes) and _same(a.roadway, b.roadway)
        assert _same(a.paved, b.paved), a.curve_id


def test_at_most_max_batches_are_kept_and_released_ones_come_back_the_same():
    net = _net("roundabout")
    curves = extract_curves(net)
    book = AreaBook(net, curves, batch_curves=4, max_batches=2)
    assert len(book.batches) > 3
    first = curves[0].paved
    wkb = shapely.to_wkb(first)
    for c in curves:
        assert c.own_lanes is not None and c.roadway is not None and c.paved is not None
        assert len(book.held()) <= 2
        kept = sum(x._paved is not None for x in curves)
        assert kept <= sum(len(book.batches[b]) for b in book.held())
    assert book.built == len(book.batches)  # a sweep in order builds each batch once
    assert curves[0]._paved is None  # released ...
    again = curves[0].paved  # ... and built again when read, the same geometry
    assert book.built == len(book.batches) + 1 and again is not first
    assert shapely.to_wkb(again) == wkb
    book.release()
    assert book.held() == [] and all(c._own is None for c in curves)


def test_areas_set_for_good_are_not_released():
    net = _net("intersection")
    curves = extract_curves(net)
    book = AreaBook(net, curves, batch_curves=1, max_batches=1)
    box = shapely.box(0, 0, 1, 1)
    curves[0].set_areas(box, box, box)
    for c in curves[1:]:
        assert c.paved is not None
    assert curves[0].paved is box and curves[0].area_book is None
    assert len(book.held()) == 1 and book.built >= len(book.batches) - 1


def test_an_area_does_not_depend_on_the_batch_that_builds_it():
    net = _net("roundabout")
    small = extract_curves(net)
    AreaBook(net, small, batch_curves=1, max_batches=1)
    whole = extract_curves(net)
    AreaBook(net, whole, batch_curves=10_000)
    for a, b in zip(small, whole, strict=True):
        for name in ("own_lanes", "roadway", "paved"):
            assert shapely.to_wkb(getattr(a, name)) == shapely.to_wkb(getattr(b, name))


def test_curves_without_areas_have_no_book():
    curves = extract_curves(_net("intersection"), areas=False)
    assert all(c.area_book is None and c.own_lanes is None for c in curves)


def test_batches_do_not_split_a_junction():
    curves = extract_curves(_net("intersection"), areas=False)
    batches = _batches(curves, 3)
    assert [c for b in batches for c in b] == curves
    seen: set[str] = set()
    for b in batches:
        js = {c.junction for c in b}
        assert not js & seen
        seen |= js
    with pytest.raises(ValueError):
        AreaBook(None, curves, batch_curves=0)


def _curve_values(c) -> tuple:
    return (c.curve_id, c.kind, c.junction, c.lanes, c.core_lanes, c.centerline.tobytes(),
            c.core_start_m, c.core_end_m, c.profile_radius_m.tobytes(), c.min_radius_m,
            c.turn_angle_deg, c.length_m, c.lane_width_m, c.max_grade_pct,
            c.max_grade_change_pct)




# --------------------------------------------------------------------------- levels

def _curve(net, curve_id: str, approach_m: float = 30.0):
    from clearance.networks.curves import CurveOptions

    curves = extract_curves(net, options=CurveOptions(approach_length_m=approach_m))
    (c,) = [c for c in curves if c.curve_id == curve_id]
    return c


def test_flat_networks_have_no_levels_and_3d_samples_do():
    from clearance.networks.area_book import network_is_flat

    for name in ("intersection", "roundabout"):
        net = _net(name)
        assert network_is_flat(net)
        assert all(c.levels == () for c in extract_curves(net))
    for name in ("parking_ramp", "helix", "garage"):
        net = _net(name)
        assert not network_is_flat(net)
        ramps = [c for c in extract_curves(net) if c.kind == "ramp"]
        assert ramps and all(len(c.levels) >= 3 for c in ramps), name


def test_no_part_of_a_helix_level_lies_a_storey_above_or_below():
    from clearance.analysis.levels import LEVEL_BAND_M, band_pieces
    from clearance.networks.area_groups import AreaIndex

    net = _net("helix")
    ramp = _curve(net, "ramp:helix_0->helix_0")
    levels = ramp.levels
    assert len(levels) == 10  # 9.6 m of rise in slots of 1 m
    # the helix lane's last straight (9.6 m up) runs out over the first turn's start: in
    # plan its part that lies over nothing of the lowest storey is paved, on the lowest
    # storey it is not (the top storey's last turn lies on the first turn in plan)
    helix = net.lanes["helix_0"].shape
    (top,) = band_pieces(helix, 9.0, 10.0)
    (low,) = band_pieces(helix, -1.0, 2.5)
    top_fp = shapely.buffer(shapely.LineString(top), 1.75)
    low_fp = shapely.buffer(shapely.LineString(low), 1.75)
    assert shapely.intersection(top_fp, low_fp).area > 5.0  # they overlap in plan
    only_top = shapely.difference(top_fp, shapely.buffer(low_fp, 1.0))
    assert only_top.area > 20.0 and ramp.paved.covers(only_top)
    assert levels[0].areas.paved.intersection(only_top).area < 1e-6
    assert levels[-1].areas.paved.covers(only_top)
    assert levels[0].areas.paved.covers(shapely.buffer(shapely.LineString(low[:20]), 1.5))
    # each middle storey's own lanes are 3 m of height of the helix (3 / 3.2 of a turn of
    # a 3.5 m lane): the plan's ring but for a gap of 0.2 / 3.2 of a turn
    turn_area = 2 * np.pi * 9.0 * 3.5
    ring = shapely.Point(0.0, 0.0).buffer(10.75, quad_segs=64).difference(
        shapely.Point(0.0, 0.0).buffer(7.25, quad_segs=64))
    assert ramp.own_lanes.covers(ring.buffer(-0.05))
    for lv in levels[2:-2]:
        own = lv.areas.own_lanes
        assert own.area == pytest.approx(turn_area * 2 * LEVEL_BAND_M / 3.2, rel=0.03)
        assert ring.difference(own).area == pytest.approx(turn_area * 0.2 / 3.2, rel=0.1)
    # and built from the members of the plan areas
    assert AreaIndex(net).plain_edges(ramp.lanes) == ("approach", "helix", "exit")


def test_level_swept_width_on_the_helix_is_one_passage_against_the_closed_form():
    # issue 17: P's swept width on the helix (radius 9 m, 3.5 m lane, 3.2 m per turn) was
    # the plan view's union of the turns and the exit above the first turn (about 7 m);
    # one passage sweeps the steady-state safe pathway at the centre line's radius
    import dataclasses
    import math

    from clearance.analysis.clearance import evaluate
    from clearance.analysis.control_law import safe_pathway
    from clearance.networks.driving.drive import DriveOptions, drive
    from clearance.networks.driving.runs import curve_areas
    from clearance.vehicles.table import bundled_table, load_tables

    net = _net("helix")
    ramp = _curve(net, "ramp:helix_0->helix_0")
    p = load_tables([bundled_table("aashto_green_book")], ["P"]).vehicle("P")
    (d,) = drive(net, [(p, ramp)], options=DriveOptions(use_sumo=False, swing=False))
    rho = math.sqrt(9.0**2 - p.wheelbase_m**2)
    closed = float(safe_pathway(rho, p.wheelbase_m, p.width_m, p.front_overhang_m))
    assert closed == pytest.approx(3.06, abs=0.01)
    # within 0.05 m (1.6 %): SUMO's chords and the smoothed path's radius differ a little
    # from 9 m, and the widths are sampled every 0.5 m
    assert d.result.swept.max_swept_width_m == pytest.approx(closed, abs=0.05)
    widths = d.result.swept.swept_width_m
    assert widths[:, 0].min() >= ramp.core_start_m - 1e-6
    assert widths[:, 0].max() <= ramp.core_end_m + 1e-6
    middle = widths[(widths[:, 0] > 80.0) & (widths[:, 0] < 180.0), 1]
    assert np.median(middle) == pytest.approx(closed, abs=0.03)
    # judged in plan, the same run's widths overlap the other turns and the exit
    areas = curve_areas(ramp)
    plan = evaluate(d.run, dataclasses.replace(areas, levels=()),
                    feature_m=(ramp.core_start_m, ramp.core_end_m))
    assert plan.swept.max_swept_width_m > 6.0
    assert plan.verdict == d.result.verdict  # the turns lie on each other: same verdict


def test_the_garage_ramp_is_clear_in_plan_and_fails_by_level_for_the_p():
    # the P, following its lane, offtracks inward round the tight upper corner (radius
    # 6.6 m, z about 2.9 m) by about 0.13 m beyond its lane; in plan the ramp's own wide
    # bend on the lower floor (z about 0.4 m) lies under the inside of that corner, so the
    # plan areas hold the offtracking (the swung path the study then finds is clear by
    # level too: a driver swings wide in the 3.5 m lane)
    import dataclasses

    from clearance.analysis.clearance import evaluate
    from clearance.networks.driving.drive import DriveOptions, drive
    from clearance.networks.driving.runs import curve_areas
    from clearance.vehicles.table import bundled_table, load_tables

    net = _net("garage")
    ramp = _curve(net, "ramp:ramp_in_0->ramp_down_0")
    p = load_tables([bundled_table("aashto_green_book")], ["P"]).vehicle("P")
    (d,) = drive(net, [(p, ramp)], options=DriveOptions(use_sumo=False, swing=False))
    feature = (ramp.core_start_m, ramp.core_end_m)
    plan = evaluate(d.run, dataclasses.replace(curve_areas(ramp), levels=()), feature_m=feature)
    assert plan.verdict == "clear" and plan.margin_m > 0.05
    by_level = d.result
    assert by_level.verdict == "fails"
    assert by_level.clearance.paved_margin_m == pytest.approx(-0.13, abs=0.03)
    reason = by_level.clearance.reason
    assert "leaves the paved area" in reason and "on the level at 2.5 m" in reason
    # where it fails: the inside of the upper corner (radius 6.6 m about (-30, -6.6), its
    # lane's inner edge at 4.85 m), over the lower bend's lane: paved in plan, not on that
    # level
    inside = shapely.Point(-30.0, -6.6).buffer(6.6 - 1.75, quad_segs=32)
    hit = shapely.intersection(by_level.measured, inside)
    assert hit.area > 0.05
    upper = [lv for lv in curve_areas(ramp).levels if lv.z_m == pytest.approx(2.5, abs=0.6)]
    assert upper and all(lv.areas.paved.intersection(hit).area < 0.1 * hit.area for lv in upper)
    assert curve_areas(ramp).own_lanes.covers(hit)  # the plan's own lanes: the lower bend
