"""Steering sensor look-up table (ERTS): both directions, offset, refusal off the table."""

import numpy as np
import pytest

from clearance.vehicles.errors import InputError
from clearance.vehicles.sensor import SteeringSensor

# The start and end of the ERTS table (angle, reading), with its offset.
ERTS = [(-72, -42181), (-72, -42025), (-71, -41869), (-71, -41713), (-1, -7397), (0, -7290),
        (0, -7183), (0, -7077), (1, -6970), (1, -6864), (99, 41557), (99, 41713),
        (100, 41869), (100, 42025), (100, 42181)]


def test_round_trip_on_a_strictly_monotone_table():
    s = SteeringSensor([(-40, -2000), (-10, -450), (0, 0), (10, 520), (40, 2100)], offset=37)
    angles = np.linspace(-40, 40, 81)
    np.testing.assert_allclose(s.angle(s.reading(angles)), angles, atol=1e-9)
    readings = np.linspace(-2000 + 37, 2100 + 37, 51)
    np.testing.assert_allclose(s.reading(s.angle(readings)), readings, atol=1e-9)


def test_offset_shifts_readings():
    a = SteeringSensor([(0, 0), (10, 100)], offset=0.0)
    b = SteeringSensor([(0, 0), (10, 100)], offset=-1930.0)
    assert float(b.reading(5.0)) == float(a.reading(5.0)) - 1930.0
    assert float(b.angle(-1930.0 + 50.0)) == 5.0


def test_erts_table_with_repeated_angles():
    s = SteeringSensor(ERTS, offset=-1930)
    # straight ahead reads the mean of the three zero-angle entries plus the offset
    assert float(s.reading(0.0)) == pytest.approx((-7290 - 7183 - 7077) / 3 - 1930)
    # reading -> angle -> reading stays within one table step (the table's resolution)
    r = np.array([-42181, -7290, 0, 42000], dtype=float) - 1930
    back = s.reading(s.angle(r))
    assert np.all(np.abs(back - r) < 160)


@pytest.mark.parametrize("angle", [-73.0, 100.5, float("nan")])
def test_refuses_angles_off_the_table(angle):
    with pytest.raises(InputError, match="off the table"):
        SteeringSensor(ERTS, offset=-1930).reading(angle)


def test_refuses_readings_off_the_table():
    s = SteeringSensor(ERTS, offset=-1930)
    with pytest.raises(InputError, match="off the table"):
        s.angle(42181.0)  # without the offset: beyond the last entry
    assert float(s.angle(42181.0 - 1930)) == 100.0


def test_refuses_non_monotone_tables():
    with pytest.raises(InputError, match="increase"):
        SteeringSensor([(0, 0), (1, 0)])
    with pytest.raises(InputError, match="decrease"):
        SteeringSensor([(1, 0), (0, 1)])
