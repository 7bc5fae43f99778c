"""A flight's phases from a height history (``physics.flight_phases``) on synthetic logs with known answers."""

import numpy as np
import pytest

from pchute_exudyn.physics.flight_phases import (
    LANDED_BAND,
    FlightPhaseError,
    band_descent_rate,
    flight_phases,
    theil_sen_slope,
    touchdown_index,
)

RATE_DROGUE, RATE_MAIN, MAIN_HEIGHT = 25.0, 6.0, 300.0


def _flight(noise: float = 0.0, seed: int = 1, rate: float = 20.0):
    """A dual-deploy flight sampled at ``rate`` Hz: 5 s on a pad at 1400 m, a boost and coast to 1000 m above it
    13 s later (a parabola), a free fall to the drogue's 25 m/s, then steady to 300 m above the pad, the main at
    6 m/s to the ground, 5 s on the ground; heights above sea level with ``noise`` (m rms)."""
    pad, launch, top, coast = 1400.0, 5.0, 1000.0, 13.0   # the coast slows at 2 top / coast^2 = 11.8 m/s^2
    t = np.arange(0.0, 5.0 + coast + 3.0 + (top - MAIN_HEIGHT) / RATE_DROGUE + MAIN_HEIGHT / RATE_MAIN + 5.0,
                  1.0 / rate)
    h = np.full_like(t, pad)
    up = (t > launch) & (t <= launch + coast)
    h[up] = pad + top * (1.0 - ((launch + coast - t[up]) / coast) ** 2)
    fall = RATE_DROGUE / 9.81   # s of free fall from the apogee to the drogue's rate, then steady
    drop = 0.5 * RATE_DROGUE * fall
    drogue_end = launch + coast + fall + (top - drop - MAIN_HEIGHT) / RATE_DROGUE
    down = t > launch + coast
    since = t[down] - launch - coast
    h[down] = pad + top - np.where(since < fall, 0.5 * 9.81 * since ** 2, drop + RATE_DROGUE * (since - fall))
    main = t > drogue_end
    h[main] = pad + MAIN_HEIGHT - RATE_MAIN * (t[main] - drogue_end)
    h = np.maximum(h, pad)
    return t, h + np.random.default_rng(seed).normal(0.0, noise, len(t))


def test_the_pad_the_launch_and_the_apogee_of_a_clean_flight():
    t, h = _flight()
    phases = flight_phases(t, h)
    assert phases.pad_level == pytest.approx(1400.0)
    assert phases.launch_time == pytest.approx(5.0, abs=0.5)   # the last sample within 1 m of the pad
    assert t[phases.launch_index] == phases.launch_time
    assert phases.apogee_time == pytest.approx(18.0, abs=0.05)
    assert phases.apogee_height == pytest.approx(2400.0, abs=0.5)


def test_band_rates_of_a_noisy_log_with_charge_spikes_are_the_flown_ones():
    """1 m rms noise and a 150 m pressure spike at each deployment (the drogue's 1 s after the apogee): the band
    rates within 1 %."""
    t, h = _flight(noise=1.0)
    for when in (19.0, 18.0 + RATE_DROGUE / 9.81 + (1000.0 - 0.5 * RATE_DROGUE ** 2 / 9.81 - MAIN_HEIGHT) / RATE_DROGUE):
        h[np.abs(t - when) < 0.15] -= 150.0
    phases = flight_phases(t, h)
    drogue, used = band_descent_rate(t, h, phases, 1400.0 + 400.0, 1400.0 + 900.0)
    assert drogue == pytest.approx(RATE_DROGUE, rel=0.01) and used > 300
    main, _ = band_descent_rate(t, h, phases, 1400.0 + 50.0, 1400.0 + 250.0)
    assert main == pytest.approx(RATE_MAIN, rel=0.01)
    assert phases.apogee_time == pytest.approx(18.0, abs=0.1)


def test_a_single_sample_derivative_is_what_the_band_rate_is_not():
    """The derivative of one noisy pair swings by tens of m/s; the Theil-Sen slope does not."""
    t, h = _flight(noise=1.0)
    derivative = np.diff(h) / np.diff(t)
    assert np.std(derivative[(t[1:] > 22.0) & (t[1:] < 40.0)]) > 10.0
    assert theil_sen_slope(t[(t > 22.0) & (t < 40.0)], h[(t > 22.0) & (t < 40.0)]) == pytest.approx(-RATE_DROGUE,
                                                                                                    rel=0.01)


@pytest.mark.parametrize("bad, message", [
    (lambda t, h: (t, np.full_like(h, 1400.0)), "never rises"),
    (lambda t, h: (t[t < 17.0], h[t < 17.0]), "still rises at the log's end"),
    (lambda t, h: (t, np.where(t > 18.0, 2400.0, h)), "never falls"),
    (lambda t, h: (t[::-1], h), "times must increase"),
])
def test_a_log_without_a_launch_an_apogee_a_descent_or_ordered_times_says_which(bad, message):
    t, h = _flight()
    with pytest.raises(FlightPhaseError, match=message):
        flight_phases(*bad(t, h))


@pytest.mark.parametrize("field", [0.0, 40.0, -25.0])
def test_the_touchdown_on_a_field_at_or_off_the_pads_level(field):
    """The main's descent at 6 m/s ends on a field ``field`` m above the pad (a hill; below it, a valley), with 1 m
    rms noise: the touchdown is where the descent stops, to within the band's crossing (LANDED_BAND at 6 m/s) and a
    second of the running median."""
    t, clean = _flight()
    t, clean = np.concatenate([t, t[-1] + np.arange(1, 201) * 0.05]), np.concatenate([clean, np.full(200, 1400.0)])
    landed = t[np.argmax((t > 30.0) & (clean <= 1400.0))]   # on the pad's level; 15 s on the ground
    touchdown = landed - field / RATE_MAIN
    after = t >= min(landed, touchdown)
    h = clean.copy()
    h[after] = np.maximum(1400.0 - RATE_MAIN * (t[after] - landed), 1400.0 + field)
    h += np.random.default_rng(2).normal(0.0, 1.0, len(t))
    found = t[touchdown_index(t, h, flight_phases(t, h))]
    assert found == pytest.approx(touchdown, abs=LANDED_BAND / RATE_MAIN + 1.0)


def test_a_log_that_ends_in_the_air_has_no_touchdown():
    t, h = _flight()
    keep = t < 60.0
    assert touchdown_index(t[keep], h[keep], flight_phases(t[keep], h[keep])) is None
