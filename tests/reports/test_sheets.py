"""Swept-path sheets: the PDF, its pages and paper, the scale, the blocks."""

import hashlib
import math
import re
from pathlib import Path

import pytest

from clearance.networks.samples.build import sample_networks
from clearance.networks.selection import Selection
from clearance.reports.documents.drawing import Shown, view_bounds
from clearance.reports.documents.figures import shown_runs
from clearance.reports.documents.sheets import (
    FRAME_MM,
    MAX_SHEETS,
    PAPER_MM,
    SCALES,
    fit_scale,
    manoeuvre_box,
    pick_sheets,
    sheet_view,
    title_rows,
    vehicle_rows,
    verdict_rows,
    write_sheets,
)
from clearance.reports.study.run import run_study
from clearance.vehicles.table import bundled_table_paths, load_tables

NET = next(p for p in sample_networks() if p.stem.startswith("intersection"))
VEHICLES = ["P", "WB-67"]
PT_PER_MM = 72 / 25.4


@pytest.fixture(scope="module")
def study():
    table = load_tables(bundled_table_paths(), VEHICLES)
    return run_study([NET], table, workers=1, clearance_m=0.3,
                     selection=Selection(junctions=("T",)))


def pdf_pages(data: bytes) -> list[tuple[float, float]]:
    """The (width, height) in points of every page of a PDF (a minimal parse: matplotlib
    writes one ``/Type /Page`` object with its ``/MediaBox`` per page)."""
    pages = []
    for m in re.finditer(rb"<<[^>]*?/Type\s*/Page\b(?!s).*?>>", data, re.S):
        box = re.search(rb"/MediaBox\s*\[\s*0\s+0\s+([\d.]+)\s+([\d.]+)\s*\]", m.group(0))
        pages.append((float(box.group(1)), float(box.group(2))) if box else (0.0, 0.0))
    return pages


def test_a_pdf_per_network_with_the_expected_pages_on_a3_landscape(study, tmp_path):
    written = write_sheets(study, tmp_path, bundled_table_paths(), limit=3)
    assert written == [tmp_path / "intersection.pdf"]
    data = written[0].read_bytes()
    assert data.startswith(b"%PDF")
    runs = [r for r in study.records if r.verdict != "error"]
    pages = pdf_pages(data)
    assert len(pages) == min(3, len(runs)) == 3
    for w, h in pages:  # A3 landscape: 420 x 297 mm
        assert w == pytest.approx(PAPER_MM[0] * PT_PER_MM, abs=0.5)
        assert h == pytest.approx(PAPER_MM[1] * PT_PER_MM, abs=0.5)
        assert w > h


def test_the_sheets_go_worst_first_one_curve_each_before_the_second_vehicle(study):
    chosen = pick_sheets(study.records, 100)
    order = {"cannot-turn": 0, "fails": 1, "encroaches": 2, "clear": 3}
    curves = {r.curve_id for r in study.records}
    firsts = chosen[:len(curves)]
    assert {r.curve_id for r in firsts} == curves
    keys = [(order[r.verdict], r.margin_m) for r in firsts]
    assert keys == sorted(keys)
    assert len(chosen) == len([r for r in study.records if r.verdict != "error"])


def test_fit_scale_takes_the_first_scale_that_fits():
    fw, fh = FRAME_MM[2:]
    # exactly the frame at 1:250 fits 1:250, not 1:200
    assert fit_scale(fw * 0.25, fh * 0.25) == 250
    assert fit_scale(fw * 0.25 + 0.01, fh * 0.1) == 500
    assert fit_scale(fw * 0.2, fh * 0.2) == 200
    assert fit_scale(1e6, 1.0) == SCALES[-1]


def test_the_sheet_scale_fits_the_manoeuvre_and_is_exact(study):
    by_id = {c.curve_id: c for n in study.networks for c in n.curves}
    for r in pick_sheets(study.records, 4):
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
    for r in pick_sheets(study.records, 8):
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
    assert rows["date"] == "2026-01-02"
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
        if r.vehicle == "P":
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
            "--units", "ft"]
    assert main(args) == 0
    rows = (out / "clearance.csv").read_text().splitlines()[1:]
    pdf = out / "sheets" / "intersection.pdf"
    assert len(pdf_pages(pdf.read_bytes())) == min(MAX_SHEETS, len(rows))
    # a second run replaces the folder (the sheets are part of the report's layout)
    assert main(args) == 0 and pdf.is_file()


def test_analytic_studies_get_sheets_of_their_envelopes(tmp_path):
    table = load_tables(bundled_table_paths(), ["P"])
    study = run_study([NET], table, method="analytic", workers=1,
                      selection=Selection(junctions=("T",)))
    written = write_sheets(study, tmp_path, bundled_table_paths(), limit=2)
    assert len(pdf_pages(written[0].read_bytes())) == 2
