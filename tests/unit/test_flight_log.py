"""Flight logs as they come (``results.flight_log``): excerpts of real AltOS and Blue Raven exports (two altimeters
on one flight agreeing), a generic CSV in feet, and bad logs refused in one line."""

import numpy as np
import pytest

from pchute_exudyn.errors import InputError
from pchute_exudyn.results.flight_log import FOOT, read_flight_log
from tests.helpers import ROOT

ALTOS = ROOT / "tests" / "data" / "flight_logs" / "altos_nustars26_ft1_every20th.csv"


def test_an_altos_export_is_read_as_it_comes_with_its_pad_apogee_and_band_rates():
    """NUSTARS IREC FT1 (tests/data/flight_logs/SOURCES.md): every 20th row of the TeleMega's export, a text state
    column, two columns named altitude (baro, then GPS), GPS and sensor rows sharing time stamps. Apogee 2199 m above
    the pad at 20.4 s in the full log; the drogue's and the main's rates as the full log gives them (16.2 and 4.9
    m/s over these bands, ``physics.flight_phases`` on all 4796 rows)."""
    log = read_flight_log(ALTOS)
    assert log.format == "AltOS" and log.kind == "barometric"
    assert np.all(np.diff(log.time) > 0.0)
    assert log.pad_altitude == pytest.approx(185.27, abs=0.05)   # altitude - height: 186.63 - 1.36 on its first row
    phases = log.phases
    assert phases.apogee_height - phases.pad_level == pytest.approx(2199.0, rel=0.01)
    assert phases.apogee_time == pytest.approx(20.4, abs=1.0)
    drogue, _ = log.descent_rate(400.0, 1800.0)
    main, used = log.descent_rate(30.0, 150.0)
    assert drogue == pytest.approx(16.2, rel=0.05)
    assert main == pytest.approx(4.9, rel=0.1) and used >= 5


def _generic(tmp_path, header, times, heights, name="log.csv"):
    path = tmp_path / name
    path.write_text(header + "\n" + "\n".join(f"{t:.3f},{h:.3f}" for t, h in zip(times, heights)) + "\n")
    return path


def _flight():
    t = np.arange(0.0, 120.0, 0.05)
    h = np.where(t < 10.0, 3.0 * t * t, 300.0 - 8.0 * (t - 10.0))   # a climb to 300 m, then 8 m/s down
    h[t < 1.0] = 0.0
    return t, np.maximum(h, 0.0) + 100.0


def test_a_generic_log_in_feet_gives_metres_per_second(tmp_path):
    t, h = _flight()
    log = read_flight_log(_generic(tmp_path, "time (s),altitude (ft)", t, h / FOOT))
    assert log.format == "generic"
    assert log.descent_rate(50.0, 250.0)[0] == pytest.approx(8.0, rel=1e-3)


@pytest.mark.parametrize("header, change, message", [
    ("time (s),altitude", lambda t, h: (t, h), "has unit 'none': say m or ft"),
    ("time (s),altitude (m)", lambda t, h: (np.where(np.arange(len(t)) == 50, t[40], t), h), "time goes back"),
    ("time (s),pressure (Pa)", lambda t, h: (t, h), "needs a time column and a height column"),
])
def test_a_bad_log_is_refused_in_one_line(tmp_path, header, change, message):
    t, h = _flight()
    with pytest.raises(InputError, match=message) as caught:
        read_flight_log(_generic(tmp_path, header, *change(t, h)))
    assert "\n" not in str(caught.value)


def test_a_log_that_never_descends_says_so(tmp_path):
    t = np.arange(0.0, 20.0, 0.05)
    log = read_flight_log(_generic(tmp_path, "time (s),height (m)", t, np.minimum(20.0 * t, 300.0)))
    with pytest.raises(InputError, match="no descent"):
        log.descent_rate(50.0, 250.0)


def test_two_altimeters_on_one_flight_read_the_same_apogee_and_rates():
    """A Blue Raven (feet, its own column names, hex and flag columns) and a TeleMega (AltOS) flew together on the
    NUSTARS flight of 2025-08-16 (tests/data/flight_logs/SOURCES.md): from every 20th row of each, the apogee within
    0.5 % and the drogue's and the main's band rates within 2 % and 5 % (the full logs: 1236.7 against 1235.4 m,
    22.74 against 22.76 and 5.58 against 5.72 m/s)."""
    raven = read_flight_log(ROOT / "tests" / "data" / "flight_logs" / "blueraven_nustars_20250816_every20th.csv")
    altos = read_flight_log(ROOT / "tests" / "data" / "flight_logs" / "altos_nustars_20250816_every20th.csv")
    assert (raven.format, altos.format) == ("Blue Raven", "AltOS")
    tops = [log.phases.apogee_height - log.phases.pad_level for log in (raven, altos)]
    assert tops[0] == pytest.approx(tops[1], rel=0.005) and tops[0] == pytest.approx(1236.0, rel=0.005)
    assert raven.descent_rate(300.0, 900.0)[0] == pytest.approx(altos.descent_rate(300.0, 900.0)[0], rel=0.02)
    assert raven.descent_rate(20.0, 120.0)[0] == pytest.approx(altos.descent_rate(20.0, 120.0)[0], rel=0.05)
