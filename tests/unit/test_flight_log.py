"""Flight logs as they come (``results.flight_log``, ``results.log_formats``): excerpts of real AltOS, Blue Raven,
Raven FIP, Eggtimer, CATS and StratoLogger logs (tests/data/flight_logs/SOURCES.md; two altimeters on one flight
agreeing), a generic CSV in feet, the descent to the touchdown, and bad logs refused in one line."""

import numpy as np
import pytest

from pchute_exudyn.errors import InputError
from pchute_exudyn.results.flight_log import FOOT, read_flight_log
from tests.helpers import ROOT

LOGS = ROOT / "tests" / "data" / "flight_logs"
ALTOS = LOGS / "altos_nustars26_ft1_every20th.csv"


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


def _lines(tmp_path, text, name="log.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize("times, heights, message", [
    (np.arange(0.0, 20.0, 0.05), lambda t: np.minimum(20.0 * t, 300.0), "never falls 10 m below .*: no descent"),
    (np.arange(0.0, 12.0, 0.05), lambda t: 20.0 * t, r"still rises at the log's end .*: no apogee"),
    (np.arange(0.0, 20.0, 0.05), lambda t: 0.1 * np.sin(t), r"never rises 10 m above the pad level .*: no launch"),
])
def test_a_log_with_no_launch_apogee_or_descent_is_refused_on_reading(tmp_path, times, heights, message):
    """A log that only climbs (cut off before the apogee), that climbs and stays up, or that never leaves the pad:
    refused by ``read_flight_log`` in one line naming the file and the height."""
    path = _generic(tmp_path, "time (s),height (m)", times, heights(times))
    with pytest.raises(InputError, match=f"log.csv: height: the height {message}") as caught:
        read_flight_log(path)
    assert "\n" not in str(caught.value)


@pytest.mark.parametrize("text, message", [
    ("", "the file is empty"),
    ("\n\n", "the file is empty"),
    ("time (s),altitude (m)\n", r"the header \('time \(s\),altitude \(m\)'\) has no data rows"),
    ("#version,serial,flight,time,state,state_name,height,altitude\n", "has no data rows"),
    ("time (s),altitude (m)\n0.0,1.0\n0.1,1.2\n0.2,abc\n", r"row 4, column 'altitude \(m\)': 'abc' is not a number"),
    ("#version,serial,flight,time,state,state_name,height,altitude\n6, 1, 1, 0.0, 3, boost, 1.0, 200.0\n"
     "6, 1, 1, 0.1, 3, boost, 2.x, 201.0\n", r"row 3, column 'height': '2.x' is not a number"),
    ("time (s),altitude (m)\n0.0,1.0\n0.1,1.2\n0.05,1.3\n", r"row 4, column 'time \(s\)': time goes back "
                                                           r"\(0.1 s, then 0.05 s\)"),
    ("T,Alt,Veloc,Filt_Alt,FVeloc,LDA,LowV,Apogee,N-O,Drogue,Main\n0,4,0,0,0,0,0,0,0,0,0\n50,x,0,0,0,0,0,0,0,0,0\n",
     r"row 3, column 'Alt': 'x' is not a number"),
    ("time,altitude (m)\n0,1\n", None),
])
def test_a_bad_file_is_refused_in_one_line_naming_the_row_column_and_value(tmp_path, text, message):
    path = _lines(tmp_path, text)
    if message is None:   # two samples: read, then refused by the phases
        message = r"height: times must increase from sample to sample \(at least three samples\)"
    with pytest.raises(InputError, match=message) as caught:
        read_flight_log(path)
    assert str(path) in str(caught.value) and "\n" not in str(caught.value)


def test_the_descent_runs_from_the_apogee_to_the_touchdown_without_the_pad(tmp_path):
    """A synthetic flight: 300 m at 10 s, 8 m/s down, on the pad from 47.5 s for 72 s more: ``descent`` gives the
    samples from the apogee (or ``after`` s past it) to the touchdown, heights above the pad level."""
    t, h = _flight()
    log = read_flight_log(_generic(tmp_path, "time (s),altitude (m)", t, h))
    assert log.touchdown_time == pytest.approx(47.5, abs=0.1)   # the descent's line extended to the rest level
    time, height = log.descent()
    assert time[0] == pytest.approx(log.phases.apogee_time, abs=0.05) and time[-1] == log.time[log.touchdown_index]
    assert height.max() == pytest.approx(300.0, abs=5.0) and height[-1] == pytest.approx(0.0, abs=8.0)
    later, _ = log.descent(after=5.0)
    assert later[0] == pytest.approx(log.phases.apogee_time + 5.0, abs=0.05) and later[-1] == time[-1]


def test_a_stratologger_csv_is_read_in_feet_and_agrees_with_the_telemetrum_beside_it():
    """ISSUIUC 2021-10-30 (SOURCES.md): a StratoLogger (``altitude_ft``, a text temperature ``76.7F``) and a
    TeleMetrum (AltOS, telemetry rows with GPS) flew together: apogees within 0.5 %, drogue band rates within 3 %;
    the StratoLogger's board at 76.7 F = 298.0 K on the pad; it lands 11.6 m above its pad level (a slope)."""
    strato = read_flight_log(LOGS / "stratologger_issuiuc_20211030_every10th.csv")
    tele = read_flight_log(LOGS / "altos_telemetrum_issuiuc_20211030_every5th.csv")
    assert (strato.format, tele.format) == ("StratoLogger", "AltOS")
    tops = [log.phases.apogee_height - log.phases.pad_level for log in (strato, tele)]
    assert tops[0] == pytest.approx(tops[1], rel=0.005) and tops[0] == pytest.approx(2840.0, rel=0.005)
    assert strato.descent_rate(1000.0, 2500.0)[0] == pytest.approx(tele.descent_rate(1000.0, 2500.0)[0], rel=0.03)
    assert strato.temperature[0] == pytest.approx((76.7 - 32.0) / 1.8 + 273.15)
    assert strato.touchdown_time == pytest.approx(188.0, abs=1.0)
    assert tele.events["apogee"] == pytest.approx(tele.phases.apogee_time, abs=1.0) and "main" in tele.events
    assert np.nanmax(tele.latitude_deg) == pytest.approx(41.49, abs=0.05) and tele.touchdown_time is None


def test_a_baro_only_altos_export_reads_without_gps():
    """NUSTARS FT1 2025 backup (SOURCES.md): an AltOS export with no GPS columns: heights, pad altitude, pressure,
    board temperature and the drogue/main states; no GPS arrays."""
    log = read_flight_log(LOGS / "altos_baro_only_nustars25_ft1_every10th.csv")
    assert log.format == "AltOS" and log.latitude_deg is None and log.gps_altitude is None
    assert log.phases.apogee_height - log.phases.pad_level == pytest.approx(1220.0, rel=0.005)
    assert log.pad_altitude == pytest.approx(231.9, abs=0.5)
    assert log.pressure[0] == pytest.approx(98328.0) and log.temperature[0] == pytest.approx(3.7 + 273.15)
    assert log.events["apogee"] == pytest.approx(log.phases.apogee_time, abs=0.5)
    assert log.events["main"] == pytest.approx(57.97, abs=0.5)


def test_a_raven_fip_export_gives_the_apogee_its_companion_altimeter_states():
    """Featherweight Raven through FIP (SOURCES.md): every channel on its own clock, ended channels as two empty
    cells. The apogee 1009 ft AGL that the same flight's PerfectFlite Pnut states, within 1 %; the Raven's own apogee
    flag within 0.3 s of the barometric peak; pressure from atm, the board temperature from deg F."""
    log = read_flight_log(LOGS / "raven_fip_topshot_every2nd_baro_rows.csv")
    assert log.format == "Raven FIP" and log.kind == "barometric"
    assert (log.phases.apogee_height - log.phases.pad_level) / FOOT == pytest.approx(1009.0, rel=0.01)
    assert log.events["apogee"] == pytest.approx(log.phases.apogee_time, abs=0.3)
    assert log.pad_altitude == pytest.approx(2542.31 * FOOT - 1.31445 * FOOT, abs=1.0)
    assert log.pressure[0] == pytest.approx(0.91148 * 101325.0, rel=1e-4)
    assert log.temperature[0] == pytest.approx((41.1 - 32.0) / 1.8 + 273.15, abs=0.05)
    assert log.touchdown_time is not None and log.touchdown_time > log.phases.apogee_time + 30.0


def test_an_eggtimer_log_reads_ms_and_feet_and_stops_in_the_air():
    """Skyward's Lynx, EuRoC 2021 (SOURCES.md): ``T`` in ms, ``Alt`` in ft; apogee 10094 ft in the full log at
    23.15 s (its Apogee marker); the log stops at 93.8 s in the air (a last row of zeros): no touchdown, the descent
    to the log's end."""
    log = read_flight_log(LOGS / "eggtimer_lynx_euroc21_every5th.csv")
    assert log.format == "Eggtimer" and log.time[1] - log.time[0] == pytest.approx(0.25)
    assert log.phases.apogee_height - log.phases.pad_level == pytest.approx(10094.0 * FOOT, rel=0.015)
    assert log.phases.apogee_time == pytest.approx(23.15, abs=0.5)
    assert log.touchdown_time is None and log.descent()[0][-1] == log.time[-1]


def test_eggtimer_markers_are_the_events(tmp_path):
    """The Eggtimer's event columns hold the altitude at the sample its channel fired (the excerpt's header); the
    first row's markers are not events."""
    header = (LOGS / "eggtimer_lynx_euroc21_every5th.csv").read_text().splitlines()[0]
    rows = [f"{50 * i},{a},0,0,0,0,0,{ap},0,{dr},{mn}" for i, (a, ap, dr, mn) in enumerate(
        [(0, 0, 9, 9)] + [(min(20 * i, 900), 0, 0, 0) for i in range(1, 60)] + [(900, 900, 0, 0), (895, 0, 895, 0)]
        + [(max(895 - 3 * i, 0), 0, 0, 0) for i in range(1, 400)])]
    rows[300] = rows[300].rsplit(",", 1)[0] + ",300"
    log = read_flight_log(_lines(tmp_path, header + "\n" + "\n".join(rows) + "\n"))
    assert log.events == {"apogee": pytest.approx(61 * 0.05), "main": pytest.approx(300 * 0.05)}


def test_a_cats_ground_station_record_gives_the_states_and_the_touchdown():
    """CATS ground station, ASAT at EuRoC 2023 (SOURCES.md): ``ts`` in deciseconds, two links' rows merged; the
    DROGUE and MAIN states are the events; the touchdown within 5 s of the TOUCHDOWN state."""
    path = LOGS / "cats_groundstation_asat_euroc23_every2nd.csv"
    log = read_flight_log(path)
    rows = np.array([line.split(",")[:7] for line in path.read_text().splitlines()[1:]], float)
    first = {state: rows[rows[:, 2] == state, 1].min() / 10.0 for state in (5, 6, 7)}
    assert log.format == "CATS" and log.events == {"apogee": pytest.approx(first[5]), "main": pytest.approx(first[6])}
    assert log.touchdown_time == pytest.approx(first[7], abs=5.0)
    assert log.phases.apogee_height - log.phases.pad_level == pytest.approx(2296.0, abs=10.0)
    assert log.latitude_deg is None   # no GNSS fix in this record


def test_a_cats_flight_info_export_reads_its_ts_in_ms():
    """CATS Vega flight info, ARIS Piccard at EuRoC 2021 (SOURCES.md): ``ts`` in ms since the board's start, the
    leading index column ignored; the early firmware's apogee of about 7500 m that its README warns of; the record
    ends 31 s after the apogee, in the air."""
    log = read_flight_log(LOGS / "cats_flight_info_piccard_euroc21_every20th.csv")
    assert log.format == "CATS" and log.time[1] - log.time[0] == pytest.approx(0.2)
    assert log.phases.apogee_height - log.phases.pad_level == pytest.approx(7480.0, rel=0.01)
    assert log.touchdown_time is None


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
