"""The report's figures: the swept-path drawing, the base plan, colours and units."""

import math

import numpy as np
import pytest
import shapely

from clearance.networks.plot import pavement_area
from clearance.networks.reader import read_network
from clearance.networks.samples.build import sample_networks
from clearance.networks.selection import Selection
from clearance.reports.documents.drawing import draw_curve, overreach
from clearance.reports.documents.figures import plot_curve, shown_runs
from clearance.reports.documents.plotting import (
    PALETTE,
    PNG_SVG,
    add_scale_bar,
    new_figure,
    plan_axes,
    vehicle_colours,
)
from clearance.reports.study.run import run_study
from clearance.vehicles.table import bundled_table_paths, load_tables

NET = next(p for p in sample_networks() if p.stem.startswith("intersection"))


@pytest.fixture(scope="module")
def study():
    table = load_tables(bundled_table_paths(), ["P", "SU-30", "WB-67"])
    return run_study([NET], table, workers=1, selection=Selection(junctions=("T",)))


def test_a_vehicle_keeps_its_colour_in_every_figure(study):
    nc = study.networks[0]
    seen: dict[str, set[str]] = {}
    for curve in nc.curves:
        recs = [r for r in study.records if r.curve_id == curve.curve_id]
        for subset in (recs, recs[1:], recs[::-1]):
            shown = shown_runs(nc, curve, subset, study.table)
            colours = [s.colour for s in shown]
            assert len(set(colours)) == len(colours)  # told apart within a figure
            for s in shown:
                seen.setdefault(s.record.vehicle, set()).add(s.colour)
    assert all(len(c) == 1 for c in seen.values())
    assert seen["P"] == {PALETTE[0]}  # by the table's order, not by the figure's
    names = [f"v{i}" for i in range(len(PALETTE))]
    assert len(set(vehicle_colours(names).values())) == len(PALETTE)


def test_units_ft_put_ticks_and_scale_bar_in_round_feet():
    fig, ax = new_figure()
    ax.set_xlim(0.0, 60.0)
    ax.set_ylim(0.0, 45.0)
    plan_axes(ax, "ft")
    length = add_scale_bar(ax, "ft")
    fig.canvas.draw()
    assert "[ft]" in ax.get_xlabel() and "[ft]" in ax.get_ylabel()
    ticks = [t for t in ax.get_xticks() if 0 <= t <= 60]
    fmt = ax.xaxis.get_major_formatter()
    ft = [t / 0.3048 for t in ticks]
    assert len(ticks) >= 3 and np.allclose(ft, np.round(ft))  # ticks at whole feet ...
    assert [float(fmt(t)) for t in ticks] == pytest.approx(ft)  # ... labelled in feet
    assert fmt(-7e-15) == "0"  # a zero computed a hair off zero reads as zero
    assert length / 0.3048 in (10.0, 20.0, 25.0, 50.0)
    texts = [t.get_text() for t in ax.texts]
    assert f"{length / 0.3048:g} ft" in texts
    assert not any(t.endswith(" m") for t in texts)


def test_curbs_only_where_the_pavement_ends():
    net = read_network(NET)
    road = [k for k, lane in net.lanes.items() if lane.allows_road_vehicles()]
    area = pavement_area(net, road, list(net.junctions.values()))
    edge = area.boundary
    # two lanes of one edge side by side: their common line is no edge of pavement
    pairs = 0
    for k, lane in net.lanes.items():
        other = net.lanes.get(f"{lane.edge}_{lane.index + 1}")
        if lane.is_internal or other is None or k not in road:
            continue
        a, b = (shapely.LineString(x.shape[:, :2]).interpolate(0.5, normalized=True)
                for x in (lane, other))
        mid = shapely.Point((a.x + b.x) / 2, (a.y + b.y) / 2)
        assert edge.distance(mid) > 1.0
        pairs += 1
        # the right side of the rightmost lane is one: half a width from its centre
        if lane.index == 0:
            d = edge.distance(a)
            assert d == pytest.approx(lane.width_m / 2, abs=0.05)
    assert pairs > 0


def test_the_curve_drawing_hatches_the_conflict_and_says_where_a_run_stops(study, tmp_path):
    nc = study.networks[0]
    recs = sorted(study.records, key=lambda r: r.margin_m if math.isfinite(r.margin_m) else -99)
    worst = recs[0]
    curve = next(c for c in nc.curves if c.curve_id == worst.curve_id)
    records = [r for r in study.records if r.curve_id == curve.curve_id]
    fig, ax = new_figure()
    handles = draw_curve(ax, nc, curve, shown_runs(nc, curve, records, study.table), "ft")
    texts = [t.get_text() for t in ax.texts]
    hatches = {p.get_hatch() for p in ax.patches}
    labels = [h.get_label() for h in handles]
    assert worst.margin_m < 0 and ("////" in hatches or "xxxx" in hatches)
    assert any(t.startswith("offtracking ") and t.endswith(" ft") for t in texts)
    assert any(t.endswith(("ft beyond its lanes", "ft beyond the pavement")) for t in texts)
    if worst.verdict == "cannot-turn":
        assert any("stops" in t or "cannot hold the path" in t for t in texts)
    for needed in ("outer front wheel path", "inner rear wheel path", "outside the pavement",
                   "outside its own lanes (paved)", "edge of pavement", "own lanes"):
        assert needed in labels
    assert not any(t.endswith(" m") for t in texts)
    png, svg = plot_curve(nc, curve, records, tmp_path / "fig", table=study.table, units="ft",
                          formats=PNG_SVG)
    assert png.stat().st_size > 10_000 and "<pattern" in svg.read_text()


def test_overreach_is_the_margin_beyond_the_area():
    area = shapely.box(0, 0, 10, 3.5)
    env = shapely.Polygon([(2, 1), (8, 1), (8, 4.2), (2, 3.9)])
    a, b, d = overreach(env, area)
    assert d == pytest.approx(0.7, abs=0.01)
    assert tuple(np.round(b, 6)) == (8.0, 3.5)


def test_a_swung_run_is_drawn_on_its_path_with_the_lane_line_dashed_beside_it(study):
    nc = study.networks[0]
    swung = [r for r in study.records if r.path == "swung"]
    assert swung, "the sample's junction T has swung runs (WB-67 at the tight corners)"
    rec = swung[0]
    curve = next(c for c in nc.curves if c.curve_id == rec.curve_id)
    [shown] = shown_runs(nc, curve, [rec], study.table)
    assert shown.driven.path == "swung" and shown.driven.swing_m > 0
    fig, ax = new_figure()
    handles = draw_curve(ax, nc, curve, [shown], "m")
    lines = {ln.get_gid(): ln for ln in ax.get_lines() if ln.get_gid()}
    taken, lane = lines["path-taken"], lines["lane-centre-line"]
    assert taken.get_linestyle() == "-" and lane.get_linestyle() == "--"
    # the path taken is the steered axle's, off the lane line by about the swing
    tr = shown.run.trajectory
    assert np.allclose(taken.get_xydata(), np.c_[tr.xf_m, tr.yf_m])
    assert np.allclose(lane.get_xydata(), curve.centerline[:, :2])
    line = shapely.LineString(curve.centerline[:, :2])
    apart = max(line.distance(shapely.Point(p)) for p in taken.get_xydata())
    assert apart >= 0.5 * shown.driven.swing_m  # off the lane line (it swung out)
    assert "path-followed" not in lines  # a lane run's dashed path is not drawn too
    labels = [h.get_label() for h in handles]
    assert f"{rec.vehicle}: path taken, swung {shown.driven.swing_m:.2f} m out" in labels
    assert "lane centre line (not taken)" in labels
    dashed = next(h for h in handles if h.get_label().startswith("lane centre line"))
    assert dashed.get_linestyle() == "--"
    # a run on its lane keeps the one dashed path followed
    lane_rec = next(r for r in study.records if r.path == "lane" and r.verdict != "error")
    lane_curve = next(c for c in nc.curves if c.curve_id == lane_rec.curve_id)
    fig, ax = new_figure()
    handles = draw_curve(ax, nc, lane_curve, shown_runs(nc, lane_curve, [lane_rec],
                                                        study.table), "m")
    gids = {ln.get_gid() for ln in ax.get_lines()}
    assert "path-followed" in gids and "lane-centre-line" not in gids
    assert not any("not taken" in h.get_label() for h in handles)
