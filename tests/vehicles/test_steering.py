"""Steering mechanisms against independent facts: Ackermann condition, symmetry, zero."""

import math
import warnings

import numpy as np
import pytest

from clearance.vehicles.errors import InputError
from clearance.vehicles.steering import (
    Breakpoints,
    RackPinion,
    Steering,
    ackermann_angles,
    angle_from_curvature,
    bicycle_from_inner,
    curvature_from_angle,
    equivalent_bicycle,
    ideal_outer_from_inner,
)

L, W = 2.7, 1.55
PHI = np.concatenate([np.linspace(-1.2, -1e-6, 50), np.linspace(1e-6, 1.2, 50)])


def test_ackermann_condition_holds_at_every_angle():
    inner, outer = ackermann_angles(PHI, L, W)
    lhs = 1 / np.tan(np.abs(outer)) - 1 / np.tan(np.abs(inner))
    np.testing.assert_allclose(lhs, W / L, rtol=1e-9)
    # and the bicycle angle is the mean cotangent of the two wheels
    np.testing.assert_allclose(equivalent_bicycle(inner, outer), PHI, rtol=1e-9, atol=1e-12)


def test_exact_at_zero_without_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inner, outer = ackermann_angles(0.0, L, W)
        assert inner == 0.0 and outer == 0.0
        assert bicycle_from_inner(0.0, L, W) == 0.0
        assert ideal_outer_from_inner(0.0, L, W) == 0.0
        assert equivalent_bicycle(0.0, 0.0) == 0.0
        assert curvature_from_angle(0.0, L) == 0.0
        assert angle_from_curvature(0.0, L) == 0.0
        a = Steering("ackermann", L, W).wheel_angles(0.0)
        assert (a.left, a.right, a.bicycle) == (0.0, 0.0, 0.0)


def test_inner_wheel_matches_radius_relation():
    # rho = l cot(delta_i) + w/2 = l cot(delta_o) - w/2 = l / tan(phi)
    inner, outer = ackermann_angles(PHI[PHI > 0], L, W)
    rho = L / np.tan(PHI[PHI > 0])
    np.testing.assert_allclose(L / np.tan(inner) + W / 2, rho, rtol=1e-9)
    np.testing.assert_allclose(L / np.tan(outer) - W / 2, rho, rtol=1e-9)
    np.testing.assert_allclose(bicycle_from_inner(inner, L, W), PHI[PHI > 0], rtol=1e-12)


@pytest.mark.parametrize("kind", ["ackermann", "parallel"])
def test_left_turn_mirrors_right_turn(kind):
    s = Steering(kind, L, W, ratio=15.0)
    sw = np.linspace(0.0, 3.5, 30)
    left, right = s.wheel_angles(sw), s.wheel_angles(-sw)
    np.testing.assert_allclose(left.left, -right.right, atol=1e-15)
    np.testing.assert_allclose(left.right, -right.left, atol=1e-15)
    np.testing.assert_allclose(left.bicycle, -right.bicycle, atol=1e-15)


def test_left_turn_turns_left_wheel_more():
    a = Steering("ackermann", L, W, ratio=15.0).wheel_angles(3.0)
    assert a.left > a.right > 0 and a.inner == a.left
    b = Steering("ackermann", L, W, ratio=15.0).wheel_angles(-3.0)
    assert b.right < b.left < 0 and b.inner == b.right


def test_percent_ackermann_zero_equals_parallel():
    inner = np.linspace(0.0, 0.7, 20)
    zero = Steering("ackermann", L, W, ackermann_pct=0.0)
    par = Steering("parallel", L, W)
    np.testing.assert_allclose(zero.outer_for_inner(inner), par.outer_for_inner(inner))
    np.testing.assert_allclose(zero.outer_for_inner(inner), inner)
    a = zero.wheel_angles(np.linspace(-4, 4, 17))
    np.testing.assert_allclose(a.left, a.right)


def test_percent_ackermann_interpolates_between_parallel_and_ideal():
    i = 0.6
    ideal = float(ideal_outer_from_inner(i, L, W))
    half = float(Steering("ackermann", L, W, ackermann_pct=50.0).outer_for_inner(i))
    assert half == pytest.approx((i + ideal) / 2, rel=1e-12)
    table = Breakpoints.parse("0:100; 720:0", x_scale=math.pi / 180)
    s = Steering("ackermann", L, W, ratio=16.0, ackermann_pct=table, steering_range_rad=4 * math.pi)
    a = s.wheel_angles(2 * math.pi)  # 360 deg of steering wheel: 50 %
    i2, o_ideal = ackermann_angles(2 * math.pi / 16.0, L, W)
    assert float(a.outer) == pytest.approx(float(i2 - 0.5 * (i2 - o_ideal)), rel=1e-12)


def test_steering_ratio_table_and_range_and_deadband():
    table = Breakpoints.parse("-360:13.5; 0:13; 360:13.5", x_scale=math.pi / 180)
    s = Steering("parallel", L, W, ratio=table, steering_range_rad=2 * math.pi)
    assert float(s.wheel_angles(math.pi).left) == pytest.approx(math.pi / 13.25)
    # beyond the steering range the input is held at the range
    assert float(s.wheel_angles(3 * math.pi).left) == pytest.approx(2 * math.pi / 13.5)
    d = Steering("parallel", L, W, ratio=10.0, deadband_rad=0.2)
    assert float(d.wheel_angles(0.15).left) == 0.0
    assert float(d.wheel_angles(1.2).left) == pytest.approx(0.1)


def test_rear_steered_axle_turns_wheels_the_other_way():
    front = Steering("ackermann", L, W, ratio=15.0).wheel_angles(2.0)
    rear = Steering("ackermann", L, W, ratio=15.0, steered_axle="rear").wheel_angles(2.0)
    assert float(rear.left) == -float(front.left) and float(rear.bicycle) == float(front.bicycle)


def test_rack_and_pinion_reference_linkage():
    # The reference block's defaults, worked by hand with the law of cosines at the full
    # steering range 1.25 pi: rack travel 0.0057 * 3.927 = 0.022384 m;
    # beta0 = pi/2 - atan(0.2/0.25) - acos(0.050996/0.064031) = 0.24699 rad;
    # l1 = 0.272384: beta = pi/2 - 0.63332 - acos(0.062689/0.067585) = 0.55598 (+17.64 deg);
    # l1 = 0.227616: beta = 0.00710 rad (-13.74 deg).
    rp = RackPinion(1.0, 0.5, 0.1, 0.248, 0.2, 0.0057)
    left, right = rp.wheel_angles(1.25 * math.pi)
    assert math.degrees(float(left)) == pytest.approx(17.64, abs=0.05)
    assert math.degrees(float(right)) == pytest.approx(13.74, abs=0.05)
    l2, r2 = rp.wheel_angles(-1.25 * math.pi)
    assert float(l2) == pytest.approx(-float(right)) and float(r2) == pytest.approx(-float(left))
    s = Steering("rack_pinion", 1.5, 1.0, rack=rp)
    l3, r3 = rp.wheel_angles(3.0)
    assert float(s.outer_for_inner(float(l3))) == pytest.approx(float(r3), abs=1e-6)
    assert float(s.steering_for_inner(float(l3))) == pytest.approx(3.0, abs=1e-4)


def test_rack_that_cannot_close_is_refused():
    with pytest.raises(InputError, match="cannot meet"):
        RackPinion(1.0, 0.5, 0.1, 0.5, 0.2, 0.0057)
    with pytest.raises(InputError, match="not shorter"):
        RackPinion(1.0, 1.2, 0.1, 0.248, 0.2, 0.0057)


def test_curvature_round_trip():
    kappa = np.linspace(-0.3, 0.3, 41)
    np.testing.assert_allclose(curvature_from_angle(angle_from_curvature(kappa, L), L), kappa,
                               atol=1e-15)


def test_bad_breakpoints_are_refused():
    with pytest.raises(InputError):
        Breakpoints.parse("0:1; 0:2")
    with pytest.raises(InputError):
        Breakpoints.parse("0-1")
