"""The screened compass rounds choose what judging every move chooses."""

from __future__ import annotations

import pytest

from clearance.networks.curves import CurveOptions, extract_curves
from clearance.networks.driving.drive import DriveOptions, drive
from clearance.networks.driving.runs import DriveStats
from clearance.networks.driving.trials import Trials
from clearance.networks.reader import read_network
from clearance.reports.study.run import APPROACH_M
from clearance.vehicles.table import bundled_table, load_tables


def _chosen(runs):
    return [(d.curve.curve_id, d.vehicle.name, d.verdict, d.path, d.swing_m, d.reason,
             d.result.clearance.margin_m, d.result.clearance.paved_margin_m) for d in runs]


@pytest.mark.parametrize("sample", ["intersection", "roundabout"])
def test_the_screened_search_chooses_as_the_exhaustive_one(sample, monkeypatch):
    """Every run of a bus and a tractor-semitrailer on a sample network, driven with the
    screened compass rounds and with every move judged: the same path, verdict, margins
    and words, run by run, while many moves were left unjudged."""
    net = read_network(f"networks/samples/{sample}/{sample}.net.xml")
    curves = extract_curves(net, options=CurveOptions(approach_length_m=APPROACH_M))
    table = load_tables([bundled_table("aashto_green_book")], names=["CITY-BUS", "WB-62"])
    pairs = [(v, c) for c in curves for v in table.vehicles()]
    options = DriveOptions(use_sumo=False)
    screened_stats = DriveStats()
    screened = _chosen(drive(net, pairs, options=options, stats=screened_stats))
    monkeypatch.setattr(Trials, "_bound", lambda self, d, cand, run: None)
    every_stats = DriveStats()
    every = _chosen(drive(net, pairs, options=options, stats=every_stats))
    assert screened == every
    assert every_stats.swing_screened == 0
    assert screened_stats.swing_screened > 0
    assert screened_stats.swing_judged + screened_stats.swing_screened == \
        every_stats.swing_judged
    assert sum(r[3] == "swung" for r in screened) > 5  # the search did choose paths
