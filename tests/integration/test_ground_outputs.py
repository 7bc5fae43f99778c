"""What a run says about the ground (issue 48): each point's height above the case's ground beside its altitude, the
touchdown velocity split into a descent rate and a horizontal speed over the ground beside the total, and the
figures that show them (the ground track, the overview's events and its Mach and dynamic pressure panels).

The runs are a drag body (``PROBE``: C_N = C_D sin(alpha'), aerodynamic centre at the centre of mass, so it falls
along its air-relative velocity without turning) started at its steady rate of descent: at the ground it descends
at sqrt(2 m g / (rho C_D S)) of the ground's density and moves with the air."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.registries.columns import column
from pchute_exudyn.results.run_line import run_line

GROUND = 1000.0   # m
MASS, AREA, DRAG, GRAVITY = 100.0, 20.0, 1.0, 9.80665   # kg, m^2, -, m/s^2
FLAT = f"""
[planet]
model = "flat"
gravity = {GRAVITY}
"""
ROTATING = """
[planet]                      # WGS-84, turning: the local vertical turns away from the start point's as it drifts
name = "Earth"
gravitational_parameter = 3.986004418e14
equatorial_radius = 6378137.0
polar_radius = 6356752.314
rotation_rate = 7.292115e-5
[start]
latitude_deg = 50.0
longitude_deg = 0.0
"""
PROBE = f"""
[case]
vehicle = "probe"
[atmosphere]
model = "us76"
[bodies.probe]
mass = {MASS}
inertia = [10.0, 10.0, 10.0]
initial.altitude = 1300.0
initial.velocity_down = 8.43
[bodies.probe.aerodynamics]
reference_area = {AREA}
axial_coefficient = {DRAG}
center = [0.0, 0.0, 0.0]
normal_coefficient = {{ alpha_deg = [0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0], value = [0.0, 0.2588, 0.5, 0.7071, 0.8660, 0.9659, 1.0] }}
[simulation]
duration = 100.0
ground_altitude = {GROUND}
[simulation.steps]
full = 0.01
"""


@pytest.fixture(scope="module")
def probe(tmp_path_factory):
    path = tmp_path_factory.mktemp("probe") / "probe.toml"
    path.write_text(FLAT + PROBE)
    return path


@pytest.fixture(scope="module")
def turning(tmp_path_factory):
    path = tmp_path_factory.mktemp("turning") / "probe.toml"
    path.write_text(ROTATING + PROBE)
    return path


def touchdown_of(result):
    return result.summary.touchdown


def test_height_is_the_altitude_above_the_cases_ground(probe):
    result = pc.simulate(pc.load_case(probe), duration=5.0)
    altitude, height = column("{owner}_altitude", "probe"), column("{owner}_height", "probe")
    assert result.units[height] == "m"
    assert np.array_equal(result[height], result[altitude] - GROUND)
    assert result[height][0] == pytest.approx(300.0)


def test_every_altitude_column_has_its_height(tmp_path):
    from tests.helpers import MER

    result = pc.simulate(pc.load_case(MER / "case1.toml"), "sp", duration=0.2)
    altitudes = [name for name in result.columns if name.endswith("_altitude")]
    assert len(altitudes) >= 3   # the bodies and the confluence
    for name in altitudes:
        assert np.array_equal(result[name[:-len("altitude")] + "height"], result[name])   # ground at 0 m


def test_in_still_air_it_lands_at_the_steady_rate_of_descent_with_no_horizontal_speed(probe):
    result = pc.simulate(pc.load_case(probe))
    touchdown = touchdown_of(result)
    atmosphere = pc.load_case(probe).atmosphere
    density = atmosphere.state(GROUND)[0]
    steady = math.sqrt(2.0 * MASS * GRAVITY / (density * DRAG * AREA))
    # the steady rate grows with height (thinner air); the probe follows it with the lag of its drag's time constant
    # V / (2 g): V^3 / (4 g) times the density's logarithmic decrease with height, 2.2e-4 of V here
    thinning = (math.log(atmosphere.state(GROUND - 1.0)[0]) - math.log(atmosphere.state(GROUND + 1.0)[0])) / 2.0
    assert touchdown.descent_rate == pytest.approx(steady + steady ** 3 / (4.0 * GRAVITY) * thinning, rel=1e-5)
    assert touchdown.horizontal_speed_over_ground == pytest.approx(0.0, abs=1e-9)
    assert touchdown.speed == pytest.approx(touchdown.descent_rate, rel=1e-12)
    line = run_line(result.summary, "out")
    assert f"descent rate {touchdown.descent_rate:.2f} m/s, horizontal speed 0.00 m/s" in line


def test_in_a_steady_wind_it_lands_moving_with_the_wind(probe):
    wind_east, wind_north = 3.0, -4.0   # m/s: 5 m/s
    result = pc.simulate(pc.load_case(probe, {"atmosphere.wind.east": wind_east,
                                              "atmosphere.wind.north": wind_north}))
    touchdown = touchdown_of(result)
    still = touchdown_of(pc.simulate(pc.load_case(probe)))
    assert touchdown.horizontal_speed_over_ground == pytest.approx(5.0, abs=1e-6)
    assert touchdown.descent_rate == pytest.approx(still.descent_rate, rel=1e-6)
    assert touchdown.speed == pytest.approx(math.hypot(5.0, still.descent_rate), rel=1e-6)
    from pchute_exudyn.study.runner import scalar_outputs

    outputs = scalar_outputs(result)
    assert outputs["touchdown_horizontal_speed"] == touchdown.horizontal_speed_over_ground
    assert outputs["touchdown_descent_rate"] == touchdown.descent_rate
    assert outputs["touchdown_speed"] == touchdown.speed


def test_the_speeds_at_touchdown_add_up_over_a_rotating_earth(turning, tmp_path):
    """Descent rate (down the local vertical) and horizontal speed over the ground (across it) are the two parts of
    the velocity relative to the ground: their squares add up to the total's; the air turns with the Earth, so the
    probe lands moving with the wind."""
    result = pc.simulate(pc.load_case(turning, {"atmosphere.wind.east": 5.0}))
    touchdown = touchdown_of(result)
    assert touchdown.descent_rate ** 2 + touchdown.horizontal_speed_over_ground ** 2 == pytest.approx(
        touchdown.speed ** 2, rel=1e-12)
    assert touchdown.horizontal_speed_over_ground == pytest.approx(5.0, abs=0.05)
    result.save(tmp_path / "run", plot=False)
    assert pc.Result.load(tmp_path / "run").summary.touchdown == touchdown


def test_a_saved_run_has_its_ground_track_and_the_overview_its_mach_and_pressure(probe, tmp_path):
    from pchute_exudyn.views.plotting import plot_overview

    result = pc.simulate(pc.load_case(probe, {"atmosphere.wind.east": 5.0}))
    paths = result.save(tmp_path / "run")
    assert paths["ground_track"].name == "ground_track.png" and paths["ground_track"].stat().st_size > 10000
    labels = [ax.get_ylabel() for ax in plot_overview(result).axes]
    assert labels == ["line tension (N)", "probe altitude (m)", "probe Mach number (-)",
                      "probe dynamic pressure (Pa)", "probe altitude (m)"]
    time_axes = plot_overview(result).axes[:4]
    touchdown = touchdown_of(result).time
    assert all(any(np.allclose(line.get_xdata(), touchdown) for line in ax.get_lines()) for ax in time_axes)
