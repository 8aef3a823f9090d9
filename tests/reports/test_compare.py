"""`clearance compare`: the table, the figures, and templates that agree with steady state."""

import csv
import math

import numpy as np
import pytest

from clearance.analysis.control_law import safe_pathway
from clearance.analysis.turning import turning_metrics
from clearance.reports.cli.main import main
from clearance.reports.documents.compare import PANEL_LINES, comparison_table, panels_of
from clearance.reports.documents.templates import (
    build_templates,
    steady_words,
    template_dimensions,
    template_path,
    write_template_sheets,
)
from clearance.vehicles.table import bundled_table, load_tables
from tests.reports.pdf import pdf_pages

NAMES = ["2009 Smart Car", "2010 Honda Odyssey", "P", "SU-30"]


def test_comparison_table_is_sorted_and_in_units():
    t = load_tables(None, NAMES)
    m, ft = comparison_table(t, "m"), comparison_table(t, "ft")
    assert list(m.wall_to_wall) == sorted(m.wall_to_wall)
    assert m.vehicle.iloc[0] == "2009 Smart Car" and m.vehicle.iloc[-1] == "SU-30"
    assert ft.ctr.iloc[-1] == pytest.approx(38.0)  # SU-30's published CTR, in feet
    assert m.ctr.iloc[-1] == pytest.approx(38.0 * 0.3048)


def test_template_path_geometry():
    p = template_path(12.0, 180.0, 10.0)
    assert p[0].tolist() == [-10.0, 0.0]
    assert p[-1, 0] == pytest.approx(-10.0) and p[-1, 1] == pytest.approx(24.0)


def test_180_degree_template_reaches_the_steady_swept_width():
    # The arc is 3 % wider than the minimum CTR; half a circle is long enough for a car
    # to settle, so the template's swept width is the steady-state width at that radius.
    t = load_tables([bundled_table("paper_table1")], ["2010 Honda Pilot"])
    (tpl,) = build_templates(t, 180.0)
    v = tpl.vehicle
    rho = math.sqrt(tpl.radius_m**2 - v.wheelbase_m**2)
    expected = float(safe_pathway(rho, v.wheelbase_m, v.width_m, v.front_overhang_m))
    assert tpl.run.followed
    assert tpl.swept.max_swept_width_m == pytest.approx(expected, rel=0.01)


def test_templates_are_drawn_at_the_minimum_ctr_their_titles_give():
    """The steered axle runs on the arc of the CTR at full lock itself (within 10 cm over the
    middle of a 180-degree turn), entered through its steering transition: the template is
    what its title says, not a 3 % wider circle."""
    from clearance.reports.documents.templates import arc_centre

    t = load_tables(None, ["P", "CITY-BUS", "WB-62"])
    for tpl in build_templates(t, 180.0):
        v = tpl.vehicle
        assert tpl.radius_m == math.hypot(v.min_radius_m, v.wheelbase_m)  # the CTR itself
        assert tpl.transition_m > 0 and tpl.run.followed
        tr = tpl.run.trajectory
        cx, cy = arc_centre(tpl)
        # the arc runs from below the centre (-90 degrees) round to above it (+90): its
        # middle third, well clear of the transitions
        polar = np.degrees(np.arctan2(tr.yf_m - cy, tr.xf_m - cx))
        middle = (np.abs(polar) < 30.0) & (tr.xf_m > cx)
        r = np.hypot(tr.xf_m[middle] - cx, tr.yf_m[middle] - cy)
        assert middle.any() and np.abs(r - tpl.radius_m).max() < 0.10, v.name


def test_compare_command_writes_table_and_figures(tmp_path, capsys):
    args = ["compare", "-o", str(tmp_path)]
    for n in NAMES[:2]:
        args += ["--vehicle", n]
    assert main(args) == 0
    rows = list(csv.DictReader(open(tmp_path / "compare.csv")))
    assert [r["vehicle"] for r in rows] == NAMES[:2]
    for stem in ("turning_circles", "rho_theta", "swept_width_theta", "templates_90",
                 "templates_180"):
        assert (tmp_path / f"{stem}.png").stat().st_size > 10_000
        assert (tmp_path / f"{stem}.svg").read_text().startswith("<?xml")
    assert "2010 Honda Odyssey" in capsys.readouterr().out
    assert len(pdf_pages((tmp_path / "templates.pdf").read_bytes())) == 2  # one per model


def test_template_dimensions_agree_with_the_steady_state():
    # a car through 180 degrees: at three quarters of the arc it turns steadily, so the
    # swept width on that ray and the inside radius are the steady-state ones (DESIGN §4)
    t = load_tables([bundled_table("paper_table1")], ["2010 Honda Pilot"])
    (tpl,) = build_templates(t, 180.0)
    v = tpl.vehicle
    d = template_dimensions(tpl)
    rho = math.sqrt(tpl.radius_m**2 - v.wheelbase_m**2)
    assert d["ctr_m"] == tpl.radius_m
    assert d["inside_radius_m"] == pytest.approx(rho - v.width_m / 2, rel=0.01)
    swept = float(safe_pathway(rho, v.wheelbase_m, v.width_m, v.front_overhang_m))
    assert d["swept"][2] == pytest.approx(swept, rel=0.02)
    assert math.isnan(d["trailer_inside_radius_m"]) and math.isnan(d["max_articulation_deg"])


def test_template_sheets_one_a3_page_per_vehicle_with_trailer_words(tmp_path):
    t = load_tables(None, ["P", "WB-62", "WB-40"])
    built = {a: build_templates(t, a) for a in (90.0, 180.0)}
    path = write_template_sheets(t, tmp_path / "templates.pdf", "ft", built)
    pages = pdf_pages(path.read_bytes())
    assert len(pages) == 3
    assert all(w == pytest.approx(420 * 72 / 25.4, abs=0.5) and
               h == pytest.approx(297 * 72 / 25.4, abs=0.5) for w, h in pages)
    m = turning_metrics(t).set_index("vehicle")
    assert steady_words(m.loc["WB-62"], "ft").startswith("no steady state at full lock")
    words = steady_words(m.loc["WB-40"], "ft")
    assert words.startswith("steady state") and words.endswith(" ft")
    assert steady_words(m.loc["P"], "ft") == ""
    # the trailer's own inside radius is measured and lies inside the combination's sweep
    d = template_dimensions(built[180.0][2])
    assert d["trailer_inside_radius_m"] >= d["inside_radius_m"] - 1e-9
    assert 0 < d["max_articulation_deg"] < 90


def test_compare_table_tells_the_wb62_from_the_wb67():
    c = comparison_table(load_tables(None, ["WB-62", "WB-67", "P"]), "ft")
    by = c.set_index("vehicle")
    # same tractor, so the same tractor columns; the design turn with the trailer differs
    # (Green Book minimum inside radii 7.9 ft and 1.9 ft)
    assert by.loc["WB-62", "ctr"] == by.loc["WB-67", "ctr"]
    assert by.loc["WB-62", "design_inside_radius"] == pytest.approx(7.9, abs=1.0)
    assert by.loc["WB-67", "design_inside_radius"] == pytest.approx(1.9, abs=1.0)
    assert not by.loc["WB-62", "steady_state"] and by.loc["P", "steady_state"] is None


def test_small_multiples_keep_each_panel_to_a_few_lines():
    t = load_tables(None)
    panels = panels_of(list(t.names), list(t.frame["category"]))
    assert sorted(n for _, ms in panels for n in ms) == sorted(t.names)
    assert max(len(ms) for _, ms in panels) <= PANEL_LINES
