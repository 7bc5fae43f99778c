"""Lines in series through a massless confluence (docs/models/step_control.md, "Lines in series"): one line of the
series stiffness, exact in the massless limit; SP and the equilibrium point fly such a pair."""


import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.physics.lines import series_pair

HANGING = '''
[case]
name = "two lines in series"
description = "A mass hanging at rest from a fixed point by two lines in series"
vehicle = "payload"
[planet]
model = "flat"
gravity = 9.81
[bodies.anchor]
fixed = true
points.top = [0.0, 0.0, 0.0]
initial.altitude = 100.0
[bodies.payload]
mass = 100.0
inertia = [10.0, 10.0, 10.0]
points.top = [0.0, 0.0, 0.0]
[bodies.payload.initial]
altitude = {payload}
[systems.hang.confluence]
mass = 1.0
initial.altitude = {confluence}
[systems.hang.lines.upper]
attach = "anchor.top"
free_length = 10.0
stiffness = 40000.0
damping = 400.0
[systems.hang.lines.lower]
attach = "payload.top"
free_length = 15.0
stiffness = 20000.0
damping = 200.0
[simulation]
duration = 2.0
output_step = 0.5
stop_at_ground = false
'''
WEIGHT = 100.0 * 9.81
SERIES_STIFFNESS = 40000.0 * 20000.0 / 60000.0


@pytest.mark.parametrize("method, options", [("sp", {"preset": "thesis"}), ("equilibrium", {})])
def test_two_lines_in_series_hang_as_one_line_of_the_series_stiffness(tmp_path, method, options):
    """Started at the static state of one line of stiffness K1 K2 / (K1 + K2) and free length L1 + L2, the pair (the
    massless confluence of SP's thesis preset and of the equilibrium point) holds the mass there: the tension is m g
    and the length L1 + L2 + m g / K_s, within 1e-9, at the adaptive steps and at a fixed one."""
    length = 25.0 + WEIGHT / SERIES_STIFFNESS
    path = tmp_path / "hang.toml"
    path.write_text(HANGING.format(payload=100.0 - length, confluence=100.0 - 10.0 - WEIGHT / 40000.0))
    case = pc.load_case(path)
    for step in ("auto", 0.01):
        result = pc.simulate(case, method, "rk4", step, **options)
        for line in ("upper", "lower"):
            np.testing.assert_allclose(result[f"tension_{line}"], WEIGHT, rtol=1e-9)
        np.testing.assert_allclose(100.0 - result["payload_altitude"], length, rtol=1e-9)
        # the confluence where the stretches put it: the upper line stretched m g / K1
        np.testing.assert_allclose(100.0 - result["confluence_altitude"], 10.0 + WEIGHT / 40000.0, rtol=1e-9)


def test_the_pair_is_one_kelvin_voigt_line_when_the_time_constants_are_equal():
    """C_s = (C1 K2^2 + C2 K1^2) / (K1 + K2)^2 is tau K_s when C1 / K1 = C2 / K2 = tau: the pair's tension at any
    stretch and rate is that of one line of K_s and tau K_s; the weight along the pair adds to the first line's."""
    lines = np.array([[10.0, 40000.0, 400.0], [15.0, 20000.0, 200.0]])
    tables, counts = np.zeros((2, 2, 2)), np.zeros(2, np.int64)
    for stretch, rate in ((0.01, 0.0), (0.05, 0.3), (0.02, -0.1)):
        first, second, e1, _ = series_pair(lines, tables, counts, 25.0 + stretch, rate, 0.0)
        assert second == pytest.approx(SERIES_STIFFNESS * stretch + 0.01 * SERIES_STIFFNESS * rate, rel=1e-12)
        assert first == second and e1 == pytest.approx(stretch * 20000.0 / 60000.0, rel=1e-12)
    first, second, _, _ = series_pair(lines, tables, counts, 25.05, 0.0, 9.81)
    assert first - second == pytest.approx(9.81, rel=1e-12)
    assert series_pair(lines, tables, counts, 24.9, 1.0, 0.0)[:2] == (0.0, 0.0)   # slack: no tension


def test_the_series_compliance_error_is_second_order_in_frequency():
    """With unequal time constants the pair's compliance 1/(K_s + C_s s) matches 1/(K1 + C1 s) + 1/(K2 + C2 s) to
    first order in the frequency; the relative difference is omega^2 Var_w(tau) (the doc's bound) to 2 %."""
    k1, c1, k2, c2 = 40000.0, 400.0, 20000.0, 50.0
    k_s = k1 * k2 / (k1 + k2)
    c_s = (c1 * k2 ** 2 + c2 * k1 ** 2) / (k1 + k2) ** 2
    weights, taus = np.array([k_s / k1, k_s / k2]), np.array([c1 / k1, c2 / k2])
    variance = float(np.sum(weights * (taus - np.sum(weights * taus)) ** 2))
    for omega in (1.0, 5.0, 20.0):
        s = 1j * omega
        exact = 1.0 / (k1 + c1 * s) + 1.0 / (k2 + c2 * s)
        one = 1.0 / (k_s + c_s * s)
        assert abs(exact - one) / abs(exact) == pytest.approx(omega ** 2 * variance, rel=0.02)
