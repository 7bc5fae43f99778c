"""`pchute new --dual-deploy` (issue 48): the one command writes a dual deploy that loads and runs to touchdown from
apogee, its drogue one lag after the first apogee sample, its main at its height above the ground; `--from-rocketpy`
starts at a RocketPy export's apogee; `pchute compare` reads RocketPy's export with no column map; each bad input
gives one line."""

import json
import math

import pytest

from pchute_exudyn.case.files import tomllib
from pchute_exudyn.case.loader import build_case
from pchute_exudyn.cli import main
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

EXPORTS = ROOT / "validation" / "rocketpy"
FORM = ["--dual-deploy", "--planet", "earth", "--canopy-type", "flat_circular", "--mass", "21.31", "--diameter",
        "0.15", "--length", "2.5", "--drogue-drag-area", "1", "--main-drag-area", "10", "--main-height", "300",
        "--drogue-mass", "0.17", "--main-mass", "1.06"]
ROCKETPY_MATCHED = ["--body-drag", "off", "--drogue-after-main", "cut"]
"""RocketPy's descent (issue 56): no body drag, one C_D S at a time; the case these tests were written on."""
ROCKET = FORM + ROCKETPY_MATCHED
START = ["--latitude", "32.99", "--longitude", "-106.97", "--ground-elevation", "1400", "--height", "2500",
         "--velocity-east", "15"]


def _write(tmp_path, *extra) -> tuple:
    path = tmp_path / "rocket.toml"
    assert main(["new", str(path), *ROCKET, *extra]) == 0
    return path, tomllib.loads(path.read_text())


def test_the_dual_deploy_loads_as_written(tmp_path):
    path, _ = _write(tmp_path, *START)
    build_case(tomllib.loads(path.read_text()), {}, str(path))


def test_the_dual_deploy_says_what_a_dual_deploy_needs(tmp_path):
    _, data = _write(tmp_path, *START)
    assert data["bodies"]["rocket"]["mass_includes_packed"] is True
    assert data["start"]["velocities_relative_to"] == "ground" and data["start"]["latitude_deg"] == 32.99
    drogue, main_ = data["systems"]["drogue"], data["systems"]["main"]
    assert drogue["packed"] and main_["packed"]
    assert drogue["deploy_trigger"] == {"quantity": "apogee", "rate": 100.0, "lag": 1.0}
    assert main_["deploy_trigger"] == {"quantity": "altitude", "below": 300.0, "reference": "ground", "rate": 100.0}
    assert drogue["cutaway_trigger"] == {"after": "main.deploy"}
    rocket = data["bodies"]["rocket"]
    assert rocket["initial"]["altitude"] == 3900.0 and rocket["initial"]["velocity_east"] == 15.0
    assert (rocket["initial"]["yaw_deg"], rocket["initial"]["pitch_deg"]) == (90.0, 0.0)   # nose east, level
    assert data["simulation"]["ground_altitude"] == 1400.0


def test_the_dual_deploy_runs_from_apogee_to_touchdown(tmp_path, capsys):
    case, _ = _write(tmp_path, *START)
    assert main(["run", str(case), "--no-plot", "--quiet", "--out", str(tmp_path / "out")]) == 0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    events = {(e["event"], e.get("system")): e for e in summary["events"]}
    # started at apogee (vertical speed 0): the first sample at 0.01 s sees it, the drogue 1 s later
    assert events["deploy", "drogue"]["time"] == pytest.approx(0.01 + 1.0, abs=1e-9)
    main_deploy = events["deploy", "main"]
    assert main_deploy["trigger"]["measured"] == pytest.approx(300.0, abs=1.0)
    assert events["cutaway", "drogue"]["time"] == main_deploy["time"]
    touchdown = events["touchdown", None]
    assert 120.0 < touchdown["time"] < 180.0 and 5.0 < touchdown["vertical_speed"] < 8.0
    # still air, no rotation, normal gravity: nothing pushes it north (spherical gravity drifted it 7.7 m there)
    assert abs(summary["final"]["vehicle_north"]) < 0.01


def test_the_start_comes_from_a_rocketpy_export(tmp_path, capsys):
    _, data = _write(tmp_path, "--from-rocketpy", str(EXPORTS / "dual_deploy_flight.csv"))
    assert "its apogee, 3456.49 m" in capsys.readouterr().out
    initial = data["bodies"]["rocket"]["initial"]
    assert initial["altitude"] == pytest.approx(3456.491, abs=0.01) and initial["velocity_down"] == 0.0
    assert initial["velocity_east"] == pytest.approx(12.89, abs=0.01)
    assert data["simulation"]["ground_altitude"] == pytest.approx(1400.0)
    assert data["start"]["latitude_deg"] == pytest.approx(32.99, abs=1e-4)


def test_compare_reads_a_rocketpy_export_without_a_column_map(tmp_path, capsys):
    case = tmp_path / "payload.toml"
    assert main(["new", str(case), "--planet", "earth", "--mass", "100", "--drag-area", "40", "--altitude",
                 "3000"]) == 0
    assert main(["run", str(case), "--no-plot", "--quiet", "--out", str(tmp_path / "run")]) == 0
    capsys.readouterr()
    assert main(["compare", str(tmp_path / "run"), str(EXPORTS / "descent.csv"), "--altitudes", "2500,1500,500",
                 "--out", str(tmp_path / "cmp")]) == 0
    comparison = json.loads((tmp_path / "cmp" / "comparison.json").read_text())
    assert set(comparison["columns"]) == {"vehicle_altitude", "vehicle_velocity_down"}
    assert comparison["descent"]["b"]["ground_time"] == pytest.approx(418.898, abs=0.01)


def _export(tmp, name: str, text: str) -> str:
    path = tmp / name
    path.write_text(text)
    return str(path)


CLIMBING = "# Time (s),Z (m),Vz (m/s)\n0.0,100.0,50.0\n1.0,150.0,40.0\n"
NO_VZ = "# Time (s),Z (m),Vx (m/s)\n0.0,100.0,5.0\n1.0,110.0,5.0\n"
NAN_ROW = "# Time (s),Z (m),Vz (m/s)\n0.0,100.0,5.0\n1.0,nan,-5.0\n"

BATTERY = [
    ("a NaN start velocity", lambda t: ["new", t / "r.toml", *ROCKET, "--height", "2500", "--velocity-east", "nan"],
     "velocity_east = nan: must be a number from -3000 to 3000 (m/s, over the ground)"),
    ("the main above the start", lambda t: ["new", t / "r.toml", *ROCKET, "--height", "250"],
     "main_height = 300.0: must be below the start's height above the ground, 250 m"),
    ("no main height", lambda t: ["new", t / "r.toml", "--dual-deploy", "--planet", "earth", "--length", "2",
                                  "--drogue-drag-area", "1", "--main-drag-area", "10"],
     "main_height: required with dual_deploy (m)"),
    ("a rocket option without --dual-deploy", lambda t: ["new", t / "r.toml", "--velocity-east", "3"],
     "velocity_east = 3.0: only with dual_deploy"),
    ("a dual deploy on Mars", lambda t: ["new", t / "r.toml", *ROCKET[:1], *ROCKET[3:]], "planet = 'mars'"),
    ("an export without Vz", lambda t: ["new", t / "r.toml", *ROCKET, "--from-rocketpy", _export(t, "e.csv", NO_VZ)],
     "missing: Vz"),
    ("an export still climbing", lambda t: ["new", t / "r.toml", *ROCKET, "--from-rocketpy",
                                            _export(t, "e.csv", CLIMBING)],
     "Vz = 40 m/s at its last row (t = 1 s): no apogee"),
    ("an export with a NaN", lambda t: ["new", t / "r.toml", *ROCKET, "--from-rocketpy",
                                        _export(t, "e.csv", NAN_ROW)],
     "e.csv: line 3, Z (m) = nan: must be a finite number"),
    ("no such export", lambda t: ["new", t / "r.toml", *ROCKET, "--from-rocketpy", t / "none.csv"],
     "none.csv': no such file"),
    ("an export and a start height", lambda t: ["new", t / "r.toml", *ROCKET, "--height", "900", "--from-rocketpy",
                                                EXPORTS / "dual_deploy_flight.csv"],
     "height = 900.0: the start comes from from_rocketpy"),
]


@pytest.mark.parametrize("name, make_args, expected", BATTERY, ids=[entry[0] for entry in BATTERY])
def test_bad_dual_deploy_input_gives_one_line(name, make_args, expected, tmp_path):
    code, err, seconds, touched = run_bad_input(make_args, tmp_path)
    assert_one_line(code, err, expected, touched, seconds)


def test_the_two_section_form_writes_the_ejection_the_shock_cord_and_the_openings_and_flies(tmp_path):
    """`--shock-cord-length` (issue 55): the nose cone carried until the apogee ejection, tied by a rated nylon
    cord; both canopies packed in the booster, on its eye bolt, opening by their type's law; the run reports the
    cord's snatch and margin."""
    path = tmp_path / "rocket.toml"
    assert main(["new", str(path), *FORM, *START, "--shock-cord-length", "6", "--ejection-speed", "4", "--nose-mass",
                 "2"]) == 0
    data = tomllib.loads(path.read_text())
    assert data["case"]["vehicle"] == "booster" and data["bodies"]["nose"]["mass"] == 2.0
    assert data["separations"]["nose"]["speed"] == 4.0
    cord = data["tethers"]["shock_cord"]
    assert cord["ends"] == ["booster.harness", "nose.harness"] and cord["free_length"] == 6.0
    assert cord["material"] == "nylon" and cord["breaking_strength"] == 6000.0
    for name in ("drogue", "main"):
        system = data["systems"][name]
        assert system["deploy_point"] == "booster.line_stretch" and system["inflation"]["fill_constant"] == [8.0]
        assert system["packed"] and system["lines"]["bridle"]["attach"] == "booster.harness"
        assert system["inflation"]["overinflation"] == 1.7   # the flat circular's C_x (Knacke)
    assert "cutaway_trigger" not in data["systems"]["drogue"]   # on its harness after the main opens (the default)
    assert data["bodies"]["booster"]["aerodynamics"]["reference_area"] == pytest.approx(math.pi * 0.15**2 / 4.0)
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--no-plot", "--quiet", "--t-end", "8"]) == 0
    deployments = {d["system"]: d for d in json.loads((out / "summary.json").read_text())["deployments"]}
    shock_cord = deployments["shock_cord"]
    assert shock_cord["kind"] == "tether" and shock_cord["snatch_load"] > 0.0
    assert shock_cord["lines"]["shock_cord"]["margin"] == pytest.approx(
        6000.0 / shock_cord["lines"]["shock_cord"]["load"] - 1.0)
    assert deployments["drogue"]["opening_load"] > 0.0


@pytest.mark.parametrize("extra, message", [
    (["--shock-cord-length", "0.2"], "shock_cord_length = 0.2: must be at least the nose cone's reach"),
    (["--shock-cord-length", "6", "--nose-mass", "30"], "nose_mass = 30.0: must be below the rocket's mass"),
    (["--nose-mass", "2"], "nose_mass = 2.0: only with shock_cord_length"),
    (["--ejection-speed", "3"], "ejection_speed = 3.0: only with shock_cord_length"),
    (["--shock-cord-length", "6", "--ejection-speed", "0"], "ejection_speed = 0.0: must be a number > 0"),
])
def test_bad_two_section_choices_give_one_line(tmp_path, extra, message):
    code, err, seconds, touched = run_bad_input(lambda t: ["new", str(t / "rocket.toml"), *ROCKET, *START, *extra],
                                                tmp_path)
    assert_one_line(code, err, message, touched, seconds)
