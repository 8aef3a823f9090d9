"""Loading vehicle tables: bundled tables, units, derived columns and every bad-row case."""

import math
from pathlib import Path

import pytest

from vehicles.errors import InputError, TableError
from vehicles.table import bundled_table, bundled_table_paths, load_tables

FT = 0.3048
HEADER = "name,category,units,length,width,wheelbase,front_overhang,source"


def write(tmp_path: Path, text: str, name: str = "t.csv") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def problems_of(path: Path) -> list[str]:
    with pytest.raises(TableError) as info:
        load_tables([path])
    return info.value.problems


def test_paper_table_loads_all_24_models_in_feet():
    t = load_tables([bundled_table("paper_table1")])
    assert len(t) == 24
    civic = t.frame.iloc[0]
    assert civic["name"] == "2010 Honda Civic Coupe"
    assert civic["wheelbase_m"] == pytest.approx(8.692 * FT)
    assert civic["rear_overhang_m"] == pytest.approx((14.625 - 8.692 - 2.566) * FT)
    assert math.degrees(civic["max_inner_steer_rad"]) == pytest.approx(40.0)
    assert (t.frame["w_l"] > 0).all()


def test_smart_w_l_disagreement_is_a_warning_naming_the_row():
    t = load_tables([bundled_table("paper_table1")])
    assert len(t.warnings) == 1
    assert "Smart" in t.warnings[0] and "w_l" in t.warnings[0] and "0.835" in t.warnings[0]


def test_every_bundled_table_loads_with_unique_names():
    t = load_tables()
    assert len(t) == len(set(t.names)) >= 24
    assert len(bundled_table_paths()) >= 2


def test_select_rows_by_name_in_given_order():
    t = load_tables([bundled_table("paper_table1")], ["2009 Smart Car", "2010 Honda Pilot"])
    assert t.names == ["2009 Smart Car", "2010 Honda Pilot"]


def test_unknown_name_suggests_a_close_one():
    with pytest.raises(InputError, match="did you mean '2009 Smart Car'"):
        load_tables([bundled_table("paper_table1")], ["2009 Smart"])


def test_lock_forms_agree_for_the_same_vehicle(tmp_path):
    # P car (DESIGN.md check figure): l = 11 ft, B = 7 ft, CTR = 21 ft; the same lock as an
    # inner-wheel angle: cot(delta_i) = (rho - w/2)/l with rho = sqrt(21^2 - 11^2).
    rho = math.sqrt(21**2 - 11**2)
    inner = math.degrees(math.atan2(11, rho - 3.5))
    curb = 2 * math.hypot(rho + 3.5, 11)
    wall = 2 * math.hypot(rho + 3.5, 14)
    p = write(tmp_path, HEADER + ",ctr,max_steer_deg,curb_to_curb,wall_to_wall\n"
              f"P,car,ft,19,7,11,3,test,21,{inner},,\n"
              f"P2,car,ft,19,7,11,3,test,,,{curb},\n"
              f"P3,car,ft,19,7,11,3,test,,,,{wall}\n")
    f = load_tables([p]).frame
    for i in range(3):
        assert f["min_radius_m"][i] == pytest.approx(rho * FT, rel=1e-9)
        assert math.degrees(f["max_inner_steer_rad"][i]) == pytest.approx(inner, rel=1e-6)


def test_metres_and_feet_give_the_same_vehicle(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg\n"
              "A,car,ft,15,6,9,3,test,38\n"
              f"B,car,m,{15 * FT},{6 * FT},{9 * FT},{3 * FT},test,38\n")
    f = load_tables([p]).frame
    for col in ("length_m", "wheelbase_m", "min_radius_m", "rear_overhang_m"):
        assert f[col][0] == pytest.approx(f[col][1], rel=1e-12)


def test_defaults_are_documented_values(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg\nA,car,m,4.5,1.8,2.7,0.9,test,35\n")
    row = load_tables([p]).frame.iloc[0]
    assert row["track_m"] == 1.8  # the body width
    assert row["steering"] == "ackermann" and row["ackermann_pct"] == 100.0
    assert row["steered_axle"] == "front"
    assert row["max_steer_rate_rad_s"] == pytest.approx(2 * row["max_steer_rad"] / 4.0)


def test_trailer_rear_overhang_from_overall_length(tmp_path):
    p = write(tmp_path, HEADER + ",ctr,hitch_offset,trailer_wheelbase,trailer_width\n"
              "WB,semi,ft,69,8.5,19.5,4,test,41,0,41,8.5\n")
    row = load_tables([p]).frame.iloc[0]
    assert row["trailer_rear_overhang_m"] == pytest.approx(4.5 * FT)
    assert row["rear_overhang_m"] == 0.0


# --- every bad-row case: message names file, line, column, value and reason -------------

def test_missing_and_unknown_columns(tmp_path):
    p = write(tmp_path, "name,category,units,length,widht,wheelbase,source\nA,c,m,4,1.8,2.7,x\n")
    probs = problems_of(p)
    assert any("missing required column 'front_overhang'" in s for s in probs)
    assert any("missing required column 'width'" in s for s in probs)
    assert any("unknown column 'widht'" in s and "did you mean 'width'" in s for s in probs)
    assert all(str(p) in s for s in probs)


def test_not_a_number_negative_and_zero(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg\n"
              "A,car,m,4.5,wide,2.7,0.9,test,35\n"
              "B,car,m,4.5,1.8,-2.7,0.9,test,35\n"
              "C,car,m,4.5,1.8,0,0.9,test,35\n")
    probs = problems_of(p)
    assert any(":2 (A): column width: 'wide': not a number" in s for s in probs)
    assert any(":3 (B): column wheelbase: '-2.7': must be greater than zero" in s for s in probs)
    assert any(":4 (C): column wheelbase: '0': must be greater than zero" in s for s in probs)


def test_lock_of_90_degrees_or_more(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg\nA,car,m,4.5,1.8,2.7,0.9,test,95\n"
              "B,car,m,4.5,1.8,2.7,0.9,test,90\n")
    probs = problems_of(p)
    assert len(probs) == 2 and all("90 degrees or more" in s for s in probs)


def test_radius_lock_that_needs_more_than_90_degrees(tmp_path):
    # CTR barely above the wheelbase: rho = 0.5 m < w/2 = 0.9 m
    p = write(tmp_path, HEADER + ",ctr\nA,car,m,4.5,1.8,2.7,0.9,test,2.746\n")
    assert "90 degrees or more" in problems_of(p)[0]
    p = write(tmp_path, HEADER + ",ctr\nA,car,m,4.5,1.8,2.7,0.9,test,2.5\n")
    assert "no such turning circle" in problems_of(p)[0]


def test_negative_rear_overhang(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg\nA,car,m,3.0,1.8,2.7,0.9,test,35\n")
    (msg,) = problems_of(p)
    assert "column length" in msg and "rear overhang comes out -0.6" in msg


def test_two_lock_columns_that_disagree(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg,ctr\nA,car,m,4.5,1.8,2.7,0.9,test,35,8\n")
    (msg,) = problems_of(p)
    assert "disagree" in msg and "max_steer_deg" in msg and "ctr" in msg


def test_no_lock_at_all(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg\nA,car,m,4.5,1.8,2.7,0.9,test,\n")
    assert "steering lock needs one of" in problems_of(p)[0]


def test_duplicate_names_across_tables(tmp_path):
    a = write(tmp_path, HEADER + ",max_steer_deg\nA,car,m,4.5,1.8,2.7,0.9,test,35\n", "a.csv")
    b = write(tmp_path, HEADER + ",max_steer_deg\nA,car,m,4.5,1.8,2.7,0.9,test,35\n", "b.csv")
    with pytest.raises(TableError) as info:
        load_tables([a, b])
    assert "duplicate name" in info.value.problems[0] and "a.csv:2" in info.value.problems[0]


def test_every_bad_row_is_reported_at_once(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg\n"
              "A,car,m,4.5,1.8,2.7,0.9,test,95\n"
              "B,car,yd,4.5,1.8,2.7,0.9,test,35\n"
              "C,car,m,4.5,1.8,2.7,0.9,test,35\n"
              "D,car,m,1.0,1.8,2.7,0.9,test,35\n")
    probs = problems_of(p)
    assert len(probs) == 3
    assert [s.split(":")[1].split(" ")[0] for s in probs] == ["2", "3", "5"]


def test_missing_file_empty_file_and_directory(tmp_path):
    with pytest.raises(InputError, match="no such vehicle table"):
        load_tables([tmp_path / "none.csv"])
    with pytest.raises(InputError, match="empty file"):
        load_tables([write(tmp_path, "")])
    with pytest.raises(InputError, match="is a directory"):
        load_tables([tmp_path])


def test_rack_pinion_needs_its_linkage(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg,steering\nA,car,m,4.5,1.8,2.7,0.9,test,30,"
              "rack_pinion\n")
    assert "needs the linkage columns" in problems_of(p)[0]


def test_rack_pinion_row_with_linkage_loads(tmp_path):
    p = write(tmp_path, HEADER + ",track,max_steer_deg,steering,pinion_radius,rack_length,"
              "steering_arm,tie_rod,rack_offset,steering_range_deg\n"
              "A,car,m,4.5,1.8,2.7,0.9,test,1.0,15,rack_pinion,0.0057,0.5,0.1,0.248,0.2,225\n")
    row = load_tables([p]).frame.iloc[0]
    assert math.degrees(row["max_inner_steer_rad"]) == pytest.approx(15.0)
    assert 0 < row["max_outer_steer_rad"] < row["max_inner_steer_rad"]


def test_vclass_defaults_from_the_category_and_can_be_given(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg,vclass\n"
              "A,passenger car,m,4.5,1.8,2.7,0.9,test,35,\n"
              "B,city bus,m,12,2.5,6,2.5,test,40,\n"
              "C,semitrailer combination,m,20,2.5,6,1.2,test,40,\n"
              "D,passenger car,m,5,2,3,1,test,35,Taxi\n")
    t = load_tables([p])
    assert [v.vclass for v in t.vehicles()] == ["passenger", "bus", "trailer", "taxi"]
    assert list(t.frame["vclass"]) == ["passenger", "bus", "trailer", "taxi"]
    # the bundled tables: every row has the class its category names
    bundled = {v.name: v.vclass for v in load_tables().vehicles()}
    assert bundled["P"] == "passenger" and bundled["CITY-BUS"] == "bus"
    assert bundled["SU-30"] == "truck" and bundled["WB-67"] == "trailer"


def test_unknown_vclass_is_a_row_problem(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg,vclass\nA,car,m,4.5,1.8,2.7,0.9,test,35,"
              "hovercraft\n")
    (problem,) = problems_of(p)
    assert "column vclass" in problem and "hovercraft" in problem
