"""Bicycle model: exact arcs close their circles, Euler drifts, limits hold."""

from __future__ import annotations

import math

import numpy as np
import pytest

from clearance.analysis.kinematics import (
    SpeedProfile,
    arc_step,
    as_speed_profile,
    integrate,
    limit_steering,
    ramp_arc,
    ramp_step,
)
from clearance.analysis.polyline import fit_circle


def test_constant_lock_closes_circle_of_radius_l_over_tan_phi() -> None:
    wheelbase, phi, v, dt = 3.2, 0.45, 2.0, 0.05
    rho = wheelbase / math.tan(phi)
    period = 2 * math.pi * rho / v
    n = int(round(period / dt))
    dt = period / n  # an exact number of steps per lap
    x, y, th = integrate(0.0, 0.0, 0.0, v, phi, wheelbase, dt, n)
    # the centre of a left turn from the origin heading +x is (0, rho)
    r = np.hypot(x, y - rho)
    assert np.max(np.abs(r / rho - 1)) < 1e-3
    assert math.hypot(x[-1], y[-1]) < 1e-3 * rho  # back at the start
    assert th[-1] == pytest.approx(2 * math.pi, rel=1e-9)
    xc, yc, rfit = fit_circle(x, y)
    assert rfit == pytest.approx(rho, rel=1e-3)


def test_right_lock_mirrors_left_lock() -> None:
    left = integrate(1.0, 2.0, 0.3, 1.5, 0.3, 2.7, 0.1, 200)
    right = integrate(1.0, 2.0, 0.3, 1.5, -0.3, 2.7, 0.1, 200)
    # mirror about the line through (1, 2) at heading 0.3
    c, s = math.cos(0.3), math.sin(0.3)
    dx, dy = right[0] - 1.0, right[1] - 2.0
    along = dx * c + dy * s
    across = -dx * s + dy * c
    mx = 1.0 + along * c + across * s
    my = 2.0 + along * s - across * c
    assert np.allclose(mx, left[0], atol=1e-9)
    assert np.allclose(my, left[1], atol=1e-9)
    assert np.allclose(right[2] - 0.3, -(left[2] - 0.3), atol=1e-12)


def test_zero_steer_is_a_straight_line_and_tiny_steer_is_continuous() -> None:
    x0, y0, _ = arc_step(0.0, 0.0, 0.7, 3.0, 0.0, 2.5, 1.0)
    assert float(x0) == pytest.approx(3 * math.cos(0.7), abs=1e-15)
    assert float(y0) == pytest.approx(3 * math.sin(0.7), abs=1e-15)
    x1, y1, th1 = arc_step(0.0, 0.0, 0.7, 3.0, 1e-12, 2.5, 1.0)
    assert np.isfinite([x1, y1, th1]).all()
    assert float(x1) == pytest.approx(float(x0), abs=1e-10)


def test_euler_exercise_small_error_exact_arc_agrees() -> None:
    # Robotics-article exercise: 1 m/s, delta = 0.3 rad, 10 s at 50 Hz; fit a circle.
    wheelbase, delta, v, dt, n = 2.5, 0.3, 1.0, 1 / 50, 500
    expected = wheelbase / math.tan(delta)
    xe, ye, _ = integrate(0.0, 0.0, 0.0, v, delta, wheelbase, dt, n, method="euler")
    xa, ya, _ = integrate(0.0, 0.0, 0.0, v, delta, wheelbase, dt, n, method="arc")
    r_euler = fit_circle(xe, ye)[2]
    r_arc = fit_circle(xa, ya)[2]
    err_euler = abs(r_euler / expected - 1)
    err_arc = abs(r_arc / expected - 1)
    assert err_arc < 1e-3
    assert err_arc < 1e-9  # exact up to rounding
    # Euler: equal chords turning by equal angles lie on a circle of radius
    # ds / (2 sin(dtheta / 2)), slightly larger than rho; its centre is shifted.
    ds = v * dt
    dtheta = ds * math.tan(delta) / wheelbase
    assert r_euler == pytest.approx(ds / (2 * math.sin(dtheta / 2)), rel=1e-9)
    assert 1e-8 < err_euler < 1e-3
    assert r_euler > expected
    xc_e, yc_e, _ = fit_circle(xe, ye)
    assert math.hypot(xc_e, yc_e - expected) == pytest.approx(ds / 2, rel=1e-3)


def test_vectorised_batch_equals_one_by_one() -> None:
    phis = np.array([-0.5, -0.1, 0.0, 0.2, 0.6])
    wbs = np.array([2.5, 3.0, 4.0, 6.0, 12.0])
    bx, by, bth = integrate(0.0, 0.0, 0.1, 2.0, phis, wbs, 0.05, 100)
    for i in range(len(phis)):
        x, y, th = integrate(0.0, 0.0, 0.1, 2.0, phis[i], wbs[i], 0.05, 100)
        assert np.allclose(bx[:, i], x) and np.allclose(by[:, i], y)
        assert np.allclose(bth[:, i], th)


def test_limit_steering_rate_then_lock() -> None:
    prev = np.array([0.0, 0.0, 0.55, -0.3])
    cmd = np.array([1.0, -0.01, 1.0, 0.0])
    out = limit_steering(prev, cmd, 0.6, 0.4, 0.05)
    assert np.allclose(out, [0.02, -0.01, 0.57, -0.28])
    locked = limit_steering(prev, cmd, 0.56, np.inf, 0.05)
    assert np.allclose(locked, [0.56, -0.01, 0.56, 0.0])


def test_speed_profile_by_station_and_time() -> None:
    p = SpeedProfile("time", (0.0, 4.0), (1.0, 3.0))
    assert np.allclose(p.speed(station_m=[100.0, 0.0], time_s=[2.0, 10.0]), [2.0, 3.0])
    assert as_speed_profile(p) is p
    assert p.min_speed_m_s == 1.0 and p.max_speed_m_s == 3.0


@pytest.mark.parametrize(
    "args",
    [
        ("distance", (0.0,), (1.0,)),
        ("station", (0.0, 0.0), (1.0, 2.0)),
        ("station", (0.0, 1.0), (1.0, 0.0)),
        ("station", (0.0, 1.0), (1.0,)),
    ],
)
def test_speed_profile_rejects_bad_input(args: tuple) -> None:
    with pytest.raises(ValueError, match="speed profile"):
        SpeedProfile(*args)


def test_bad_speed_and_step_raise_input_error() -> None:
    with pytest.raises(ValueError, match="speed"):
        as_speed_profile("fast")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="dt_s"):
        integrate(0, 0, 0, 1, 0, 2, 0.0, 3)
    with pytest.raises(ValueError, match="method"):
        integrate(0, 0, 0, 1, 0, 2, 0.1, 3, method="rk4")  # type: ignore[arg-type]


def _ramp_steer_exact(v: float, wb: float, rate: float, t_end: float, n: int = 20001
                      ) -> tuple[float, float, float]:
    """Rear axle after a ramp steer ``phi = rate t`` from rest at the origin (Simpson).

    The heading has a closed form, ``theta = v (1 - cos(rate t)) / (l rate)`` (the rear axle
    turns at ``v sin(phi) / l`` when the front axle moves at ``v``); the position is the
    Fresnel-type integral of ``v cos(phi) (cos theta, sin theta)``, by Simpson's rule on
    ``n`` points.
    """
    t = np.linspace(0.0, t_end, n)
    th = v * (1.0 - np.cos(rate * t)) / (wb * rate)
    w = np.ones(n)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    w *= (t[1] - t[0]) / 3.0
    vr = v * np.cos(rate * t)
    return float(w @ (vr * np.cos(th))), float(w @ (vr * np.sin(th))), float(th[-1])


def test_ramp_steer_is_second_order_in_the_step() -> None:
    v, wb, rate, t_end = 2.0, 3.0, 0.03, 15.0  # the wheel turns to 0.45 rad in 15 s
    ex, ey, eth = _ramp_steer_exact(v, wb, rate, t_end)
    errors, held = [], []
    for dt in (0.1, 0.05):
        x = y = th = xh = yh = thh = 0.0
        for k in range(round(t_end / dt)):
            p0, p1 = rate * k * dt, rate * (k + 1) * dt
            x, y, th = ramp_step(x, y, th, v * dt, p0, p1, wb)
            # the step's new steering held over the whole step (the loop before the ramp)
            xh, yh, thh = arc_step(xh, yh, thh, v * math.cos(p1), p1, wb, dt)
        errors.append(math.hypot(x - ex, y - ey))
        held.append(math.hypot(xh - ex, yh - ey))
        assert th == pytest.approx(eth, abs=1e-6)  # Simpson's turn: fourth order
    assert errors[0] < 0.002 and held[0] > 0.1  # the held steering lags 0.17 m
    assert errors[0] / errors[1] == pytest.approx(4.0, rel=0.05)  # second order
    assert held[0] / held[1] == pytest.approx(2.0, rel=0.05)  # first order


def test_ramp_arc_of_a_rear_steered_unit_turns_by_tan() -> None:
    # the reference (front) axle travels the whole distance; held steering: the exact arc
    ds, dth = ramp_arc(0.4, 0.4, 2.5, 1.2, front_steered=False)
    assert float(ds) == 1.2 and float(dth) == pytest.approx(1.2 * math.tan(0.4) / 2.5)
    ds, dth = ramp_arc(-0.4, 0.4, 2.5, 1.2, front_steered=True)  # through straight
    assert float(dth) == pytest.approx(0.0, abs=1e-15) and float(ds) < 1.2
