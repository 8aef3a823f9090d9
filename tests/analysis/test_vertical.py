"""Vertical checks against closed forms: kinks, crests and sags of known radius."""

from __future__ import annotations

import math

import numpy as np
import pytest

from clearance.analysis.vertical import (
    Body,
    body_clearance,
    front_contact,
    suspect_points,
    without_points,
)
from clearance.vehicles.underside import underside_from
from clearance.vehicles.vehicle import Vehicle


def flat_body(clearance: float, wheelbase: float = 2.7, front: float = 0.9,
              rear: float = 1.0) -> Body:
    """A body whose angles are derived from its clearance: a flat plate at ``clearance``."""
    v = Vehicle("x", wheelbase, 1.5, 1.8, front, rear, 0.6, 0.7, 0.4,
                underside=underside_from(clearance, None, None, None, wheelbase, front, rear,
                                         "passenger"))
    return Body.of(v)


def ramp_profile(grade: float = 0.15, rise: float = 3.0) -> tuple[np.ndarray, np.ndarray]:
    """Level, a ramp of ``grade`` with no transition, level again."""
    run = rise / grade
    s = np.array([0.0, 20.0, 20.0 + run, 40.0 + run])
    return s, np.array([0.0, 0.0, rise, rise])


def test_ramp_without_transition_scrapes_a_low_car_and_not_an_suv():
    s, z = ramp_profile(0.15)
    theta = math.atan(0.15)
    low = body_clearance(s, z, flat_body(0.10))
    suv = body_clearance(s, z, flat_body(0.22))
    # the foot of the ramp (a sag): the front end when the front tyre reaches it (the car
    # still level), the rear end when the rear tyre does (the car on the ramp)
    assert low.part_margins_m["front overhang"] == pytest.approx(0.10 - 0.9 * 0.15, abs=1e-6)
    assert low.part_margins_m["rear overhang"] == pytest.approx(0.10 - 1.0 * 0.15, abs=1e-6)
    # its top (a crest): the two halves of the wheelbase at theta / 2 to the chord
    assert low.part_margins_m["underside"] == pytest.approx(
        0.10 - 1.35 * math.tan(theta / 2), abs=1e-5)
    assert low.scrapes and low.part == "rear overhang"
    assert low.margin_m == pytest.approx(-0.05, abs=1e-6)
    assert 20.0 - 1.0 - 1e-6 <= low.station_m <= 20.0 + 1e-6  # behind the foot of the ramp
    assert not suv.scrapes
    assert suv.margin_m == pytest.approx(0.22 - 0.15, abs=1e-6)


def test_breakover_on_a_crest_of_known_radius():
    radius, wheelbase = 20.0, 2.7
    a = np.linspace(-0.6, 0.6, 2001)
    s, z = radius * np.sin(a), radius * np.cos(a) - radius
    sagitta = radius - math.sqrt(radius ** 2 - (wheelbase / 2) ** 2)
    for clearance in (0.04, 0.05):
        r = body_clearance(s, z, flat_body(clearance, wheelbase), span_m=(-5.0, 5.0))
        assert r.part == "underside"
        assert r.margin_m == pytest.approx(clearance - sagitta, abs=2e-4)
    assert body_clearance(s, z, flat_body(0.04, wheelbase)).scrapes
    assert not body_clearance(s, z, flat_body(0.05, wheelbase)).scrapes


def test_given_breakover_angle_raises_the_middle_of_the_underside():
    # a crest of two planes at the breakover angle touches the body exactly at mid-wheelbase
    beta = math.radians(23.5)
    wheelbase = 2.842
    body = Body(wheelbase, 0.781, 1.140, 0.216, math.tan(math.radians(37.5)),
                math.tan(math.radians(34.6)), math.tan(beta / 2))
    g = math.tan(beta / 2)  # each side of the crest at beta/2 to the level
    s = np.array([-30.0, 0.0, 30.0])
    z = np.array([-30 * g, 0.0, -30 * g])
    r = body_clearance(s, z, body)
    assert r.part_margins_m["underside"] == pytest.approx(0.0, abs=1e-4)
    steeper = np.array([-30 * 1.1 * g, 0.0, -30 * 1.1 * g])
    assert body_clearance(s, steeper, body).scrapes


def test_approach_and_departure_on_a_sag_of_known_radius():
    radius, wheelbase, front, rear, clearance = 15.0, 2.7, 0.9, 1.2, 0.12
    a = np.linspace(-0.7, 0.7, 3001)
    s, z = radius * np.sin(a), radius - radius * np.cos(a)
    h0 = math.sqrt(radius ** 2 - (wheelbase / 2) ** 2)
    # on a circle every placement is alike: the ground above the chord's extension at the
    # body's ends
    want_front = clearance - (h0 - math.sqrt(radius ** 2 - (wheelbase / 2 + front) ** 2))
    want_rear = clearance - (h0 - math.sqrt(radius ** 2 - (wheelbase / 2 + rear) ** 2))
    r = body_clearance(s, z, flat_body(clearance, wheelbase, front, rear), span_m=(-3.0, 3.0))
    assert r.part_margins_m["front overhang"] == pytest.approx(want_front, abs=2e-4)
    assert r.part_margins_m["rear overhang"] == pytest.approx(want_rear, abs=2e-4)
    assert r.part == "rear overhang" and r.scrapes == (want_rear < 0)
    # between the axles the ground is below the chord on a sag: the clearance itself
    assert r.part_margins_m["underside"] == pytest.approx(clearance, abs=1e-9)


def test_direction_of_travel_swaps_the_overhangs():
    s, z = ramp_profile(0.15)
    body = flat_body(0.10, front=0.9, rear=1.0)
    up = body_clearance(s, z, body)
    down = body_clearance(s, z[::-1].copy(), body)  # the ramp driven the other way
    assert down.part_margins_m["front overhang"] == pytest.approx(
        up.part_margins_m["front overhang"], abs=1e-6)
    assert down.part_margins_m["rear overhang"] == pytest.approx(
        up.part_margins_m["rear overhang"], abs=1e-6)


def test_span_limits_the_placements():
    s, z = ramp_profile(0.15)
    body = flat_body(0.10)
    far = body_clearance(s, z, body, span_m=(60.0, 60.5))  # on the upper level only
    assert not far.scrapes and far.margin_m == pytest.approx(0.10, abs=1e-9)


def test_degenerate_profiles():
    body = flat_body(0.10)
    level = body_clearance(np.array([0.0, 50.0]), np.array([2.0, 2.0]), body)
    assert level.margin_m == 0.10 and level.part == "" and math.isnan(level.station_m)
    one = body_clearance(np.array([3.0]), np.array([1.0]), body)
    assert one.margin_m == 0.10
    uniform = body_clearance(np.array([0.0, 100.0]), np.array([0.0, 30.0]), body)
    assert uniform.margin_m == pytest.approx(0.10, abs=1e-9)
    with pytest.raises(ValueError, match="at least one"):
        body_clearance(np.array([]), np.array([]), body)
    with pytest.raises(ValueError, match="decrease"):
        body_clearance(np.array([0.0, 2.0, 1.0]), np.array([0.0, 1.0, 0.0]), body)
    with pytest.raises(ValueError, match="finite"):
        body_clearance(np.array([0.0, 1.0]), np.array([0.0, np.nan]), body)


def test_front_contact_keeps_the_wheelbase_as_chord():
    s, z = ramp_profile(0.15)
    rear = np.linspace(10.0, 50.0, 81)
    front = front_contact(s, z, rear, 2.7)
    chord = np.hypot(front - rear, np.interp(front, s, z) - np.interp(rear, s, z))
    assert np.allclose(chord, 2.7, atol=1e-9)


def test_suspect_point_found_and_taken_out():
    s = np.array([0.0, 50.0, 122.0, 200.0, 260.0])
    z = np.array([40.0, 40.2, 218.0, 40.6, 40.8])
    found = suspect_points(s, z)
    assert found.tolist() == [2]
    clean = without_points(s, z, found)
    assert np.all(np.abs(np.diff(clean) / np.diff(s)) < 0.01)
    # a spike of a few centimetres (survey noise) and a steep real ramp are not suspect
    assert suspect_points(s, np.array([40.0, 40.2, 40.25, 40.6, 40.8])).tolist() == []
    ramp_s, ramp_z = ramp_profile(0.20)
    assert suspect_points(ramp_s, ramp_z).tolist() == []
