"""Absurd and silently accepted values in case, study and fit files (issue 34, "absurd values"): each is one line
naming the key, the value and what is allowed, a non-zero exit, no traceback and nothing touched outside the output.
Also: every shipped case loads without a warning, the plausibility table of docs/case-format.md is the code's, and a
warning reaches the run line and summary.json.
"""

import json
from pathlib import Path

import pytest

from pchute_exudyn.case.plausible import RANGES, check_value, markdown_table
from pchute_exudyn.errors import CaseError, PchuteError
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

CASE1 = str(ROOT / "cases" / "mer" / "case1.toml")
PA1 = str(ROOT / "cases" / "cev_pa1.toml")
PA1_WINDS = str(ROOT / "cases" / "cev_pa1_winds.toml")
PA1_INFLATION = str(ROOT / "cases" / "cev_pa1_inflation.toml")
RISER_TABLE = "main.lines.riser.load_elongation."
MSL_EDL = str(ROOT / "cases" / "edl" / "msl.toml")
SUPERSONIC = "main.inflation.supersonic"
HANGING = str(ROOT / "tests" / "cases" / "hanging_kevlar.toml")
LOWER = "hang.lines.lower."
TURBULENCE = "atmosphere.turbulence."
SHORT = ["--method", "sp", "--t-end", "0.2"]


def _file(tmp: Path, name: str, text: str) -> str:
    path = tmp / name
    path.write_text(text)
    return str(path)


def _gusty(tmp: Path) -> str:
    return _file(tmp, "gust.toml", f'extends = "{Path(PA1_WINDS).as_posix()}"\n[[atmosphere.gusts]]\namplitude = 5.0\n'
                                   'start = 0.1\nlength = 4.0\ndirection = [0.0, 1.0, 0.0]\n')


def _nested(tmp: Path) -> str:
    return _file(tmp, "nested.toml", f'extends = "{Path(CASE1).as_posix()}"\nx = {"[" * 5000}{"]" * 5000}\n')


def _turbulent(length_u: float) -> list:
    """PA1 (40 m/s at the start) in turbulence given by intensities and scale lengths."""
    keys = {"seed": 1, "sigma_u": 1, "sigma_v": 1, "sigma_w": 1, "length_u": length_u, "length_v": 100,
            "length_w": 100}
    return [a for key, value in keys.items() for a in ("--set", f"{TURBULENCE}{key}={value}")]


def _study(tmp: Path, runs: int = 1, parameters: str = "") -> list:
    path = _file(tmp, "study.toml", f'[study]\ncase = "{Path(CASE1).as_posix()}"\nruns = {runs}\nseed = 1\n'
                                    f'duration = 0.2\n[[study.configurations]]\nmethod = "sp"\nsteps = [1e-2]\n'
                                    f'{parameters}')
    return ["study", path, "--out", str(tmp / "study_out"), "--workers", "1", "--no-progress"]


DRAWN = '[parameters."vehicle.initial.velocity_down"]\ndistribution = "normal"\nmean = 0.0\nstd = 1.0\n'


def _fit(tmp: Path, target: str, extra: str = "", free: str = "") -> list:
    (tmp / "data.csv").write_text("time,tension_riser\n0,0\n0.5,10\n")
    (tmp / "nan.csv").write_text("time,tension_riser\n0,0\nnan,5\n0.5,10\n")
    (tmp / "back.csv").write_text("time,tension_riser\n0,0\n0.5,5\n0.2,10\n")
    case = _file(tmp, "short.toml", f'extends = "{Path(CASE1).as_posix()}"\n[simulation]\nduration = 0.5\n')
    path = _file(tmp, "fit.toml", f'[fit]\ncase = "{Path(case).as_posix()}"\nmethod = "sp"\nstep = 1e-2\n{extra}\n'
                                  f'[free."parachute.aerodynamics.axial_coefficient"]\nlow = 0.3\nhigh = 0.7\n'
                                  f'{free}[[targets]]\n{target}\n')
    return ["fit", path, "--out", str(tmp / "fit_out"), "--workers", "1"]


def _conditions(tmp: Path, keys: str = "dynamic_pressure = 846.0\n") -> str:
    """cases/mer/edl.toml with its vehicle's start given as flight conditions (Mach 2.07 at -25 deg, east, and
    ``keys``) instead of its altitude and velocity."""
    edl = (ROOT / "cases" / "mer" / "edl.toml").as_posix()
    return _file(tmp, "conditions.toml", f'extends = "{edl}"\nremove = ["bodies.vehicle.initial.altitude", '
                                         '"bodies.vehicle.initial.velocity_down", '
                                         '"bodies.vehicle.initial.velocity_east"]\n[bodies.vehicle.initial]\n'
                                         f'mach = 2.07\nflight_path_deg = -25.0\nheading_deg = 90.0\n{keys}')


def _unrated(tmp: Path) -> str:
    """tests/cases/hanging_kevlar.toml with its lower line's material but without its breaking strength."""
    return _file(tmp, "unrated.toml", f'extends = "{Path(HANGING).as_posix()}"\n'
                                      'remove = ["systems.hang.lines.lower.breaking_strength"]\n')


HISTORY = 'history = "data.csv"\ncolumn = "tension_riser"\nstd = 1.0'

BATTERY = [
    # impossible values of single keys (case.plausible.RANGES)
    ("line table of 1e307 N", lambda t: ["run", PA1_INFLATION, "--set", RISER_TABLE + "strain=[0.0, 0.1]", "--set",
                                          RISER_TABLE + "tension=[0.0, 1e307]"],
     "systems.main.lines.riser.load_elongation.tension = [0.0, 1e+307]: each must be within 0..1e+12 (N)"),
    ("initial speed of 3e7 m/s", lambda t: ["run", CASE1, "--set", "vehicle.initial.velocity_down=3e7"],
     "bodies.vehicle.initial.velocity_down = 30000000.0: must be within -20000..20000 (m/s) for this tool"),
    ("start faster than the escape speed", lambda t: ["run", CASE1, "--set", "vehicle.initial.velocity_east=6000"],
     "bodies.vehicle.initial.velocity_east = 6000.0: gives a start speed of 6000 m/s, faster than the escape speed "
     "there (5017.56 m/s)"),
    ("mass of 1e20 kg", lambda t: ["run", CASE1, "--set", "vehicle.mass=1e20"],
     "bodies.vehicle.mass = 1e+20: must be within 1e-06..1e+15 (kg)"),
    ("confluence mass of 1e-12 kg", lambda t: ["run", CASE1, "--set", "main.confluence.mass=1e-12"],
     "systems.main.confluence.mass = 1e-12: must be within 1e-09..1e+09 (kg)"),
    ("inertia of 1e20", lambda t: ["run", CASE1, "--set", "vehicle.inertia=[1e20, 1e20, 1e20]"],
     "bodies.vehicle.inertia = [1e+20, 1e+20, 1e+20]: each must be within -1e+18..1e+18 (kg m^2)"),
    ("line stiffness of 1e300", lambda t: ["run", CASE1, "--set", "systems.*.lines.*.stiffness=1e300"],
     "must be within 0..1e+15 (N/m)"),
    ("wind of 5 km/s", lambda t: ["run", PA1_WINDS, "--set", "atmosphere.wind.speed=5000"],
     "atmosphere.wind.speed = 5000: must be within -1000..1000 (m/s)"),
    ("turbulence scale length of 1 mm", lambda t: ["run", PA1, *_turbulent(0.001)],
     "atmosphere.turbulence.length_u = 0.001: must be within 0.1..1e+06 (m)"),
    ("gust of 1e5 m/s", lambda t: ["run", _gusty(t), "--set", "atmosphere.gusts[0].amplitude=1e5"],
     "atmosphere.gusts[0].amplitude = 100000.0: must be within -1000..1000 (m/s)"),
    ("release airspeed of 3e4 m/s", lambda t: ["run", str(ROOT / "validation" / "output" / "release" /
                                                          "cargo_release.toml"), "--set", "start.release.airspeed=3e4"],
     "start.release.airspeed = 30000.0: must be within 0..20000 (m/s)"),
    ("gravity of 1e4", lambda t: ["run", str(ROOT / "cases" / "simple" / "simple.toml"), "--set",
                                  "planet.gravity=1e4"], "planet.gravity = 10000.0: must be within 0..1000 (m/s^2)"),
    ("duration of 1e9 s", lambda t: ["run", CASE1, "--set", "simulation.duration=1e9"],
     "simulation.duration = 1000000000.0: must be within 1e-09..1e+08 (s)"),
    # time scales against the step
    ("turbulence scale crossed within a step", lambda t: ["run", PA1, *_turbulent(0.2), *SHORT],
     "atmosphere.turbulence.length_u = 0.2: must be >= 0.4 m: the vehicle at 40 m/s crosses it in less than the "
     "integration step (0.01 s)"),
    ("gust shorter than the step", lambda t: ["run", _gusty(t), "--set", "atmosphere.gusts[0].length=0.001", *SHORT],
     "atmosphere.gusts[0].length = 0.001: must be >= the integration step (0.01 s)"),
    ("gust direction overflowing", lambda t: ["run", _gusty(t), "--set", "atmosphere.gusts[0].direction=[1e308, 1e308, 0]"],
     "atmosphere.gusts[0].direction = [1e+308, 1e+308, 0]: its length overflows"),
    # line materials (docs/models/line_materials.md)
    ("unknown line material", lambda t: ["run", HANGING, "--set", LOWER + 'material="kevlr"'],
     "systems.hang.lines.lower.material = 'kevlr': unknown line material; the materials are: kevlar, technora, "
     "nylon"),
    ("material without breaking strength", lambda t: ["run", _unrated(t)],
     "systems.hang.lines.lower.breaking_strength: required (N) with material = 'kevlar': the line's rated breaking "
     "strength, all its legs or plies together"),
    ("zero breaking strength", lambda t: ["run", HANGING, "--set", LOWER + "breaking_strength=0"],
     "systems.hang.lines.lower.breaking_strength = 0: must be > 0 (N)"),
    ("negative breaking strength", lambda t: ["run", HANGING, "--set", LOWER + "breaking_strength=-2500.0"],
     "systems.hang.lines.lower.breaking_strength = -2500.0: must be > 0 (N)"),
    ("breaking strength of 1e13 N", lambda t: ["run", HANGING, "--set", LOWER + "breaking_strength=1e13"],
     "systems.hang.lines.lower.breaking_strength = 10000000000000.0: must be within 0..1e+12 (N) for this tool"),
    ("material and stiffness", lambda t: ["run", HANGING, "--set", LOWER + "stiffness=1e5"],
     "systems.hang.lines.lower.stiffness = 100000.0: give one of material (with breaking_strength), stiffness or "
     "load_elongation, not stiffness with material = 'kevlar'"),
    ("material and line table", lambda t: ["run", str(ROOT / "tests" / "cases" / "hanging_table.toml"), "--set",
                                           LOWER + 'material="nylon"', "--set", LOWER + "breaking_strength=5e3"],
     ": give one of material (with breaking_strength), stiffness or load_elongation, not load_elongation with "
     "material = 'nylon'"),
    ("breaking strength without material", lambda t: ["run", CASE1, "--set", "main.lines.riser.breaking_strength=1e4"],
     "systems.main.lines.riser.breaking_strength = 10000.0: needs material (one of: kevlar, technora, nylon): the "
     "strength scales that material's load-elongation curve"),
    # silently accepted before
    # a start given as flight conditions (bodies.<vehicle>.initial: mach, dynamic_pressure, ...)
    ("dynamic pressure no altitude gives at that Mach", lambda t: ["run", _conditions(t, "dynamic_pressure = 1e7\n")],
     "bodies.vehicle.initial.dynamic_pressure = 10000000.0: with initial.mach = 2.07: no altitude of the mars_grc "
     "atmosphere (-10000 to 100000 m) gives 1e+07 Pa at Mach 2.07"),
    ("both altitude and mach", lambda t: ["run", _conditions(t), "--set", "vehicle.initial.altitude=9500"],
     "bodies.vehicle.initial.altitude = 9500: give either altitude and the velocity_* keys or the flight conditions "
     "(mach, dynamic_pressure, flight_path_deg, heading_deg), not both"),
    ("mach without dynamic_pressure", lambda t: ["run", _conditions(t, "")],
     "bodies.vehicle.initial.dynamic_pressure: required with mach, flight_path_deg, heading_deg"),
    ("mach in an atmosphere without a speed of sound", lambda t: [
        "run", _conditions(t), "--set", 'atmosphere.model="table"', "--set",
        f'atmosphere.file="{(ROOT / "tests" / "cases" / "constant_air.csv").as_posix()}"'],
     "the table atmosphere has no speed of sound, so a Mach number cannot be turned into a speed"),
    ("extends overridden", lambda t: ["run", CASE1, "--set", "extends=other.toml"],
     "--set extends=other.toml: extends: cannot be overridden"),
    ("remove overridden", lambda t: ["run", CASE1, "--set", "remove=[\"planet\"]"], "remove: cannot be overridden"),
    ("TOML nested 5000 deep", lambda t: ["run", _nested(t)], "malformed TOML: arrays or tables nested too deeply"),
    ("override nested 5000 deep", lambda t: ["run", CASE1, "--set", "vehicle.mass=" + "[" * 5000 + "]" * 5000],
     "vehicle.mass: the value's arrays or tables are nested too deeply"),
    ("vehicle is a canopy", lambda t: ["run", PA1, "--set", "case.vehicle=main_canopy"],
     "case.vehicle = 'main_canopy': is a canopy of system 'main'"),
    ("deploy point on the own canopy", lambda t: ["run", PA1, "--set", "main.deploy_point=\"main_canopy.riser\""],
     "systems.main.deploy_point = 'main_canopy.riser': is on the system's own canopy 'main_canopy'"),
    ("power-law ground above the flight", lambda t: ["run", PA1_WINDS, "--set", "atmosphere.wind.ground_altitude=5000"],
     "atmosphere.wind.ground_altitude = 5000.0: must be below the vehicle's start altitude (2300 m)"),
    ("turbulence ground above the flight", lambda t: ["run", PA1_WINDS, "--set",
                                                       TURBULENCE + "ground_altitude=3000"],
     "atmosphere.turbulence.ground_altitude = 3000.0: must be below the vehicle's start altitude (2300 m)"),
    ("reefing stages that shrink", lambda t: ["run", PA1_INFLATION, "--set",
                                              "main.inflation.fraction=[0.5, 0.25, 1.0]"],
     "systems.main.inflation.fraction = [0.5, 0.25, 1.0]: must not decrease from stage to stage"),
    ("canopy placed below the ground", lambda t: ["run", PA1, "--set", "capsule.initial.altitude=1203", "--set",
                                                  "capsule.initial.velocity_down=-40", "--set",
                                                  "capsule.initial.velocity_east=0", "--set",
                                                  "drogue.deploy_time=0.05", *SHORT, "--out", str(t / "o")],
     "systems.drogue.deploy_time = 0.05 s places canopy 'drogue_canopy' at line stretch at 1181.99 m, below the "
     "ground (simulation.ground_altitude = 1200 m)"),
    # supersonic openings (cases/edl)
    ("supersonic load factor below 1", lambda t: ["run", MSL_EDL, "--set", f"{SUPERSONIC}.load_factor=0.8"],
     "systems.main.inflation.supersonic.load_factor = 0.8: must be >= 1 (the peak drag area over the filled one)"),
    ("supersonic Mach range reversed", lambda t: ["run", MSL_EDL, "--set", f"{SUPERSONIC}.mach_range=[2.1, 1.5]"],
     "systems.main.inflation.supersonic.mach_range = [2.1, 1.5]: must be [low, high] with 0 < low < high"),
    ("breathing amplitude of 1", lambda t: ["run", MSL_EDL, "--set",
                                            f"{SUPERSONIC}.breathing_amplitude={{mach=[1.2, 1.5], value=[0.0, 1.0]}}"],
     "systems.main.inflation.supersonic.breathing_amplitude = [0.0, 1.0]: each must be in [0, 1)"),
    ("supersonic wake factor below zero", lambda t: ["run", MSL_EDL, "--set", f"{SUPERSONIC}.wake_coefficient=6.0"],
     "systems.main.inflation.supersonic.wake_coefficient = 6.0: gives k_w d / D_0 = 1.26 for canopy 'parachute': it "
     "must stay below 1"),
    ("supersonic Mach table below zero", lambda t: ["run", MSL_EDL, "--set",
                                                    f"{SUPERSONIC}.fill_constant={{mach=[-1.0, 1.8], value=[8.0, 11.5]}}"],
     "systems.main.inflation.supersonic.fill_constant.mach = [-1.0, 1.8]: must be Mach numbers >= 0, increasing "
     "strictly"),
    ("supersonic opening with an overinflation", lambda t: ["run", MSL_EDL, "--set",
                                                            "main.inflation.overinflation=1.2"],
     "systems.main.inflation.overinflation = 1.2: must be left out (or 1) with a supersonic opening"),
    # studies: limits
    ("study of 2e6 runs", lambda t: _study(t, 2_000_000, DRAWN),
     "study.runs = 2000000: must be <= 1000000"),
    ("study linspace of 1e9 values", lambda t: _study(t, 1, '[parameters."vehicle.mass"]\n'
                                                            'linspace = {start = 500, stop = 900, num = 1000000000}\n'),
     "linspace.num = 1000000000: must be <= 1000000"),
    ("study grid value NaN", lambda t: _study(t, 1, '[parameters."vehicle.mass"]\nvalues = [800.0, nan]\n'),
     "values = [800.0, nan]: must be finite numbers"),
    ("study range of 4e8 values", lambda t: _study(t, 1, '[parameters."vehicle.mass"]\n'
                                                         'range = {start = 500, stop = 900, step = 1e-6}\n'),
     "range.step = 1e-06: gives 4e+08 values; a study runs at most 1000000"),
    ("study grid times samples too large", lambda t: _study(t, 600_000, DRAWN + '[parameters."vehicle.mass"]\n'
                                                                               'values = [700, 800]\n'),
     "the study expands into 1.2e+06 runs"),
    ("study seed distribution on a velocity key", lambda t: _study(t, 2, '[parameters."vehicle.initial.velocity_down"]'
                                                                         '\ndistribution = "seed"\n'),
     "parameters.\"vehicle.initial.velocity_down\".distribution = 'seed': 'seed' draws integers from 0 to 2^31 - 1, "
     "for a seed key (atmosphere.turbulence.seed); this key is in m/s"),
    ("study draw impossible for every run", lambda t: _study(t, 1, '[parameters."vehicle.initial.velocity_down"]\n'
                                                                   'distribution = "uniform"\nlow = 3e7\n'
                                                                   'high = 4e7\n'),
     "must be within -20000..20000 (m/s) for this tool"),
    # fits: targets and budget
    ("fit target std of 1e300", lambda t: _fit(t, 'event = "start"\ntime = 0.0\nstd = 1e300'),
     "targets[0].std = 1e+300: the std must be within 1e-09..1e+06"),
    ("fit target std of 1e-300", lambda t: _fit(t, HISTORY.replace("1.0", "1e-300")),
     "targets[0].std = 1e-300: the std must be within 1e-08..1e+07"),
    ("fit target weight of 1e-300", lambda t: _fit(t, 'final = "vehicle_altitude"\nvalue = 8000.0\nweight = 1e-300'),
     "targets[0].weight = 1e-300: the std must be within 8e-06..8e+09"),
    ("fit history with a NaN time", lambda t: _fit(t, HISTORY.replace("data.csv", "nan.csv")),
     "nan.csv: time is not a finite number at sample 2 (nan)"),
    ("fit history with time going back", lambda t: _fit(t, HISTORY.replace("data.csv", "back.csv")),
     "back.csv: time goes back at sample 3 (0.2 s after 0.5 s); times must increase strictly"),
    ("fit budget below one Jacobian", lambda t: _fit(t, HISTORY, "max_runs = 2"),
     "fit.max_runs = 2: must be >= 3"),
    ("fit budget not an integer", lambda t: _fit(t, HISTORY, "max_runs = 1e9"),
     "fit.max_runs = 1000000000.0: must be an integer from 1 to 1000000"),
    ("fit whose trial run fails", lambda t: _fit(t, HISTORY, free='[free."vehicle.mass"]\nlow = 1e-5\nhigh = 2e-5\n'
                                                                  'initial = 1.5e-5\n'),
     "the run at the starting values failed: the fixed RK4 step 0.01 s is too long for body vehicle on its lines"),
]


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_absurd_value_gives_one_line_and_a_nonzero_exit(tmp_path, name, make_args, expected):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)


def test_the_battery_is_large_and_distinct():
    assert len(BATTERY) >= 25 and len({entry[0] for entry in BATTERY}) == len(BATTERY)


SHIPPED = sorted([*ROOT.glob("cases/**/*.toml"), *ROOT.glob("tests/cases/*.toml"), *ROOT.glob("tests/data/*.toml"),
                  *(p for p in ROOT.glob("validation/output/**/*.toml") if p.name not in ("study.toml", "fit.toml"))])


def test_every_shipped_case_loads_without_a_warning():
    import pchute_exudyn as pc

    assert len(SHIPPED) >= 25
    warned = {str(path.relative_to(ROOT)): pc.load_case(path).warnings for path in SHIPPED}
    assert not {path: warnings for path, warnings in warned.items() if warnings}


def test_the_docs_plausibility_table_is_the_codes():
    text = (ROOT / "docs" / "case-format.md").read_text()
    documented = text.split("<!-- plausible:begin -->\n", 1)[1].split("\n<!-- plausible:end -->", 1)[0]
    assert documented == markdown_table()
    assert all(entry.plausible[0] >= entry.impossible[0] and entry.plausible[1] <= entry.impossible[1]
               for entry in RANGES)


def test_an_implausible_value_warns_in_the_run_line_and_the_summary(tmp_path, capsys):
    from pchute_exudyn.cli import main

    out = tmp_path / "heavy"
    code = main(["run", CASE1, "--set", "vehicle.mass=1e13", *SHORT, "--no-plot", "--out", str(out)])
    captured = capsys.readouterr()
    warning = "bodies.vehicle.mass = 10000000000000.0 is implausible: outside 0.01..1e+12 (kg)"
    assert code == 0 and captured.err.strip() == f"pchute run: warning: {warning}"
    assert captured.out.strip().endswith("(1 warning(s): see summary.json)")
    assert json.loads((out / "summary.json").read_text())["warnings"] == [warning]


def test_the_api_refuses_an_impossible_value_with_one_line():
    import pchute_exudyn as pc

    with pytest.raises(PchuteError) as info:
        pc.load_case(CASE1, {"vehicle.initial.velocity_east": -3e7})
    assert isinstance(info.value, CaseError) and len(str(info.value).splitlines()) == 1
    assert "bodies.vehicle.initial.velocity_east = -30000000.0: must be within -20000..20000 (m/s)" in str(info.value)
    assert pc.load_case(CASE1).warnings == ()


def test_a_study_run_drawing_an_impossible_speed_fails_alone(tmp_path):
    code, err, _, touched = run_bad_input(lambda t: _study(t, 3, DRAWN.replace("std = 1.0", "std = 3e7")), tmp_path)
    rows = (tmp_path / "study_out" / "runs.csv").read_text().splitlines()
    assert code == 1 and not touched and len(rows) == 4, err
    assert all(",failed," in row and "must be within -20000..20000 (m/s) for this tool" in row for row in rows[1:])


def test_check_value_names_what_is_allowed():
    assert check_value("bodies.x.mass", 800.0) == (None, None)
    assert check_value("systems.main.lines.riser.stiffness", 1e11)[1].endswith("outside 0..1e+10 (N/m)")
    assert check_value("atmosphere.gusts[3].amplitude", 2e3)[0] == "must be within -1000..1000 (m/s) for this tool"
    assert check_value("no.such.key", 1e300) == (None, None)
