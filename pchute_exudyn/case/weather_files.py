"""``[atmosphere]``'s weather files: which reader a file needs and the keys that choose within it.

``model = "sounding"`` reads a radiosonde sounding, a University of Wyoming listing (``case.soundings``) or a NOAA
IGRA 2 data file (``case.igra2``), told apart by their content; ``time`` picks one of an IGRA 2 file's soundings.
``model = "forecast"`` reads a weather model's netCDF grid (``case.forecasts``) at the start point, at ``time`` and
for ensemble ``member``. Each gives a ``soundings.Sounding``, which ``soundings.sounding_air`` makes the run's air and
wind.
"""

from __future__ import annotations

import re
from datetime import datetime
from pathlib import Path

from ..errors import CaseError
from .fields import Table
from .forecasts import read_forecast
from .igra2 import is_igra2, read_igra2_sounding
from .soundings import Sounding, read_wyoming_sounding

TIME_FORMATS = ("%Y-%m-%dT%H", "%Y-%m-%dT%H:%M")
"""``time``: UTC to the hour or the minute (a trailing 'Z' is allowed)."""
WYOMING_TIME = re.compile(r"at (\d\d)Z (\d\d) (\w{3}) (\d{4})")
"""A Wyoming listing's first line's time: 'Observations at 12Z 01 Jan 2016'."""


def read_weather(t: Table, model: str, site: tuple | None) -> Sounding:
    """The ``Sounding`` of ``[atmosphere]`` ``t``'s weather file for ``model`` ("sounding" or "forecast");
    ``site`` the start point's (latitude, longitude) in deg, None when the case does not give them."""
    file, time = t.string("file"), read_time(t)
    if model == "sounding":
        return read_sounding_file(file, time)
    if site is None:
        raise t.error("model", "a forecast's air is taken at the start point: give [start] latitude_deg and "
                               "longitude_deg (deg)", model)
    return read_forecast(file, site, time, read_member(t))


def read_time(t: Table) -> datetime | None:
    """``time`` (UTC), None when absent."""
    text = t.string("time", None)
    if text is None:
        return None
    for form in TIME_FORMATS:
        try:
            return datetime.strptime(text.removesuffix("Z"), form)
        except ValueError:
            continue
    raise t.error("time", "must be a UTC time \"YYYY-MM-DDTHH\" or \"YYYY-MM-DDTHH:MM\", e.g. \"2016-01-01T12\"",
                  text)


def read_member(t: Table) -> int | None:
    """``member``: an ensemble member's number (an integer >= 0; a whole float from a study's range), None when
    absent."""
    value = t.raw("member", None, "")
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value < 0 or value != int(value):
        raise t.error("member", "must be an ensemble member's number (an integer >= 0)", value)
    return int(value)


def read_sounding_file(path, time: datetime | None = None) -> Sounding:
    """A sounding file of either format (told by its content) at ``time`` (an IGRA 2 file's choice; a Wyoming
    listing's one sounding must be at it when given)."""
    path = Path(path)
    if not path.is_file():
        raise CaseError(str(path), "", "sounding file not found")
    with path.open(errors="replace") as handle:
        head = handle.read(200)
    if is_igra2(head):
        return read_igra2_sounding(path, time)
    sounding = read_wyoming_sounding(path)
    if time is not None and _wyoming_time(sounding.station) != time:
        raise CaseError(str(path), "", f"time {time:%Y-%m-%dT%H:%M} UTC: the listing holds one sounding, "
                                       f"{sounding.station!r}; leave time out or give its time")
    return sounding


def _wyoming_time(station: str) -> datetime | None:
    found = WYOMING_TIME.search(station)
    try:
        return datetime.strptime(" ".join(found.groups()), "%H %d %b %Y") if found else None
    except ValueError:
        return None
