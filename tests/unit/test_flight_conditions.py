"""Flight conditions as a start (``physics.conditions``): the altitude and speed at which an atmosphere gives a Mach
number and a dynamic pressure, solved back from conditions computed at a chosen altitude."""

from __future__ import annotations

import pytest

from pchute_exudyn.physics.atmosphere import US76, MarsGRC, TabulatedAtmosphere
from pchute_exudyn.physics.conditions import ConditionsError, altitude_and_speed


@pytest.mark.parametrize("atmosphere, altitude, speed", [
    (US76(), 12345.678, 300.0), (US76(), 31000.0, 700.0), (US76(), -1000.0, 120.0), (US76(), 80000.0, 2000.0),
    (MarsGRC(), 9876.5, 450.0), (MarsGRC(), -3000.0, 300.0), (MarsGRC(), 60000.0, 900.0)])
def test_conditions_computed_at_an_altitude_solve_back_to_it(atmosphere, altitude, speed):
    """M = V / a(h) and q = rho(h) V^2 / 2 at a chosen h give back h within 1e-6 m and V within 1e-9 relative."""
    density, sound = atmosphere.state(altitude)
    found, found_speed = altitude_and_speed(atmosphere, speed / sound, 0.5 * density * speed ** 2)
    assert found == pytest.approx(altitude, abs=1e-6)
    assert found_speed == pytest.approx(speed, rel=1e-9)


def test_a_dynamic_pressure_no_altitude_gives_is_refused_with_the_span():
    with pytest.raises(ConditionsError, match=r"no altitude of the us76 atmosphere \(-5000 to 86000 m\) gives "
                                              r"1e\+07 Pa at Mach 2: it spans"):
        altitude_and_speed(US76(), 2.0, 1e7)


def test_an_atmosphere_without_a_speed_of_sound_is_refused():
    table = TabulatedAtmosphere((0.0, 1000.0), (1.2, 1.1))
    with pytest.raises(ConditionsError, match="has no speed of sound"):
        altitude_and_speed(table, 2.0, 1000.0)
