"""Golden verdict files: every id round-trips; new, gone, worse and better runs are found."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from clearance.networks.samples.build import SAMPLES_DIR
from clearance.networks.selection import Selection
from clearance.reports.results.golden import compare, golden_text, read_golden, relevant
from clearance.vehicles.errors import InputError

#: Ids as SUMO writes them for OpenStreetMap networks (issue 13), and worse.
ODD_IDS = ["turn:123:156775056#13_0->-27149243_1", "roundabout:a40:a77[0]_0->a21a_0",
           "turn:cluster_1_#2more:a#1_0->b_0", "#leading-hash", 'a "quoted", id', "bend:*:?"]


def frame(ids, verdicts=None, margins=None, vehicle="P", network="n"):
    n = len(ids)
    return pd.DataFrame({
        "network": [network] * n, "vehicle": [vehicle] * n, "curve_id": ids,
        "verdict": verdicts or ["clear"] * n, "margin_m": margins or [0.1] * n,
        "kind": [c.split(":", 1)[0] for c in ids], "junction": ["J"] * n})


def test_every_id_round_trips(tmp_path):
    g = tmp_path / "g.csv"
    f = frame(ODD_IDS, ["clear", "fails", "encroaches", "cannot-turn", "error", "clear"],
              [0.123, -0.5, -0.1, float("nan"), float("nan"), 2.0])
    g.write_text(golden_text(f))
    back = read_golden(g)
    assert list(back.curve_id) == ODD_IDS
    assert list(back.verdict) == list(f.verdict)
    assert list(back.kind) == [c.split(":", 1)[0] for c in ODD_IDS]
    # the header comes after the comment lines: data start on line 4
    assert list(back.line) == list(range(4, 4 + len(ODD_IDS)))


def test_the_samples_golden_file_gives_the_old_expectations():
    # the old reader (pandas, '#' as comment) on a file whose ids have no '#'
    path = SAMPLES_DIR / "golden_verdicts.csv"
    old = pd.read_csv(path, dtype=str, keep_default_na=False, comment="#")
    new = read_golden(path)
    assert len(new) == len(old) == 315
    cols = ["network", "vehicle", "curve_id", "verdict"]
    assert new[cols].values.tolist() == old[cols].values.tolist()


@pytest.mark.parametrize("body, message", [
    ("n,P,a#1,splendid\n", r"g.csv:4: unknown verdict 'splendid'"),
    ("n,P,a#1,clear\nn,P,a#1,fails\n", "g.csv:5: the same network, vehicle and curve as line 4"),
    ("n,P,,clear\n", "g.csv:4: empty curve_id"),
    ("n,P,a,clear,extra\n", "g.csv:4: 5 fields, the header has 4"),
])
def test_errors_name_file_and_line(tmp_path, body, message):
    g = tmp_path / "g.csv"
    g.write_text("# one\n# two\nnetwork,vehicle,curve_id,verdict\n" + body)
    with pytest.raises(InputError, match=message):
        read_golden(g)


def test_compare_sorts_worse_better_new_gone():
    golden = read_frame(frame(["a", "b", "c", "gone#1"],
                              ["encroaches", "fails", "clear", "clear"]))
    found = frame(["a", "b", "c", "new#1"], ["fails", "clear", "clear", "clear"])
    found = pd.concat([found, frame(["c"], ["clear"], vehicle="WB-62")], ignore_index=True)
    r = compare(found, golden)
    assert r.expected == 4 and r.as_expected == 1
    assert r.worse == ["n: a: P: fails (+0.10 m), expected encroaches"]
    assert r.better == ["n: b: P: clear (+0.10 m), golden says fails"]
    assert r.gone_curves == ["n: gone#1 (expected P clear)"]
    assert r.new_curves == ["n: new#1 (P clear (+0.10 m))"]
    assert r.new_runs == ["n: c: WB-62 clear (+0.10 m)"]
    # a waived regression is reported apart and is not a regression
    r = compare(found, golden, {("n", "P", "a"): "known tight spot"})
    assert r.worse == [] and r.worse_waived == [
        "n: a: P: fails (+0.10 m), expected encroaches; waived: known tight spot"]


def test_a_missing_run_on_a_curve_still_there_is_worse():
    golden = read_frame(pd.concat([frame(["a"]), frame(["a"], vehicle="WB-62")]))
    r = compare(frame(["a"]), golden)
    assert r.worse == ["n: a: WB-62: no such run any more (expected clear)"]
    assert r.gone_curves == [] and r.new_curves == []


def read_frame(f: pd.DataFrame) -> pd.DataFrame:
    """A golden frame as read_golden gives it (through a file)."""
    import tempfile

    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "g.csv"
        p.write_text(golden_text(f.reset_index(drop=True)))
        return read_golden(p)


def test_relevant_keeps_the_selection_and_counts_what_it_cannot_tell():
    g = read_frame(pd.concat([
        frame(["turn:J:a"]), frame(["roundabout:R:b"]).assign(junction="R"),
        frame(["turn:K:c"]).assign(junction="K"), frame(["turn:J:a"], network="other"),
        frame(["turn:J:a"], vehicle="WB-62")]))
    found = {("n", "turn:J:a")}
    judged, outside, unknown = relevant(g, ["P"], ["n"], found, Selection(kinds=("turn",)))
    assert list(judged.curve_id) == ["turn:J:a", "turn:K:c"]  # K is gone: judged
    assert (outside, unknown) == (1, 0)
    judged, outside, unknown = relevant(g, ["P"], ["n"], found, Selection(junctions=("J",)))
    assert list(judged.curve_id) == ["turn:J:a"] and (outside, unknown) == (2, 0)
    judged, outside, unknown = relevant(g, ["P"], ["n"], found, Selection(bbox=(0, 0, 1, 1)))
    assert list(judged.curve_id) == ["turn:J:a"] and (outside, unknown) == (0, 2)
    # a file without a junction column cannot say which junction a gone curve had
    g2 = g.assign(junction="")
    judged, outside, unknown = relevant(g2, ["P"], ["n"], found, Selection(junctions=("J",)))
    assert list(judged.curve_id) == ["turn:J:a"] and (outside, unknown) == (0, 2)
