"""Swung paths on designed corners: a driver swings wide where the lane is too tight."""

from __future__ import annotations

import pytest

from clearance.networks.curves import extract_curves
from clearance.networks.driving.drive import DriveOptions, drive
from clearance.networks.reader import read_network
from clearance.networks.sumo.tools import netconvert_plain
from clearance.vehicles.table import bundled_table, load_tables
from tests.networks.corners import corner


@pytest.fixture(scope="module")
def table():
    return load_tables([bundled_table("aashto_green_book")], ["P", "CITY-BUS"])


def _turn(tmp_path, netconvert, name, radius_m, fwd, opp, width_m, lane=0):
    nodes, edges, cons = corner(radius_m, fwd, opp, width_m)
    path = netconvert_plain(tmp_path, name, nodes=f"<nodes>{nodes}</nodes>",
                            edges=f"<edges>{edges}</edges>",
                            connections=f"<connections>{cons}</connections>",
                            options=["--no-turnarounds"])
    net = read_network(path)
    want = f"turn:J:AJ_{lane}->JB_{lane}"
    curves = [c for c in extract_curves(net, ["turn"]) if c.curve_id == want]
    assert len(curves) == 1
    return net, curves[0]


def _drive(net, vehicle, curve, swing=True):
    return drive(net, [(vehicle, curve)], options=DriveOptions(use_sumo=False,
                                                               swing=swing))[0]


def test_car_swings_into_the_opposing_lane_at_a_3m_corner(tmp_path, netconvert, table):
    net, c = _turn(tmp_path, netconvert, "two_way", 3.0, 1, 1, 3.2)
    r = _drive(net, table.vehicle("P"), c)
    assert r.lane_verdict == "fails"  # on its lane it cuts the 3 m curb
    assert r.lane_margin_m < -0.2
    assert (r.verdict, r.path, r.encroaches_on) == ("encroaches", "swung", "opposing lanes")
    assert r.result.clearance.paved_margin_m >= 0
    assert r.result.clearance.roadway_margin_m < 0
    assert "into the opposing lanes" in r.reason and "on the lane centre line: fails" in r.reason
    # without the search the lane's result stands, the same as lane_verdict
    lane_only = _drive(net, table.vehicle("P"), c, swing=False)
    assert (lane_only.verdict, lane_only.path) == (r.lane_verdict, "lane")
    assert lane_only.result.margin_m == pytest.approx(r.lane_margin_m)


def test_car_fails_where_the_lane_is_all_the_pavement(tmp_path, netconvert, table):
    net, c = _turn(tmp_path, netconvert, "one_lane", 3.0, 1, 0, 3.2)
    r = _drive(net, table.vehicle("P"), c)
    assert r.verdict == "fails"
    assert r.encroaches_on == "shoulder"
    # the best path found leaves the pavement by no more than the lane path
    assert r.result.clearance.paved_margin_m >= r.lane_result.clearance.paved_margin_m
    assert "paved area by" in r.reason


def test_bus_swings_into_the_second_lane_and_clears_the_curb(tmp_path, netconvert, table):
    net, c = _turn(tmp_path, netconvert, "bus", 6.0, 2, 0, 3.5)  # 3.5 m bus lanes
    r = _drive(net, table.vehicle("CITY-BUS"), c)
    assert r.lane_verdict == "fails"  # the lane path runs over the 6 m curb
    assert (r.verdict, r.path, r.encroaches_on) == ("encroaches", "swung",
                                                    "same-direction lanes")
    assert r.result.clearance.paved_margin_m >= 0  # clears the curb
    assert r.result.clearance.roadway_margin_m >= 0  # inside its own direction's lanes
    assert r.swing_m > 0


def test_the_path_kept_reaches_least_into_the_opposing_lanes(tmp_path, netconvert, table,
                                                             monkeypatch):
    """Among the paved paths tried, the one kept reaches least far beyond its roadway (a
    designer draws the smallest swing that clears the curb, not the one with most room to
    it), and the search stops at the first round that finds a paved path."""
    import clearance.networks.driving.swing as swing
    from clearance.networks.driving.judging import BETTER_BY_M, tier

    seen = []
    choose = swing._choose

    def spy(d, lane, tried, *rest):
        seen.append(list(tried))
        return choose(d, lane, tried, *rest)

    monkeypatch.setattr(swing, "_choose", spy)
    net, c = _turn(tmp_path, netconvert, "two_way_least", 3.0, 1, 1, 3.2)
    r = _drive(net, table.vehicle("P"), c)
    assert r.encroaches_on == "opposing lanes"
    (tried,) = seen
    paved = [c for _, c in tried if c is not None and tier(c) == 2]
    assert paved
    kept = r.result.clearance.roadway_margin_m
    assert kept >= max(p.roadway_margin_m for p in paved) - BETTER_BY_M
    # rounds: nothing larger than the round that found the first paved path was driven
    rounds = [cand.step for cand, res in tried]
    first = min(cand.step for cand, c in tried if c is not None and tier(c) >= 2)
    assert max(rounds) == first


def test_bus_between_two_lane_roads_takes_a_refined_line_to_stay_paved(tmp_path, netconvert,
                                                                      table, monkeypatch):
    """A city bus turning right at a 3 m corner between two-lane one-way roads (3.5 m
    lanes): none of the family's shapes keeps it on the pavement; the refined line does,
    within the refinement's bounds, out over the second lane and the junction's corner
    (paved, beyond its roadway: ``opposing lanes`` in the tool's three words)."""
    import clearance.networks.driving.swing as swing
    from clearance.networks.driving.refine import RefineSearch
    from clearance.networks.driving.runs import DriveStats

    net, c = _turn(tmp_path, netconvert, "bus_two_lanes", 3.0, 2, 0, 3.5)
    bus = table.vehicle("CITY-BUS")
    stats = DriveStats()
    r = drive(net, [(bus, c)], options=DriveOptions(use_sumo=False), stats=stats)[0]
    assert (r.verdict, r.path, r.encroaches_on) == ("encroaches", "swung", "opposing lanes")
    assert r.result.clearance.paved_margin_m >= 0
    assert r.reason.startswith("takes its own line:")
    assert r.swing_m > 2.0  # out over the second lane
    assert stats.refine_runs == 1
    assert 0 < stats.refine_candidates <= RefineSearch().count
    again = drive(net, [(bus, c)], options=DriveOptions(use_sumo=False))[0]
    assert (again.reason, again.result.clearance.margin_m) == (r.reason,
                                                               r.result.clearance.margin_m)
    # the family of shapes alone leaves the pavement
    monkeypatch.setattr(swing, "_refine", lambda *args: 0)
    family = drive(net, [(bus, c)], options=DriveOptions(use_sumo=False))[0]
    assert family.verdict == "fails"
    assert family.result.clearance.paved_margin_m < -0.1


def test_the_refinement_is_not_tried_far_off_the_pavement(tmp_path, netconvert, table):
    """The bus on one-lane roads leaves the pavement by metres whatever line it takes: the
    refinement is for near misses and leaves such a run alone."""
    from clearance.networks.driving.runs import DriveStats

    net, c = _turn(tmp_path, netconvert, "bus_one_lane", 3.0, 1, 0, 3.2)
    stats = DriveStats()
    r = drive(net, [(table.vehicle("CITY-BUS"), c)], options=DriveOptions(use_sumo=False),
              stats=stats)[0]
    assert r.verdict == "fails" and r.result.clearance.paved_margin_m < -1.0
    assert (stats.refine_runs, stats.refine_candidates) == (0, 0)


def test_only_results_that_may_be_kept_are_held_and_the_choice_is_the_same(
        tmp_path, netconvert, table, monkeypatch):
    """A run's search drives hundreds of lines; the results of those that can no longer be
    kept are dropped as it goes, and the path kept is the one keeping them all gives."""
    import clearance.networks.driving.swing as swing

    net, c = _turn(tmp_path, netconvert, "bus_prune", 3.0, 2, 0, 3.5)
    bus = table.vehicle("CITY-BUS")
    sizes = []
    choose = swing._choose

    def spy(d, lane, tried, results, *rest):
        sizes.append((len(tried), len(results)))
        return choose(d, lane, tried, results, *rest)

    monkeypatch.setattr(swing, "_choose", spy)
    pruned = drive(net, [(bus, c)], options=DriveOptions(use_sumo=False))[0]
    monkeypatch.setattr(swing, "_prune", lambda results: None)
    kept_all = drive(net, [(bus, c)], options=DriveOptions(use_sumo=False))[0]
    (tried, held), (_, every) = sizes
    assert tried > 50 and held < tried / 10 and every > held
    assert (pruned.verdict, pruned.reason, pruned.result.clearance.margin_m) == (
        kept_all.verdict, kept_all.reason, kept_all.result.clearance.margin_m)


def test_a_through_passage_swings_the_same_way_whatever_its_float_noise():
    """The roundabout sample's passages straight across have a net turn of +-1e-13 degrees
    (or exactly 0): float noise, whose sign used to choose the side of their swing search
    (and 0 none at all). Each is now searched toward the ring's inside, so SU-30 across
    C3 -> C1 gets the same verdict whichever noise its turn carries: the golden
    encroaches, the lane path's fails being the search's absence."""
    from clearance.analysis.polyline import prepare_path
    from clearance.networks.curves import CurveOptions
    from clearance.networks.driving.room import outside_sign, search_turn_deg
    from clearance.reports.study.run import APPROACH_M

    net = read_network("networks/samples/roundabout/roundabout.net.xml")
    curves = extract_curves(net, options=CurveOptions(approach_length_m=APPROACH_M))
    through = [c for c in curves if abs(c.turn_angle_deg) < 1e-6]
    assert len(through) == 8
    for c in through:  # counter-clockwise rings: the inside is to the left
        path = prepare_path(c.centerline[:, :2], 0.1)
        assert outside_sign(search_turn_deg(c.turn_angle_deg, path,
                                            (c.core_start_m, c.core_end_m))) == 1.0
    su30 = load_tables([bundled_table("aashto_green_book")], names=["SU-30"]).vehicles()[0]
    c3 = next(c for c in through if c.curve_id == "roundabout:C3:C3_in_0->C1_out_0")
    seen = set()
    for noise in (0.0, 1e-13, -1e-13):  # the same curve (its areas built once), its noise set
        object.__setattr__(c3, "turn_angle_deg", noise)
        [d] = drive(net, [(su30, c3)], options=DriveOptions(use_sumo=False, swing=True))
        seen.add((d.verdict, round(d.result.margin_m, 6)))
    assert len(seen) == 1 and next(iter(seen))[0] == "encroaches"


def test_moves_left_unjudged_change_nothing_the_search_keeps(tmp_path, netconvert, table,
                                                             monkeypatch):
    """The compass search leaves unjudged the moves whose floors show they cannot win
    (:func:`clearance.analysis.screen.reach_floors`); judging every move instead keeps
    the same path, verdict, margins and reason, run by run, on corners where it refines."""
    import clearance.networks.driving.swing as swing
    from clearance.networks.driving.runs import DriveStats

    cases = []
    for name, radius, width in (("r3", 3.0, 3.5), ("r4", 4.0, 3.5), ("r6", 6.0, 3.0)):
        net, c = _turn(tmp_path, netconvert, name, radius, 2, 0, width)
        cases += [(net, v, c) for v in (table.vehicle("P"), table.vehicle("CITY-BUS"))]

    def run_all():
        stats = DriveStats()
        out = [drive(net, [(v, c)], options=DriveOptions(use_sumo=False), stats=stats)[0]
               for net, v, c in cases]
        return out, stats

    screened, stats = run_all()
    monkeypatch.setattr(swing, "_cannot_win", lambda *args: False)
    every, all_judged = run_all()
    assert stats.refine_runs == 3 and stats.swing_screened > stats.swing_judged
    assert all_judged.swing_screened == 0
    assert all_judged.swing_judged == stats.swing_judged + stats.swing_screened
    for a, b in zip(screened, every, strict=True):
        assert (a.verdict, a.reason, a.path, a.swing_m) == (b.verdict, b.reason, b.path,
                                                            b.swing_m)
        assert a.result.clearance == b.result.clearance
