"""A barometric altimeter's heights read through the day's air (physics.barometric): closed forms."""

import numpy as np
import pytest

from pchute_exudyn.physics.atmosphere import US76, US76_G0, US76_R
from pchute_exudyn.physics.barometric import (
    STANDARD_LAPSE,
    geometric_heights,
    lapse_layer,
    pressure_altitude,
    standard_pressure,
)

HEIGHTS = np.linspace(-5.0, 2500.0, 11)   # m above a pad
PAD = 200.0                               # m: the pad's standard height


def test_standard_pressure_is_us76_and_inverts():
    assert standard_pressure(0.0) == pytest.approx(101325.0, rel=1e-12)
    assert standard_pressure(1000.0) == pytest.approx(US76().pressure(1000.0), rel=2e-4)   # geopotential vs geometric
    assert pressure_altitude(standard_pressure(HEIGHTS)) == pytest.approx(HEIGHTS, abs=1e-9)


def test_a_standard_day_leaves_the_heights_as_the_altimeter_read_them():
    us76 = US76()
    heights = geometric_heights(HEIGHTS, PAD, lambda z: us76.states(z + PAD)[0])
    assert heights == pytest.approx(HEIGHTS, abs=0.12)   # the geopotential metre: 0.1 m at 2.5 km


def test_a_hot_day_reads_through_the_closed_form_of_its_layer():
    """A 35 C day of standard lapse through the pad's pressure: z = (T_g / L) (1 - (p / p_g)^(R L / g))."""
    pad_pressure, hot = float(standard_pressure(PAD)), 308.15
    heights = geometric_heights(HEIGHTS, PAD, lambda z: lapse_layer(z, pad_pressure, hot)[2])
    pressures = standard_pressure(PAD + HEIGHTS)
    closed = hot / STANDARD_LAPSE * (1.0 - (pressures / pad_pressure) ** (US76_R * STANDARD_LAPSE / US76_G0))
    assert heights == pytest.approx(closed, abs=1e-4)
    assert heights[-1] / HEIGHTS[-1] == pytest.approx(1.0743, abs=1e-4)   # the altimeter reads 7 % low


def test_an_isothermal_layer_is_exponential():
    pressures, temperatures, densities = lapse_layer(np.array([0.0, 1000.0]), 1e5, 250.0, lapse=0.0)
    assert pressures[1] == pytest.approx(1e5 * np.exp(-US76_G0 * 1000.0 / (US76_R * 250.0)), rel=1e-12)
    assert temperatures.tolist() == [250.0, 250.0]
    assert densities[0] == pytest.approx(1e5 / (US76_R * 250.0), rel=1e-12)
