"""A run against a flight log, read the same way on both sides (results.log_compare): synthetic descents whose
figures are known in closed form."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pchute_exudyn.physics.flight_phases import band_rate
from pchute_exudyn.results.log_compare import RATE_SPAN, bands, descent, gps_drift, rate_change, with_rates

TAU = 1.0   # s: the main's deceleration time constant


def two_canopy_descent(noise: float = 0.0, seed: int = 0):
    """20 m/s to 200 m at t = 90 s, then a rate 5 + 15 exp(-(t - 90) / TAU) m/s to the ground; 20 Hz samples."""
    t = np.arange(0.0, 90.0 + 40.0, 0.05)
    after = np.clip(t - 90.0, 0.0, None)
    h = np.where(t < 90.0, 2000.0 - 20.0 * t, 200.0 - 5.0 * after - 15.0 * TAU * (1.0 - np.exp(-after / TAU)))
    keep = h >= 0.0
    return t[keep], h[keep] + np.random.default_rng(seed).normal(0.0, noise, np.count_nonzero(keep))


def exact_height(t):
    after = max(t - 90.0, 0.0)
    return 2000.0 - 20.0 * t if t < 90.0 else 200.0 - 5.0 * after - 15.0 * TAU * (1.0 - math.exp(-after / TAU))


def test_the_rate_change_is_halfway_from_the_drogue_to_the_main():
    """Where the fall over RATE_SPAN, centred, is 12.5 m/s: halfway from 20 to 5 m/s."""
    t, h = two_canopy_descent()
    when, height = rate_change(t, h)
    span = RATE_SPAN / 2.0
    expected = brentq(lambda x: (exact_height(x - span) - exact_height(x + span)) / RATE_SPAN - 12.5, 85.0, 95.0)
    assert when == pytest.approx(expected, abs=0.05)
    assert height == pytest.approx(exact_height(when), abs=0.5)


def test_one_canopy_has_no_rate_change():
    t = np.arange(0.0, 100.0, 0.05)
    assert rate_change(t, 1000.0 - 8.0 * t) is None


def test_band_rates_are_theil_sen_slopes_robust_to_noise_and_spikes():
    t, h = two_canopy_descent(noise=1.0)
    h[::97] += 150.0   # ejection-like spikes on 1 % of the samples
    side = descent(t, h)
    chosen = bands(side.apogee_height, side.rate_change)
    assert chosen["drogue"][0] > 200.0 and chosen["main"][1] < 200.0
    rated = with_rates(side, t, h, chosen)
    assert rated.rates["drogue"][0] == pytest.approx(20.0, rel=0.005)
    assert rated.rates["main"][0] == pytest.approx(5.0, rel=0.01)
    assert math.isnan(band_rate(t, h, 5000.0, 6000.0)[0])


def test_drift_between_two_fixes():
    """0.01 deg of latitude: 1111.95 m on the mean sphere."""
    assert gps_drift([40.0, 40.01], [-88.0, -88.0]) == pytest.approx(1111.95, rel=1e-5)
