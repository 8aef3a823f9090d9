"""The runs a drawing drives again (clearance.reports.documents.drawing.rerun): the study's own
path, its line
driven again without the search of swung paths, and the same drawings as with the search."""

from __future__ import annotations

import dataclasses

import pytest

import clearance.networks.driving.drive
import clearance.networks.driving.swing
from clearance.networks.samples.build import sample_networks
from clearance.reports.documents.drawing import rerun
from clearance.reports.documents.figures import plot_curve
from clearance.reports.exports.study import drawn_geometry
from clearance.reports.results.records import COLUMNS
from clearance.reports.study.run import Study, run_study
from clearance.vehicles.table import bundled_table_paths, load_tables

NET = next(p for p in sample_networks() if p.stem.startswith("intersection"))
#: Vehicles that take swung paths at the sample's corners.
VEHICLES = ["CITY-BUS", "WB-62"]


@pytest.fixture(scope="module")
def study() -> Study:
    return run_study([NET], load_tables(bundled_table_paths(), VEHICLES), workers=1)


def no_search(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Count the searches of swung paths from now on (by the driver's own name too)."""
    calls: list[int] = []
    real = clearance.networks.driving.swing.swing_pass

    def counted(*args, **kwargs) -> int:
        calls.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(clearance.networks.driving.swing, "swing_pass", counted)
    monkeypatch.setattr(clearance.networks.driving.drive, "swing_pass", counted)
    return calls


def without_lines(study: Study) -> Study:
    """The study as records made without their lines (the search's fallback)."""
    return dataclasses.replace(study, records=[dataclasses.replace(r, line=None)
                                               for r in study.records])


def test_a_swung_record_keeps_its_line_and_no_output_column_says_it(study):
    swung = [r for r in study.records if r.path == "swung"]
    assert len(swung) >= 4, "the buses swing at the sample's corners"
    assert all(r.line is not None and r.line.swing_m != 0 for r in swung)
    assert all(r.line is None for r in study.records if r.path == "lane")
    assert "line" not in COLUMNS and "line" not in study.records[0].row()
    assert "line" not in study.frame().columns


def test_rerun_reproduces_every_record_without_searching(study, monkeypatch):
    nc = study.networks[0]
    vehicles = {v.name: v for v in study.table.vehicles()}
    curves = {c.curve_id: c for c in nc.curves}
    calls = no_search(monkeypatch)
    for cid, curve in curves.items():
        records = [r for r in study.records if r.curve_id == cid]
        runs = rerun(nc, curve, [vehicles[r.vehicle] for r in records], records,
                     study.clearance_m)
        for r, d in zip(records, runs, strict=True):
            assert d.result is not None, (r.vehicle, cid)
            c = d.result.clearance
            assert (d.verdict, c.margin_m, c.paved_margin_m) == (
                r.verdict, r.margin_m, r.paved_margin_m), (r.vehicle, cid)
            assert (d.path, d.lane_verdict, d.lane_margin_m) == (
                r.path, r.lane_verdict, r.lane_margin_m), (r.vehicle, cid)
            assert d.encroaches_on == r.encroaches_on
            if r.path == "swung":
                assert r.line is not None and d.swing_m == r.line.swing_m != 0
    assert calls == []  # not one search of swung paths


def test_a_record_without_its_line_is_searched_again_as_before(study, monkeypatch):
    nc = study.networks[0]
    vehicles = {v.name: v for v in study.table.vehicles()}
    rec = next(r for r in study.records if r.path == "swung")
    curve = next(c for c in nc.curves if c.curve_id == rec.curve_id)
    calls = no_search(monkeypatch)
    [d] = rerun(nc, curve, [vehicles[rec.vehicle]], [dataclasses.replace(rec, line=None)],
                study.clearance_m)
    assert calls == [1] and d.path == "swung" and d.verdict == rec.verdict
    assert d.result is not None and d.result.clearance.margin_m == rec.margin_m
    assert rerun(nc, curve, [], [], study.clearance_m) == []


def test_the_drawings_are_those_of_the_search(study, tmp_path):
    """A figure and the exports' drawn runs with the lines are those drawn by searching the
    swung paths again (the records without their lines), byte for byte."""
    nc = study.networks[0]
    swung = {r.curve_id for r in study.records if r.path == "swung"}
    curve = next(c for c in nc.curves if c.curve_id in swung)
    files = {}
    for name, s in (("lines", study), ("searched", without_lines(study))):
        records = [r for r in s.records if r.curve_id == curve.curve_id]
        files[name] = [p.read_bytes() for p in plot_curve(
            nc, curve, records, tmp_path / name, table=s.table)]
    assert files["lines"] == files["searched"]
    drawn, before = drawn_geometry(study, 4), drawn_geometry(without_lines(study), 4)
    assert drawn.keys() == before.keys()
    assert any(r.path == "swung" for r in study.records
               if (r.network, r.vehicle, r.curve_id) in drawn)
    for key, (outlines, paths) in drawn.items():
        was_outlines, was_paths = before[key]
        assert len(outlines) == len(was_outlines) and len(paths) == len(was_paths)
        assert all(a.equals_exact(b, 0.0) for a, b in zip(outlines, was_outlines, strict=True))
        assert all(a.equals_exact(b, 0.0) for a, b in zip(paths, was_paths, strict=True))


def test_the_exports_task_carries_only_the_lines_it_draws(study):
    """(clearance.reports.cli.report) A network's exports drive its worst run of each of the worst
    curves again; the other records go to the worker without their lines."""
    from clearance.reports.documents.drawings import network_tasks

    tasks = {d.part: d.task for d, _ in network_tasks(study, [], "m", None)}
    drawn = drawn_geometry(study)
    exported = tasks["exports"].records
    assert [r.curve_id for r in exported] == [r.curve_id for r in study.records]
    for r, was in zip(exported, study.records, strict=True):
        assert (r.line is not None) == (was.line is not None
                                        and (r.network, r.vehicle, r.curve_id) in drawn)
        assert r.line is None or r.line is was.line
    assert any(r.line is not None for r in exported)
    assert any(r.line is None and r.path == "swung" for r in exported)
