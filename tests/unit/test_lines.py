"""The tension-only line law (thesis Eqs. 1.6-1.7, mer.md "Lines")."""

import numpy as np
import pytest

from pchute_exudyn.physics.lines import LineLaw, line_states, tension_magnitude

BRIDLE = LineLaw(0.7152, 47000.0, 470.0)   # L0 (m), K (N/m), C (N s/m): a MER bridle


def test_closed_form_taut_values():
    # K (L - L0) + C dL/dt: 47000 * 0.01 + 470 * 0.2 = 470 + 94 = 564 N
    assert BRIDLE.tension(0.7252 - 0.7152, 0.2) == pytest.approx(564.0, rel=1e-12)
    assert tension_magnitude([[0.7252]], 0.2, [BRIDLE])[0, 0] == pytest.approx(564.0, rel=1e-12)
    # shortening fast while stretched: the linear law would push (470 - 470 * 2 = -470 N): clipped to 0
    assert BRIDLE.tension(0.7252 - 0.7152, -2.0) == 0.0
    assert tension_magnitude([[0.7252]], -2.0, [BRIDLE])[0, 0] == 0.0


def test_zero_when_slack_whatever_the_rate():
    lengths = np.array([0.1, 0.7, 0.7152])   # the last is exactly at free length: slack by definition (L > L0 taut)
    for rate in (-5.0, 0.0, 5.0):
        assert np.all(tension_magnitude(lengths[:, None], rate, [BRIDLE]) == 0.0)
        assert all(BRIDLE.tension(length - 0.7152, rate) == 0.0 for length in lengths)


def test_never_negative_on_random_states():
    rng = np.random.default_rng(1)
    length = rng.uniform(0.0, 2.0, 10000)
    rate = rng.uniform(-50, 50, 10000)
    tension = tension_magnitude(length[:, None], rate[:, None], [LineLaw(1.0, 6e4, 600.0)])[:, 0]
    assert np.all(tension >= 0.0)
    taut_pulling = (length > 1.0) & (6e4 * (length - 1) + 600 * rate > 0)
    assert np.all((tension > 0) == taut_pulling)


def test_vectorised_over_lines_direction_and_rate():
    # confluence at the origin moving up at 1 m/s; two lines: one straight up (stretched), one along +x (slack)
    attach = np.array([[0.0, 0.0, 1.1], [0.5, 0.0, 0.0]])
    attach_velocity = np.zeros((2, 3))
    state = line_states(attach, attach_velocity, np.zeros(3), np.array([0.0, 0.0, 1.0]),
                        [LineLaw(1.0, 1000.0, 10.0)] * 2)
    np.testing.assert_allclose(state.length, [1.1, 0.5])
    np.testing.assert_allclose(state.direction, [[0, 0, 1], [1, 0, 0]])
    np.testing.assert_allclose(state.length_rate, [-1.0, 0.0])        # the confluence closes on the upper point
    np.testing.assert_allclose(state.tension, [1000 * 0.1 - 10 * 1.0, 0.0])
    np.testing.assert_array_equal(state.taut, [True, False])
    # the line pulls the confluence toward the attach point and the body toward the confluence
    np.testing.assert_allclose(state.force_on_confluence()[0], [0, 0, 90.0])
    np.testing.assert_allclose(state.force_on_body()[0], [0, 0, -90.0])


def test_broadcasts_over_samples():
    attach = np.zeros((5, 3, 3))
    attach[..., 2] = np.linspace(1.0, 1.4, 5)[:, None]
    state = line_states(attach, np.zeros((5, 3, 3)), np.zeros((5, 3)), np.zeros((5, 3)),
                        [LineLaw(1.0, 100.0, 0.0)] * 3)
    assert state.tension.shape == (5, 3)
    np.testing.assert_allclose(state.tension[:, 0], 100 * np.clip(np.linspace(0, 0.4, 5), 0, None))
