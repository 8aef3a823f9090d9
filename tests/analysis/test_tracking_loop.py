"""The compiled loop's one-run formulas agree with the vectorised ones they restate."""

from __future__ import annotations

import numpy as np
import pytest

from clearance.analysis.kinematics import limit_steering, ramp_step
from clearance.analysis.tracking_loop import (
    articulation_one,
    limit_one,
    predictive_stanley,
    ramp_step_one,
    stanley_residual,
)
from clearance.analysis.trailer import advance_articulation

RNG = np.random.default_rng(11)


@pytest.mark.parametrize("front", [True, False])
def test_ramp_step_one_is_ramp_step(front: bool) -> None:
    for _ in range(200):
        x, y, th = RNG.uniform(-50, 50, 3)
        phi0 = RNG.choice([0.0, RNG.uniform(-0.7, 0.7)])
        phi1 = RNG.choice([phi0, RNG.uniform(-0.7, 0.7)])
        wb, d = RNG.uniform(1.5, 8.0), RNG.uniform(0.0, 3.0)
        expected = [float(v) for v in ramp_step(x, y, th, d, phi0, phi1, wb, front)]
        got = ramp_step_one(x, y, th, phi0, phi1, wb, d, front)
        assert list(got[:3]) == pytest.approx(expected, abs=1e-12)
        # the arc it reports is the one it took: the heading changed by dtheta
        assert got[2] - th == pytest.approx(got[4], abs=1e-12)


def test_limit_one_is_limit_steering() -> None:
    for _ in range(200):
        prev, cmd = RNG.uniform(-1.2, 1.2, 2)
        lock, rate, dt = RNG.uniform(0.3, 0.8), RNG.uniform(0.05, 1.0), 0.1
        expected = float(limit_steering(prev, cmd, lock, rate, dt))
        assert limit_one(prev, cmd, lock, rate * dt) == pytest.approx(expected, abs=1e-15)
    assert limit_one(0.59, 0.9, 0.6, np.inf) == 0.6


@pytest.mark.parametrize("substeps", [1, 3])
def test_articulation_one_is_advance_articulation(substeps: int) -> None:
    for _ in range(100):
        psi, k = RNG.uniform(-0.8, 0.8), RNG.uniform(-0.2, 0.2)
        ds, e, lt = RNG.uniform(0.0, 0.5), RNG.uniform(-1.0, 1.0), RNG.uniform(3.0, 13.0)
        expected = float(advance_articulation(psi, k, ds, e, lt, substeps))
        assert articulation_one(psi, k, ds, e, lt, substeps) == pytest.approx(expected,
                                                                              abs=1e-14)


def _bisected(args: tuple, lock: float) -> float:
    """The command by plain bisection of :func:`stanley_residual` over the lock, as the loop
    found it before regula falsi finished its last bracket (the reference)."""
    lo, hi = -lock, lock
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if stanley_residual(mid, *args) > 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-13:
            break
    return 0.5 * (lo + hi)


def _curve_states() -> list[tuple]:
    """Front-steered states on a path that runs straight into a 12 m circle: on it, off it
    both ways, heading off, wheel anywhere within the lock."""
    rng = np.random.default_rng(7)
    st = np.arange(0.0, 60.05, 0.1)
    k = np.where(st < 20.0, 0.0, 1 / 12.0)
    hd = np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(st))])
    out = []
    for _ in range(400):
        s_f = float(rng.uniform(5.0, 50.0))
        th_path = float(np.interp(s_f, st, hd))
        lock = float(rng.uniform(0.5, 0.75))
        out.append((s_f, float(rng.normal(0.0, 0.5)), th_path + float(rng.normal(0.0, 0.2)),
                    float(rng.uniform(-lock, lock)), 2.0, float(rng.uniform(2.5, 7.0)), lock,
                    float(rng.uniform(0.2, 0.5)), 2.5, 0.1, st, hd, k, len(st), th_path))
    return out


def test_predictive_stanley_finds_the_bisections_root() -> None:
    """Regula falsi in the last milliradian finds the root bisection finds (the residual has
    several roots where the wheel unwinds from lock: the same one, not a neighbour)."""
    found = 0
    for state in _curve_states():
        lock = state[6]
        args = (state[0], state[1], state[2], state[3], *state[4:])
        ref = _bisected(args, lock)
        got = predictive_stanley(*state)
        if stanley_residual(-lock, *args) > 0.0 > stanley_residual(lock, *args):
            found += 1
            assert abs(got - ref) < 1e-11
    assert found > 200


def test_predictive_stanley_stops_where_the_rate_decides() -> None:
    """With the step's largest change given, a command beyond it may be found coarsely: the
    wheel then moves by exactly that change, as it does toward the precise command."""
    dt, limited = 0.1, 0
    for state in _curve_states():
        phi, lock, rate = state[3], state[6], state[7]
        precise = predictive_stanley(*state)
        coarse = predictive_stanley(*state, rate * dt)
        assert limit_one(phi, coarse, lock, rate * dt) == limit_one(phi, precise, lock, rate * dt)
        assert (abs(coarse - phi) > rate * dt) == (abs(precise - phi) > rate * dt)
        limited += abs(precise - phi) > rate * dt
    assert 50 < limited < 400
