"""The day's air from a NOAA IGRA 2 sounding file (the Integrated Global Radiosonde Archive's "data" text, version
2.0 to 2.2), as ``[atmosphere] model = "sounding"`` reads it.

A file holds one station's soundings, each a header record and its levels in fixed columns (1-based, inclusive):

* **header**: ``#`` in 1, the station's ID 2-12, YEAR 14-17, MONTH 19-20, DAY 22-23, HOUR 25-26 (UTC, 99:
  unknown), RELTIME 28-31, NUMLEV 33-36 (the levels that follow), P_SRC 38-45, NP_SRC 47-54, LAT 56-62 and
  LON 64-71 (deg x 10000);
* **level**: LVLTYP1 1, LVLTYP2 2, ETIME 4-8, PRESS 10-15 (Pa), PFLAG 16, GPH 17-21 (geopotential m'), ZFLAG 22,
  TEMP 23-27 (0.1 deg C), TFLAG 28, RH 29-33 (0.1 %), DPDP 35-39 (the dew point's depression below the temperature,
  0.1 deg C), WDIR 41-45 (deg, where the wind comes from), WSPD 47-51 (0.1 m/s). -9999 is a missing value, -8888 one
  removed by the archive's quality checks.

Read into ``soundings.profile_sounding``: the air at the levels with a pressure, a height and a temperature (moist
where DPDP is given: ``physics.barometric.dewpoint_mixing_ratio``), the wind at the levels with a height, a direction
and a speed. The case picks a sounding by its nominal ``time`` (UTC); a file of one sounding needs none.
"""

from __future__ import annotations

from datetime import datetime
from pathlib import Path

import numpy as np

from ..errors import CaseError
from ..physics.barometric import dewpoint_mixing_ratio
from ..physics.wind import wind_from_direction
from .soundings import Sounding, profile_sounding

FIELDS = (("PRESS", 9, 15, 1.0), ("GPH", 16, 21, 1.0), ("TEMP", 22, 27, 0.1), ("DPDP", 34, 39, 0.1),
          ("WDIR", 40, 45, 1.0), ("WSPD", 46, 51, 0.1))
"""(name, first column, end column (0-based, exclusive), scale to Pa, m', deg C, deg C, deg, m/s) of the level
fields read."""
MISSING = (-9999, -8888)
"""Missing, and removed by quality assurance."""
LISTED = 6
"""Soundings' times named in a message."""
TIME_FORMAT = "%Y-%m-%dT%H"


def is_igra2(text: str) -> bool:
    """True when ``text`` begins as an IGRA 2 data file: a header record ('#', an 11-character ID, the year)."""
    first = next((line for line in text.splitlines() if line.strip()), "")
    return first.startswith("#") and len(first) >= 36 and first[13:17].isdigit()


def read_igra2_sounding(path, time: datetime | None = None) -> Sounding:
    """The sounding of ``path`` at ``time`` (UTC, to the hour; None: the file's only sounding); CaseError naming the
    file, the line and the value, or the soundings it holds."""
    path = Path(path)
    lines = path.read_text(errors="replace").splitlines()
    headers = [number for number, line in enumerate(lines) if line.startswith("#")]
    times = [_header_time(path, number, lines[number]) for number in headers]
    chosen = _choose(path, headers, times, time)
    header = lines[chosen]
    count = _integer(path, chosen, header, "NUMLEV", 32, 36)
    levels = lines[chosen + 1:chosen + 1 + count]
    if len(levels) != count or any(line.startswith("#") for line in levels):
        held = next((k for k, line in enumerate(levels) if line.startswith("#")), len(levels))
        raise CaseError(str(path), "", f"line {chosen + 1}: the sounding announces {count} levels (NUMLEV) but "
                                       f"{held} follow it: the file is cut short")
    rows = np.array([[_field(path, chosen + 1 + k, line, field) for field in FIELDS] for k, line in enumerate(levels)],
                    float).reshape(-1, len(FIELDS))
    rows = rows[np.argsort(rows[:, 1], kind="stable")]   # the height-only wind levels come after the others
    pressure, height, celsius, depression, direction, speed = rows.T
    temperature = _once_per_height(height, celsius + 273.15)
    mixing = dewpoint_mixing_ratio(pressure, temperature - depression)
    east, north = np.array([wind_from_direction(s, d) for s, d in zip(speed, direction)], float).reshape(-1, 2).T
    east = _once_per_height(height, east)   # north goes with it: a level needs both
    latitude = _integer(path, chosen, header, "LAT", 55, 62) / 1e4
    longitude = _integer(path, chosen, header, "LON", 63, 71) / 1e4
    when = times[headers.index(chosen)]
    station = (f"{header[1:12].strip()} at {when.strftime(TIME_FORMAT) if when else 'an unknown hour'} UTC "
               f"({latitude:.4f} N, {longitude:.4f} E)")
    return profile_sounding(str(path), station, height, pressure, temperature, mixing, east, north, "GPH")


def _once_per_height(height: np.ndarray, values: np.ndarray) -> np.ndarray:
    """``values`` with nan where a level repeats the height of the level with a value before it (a pressure level
    and a wind level of one height count once, the first)."""
    values = values.copy()
    given = np.flatnonzero(np.isfinite(height) & np.isfinite(values))
    values[given[1:][np.diff(height[given]) == 0.0]] = np.nan
    return values


def _choose(path: Path, headers: list, times: list, time: datetime | None) -> int:
    """The line number of the chosen sounding's header."""
    if not headers:
        raise CaseError(str(path), "", "holds no IGRA 2 sounding: no header record beginning '#'")
    listed = ", ".join(t.strftime(TIME_FORMAT) if t else "unknown hour" for t in times[:LISTED])
    held = f"{listed}{', ...' if len(times) > LISTED else ''}"
    if time is None:
        if len(headers) > 1:
            raise CaseError(str(path), "", f"holds {len(headers)} soundings ({held}): choose one with [atmosphere] "
                                           "time = \"YYYY-MM-DDTHH\" (UTC)")
        return headers[0]
    for number, when in zip(headers, times):
        if when == time:
            return number
    known = [t for t in times if t]
    span = f" from {min(known).strftime(TIME_FORMAT)} to {max(known).strftime(TIME_FORMAT)}" if known else ""
    raise CaseError(str(path), "", f"has no sounding at {time.strftime('%Y-%m-%dT%H:%M')} UTC: it holds "
                                   f"{len(headers)}{span} ({held})")


def _header_time(path: Path, number: int, line: str) -> datetime | None:
    """The sounding's nominal time (UTC), None when its hour is 99 (unknown)."""
    year, month, day, hour = (_integer(path, number, line, name, a, b) for name, a, b in (
        ("YEAR", 13, 17), ("MONTH", 18, 20), ("DAY", 21, 23), ("HOUR", 24, 26)))
    if hour == 99:
        return None
    try:
        return datetime(year, month, day, hour)
    except ValueError:
        raise CaseError(str(path), "", f"line {number + 1}: {line[13:26]!r} is not a date and hour "
                                       "(YEAR MONTH DAY HOUR)") from None


def _integer(path: Path, number: int, line: str, name: str, start: int, end: int) -> int:
    text = line[start:end].strip()
    try:
        return int(text)
    except ValueError:
        raise CaseError(str(path), "", f"line {number + 1}, {name} (columns {start + 1}-{end}): {text!r} is not an "
                                       "integer") from None


def _field(path: Path, number: int, line: str, field: tuple) -> float:
    """One level's value in its unit (nan when missing); ``number`` the line's index."""
    name, start, end, scale = field
    value = _integer(path, number, line, name, start, end)
    return np.nan if value in MISSING else value * scale
