"""Atmosphere and aerodynamics kernels against hand values (mer.md "Atmosphere", "Parachute aerodynamics")."""

import math

import numpy as np
import pytest

from pchute_exudyn.case.tables import read_atmosphere_table
from pchute_exudyn.physics.aerodynamics import CoefficientTable, aerodynamic_force, angle_of_attack_deg
from pchute_exudyn.physics.atmosphere import MarsGRC, OutsideAtmosphereError

MER_CN = CoefficientTable((0.0, 5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 90.0),
                          (0.0, 0.040, 0.080, 0.110, 0.130, 0.150, 0.140, 0.110, 0.0))


@pytest.mark.parametrize("h, expected", [
    (0.0, 0.699 / (0.1921 * (273.1 - 31.0))),                                          # 0.015030 kg/m^3
    (5000.0, 0.699 * math.exp(-0.45) / (0.1921 * (273.1 - 31.0 - 4.99))),             # lower layer
    (8380.217, 0.699 * math.exp(-0.00009 * 8380.217) / (0.1921 * (273.1 - 23.4 - 0.00222 * 8380.217))),
])
def test_mars_grc_hand_values(h, expected):
    assert MarsGRC().density(h) == pytest.approx(expected, rel=1e-13)


def test_mars_grc_numbers():
    assert MarsGRC().density(0.0) == pytest.approx(0.015030, abs=2e-6)
    # 8000 m: T = -41.16 C, p = 0.3403 kPa -> 0.3403 / (0.1921 * 231.94) = 0.007637 kg/m^3
    assert MarsGRC().density(8000.0) == pytest.approx(0.007637, abs=2e-6)


def test_table_is_log_linear_and_exact_for_an_exponential(tmp_path):
    path = tmp_path / "atm.csv"
    heights = np.arange(0.0, 12001.0, 2000.0)
    path.write_text("# exponential, H = 11.1 km\naltitude,density\n"
                    + "".join(f"{h},{0.02 * math.exp(-h / 11100.0)}\n" for h in heights))
    table = read_atmosphere_table(path)
    for h in (0.0, 1234.0, 7777.7, 12000.0):
        assert table.density(h) == pytest.approx(0.02 * math.exp(-h / 11100.0), rel=1e-12)
    with pytest.raises(OutsideAtmosphereError, match="outside the atmosphere table"):
        table.density(12000.1)


def test_axial_force_at_zero_incidence():
    # falling straight down along the parachute +x (nadir) axis: pure drag q S C_A, upward
    rho, v = 0.01, 80.0
    force = aerodynamic_force((0.0, 0.0, -v), (0.0, 0.0, -1.0), rho, 178.47, 0.46, MER_CN)
    assert force == pytest.approx((0.0, 0.0, 0.5 * rho * v * v * 178.47 * 0.46), rel=1e-14)


def test_normal_force_opposes_crossflow_and_table_interpolates():
    # velocity at 25 deg from the axis: C_N(25) = 0.14, C_A constant
    alpha = math.radians(25.0)
    velocity = (math.sin(alpha) * 50.0, 0.0, -math.cos(alpha) * 50.0)
    axis = (0.0, 0.0, -1.0)
    q_s = 0.5 * 0.01 * 2500.0 * 10.0
    f = aerodynamic_force(velocity, axis, 0.01, 10.0, 0.5, MER_CN)
    assert MER_CN(25.0) == pytest.approx(0.14)
    assert f[0] == pytest.approx(-q_s * 0.14)            # against the crossflow (+x of the frame)
    assert f[2] == pytest.approx(q_s * 0.5)              # axial: -q S C_A e with e = -z
    assert angle_of_attack_deg(velocity, axis) == pytest.approx(25.0)


def test_folded_angle_beyond_90_degrees():
    # alpha = 150 deg folds to alpha' = 30 deg: C_N = 0.15
    alpha = math.radians(150.0)
    velocity = (math.sin(alpha), 0.0, -math.cos(alpha))
    f = aerodynamic_force(velocity, (0.0, 0.0, -1.0), 2.0, 1.0, 0.0, MER_CN)
    assert f[0] == pytest.approx(-1.0 * 0.15)
    assert aerodynamic_force((0, 0, 0), (0, 0, -1), 1.0, 1.0, 1.0, MER_CN) == (0.0, 0.0, 0.0)


def test_table_interpolation_is_linear_inside_and_held_beyond_the_ends():
    from pchute_exudyn.physics.interpolation import bracket, interpolate_held
    xs, ys = (0.0, 1.0, 3.0), (10.0, 20.0, 0.0)
    assert interpolate_held(xs, ys, 0.5) == pytest.approx(15.0)
    assert interpolate_held(xs, ys, 2.0) == pytest.approx(10.0)
    assert interpolate_held(xs, ys, -5.0) == 10.0 and interpolate_held(xs, ys, 9.0) == 0.0
    assert interpolate_held(xs, ys, 1.0) == 20.0                     # a breakpoint is hit exactly
    assert bracket(xs, 0.0) == (1, 0.0) and bracket(xs, 3.0) == (2, 1.0)
