"""Selecting curves by kind, junction and bounding box, before any area is built."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from clearance.networks.curves import KINDS, extract_curves
from clearance.networks.reader import read_network
from clearance.networks.samples.build import SAMPLES_DIR
from clearance.networks.selection import (
    Selection,
    check_junctions,
    feature_line,
    in_bbox,
    load_selected,
    parse_bbox,
    select,
)
from clearance.vehicles.errors import InputError


@pytest.fixture(scope="module")
def roundabout():
    return read_network(SAMPLES_DIR / "roundabout" / "roundabout.net.xml")


@pytest.fixture(scope="module")
def intersection():
    return read_network(SAMPLES_DIR / "intersection" / "intersection.net.xml")


def test_kind_and_junction_select_exactly_those_curves(intersection):
    every = extract_curves(intersection, areas=False)
    picked = load_selected(intersection, Selection(junctions=("T",)))
    assert {c.curve_id for c in picked} == {c.curve_id for c in every if c.junction == "T"}
    assert 0 < len(picked) < len(every)
    # every curve of T has an id naming T: an independent view of the same set
    assert all(c.curve_id.startswith("turn:T:") for c in picked)
    assert load_selected(intersection, Selection(kinds=("ramp",))) == []


def test_selected_curves_get_the_same_areas_as_a_full_extraction(roundabout):
    full = {c.curve_id: c for c in extract_curves(roundabout)}
    picked = load_selected(roundabout, Selection(junctions=("C1",)))
    assert len(picked) == 4
    for c in picked:
        other = full[c.curve_id]
        for name in ("own_lanes", "roadway", "paved"):
            a, b = getattr(c, name), getattr(other, name)
            assert a is not None and a.area > 0
            assert a.symmetric_difference(b).area < 1e-6 * b.area, (c.curve_id, name)
    # only the kept curves are in the new book: nothing else is ever built for them
    book = picked[0].area_book
    assert sum(len(b) for b in book.batches) == len(picked)


def test_bbox_keeps_curves_whose_feature_meets_the_box(intersection):
    curves = extract_curves(intersection, areas=False)
    t = intersection.junctions["T"]
    xs, ys = t.shape[:, 0], t.shape[:, 1]
    box = (float(xs.min()), float(ys.min()), float(xs.max()), float(ys.max()))
    picked = select(curves, Selection(bbox=box))
    # an independent test of the same thing: shapely on the whole feature line
    expected = {c.curve_id for c in curves
                if shapely.LineString(feature_line(c)).intersects(shapely.box(*box))
                or (len(feature_line(c)) == 1 and shapely.box(*box).covers(
                    shapely.Point(feature_line(c)[0])))}
    assert {c.curve_id for c in picked} == expected
    assert {c.junction for c in picked} == {"T"}  # the two junctions are apart
    # a box round the whole network keeps everything; one far away nothing
    pts = np.vstack([c.centerline[:, :2] for c in curves])
    whole = (*pts.min(axis=0), *pts.max(axis=0))
    assert len(select(curves, Selection(bbox=whole))) == len(curves)
    assert select(curves, Selection(bbox=(1e6, 1e6, 1e6 + 1, 1e6 + 1))) == []


def test_bbox_ignores_lead_in_and_run_out(intersection):
    # a box on a curve's approach, before its feature starts, does not select it
    c = next(c for c in extract_curves(intersection, areas=False) if c.junction == "T")
    x, y = c.centerline[0, :2]
    assert c.core_start_m > 5
    assert not in_bbox(c, (x - 0.5, y - 0.5, x + 0.5, y + 0.5))
    fx, fy = feature_line(c)[len(feature_line(c)) // 2]
    assert in_bbox(c, (fx - 0.01, fy - 0.01, fx + 0.01, fy + 0.01))


def test_unknown_junction_names_close_matches(intersection):
    with pytest.raises(InputError, match=r"--junction 'TT'.*intersection.net.xml.*'T'"):
        check_junctions(["TT"], [intersection])
    check_junctions(["T", "X"], [intersection])  # known ones pass


def test_parse_bbox_rejects_bad_boxes():
    assert parse_bbox("-1,-2.5,3,4") == (-1.0, -2.5, 3.0, 4.0)
    for bad in ("1,2,3", "a,b,c,d", "0,0,1,nan", "5,0,1,1", "0,5,1,1", ""):
        with pytest.raises(InputError, match="--bbox"):
            parse_bbox(bad)


def test_unknown_kind_is_bad_input():
    with pytest.raises(InputError, match="unknown curve kind"):
        Selection(kinds=("spiral",))
    assert Selection(kinds=KINDS[:1]).effective_kinds() == KINDS[:1]
