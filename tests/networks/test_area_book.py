"""Areas built on demand per batch of curves, with a bound on the batches kept."""

from __future__ import annotations

import pytest
import shapely

from networks.area_book import AreaBook, _batches
from networks.areas import attach_areas
from networks.curves import extract_curves
from networks.reader import read_network
from networks.samples.sources import SAMPLES_DIR


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


