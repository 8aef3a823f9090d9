"""Waiver files: globs over ids with '#' and '[', accepted verdicts, unused waivers, errors."""

from __future__ import annotations

import pytest

from clearance.reports.results.waivers import WAIVABLE, Waiver, apply_waivers, read_waivers
from clearance.vehicles.errors import InputError

VEHICLES = ["P", "WB-62", "2008 Chrysler Town & Country"]
HEAD = "curve_id,vehicle,verdict,reason\n"


def write(tmp_path, text):
    p = tmp_path / "w.csv"
    p.write_text(text)
    return p


def test_read_back_ids_with_hash_quotes_and_an_optional_network(tmp_path):
    p = write(tmp_path, "# accepted by the design team\n" + HEAD.strip() + ",network\n"
              '"turn:123:156775056#13_0->-27149243_1",P,fails,"kerb, known",bologna\n'
              "roundabout:a40:*,*,encroaches,narrow ring,\n"
              "#odd,2008 Chrysler Town & Country,cannot-turn,a leading hash is data,\n")
    ws = read_waivers(p, VEHICLES)
    assert [(w.line, w.curve_id, w.vehicle, w.verdict, w.reason, w.network) for w in ws] == [
        (3, "turn:123:156775056#13_0->-27149243_1", "P", "fails", "kerb, known", "bologna"),
        (4, "roundabout:a40:*", "*", "encroaches", "narrow ring", "*"),
        (5, "#odd", "2008 Chrysler Town & Country", "cannot-turn", "a leading hash is data",
         "*"),
    ]


@pytest.mark.parametrize("text, message", [
    (HEAD + "a,P,clear,fine\n", "w.csv:2: verdict 'clear' cannot be accepted"),
    (HEAD + "a,P,error,crash\n", "w.csv:2: verdict 'error' cannot be accepted"),
    (HEAD + "a,P,fails,ok\nb,PP,fails,typo\n", r"w.csv:3: unknown vehicle 'PP'.*'P'"),
    ("curve_id,vehicle,verdict\na,P,fails\n", r"w.csv:1: missing column\(s\) reason"),
    (HEAD + "a,P,fails,\n", "w.csv:2: empty reason"),
    (HEAD + ",P,fails,why\n", "w.csv:2: empty curve_id"),
])
def test_bad_files_name_file_and_line(tmp_path, text, message):
    with pytest.raises(InputError, match=message):
        read_waivers(write(tmp_path, text), VEHICLES)


def test_a_run_no_worse_than_the_accepted_verdict_is_waived():
    order = ["clear", *WAIVABLE, "error"]  # best to worst
    for accepted in WAIVABLE:
        w = Waiver("w.csv", 2, "*", "*", accepted, "r")
        got = [w.accepts(v) for v in order]
        k = order.index(accepted)
        # waived: every verdict from encroaches down to the accepted one, nothing else
        assert got == [False] + [1 <= i <= k for i in range(1, len(order) - 1)] + [False]


def test_globs_literal_ids_vehicles_networks_and_unused():
    ws = [Waiver("w.csv", 2, "turn:1:a#13_*", "*", "fails", "first"),
          Waiver("w.csv", 3, "roundabout:a40:a77[0]_0->a21a_0", "P", "encroaches", "ring"),
          Waiver("w.csv", 4, "turn:*", "WB-62", "cannot-turn", "broad", network="city"),
          Waiver("w.csv", 5, "bend:*", "*", "fails", "never used")]
    runs = [("n", "P", "turn:1:a#13_0->b_0", "fails"),            # 2
            ("n", "P", "turn:1:a#14_0->b_0", "fails"),            # none matches
            ("n", "P", "roundabout:a40:a77[0]_0->a21a_0", "encroaches"),  # 3, literally
            # 3 as a glob too ([0] is the class of '0'; write [[]0] for a literal bracket)
            ("n", "P", "roundabout:a40:a770_0->a21a_0", "encroaches"),
            ("n", "WB-62", "turn:1:a#13_0->b_0", "cannot-turn"),  # 2 too mild, 4 elsewhere
            ("city", "WB-62", "turn:9:x_0->y_0", "cannot-turn"),  # 4
            ("n", "P", "turn:1:a#13_1->b_0", "clear")]             # clear: not waived
    w = apply_waivers(runs, ws)
    assert w.reasons == {("n", "P", "turn:1:a#13_0->b_0"): "first",
                         ("n", "P", "roundabout:a40:a77[0]_0->a21a_0"): "ring",
                         ("n", "P", "roundabout:a40:a770_0->a21a_0"): "ring",
                         ("city", "WB-62", "turn:9:x_0->y_0"): "broad"}
    assert list(w.too_bad) == [("n", "WB-62", "turn:1:a#13_0->b_0")]
    assert w.too_bad[("n", "WB-62", "turn:1:a#13_0->b_0")].line == 2
    assert [u.line for u in w.unused] == [5]


def test_the_first_waiver_that_accepts_the_verdict_wins():
    ws = [Waiver("w.csv", 2, "*", "*", "encroaches", "mild only"),
          Waiver("w.csv", 3, "turn:*", "*", "fails", "turns may fail")]
    w = apply_waivers([("n", "P", "turn:a", "fails"), ("n", "P", "turn:b", "encroaches")], ws)
    assert w.reasons == {("n", "P", "turn:a"): "turns may fail",
                         ("n", "P", "turn:b"): "mild only"}
    assert w.too_bad == {} and w.unused == []
