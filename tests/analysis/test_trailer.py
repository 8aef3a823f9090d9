"""Trailer kinematics: no side slip at the trailer axle, closed-form steady state."""

from __future__ import annotations

import math

import numpy as np
import pytest

from clearance.analysis.kinematics import arc_step, integrate
from clearance.analysis.trailer import (
    advance_articulation,
    steady_articulation_rad,
    steady_trailer_radius_m,
    trailer_axle_point,
    trailer_heading_rate,
)

# (tractor wheelbase wb, hitch offset e, trailer wheelbase l_t, rear-axle radius rho)
CASES = [
    (5.0, -0.3, 12.0, 15.0),  # tractor-semitrailer, fifth wheel ahead of the rear axle
    (2.8, 1.1, 3.5, 7.0),  # car with a drawbar trailer behind the rear axle
    (5.0, 0.0, 10.0, -20.0),  # kingpin on the axle, right turn
]


def _drive(wb, e, lt, rho, n, dt=0.05, v=2.0, substeps=1):
    phi = math.atan(wb / rho)
    x, y, th = integrate(0.0, 0.0, 0.0, v, phi, wb, dt, n)
    psi = np.zeros(n + 1)
    k = math.tan(phi) / wb
    for i in range(n):
        psi[i + 1] = advance_articulation(psi[i], k, v * dt, e, lt, substeps)
    return x, y, th, psi


@pytest.mark.parametrize(("wb", "e", "lt", "rho"), CASES)
def test_steady_state_matches_closed_form(wb, e, lt, rho) -> None:
    # long enough for the transient (decay length ~ l_t) to die out
    x, y, th, psi = _drive(wb, e, lt, rho, n=4000)
    psi_ss = float(steady_articulation_rad(rho, e, lt))
    assert psi[-1] == pytest.approx(psi_ss, rel=1e-3)
    tx, ty = trailer_axle_point(x[-1], y[-1], th[-1], th[-1] - psi[-1], e, lt)
    centre = (0.0, rho)  # turn from the origin heading +x
    r_t = math.hypot(tx - centre[0], ty - centre[1])
    assert r_t == pytest.approx(float(steady_trailer_radius_m(rho, e, lt)), rel=1e-3)


@pytest.mark.parametrize(("wb", "e", "lt", "rho"), CASES)
def test_closed_form_trailer_is_tangent_to_its_circle(wb, e, lt, rho) -> None:
    # independent geometry: in steady state the trailer axle moves on a circle about the
    # tractor's turning centre, so its heading is perpendicular to the radius to it
    psi = float(steady_articulation_rad(rho, e, lt))
    tx, ty = trailer_axle_point(0.0, 0.0, 0.0, -psi, e, lt)
    radial = np.array([float(tx), float(ty) - rho])
    heading = np.array([math.cos(-psi), math.sin(-psi)])
    assert abs(radial @ heading) < 1e-9 * abs(rho)


def test_trailer_axle_does_not_slip_sideways() -> None:
    # tractor on a slalom of arcs; trailer heading from the ODE; the trailer axle's
    # velocity (finite differences of the geometric construction) stays along its heading
    wb, e, lt, v, dt = 4.0, -0.4, 9.0, 2.0, 0.002
    n = 6000
    t = np.arange(n) * dt
    phi = 0.45 * np.sin(2 * math.pi * t / 6.0)
    x, y, th = np.zeros(n + 1), np.zeros(n + 1), np.zeros(n + 1)
    psi = np.zeros(n + 1)
    for i in range(n):
        x[i + 1], y[i + 1], th[i + 1] = arc_step(x[i], y[i], th[i], v, phi[i], wb, dt)
        psi[i + 1] = advance_articulation(psi[i], math.tan(phi[i]) / wb, v * dt, e, lt)
    theta_t = th - psi
    tx, ty = trailer_axle_point(x, y, th, theta_t, e, lt)
    vx = (tx[2:] - tx[:-2]) / (2 * dt)
    vy = (ty[2:] - ty[:-2]) / (2 * dt)
    side = -vx * np.sin(theta_t[1:-1]) + vy * np.cos(theta_t[1:-1])
    speed = np.hypot(vx, vy)
    assert np.max(np.abs(psi)) > 0.3  # the manoeuvre articulates
    assert np.max(np.abs(side)) < 1e-3 * np.max(speed)
    # and the heading rate formula agrees with the finite difference of theta_t
    phi_at_sample = 0.5 * (phi[:-1] + phi[1:])  # steering changes at each sample
    rate = trailer_heading_rate(v, phi_at_sample, psi[1:-1], wb, e, lt)
    fd = (theta_t[2:] - theta_t[:-2]) / (2 * dt)
    assert np.max(np.abs(rate - fd)) < 2e-3 * np.max(np.abs(fd))


def test_left_and_right_are_mirror_images() -> None:
    _, _, _, left = _drive(5.0, -0.3, 12.0, 15.0, n=500)
    _, _, _, right = _drive(5.0, -0.3, 12.0, -15.0, n=500)
    assert np.allclose(left, -right, atol=1e-12)
    assert float(steady_articulation_rad(-15.0, -0.3, 12.0)) == pytest.approx(
        -float(steady_articulation_rad(15.0, -0.3, 12.0))
    )


def test_no_steady_state_when_trailer_longer_than_hitch_radius() -> None:
    assert math.isnan(float(steady_articulation_rad(3.0, 0.5, 10.0)))
    assert math.isnan(float(steady_trailer_radius_m(3.0, 0.5, 10.0)))


def test_rk4_substeps_converge() -> None:
    one = advance_articulation(0.2, 0.1, 0.5, 0.7, 3.0, substeps=1)
    many = advance_articulation(0.2, 0.1, 0.5, 0.7, 3.0, substeps=200)
    assert abs(float(one - many)) < 1e-6
