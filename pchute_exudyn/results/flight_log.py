"""A flight computer's log as it comes (``FlightLog``): the times, the heights above the pad and what they are, the
flight's phases (``physics.flight_phases``), robust descent rates over height bands, the descent from the apogee to
the touchdown, and what else the log records (pressure, temperature, GPS, the flight computer's own events).

``read_flight_log`` picks the reader by the file's first line (``results.log_formats``: AltOS, Blue Raven, Raven FIP,
Eggtimer, CATS, StratoLogger, generic) and refuses a log it cannot use in one line: an empty file, a header without
rows, text in a numeric column, times that go back, a height of unknown unit, a log that never rises, stops before
its apogee or never descends.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..physics.barometric import temperature_offset
from ..physics.flight_phases import (
    FlightPhaseError,
    Phases,
    band_descent_rate,
    flight_phases,
    theil_sen_slope,
    touchdown_index,
)
from . import log_formats
from .log_formats import BLUE_RAVEN, FOOT, HEIGHT_NAMES, HEIGHT_UNITS  # noqa: F401  (their home; read here too)

LANDING_FIT = 3.0
"""s: the samples the touchdown's time is extended from, and the rest level's (``FlightLog.touchdown_time``)."""
MIN_GPS_HEIGHT = 50.0
"""m above the pad: GPS samples lower are left out of the day's temperature (the ground's multipath)."""
MIN_GPS_FIXES = 50
"""GPS fixes at least for the day's temperature from the log."""


@dataclass(frozen=True)
class FlightLog:
    """One flight's record.

    Attributes
    ----------
    source : str
        The file it was read from.
    format : str
        The reader's name: "AltOS", "Blue Raven", "Raven FIP", "Eggtimer", "CATS", "StratoLogger" or "generic".
    time : ndarray
        s, increasing (the log's own zero).
    height : ndarray
        m, as the log gives it: above the pad (AltOS) or as its column says (the pad level: ``phases.pad_level``).
    kind : str
        "barometric" or "gps": what the heights are.
    pad_altitude : float or None
        m above sea level of the pad, where the log gives it.
    pressure : ndarray or None
        Pa, the barometer's reading at each time, where the log has it.
    temperature : ndarray or None
        K, at each time: the flight computer's own sensor inside the airframe (board, not ambient) in every named
        format (``results.log_formats``); in a generic CSV, whatever its ``temperature`` column is.
    latitude_deg, longitude_deg : ndarray or None
        degrees, the GPS fix at each time (nan before a fix), where the log has GPS.
    gps_altitude : ndarray or None
        m above sea level, the GPS altitude at each time (nan before a fix).
    events : dict
        ``{"apogee": s, "main": s}``: the times the flight computer fired its apogee (drogue) and main charges or
        entered those states, as far as the log records them.
    """

    source: str
    format: str
    time: np.ndarray = field(repr=False)
    height: np.ndarray = field(repr=False)
    kind: str = "barometric"
    pad_altitude: float | None = None
    pressure: np.ndarray | None = field(default=None, repr=False)
    temperature: np.ndarray | None = field(default=None, repr=False)
    latitude_deg: np.ndarray | None = field(default=None, repr=False)
    longitude_deg: np.ndarray | None = field(default=None, repr=False)
    gps_altitude: np.ndarray | None = field(default=None, repr=False)
    events: dict = field(default_factory=dict)

    @cached_property
    def phases(self) -> Phases:
        """The pad level, the launch and the apogee (``physics.flight_phases``), found once."""
        try:
            return flight_phases(self.time, self.height)
        except FlightPhaseError as exc:
            raise InputError(f"{self.source}: height: {exc}") from None

    @cached_property
    def touchdown_index(self) -> int | None:
        """Index of the touchdown (``physics.flight_phases.touchdown_index``: the running median of
        TOUCHDOWN_WINDOW s back on the pad's level or at rest), None when the log ends in the air."""
        return touchdown_index(self.time, self.height, self.phases)

    @cached_property
    def touchdown_time(self) -> float | None:
        """s (the log's clock) of the touchdown, or None when the log ends in the air: the line through the samples
        of the LANDING_FIT s before the touchdown sample (a Theil-Sen line) extended to the level the log comes to rest
        at (the median of its next LANDING_FIT s). The touchdown sample is the first within a few metres of that
        level, up to a second early under a main."""
        if self.touchdown_index is None:
            return None
        k = self.touchdown_index
        landed = float(self.time[k])
        before = (self.time >= landed - LANDING_FIT) & (self.time <= landed)
        after = (self.time >= landed) & (self.time <= landed + LANDING_FIT)
        if np.count_nonzero(before) < 5:
            return landed
        slope = theil_sen_slope(self.time[before], self.height[before])
        if not slope < 0.0:
            return landed
        intercept = float(np.median(self.height[before] - slope * self.time[before]))
        reached = (float(np.median(self.height[after])) - intercept) / slope
        return float(np.clip(reached, landed - LANDING_FIT, landed + LANDING_FIT))

    def descent(self, after: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """(time in s, height in m above the pad level) of the samples from ``after`` s past the apogee to the
        touchdown (to the log's end when it ends in the air): the pad samples before the launch and after the
        landing left out."""
        start = int(np.searchsorted(self.time, self.phases.apogee_time + after))
        stop = len(self.time) if self.touchdown_index is None else self.touchdown_index + 1
        return self.time[start:stop], self.height[start:stop] - self.phases.pad_level

    def gps_temperature_offset(self, ground_altitude: float | None = None) -> tuple[float, int] | None:
        """(K, samples): how much warmer than the standard atmosphere the day was, from the log's own GPS: the
        offset at which its barometric heights, read through the day, best match its GPS heights over the descent
        (``physics.barometric.temperature_offset``; samples MIN_GPS_HEIGHT above the pad with a fix, GPS heights
        above the median GPS altitude on the pad). The pad's standard height is the log's own reading, else
        ``ground_altitude`` (m). None for a log without GPS or barometer, or with fewer than MIN_GPS_FIXES fixes."""
        if self.gps_altitude is None or self.kind != "barometric":
            return None
        pad = self.gps_altitude[: self.phases.launch_index + 1]
        time, baro = self.descent()
        gps = self.gps_altitude[np.searchsorted(self.time, time)] - (np.nanmedian(pad) if np.isfinite(pad).any()
                                                                     else np.nan)
        fixed = np.isfinite(gps) & (baro > MIN_GPS_HEIGHT)
        standard = self.pad_altitude if self.pad_altitude is not None else ground_altitude
        if np.count_nonzero(fixed) < MIN_GPS_FIXES or standard is None:
            return None
        return temperature_offset(baro[fixed], gps[fixed], standard), int(np.count_nonzero(fixed))

    def descent_rate(self, low: float, high: float) -> tuple[float, int]:
        """(m/s, positive down; samples used) between ``low`` and ``high`` (m above the pad) after the apogee: the
        Theil-Sen slope of the samples there (``physics.flight_phases.band_descent_rate``)."""
        phases = self.phases
        return band_descent_rate(self.time, self.height, phases, phases.pad_level + low, phases.pad_level + high)


def read_flight_log(path) -> FlightLog:
    """The log at ``path`` (the formats of ``results.log_formats``), its launch and apogee found (so that a log that
    cannot be used is refused here). InputError in one line naming the file, the column and the value."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no such file; give the path of a flight log")
    with path.open(encoding="utf-8-sig", errors="replace") as handle:
        first = handle.readline().strip()
    log = FlightLog(str(path), **_reader(first)(path))
    log.phases   # noqa: B018  (found now: a log with no launch, apogee or descent is refused on reading)
    return log


def named_log_format(path) -> bool:
    """Whether the file at ``path`` is a flight computer's own export (a named format of ``results.log_formats``,
    told by its first line), not a generic CSV."""
    with Path(path).open(encoding="utf-8-sig", errors="replace") as handle:
        return _reader(handle.readline().strip()) is not log_formats.generic


def _reader(first: str):
    """The reader of a file whose first line is ``first``."""
    cells = [cell.strip() for cell in first.replace(";", ",").split(",")]
    if first.startswith("#version,serial,flight,"):
        return log_formats.altos
    if all(name in cells for name in BLUE_RAVEN):
        return log_formats.blue_raven
    if "bILBA" in cells and any(cell.startswith("Time@") for cell in cells):
        return log_formats.raven_fip
    if cells[:2] == ["T", "Alt"]:
        return lambda path: log_formats.eggtimer(path, ";" if ";" in first else ",")
    if first.startswith("link,ts[deciseconds],state,"):
        return log_formats.cats_ground_station
    if "ts" in cells and "height" in cells:
        return log_formats.cats_flight_info
    return log_formats.generic
