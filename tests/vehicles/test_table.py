"""Loading vehicle tables: bundled tables, units, derived columns and every bad-row case."""

import math
from pathlib import Path

import pytest

from clearance.vehicles.errors import InputError, TableError
from clearance.vehicles.schema import ALL_COLUMNS
from clearance.vehicles.table import bundled_table, bundled_table_paths, load_tables
from tests.timeouts import within

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
    # P car (docs/design.md check figure): l = 11 ft, B = 7 ft, CTR = 21 ft; the same lock as an
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
    assert any(":3 (B): column wheelbase: '-2.7': outside the range [0.3, 20] m" in s
               for s in probs)
    assert any(":4 (C): column wheelbase: '0': outside the range [0.3, 20] m" in s for s in probs)


def test_lock_of_90_degrees_or_more(tmp_path):
    p = write(tmp_path, HEADER + ",max_steer_deg\nA,car,m,4.5,1.8,2.7,0.9,test,95\n"
              "B,car,m,4.5,1.8,2.7,0.9,test,90\n")
    probs = problems_of(p)
    assert len(probs) == 2 and all("outside the range [1, 80] deg" in s for s in probs)


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


def test_a_rear_steered_vehicle_with_a_trailer_is_a_table_problem(tmp_path):
    # the tracking model cannot tow from a steered axle: the table says so, naming the row
    p = write(tmp_path, HEADER + ",curb_to_curb,hitch_offset,trailer_wheelbase,steered_axle"
              "\nRS,truck,m,16,2.5,5,1.2,test,25,0,8,rear\n")
    (msg,) = problems_of(p)
    assert ":2 (RS): column steered_axle" in msg and "trailer is not supported" in msg


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


# -- hostile files and cells


ROW = "A,car,m,4.5,1.8,2.7,0.9,test,35\n"


@pytest.mark.parametrize("kind", ["fifo", "device", "directory", "symlink-loop",
                                  "under-a-file"])
def test_only_regular_files_are_read_as_tables(tmp_path, kind):
    import os

    p = tmp_path / "t.csv"
    if kind == "fifo":
        os.mkfifo(p)  # opening it for reading would wait for a writer
        expected = "is a FIFO, not a regular file"
    elif kind == "device":
        p = Path("/dev/zero")  # endless
        expected = "is a character device, not a regular file"
    elif kind == "directory":
        p.mkdir()
        expected = "is a directory, not a regular file"
    elif kind == "symlink-loop":
        os.symlink(tmp_path / "u.csv", p)
        os.symlink(p, tmp_path / "u.csv")
        expected = "cannot be read (Too many levels of symbolic links)"
    else:  # unreadable even for root: a path through a regular file
        write(tmp_path, HEADER + ",max_steer_deg\n" + ROW, "f")
        p = tmp_path / "f" / "t.csv"
        expected = "cannot be read (Not a directory)"
    with pytest.raises(InputError) as info:
        within(10, load_tables, [p])
    assert str(info.value) == f"{p}: {expected}"


def test_a_table_over_the_size_cap_is_refused(tmp_path, monkeypatch):
    p = write(tmp_path, HEADER + ",max_steer_deg\n" + ROW * 100)  # 3,500 bytes
    monkeypatch.setenv("CLEARANCE_MAX_TABLE_MB", "0.001")
    with pytest.raises(InputError) as info:
        load_tables([p])
    assert str(info.value) == (f"{p}: refused: the vehicle table is larger than 0.001 MB; to "
                               "read it anyway, set the environment variable "
                               "CLEARANCE_MAX_TABLE_MB higher")
    monkeypatch.setenv("CLEARANCE_MAX_TABLE_MB", "0.01")
    with pytest.raises(TableError, match="duplicate name"):  # read, and its rows checked
        load_tables([p])


def test_not_utf8_and_nul_bytes_name_the_line(tmp_path):
    p = tmp_path / "t.csv"
    p.write_bytes((HEADER + ",max_steer_deg\n" + ROW).encode() + b"B\xe9,car\n")
    with pytest.raises(InputError, match=r"t\.csv:3: not UTF-8 text"):
        load_tables([p])
    p.write_bytes((HEADER + ",max_steer_deg\n" + ROW + "B\0,car\n").encode())
    with pytest.raises(InputError, match=r"t\.csv:3: a NUL character"):
        load_tables([p])


def test_a_byte_order_mark_is_read_and_utf16_is_refused(tmp_path):
    text = HEADER + ",max_steer_deg\n" + ROW
    p = tmp_path / "t.csv"
    p.write_bytes(b"\xef\xbb\xbf" + text.encode())  # as spreadsheets write it
    assert load_tables([p]).names == ["A"]
    p.write_bytes(text.encode("utf-16"))
    with pytest.raises(InputError, match=r"t\.csv:1: not UTF-8 text \(byte 0: b'\\xff'\)"):
        load_tables([p])


def test_a_quoted_line_break_in_a_name_is_refused_and_later_lines_stay_right(tmp_path):
    # it silently became "CarTwo", and every later line number was one low
    p = write(tmp_path, HEADER + ',max_steer_deg\n"Car\nTwo",car,m,4.5,1.8,2.7,0.9,test,35\n'
              "B,car,m,4.5,1.8,-1,0.9,test,35\n")
    probs = problems_of(p)
    assert probs[0] == (f"{p}:2: column name: 'Car\\nTwo': holds a line or paragraph "
                        "separator (U+000A)")
    assert probs[1].startswith(f"{p}:4 (B): column wheelbase: '-1': outside the range")
    assert len(probs) == 2


def test_a_line_separator_in_a_name_is_named_as_such(tmp_path):
    # U+2028 is no line break in CSV: it was read as one, giving "has 1 fields"
    p = write(tmp_path, HEADER + ",max_steer_deg\nCar\u2028Two,car,m,4.5,1.8,2.7,0.9,test,35\n"
              + "B,car,m,4.5,1.8,2.7,0.9,test,35\n")
    assert problems_of(p) == [f"{p}:2: column name: 'Car\\u2028Two': holds a line or "
                              "paragraph separator (U+2028)"]
    p = write(tmp_path, HEADER + ",max_steer_deg\nCar\x07,car,m,4.5,1.8,2.7,0.9,test,35\n")
    assert problems_of(p) == [f"{p}:2: column name: 'Car\\x07': holds a control character "
                              "(U+0007)"]


def test_crlf_and_a_quoted_comma_keep_their_lines(tmp_path):
    p = tmp_path / "t.csv"
    p.write_bytes((HEADER + ",max_steer_deg\r\n" + '"Van, long",car,m,4.5,1.8,2.7,0.9,"a, b",'
                   "35\r\n\r\nB,car,m,4.5,1.8,2.7,0.9,test,35\r\n").encode())
    t = load_tables([p])
    assert t.names == ["Van, long", "B"]
    assert list(t.frame["line"]) == [2, 4]
    assert t.frame["source"].iloc[0] == "a, b"
    # a line break in any text cell is refused, at the line its row starts on
    p.write_bytes((HEADER + ",max_steer_deg\r\n" + 'V,car,m,4.5,1.8,2.7,0.9,"a\r\nb",35\r\n'
                   "B,car,m,4.5,1.8,2.7,0.9,test,x\r\n").encode())
    probs = problems_of(p)
    assert probs[0] == (f"{p}:2 (V): column source: 'a\\r\\nb': holds a line or paragraph "
                        "separator (U+000D)")
    assert probs[1] == f"{p}:4 (B): column max_steer_deg: 'x': not a number"


def test_ackermann_beyond_its_range_and_an_outer_wheel_turning_back(tmp_path):
    # 400 % gave an outer wheel of -59.8 degrees, accepted
    p = write(tmp_path, HEADER + ",max_steer_deg,ackermann_pct\n" + ROW[:-1] + ",400\n")
    (prob,) = problems_of(p)
    assert prob.startswith(f"{p}:2 (A): column ackermann_pct: '400': outside the range "
                           "[0, 150] %")
    # within the range, on a vehicle whose ideal outer wheel lags far behind: refused by
    # the angle it really comes out at
    p = write(tmp_path, HEADER + ",max_steer_deg,ackermann_pct\n"
              "W,car,m,4.5,3,0.5,0.9,test,80,150\n")
    (prob,) = problems_of(p)
    assert prob.startswith(f"{p}:2 (W): column ackermann_pct: the outer wheel comes out at -")
    assert "at full lock (inner 80.0)" in prob


@pytest.mark.parametrize("text, expected", [
    ("0:100;10:400", "table value 400 outside the range [0, 150] %"),
    ("0:100;10:nan", "table value nan outside the range [0, 150] %"),
    ("nan:100;10:90", "breakpoint angle nan outside +/-1800 degrees of steering-wheel angle"),
    ("0:100;inf:90", "breakpoint angle inf outside +/-1800 degrees of steering-wheel angle"),
    ("1e300:100;1e301:90",
     "breakpoint angle 1e+300 outside +/-1800 degrees of steering-wheel angle"),
])
def test_breakpoint_tables_out_of_range(tmp_path, text, expected):
    p = write(tmp_path, HEADER + ",max_steer_deg,ackermann_pct\n" + ROW[:-1] + f",{text}\n")
    assert problems_of(p) == [f"{p}:2 (A): column ackermann_pct: {text!r}: {expected}"
                              + (f" ({ALL_COLUMNS['ackermann_pct'].why})" if "table value"
                                 in expected else "")]
    p = write(tmp_path, HEADER + ",max_steer_deg,ackermann_pct\n" + ROW[:-1]
              + ",-900:100;0:80;900:120\n")
    assert load_tables([p]).frame["ackermann_pct"].iloc[0] == "-900:100;0:80;900:120"


def test_a_hitch_ahead_of_the_front_axle_is_refused(tmp_path):
    # 6 m ahead of the rear axle of a 3.5 m wheelbase: a trailer rear overhang of 102.8 m
    head = HEADER + ",max_steer_deg,hitch_offset,trailer_wheelbase\n"
    p = write(tmp_path, head + "T,truck,m,15,2.5,3.5,1.2,test,40,-6,8\n")
    assert problems_of(p) == [
        f"{p}:2 (T): column hitch_offset: -6 m: puts the hitch at or ahead of the front axle "
        "(wheelbase 3.5 m); a towed unit is hitched behind it"]
    p = write(tmp_path, head + "T,truck,m,15,2.5,3.5,1.2,test,40,-0.5,8\n")  # a fifth wheel
    assert load_tables([p]).frame["hitch_offset_m"].iloc[0] == pytest.approx(-0.5)


def test_a_name_or_a_table_given_twice_is_taken_once(tmp_path):
    table = bundled_table("aashto_green_book")
    t = load_tables([table, table, Path(str(table).replace("/tables/", "/tables/./"))],
                    ["P", "SU-30", "P"])
    assert t.names == ["P", "SU-30"]


# -- generated malformed tables (hypothesis): nothing but InputError escapes, nothing hangs

from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from clearance.vehicles.schema import OPTIONAL, REQUIRED, TRAILER  # noqa: E402

_NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.floats(-100, 100).map(lambda x: f"{x:.3g}"),
    st.sampled_from(["", "0", "-0", "1e-300", "1e300", "nan", "inf", "-inf", "90", "89.99",
                     "1_0", "0x10", "1,5", "10:1;20:2", "0:100;-5:50", "a:b", ":", ";"]),
)
_TEXT = st.text(alphabet=st.sampled_from(list('aZ9 ,";:\n\r\t\u2028\u0085\x00\x07é#-.')),
                max_size=12)
_CELL = st.one_of(_NUMBERS, _TEXT, st.sampled_from(["m", "ft", "ackermann", "parallel",
                                                   "rack_pinion", "front", "rear", "P"]))


def _quoted(cell: str) -> str:
    return '"' + cell.replace('"', '""') + '"' if any(c in cell for c in ',"\n\r') else cell


@st.composite
def _tables(draw) -> str:
    names = [c.name for c in REQUIRED]
    extra = draw(st.lists(st.sampled_from([c.name for c in OPTIONAL + TRAILER]
                                          + ["max_steer_deg", "ctr", "curb_to_curb",
                                             "bogus"]), max_size=6))
    header = draw(st.permutations(names + extra))
    if draw(st.booleans()):
        header = header[: draw(st.integers(0, len(header)))]
    rows = draw(st.lists(st.lists(_CELL, min_size=max(len(header) - 1, 0),
                                  max_size=len(header) + 1), max_size=4))
    eol = draw(st.sampled_from(["\n", "\r\n", "\r"]))
    lines = [",".join(header)] + [",".join(map(_quoted, r)) for r in rows]
    return eol.join(lines) + draw(st.sampled_from(["", eol, '"']))


@settings(max_examples=200, deadline=2000, suppress_health_check=[HealthCheck.too_slow])
@given(text=_tables())
def test_generated_tables_raise_nothing_but_input_errors(tmp_path_factory, text):
    p = tmp_path_factory.mktemp("h") / "t.csv"
    p.write_text(text, encoding="utf-8", errors="surrogatepass")
    try:
        table = load_tables([p])
    except InputError:
        return
    for row in table.vehicles():  # what loads is usable
        assert row.wheelbase_m > 0 and math.isfinite(row.max_steer_rad)
    assert set(table.frame.columns) >= {"name", "wheelbase_m"}


@settings(max_examples=100, deadline=2000)
@given(data=st.binary(max_size=400))
def test_generated_bytes_raise_nothing_but_input_errors(tmp_path_factory, data):
    p = tmp_path_factory.mktemp("b") / "t.csv"
    p.write_bytes((HEADER + ",max_steer_deg\n").encode() + data)
    try:
        load_tables([p])
    except InputError:
        pass


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
