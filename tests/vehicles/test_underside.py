"""Underside data: the Hummer H3's published figures, derived angles, class defaults."""

from __future__ import annotations

import math

import pytest

from clearance.vehicles.errors import TableError
from clearance.vehicles.table import bundled_table, load_tables
from clearance.vehicles.underside import DEFAULT_CLEARANCE_M, underside_from


def test_hummer_h3_carries_its_published_figures():
    t = load_tables([bundled_table("paper_table1")], ["Hummer H3"])
    u = t.vehicles()[0].underside
    assert u is not None and u.note == "given"
    assert u.ground_clearance_m == pytest.approx(0.216, abs=1e-5)
    assert [round(math.degrees(a), 1) for a in (u.approach_rad, u.departure_rad,
                                                u.breakover_rad)] == [37.5, 34.6, 23.5]
    # its breakover height: the lines at 11.75 deg from contacts 2.842 m apart meet 0.296 m up
    assert u.mid_height_m(9.325 * 0.3048) == pytest.approx(1.4212 * math.tan(math.radians(11.75)),
                                                           abs=1e-3)


def test_bundled_vehicles_without_a_source_get_the_flagged_class_default():
    t = load_tables()
    for v in t.vehicles():
        u = v.underside
        assert u is not None
        if v.name == "Hummer H3":
            continue
        assert u.defaulted and "no source" in u.note, v.name
        assert u.ground_clearance_m == DEFAULT_CLEARANCE_M[v.vclass]
    notes = dict(zip(t.frame.name, t.frame.underside_note, strict=True))
    assert notes["Hummer H3"] == "given"
    assert notes["P"].startswith("ground clearance: default 0.10 m for passenger (no source)")


def test_angles_derived_from_the_clearance_and_the_clearance_from_the_breakover():
    u = underside_from(0.15, None, None, None, 3.0, 1.0, 0.5, "passenger")
    assert math.tan(u.approach_rad) == pytest.approx(0.15)
    assert math.tan(u.departure_rad) == pytest.approx(0.30)
    assert math.tan(u.breakover_rad / 2) == pytest.approx(0.10)
    assert u.mid_height_m(3.0) == pytest.approx(0.15)
    w = underside_from(None, None, None, math.radians(20.0), 3.0, 1.0, 0.5, "passenger")
    assert w.ground_clearance_m == pytest.approx(1.5 * math.tan(math.radians(10.0)))
    assert "derived from the breakover angle" in w.note and not w.defaulted


def test_a_clearance_of_zero_is_refused_naming_the_row(tmp_path):
    path = tmp_path / "t.csv"
    path.write_text("name,category,units,length,width,wheelbase,front_overhang,max_steer_deg,"
                    "ground_clearance,grade_limit_pct,source\n"
                    "Flat,passenger car,m,4.5,1.8,2.7,0.9,35,0,150,x\n")
    with pytest.raises(TableError) as info:
        load_tables([str(path)])
    text = str(info.value)
    assert "ground_clearance" in text and "grade_limit_pct" in text and ":2" in text
