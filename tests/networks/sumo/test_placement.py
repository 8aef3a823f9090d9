"""Where SUMO's placements of a swung path are hinted: the centre line's nearest stations."""

from __future__ import annotations

import numpy as np

from clearance.analysis.polyline import prepare_path
from clearance.networks.sumo.placement import centre_stations


def test_a_swung_path_is_matched_to_its_own_leg_of_a_centre_line_that_turns_back():
    # a U-turn whose legs are 3 m apart; the swung line leaves the lower leg by 1.8 m, nearer
    # the upper leg than its own
    a = np.radians(np.linspace(-90.0, 90.0, 37))
    loop = np.column_stack([30.0 + 1.5 * np.cos(a), 1.5 + 1.5 * np.sin(a)])
    centre = prepare_path(np.vstack([[(0.0, 0.0)], loop, [(0.0, 3.0)]]), spacing_m=0.5)
    line = prepare_path([(5.0, 0.0), (10.0, 1.8), (20.0, 1.8), (25.0, 0.0)], spacing_m=0.5)
    x, y = np.array([15.0, 5.0, 25.0]), np.array([1.8, 0.0, 0.0])
    along = np.array([line.length_m / 2, 0.0, line.length_m])
    st = centre_stations(centre, line, x, y, along)
    np.testing.assert_allclose(st, [15.0, 5.0, 25.0], atol=0.05)
    # the upper leg is nearer the middle point: a search of the whole line would take it
    upper = np.flatnonzero(centre.xy[:, 1] > 2.9)
    assert float(np.min(np.hypot(*(centre.xy[upper] - (15.0, 1.8)).T))) < 1.8
