"""The compiled loop's one-run formulas agree with the vectorised ones they restate."""

from __future__ import annotations

import numpy as np
import pytest

from analysis.kinematics import arc_step, limit_steering
from analysis.tracking_loop import arc_step_one, articulation_one, limit_one
from analysis.trailer import advance_articulation

RNG = np.random.default_rng(11)


def test_arc_step_one_is_arc_step() -> None:
    for _ in range(200):
        x, y, th = RNG.uniform(-50, 50, 3)
        phi = RNG.choice([0.0, RNG.uniform(-0.7, 0.7)])
        wb, ds = RNG.uniform(1.5, 8.0), RNG.uniform(0.0, 3.0)
        expected = [float(v) for v in arc_step(x, y, th, 1.0, phi, wb, ds)]
        assert list(arc_step_one(x, y, th, phi, wb, ds)) == pytest.approx(expected, abs=1e-12)


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
