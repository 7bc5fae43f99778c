"""The day's air from a radiosonde sounding (case.soundings): a real University of Wyoming listing read, a case's air
and wind equal to its levels interpolated, and bad listings refused in one line."""

import math

import numpy as np
import pytest

from pchute_exudyn.case import load_case
from pchute_exudyn.case.soundings import KNOT, read_wyoming_sounding
from pchute_exudyn.errors import CaseError
from pchute_exudyn.physics.atmosphere import US76_R
from tests.helpers import ROOT

DTX = ROOT / "tests" / "data" / "weather" / "uwyo_72632_DTX_2016010112.txt"
SOUNDING = {"atmosphere.model": "sounding", "atmosphere.file": str(DTX)}
"""The shipped rocket case flown in the sounding's air."""


def test_a_wyoming_listing_reads_its_levels_in_si():
    s = read_wyoming_sounding(DTX)
    assert s.station == "72632 DTX White Lake Observations at 12Z 01 Jan 2016"
    assert len(s.altitude) == 118 and len(s.wind_altitude) == 117   # 1000 hPa lies under the ground; 7.4 hPa no wind
    assert s.altitude[0] == pytest.approx(329.0 * 6356766.0 / (6356766.0 - 329.0), rel=1e-12)   # geopotential 329 m
    assert s.pressure[0] == 97800.0 and s.temperature[0] == pytest.approx(268.85)
    virtual = 268.85 * (1.0 + 0.00236 / 0.621972) / 1.00236                       # MIXR 2.36 g/kg
    assert s.density[0] == pytest.approx(97800.0 / (US76_R * virtual), rel=1e-12)
    speed, angle = 12 * KNOT, math.radians(240.0)                                  # 240 deg at 12 kt: a south-westerly
    assert (s.east[0], s.north[0]) == pytest.approx((-speed * math.sin(angle), -speed * math.cos(angle)), rel=1e-12)
    assert s.east[0] > 0.0 and s.north[0] > 0.0


def test_a_case_flies_in_the_soundings_air_and_wind():
    """Density (log-linear), temperature and wind (linear) at three heights equal the levels' within 1e-6."""
    case, s = load_case(ROOT / "cases" / "rocket" / "dual_deploy.toml", SOUNDING), read_wyoming_sounding(DTX)
    for altitude in (500.0, 1500.0, 3000.0):
        density, sound = case.atmosphere.state(altitude)
        assert density == pytest.approx(math.exp(np.interp(altitude, s.altitude, np.log(s.density))), rel=1e-6)
        assert sound**2 / (1.4 * 287.05287) == pytest.approx(np.interp(altitude, s.altitude, s.temperature), rel=1e-6)
        east, north = case.wind.at(altitude)
        assert east == pytest.approx(np.interp(altitude, s.wind_altitude, s.east), abs=1e-6)
        assert north == pytest.approx(np.interp(altitude, s.wind_altitude, s.north), abs=1e-6)


BAD = [
    ("72632 DTX White Lake\n\n 978.0    329\n", "not a University of Wyoming sounding: no table head"),
    ("   PRES   HGHT   TEMP   DWPT   RELH   MIXR   DRCT   SPED   THTA   THTE   THTV\n"
     "    hPa     m      C      C      %    g/kg    deg    m/s      K      K      K\n---\n",
     "the table head must begin PRES HGHT TEMP DWPT RELH MIXR DRCT SKNT in hPa m C C % g/kg deg knot"),
    (None, "line 8, column TEMP: '-4.x' is not a number"),
    (None, "HGHT = 300 m does not rise above the level before it"),
]


@pytest.mark.parametrize("text, message", BAD, ids=["no head", "units", "text", "heights"])
def test_a_bad_listing_is_refused_in_one_line(text, message, tmp_path):
    lines = DTX.read_text().splitlines(keepends=True)
    if text is None and "not a number" in message:
        lines[7] = lines[7].replace("   -4.3", "   -4.x")
    elif text is None:
        lines[8] = lines[8].replace("    385", "    300")
    path = tmp_path / "bad.txt"
    path.write_text(text if text is not None else "".join(lines))
    with pytest.raises(CaseError) as caught:
        read_wyoming_sounding(path)
    assert message in str(caught.value) and "\n" not in str(caught.value)


def test_a_wind_beside_the_sounding_is_refused():
    with pytest.raises(CaseError, match="gives the wind: leave \\[atmosphere.wind\\] out"):
        load_case(ROOT / "cases" / "cev_pa1_winds.toml", SOUNDING)
