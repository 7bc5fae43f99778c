"""The rocket as it hangs (issue 56), in real runs: the body alone falling broadside reaches the terminal velocity of
its cross-flow drag; under the main with the drogue still on its harness (the default) the rocket settles at the
rate of both canopies' C_D S; the main deploys its lag after the trigger's sample."""

import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.authoring.write import new_case_text
from pchute_exudyn.case.files import tomllib
from pchute_exudyn.case.loader import build_case
from pchute_exudyn.physics.slender_body import crossflow_normal_coefficient

GRAVITY = 9.80665   # m/s^2: the flat planet's
ROCKET = dict(dual_deploy=True, planet="flat", canopy_type="flat_circular", mass=12.8, diameter=0.1, length=2.6,
              drogue_diameter=0.6096, drogue_drag_coefficient=1.6, main_drag_area=4.0, ground_elevation=200.0)


def _case(data: dict, name: str):
    return build_case(data, {}, name)


def test_the_body_alone_falling_broadside_reaches_its_crossflow_terminal_velocity():
    data = tomllib.loads(new_case_text(**ROCKET, main_height=100.0, height=900.0))
    for key in ("drogue_canopy", "main_canopy"):
        del data["bodies"][key]
    del data["systems"]
    data["bodies"]["rocket"]["mass_includes_packed"] = False
    data["simulation"]["duration"] = 20.0
    case = _case(data, "the rocket body alone, broadside")
    result = pc.simulate(case)
    rocket = case.bodies["rocket"].aerodynamics
    drag_area = rocket.reference_area * crossflow_normal_coefficient(90.0, 2.6, 0.1)   # eta C_dc L d
    assert drag_area == pytest.approx(0.7758 * 1.2 * 0.26, rel=1e-4)
    assert np.max(np.abs(result["rocket_angle_of_attack_deg"][1:] - 90.0)) < 1e-6   # no moment: it stays broadside
    altitude, rate = result["rocket_altitude"][-1], result["rocket_velocity_down"][-1]
    terminal = math.sqrt(2.0 * 12.8 * GRAVITY / (case.atmosphere.density(altitude) * drag_area))
    assert rate == pytest.approx(terminal, rel=0.005)   # measured: 0.22 % fast (it lags the thickening air)


def test_under_the_main_with_the_drogue_attached_it_settles_at_both_canopies_rate():
    data = tomllib.loads(new_case_text(**ROCKET, body_drag="off", main_height=200.0, height=260.0))
    assert "cutaway_trigger" not in data["systems"]["drogue"]
    case = _case(data, "drogue attached under the main")
    result = pc.simulate(case)
    assert result.summary.end == "touchdown"
    height = 30.0
    when = np.interp(-(200.0 + height), -result["rocket_altitude"], result.time)
    rate = float(np.interp(when, result.time, result["rocket_velocity_down"]))
    both = 4.0 + 1.6 * math.pi * 0.6096**2 / 4.0   # m^2: the main's C_D S and the 24 in drogue's
    steady = math.sqrt(2.0 * 12.8 * GRAVITY / (case.atmosphere.density(200.0 + height) * both))
    assert rate == pytest.approx(steady, rel=0.01)   # measured: 0.20 % fast
    alone = math.sqrt(2.0 * 12.8 * GRAVITY / (case.atmosphere.density(200.0 + height) * 4.0))
    assert rate < 0.96 * alone   # the drogue's share is not lost


def test_the_main_deploys_its_lag_after_the_trigger_sample():
    choices = dict(**ROCKET, body_drag="off", main_height=200.0, height=260.0, main_opening_time=1.5)
    events = {}
    for lag in (0.0, 0.7):
        result = pc.simulate(_case(tomllib.loads(new_case_text(**choices, main_lag=lag)), f"lag {lag}"),
                             duration=14.0)
        events[lag] = {(e.kind, getattr(e, "system", None)): e.time for e in result.summary.events}
    assert events[0.7]["deploy", "main"] == pytest.approx(events[0.0]["deploy", "main"] + 0.7, abs=1e-9)
