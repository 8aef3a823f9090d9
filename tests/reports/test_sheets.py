"""Swept-path sheets: the PDF, its pages and paper, the scale, the blocks, the index, the
title block, the ghost, the storeys of a helix."""

import hashlib
import math
import re
from pathlib import Path

import numpy as np
import pytest
import shapely

from clearance.networks.samples.build import sample_networks
from clearance.networks.selection import Selection
from clearance.reports.documents.drawing import Shown, view_bounds
from clearance.reports.documents.figures import shown_runs
from clearance.reports.documents.sheet_blocks import PAPER_MM, vehicle_rows, verdict_rows
from clearance.reports.documents.sheet_settings import Project, SheetSettings
from clearance.reports.documents.sheets import (
    FRAME_MM,
    SCALES,
    fit_scale,
    manoeuvre_box,
    pick_sheets,
    sheet_pages,
    sheet_view,
    title_rows,
    write_sheets,
)
from clearance.reports.documents.storeys import LAST_TURN_RAD
from clearance.reports.study.run import run_study
from clearance.vehicles.table import bundled_table_paths, load_tables
from tests.reports.pdf import pdf_pages, pdf_text

NET = next(p for p in sample_networks() if p.stem.startswith("intersection"))
VEHICLES = ["P", "CITY-BUS", "WB-67"]
PT_PER_MM = 72 / 25.4


@pytest.fixture(scope="module")
def study():
    table = load_tables(bundled_table_paths(), VEHICLES)
    return run_study([NET], table, workers=1, clearance_m=0.3,
                     selection=Selection(junctions=("T",)))


def test_a_pdf_per_network_with_the_expected_pages_on_a3_landscape(study, tmp_path):
    written = write_sheets(study, tmp_path, bundled_table_paths(), settings=SheetSettings(
        "all", 3))
    assert written == [tmp_path / "intersection.pdf"]
    data = written[0].read_bytes()
    assert data.startswith(b"%PDF")
    pages = pdf_pages(data)
    assert len(pages) == 1 + 3  # the index, then the sheets
    for w, h in pages:  # A3 landscape: 420 x 297 mm
        assert w == pytest.approx(PAPER_MM[0] * PT_PER_MM, abs=0.5)
        assert h == pytest.approx(PAPER_MM[1] * PT_PER_MM, abs=0.5)
        assert w > h


def test_every_vehicle_not_clear_gets_its_sheet_grouped_by_curve_worst_first(study):
    """The city bus gets its sheets beside the WB-67 that fails worse on the same curves."""
    chosen = pick_sheets(study.records)
    assert {(r.curve_id, r.vehicle) for r in chosen} == {
        (r.curve_id, r.vehicle) for r in study.records if r.verdict not in ("clear", "error")}
    assert any(r.vehicle == "CITY-BUS" for r in chosen)
    order = {"cannot-turn": 0, "fails": 1, "encroaches": 2, "clear": 3}
    curves = list(dict.fromkeys(r.curve_id for r in chosen))
    # grouped: each curve's sheets together, the curves in the order of their worst runs
    assert [r.curve_id for r in chosen] == sorted((r.curve_id for r in chosen), key=curves.index)
    firsts = [next(r for r in chosen if r.curve_id == c) for c in curves]
    keys = [(order[r.verdict], r.margin_m) for r in firsts]
    assert keys == sorted(keys)
    for c in curves:
        mine = [(order[r.verdict], r.margin_m) for r in chosen if r.curve_id == c]
        assert mine == sorted(mine)
    every = pick_sheets(study.records, "all")
    assert len(every) == len([r for r in study.records if r.verdict != "error"])
    assert pick_sheets(study.records, "none") == []


def test_the_runs_picked_pick_themselves_again_beside_the_ghosts_runs(study):
    """What a report sends a worker (the runs picked and the ghost's on their curves) picks
    the same sheets there."""
    for which, limit in (("not-clear", None), ("not-clear", 3), ("all", 4)):
        picked = pick_sheets(study.records, which, limit)
        ids = {r.curve_id for r in picked}
        ghosts = [r for r in study.records if r.vehicle == "P" and r.curve_id in ids
                  and all(r is not p for p in picked)]
        assert pick_sheets(picked + ghosts, which, limit) == picked


def test_fit_scale_takes_the_first_scale_that_fits():
    fw, fh = FRAME_MM[2:]
    # exactly the frame at 1:250 fits 1:250, not 1:200
    assert fit_scale(fw * 0.25, fh * 0.25) == 250
    assert fit_scale(fw * 0.25 + 0.01, fh * 0.1) == 500
    assert fit_scale(fw * 0.2, fh * 0.2) == 200
    assert fit_scale(1e6, 1.0) == SCALES[-1]


def test_the_sheet_scale_fits_the_manoeuvre_and_is_exact(study):
    by_id = {c.curve_id: c for n in study.networks for c in n.curves}
    for r in pick_sheets(study.records, "all", 4):
        curve = by_id[r.curve_id]
        (x0, x1, y0, y1), n = sheet_view(curve, Shown(r, "k"))
        assert n in SCALES and n in (100, 200, 250, 500, 1000)
        # the bounds fill the frame at 1:n: 1 mm of paper is n mm of ground
        assert (x1 - x0) * 1000 / n == pytest.approx(FRAME_MM[2])
        assert (y1 - y0) * 1000 / n == pytest.approx(FRAME_MM[3])
        # the manoeuvre is on the sheet: the feature and the swept path near it
        b = manoeuvre_box(curve, Shown(r, "k"))
        assert x0 <= b[0] and b[2] <= x1 and y0 <= b[1] and b[3] <= y1
        finer = [s for s in SCALES if s < n]
        if finer:  # the next finer scale does not hold the manoeuvre with its margin
            assert ((b[2] - b[0] + 6) * 1000 / finer[-1] > FRAME_MM[2]
                    or (b[3] - b[1] + 6) * 1000 / finer[-1] > FRAME_MM[3])


def test_a_sheet_is_drawn_from_the_manoeuvre_not_the_lead_in(study):
    """The whole envelope (a vehicle length of lead-in and run-out) would need a coarser
    scale on some sheet; the manoeuvre's view never needs more room than it."""
    by_id = {c.curve_id: c for n in study.networks for c in n.curves}
    finer = 0
    for r in pick_sheets(study.records, "all", 8):
        curve = by_id[r.curve_id]
        _, n = sheet_view(curve, Shown(r, "k"))
        vx0, vx1, vy0, vy1 = view_bounds(curve, [Shown(r, "k")], pad_m=5.0,
                                         aspect=FRAME_MM[2] / FRAME_MM[3])
        whole = fit_scale(vx1 - vx0, vy1 - vy0)
        assert n <= whole
        finer += n < whole
    assert finer, "the lead-in no longer sets the scale of any sheet"


def test_title_block_hashes_are_the_files_sha256(study):
    nc = study.networks[0]
    rows = dict(title_rows(nc, bundled_table_paths(), date="2026-01-02"))
    assert rows["run on"] == "2026-01-02"
    digest = hashlib.sha256(Path(nc.path).read_bytes()).hexdigest()[:16]
    assert rows["network file"].endswith(digest)
    assert rows["tool"].startswith("sumo-clearance ")


def test_vehicle_block_in_feet(study):
    wb67 = next(v for v in study.table.vehicles() if v.name == "WB-67")
    rows = dict(vehicle_rows(wb67, "ft"))
    # the Green Book WB-67: 73.5 ft long, 8.5 ft wide (its table row, in feet)
    assert rows["overall length"] == f"{wb67.overall_length_m / 0.3048:.2f} ft"
    assert rows["width"] == "8.50 ft"
    assert rows["trailer wheelbase"].endswith(" ft")
    assert all(" m" not in v for k, v in rows.items() if k != "source")


def test_trailer_offtracking_is_reported_and_on_the_sheet(study):
    """The WB-67's runs carry the trailer's offtracking, larger than the tractor's on a turn
    (its steady state against the tractrix closed form is
    tests/analysis/test_envelope.py::test_semitrailer_offtracking_reaches_its_closed_form); the
    car's runs have none. The sheet's verdict block says it."""
    nc = study.networks[0]
    seen = 0
    for r in study.records:
        if r.vehicle in ("P", "CITY-BUS"):
            assert math.isnan(r.trailer_offtracking_m)
        elif r.verdict != "error" and abs(r.turn_angle_deg) > 45:
            assert r.max_offtracking_m < r.trailer_offtracking_m, r.curve_id
            seen += 1
    assert seen
    curve = next(c for c in nc.curves if abs(c.turn_angle_deg) > 45)
    recs = [r for r in study.records if r.curve_id == curve.curve_id]
    [shown] = [s for s in shown_runs(nc, curve, recs, study.table) if s.record.vehicle == "WB-67"]
    rows = dict(verdict_rows(shown, "m"))
    assert rows["largest trailer offtracking"] == f"{shown.record.trailer_offtracking_m:.2f} m"


def test_rerun_for_the_drawing_gives_the_studys_verdict_and_margin(study):
    nc = study.networks[0]
    for curve in nc.curves[:3]:
        recs = [r for r in study.records if r.curve_id == curve.curve_id]
        for s in shown_runs(nc, curve, recs, study.table):
            assert s.driven is not None and s.driven.result is not None
            assert s.driven.verdict == s.record.verdict
            assert s.driven.result.clearance.margin_m == pytest.approx(s.record.margin_m,
                                                                       abs=1e-9)


def test_clearance_report_writes_the_sheets_into_its_folder(tmp_path):
    from clearance.reports.cli.main import main

    out = tmp_path / "rep"
    args = ["report", "-n", str(NET), "-o", str(out), "--vehicle", "P", "--junction", "T",
            "--units", "ft", "--sheets", "all"]
    assert main(args) == 0
    rows = (out / "clearance.csv").read_text().splitlines()[1:]
    pdf = out / "sheets" / "intersection.pdf"
    assert len(pdf_pages(pdf.read_bytes())) == 1 + len(rows)
    # a second run replaces the folder (the sheets are part of the report's layout)
    assert main(args + ["--max-sheets", "2"]) == 0
    assert len(pdf_pages(pdf.read_bytes())) == 1 + 2
    # the index says how many runs the limit left without a sheet
    assert f"{len(rows) - 2} more runs, past the limit" in " ".join(pdf_text(pdf, 1).split())
    assert main(args + ["--sheets", "none"]) == 0 and not pdf.exists()


def test_analytic_studies_get_sheets_of_their_envelopes(tmp_path):
    table = load_tables(bundled_table_paths(), ["P"])
    study = run_study([NET], table, method="analytic", workers=1,
                      selection=Selection(junctions=("T",)))
    written = write_sheets(study, tmp_path, bundled_table_paths(),
                           settings=SheetSettings("all", 2))
    assert len(pdf_pages(written[0].read_bytes())) == 1 + 2


def test_the_index_lists_every_sheet_and_the_title_block_is_filled(study, tmp_path):
    """The first page indexes every sheet by its drawing number; every sheet's title block
    carries the project's fields whole (a long name wraps, never cut short), and the index
    counts as many sheets as follow it."""
    name = ("Harbour Road and Quay Street junction improvements, stage 2: swept-path "
            "assessment of the design vehicles for the bus interchange")
    project = Project(name=name, drawing_number="HR-SP", drawn="A. Designer",
                      checked="B. Engineer", revision="P02", date="2026-12-06")
    settings = SheetSettings(project=project)
    [pdf] = write_sheets(study, tmp_path, bundled_table_paths(), settings=settings)
    pages = sheet_pages(study, study.networks[0], settings)
    assert len(pdf_pages(pdf.read_bytes())) == 1 + len(pages)
    index = pdf_text(pdf, 1)
    for page in pages:
        line = next(x for x in index.splitlines() if project.sheet_number(page.number) in x)
        assert page.shown.record.vehicle in line and page.shown.record.verdict in line
    assert "HR-SP-000" in index  # the index's own number
    for n, page in enumerate(pages, start=2):
        text = pdf_text(pdf, n)
        words = " ".join(text.split())
        assert name in words or all(w in words for w in name.split())
        assert project.sheet_number(n - 1) in text and "P02" in text
        assert "A. Designer" in text and "B. Engineer" in text and "2026-12-06" in text
        assert text.count("SIGNATURE") == 3 and "APPROVED" in text
        assert f"{n - 1} of {len(pages)}" in text
        assert page.shown.record.curve_id in text


def test_a_ghost_stands_on_the_other_vehicles_sheets(study, tmp_path):
    """With a ghost (a route study's baseline), every other vehicle's sheet of a curve the
    ghost ran shows it, driven again; its own sheets show none."""
    settings = SheetSettings(ghost="CITY-BUS")
    pages = sheet_pages(study, study.networks[0], settings)
    mine = [p for p in pages if p.shown.record.vehicle == "CITY-BUS"]
    others = [p for p in pages if p.shown.record.vehicle != "CITY-BUS"]
    assert mine and others
    assert all(p.ghost is None for p in mine)
    for p in others:
        assert p.ghost is not None and p.ghost.record.vehicle == "CITY-BUS"
        assert p.ghost.record.curve_id == p.shown.record.curve_id
        assert p.ghost.driven is not None and p.ghost.driven.verdict == p.ghost.record.verdict
    [pdf] = write_sheets(study, tmp_path, bundled_table_paths(), settings=settings)
    text = pdf_text(pdf, 1 + others[0].number)
    assert "compared with" in text and "CITY-BUS for comparison" in text


def test_bad_project_files_and_options_exit_2_naming_them(tmp_path, monkeypatch, capsys):
    from clearance.reports.cli.main import main

    monkeypatch.chdir(tmp_path)
    base = ["report", "-n", str(NET), "-o", str(tmp_path / "rep"), "--vehicle", "P"]
    (tmp_path / "clearance.toml").write_text('[project]\nname = "X"\ndrawn_by = "me"\n')
    assert main(base) == 2
    err = capsys.readouterr().err
    assert "clearance.toml" in err and "drawn_by" in err and "Traceback" not in err
    (tmp_path / "clearance.toml").write_text("[project\n")
    assert main(base) == 2 and "not a TOML file" in capsys.readouterr().err
    assert main(base + ["--project", str(tmp_path / "missing.toml")]) == 2
    assert "missing.toml" in capsys.readouterr().err
    assert main(base + ["--ghost", "NOPE"]) == 2 and "NOPE" in capsys.readouterr().err
    assert main(base + ["--max-sheets", "-1"]) == 2 and "--max-sheets" in capsys.readouterr().err
    assert not (tmp_path / "rep").exists()


def test_the_project_file_beside_the_study_fills_the_title_block(tmp_path, monkeypatch):
    from clearance.reports.cli.main import main

    monkeypatch.chdir(tmp_path)
    (tmp_path / "clearance.toml").write_text(
        '[project]\nname = "Quay Street"\ndrawing_number = "QS"\nrevision = "A"\n'
        "date = 2026-12-01\n")
    out = tmp_path / "rep"
    assert main(["report", "-n", str(NET), "-o", str(out), "--vehicle", "P", "--junction",
                 "T", "--max-sheets", "1", "--revision", "B"]) == 0
    text = pdf_text(out / "sheets" / "intersection.pdf", 2)
    assert "Quay Street" in text and "QS-001" in text and "2026-12-01" in text
    assert re.search(r"\bB\b", text) and not re.search(r"REVISION\s+A\b", text)


HELIX = next(p for p in sample_networks() if p.stem.startswith("helix"))


def test_a_helix_gets_one_storey_per_view(tmp_path):
    """The helix ramp turns three times: the city bus's run on it is drawn on three sheets,
    each a storey, whose path does not pass over itself (the whole run's does) and whose
    heights follow one another up the ramp."""
    table = load_tables(bundled_table_paths(), ["CITY-BUS"])
    study = run_study([HELIX], table, workers=1, selection=Selection(kinds=("ramp",)))
    nc = study.networks[0]
    pages = sheet_pages(study, nc, SheetSettings("all"))
    assert [p.storey[:2] for p in pages] == [(1, 3), (2, 3), (3, 3)]
    curve = next(c for c in nc.curves if c.kind == "ramp")
    [whole] = shown_runs(nc, curve, study.records, study.table)
    tr = whole.run.trajectory
    assert not shapely.LineString(list(zip(tr.xf_m, tr.yf_m, strict=True))).is_simple
    assert np.ptp(np.unwrap(tr.theta_rad)) > 2.5 * 2 * math.pi
    heights = []
    for p in pages:  # each view turns one circle, and a last one's run-out beyond it
        tr = p.shown.run.trajectory
        assert np.ptp(np.unwrap(tr.theta_rad)) <= 2 * math.pi + LAST_TURN_RAD
        heights.append(p.storey[2:])
    # the storeys' samples cover the run, each boundary sample in two of them
    assert sum(len(p.shown.run.trajectory) for p in pages) == len(whole.run.trajectory) + 2
    assert all(a[1] <= b[0] + 0.5 for a, b in zip(heights, heights[1:], strict=False))
    assert heights[-1][1] - heights[0][0] > 6.0
    [pdf] = write_sheets(study, tmp_path, bundled_table_paths(), settings=SheetSettings("all"))
    assert "storey 2 of 3" in pdf_text(pdf, 3)


def test_sheets_drawn_in_parts_by_workers_join_into_the_same_pdf(study, tmp_path):
    """A network's sheets in parts of SHEETS_PER_TASK runs (a curve's runs together), drawn
    in worker processes and joined after their index, give the pages, drawing numbers and
    index of the sheets drawn in one piece here."""
    from clearance.reports.documents import drawings as d
    from clearance.reports.study.executor import make_executor

    settings = SheetSettings("all", ghost="P")
    runs = pick_sheets(study.records, "all")
    nc = study.networks[0]
    one = write_sheets(study, tmp_path / "one", bundled_table_paths(), settings=settings)[0]
    old = d.SHEETS_PER_TASK
    d.SHEETS_PER_TASK = 4
    try:
        tasks = [t for t, _ in d.network_tasks(study, bundled_table_paths(), "m", None,
                                               settings) if t.part == "sheets"]
        assert len(tasks) >= 3
        curves = [{c for _, c in t.task.runs} for t in tasks]
        assert all(a.isdisjoint(b) for i, a in enumerate(curves) for b in curves[i + 1:])
        assert [k for t in tasks for k in t.task.runs] == [(r.vehicle, r.curve_id)
                                                           for r in runs]
        with make_executor(2) as ex:
            drawings = d.Drawings(ex, tmp_path / "parts")
            for t in tasks:
                drawings.submit(t, nc.path)
            drawings.finish()
            drawings.write_sheets(study, bundled_table_paths(), settings)
    finally:
        d.SHEETS_PER_TASK = old
    joined = tmp_path / "parts" / "sheets" / one.name
    assert len(pdf_pages(joined.read_bytes())) == len(pdf_pages(one.read_bytes()))
    a, b = pdf_text(joined), pdf_text(one)
    assert re.sub(r"\s+", " ", a) == re.sub(r"\s+", " ", b)
