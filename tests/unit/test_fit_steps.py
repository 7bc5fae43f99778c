"""A fit's flags and steps near its bounds (fit.solve) and a run's alignment to a flight log (fit.evaluate)."""

import numpy as np
import pytest

from pchute_exudyn.fit.evaluate import aligned_to_log
from pchute_exudyn.fit.solve import DIFFERENCE_STEP, _signed_step, at_bounds


def test_a_value_within_the_jacobians_step_of_a_bound_is_at_the_bound():
    """The trust-region method never lands on a bound: 1e-5 of the range from it is on it, for the fit's own
    derivative (a step of DIFFERENCE_STEP) cannot tell the two apart."""
    assert at_bounds([1e-5, 1.0 - 1e-5, 0.5, 2.0 * DIFFERENCE_STEP]) == [True, True, False, False]


@pytest.mark.parametrize("u, step, expected", [(0.5, 0.1, 0.1), (0.95, 0.1, -0.1), (0.3, 0.8, 0.7),
                                               (0.7, 0.8, -0.7)])
def test_a_widened_step_stays_inside_the_bounds(u, step, expected):
    assert _signed_step(u, step) == pytest.approx(expected)
    assert 0.0 <= u + _signed_step(u, step) <= 1.0


def test_a_run_is_aligned_to_a_log_shifted_in_time_and_height():
    """A descent log 0.07 s late and 0.4 m high (its apogee time and pad level as a log knows them): the aligned run
    matches it to the interpolation's error, where the unaligned one is metres off."""
    time = np.arange(0.0, 60.0, 0.05)
    height = 1000.0 - 4.9 * np.minimum(time, 3.0) ** 2 - 29.4 * np.clip(time - 3.0, 0.0, None)
    times = np.arange(0.5, 55.0, 0.1)
    measured = np.interp(times - 0.07, time, height) + 0.4
    assert np.abs(np.interp(times, time, height) - measured).max() > 1.5
    assert np.abs(aligned_to_log(time, height, times, measured) - measured).max() < 0.01
