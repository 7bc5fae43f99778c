"""`pchute new` writes nothing its own run refuses, and reads no broken RocketPy export (issue 59, item 3):
contradictory options are refused; an implausible option is warned with the case reader's own range; the written
case is dry-run first (the reader, the run's plan, the flight to its first line stretch), and a case that run refuses
is one line naming the option, with nothing written; an export's rows are checked (time, finite and plausible values,
unit quaternions) and a bad row is one line naming the file, its line and its column."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from pchute_exudyn.case.plausible import range_of
from pchute_exudyn.cli import main
from pchute_exudyn.results import rocketpy_export
from tests.bad_input_harness import assert_one_line, run_bad_input
from tests.helpers import ROOT

ROCKET = ["--dual-deploy", "--planet", "earth", "--canopy-type", "flat_circular", "--mass", "21.31", "--diameter",
          "0.15", "--length", "2.5", "--drogue-drag-area", "1", "--main-drag-area", "10", "--main-height", "300",
          "--drogue-mass", "0.17", "--main-mass", "1.06", "--body-drag", "off", "--drogue-after-main", "cut",
          "--ground-elevation", "1400"]
"""The dual deploy of tests/integration/test_dual_deploy.py (RocketPy's descent: no body drag)."""
EXPORT = ROOT / "validation" / "rocketpy" / "dual_deploy_flight.csv"
APOGEE_LINE = 31
"""The export's line (from 1) of its first row past apogee (Vz <= 0): line 1 is its header."""


def _broken(tmp: Path, line: int, column: int, value: str, swap_time: bool = False) -> str:
    """EXPORT with the cell ``column`` (from 0) of ``line`` (from 1) set to ``value``; or, ``swap_time``, that line's
    time swapped with the next line's."""
    lines = EXPORT.read_text(encoding="utf-8").splitlines()
    cells = [line_text.split(",") for line_text in lines[line - 1:line + 1]]
    if swap_time:
        cells[0][0], cells[1][0] = cells[1][0], cells[0][0]
    else:
        cells[0][column] = value
    lines[line - 1:line + 1] = [",".join(row) for row in cells]
    path = tmp / "broken.csv"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return str(path)


def _zero_quaternion(tmp: Path) -> str:
    path = Path(_broken(tmp, APOGEE_LINE, 7, "0.000000"))
    lines = path.read_text(encoding="utf-8").splitlines()
    cells = lines[APOGEE_LINE - 1].split(",")
    cells[7:11] = ["0.000000"] * 4
    lines[APOGEE_LINE - 1] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return str(path)


def _edited(tmp: Path, edit) -> str:
    """EXPORT with ``edit(rows)`` applied to its lines split into cells (the header's first)."""
    rows = [line.split(",") for line in EXPORT.read_text(encoding="utf-8").splitlines()]
    edit(rows)
    path = tmp / "broken.csv"
    path.write_text("\n".join(",".join(row) for row in rows) + "\n", encoding="utf-8")
    return str(path)


def _without_latitude(rows) -> None:
    for row in rows:
        del row[11]


def _without_e3(rows) -> None:
    for row in rows:
        del row[10]


def _without_agl(rows) -> None:
    for row in rows:
        del row[13]


def _ground_at_6400_m(rows) -> None:   # every Altitude AGL 5000 m lower: Z - AGL the same on each row, AGL < 0
    for row in rows[1:]:
        row[13] = f"{float(row[13]) - 5000.0:.6f}"


REFUSED = [
    ("altitude beside height", lambda t: [*ROCKET, "--altitude", "3000", "--height", "2500"],
     "altitude = 3000.0: not with height (--height): the start is the ground's altitude plus the height"),
    ("an apogee lag past the main's height", lambda t: [*ROCKET, "--height", "2500", "--apogee-lag", "100"],
     "apogee_lag = 100.0 (--apogee-lag): the written case's run would fail "),
    ("an apogee lag of 1e6 s", lambda t: [*ROCKET, "--height", "2500", "--apogee-lag", "1e6"],
     "apogee_lag = 1000000.0 (--apogee-lag): the written case's run would refuse it: 1.00022e+06 s sampled every "
     "0.05 s is 4e+06 samples of 79 values, about 13 GB"),
    ("a climb out of the atmosphere", lambda t: [*ROCKET, "--height", "2500", "--velocity-up", "3000"],
     "velocity_up = 3000.0 (--velocity-up): the written case's run would fail "),
    ("a static line time of 1e6 s", lambda t: ["--release-airspeed", "50", "--static-line-time", "1e6"],
     "static_line_time = 1000000.0 (--static-line-time): the written case's run would refuse it: 1.00019e+06 s "
     "sampled every 0.02 s is 4e+06 samples of 51 values, about 8 GB"),
    ("line stretch after touchdown", lambda t: ["--release-airspeed", "50", "--static-line-time", "100"],
     "static_line_time = 100.0 (--static-line-time): the written case's run reaches the ground at 65.81 s, before "
     "the line stretch of main"),
    ("an all-zero quaternion", lambda t: [*ROCKET, "--from-rocketpy", _zero_quaternion(t)],
     f"broken.csv: line {APOGEE_LINE}, e0 = 0: with e1..e3 a quaternion of norm 0: an attitude needs norm 1"),
    ("two times swapped at apogee", lambda t: [*ROCKET, "--from-rocketpy", _broken(t, APOGEE_LINE - 1, 0, "",
                                                                                    swap_time=True)],
     f"broken.csv: line {APOGEE_LINE}, Time (s) = 14: time goes back (14 s after 14.5 s)"),
    ("a time glitch to 1000 s", lambda t: [*ROCKET, "--from-rocketpy", _broken(t, 6, 0, "1000.000000")],
     "broken.csv: line 7, Time (s) = 2.5: time goes back (2.5 s after 1000 s)"),
    ("an altitude of 1e300 m", lambda t: [*ROCKET, "--from-rocketpy", _broken(t, 8, 3, "1e300")],
     "broken.csv: line 8, Z (m) = 1e+300: must be within -50000..1e+07 (m) for this tool"),
    ("an altitude jump of 800 m at apogee", lambda t: [*ROCKET, "--from-rocketpy",
                                                       _broken(t, APOGEE_LINE - 1, 3, "4256.305276")],
     f"broken.csv: line {APOGEE_LINE - 1}, Z (m) = 4256.31: +802.182 m from line {APOGEE_LINE - 2} in 0.5 s, where "
     "Vz (m/s) gives +2.18178 m (its trapezoid); allowed: within 10 m + 20% of the change"),
    ("an AGL glitch of 900 m at apogee", lambda t: [*ROCKET, "--from-rocketpy",
                                                    _broken(t, APOGEE_LINE - 1, 13, "2956.305276")],
     f"broken.csv: line {APOGEE_LINE - 1}, Altitude AGL (m) = 2956.31: Z (m) - Altitude AGL (m) = 500 m here, 1400 m "
     "on line 2: the launch site's elevation must be the same on every row (within 1 m)"),
    ("an AGL below the ground", lambda t: [*ROCKET, "--from-rocketpy", _edited(t, _ground_at_6400_m)],
     "broken.csv: line 2, Altitude AGL (m) = -4000: below the ground; allowed: >= 0 m (within 1 m)"),
    ("a longitude without latitude", lambda t: [*ROCKET, "--from-rocketpy", _edited(t, _without_latitude)],
     "broken.csv: Longitude (°) without Latitude: a position needs both columns or neither"),
    ("a quaternion without e3", lambda t: [*ROCKET, "--from-rocketpy", _edited(t, _without_e3)],
     "broken.csv: e0, e1, e2 without e3: an attitude quaternion needs all four columns or none"),
]


@pytest.mark.parametrize("export", [EXPORT, EXPORT.with_name("descent.csv")], ids=["dual deploy", "descent"])
def test_rocketpys_own_exports_keep_their_altitude_steps_well_inside_the_tolerance(export):
    # the step check must not be near refusing a true RocketPy export: ΔZ against the trapezoid of Vz
    columns, _, _, _ = rocketpy_export.read_rows(export)
    rise = np.diff(columns["Z"])
    by_speed = 0.5 * (columns["Vz"][:-1] + columns["Vz"][1:]) * np.diff(columns["time"])
    absolute, relative = rocketpy_export.STEP_TOLERANCE
    assert np.max(np.abs(rise - by_speed) / (absolute + relative * np.abs(rise))) < 0.1   # 0.052 measured


@pytest.mark.parametrize("name, make_options, expected", REFUSED, ids=[entry[0] for entry in REFUSED])
def test_a_case_its_run_refuses_or_a_broken_export_is_one_line_and_nothing_written(name, make_options, expected,
                                                                                    tmp_path):
    code, err, seconds, touched = run_bad_input(lambda t: ["new", t / "r.toml", *make_options(t)], tmp_path)
    assert_one_line(code, err, expected, touched, seconds)
    assert code == 1 and not (tmp_path / "r.toml").exists()
    if name in FALLS:   # with no drag before the drogue, the rocket flies in vacuum until the run fails
        rise, speed, what = FALLS[name]
        failed = float(re.search(r"would fail ([\d.]+) s into its flight", err)[1])
        root = math.sqrt(speed**2 - 2.0 * G * rise)
        first = (speed - root) / G if speed > root else (speed + root) / G   # the first time it gets there
        assert failed == pytest.approx(first, abs=0.15), err
        assert what in err, err


G = 9.797
"""m/s^2: normal gravity near 3900 m at the equator (WGS-84), within 0.1 % to 86 km for these closed forms."""
FALLS = {"an apogee lag past the main's height": (-(2500.0 - 300.0), 0.0, "main_bridle (system main) over-stretched"),
         "a climb out of the atmosphere": (86000.0 - 3900.0, 3000.0, "is outside the US76 atmosphere")}
"""Refusal -> (the height gained when the run fails, m: the main's trigger height from apogee, or the atmosphere's
top from the start; the upward start speed, m/s; the engine's reason): the time of h = v t - g t^2 / 2."""


def test_an_implausible_option_is_warned_with_the_case_readers_range(tmp_path, capsys):
    key = "systems.drogue.deploy_trigger.lag"
    low, high = range_of(key).plausible
    path = tmp_path / "high.toml"
    assert main(["new", str(path), *ROCKET, "--body-drag", "on", "--height", "30000", "--apogee-lag", "65"]) == 0
    err = capsys.readouterr().err
    assert err == (f"pchute new: warning: apogee_lag = 65.0 (--apogee-lag) is implausible: outside {low:g}..{high:g} "
                   f"(s), the case reader's range of {key}\n")
    assert "lag = 65.0" in path.read_text()


def test_a_main_opening_over_hours_is_warned_with_the_case_readers_range(tmp_path, capsys):
    """The battery's --main-opening-time 1e4: the main never opened before touchdown (17.8 m/s instead of 5.4 m/s)."""
    key = "systems.main.drag_area_schedule.time"
    low, high = range_of(key).plausible
    assert main(["new", str(tmp_path / "slow.toml"), *ROCKET, "--main-opening-time", "1e4"]) == 0
    assert capsys.readouterr().err == (f"pchute new: warning: main_opening_time = 10000.0 (--main-opening-time) is "
                                       f"implausible: outside {low:g}..{high:g} (s), the case reader's range of {key}\n")


def test_an_export_without_its_ground_says_where_the_ground_is_put(tmp_path, capsys):
    """The battery's export without Altitude AGL: the ground went to 0 m without a word (1400 m too low)."""
    arguments = [a for a in ROCKET if a not in ("--ground-elevation", "1400")]
    assert main(["new", str(tmp_path / "g.toml"), *arguments, "--from-rocketpy", _edited(tmp_path, _without_agl)]) == 0
    assert ("the export has no 'Altitude AGL' column, so the ground is put at 0 m (the ellipsoid); give the launch "
            "site's with --ground-elevation") in capsys.readouterr().err
