"""The supersonic opening (docs/models/supersonic_opening.md) against its closed forms: a canopy towed at a constant
supersonic speed (tug and canopy of 1e13 kg, no gravity, constant air) sees exactly q S C_A f(t), with f the fill law
whose C_x is the model's load factor at the line-stretch Mach number, whose fill time is n(M) D_0 / V and whose
breathing follows once the overinflation has decayed; the first peak is q S C_A C_k."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pchute_exudyn import load_case, simulate
from pchute_exudyn.errors import CaseError
from pchute_exudyn.physics.inflation import Inflation, InflationStage, nominal_diameter
from pchute_exudyn.physics.supersonic_opening import MachTable, SupersonicOpening
from tests.helpers import ROOT

DENSITY, SOUND, SPEED = 0.02, 300.0, 540.0        # kg/m^3 (tests/cases/constant_air.csv), m/s, m/s: Mach 1.8
AREA, AXIAL = 178.47, 0.46                        # m^2, -
FILL_TIME = 0.25                                  # s: the fill constant is chosen to give it
OPENING = dict(load_factor=1.5, reference_mach=1.7, mach_slope=0.4, wake_coefficient=0.5, forebody_diameter=1.5)
BREATHING = (0.08, 0.2)                           # relative amplitude (-), Strouhal number (-)

TOWED = '''
[case]
name = "towed supersonic canopy"
vehicle = "tug"
[planet]
model = "flat"
gravity = 0.0
[atmosphere]
model = "table"
file = "{air}"
speed_of_sound = {sound}
[bodies.tug]
mass = 1.0e13
inertia = [1.0e13, 1.0e13, 1.0e13]
points = {{ bridle = [0.0, 0.0, 0.0], line_stretch = [-3.0, 0.0, 0.0] }}
[bodies.tug.initial]
altitude = 5000.0
velocity_east = {speed}
yaw_deg = 90.0
roll_deg = -90.0
[bodies.canopy]
mass = 1.0e13
inertia = [1.0e13, 1.0e13, 1.0e13]
points.riser = [20.0, 0.0, 0.0]
[bodies.canopy.aerodynamics]
reference_area = {area}
axial_coefficient = {axial}
center = [0.0, 0.0, 0.0]
normal_coefficient = {{ alpha_deg = [0.0, 90.0], value = [0.0, 0.0] }}
[systems.tow]
canopy = "canopy"
deploy_time = 0.0
deploy_point = "tug.line_stretch"
confluence.mass = 1.0
lines.bridle = {{ attach = "tug.bridle", free_length = 3.0, stiffness = 1.0e6, damping = 1.0e3 }}
lines.riser = {{ attach = "canopy.riser", free_length = 20.0, stiffness = 1.0e6, damping = 1.0e3 }}
[systems.tow.inflation]
stage_start = [0.0]
fraction = [1.0]
fill_constant = [99.0]
exponent = [2.0]
overinflation_decay = 0.25
[systems.tow.inflation.supersonic]
load_factor = {load_factor}
reference_mach = {reference_mach}
mach_slope = {mach_slope}
wake_coefficient = {wake_coefficient}
forebody_diameter = {forebody_diameter}
fill_constant = {{ mach = [1.0, 2.5], value = [{fill}, {fill}] }}
{breathing}
[simulation]
duration = 1.5
output_step = 0.0025
stop_at_ground = false
steps = {{ full = 1.0e-4, full_implicit = 1.0e-3, sp = 1.0e-3, equilibrium = 1.0e-3 }}
'''


def _towed(tmp_path, breathing: bool):
    diameter = nominal_diameter(AREA)
    fill = FILL_TIME * SPEED / diameter
    amplitude, strouhal = BREATHING
    rows = (f"breathing_amplitude = {{ mach = [1.0, 2.5], value = [{amplitude}, {amplitude}] }}\n"
            f"breathing_strouhal = {strouhal}") if breathing else ""
    path = tmp_path / "towed.toml"
    path.write_text(TOWED.format(air=(ROOT / "tests" / "cases" / "constant_air.csv").as_posix(), sound=SOUND,
                                 speed=SPEED, area=AREA, axial=AXIAL, fill=fill, breathing=rows, **OPENING))
    model = SupersonicOpening(**OPENING, fill_constant=MachTable((1.0, 2.5), (fill, fill)),
                              breathing_amplitude=MachTable((1.0, 2.5), (amplitude,) * 2) if breathing else None,
                              breathing_strouhal=strouhal)
    return path, model, diameter


@pytest.mark.parametrize("method", ["full", "sp"])
def test_an_infinite_mass_supersonic_opening_follows_its_law_and_peaks_at_q_s_cd_ck(tmp_path, method):
    path, model, diameter = _towed(tmp_path, breathing=False)
    columns = simulate(load_case(path), method, "rk4").columns
    load_factor = model.load_factor_at(SPEED / SOUND, diameter)
    assert load_factor == pytest.approx((1.5 + 0.4 * 0.1) * (1.0 - 0.5 * 1.5 / diameter), rel=1e-12)
    law = Inflation((InflationStage(0.0, 1.0, 99.0, 2.0),), overinflation_decay=0.25)
    fraction = np.array([law.fraction(t, [FILL_TIME], load_factor) for t in columns["time"]])
    q_s_cd = 0.5 * DENSITY * SPEED ** 2 * AREA * AXIAL
    np.testing.assert_allclose(columns["tow_drag_area_fraction"], fraction, rtol=0, atol=1e-9)
    force = columns["canopy_aerodynamic_force"]
    assert np.max(np.abs(force - q_s_cd * fraction)) / q_s_cd < 1e-6
    assert abs(force.max() / (q_s_cd * load_factor) - 1.0) < 1e-6


def test_the_filled_canopy_breathes_at_its_strouhal_frequency_once_the_overinflation_has_decayed(tmp_path):
    path, model, diameter = _towed(tmp_path, breathing=True)
    columns = simulate(load_case(path), "sp", "rk4").columns
    time = columns["time"]
    amplitude, strouhal = BREATHING
    start = FILL_TIME + 0.25
    after = time > start
    expected = 1.0 + amplitude * np.sin(2.0 * math.pi * strouhal * SPEED / diameter * (time[after] - start))
    np.testing.assert_allclose(columns["tow_drag_area_fraction"][after], expected, rtol=0, atol=1e-9)
    assert abs(columns["tow_drag_area_fraction"].max() - model.load_factor_at(SPEED / SOUND, diameter)) < 1e-9


def test_a_supersonic_opening_in_air_without_a_speed_of_sound_is_refused_in_one_line(tmp_path):
    path, _, _ = _towed(tmp_path, breathing=False)
    path.write_text(path.read_text().replace(f"speed_of_sound = {SOUND}\n", ""))
    with pytest.raises(CaseError, match="systems.tow.inflation.supersonic: a supersonic opening needs the speed of "
                                        "sound"):
        load_case(path)
