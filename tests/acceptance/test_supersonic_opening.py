"""The supersonic opening (docs/models/supersonic_opening.md) against its closed forms: a canopy towed at a constant
supersonic speed (validation/canopy_checks.py's tug and canopy made 1e13 kg, no gravity, constant air) sees exactly q S C_A f(t), with f the fill law
whose C_x is the model's load factor at the line-stretch Mach number, whose fill time is n(M) D_0 / V and whose
breathing follows once the overinflation has decayed; the first peak is q S C_A C_k."""

from __future__ import annotations

import json
import math
import sys

import numpy as np
import pytest

from pchute_exudyn import load_case, simulate
from pchute_exudyn.errors import CaseError
from pchute_exudyn.physics.inflation import Inflation, InflationStage, nominal_diameter
from pchute_exudyn.physics.supersonic_opening import MachTable, SupersonicOpening
from tests.helpers import ROOT

sys.path.insert(0, str(ROOT / "validation"))
import canopy_checks  # noqa: E402

DENSITY, SOUND, SPEED = 0.02, 300.0, 540.0        # kg/m^3 (tests/cases/constant_air.csv), m/s, m/s: Mach 1.8
AREA, AXIAL = 178.47, 0.46                        # m^2, -
FILL_TIME = 0.25                                  # s: the fill constant is chosen to give it
OPENING = dict(load_factor=1.5, reference_mach=1.7, mach_slope=0.4, wake_coefficient=0.5, forebody_diameter=1.5)
BREATHING = (0.08, 0.2)                           # relative amplitude (-), Strouhal number (-)

def _towed(tmp_path, breathing: bool, sound: float | None = SOUND):
    """validation/canopy_checks.py's towed canopy at Mach 1.8 in constant air, made infinitely massive (1e13 kg), its
    stiff lines, one stage and the supersonic opening (with its breathing when ``breathing``): (case, model, D_0)."""
    diameter = nominal_diameter(AREA)
    fill = FILL_TIME * SPEED / diameter
    amplitude, strouhal = BREATHING
    path = tmp_path / "towed.toml"
    path.write_text(canopy_checks.TOWED.format(air=(ROOT / "tests" / "cases" / "constant_air.csv").as_posix(),
                                               speed=SPEED, area=AREA, axial_coefficient=AXIAL))
    opening = {**OPENING, "fill_constant": {"mach": [1.0, 2.5], "value": [fill, fill]}}
    if breathing:
        opening.update(breathing_amplitude={"mach": [1.0, 2.5], "value": [amplitude, amplitude]},
                       breathing_strouhal=strouhal)
    overrides = {**{f"bodies.{b}.{key}": value for b in ("tug", "canopy") for key, value in
                    (("mass", 1e13), ("inertia", [1e13] * 3))},
                 **{f"systems.tow.lines.{line}.stiffness": 1e6 for line in ("bridle", "riser")},
                 "systems.tow.inflation": {"stage_start": [0.0], "fraction": [1.0], "fill_constant": [99.0],
                                           "exponent": [2.0], "overinflation_decay": 0.25, "supersonic": opening},
                 "simulation.duration": 1.5, "simulation.output_step": 0.0025,
                 "simulation.steps": {"full": 1e-4, "full_implicit": 1e-3, "sp": 1e-3, "equilibrium": 1e-3}}
    if sound is not None:
        overrides["atmosphere.speed_of_sound"] = sound
    model = SupersonicOpening(**OPENING, fill_constant=MachTable((1.0, 2.5), (fill, fill)),
                              breathing_amplitude=MachTable((1.0, 2.5), (amplitude,) * 2) if breathing else None,
                              breathing_strouhal=strouhal)
    return load_case(path, overrides), model, diameter


@pytest.mark.parametrize("method", ["full", "sp"])
def test_an_infinite_mass_supersonic_opening_follows_its_law_and_peaks_at_q_s_cd_ck(tmp_path, method):
    case, model, diameter = _towed(tmp_path, breathing=False)
    columns = simulate(case, method, "rk4").columns
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
    case, model, diameter = _towed(tmp_path, breathing=True)
    columns = simulate(case, "sp", "rk4").columns
    time = columns["time"]
    amplitude, strouhal = BREATHING
    start = FILL_TIME + 0.25
    after = time > start
    expected = 1.0 + amplitude * np.sin(2.0 * math.pi * strouhal * SPEED / diameter * (time[after] - start))
    np.testing.assert_allclose(columns["tow_drag_area_fraction"][after], expected, rtol=0, atol=1e-9)
    assert abs(columns["tow_drag_area_fraction"].max() - model.load_factor_at(SPEED / SOUND, diameter)) < 1e-9


def test_a_supersonic_opening_in_air_without_a_speed_of_sound_is_refused_in_one_line(tmp_path):
    with pytest.raises(CaseError, match="systems.tow.inflation.supersonic: a supersonic opening needs the speed of "
                                        "sound"):
        _towed(tmp_path, breathing=False, sound=None)


FIXED_PEAK_AFTER_OPENING = 81499.2   # N: the largest riser tension after 3 s of cases/edl/msl.toml at SP 1 ms
"""(``pchute run cases/edl/msl.toml --set simulation.duration=20``); its first peak is the nominal run of
validation/output/flown_loads/predictions.json."""


def test_adaptive_steps_fly_a_supersonic_opening_and_its_supersonic_descent_as_the_fixed_step_does():
    """A 60 kg canopy behind 3.1 t: the indicator alone let its line mode swing to twice the opening load; the
    opening cap (200 steps over the fill and decay, and while the canopy is supersonic) keeps both within a few %."""
    case = load_case(ROOT / "cases" / "edl" / "msl.toml", {"simulation.steps": {}})
    columns = simulate(case, duration=20.0).columns
    time, tension = columns["time"], columns["tension_riser"]
    recorded = json.loads((ROOT / "validation" / "output" / "flown_loads" / "predictions.json").read_text())
    assert abs(np.nanmax(tension) / recorded["msl"]["nominal"]["peak"] - 1.0) < 0.03
    assert abs(np.nanmax(tension[time > 3.0]) / FIXED_PEAK_AFTER_OPENING - 1.0) < 0.05


def test_a_line_stretch_outside_the_fitted_mach_range_is_flown_at_its_end_and_warned():
    case = load_case(ROOT / "cases" / "edl" / "msl.toml", {"bodies.vehicle.initial.mach": 1.3,
                                                          "bodies.vehicle.initial.dynamic_pressure": 300.0})
    summary = simulate(case, duration=1.2).summary
    start = summary.events_of("stage_start")[0]
    opening = case.systems["main"].inflation.supersonic
    assert start.mach < opening.mach_range[0]
    assert start.load_factor == pytest.approx(opening.load_factor + opening.mach_slope * (1.5 - 1.8), rel=1e-12)
    assert any("outside the supersonic opening's mach_range [1.5, 2.1]" in line for line in summary.warnings)
