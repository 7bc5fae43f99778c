"""Model limits stated, settings that do nothing warned, and a stop after a warning that names it (issue 59, items 4
and 5): each simplified model checks its own validity in one line (the reduced canopy's drag time constant and drag,
the supersonic load-factor law, a flight-condition start's Mach number; normal gravity's q0 in
tests/unit/test_normal_gravity.py), a setting without effect is warned, and a run stopped after an implausibility
warning names the warned setting."""

import io
import json
from contextlib import redirect_stderr
from pathlib import Path

import pytest

from pchute_exudyn.case.loader import load_case
from pchute_exudyn.cli import main
from pchute_exudyn.run.simulation import resolve_run
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

ROCKET = str(ROOT / "cases" / "rocket" / "dual_deploy.toml")
MSL = str(ROOT / "cases" / "edl" / "msl.toml")
DROP = str(ROOT / "tests" / "cases" / "vacuum_drop.toml")
DESCENT = "time,vehicle_altitude\n0,100\n1,90\n2,80\n"


def _file(tmp: Path, name: str, text: str) -> str:
    path = tmp / name
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize("mass, drogue, main_time", [(40.0, "0.874", "0.276"), (60.0, "1.11", "0.35")])
def test_a_heavy_reduced_canopy_is_warned_with_its_drag_time_constant_and_the_limit(mass, drogue, main_time):
    case = load_case(ROCKET, [f"bodies.drogue_canopy.mass={mass}", f"bodies.main_canopy.mass={mass}"])
    for system, canopy, time in (("drogue", "drogue_canopy", drogue), ("main", "main_canopy", main_time)):
        assert (f"systems.{system}.canopy_model = 'reduced': canopy '{canopy}' has a drag time constant m / (rho C_D0 "
                f"S0 V) of {time} s, above the 0.1 s a reduced canopy is valid to (auto chooses it below 0.05 s)") in "\n".join(case.warnings)
    assert not [w for w in load_case(ROCKET).warnings if "reduced" in w]   # the shipped light canopies: no word


BAD = [
    ("reduced canopy without drag",
     lambda t: ["run", ROCKET, "--set", "bodies.main_canopy.aerodynamics.axial_coefficient=0"],
     "systems.main.canopy_model = 'reduced': reduced needs canopy 'main_canopy' to have drag (its axial_coefficient "
     "at Mach 0 is 0, must be > 0)"),
    ("case mach 1e200", lambda t: ["run", MSL, "--set", "bodies.vehicle.initial.mach=1e200"],
     "bodies.vehicle.initial.mach = 1e+200: must be <= 237.7: a faster start moves at more than 20000 m/s"),
    ("pchute new --mach 1e200", lambda t: ["new", str(t / "n.toml"), "--planet", "mars", "--mach", "1e200",
                                           "--dynamic-pressure", "500"],
     "mach = 1e+200: must be <= 237.7: a faster start moves at more than 20000 m/s"),
    ("compare --altitudes 1e6", lambda t: ["compare", _file(t, "a.csv", DESCENT), _file(t, "b.csv", DESCENT),
                                           "--altitudes", "95,1e6"],
     "altitudes (--altitudes) = 1e+06: "),
    # the second battery's
    ("a first step above the largest", lambda t: ["run", ROCKET, "--set", "simulation.step_control.first=1",
                                                  "--set", "simulation.step_control.largest=0.5"],
     "simulation.step_control.first = 1.0: must not exceed the largest step (0.5 s)"),
    # warned as implausible, then stopped by what the value caused: the stop names the warned setting
    ("spin_rate 0.05 stops below the ground", lambda t: ["run", ROCKET, "--set", "planet.spin_rate=0.05", "--quiet",
                                                         "--no-plot"],
     "(the case has implausible settings, warned before the run: planet.spin_rate = 0.05)"),
    ("rotation_rate 1 leaves the atmosphere", lambda t: ["run", ROCKET, "--set", "planet.rotation_rate=1", "--quiet",
                                                         "--no-plot"],
     "(the case has implausible settings, warned before the run: planet.rotation_rate = 1)"),
    ("first step 1e6 s", lambda t: ["run", ROCKET, "--set", "simulation.step_control={first=1e6,largest=1e6}",
                                    "--quiet", "--no-plot"],
     "(the case has implausible settings, warned before the run: simulation.step_control.first = 1000000.0, "
     "simulation.step_control.largest = 1000000.0)"),
]


@pytest.mark.parametrize("name, make_args, expected", BAD, ids=[b[0] for b in BAD])
def test_a_model_outside_its_limits_is_refused_in_one_line(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    lines = [line for line in err.splitlines() if "warning:" not in line]   # the implausibility warnings come first
    assert_one_line(code, "\n".join(lines), expected, touched, seconds)


def test_a_supersonic_law_below_1_at_line_stretch_is_warned():
    """MSL's main at Mach 1.685 (its last stage's start) with s_M = 16.75: C_k = 1.726 + 16.75 (1.685 - 1.8) = -0.2,
    held at 1."""
    case = load_case(MSL, {"systems.main.inflation.supersonic.mach_slope": 16.75})
    from pchute_exudyn.run.simulation import simulate

    summary = simulate(case, duration=1.2).summary
    start = summary.events_of("stage_start")[0]
    assert start.load_factor == 1.0
    law = 1.726 + 16.75 * (start.mach - 1.8)
    assert law == pytest.approx(-0.2, abs=0.01)
    assert (f"systems.main.inflation.supersonic: its load-factor law gives C_k = {law:.4g} at the line-stretch Mach "
            f"{start.mach:.3g}, below 1") in "\n".join(summary.warnings)


def test_step_control_with_a_fixed_step_is_warned(tmp_path):
    case = load_case(DROP, {"simulation.step_control": {"relative": 1e-4}})
    err = io.StringIO()
    with redirect_stderr(err):
        assert main(["run", DROP, "--set", "simulation.step_control={relative=1e-4}", "--dt", "0.01", "--t-end",
                     "0.1", "--quiet", "--no-plot", "--out", str(tmp_path / "run")]) == 0
    line = ("pchute run: warning: simulation.step_control: has no effect in this run: its step is fixed (0.01 s, "
            "from --dt, [simulation.steps] or the stability limit)")
    assert err.getvalue().count(line) == 1   # once, before the run
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert any(w.startswith(line[len("pchute run: warning: "):]) for w in summary["warnings"])
    assert resolve_run(case).warnings == ()                       # adaptive steps (RK4, no step): it acts
    assert resolve_run(load_case(DROP), step=0.01).warnings == ()   # no step_control table: nothing to say


def test_spin_rate_with_spherical_gravity_in_a_frame_that_does_not_turn_is_warned():
    case = load_case(DROP, {"planet.gravity_model": "spherical", "planet.spin_rate": 7.292115e-5})
    assert ("planet.spin_rate = 7.29211e-05: has no effect in this case: only normal gravity's centrifugal term reads "
            "the planet's spin") in "\n".join(case.warnings)
    assert not load_case(DROP, {"planet.spin_rate": 7.292115e-5}).warnings   # normal gravity reads it


def test_a_flattened_normal_gravity_planet_flies(tmp_path):
    """polar_radius = 1e6 m (e' = 6.3; the q0 series diverges there): gravity a number, the drop reaches the
    ground."""
    assert main(["run", DROP, "--set", "planet.polar_radius=1e6", "--set", "planet.spin_rate=7.292115e-5", "--dt",
                 "0.05", "--quiet", "--no-plot", "--out", str(tmp_path / "run")]) == 0
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["end"] == "touchdown"


@pytest.mark.parametrize("case_file, key, value", [
    (ROCKET, "simulation.step_control.largest", 5.0),   # the battery's: apogee sensed 5 s late, 4x the drogue's load
    (MSL, "systems.main.inflation.supersonic.forebody_diameter", 1e4),
    (MSL, "systems.main.inflation.supersonic.load_factor", 1e6),
    (MSL, "systems.main.inflation.supersonic.mach_slope", 1e6)])
def test_a_step_or_an_opening_law_out_of_its_plausible_range_is_warned(case_file, key, value):
    from pchute_exudyn.case.plausible import range_of

    low, high = range_of(key).plausible
    assert not low <= value <= high
    assert any(w.startswith(f"{key} = {value}") for w in load_case(case_file, {key: value}).warnings)
    assert not [w for w in load_case(case_file).warnings if key in w]   # the shipped case: no word


def test_a_reduced_canopy_under_a_method_that_flies_it_rigid_is_warned():
    case = load_case(ROCKET)   # both systems named reduced
    assert resolve_run(case, "sp").warnings == ()
    assert resolve_run(case, "full").warnings == tuple(
        f"systems.{name}.canopy_model = 'reduced': has no effect in this run: the full method flies every canopy "
        "rigid (a reduced canopy is SP's, --method sp)" for name in ("drogue", "main"))


def test_a_level_to_fall_below_that_the_start_is_already_below_is_warned():
    """The battery's main at 5000 m above a 2500 m start: it opened with the drogue at apogee, without a word."""
    case = load_case(ROCKET, ["main.deploy_trigger.below=5000"])
    assert ("systems.main.deploy_trigger is met from the start: the vehicle starts at 3900 m, already below 6400 m "
            "(5000 m above the ground), so it fires at its first sample") in "\n".join(case.warnings)
    assert not [w for w in load_case(ROCKET).warnings if "met from the start" in w]


def test_an_ellipsoid_flatter_than_any_planet_is_warned():
    """The battery's polar_radius = 1e5 m under Earth's equator (flattening 0.98): 522 m/s^2 of gravity, no word."""
    assert ("planet.polar_radius = 100000 is implausible: a flattening (a - b) / a of 0.984 against equatorial_radius "
            "= 6.37814e+06 m") in "\n".join(load_case(ROCKET, ["planet.polar_radius=1e5", "planet.spin_rate=7.292115e-5"]).warnings)
    saturn = load_case(ROCKET, ["planet.polar_radius=5753860.0", "planet.spin_rate=7.292115e-5"])   # Earth's a with Saturn's 0.098: a planet's
    assert not [w for w in saturn.warnings if "polar_radius" in w]


def test_an_output_step_below_every_step_is_warned():
    """The second battery's output_step = 1e-7 s: summary.json recorded it, the output held one row per step."""
    case = load_case(DROP, {"simulation.output_step": 1e-4})
    assert resolve_run(case, step=0.01).warnings == (
        "simulation.output_step = 0.0001 s: has no effect below the run's step (0.01 s): the output holds one row per "
        "step",)
    assert resolve_run(case, step=1e-4).warnings == ()   # a row per step is what it asks for


def test_a_ground_below_the_atmosphere_is_warned():
    """The second battery's ground at -6000 m under US76 (from -5 km): an internal error from the air there."""
    assert ("simulation.ground_altitude = -6000 is implausible: outside the atmosphere the descent flies through "
            "(-5000 to 86000 m, US76 atmosphere): the run stops where the air ends, before touchdown") in \
        "\n".join(load_case(ROCKET, ["simulation.ground_altitude=-6000"]).warnings)


def test_a_wind_direction_of_many_turns_is_warned():
    """The third battery's from_deg = 1e9 ran without a word."""
    case = load_case(str(ROOT / "cases" / "airdrop" / "static_line.toml"),
                     {"atmosphere.wind.speed": 5.0, "atmosphere.wind.from_deg": 7200.0})
    assert any(w.startswith("atmosphere.wind.from_deg = 7200.0 is implausible") for w in case.warnings)


def test_each_warning_is_printed_once_and_the_runs_own_is_not_lost(tmp_path):
    """The fourth battery's: with a warning of the plan and one of the run (a trigger unfired), the plan's was
    printed twice and the run's not at all."""
    err = io.StringIO()
    with redirect_stderr(err):
        assert main(["run", ROCKET, "--t-end", "3", "--dt", "0.01", "--set", "simulation.step_control.relative=1e-6",
                     "--quiet", "--no-plot", "--out", str(tmp_path / "run")]) == 0
    lines = [line for line in err.getvalue().splitlines() if line.startswith("pchute run: warning: ")]
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert sorted(lines) == sorted(f"pchute run: warning: {w}" for w in summary["warnings"])
    assert any("never fired" in line for line in lines) and len(lines) == len(set(lines)) == 2
