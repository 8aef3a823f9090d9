"""Areas of curves: nesting, sealed joins, shared results."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from networks.areas import MIN_HOLE_M2, _fill_small_holes, _union_rows, attach_areas
from networks.curves import extract_curves
from networks.reader import read_network


def _wkb(parts) -> list[list[bytes]]:
    """Areas (arrays of geometries, e.g. own lanes, roadway, paved) as WKB, to compare
    them byte for byte."""
    return [[shapely.to_wkb(g) for g in part] for part in parts]


def _intersection_job():
    """The intersection sample's areas as one job (all its curves)."""
    from networks.area_groups import AreaIndex, BatchPlan
    from networks.areas import make_job
    from networks.samples.sources import SAMPLES_DIR

    net = read_network(SAMPLES_DIR / "intersection" / "intersection.net.xml")
    curves = extract_curves(net, areas=False)
    plan = BatchPlan(AreaIndex(net))
    for c in curves:
        plan.add(c)
    return make_job(plan, curves)


def test_union_rows_skip_missing_geometry():
    g = np.array([shapely.box(0, 0, 1, 1), None, shapely.box(1, 0, 2, 1)], dtype=object)
    out = _union_rows([[0, 1, 2], [1], [0, 1]], g)
    assert [round(x.area, 9) for x in out] == [2.0, 0.0, 1.0]


def test_small_holes_are_filled_islands_kept():
    square = shapely.box(0, 0, 20, 20)
    wedge = shapely.box(5, 5, 5.5, 5.5)  # 0.25 m2: a gap between lane pieces
    island = shapely.box(10, 10, 14, 14)  # 16 m2: a traffic island
    area = square.difference(wedge).difference(island)
    filled = _fill_small_holes(area)
    assert filled.area == 400 - 16 and 0.25 < MIN_HOLE_M2 < 16


def test_kinked_lanes_leave_no_gap_and_areas_nest(build_net):
    # two one-lane edges meeting at 30 degrees, and a side road making a junction
    a = math.radians(30)
    nodes = (
        '<node id="A" x="-60" y="0"/><node id="B" x="0" y="0" type="priority"/>'
        f'<node id="C" x="{60 * math.cos(a):.3f}" y="{60 * math.sin(a):.3f}"/>'
        '<node id="D" x="0" y="-60"/>'
    )
    edges = (
        '<edge id="AB" from="A" to="B" numLanes="1"/><edge id="BC" from="B" to="C" numLanes="1"/>'
        '<edge id="DB" from="D" to="B" numLanes="1"/><edge id="BA" from="B" to="A" numLanes="1"/>'
    )
    net = read_network(build_net(nodes, edges))
    curves = extract_curves(net, ["turn"], areas=False)
    assert all(c.own_lanes is None for c in curves)
    attach_areas(net, curves)
    for c in curves:
        assert c.own_lanes.difference(c.paved).area < 1e-3, c.curve_id
        assert c.roadway.difference(c.paved).area < 1e-6, c.curve_id
        assert shapely.covers(c.paved, shapely.LineString(c.centerline[:, :2]).buffer(0.5))
    # the turns at B that share a roadway (and whose own lanes it covers) share one
    # paved area: it is the junction's grown by that roadway
    at_b = [c for c in curves if c.junction == "B"]
    assert len(at_b) >= 3
    by_road: dict[int, set[int]] = {}
    for c in at_b:
        by_road.setdefault(id(c.roadway), set()).add(id(c.paved))
    assert all(len(p) == 1 for p in by_road.values()) or len(at_b) == len(
        {id(c.paved) for c in at_b})
    # every one of them holds the junction's polygon
    polygon = shapely.Polygon(net.junctions["B"].shape[:, :2])
    assert all(polygon.difference(c.paved).area < 1e-6 for c in at_b)


def test_threaded_calls_equal_one_call_in_any_thread(monkeypatch):
    from networks import areas

    pts = shapely.points(np.arange(1000.0), np.zeros(1000))
    radii = np.linspace(0.5, 2.0, 1000)
    whole = shapely.buffer(pts, radii)
    monkeypatch.setattr(areas, "WORKERS", 2)
    monkeypatch.setattr(areas, "MIN_SPLIT", 8)
    split = areas._threaded(shapely.buffer, pts, radii)
    inside = areas._pool().submit(areas._threaded, shapely.buffer, pts, radii).result()
    for out in (split, inside):
        assert len(out) == 1000 and shapely.equals_exact(out, whole, 0).all()


@pytest.mark.parametrize("process", ["0", "1"])
@pytest.mark.parametrize("halves_min", [4, 10**9])
def test_areas_built_in_parts_equal_those_built_alone(monkeypatch, halves_min, process):
    from networks import area_worker, areas
    from networks.area_groups import AreaIndex
    from networks.samples.sources import SAMPLES_DIR

    net = read_network(SAMPLES_DIR / "roundabout" / "roundabout.net.xml")
    curves = extract_curves(net, areas=False)
    monkeypatch.setattr(areas, "HALVES_MIN", halves_min)
    monkeypatch.setenv("CLEARANCE_PROCESS", process)
    parts = []
    build = areas._build
    monkeypatch.setattr(areas, "_build", lambda i, c: parts.append(len(c)) or build(i, c))
    sent = []
    send = area_worker.AreaWorker.send
    monkeypatch.setattr(area_worker.AreaWorker, "send", lambda w, j: sent.append(j) or send(w, j))
    built = {}
    for workers in (1, 2):
        monkeypatch.setattr(areas, "WORKERS", workers)
        built[workers] = areas.build_areas(AreaIndex(net), curves)
    if halves_min > len(curves):
        assert parts[1:] == [len(curves)] and not sent
    elif process == "1":  # the second part went to the worker process
        cut = areas._halfway(curves, 1.0 - area_worker.PROCESS_SHARE)
        assert parts[1:] == [cut] and len(sent) == 1
        assert len(sent[0].own_counts) == len(curves) - cut
    else:
        half = areas._halfway(curves)
        assert sorted(parts[1:]) == sorted([half, len(curves) - half]) and not sent
    assert _wkb(built[1]) == _wkb(built[2])


def test_a_worker_that_fails_costs_time_never_an_area(monkeypatch):
    from networks import area_worker, areas
    from networks.area_groups import AreaIndex
    from networks.samples.sources import SAMPLES_DIR

    net = read_network(SAMPLES_DIR / "roundabout" / "roundabout.net.xml")
    curves = extract_curves(net, areas=False)
    monkeypatch.setattr(areas, "HALVES_MIN", 4)
    monkeypatch.setattr(areas, "WORKERS", 1)
    alone = areas.build_areas(AreaIndex(net), curves)
    monkeypatch.setattr(areas, "WORKERS", 2)
    monkeypatch.setenv("CLEARANCE_PROCESS", "1")
    area_worker.stop()
    helper = area_worker.worker()
    assert helper is not None
    helper.proc.kill()  # dies before it gets the job
    helper.proc.wait()
    again = areas.build_areas(AreaIndex(net), curves)
    assert area_worker.worker() is None  # given up on, for good ...
    assert _wkb(alone) == _wkb(again)  # ... and the areas are all there
    area_worker.stop()
    assert area_worker.worker() is not None  # a new one after an explicit stop


def test_the_worker_answers_a_bad_job_with_an_empty_message_and_goes_on():
    import io
    import pickle

    from networks import area_worker
    from networks.areas import run_job

    job = _intersection_job()
    inp = io.BytesIO()
    area_worker._write(inp, pickle.dumps("not a job"))
    area_worker._write(inp, pickle.dumps(job))
    inp.seek(0)
    out = io.BytesIO()
    assert area_worker.serve(inp, out) == 0
    out.seek(0)
    assert area_worker._read(out) == b""
    *wkb, (run_s, idle_s) = pickle.loads(area_worker._read(out))
    answer = [shapely.from_wkb(x) for x in wkb]
    assert len(answer) == 3 and _wkb(run_job(job)) == _wkb(answer)
    assert run_s > 0 and idle_s >= 0  # how long it built, how long it waited for the job
    assert area_worker._read(out) is None


def test_junction_polygons_at_once_equal_one_by_one():
    from networks.areas import SEAL_M, junction_polygons
    from networks.samples.sources import SAMPLES_DIR

    net = read_network(SAMPLES_DIR / "roundabout" / "roundabout.net.xml")
    ids = list(net.junctions)
    out = junction_polygons(net, ids)
    for j, poly in zip(ids, out, strict=True):
        shape = net.junctions[j].shape
        if len(shape) < 3:
            assert poly is None
            continue
        one = shapely.make_valid(shapely.Polygon(shape[:, :2]))
        one = shapely.buffer(one, SEAL_M, quad_segs=1, join_style="mitre")
        assert shapely.to_wkb(poly) == shapely.to_wkb(one), j
    assert len(junction_polygons(net, [])) == 0


def test_rows_sharing_their_first_two_entries_union_them_once(monkeypatch):
    from networks import areas

    g = np.array([shapely.box(0, 0, 2, 1), shapely.box(1, 0, 3, 1), shapely.box(2, 0, 4, 2)])
    calls = []
    union = shapely.union
    monkeypatch.setattr(areas.shapely, "union", lambda a, b: calls.append(len(a)) or union(a, b))
    out = _union_rows([[0, 1, 2], [0, 1, 2], [1, 0, 2], [0, 1, 0]], g, seal=False)
    assert [round(float(a.area), 9) for a in out] == [6.0, 6.0, 6.0, 3.0]
    assert calls[0] == 2  # (0, 1) and (1, 0): two first unions for four rows
    assert shapely.to_wkb(out[0]) == shapely.to_wkb(out[1])


@pytest.mark.parametrize("workers", [2, 3])
def test_threaded_never_cuts_a_run_of_equal_labels(monkeypatch, workers):
    from networks import areas

    monkeypatch.setattr(areas, "WORKERS", workers)
    monkeypatch.setattr(areas, "MIN_SPLIT", 2)
    labels = np.repeat(np.arange(7), [5, 1, 9, 2, 2, 8, 3])
    seen = []

    def record(x):
        seen.append(x.copy())
        return x * 10

    out = areas._threaded(record, labels, runs=labels)
    assert (out == labels * 10).all()
    assert len(seen) > 1  # split ...
    for s in seen:  # ... but no label in two slices
        assert all(not set(s.tolist()) & set(o.tolist()) for o in seen if o is not s)
    one_run = np.zeros(40, dtype=int)
    seen.clear()
    assert (areas._threaded(record, one_run, runs=one_run) == 0).all() and len(seen) == 1


def test_what_a_job_prints_does_not_reach_the_answers():
    import os
    import subprocess
    import sys
    from pathlib import Path

    from networks import area_worker
    from networks.areas import run_job

    job = _intersection_job()
    code = (  # a worker whose every job prints, at Python and at C level, to stdout
        "import os, sys\n"
        "from networks import area_worker\n"
        "run = area_worker.run_job\n"
        "def noisy(job):\n"
        "    print('a stray print'); sys.stdout.flush(); os.write(1, b'a stray write')\n"
        "    return run(job)\n"
        "area_worker.run_job = noisy\n"
        "sys.exit(area_worker.main())\n"
    )
    env = dict(os.environ, PYTHONPATH=str(Path(area_worker.__file__).resolve().parents[1]))
    proc = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env)
    helper = area_worker.AreaWorker(proc)
    assert helper.send(job)
    got = helper.receive()
    helper.stop()
    assert b"a stray print" in proc.stderr.read()
    assert got is not None and _wkb(run_job(job)) == _wkb(got)


def test_threads_building_areas_at_once_share_the_worker_safely(monkeypatch):
    from concurrent.futures import ThreadPoolExecutor

    from networks import area_worker, areas
    from networks.area_groups import AreaIndex
    from networks.samples.sources import SAMPLES_DIR

    net = read_network(SAMPLES_DIR / "roundabout" / "roundabout.net.xml")
    curves = extract_curves(net, areas=False)
    monkeypatch.setattr(areas, "HALVES_MIN", 4)
    monkeypatch.setattr(areas, "WORKERS", 2)
    monkeypatch.setenv("CLEARANCE_PROCESS", "1")
    index = AreaIndex(net)
    # each thread names the other's curves as the ones it reads next: queued answers are
    # dropped and made again, never mixed up
    halves = [curves[:16], curves[16:]]

    def build(i: int) -> list[bytes]:
        out = []
        for _ in range(8):
            got = areas.build_areas(index, halves[i], ahead=[halves[1 - i]])
            out.append(_wkb(got))
        return out

    with ThreadPoolExecutor(4) as pool:
        results = list(pool.map(build, [0, 1, 0, 1]))
    singles = [_wkb(areas.build_areas(index, h)) for h in halves]
    for i, runs in enumerate(results):
        assert all(r == singles[i % 2] for r in runs)
    area_worker.stop()


def test_the_share_moves_towards_the_side_that_waited_less():
    from networks import area_worker

    def part(share: float, ahead: bool = True):
        curves = list(range(1000))
        return area_worker._Part(curves, int(1000 * (1 - share)), None, None, ahead)

    balance = area_worker._Balance()
    assert balance.share == area_worker.PROCESS_SHARE
    balance.answered(part(0.65), 0.0, 0.65, 0.0)  # nothing of this process measured yet
    assert balance.share == area_worker.PROCESS_SHARE
    balance.measured("own", 0.35, 350)  # this process: 1 ms per curve of its own part ...
    balance.measured("plan", 0.0, 650)  # ... and nothing to send the worker its part
    balance.answered(part(0.65), 0.0, 0.65, 0.0)  # the worker: 1 ms per curve: balance 0.5
    assert balance.share == pytest.approx(0.575)
    balance.answered(part(0.575), -2.0, 0.575, 0.0)  # its answer waited 2 s: worker ahead
    assert balance.share > 0.575
    higher = balance.share
    balance.answered(part(higher), 2.0, higher, 0.0)  # this process waited 2 s
    assert balance.share < higher
    lower = balance.share
    balance.answered(part(lower, ahead=False), 0.0, lower, 5.0)  # it waited for a first job
    # not counted: as if neither had waited (this share was not the reason)
    assert balance.share == area_worker.next_share(lower, 0.0, 1000, 1e-3, 0.0, 1e-3)
