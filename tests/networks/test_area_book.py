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


def test_read_in_order_the_worker_starts_on_the_next_batch_and_a_jump_drops_it(monkeypatch):
    from networks import area_worker, areas

    net = _net("roundabout")
    curves = extract_curves(net)
    eager = extract_curves(net, areas=False)
    attach_areas(net, eager)
    monkeypatch.setattr(areas, "HALVES_MIN", 2)
    monkeypatch.setattr(areas, "WORKERS", 2)
    monkeypatch.setenv("CLEARANCE_PROCESS", "1")
    monkeypatch.setattr(area_worker, "SHARE_GAIN", 0.0)  # the cuts stay where they are
    # a job counts as unanswered until its answer is read (not when it arrives, which
    # depends on timing): at most two are queued
    monkeypatch.setattr(area_worker.AreaWorker, "backlog", lambda w: w._sent - w._taken)
    book = AreaBook(net, curves, batch_curves=6, max_batches=2)
    b = book.batches
    split = [i for i, batch in enumerate(b) if areas._halfway(batch, 0.5)]
    assert split == [0, 1, 2, 3]  # four batches, each in two parts
    sent: list[int] = []
    queue = area_worker._queue

    def record(helper, index, run, **kw):
        sent.append(next(i for i, batch in enumerate(b) if batch is run))
        return queue(helper, index, run, **kw)

    monkeypatch.setattr(area_worker, "_queue", record)
    area_worker.stop()

    book.load(0)  # batch 0's part sent, and batch 1's queued behind it (two at most)
    assert sent == [0, 1]
    book.load(1)  # batch 1's part was already there; batch 2's queued
    assert sent == [0, 1, 2]
    book.load(3)  # a jump: batch 2's answer is read and dropped, batch 3's part sent
    assert sent == [0, 1, 2, 3]
    helper = area_worker.worker()
    assert helper is not None and not helper.inflight  # still in use, nothing queued
    for c, e in zip(curves, eager, strict=True):
        if c.area_batch in book.held():
            for mine, theirs in ((c.own_lanes, e.own_lanes), (c.roadway, e.roadway),
                                 (c.paved, e.paved)):
                assert shapely.to_wkb(mine) == shapely.to_wkb(theirs), c.curve_id
    book.load(2)  # read out of order: sent now, nothing queued behind it
    assert sent == [0, 1, 2, 3, 2]
    book.load(3)  # in order again, but batch 3 is the last: nothing to queue
    assert sent == [0, 1, 2, 3, 2, 3]
    book.load(0)  # a jump back: nothing queued
    book.load(1)  # in order: batch 2's part queued, in flight when the worker is stopped
    assert sent == [0, 1, 2, 3, 2, 3, 0, 1, 2] and len(helper.inflight) == 1
    area_worker.stop()  # (at once: nobody will read that answer)
    assert area_worker._WORKER is None and helper.proc.poll() is not None


def _curve_values(c) -> tuple:
    return (c.curve_id, c.kind, c.junction, c.lanes, c.core_lanes, c.centerline.tobytes(),
            c.core_start_m, c.core_end_m, c.profile_radius_m.tobytes(), c.min_radius_m,
            c.turn_angle_deg, c.length_m, c.lane_width_m, c.max_grade_pct,
            c.max_grade_change_pct)


@pytest.mark.parametrize("process", ["1", "0"])
def test_areas_built_ahead_while_extracting_are_the_same_and_are_used(
    monkeypatch, process, small_grid
):
    from networks import area_book, area_worker, areas
    from networks import curves as curves_module

    monkeypatch.setattr(area_book, "BATCH_CURVES", 40)
    monkeypatch.setattr(curves_module, "MEASURE_BATCH", 30)
    net = read_network(small_grid)
    plain = extract_curves(net, areas=False)
    attach_areas(net, plain)
    monkeypatch.setattr(areas, "HALVES_MIN", 2)
    monkeypatch.setattr(areas, "WORKERS", 2)
    monkeypatch.setenv("CLEARANCE_PROCESS", process)
    # a job counts as unanswered until its answer is read (not when it arrives, which
    # depends on timing): at most two are sent while the curves are extracted
    monkeypatch.setattr(area_worker.AreaWorker, "backlog", lambda w: w._sent - w._taken)
    sent: list = []
    queue = area_worker._queue
    monkeypatch.setattr(area_worker, "_queue", lambda helper, index, run, **kw: (
        sent.append(run) or queue(helper, index, run, **kw)))
    area_worker.stop()
    ahead = extract_curves(net, build_ahead=True)
    during = len(sent)
    book = ahead[0].area_book
    assert len(book.batches) >= 4
    # the same curves, in the same order, with the same areas
    assert [_curve_values(c) for c in ahead] == [_curve_values(c) for c in plain]
    for c, e in zip(ahead, plain, strict=True):
        for mine, theirs in ((c.own_lanes, e.own_lanes), (c.roadway, e.roadway),
                             (c.paved, e.paved)):
            assert shapely.to_wkb(mine) == shapely.to_wkb(theirs), c.curve_id
    if process == "0":
        assert not sent
        return
    assert during == 2  # the first two batches' parts went out while extracting
    # every batch's part was sent once, in order: those sent ahead were used, not dropped
    at = [next(i for i, b in enumerate(book.batches) if list(b) == list(run)) for run in sent]
    assert at == list(range(len(book.batches)))
    area_worker.stop()


def test_a_worker_that_dies_with_batches_sent_ahead_costs_no_area(monkeypatch, small_grid):
    from networks import area_book, area_worker, areas
    from networks import curves as curves_module

    monkeypatch.setattr(area_book, "BATCH_CURVES", 40)
    monkeypatch.setattr(curves_module, "MEASURE_BATCH", 30)
    monkeypatch.setattr(areas, "HALVES_MIN", 2)
    monkeypatch.setattr(areas, "WORKERS", 2)
    monkeypatch.setenv("CLEARANCE_PROCESS", "1")
    monkeypatch.setattr(area_worker, "QUEUED_PARTS", 10)
    monkeypatch.setattr(area_worker, "MAX_INFLIGHT", 3)  # at most three answers waiting
    net = read_network(small_grid)
    plain = extract_curves(net, areas=False)
    attach_areas(net, plain)
    area_worker.stop()
    ahead = extract_curves(net, build_ahead=True)
    helper = area_worker.worker()
    assert helper is not None and len(helper.inflight) == 3
    helper.proc.kill()  # dies with three parts sent ahead
    helper.proc.wait()
    for c, e in zip(ahead, plain, strict=True):
        for mine, theirs in ((c.own_lanes, e.own_lanes), (c.roadway, e.roadway),
                             (c.paved, e.paved)):
            assert shapely.to_wkb(mine) == shapely.to_wkb(theirs), c.curve_id
    assert area_worker.worker() is None  # given up on
    area_worker.stop()


def test_building_ahead_on_a_small_network_starts_no_worker(monkeypatch):
    from networks import area_worker, areas

    monkeypatch.setattr(areas, "WORKERS", 2)
    monkeypatch.setenv("CLEARANCE_PROCESS", "1")
    area_worker.stop()
    curves = extract_curves(_net("roundabout"), build_ahead=True)  # no batch to send
    assert area_worker._WORKER is None
    assert all(c.paved is not None for c in curves) and area_worker._WORKER is None
