"""A run in a radiosonde sounding's air (`[atmosphere] model = "sounding"`): the rocket drifts with the listing's
winds."""

import numpy as np

import pchute_exudyn as pc
from pchute_exudyn.case.soundings import read_wyoming_sounding
from tests.helpers import ROOT, run_cli

DTX = ROOT / "tests" / "data" / "weather" / "uwyo_72632_DTX_2016010112.txt"


def test_a_rocket_under_its_drogue_drifts_with_the_soundings_wind(tmp_path):
    """White Lake, 12Z 1 Jan 2016: a 40-60 kt westerly at 1-2 km. After 40 s under a drogue the rocket moves with
    the listing's wind at its altitude (within 1 m/s of 20 to 30 m/s: the drag's lag as the wind shears)."""
    case = tmp_path / "dtx.toml"
    done = run_cli("new", str(case), "--dual-deploy", "--planet", "earth", "--mass", "12", "--length", "2.4",
                   "--diameter", "0.13", "--drogue-drag-area", "0.5", "--main-drag-area", "9", "--main-height", "200",
                   "--height", "2000", "--ground-elevation", "329", "--latitude", "42.7", "--longitude", "-83.47")
    assert done.returncode == 0, done.stderr
    case.write_text(case.read_text().replace('model = "us76"', f'model = "sounding"\nfile = "{DTX}"'))
    result = pc.simulate(pc.load_case(case, {"simulation.duration": 40.0}), "sp")
    sounding = read_wyoming_sounding(DTX)
    altitude = result["rocket_altitude"][-1]
    wind = [np.interp(altitude, sounding.wind_altitude, component) for component in (sounding.east, sounding.north)]
    assert np.hypot(*wind) > 15.0
    assert abs(result["rocket_velocity_east"][-1] - wind[0]) < 1.0
    assert abs(result["rocket_velocity_north"][-1] - wind[1]) < 1.0
