"""Radius profiles of many lines: stations kept as four numbers."""

from __future__ import annotations

import numpy as np

from networks.profiles import Stations, profiles


def test_stations_give_back_the_profile_stations_exactly():
    rng = np.random.default_rng(7)
    lines = [np.c_[np.cumsum(rng.uniform(0.5, 4, n)), rng.uniform(-1, 1, n)] for n in (3, 9, 30)]
    p = profiles(lines, [1.3, 2.0, 10.1], [4.7, 12.9, 40.05], step_m=0.25, window_m=3.0)
    assert len(p.stations) == len(lines)
    for s, st in zip(p.s_m, p.stations, strict=True):
        assert isinstance(st, Stations) and st.count == len(s)
        assert np.array_equal(st.array(), s)
        assert s[0] == st.start_m and s[-1] <= st.stop_m
