"""How descents start (docs/case-format.md, ``[start]``): initial velocities relative to the air, a release from an
aircraft, and `pchute new`'s steady rate against the run it writes."""

from __future__ import annotations

import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.authoring.choices import NewCase
from pchute_exudyn.authoring.layout import layout
from pchute_exudyn.case.overrides import Scale, apply_override, tomllib
from pchute_exudyn.results.summary import StartEvent
from tests.helpers import ROOT

CASE1 = ROOT / "cases" / "mer" / "case1.toml"
CARGO = dict(planet="earth", mass=2000.0, canopy_diameter=30.5, canopy_type="flat_circular", canopies=3)


def test_velocities_relative_to_the_air_add_the_wind_at_the_vehicles_altitude():
    """Every body and confluence gets the steady wind at the vehicle's start altitude (a table: interpolated there),
    the file's velocities then being relative to the air; relative to the ground (the default) they are kept."""
    wind = {"atmosphere.wind.altitude": [0.0, 8380.217, 9000.0], "atmosphere.wind.east": [0.0, 7.0, 20.0],
            "atmosphere.wind.north": [0.0, -3.0, 0.0], "vehicle.initial.velocity_east": 1.0}
    ground = pc.load_case(CASE1, wind)
    air = pc.load_case(CASE1, {**wind, "start.velocities_relative_to": "air"})
    assert ground.bodies["vehicle"].initial.velocity_east == 1.0
    assert air.velocities_relative_to == "air"
    for state in [body.initial for body in air.bodies.values()] + [air.systems["main"].confluence.initial]:
        assert (state.velocity_north, state.velocity_down) == (-3.0, 0.0)
    assert air.bodies["vehicle"].initial.velocity_east == 8.0 and air.bodies["parachute"].initial.velocity_east == 7.0


def test_a_start_moving_with_a_constant_wind_is_the_still_air_run_carried_by_it():
    """Galilean invariance: MER case 1 started with the air in a 15 m/s wind is the still-air run carried by the wind
    (displaced by the wind times the time, with the same tensions; the planet's curvature under 60 m of drift moves
    them by less than the tolerances)."""
    overrides = {"simulation.duration": 4.0}
    base = pc.simulate(pc.load_case(CASE1, overrides), "sp")
    windy = pc.simulate(pc.load_case(CASE1, {**overrides, "atmosphere.wind.east": 15.0,
                                             "start.velocities_relative_to": "air"}), "sp")
    time = base.time
    np.testing.assert_allclose(windy["vehicle_east"] - base["vehicle_east"], 15.0 * time, atol=2e-3)
    np.testing.assert_allclose(windy["tension_riser"], base["tension_riser"], rtol=1e-6, atol=1e-3)


def test_a_release_gives_the_vehicle_the_aircrafts_velocity_through_the_air(tmp_path):
    """V (cos(gamma) sin(psi), cos(gamma) cos(psi), sin(gamma)) plus the wind, east/north/up; every system deploys at
    line stretch after the static line's time."""
    path = tmp_path / "release.toml"
    path.write_text(pc.new_case_text(**CARGO, altitude=1500.0, release_airspeed=65.0, release_heading_deg=30.0,
                                     release_flight_path_deg=-10.0, static_line_time=1.5))
    case = pc.load_case(path, {"atmosphere.wind.speed": 5.0, "atmosphere.wind.from_deg": 270.0})
    state = case.bodies["vehicle"].initial
    horizontal = 65.0 * math.cos(math.radians(-10.0))
    assert state.velocity_east == pytest.approx(horizontal * math.sin(math.radians(30.0)) + 5.0, rel=1e-12)
    assert state.velocity_north == pytest.approx(horizontal * math.cos(math.radians(30.0)), abs=1e-9)
    assert state.velocity_down == pytest.approx(65.0 * math.sin(math.radians(10.0)), rel=1e-12)
    assert case.release.airspeed == 65.0 and case.systems["main"].deploy_time == 1.5
    assert all(case.bodies[c].initial is None for c in case.systems["main"].canopies)


@pytest.mark.parametrize("canopies", [1, 2, 3, 5])
def test_pchute_new_prints_the_rate_its_run_descends_at(canopies):
    """The steady rate `pchute new` states (suspended mass, the cluster's drag efficiency and spread, the air where
    the drag acts) is the run's rate within 0.2 %: the case written 150 m higher, measured as it passes the stated
    altitude."""
    stated = 1500.0
    plan = layout(NewCase(**{**CARGO, "canopies": canopies}, altitude=stated))
    case = pc.new_case(**{**CARGO, "canopies": canopies}, altitude=stated + 150.0)
    result = pc.simulate(case, "sp", duration=40.0)
    when = np.interp(-stated, -result["vehicle_altitude"], result.time)
    rate = float(np.interp(when, result.time, result["vehicle_velocity_down"]))
    assert when > 15.0   # the start transient has passed (its lines at free length)
    assert rate == pytest.approx(plan.steady_rate(stated), rel=2e-3)


def test_a_released_cluster_opens_with_per_canopy_loads_and_settles(tmp_path):
    """Released at 65 m/s from 600 m: each canopy's opening load peaks during its fill (after line stretch, before
    the fill time plus its overshoot's fall is over), and the payload lands at the steady rate `pchute new` prints
    for the ground (within 1 %)."""
    path = tmp_path / "release.toml"
    choices = dict(CARGO, altitude=600.0, release_airspeed=65.0, release_heading_deg=90.0)
    path.write_text(pc.new_case_text(**choices))
    result = pc.simulate(pc.load_case(path), "sp")
    summary = result.summary
    assert summary.events[0] == StartEvent(0.0, "air", {"airspeed": 65.0, "heading_deg": 90.0,
                                                         "flight_path_deg": 0.0})
    starts = summary.events_of("stage_start")
    assert [e.canopy for e in starts] == ["canopy1", "canopy2", "canopy3"]
    assert all(e.time == pytest.approx(1.0) and e.speed == pytest.approx(65.0, rel=0.05) for e in starts)
    for canopy, stages in summary.opening_loads.items():
        (peak,) = stages[0]["peaks"].values()
        assert 1.0 < peak["time"] < 1.0 + 1.25 * starts[0].fill_time
        assert peak["tension"] == pytest.approx(np.nanmax(result[f"tension_riser_{canopy}"]))   # the largest of the run
    assert summary.end == "touchdown"
    assert summary.descent.mean_rate == pytest.approx(layout(NewCase(**choices)).steady_rate(0.0), rel=0.01)


def test_a_relative_dispersion_scales_a_coefficient_tables_values():
    """`relative = true` on a coefficient table (what `pchute new` writes for C_A) scales its values, not its
    breakpoints; a list of numbers is scaled entry by entry."""
    text = pc.new_case_text(planet="earth", mass=100.0, drag_area=40.0, altitude=3000.0)
    data = tomllib.loads(text)
    apply_override(data, {}, "canopy.aerodynamics.axial_coefficient", Scale(1.1))
    apply_override(data, {}, "vehicle.inertia", Scale(2.0))
    table = data["bodies"]["canopy"]["aerodynamics"]["axial_coefficient"]
    assert table["alpha_deg"] == [0.0, 60.0, 90.0]
    assert table["value"] == pytest.approx([0.55 * 1.1, 0.55 * 1.1, 0.0], rel=1e-15)
    inertia = tomllib.loads(text)["bodies"]["vehicle"]["inertia"]
    assert data["bodies"]["vehicle"]["inertia"] == pytest.approx([2.0 * value for value in inertia], rel=1e-15)


EDL = ROOT / "cases" / "mer" / "edl.toml"
CONDITIONS = {"mach": 2.07, "dynamic_pressure": 846.0, "flight_path_deg": -25.0, "heading_deg": 90.0}


def conditions_case(folder, **keys) -> str:
    """cases/mer/edl.toml with its vehicle started at flight conditions (``CONDITIONS`` updated by ``keys``) instead
    of its altitude and velocity."""
    path = folder / "conditions.toml"
    given = "\n".join(f"{key} = {value}" for key, value in {**CONDITIONS, **keys}.items())
    path.write_text(f'extends = "{EDL.as_posix()}"\nremove = ["bodies.vehicle.initial.altitude", '
                    '"bodies.vehicle.initial.velocity_down", "bodies.vehicle.initial.velocity_east"]\n'
                    f"[bodies.vehicle.initial]\n{given}\n")
    return str(path)


@pytest.mark.parametrize("frame", ["ground", "air"])
def test_a_start_at_flight_conditions_finds_the_altitude_and_speed_in_the_atmosphere(tmp_path, frame):
    """Mach, dynamic pressure, flight-path angle and heading give the altitude where the Mars model has that pair and
    a velocity of M a(h) at that angle through the air, the wind added whatever the velocities are relative to."""
    case = pc.load_case(conditions_case(tmp_path), {"atmosphere.wind.east": 10.0, "start.velocities_relative_to": frame})
    state = case.bodies["vehicle"].initial
    density, sound = case.atmosphere.state(state.altitude)
    air = np.array([state.velocity_east - 10.0, state.velocity_north, -state.velocity_down])
    speed = float(np.linalg.norm(air))
    assert speed == pytest.approx(2.07 * sound, rel=1e-12)
    assert 0.5 * density * speed ** 2 == pytest.approx(846.0, rel=1e-12)
    assert math.degrees(math.asin(air[2] / speed)) == pytest.approx(-25.0, abs=1e-9)
    assert air[1] == pytest.approx(0.0, abs=1e-9) and air[0] > 0.0
    assert state.conditions.mach == 2.07 and 9000.0 < state.altitude < 10000.0


def test_a_run_from_flight_conditions_records_them_at_its_first_sample(tmp_path):
    """SP from the conditions in a wind: the vehicle's Mach number and dynamic pressure at t = 0 are the given ones
    (body +x horizontal, yaw 90 deg, so that the aerodynamic centre is at the centre of mass's altitude)."""
    case = pc.load_case(conditions_case(tmp_path), {"atmosphere.wind.east": 10.0, "vehicle.initial.yaw_deg": 90.0,
                                                    "simulation.duration": 0.1})
    result = pc.simulate(case, "sp")
    assert result["vehicle_mach"][0] == pytest.approx(2.07, rel=1e-6)
    assert result["vehicle_dynamic_pressure"][0] == pytest.approx(846.0, rel=1e-6)
    assert result["vehicle_altitude"][0] == pytest.approx(case.bodies["vehicle"].initial.altitude, abs=1e-6)
