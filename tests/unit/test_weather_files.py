"""The day's air from weather files (case.weather_files): a NOAA IGRA 2 sounding and ERA5 netCDF grids (two namings,
and a GFS-style copy) read, a case's air and wind equal to the file's values interpolated by hand at the start point
and time, and bad files refused in one line."""

import math
import sys

import numpy as np
import pytest

from pchute_exudyn.case import load_case
from pchute_exudyn.case.forecasts import read_forecast
from pchute_exudyn.case.weather_files import read_sounding_file
from pchute_exudyn.errors import CaseError
from tests.helpers import ROOT

xarray = pytest.importorskip("xarray")
for module in ("netCDF4", "scipy.interpolate"):   # xarray's backend and interp: imported here, outside the budget
    pytest.importorskip(module)

WEATHER = ROOT / "tests" / "data" / "weather"
IGRA = WEATHER / "igra2_USM00070026_2010060100.txt"
DTX = WEATHER / "uwyo_72632_DTX_2016010112.txt"
EUROC = WEATHER / "era5_euroc_2022-10-13.nc"
NDRT = WEATHER / "era5_ndrt_2020-02-23.nc"
MEMBERS = WEATHER / "era5_euroc_2022-10-13_members.nc"
ROCKET = ROOT / "cases" / "rocket" / "dual_deploy.toml"
SITE = (39.389, -8.288)          # Ponte de Sor, Portugal (EuRoC), between the grid's points
FORECAST = {"atmosphere.model": "forecast", "atmosphere.file": str(EUROC), "atmosphere.time": "2022-10-13T11:36",
            "start.latitude_deg": SITE[0], "start.longitude_deg": SITE[1], "bodies.rocket.initial.altitude": 2500.0,
            "simulation.ground_altitude": 200.0}
"""The shipped rocket case flown in the ERA5 file's air, 36 min past its first time (its levels reach 3.2 km)."""
R0, G0, R_AIR = 6356766.0, 9.80665, 8.31432e3 / 28.9644   # US76's radius, g0 and air's gas constant
HEIGHTS = (400.0, 1500.0, 2800.0)


def test_an_igra2_file_reads_the_chosen_soundings_levels_in_si():
    """Barrow, Alaska, 12Z 1 June 2010: the surface level '21     0 100840B   12   -17B 1000     0    20    72'."""
    s = read_sounding_file(IGRA, _hour(12))
    assert s.station == "USM00070026 at 2010-06-01T12 UTC (71.2889 N, -156.7833 E)"
    assert s.altitude[0] == pytest.approx(12.0 * R0 / (R0 - 12.0), rel=1e-12)
    assert s.pressure[0] == 100840.0 and s.temperature[0] == pytest.approx(271.45)
    vapour = 611.2 * math.exp(17.67 * -1.7 / (-1.7 + 243.5))          # saturated at the dew point, DPDP = 0
    ratio = 0.621972 * vapour / (100840.0 - vapour)
    assert s.density[0] == pytest.approx(100840.0 * (1 + ratio) / (R_AIR * 271.45 * (1 + ratio / 0.621972)), rel=1e-12)
    speed, angle = 7.2, math.radians(20.0)
    assert (s.east[0], s.north[0]) == pytest.approx((-speed * math.sin(angle), -speed * math.cos(angle)), rel=1e-12)
    assert np.all(np.diff(s.wind_altitude) > 0.0) and s.wind_altitude[-1] > 30000.0   # height-only levels sorted in
    assert len(s.altitude) == 63 and read_sounding_file(IGRA, _hour(0)).pressure[0] == 100980.0


def test_the_dew_point_formula_gives_the_wyoming_listings_mixing_ratios():
    """UWyo's MIXR from its DWPT: within 0.6 % and their rounding to 0.01 g/kg on the listing's first 20 levels."""
    from pchute_exudyn.physics.barometric import dewpoint_mixing_ratio
    rows = np.genfromtxt(DTX, skip_header=7, max_rows=20, delimiter=[7] * 6, usecols=(0, 3, 5))
    ratio = dewpoint_mixing_ratio(rows[:, 0] * 100.0, rows[:, 1] + 273.15) * 1000.0
    assert np.allclose(ratio, rows[:, 2], rtol=0.006, atol=0.005)


def test_a_case_flies_in_the_wyoming_listings_values_read_by_hand():
    """Done-when, the listing: density, temperature and wind at three heights equal the raw columns interpolated
    (density log-linear) within 1e-6."""
    case = load_case(ROCKET, {"atmosphere.model": "sounding", "atmosphere.file": str(DTX)})
    table = [line for line in DTX.read_text().splitlines()[6:] if line[:7].strip().replace(".", "").isdigit()]
    rows = np.genfromtxt(table, delimiter=[7] * 8)
    p, h, t, mixr, drct, sknt = rows[:, 0] * 100.0, rows[:, 1], rows[:, 2] + 273.15, rows[:, 5] / 1e3, rows[:, 6], rows[:, 7] * 1852 / 3600
    air, wind = np.isfinite(t), np.isfinite(sknt)
    z = R0 * h / (R0 - h)
    density = p * (1 + mixr) / (R_AIR * t * (1 + mixr / 0.621972))
    east, north = -sknt * np.sin(np.radians(drct)), -sknt * np.cos(np.radians(drct))
    _assert_air(case, z[air], density[air], t[air], z[wind], east[wind], north[wind])


@pytest.mark.parametrize("override, hours", [({}, 0.6), ({"atmosphere.time": "2022-10-13T13:00"}, 2.0)],
                         ids=["between times", "last time"])
def test_a_case_flies_in_the_era5_files_values_interpolated_by_hand(override, hours):
    """Done-when, the netCDF file: the grid's z, t, u, v interpolated to the site and time by xarray's own linear
    interpolation, z / g0 made geometric, density p / (R T): the case's air and wind at three heights within
    1e-6."""
    case = load_case(ROCKET, {**FORECAST, **override})
    with xarray.open_dataset(EUROC) as grid:
        at = grid.interp(latitude=SITE[0], longitude=SITE[1],
                         valid_time=np.datetime64("2022-10-13T11:00") + np.timedelta64(int(hours * 3600), "s"))
        p = at.pressure_level.values * 100.0
        z, t, u, v = (at[name].values.astype(float) for name in ("z", "t", "u", "v"))
    height = z / G0
    altitude = R0 * height / (R0 - height)
    _assert_air(case, altitude, p / (R_AIR * t), t, altitude, u, v)


def test_three_namings_of_one_grid_give_one_profile(tmp_path):
    """ERA5's old naming (time, level in millibars, packed) read like its new one; a GFS-style copy of the EuRoC
    grid (gh in gpm, lat/lon with longitudes 0..360, isobaricInhPa, time) gives the same profile as ERA5's z."""
    with xarray.open_dataset(EUROC) as grid:
        gfs = grid.rename(valid_time="time", pressure_level="isobaricInhPa", latitude="lat", longitude="lon")
        gfs = gfs.assign_coords(lon=gfs.lon % 360.0).drop_vars("number")
        gfs["gh"] = (gfs.z.astype(float) / G0).assign_attrs(units="gpm")
        gfs.drop_vars("z").to_netcdf(tmp_path / "gfs.nc")
    time = _hour(12, 2022, 10, 13)
    era5, copy = read_forecast(EUROC, SITE, time, None), read_forecast(tmp_path / "gfs.nc", SITE, time, None)
    for name in ("altitude", "pressure", "temperature", "density", "east", "north"):
        assert np.allclose(getattr(copy, name), getattr(era5, name), rtol=1e-9, atol=0.0), name
    old = read_forecast(NDRT, (41.7, -86.6), _hour(17, 2020, 2, 23), None)
    assert list(old.pressure) == [100000.0, 95000.0, 90000.0, 85000.0, 80000.0, 75000.0]
    assert 270.0 < old.temperature.min() and old.temperature.max() < 285.0 and np.all(np.diff(old.altitude) > 0)


def test_an_ensemble_member_is_chosen_by_its_number():
    """The member file: member 0 is the real field; member 3's north wind is 3 m/s more, its air the same."""
    base = read_forecast(EUROC, SITE, _hour(12, 2022, 10, 13), None)
    control, third = (read_forecast(MEMBERS, SITE, _hour(12, 2022, 10, 13), k) for k in (0, 3.0))
    assert np.array_equal(control.north, base.north) and np.array_equal(control.density, base.density)
    assert np.allclose(third.north - base.north, 3.0, atol=1e-5) and np.array_equal(third.east, base.east)


BAD_CASES = [
    ({"atmosphere.time": "2022-10-13 11:00"}, "atmosphere.time = '2022-10-13 11:00': must be a UTC time"),
    ({"atmosphere.time": "2022-10-13T14:30"}, "time 2022-10-13T14:30 UTC is outside the file's times: "
                                              "2022-10-13T11:00 to 2022-10-13T13:00 UTC"),
    ({"start.latitude_deg": 41.0}, "the start point (41 N, -8.288 E) lies outside the file's grid: latitude 39 to "
                                   "39.5 deg, longitude -8.5 to -8 deg"),
    ({"atmosphere.time": None}, "holds 3 times from 2022-10-13T11:00 to 2022-10-13T13:00 UTC (2022-10-13T11:00, "
                                "2022-10-13T12:00, 2022-10-13T13:00): choose one with [atmosphere] time"),
    ({"atmosphere.file": str(MEMBERS)}, "holds 5 ensemble members (number = 0, 1, 2, 3, 4): choose one with "
                                        "[atmosphere] member = N"),
    ({"atmosphere.file": str(MEMBERS), "atmosphere.member": 7}, "has no ensemble member 7: its members are number"),
    ({"atmosphere.member": 1}, "has no ensemble members (no number, ensemble, member, realization, ens dimension)"),
    ({"atmosphere.member": 1.5}, "atmosphere.member = 1.5: must be an ensemble member's number"),
    ({"atmosphere.file": str(DTX)}, "is not a netCDF file (it begins with neither 'CDF' nor the HDF5 signature"),
    ({"atmosphere.model": "sounding", "atmosphere.file": str(IGRA), "atmosphere.time": None},
     "holds 2 soundings (2010-06-01T00, 2010-06-01T12): choose one with [atmosphere] time = \"YYYY-MM-DDTHH\""),
    ({"atmosphere.model": "sounding", "atmosphere.file": str(IGRA), "atmosphere.time": "2010-06-01T06"},
     "has no sounding at 2010-06-01T06:00 UTC: it holds 2 from 2010-06-01T00 to 2010-06-01T12"),
    ({"atmosphere.model": "sounding", "atmosphere.file": str(DTX), "atmosphere.time": "2016-01-01T00"},
     "the listing holds one sounding, '72632 DTX White Lake Observations at 12Z 01 Jan 2016'; leave time out"),
]


@pytest.mark.parametrize("override, message", BAD_CASES, ids=[
    "time form", "time outside", "site outside", "times to choose", "members to choose", "no such member",
    "member without ensemble", "member not whole", "not netcdf", "soundings to choose", "no such sounding",
    "wyoming time"])
def test_a_bad_weather_choice_is_refused_in_one_line(override, message):
    over = {**FORECAST, **{k: v for k, v in override.items() if v is not None}}
    over = {k: v for k, v in over.items() if not (k in override and override[k] is None)}
    with pytest.raises(CaseError) as caught:
        load_case(ROCKET, over)
    assert message in str(caught.value) and "\n" not in str(caught.value)


def test_a_forecast_needs_the_cases_site(tmp_path):
    text = ROCKET.read_text().replace("latitude_deg = 32.99\n", "").replace("longitude_deg = -106.97\n", "")
    (tmp_path / "rocket.toml").write_text(text)
    with pytest.raises(CaseError, match=r"atmosphere.model = 'forecast': a forecast's air is taken at the start "
                                        r"point: give \[start\] latitude_deg and longitude_deg \(deg\)$"):
        load_case(tmp_path / "rocket.toml", {k: v for k, v in FORECAST.items() if not k.startswith("start")})


def _edited(tmp_path, edit):
    with xarray.open_dataset(EUROC) as grid:
        grid = edit(grid.load())
    path = tmp_path / "edited.nc"
    grid.to_netcdf(path)
    return path


BAD_FILES = [
    (lambda g: g.drop_vars("t"), "has no temperature field (named t, tmp, air, tmpprs); its fields are: z, u, v"),
    (lambda g: g.isel(pressure_level=[0]), "fewer than two levels with a pressure, a height and a temperature"),
    (lambda g: g.assign(t=(g.t - 273.15).assign_attrs(units="K")),
     "field t runs from 5.71257 to 24.174, not temperatures in K (150 to 350 K): its units say K"),
    (lambda g: g.assign(t=g.t.assign_attrs(units="degC")), "field t: units 'degC' are not known; allowed: K"),
    (lambda g: g.assign(z=g.z.assign_attrs(units="gpm")), "field z gives 4176 m at 975 hPa, where the standard atmosphere has 323 m: its "
                                                          "units ('gpm') do not fit its values"),
    (lambda g: g.assign_coords(pressure_level=g.pressure_level.assign_attrs(units="inHg")),
     "pressure level pressure_level: units 'inHg' are not known; allowed: hPa, millibars, Pa"),
]


@pytest.mark.parametrize("edit, message", BAD_FILES, ids=["no temperature", "one level", "celsius as kelvin",
                                                          "unknown unit", "geopotential as height", "level unit"])
def test_a_bad_netcdf_file_is_refused_in_one_line(edit, message, tmp_path):
    with pytest.raises(CaseError) as caught:
        read_forecast(_edited(tmp_path, edit), SITE, _hour(12, 2022, 10, 13), None)
    assert message in str(caught.value) and "\n" not in str(caught.value) and "edited.nc" in str(caught.value)


def test_without_xarray_the_extra_to_install_is_named(monkeypatch):
    monkeypatch.setitem(sys.modules, "xarray", None)   # as if not installed: its import fails
    with pytest.raises(CaseError, match=r"era5_euroc_2022-10-13.nc: reading a netCDF weather file needs xarray and "
                                        r"netCDF4: pip install 'pchute-exudyn\[weather\]'$"):
        read_forecast(EUROC, SITE, _hour(12, 2022, 10, 13), None)


def test_a_cut_short_netcdf_file_is_refused_in_one_line(tmp_path):
    (tmp_path / "cut.nc").write_bytes(EUROC.read_bytes()[:4000])
    with pytest.raises(CaseError, match=r"cut.nc: cannot be read as netCDF: the file may be cut short or damaged$"):
        read_forecast(tmp_path / "cut.nc", SITE, _hour(12, 2022, 10, 13), None)


def test_a_cut_short_igra2_file_is_refused_in_one_line(tmp_path):
    lines = IGRA.read_text().splitlines(keepends=True)
    (tmp_path / "cut.txt").write_text("".join(lines[:100]))
    with pytest.raises(CaseError, match=r"line 1: the sounding announces 158 levels \(NUMLEV\) but 99 follow it"):
        read_sounding_file(tmp_path / "cut.txt", _hour(0))
    lines[5] = lines[5][:22] + "  -x2" + lines[5][27:]
    (tmp_path / "text.txt").write_text("".join(lines))
    with pytest.raises(CaseError, match=r"line 6, TEMP \(columns 23-27\): '-x2' is not an integer$"):
        read_sounding_file(tmp_path / "text.txt", _hour(0))


def _hour(hour, year=2010, month=6, day=1):
    from datetime import datetime
    return datetime(year, month, day, hour)


def _assert_air(case, altitude, density, temperature, wind_altitude, east, north):
    """The case's density (log-linear), temperature and wind at HEIGHTS equal the levels' within 1e-6."""
    for height in HEIGHTS:
        rho, sound = case.atmosphere.state(height)
        assert rho == pytest.approx(math.exp(np.interp(height, altitude, np.log(density))), rel=1e-6)
        assert sound**2 / (1.4 * 287.05287) == pytest.approx(np.interp(height, altitude, temperature), rel=1e-6)
        wind = case.wind.at(height)
        assert wind[0] == pytest.approx(np.interp(height, wind_altitude, east), abs=1e-6)
        assert wind[1] == pytest.approx(np.interp(height, wind_altitude, north), abs=1e-6)
