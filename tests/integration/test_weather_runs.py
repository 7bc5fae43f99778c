"""Runs in the air of weather files: an IGRA 2 sounding and an ERA5 grid drive the rocket's drift, and a study over an
ensemble file's members gives a landing footprint."""

from datetime import datetime

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.case.weather_files import read_sounding_file
from pchute_exudyn.study.footprint import footprint_statistics, touchdown_points
from tests.helpers import ROOT, study_runs

pytest.importorskip("xarray")

WEATHER = ROOT / "tests" / "data" / "weather"
ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"
IGRA = {"atmosphere.model": "sounding", "atmosphere.file": str(WEATHER / "igra2_USM00070026_2010060100.txt"),
        "atmosphere.time": "2010-06-01T00", "start.latitude_deg": 71.2889, "start.longitude_deg": -156.7833,
        "simulation.ground_altitude": 12.0}
"""Barrow, Alaska, 00Z 1 June 2010 (a 2-15 m/s south-westerly at 1-2 km)."""
ERA5 = {"atmosphere.model": "forecast", "atmosphere.file": str(WEATHER / "era5_euroc_2022-10-13.nc"),
        "atmosphere.time": "2022-10-13T12:00", "start.latitude_deg": 39.389, "start.longitude_deg": -8.288,
        "simulation.ground_altitude": 200.0}
"""Ponte de Sor, Portugal, 12Z 13 October 2022."""


@pytest.mark.parametrize("weather", [IGRA, ERA5], ids=["igra2", "era5"])
def test_a_rocket_under_its_drogue_drifts_with_the_files_wind(weather):
    """From 1500 m above the ground, 30 s under the drogue: the rocket, which left apogee at 15 m/s east over the
    ground, moves with the file's wind at its altitude (within 1 m/s: the drag's lag as the wind shears), the wind
    the sounding's own levels interpolated."""
    case = pc.load_case(ROCKET, {**weather, "bodies.rocket.initial.altitude": weather["simulation.ground_altitude"]
                                 + 1500.0, "simulation.duration": 30.0})
    result = pc.simulate(case, "sp")
    altitude = result["rocket_altitude"][-1]
    assert altitude > weather["simulation.ground_altitude"] + 600.0            # still under the drogue
    east, north = case.wind.at(altitude)
    if weather is IGRA:   # the case's wind is the file's: the sounding's own levels there
        s = read_sounding_file(WEATHER / "igra2_USM00070026_2010060100.txt", datetime(2010, 6, 1, 0))
        assert (east, north) == pytest.approx([np.interp(altitude, s.wind_altitude, c) for c in (s.east, s.north)])
    assert np.hypot(east - 15.0, north) > 10.0   # far from the start's 15 m/s east over the ground
    assert abs(result["rocket_velocity_east"][-1] - east) < 1.0
    assert abs(result["rocket_velocity_north"][-1] - north) < 1.0


STUDY = """
[study]
name = "EuRoC 2022 members"
case = "members.toml"

[[study.configurations]]
method = "sp"

[parameters."atmosphere.member"]
values = [0, 1, 2, 3, 4]
"""
CASE = f"""
extends = "{ROCKET.as_posix()}"

[start]
latitude_deg = 39.389
longitude_deg = -8.288

[atmosphere]
model = "forecast"
file = "{(WEATHER / 'era5_euroc_2022-10-13_members.nc').as_posix()}"
time = "2022-10-13T12:00"

[bodies.rocket.initial]
altitude = 700.0

[simulation]
ground_altitude = 200.0
"""


def test_a_study_over_the_ensemble_members_gives_a_footprint(tmp_path):
    """Five members whose winds differ by 3 m/s east or north (the member file, SOURCES.md): each lands displaced
    from member 0's point by that wind offset times the descent's time, less the ~3 s the rocket takes to pick up
    the offset from its start over the ground (within 5 m; 1.5 m flown); the footprint's spread follows."""
    from pchute_exudyn.study import load_study, run_study

    (tmp_path / "members.toml").write_text(CASE)
    (tmp_path / "study.toml").write_text(STUDY)
    run_study(load_study(tmp_path / "study.toml"), tmp_path / "out", workers=1, progress=False)
    rows = study_runs(tmp_path / "out")
    assert [row["atmosphere.member"] for row in rows] == ["0", "1", "2", "3", "4"]
    points = touchdown_points([{k: _number(v) for k, v in row.items()} for row in rows])
    assert len(points) == 5
    flight = float(rows[0]["touchdown_time"])
    offsets = points[1:] - points[0]
    expected = 3.0 * np.array([[1, 0], [-1, 0], [0, 1], [0, -1]]) * (flight - 3.0)
    assert np.abs(offsets - expected).max() < 5.0
    stats = footprint_statistics(points)
    assert stats["count"] == 5 and stats["sigma_major"] > 100.0


def _number(text: str):
    try:
        return float(text)
    except ValueError:
        return text


def test_a_log_is_read_through_the_forecasts_air_by_compare(tmp_path):
    """`pchute compare RUN LOG` end to end with a forecast-driven run: an altimeter's log of the run's own descent
    (its heights the standard atmosphere's for the pressures of the forecast's air, the column of the case's own
    densities integrated here; a 12 s climb before) is read back through the run's air to the run's apogee height
    within 0.5 m; as the altimeter gave it, it is 20 m short (the day is 6-9 K warmer than the standard)."""
    from pchute_exudyn.physics.barometric import pressure_altitude, standard_pressure
    from pchute_exudyn.results.log_files import compare_files

    case_file = tmp_path / "forecast.toml"
    case_file.write_text(CASE.replace("_members.nc", ".nc").replace("altitude = 700.0", "altitude = 1200.0"))
    case = pc.load_case(case_file)
    result = pc.simulate(case, "sp")
    result.save(tmp_path / "run", plot=False, csv=False)
    time = np.arange(-17.0, result["time"][-1] + 5.0, 0.05)   # 5 s on the pad, a 12 s climb, the descent
    climb = 1000.0 * (1.0 - (np.clip(time, -12.0, 0.0) / 12.0) ** 2)
    above = np.where(time < 0.0, climb, np.interp(time, result["time"], result["rocket_altitude"] - 200.0))
    grid = np.arange(0.0, 1001.0, 0.5)
    density = case.atmosphere.states(grid + 200.0)[0]
    column = np.concatenate([[0.0], np.cumsum(np.diff(grid) * 0.5 * (density[1:] + density[:-1]))]) * 9.80665
    baro = pressure_altitude(standard_pressure(200.0) - np.interp(above, grid, column)) - 200.0
    rows = ["time (s),height (m)"] + [f"{t + 17.0:.3f},{h:.4f}" for t, h in zip(time, np.maximum(baro, 0.0))]
    (tmp_path / "log.csv").write_text("\n".join(rows) + "\n")
    apogee = {row[0]: row[2:] for row in compare_files(str(tmp_path / "run"), str(tmp_path / "log.csv")).rows()}[
        "apogee height above the ground"]
    assert apogee[1] == pytest.approx(apogee[0], abs=0.5) and apogee[0] - baro.max() > 15.0   # 0.02 m; 20 m
