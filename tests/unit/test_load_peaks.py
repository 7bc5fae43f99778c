"""The peaks of a load history (``physics.load_peaks``) against closed forms."""

import math

import numpy as np
import pytest

from pchute_exudyn.physics.load_peaks import averaged_peak, first_peak, largest


def test_the_first_peak_is_the_first_hump_s_top_and_the_largest_the_highest():
    times = np.linspace(0.0, 2.0, 2001)
    loads = np.where(times < 1.0, np.sin(math.pi * times), 2.0 * np.sin(math.pi * (times - 1.0)))
    assert first_peak(times, loads) == pytest.approx((1.0, 0.5), abs=1e-3)
    assert largest(times, loads) == pytest.approx((2.0, 1.5), abs=1e-3)


def test_an_averaged_half_sine_peaks_at_its_closed_form_and_a_fast_chatter_on_it_averages_out():
    """A half sine of amplitude A and length T averaged over w peaks at A sin(pi w / 2T) / (pi w / 2T); a 500 Hz
    ripple of 10 % on it adds nothing a 20 ms window keeps (10 periods)."""
    amplitude, length, window = 1000.0, 0.2, 0.02
    times = np.linspace(0.0, 0.4, 40001)
    hump = np.where(times < length, amplitude * np.sin(math.pi * times / length), 0.0)
    half = math.pi * window / (2.0 * length)
    expected = amplitude * math.sin(half) / half
    assert averaged_peak(times, hump, 0.0, 0.4, window) == pytest.approx(expected, rel=1e-4)
    ripple = hump + 0.1 * amplitude * np.sin(2.0 * math.pi * 500.0 * times) * (times < length)
    assert averaged_peak(times, ripple, 0.0, 0.4, window) == pytest.approx(expected, rel=2e-3)
    assert largest(times, ripple)[0] > 1.05 * amplitude   # the raw peak keeps the ripple
