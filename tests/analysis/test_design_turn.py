"""The design turn against the Green Book's published inside radii, closed forms and invariants."""

import math

import numpy as np
import pandas as pd
import pytest
import shapely

from clearance.analysis.design_turn import design_turn_inside_radius
from clearance.analysis.envelope import swept_path
from clearance.analysis.tracking import TrackingSettings, simulate_batch
from clearance.analysis.turning import full_lock_metrics
from clearance.reports.documents.templates import template_path
from clearance.vehicles.table import bundled_table, load_tables

FT = 0.3048

#: Bundled AASHTO vehicles whose published minimum inside radius was found (Green Book
#: Table 2-2a; aashto_green_book.md): each must be in the table with it.
PUBLISHED = {"P": 14.4, "SU-30": 28.4, "CITY-BUS": 24.5, "S-BUS36": 23.8, "WB-40": 19.3,
             "WB-62": 7.4, "A-BUS": 21.3, "BUS-45": 24.7, "S-BUS40": 25.3}


@pytest.fixture(scope="module")
def aashto():
    table = load_tables([bundled_table("aashto_green_book")])
    turn = design_turn_inside_radius(table.frame)
    return table.frame.assign(turn_in_ft=turn.inside_radius_m / FT, turn_ctr_ft=turn.ctr_m / FT)


def test_every_published_inside_radius_is_in_the_table(aashto):
    published = aashto.set_index("name")["ref_inside_radius_m"].dropna() / FT
    assert published.round(1).to_dict() == PUBLISHED


@pytest.mark.parametrize("name", sorted(PUBLISHED))
def test_180_degree_turn_at_the_ctr_gives_the_published_inside_radius(aashto, name):
    row = aashto.set_index("name").loc[name]
    assert row.turn_in_ft == pytest.approx(PUBLISHED[name], abs=0.15)


def test_wb62_lock_is_the_published_ctr(aashto):
    # The Green Book's 44.8 ft is the outer front wheel's path (curb to curb), whose
    # CTR is 41.0 ft; read as the body corner's (wall to wall) it gave 39.1 ft and 4.0 ft.
    rows = aashto.set_index("name")
    assert rows.loc["WB-62", "turn_ctr_ft"] == pytest.approx(41.0, abs=0.05)
    assert rows.loc["WB-67", "turn_ctr_ft"] == pytest.approx(41.0, abs=0.05)
    wall_reading = math.hypot(math.sqrt(44.8**2 - (19.5 + 4.0) ** 2) - 8.5 / 2, 19.5)
    assert wall_reading == pytest.approx(39.1, abs=0.05)
    wrong = design_turn_inside_radius(rows.loc[["WB-62"]], ctr_m=wall_reading * FT)
    assert float(wrong.inside_radius_m.iloc[0]) / FT == pytest.approx(4.0, abs=0.1)


def test_the_longer_trailer_cuts_in_further(aashto):
    rows = aashto.set_index("name")
    assert rows.loc["WB-67", "turn_in_ft"] < rows.loc["WB-62", "turn_in_ft"] - 4.0


def car(**changes):
    base = dict(wheelbase_m=[2.7], width_m=[1.8], front_overhang_m=[0.9],
                rear_overhang_m=[1.0], min_radius_m=[4.5])
    return pd.DataFrame(base | changes)


def semi(hitch=0.0, lt=8.0):
    return car(trailer_wheelbase_m=[lt], hitch_offset_m=[hitch], trailer_width_m=[2.4],
               trailer_front_overhang_m=[0.5], trailer_rear_overhang_m=[1.2],
               min_radius_m=[12.0])


def test_a_full_circle_settles_on_the_steady_state():
    # 360 degrees on the arc is many wheelbases: the inner side reaches rho - B/2 and the
    # trailer sqrt(rho^2 + e^2 - l_t^2) - B_t/2 (docs/design.md §5). A trailer settles
    # over a few l_t / cos(psi) of travel: a short one, so that it has settled.
    single = design_turn_inside_radius(car(), angle_deg=360.0)
    assert float(single.inside_radius_m[0]) == pytest.approx(4.5 - 0.9, abs=1e-3)
    for hitch in (0.0, 0.6, -0.5):
        f = semi(hitch, lt=5.0)
        turn = design_turn_inside_radius(f, angle_deg=360.0)
        steady = full_lock_metrics(f.assign(
            track_m=1.8, max_steer_rad=np.arctan(2.7 / 12.0), max_inner_steer_rad=0.3,
            max_outer_steer_rad=0.2, max_articulation_rad=math.pi / 2))
        expected = math.sqrt(12.0**2 + hitch**2 - 5.0**2) - 1.2
        assert float(steady.trailer_inside_radius_m[0]) == pytest.approx(expected)
        assert float(turn.trailer_inside_radius_m[0]) == pytest.approx(expected, abs=1e-3)
        assert float(turn.towing_inside_radius_m[0]) == pytest.approx(12.0 - 0.9, abs=1e-3)


def test_a_longer_turn_cuts_in_further_and_90_degrees_less():
    f = semi(lt=9.0)
    radii = [float(design_turn_inside_radius(f, angle_deg=a).inside_radius_m[0])
             for a in (45.0, 90.0, 180.0, 360.0)]
    assert radii == sorted(radii, reverse=True)
    assert radii[0] - radii[-1] > 1.0


def test_lengths_scale_and_the_step_does_not_matter():
    f = semi(0.4, 9.5)
    metres = float(design_turn_inside_radius(f).inside_radius_m[0])
    feet = float(design_turn_inside_radius(f / FT).inside_radius_m[0]) * FT
    assert feet == pytest.approx(metres, abs=2e-4)
    fine = float(design_turn_inside_radius(f, step_m=0.01).inside_radius_m[0])
    assert fine == pytest.approx(metres, abs=2e-3)


def test_rows_are_independent_and_rear_steering_has_none():
    both = pd.concat([car(), semi()], ignore_index=True)
    together = design_turn_inside_radius(both)
    alone = [float(design_turn_inside_radius(f).inside_radius_m[0]) for f in (car(), semi())]
    np.testing.assert_allclose(together.inside_radius_m, alone, atol=2e-3)
    assert math.isnan(together.trailer_inside_radius_m[0])
    rear = design_turn_inside_radius(car(steered_axle=["rear"]))
    assert math.isnan(rear.inside_radius_m[0])


def test_bad_arguments_are_input_errors():
    with pytest.raises(ValueError, match="smaller than the wheelbase"):
        design_turn_inside_radius(car(), ctr_m=2.0)
    with pytest.raises(ValueError, match="angle_deg"):
        design_turn_inside_radius(car(), angle_deg=0.0)
    with pytest.raises(ValueError, match="lacks min_radius_m"):
        design_turn_inside_radius(car().drop(columns="min_radius_m"))


def test_agrees_with_the_tracking_controller_driving_the_same_arc():
    # An independent route to the same number: the Stanley controller of analysis/tracking.py
    # drives the steered axle along the arc (within 0.02 ft here) and the swept envelope's
    # distance from the arc's centre is the inside radius.
    table = load_tables([bundled_table("aashto_green_book")], ["CITY-BUS", "WB-62", "A-BUS"])
    vehicles = table.vehicles()
    ctr = [math.hypot(v.min_radius_m, v.wheelbase_m) for v in vehicles]
    paths = [template_path(r, 180.0, v.overall_length_m + 5.0) for v, r in
             zip(vehicles, ctr, strict=True)]
    runs = simulate_batch(vehicles, paths, TrackingSettings(tolerance_m=1.0))
    ours = design_turn_inside_radius(table.frame).inside_radius_m
    for run, r, mine in zip(runs, ctr, ours, strict=True):
        assert run.followed
        tracked = shapely.distance(shapely.Point(0.0, r), swept_path(run).envelope)
        assert tracked / FT == pytest.approx(mine / FT, abs=0.1)
