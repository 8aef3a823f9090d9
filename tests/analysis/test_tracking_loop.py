"""The compiled loop's one-run formulas agree with the vectorised ones they restate."""

from __future__ import annotations

import numpy as np
import pytest

from clearance.analysis.kinematics import limit_steering, ramp_step
from clearance.analysis.tracking_loop import articulation_one, limit_one, ramp_step_one
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
