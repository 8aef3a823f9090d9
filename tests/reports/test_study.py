"""Running a study: permissions by SUMO class, and verdicts independent of the table."""

from __future__ import annotations

from pathlib import Path

import pytest

from clearance.networks.selection import Selection
from clearance.reports.results.tables import summary
from clearance.reports.study.run import APPROACH_M, run_study
from clearance.vehicles.table import bundled_table, load_tables

#: ../shared/realnets from the repository root (a worktree sits one level deeper)
REALNETS = [Path(__file__).resolve().parents[n] / "shared" / "realnets" for n in (3, 4)]


def _realnet(name: str) -> Path:
    for folder in REALNETS:
        if (folder / name).is_file():
            return folder / name
    pytest.skip(f"{name} is not in ../shared/realnets")


def test_curves_a_vehicle_may_not_use_are_not_permitted_never_run(tmp_path, bus_street_net):
    net = bus_street_net
    table = load_tables([bundled_table("aashto_green_book")], names=["P", "CITY-BUS"])
    study = run_study([net], table, method="analytic")
    ran = {(r.vehicle, r.curve_id) for r in study.records}
    assert ("CITY-BUS", "turn:X:WX_0->XN_0") in ran
    assert ("P", "turn:X:WX_0->XN_0") not in ran
    assert ("P", "turn:X:SX_0->XN_0") in ran
    assert study.not_permitted == [("bus", "P", "turn:X:WX_0->XN_0")]
    s = summary(study, [])
    assert s["not_permitted"] == {"runs": 1, "by_vehicle": {"P": 1}}
    assert s["runs"] == len(study.records) == 3
    # never a failure: the runs that were made are the only verdicts
    assert sum(s["verdicts"].values()) == 3
    # a table with no vehicle allowed on the bus street: its curve has no verdict, and the
    # plan figure leaves it out instead of failing
    from clearance.reports.documents.figures import plot_network

    cars = run_study([net], load_tables([bundled_table("aashto_green_book")], names=["P"]),
                     method="analytic")
    assert {r.curve_id for r in cars.records} == {"turn:X:SX_0->XN_0"}
    written = plot_network(cars.networks[0], cars.frame(), tmp_path / "plan")
    assert written and all(Path(p).stat().st_size > 0 for p in written)


def test_a_vehicles_verdicts_do_not_depend_on_the_others_in_the_table():
    net = _realnet("bologna_joined.net.xml.gz")
    path = bundled_table("aashto_green_book")
    # the simulate method's model, envelopes and verdicts (with the swung paths), without
    # the replay in SUMO; the old town's south-west, whose tight corners make P swing
    old_town = Selection(bbox=(0.0, 0.0, 900.0, 700.0))
    alone = run_study([net], load_tables([path], names=["P"]), use_sumo=False,
                      selection=old_town)
    both = run_study([net], load_tables([path], names=["P", "WB-67"]), use_sumo=False,
                     selection=old_town)
    # the former rule (the longest vehicle plus 5 m, at least 25 m) gave these two tables
    # different lead-ins; now every study has the same
    wb67 = load_tables([path], names=["WB-67"]).vehicles()[0]
    assert wb67.overall_length_m + 5 > 25.0 and APPROACH_M == 30.0

    def p_rows(study):
        return [(r.curve_id, r.verdict, round(r.margin_m, 6), round(r.paved_margin_m, 6))
                for r in study.records if r.vehicle == "P"]

    assert len(p_rows(alone)) > 60
    # and the P rows include swung paths (the search is part of what must not depend)
    assert sum(r.path == "swung" for r in alone.records) > 20
    assert p_rows(alone) == p_rows(both)


def test_batch_sizes_shrink_toward_the_end_and_cover_every_run():
    from clearance.reports.study.run import BATCH_RUNS, MIN_BATCH_RUNS, batch_sizes

    for runs, workers in [(6000, 2), (6000, 1), (1000, 4), (73, 2), (1, 1)]:
        sizes = list(batch_sizes(runs, workers))
        assert sum(sizes) == runs
        assert all(a >= b for a, b in zip(sizes, sizes[1:-1], strict=False))  # the last: rest
        assert max(sizes) <= BATCH_RUNS
        assert all(s >= min(MIN_BATCH_RUNS, -(-runs // workers)) for s in sizes[:-1])
        # the last batch in flight is no more than an even share of what was left
        assert sizes[-1] <= max(MIN_BATCH_RUNS, -(-runs // (2 * workers)))
    # a quarter of what is left, at most 400: 400 while 1,600 or more are left
    assert list(batch_sizes(6000, 2))[:14] == [400] * 12 + [300, 225]
    # a junction's few runs: one even share per worker, none idle
    assert list(batch_sizes(29, 2)) == [15, 14] and list(batch_sizes(73, 2)) == [37, 36]
    assert list(batch_sizes(120, 4)) == [30] * 4


def flattened(text: str) -> str:
    """A network's XML with every height taken out: shapes in x,y, every ``z`` 0."""
    import re

    def shape(m: re.Match[str]) -> str:
        pts = [",".join(p.split(",")[:2]) for p in m.group(2).split()]
        return f'{m.group(1)}="{" ".join(pts)}"'

    text = re.sub(r'(shape|customShape)="([^"]*)"', shape, text)
    return re.sub(r' z="[^"]*"', ' z="0.00"', text)


def test_a_road_that_climbs_is_judged_as_the_same_road_flattened(tmp_path):
    # issue 27: on SUMO's own elevated test networks, straight-throughs on a 20 % road were
    # `encroaches` by 9 m (the level band cut away the lanes up and down the slope); in plan
    # they are clear. Every run has the verdict and margins of the same network flattened.
    from tests.networks.sumo.test_parity import HAND_PICKED
    from tests.networks.test_stacking import ELEVATED

    paths = []
    for name in ELEVATED:
        src = HAND_PICKED / f"{name}.net.xml"
        flat = tmp_path / f"{name}.flat.net.xml"
        flat.write_text(flattened(src.read_text()))
        paths += [src, flat]
    table = load_tables([bundled_table("aashto_green_book")], names=["P", "CITY-BUS"])
    study = run_study(paths, table, use_sumo=False, workers=2)
    frame = study.frame()
    frame["base"] = frame.network.str.removesuffix(".flat")
    sloped = frame[~frame.network.str.endswith(".flat")].set_index(["base", "curve_id",
                                                                     "vehicle"])
    flat = frame[frame.network.str.endswith(".flat")].set_index(["base", "curve_id", "vehicle"])
    both = sloped.merge(flat, left_index=True, right_index=True, suffixes=("", "_flat"))
    assert len(both) >= 40 and (sloped.max_grade_pct > 10).any()
    assert (both.verdict == both.verdict_flat).all(), both[both.verdict != both.verdict_flat]
    assert (both.margin_m - both.margin_m_flat).abs().max() < 0.01
    # the only runs of one and not the other: ramps, which only a slope makes
    assert set(sloped.index.difference(flat.index).get_level_values(1).str.split(":").str[0]
               ) <= {"ramp"}


def test_an_articulated_bus_drives_a_bus_lane_as_a_bus_trailer_and_all():
    # its trailer's SUMO type kept the passenger class: SUMO would not place it on a bus-only
    # street ("Vehicle 'v61.trailer' is not allowed to depart on any lane of edge 'a190'")
    # and the run was an `error`: 17 of A-BUS's runs on bologna_joined
    table = load_tables([bundled_table("aashto_green_book")], names=["A-BUS", "P"])
    assert {v.name: v.vclass for v in table.vehicles()} == {"A-BUS": "bus", "P": "passenger"}
    study = run_study([_realnet("bologna_joined.net.xml.gz")], table, workers=1, swing=False,
                      selection=Selection(junctions=("a54", "a55m")))
    verdicts = {(r.vehicle, r.curve_id): r.verdict for r in study.records}
    assert verdicts[("A-BUS", "turn:a54:a190_0->a77[0]_0")] != "error"
    assert verdicts[("A-BUS", "turn:a55m:a55_0->a55b_0")] != "error"
    assert "error" not in verdicts.values()
    # the bus-only streets are not P's: not run, counted
    assert ("P", "turn:a55m:a55_0->a55b_0") not in verdicts
    assert ("bologna_joined", "P", "turn:a55m:a55_0->a55b_0") in study.not_permitted
