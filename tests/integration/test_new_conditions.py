"""`pchute new --mach M --dynamic-pressure Q`: a new case that starts at line stretch at flight conditions
(authoring.flight_start) starts at that Mach number and dynamic pressure and flies to touchdown; choices the start cannot
take are one-line errors with a non-zero exit."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.case.files import tomllib
from pchute_exudyn.cli import main
from pchute_exudyn.physics.atmosphere import MarsGRC
from pchute_exudyn.physics.conditions import altitude_and_speed
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import run_cli

MORTAR = ["--planet", "mars", "--mach", "1.8", "--dynamic-pressure", "520", "--flight-path-deg", "-20"]


def test_a_case_written_at_flight_conditions_starts_at_them_and_lands(tmp_path, capsys):
    """The command line's file: its first sample has the vehicle at Mach 1.8 and 520 Pa (within 1e-9), 20 deg below
    the horizon heading north, at the altitude where the Mars model gives them; the run ends at touchdown."""
    path = tmp_path / "mortar.toml"
    assert main(["new", str(path), *MORTAR]) == 0
    altitude, speed = altitude_and_speed(MarsGRC(), 1.8, 520.0)
    assert f"line stretch at Mach 1.8 and 520 Pa: {altitude:.1f} m, {speed:.2f} m/s" in capsys.readouterr().out
    text = path.read_text()
    initial = tomllib.loads(text)["bodies"]["vehicle"]["initial"]
    assert initial == {"mach": 1.8, "dynamic_pressure": 520.0, "flight_path_deg": -20.0, "heading_deg": 0.0}
    assert f"# Mach 1.8 at 520 Pa: {altitude:.1f} m, {speed:.2f} m/s through the air" in text
    assert main(["run", str(path), "--no-plot", "--quiet", "--out", str(tmp_path / "out")]) == 0
    result = pc.Result.load(tmp_path / "out")
    assert result["vehicle_mach"][0] == pytest.approx(1.8, rel=1e-9)
    assert result["vehicle_dynamic_pressure"][0] == pytest.approx(520.0, rel=1e-9)
    assert result["vehicle_altitude"][0] == pytest.approx(altitude, abs=1e-6)
    north, east, down = (result[f"vehicle_velocity_{axis}"][0] for axis in ("north", "east", "down"))
    assert math.degrees(math.atan2(-down, math.hypot(north, east))) == pytest.approx(-20.0, abs=1e-9)
    assert east == pytest.approx(0.0, abs=1e-9) and north > 0.0
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["end"] == "touchdown"
    assert [(event["event"], event["time"]) for event in summary["events"][:2]] == [("start", 0.0), ("deploy", 0.0)]


@pytest.mark.parametrize("choices", [
    dict(planet="earth", mass=100.0, drag_area=10.0, diameter=0.6, mach=0.3, dynamic_pressure=2000.0,
         flight_path_deg=-30.0, heading_deg=90.0, wind_speed=8.0, wind_from_deg=200.0),
    dict(planet="flat", mass=5.0, drag_area=1.0, diameter=0.2, mach=0.15, dynamic_pressure=1000.0, bridles=1)],
    ids=["earth-wind", "flat-one-bridle"])
def test_every_planet_starts_at_its_flight_conditions_through_the_air(choices):
    """Through a wind too: the Mach number and dynamic pressure are the air's, at the first sample."""
    result = pc.simulate(pc.new_case(**choices), "sp", duration=0.05)
    assert result["vehicle_mach"][0] == pytest.approx(choices["mach"], rel=1e-9)
    assert result["vehicle_dynamic_pressure"][0] == pytest.approx(choices["dynamic_pressure"], rel=1e-9)
    assert np.isfinite(result["vehicle_altitude"]).all()


BAD = [
    ("mach without dynamic pressure", ["--mach", "1.8"],
     "mach = 1.8: needs dynamic_pressure too (--dynamic-pressure, a number > 0 (Pa))"),
    ("dynamic pressure without mach", ["--dynamic-pressure", "520"],
     "dynamic_pressure = 520.0: needs mach too (--mach, a number > 0 (-))"),
    ("dynamic pressure no altitude gives", ["--mach", "1.8", "--dynamic-pressure", "1e7"],
     "dynamic_pressure = 10000000.0: with mach = 1.8: no altitude of the mars_grc atmosphere (-10000 to 100000 m) "
     "gives 1e+07 Pa at Mach 1.8: it spans"),
    ("start below the ground", ["--mach", "1.8", "--dynamic-pressure", "3000"],
     "dynamic_pressure = 3000.0: with mach = 1.8 the mars_grc atmosphere puts the start at -7656.8 m, not above the "
     "ground (0 m, where the run ends)"),
    ("altitude beside mach", ["--altitude", "8000", *MORTAR[2:]],
     "altitude = 8000.0: not with mach (--mach): the flight conditions give the start altitude"),
    ("flight path without mach", ["--flight-path-deg", "-20"], "flight_path_deg = -20.0: only with mach (--mach)"),
    ("release beside mach", ["--release-airspeed", "60", *MORTAR[2:]],
     "release_airspeed = 60.0: not with mach and dynamic_pressure"),
]


@pytest.mark.parametrize("name, args, expected", BAD, ids=[entry[0] for entry in BAD])
def test_a_start_the_flight_conditions_cannot_give_is_one_line(tmp_path, name, args, expected):
    code, err, seconds, touched = run_bad_input(lambda t: ["new", str(t / "n.toml"), *args], tmp_path)
    assert_one_line(code, err, expected, touched, seconds)
    assert not (tmp_path / "n.toml").exists()


def test_the_command_exits_non_zero_with_one_line_in_a_process_of_its_own(tmp_path):
    done = run_cli("new", tmp_path / "n.toml", "--mach", "1.8", "--dynamic-pressure", "1e7")
    assert done.returncode == 1 and done.stdout == ""
    assert done.stderr.strip().splitlines() == [
        "pchute new: error: dynamic_pressure = 10000000.0: with mach = 1.8: no altitude of the mars_grc atmosphere "
        "(-10000 to 100000 m) gives 1e+07 Pa at Mach 1.8: it spans 0.1859 to 3704 Pa there"]
    assert not (tmp_path / "n.toml").exists()
