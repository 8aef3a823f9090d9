"""`clearance compare`: the table, the figures, and templates that agree with steady state."""

import csv
import math

import pytest

from analysis.control_law import safe_pathway
from reports.cli import main
from reports.compare import comparison_table
from reports.templates import build_templates, template_path
from vehicles.table import bundled_table, load_tables

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
