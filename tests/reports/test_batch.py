"""A batch as a worker runs it: one bad curve costs only its own runs, in both methods."""

from __future__ import annotations

import dataclasses
import hashlib

import numpy as np
import pytest

from clearance.networks.curves import extract_curves
from clearance.networks.reader import read_network
from clearance.networks.samples.build import sample_networks
from clearance.reports.study.batch import Batch, detached, run_batch, split_batch, worker_network
from clearance.vehicles.table import bundled_table_paths, load_tables

NET = next(p for p in sample_networks() if p.stem.startswith("intersection"))
SAMPLES = NET.parent.parent


@pytest.fixture(scope="module")
def setup():
    net = read_network(NET)
    curves = [detached(c) for c in extract_curves(net)[:4]]
    vehicles = tuple(load_tables(bundled_table_paths(), ["P", "CITY-BUS"]).vehicles())
    return net, curves, vehicles


def _folded(curve):
    """``curve`` with a centre line that turns back on itself halfway."""
    line = np.array(curve.centerline, dtype=float)
    mid = len(line) // 2
    line[mid + 1:, :2] = line[mid, :2] - (line[mid + 1:, :2] - line[mid, :2])
    out = dataclasses.replace(curve, centerline=line)
    out.set_areas(curve.own_lanes, curve.roadway, curve.paved)
    return out


@pytest.mark.parametrize("method", ["simulate", "analytic"])
def test_a_curve_that_turns_back_is_an_error_and_the_others_are_unchanged(setup, method):
    net, curves, vehicles = setup
    pairs = tuple((v, c) for c in curves for v in range(len(vehicles)))
    good = run_batch(Batch("x", 0, method, 0.0, vehicles, pairs), (str(NET), None))
    bad_curves = [curves[0], _folded(curves[1]), curves[2], curves[3]]
    bad_pairs = tuple((v, c) for c in bad_curves for v in range(len(vehicles)))
    got = run_batch(Batch("x", 0, method, 0.0, vehicles, bad_pairs), (str(NET), None))
    assert len(got) == len(good) == 4 * len(vehicles)
    for g, w in zip(got, good, strict=True):
        assert (g.curve_id, g.vehicle) == (w.curve_id, w.vehicle)
        if g.curve_id == curves[1].curve_id:
            assert g.verdict == "error"
            assert "turns back on itself" in g.reason
        else:
            assert (g.verdict, g.margin_m, g.reason) == (w.verdict, w.margin_m, w.reason)


def test_split_halves_keep_every_run_once(setup):
    _, curves, vehicles = setup
    pairs = tuple((v, c) for c in curves for v in range(len(vehicles)))
    batch = Batch("x", 3, "analytic", 0.0, vehicles, pairs)
    a, b = split_batch(batch)
    assert a.pairs + b.pairs == pairs and a.label == "x#3a" and b.label == "x#3b"
    assert split_batch(dataclasses.replace(batch, pairs=pairs[:1])) == []


def test_a_worker_without_the_file_writes_the_sent_bytes(tmp_path):
    data = NET.read_bytes()
    missing = tmp_path / "elsewhere" / NET.name
    net = worker_network((str(missing), data))
    assert hashlib.sha256(open(net.path, "rb").read()).digest() == hashlib.sha256(data).digest()
    assert net.path != str(missing) and len(net.lanes) == len(read_network(NET).lanes)


def test_a_worker_builds_the_areas_of_bare_curves_as_the_parent_does():
    """A batch sends curves without areas (bare); the worker's areas are the parent's, and
    so is every record, the conflict parts the exports draw included."""
    import pickle

    from clearance.reports.study.batch import bare, with_areas

    net = read_network(NET)
    parent = extract_curves(net)[:6]
    sent = [bare(c) for c in parent]
    assert all(c._own is None and c.area_book is None for c in sent)
    assert len(pickle.dumps(sent)) < len(pickle.dumps([detached(c) for c in parent]))
    with_areas(worker_network((str(NET), None)), sent)
    for p, s in zip(parent, sent, strict=True):
        for area in ("own_lanes", "roadway", "paved"):
            assert getattr(s, area).wkb == getattr(p, area).wkb, (p.curve_id, area)
    vehicles = tuple(load_tables(bundled_table_paths(), ["P"]).vehicles())
    shared = (str(NET), None)
    a = run_batch(Batch("x", 0, "simulate", 0.1, vehicles,
                        tuple((0, c) for c in map(bare, parent))), shared)
    b = run_batch(Batch("x", 0, "simulate", 0.1, vehicles,
                        tuple((0, detached(c)) for c in parent)), shared)
    assert [r.row() for r in a] == [r.row() for r in b]
    for ra, rb in zip(a, b, strict=True):
        assert ra.conflict is not None
        assert [g.wkb for g in ra.conflict] == [g.wkb for g in rb.conflict]


def test_a_worker_gives_bare_curves_of_a_garage_their_storeys():
    """On a network with storeys the worker builds each curve's levels as the parent's
    area book does: the same segments, the same storey areas; a flat network gets none."""
    from clearance.reports.study.batch import bare, with_areas

    helix = SAMPLES / "helix" / "helix.net.xml"
    net = read_network(helix)
    parent = [c for c in extract_curves(net) if c.kind == "ramp"]
    assert parent and all(len(c.levels) > 1 for c in parent)
    sent = [bare(c) for c in parent]
    with_areas(worker_network((str(helix), None)), sent)
    for p, s in zip(parent, sent, strict=True):
        assert [lv.z_m for lv in s.levels] == [lv.z_m for lv in p.levels], p.curve_id
        assert all(a.areas.own_lanes.wkb == b.areas.own_lanes.wkb
                   for a, b in zip(s.levels, p.levels, strict=True))
    flat = [bare(c) for c in extract_curves(read_network(NET))[:3]]
    with_areas(worker_network((str(NET), None)), flat)
    assert all(c.levels == () for c in flat)


def test_a_workers_network_is_kept_out_of_the_collectors_scans(tmp_path, monkeypatch):
    import gc
    import shutil

    from clearance.reports.study import lifetime

    # copies: the cache holds one network a process, and these must be read here
    here, there = tmp_path / "here", tmp_path / "there"
    for folder in (here, there):
        folder.mkdir()
        shutil.copy(NET, folder / NET.name)
    gc.unfreeze()
    # not in a worker (the command's own process, a test's): nothing frozen for good
    worker_network((str(here / NET.name), None))
    assert gc.get_freeze_count() == 0
    monkeypatch.setattr(lifetime, "_WORKER", True)
    try:
        net = worker_network((str(there / NET.name), None))
        # frozen: no full collection (a figure's gc.collect) scans it again ...
        assert gc.get_freeze_count() > 0
        assert not any(o is net or o is net.lanes for o in gc.get_objects())
        # ... and what comes after is collected as usual
        cycle: list = []
        cycle.append(cycle)
        del cycle
        assert gc.collect() >= 1
        assert worker_network((str(there / NET.name), None)) is net
    finally:
        gc.unfreeze()
