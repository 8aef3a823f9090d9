"""Turning geometry against closed forms, published check figures and invariants."""

import math

import numpy as np
import pandas as pd
import pytest

from clearance.analysis.control_law import (
    rho_of_theta,
    safe_pathway,
    safe_pathway_of_theta,
    theta_of_rho,
)
from clearance.analysis.turning import (
    articulation_limited_rho,
    full_lock_metrics,
    inside_radius,
    steering_sweep,
    trailer_steady_state,
    turning_metrics,
)
from clearance.vehicles.lock import rho_from_ctr
from clearance.vehicles.steering import ackermann_angles
from clearance.vehicles.table import bundled_table, load_tables

FT = 0.3048


@pytest.mark.parametrize("l, B, ctr, expected", [(11, 7, 21, 14.4), (20, 8, 38, 28.3)])
def test_design_md_check_figures(l, B, ctr, expected):
    assert float(inside_radius(rho_from_ctr(ctr, l), B)) == pytest.approx(expected, abs=0.05)


def test_paper_eq1_equals_the_ackermann_radius_and_eq3_inverts_it():
    l, w = 2.9, 1.6
    phi = np.linspace(0.01, 0.75, 60)
    inner, outer = ackermann_angles(phi, l, w)
    theta = inner - outer
    np.testing.assert_allclose(rho_of_theta(theta, l, w), l / np.tan(phi), rtol=1e-9)
    rho = np.linspace(3.0, 300.0, 100)
    np.testing.assert_allclose(rho_of_theta(theta_of_rho(rho, l, w), l, w), rho, rtol=1e-9)
    # signed: a right turn mirrors a left turn
    np.testing.assert_allclose(rho_of_theta(-theta, l, w), -l / np.tan(phi), rtol=1e-9)


def test_safe_pathway_is_the_body_width_straight_ahead_and_grows_with_lock():
    assert float(safe_pathway_of_theta(0.0, 2.7, 1.5, 1.8, 0.9)) == 1.8
    widths = safe_pathway_of_theta(np.linspace(0.001, 0.2, 50), 2.7, 1.5, 1.8, 0.9)
    assert np.all(np.diff(widths) > 0)
    # and the difference form agrees with the plain formula where both are exact
    rho = 6.0
    plain = math.hypot(rho + 0.9, 3.6) - (rho - 0.9)
    assert float(safe_pathway(rho, 2.7, 1.8, 0.9)) == pytest.approx(plain, rel=1e-12)


def test_paper_curb_to_curb_diameters_for_smart_and_pilot():
    # docs/design.md: the paper's equations with delta_max = 40 deg give ~27.7 ft and ~39.2 ft.
    t = load_tables([bundled_table("paper_table1")], ["2009 Smart Car", "2010 Honda Pilot"])
    m = turning_metrics(t)
    assert m.curb_to_curb_m[0] / FT == pytest.approx(27.7, abs=0.05)
    assert m.curb_to_curb_m[1] / FT == pytest.approx(39.2, abs=0.1)


def test_full_lock_metrics_relations_on_the_paper_table():
    t = load_tables([bundled_table("paper_table1")])
    f, m = t.frame, full_lock_metrics(t.frame)
    l, w, B, a = f.wheelbase_m, f.track_m, f.width_m, f.front_overhang_m
    rho = m.min_radius_m
    # Ackermann at lock: rho = l cot(delta_i) + w/2 = l cot(delta_o) - w/2
    np.testing.assert_allclose(l / np.tan(m.max_steer_rad) + w / 2, rho, rtol=1e-9)
    np.testing.assert_allclose(l / np.tan(m.outer_steer_rad) - w / 2, rho, rtol=1e-9)
    np.testing.assert_allclose(rho_of_theta(m.ackermann_angle_rad, l, w), rho, rtol=1e-9)
    np.testing.assert_allclose(m.wall_to_wall_m / 2 - m.inside_radius_m, m.swept_width_m,
                               rtol=1e-9)
    np.testing.assert_allclose(m.ctr_m**2, rho**2 + l**2, rtol=1e-12)
    assert np.all(m.wall_to_wall_m > m.curb_to_curb_m)
    assert np.all(m.offtracking_m > 0) and np.all(m.offtracking_m < l)
    np.testing.assert_allclose(m.swept_width_m,
                               np.hypot(rho + B / 2, l + a) - (rho - B / 2), rtol=1e-12)


def test_rear_steering_uses_the_rear_overhang():
    base = dict(wheelbase_m=[2.7], track_m=[1.5], width_m=[1.8], front_overhang_m=[0.9],
                rear_overhang_m=[1.4], max_inner_steer_rad=[0.6], max_outer_steer_rad=[0.5],
                max_steer_rad=[0.55])
    front = full_lock_metrics(pd.DataFrame(base | {"steered_axle": ["front"]}))
    rear = full_lock_metrics(pd.DataFrame(base | {"steered_axle": ["rear"]}))
    rho = 2.7 / math.tan(0.55)
    assert rear.wall_to_wall_m[0] == pytest.approx(2 * math.hypot(rho + 0.9, 2.7 + 1.4))
    assert front.wall_to_wall_m[0] == pytest.approx(2 * math.hypot(rho + 0.9, 2.7 + 0.9))
    assert rear.inside_radius_m[0] == front.inside_radius_m[0]


def test_trailer_steady_state_is_a_consistent_rigid_motion():
    # Put the tractor's rear axle at (rho, 0) heading +y around the origin (a left turn),
    # hitch e behind it, trailer axle l_t behind the hitch along the trailer's heading.
    for rho, e, lt in [(12.0, 0.0, 8.0), (9.0, 1.2, 7.0), (15.0, -0.6, 12.5)]:
        r_t, psi = trailer_steady_state(rho, e, lt)
        theta = math.pi / 2
        hitch = np.array([rho, 0.0]) - e * np.array([math.cos(theta), math.sin(theta)])
        th_t = theta - float(psi)
        axle = hitch - lt * np.array([math.cos(th_t), math.sin(th_t)])
        assert np.hypot(*axle) == pytest.approx(float(r_t), rel=1e-12)
        # the trailer axle moves tangentially: its heading is perpendicular to the radius
        heading = np.array([math.cos(th_t), math.sin(th_t)])
        assert float(np.dot(heading, axle)) == pytest.approx(0.0, abs=1e-9)
        # and its radius follows the closed form sqrt(rho^2 + e^2 - l_t^2)
        assert float(r_t) == pytest.approx(math.sqrt(rho**2 + e**2 - lt**2))
    # articulation limit: the radius that needs exactly the limit gives the limit back
    rho_lim = articulation_limited_rho(0.7, 0.5, 10.0)
    assert float(trailer_steady_state(rho_lim, 0.5, 10.0)[1]) == pytest.approx(0.7)


def test_trailer_columns_and_articulation_limit(tmp_path):
    p = tmp_path / "semi.csv"
    p.write_text("name,category,units,length,width,wheelbase,front_overhang,source,ctr,"
                 "hitch_offset,trailer_wheelbase,trailer_width,max_articulation_deg\n"
                 "A,semi,ft,69,8.5,19.5,4,test,50,0,41,8.5,89\n"
                 "B,semi,ft,69,8.5,19.5,4,test,50,0,41,8.5,30\n")
    m = full_lock_metrics(load_tables([p]).frame)
    rho = math.sqrt(50**2 - 19.5**2) * FT
    assert m.trailer_radius_m[0] == pytest.approx(math.sqrt(rho**2 - (41 * FT) ** 2))
    assert not m.articulation_limited[0] and m.articulation_limited[1]
    assert math.degrees(m.trailer_articulation_rad[1]) == pytest.approx(30.0)
    assert m.combination_swept_width_m[0] > m.swept_width_m[0]
    assert m.trailer_offtracking_m[0] > m.offtracking_m[0]


def test_steering_sweep_goes_from_straight_to_full_lock():
    t = load_tables([bundled_table("paper_table1")], ["2010 Honda Pilot"])
    s = steering_sweep(t, "2010 Honda Pilot", 30)
    assert s.rho_m.iloc[0] == np.inf and s.swept_width_m.iloc[0] == pytest.approx(6.541 * FT)
    assert math.degrees(s.inner_rad.iloc[-1]) == pytest.approx(40.0, abs=1e-6)
    assert np.all(np.diff(s.rho_m.iloc[1:]) < 0)
    assert s.rho_m.iloc[-1] == pytest.approx(t.frame.min_radius_m[0], rel=1e-6)


def test_aashto_single_units_steady_state_is_the_limit_of_the_published_turn():
    # Green Book Table 2-2a minimum inside radii come from a 180-degree turn at the CTR
    # (tests/analysis/test_design_turn.py reproduces them within 0.15 ft); the steady state
    # is that turn continued for ever, so it cuts in as far or further, but not by much.
    t = load_tables([bundled_table("aashto_green_book")])
    f = t.frame[t.frame["trailer_wheelbase_m"].isna() & t.frame["ref_inside_radius_m"].notna()]
    m = full_lock_metrics(f)
    gap = (f["ref_inside_radius_m"] - m.inside_radius_m) / FT
    assert len(f) >= 6
    assert gap.min() > -0.05 and gap.max() < 0.7


def test_no_steady_state_where_the_trailer_would_jackknife_at_full_lock():
    # WB-62 at its Green Book lock (curb to curb 89.6 ft): the kingpin's radius (36.1 ft)
    # is shorter than the trailer wheelbase (41 ft), so sqrt(rho^2 + e^2 - l_t^2) is not
    # real; the articulation limit (90 degrees) would put the trailer axle on the centre.
    t = load_tables([bundled_table("aashto_green_book")], ["WB-40", "WB-62", "WB-67", "P"])
    m = full_lock_metrics(t.frame)
    assert m.min_radius_m[1] / FT == pytest.approx(36.08, abs=0.01)
    assert m.steady_state.tolist() == [True, False, False, True]
    assert m.articulation_limited.tolist() == [False, True, True, False]
    assert m.combination_inside_radius_m[1:3].isna().all()
    assert m.trailer_articulation_rad[1:3].isna().all()
    # WB-40 keeps its steady state: sqrt(33.76^2 - 25.5^2) - 4 = 18.12 ft
    assert m.combination_inside_radius_m[0] / FT == pytest.approx(18.12, abs=0.01)
