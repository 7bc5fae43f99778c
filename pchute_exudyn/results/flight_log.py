"""A flight computer's log as it comes (``FlightLog``): the times, the heights above the pad and what they are, the
flight's phases (``physics.flight_phases``) and robust descent rates over height bands.

Formats read (``read_flight_log``, by the file's first line):

* **AltOS** (Altus Metrum TeleMega, TeleMetrum, EasyMega, EasyMini; AltosUI's CSV export): a header line starting
  ``#version,serial,flight,``; ``time`` in s from boost, ``height`` the barometric height above the pad (m),
  ``altitude`` the barometric altitude above sea level (m; the GPS altitude, later in the row, has the same name and
  is not read), ``state_name`` text. A GPS record and a sensor record share a time stamp: the first row of each time
  is kept.
* **Blue Raven** (Featherweight; the Blue Raven app's CSV export, high or low rate): a header with
  ``Flight_Time_(s)``, ``Baro_Altitude_AGL_(feet)`` and ``Baro_Altitude_ASL_(feet)``, read in feet and converted;
  its clock, hex and flag columns are not read.
* **Generic**: any CSV ``pchute compare`` reads (``results.csv_dialects``) with a time column and a height column
  named ``height``, ``altitude``, ``agl`` or ``alt``, in m or ft as its unit says; a height without a unit is
  refused (feet and metres cannot be told apart).

Heights are barometric in both unless a generic column says ``gps``. Times that go back are refused in one line.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..physics.flight_phases import FlightPhaseError, Phases, band_descent_rate, flight_phases
from .csv_dialects import read_csv_columns

FOOT = 0.3048
"""m per international foot."""
HEIGHT_UNITS = {"m": 1.0, "ft": FOOT, "feet": FOOT}
BLUE_RAVEN = ("Flight_Time_(s)", "Baro_Altitude_AGL_(feet)", "Baro_Altitude_ASL_(feet)")
"""The columns a Featherweight Blue Raven export is read by (its header has them; heights in feet)."""
HEIGHT_NAMES = ("height", "altitude", "agl", "alt")
"""Names of a generic log's height column, in the order they are looked for (the first one present is read)."""


@dataclass(frozen=True)
class FlightLog:
    """One flight's record.

    Attributes
    ----------
    source : str
        The file it was read from.
    format : str
        "AltOS", "Blue Raven" or "generic".
    time : ndarray
        s, increasing (the log's own zero).
    height : ndarray
        m, as the log gives it: above the pad (AltOS) or as its column says (the pad level: ``phases.pad_level``).
    kind : str
        "barometric" or "gps": what the heights are.
    pad_altitude : float or None
        m above sea level of the pad, where the log gives it.
    """

    source: str
    format: str
    time: np.ndarray = field(repr=False)
    height: np.ndarray = field(repr=False)
    kind: str = "barometric"
    pad_altitude: float | None = None

    @cached_property
    def phases(self) -> Phases:
        """The pad level, the launch and the apogee (``physics.flight_phases``), found once."""
        try:
            return flight_phases(self.time, self.height)
        except FlightPhaseError as exc:
            raise InputError(f"{self.source}: {exc}") from None

    def descent_rate(self, low: float, high: float) -> tuple[float, int]:
        """(m/s, positive down; samples used) between ``low`` and ``high`` (m above the pad) after the apogee: the
        Theil-Sen slope of the samples there (``physics.flight_phases.band_descent_rate``)."""
        phases = self.phases
        return band_descent_rate(self.time, self.height, phases, phases.pad_level + low, phases.pad_level + high)


def read_flight_log(path) -> FlightLog:
    """The log at ``path`` (the formats of the module docstring). InputError in one line for a file no reader takes,
    a height of unknown unit, or times that go back."""
    path = Path(path)
    with path.open(encoding="utf-8-sig", errors="replace") as handle:
        first = handle.readline()
    if first.lstrip().startswith("#version,serial,flight,"):
        return _altos(path, first)
    if all(name in first for name in BLUE_RAVEN):
        return _blue_raven(path, first)
    return _generic(path)


def _increasing(path: Path, time: np.ndarray, *columns) -> tuple:
    """``time`` and ``columns`` with the repeats of a time stamp after its first row dropped; InputError when a time
    goes back."""
    steps = np.diff(time)
    if np.any(steps < 0.0):
        row = int(np.nonzero(steps < 0.0)[0][0]) + 2
        raise InputError(f"{path}: time goes back at data row {row} ({time[row - 2]:g} s, then {time[row - 1]:g} s): "
                         "a log's times must not decrease")
    keep = np.concatenate([[True], steps > 0.0])
    return (time[keep],) + tuple(column[keep] for column in columns)


def _named_columns(path: Path, kind: str, names: list, wanted: tuple) -> np.ndarray:
    """The ``wanted`` columns (by their first index in the header ``names``) of every data row of ``path`` as floats,
    the other cells (text, hex) left alone. InputError naming the missing column or the row that is not a number."""
    missing = [name for name in wanted if name not in names]
    if missing:
        raise InputError(f"{path}: a {kind} log needs the column {missing[0]!r}; its header has "
                         f"{', '.join(names[:12])}...")
    where = [names.index(name) for name in wanted]
    rows = []
    with path.open(encoding="utf-8-sig", errors="replace") as handle:
        next(handle)
        for number, line in enumerate(handle, start=2):
            cells = line.split(",")
            if len(cells) <= max(where):
                continue   # a blank or cut-off last line
            try:
                rows.append([float(cells[index]) for index in where])
            except ValueError:
                raise InputError(f"{path}: row {number}: {', '.join(wanted)} must be numbers "
                                 f"({line.strip()[:60]!r})") from None
    return np.array(rows, float).reshape(-1, len(wanted))


def _altos(path: Path, header: str) -> FlightLog:
    names = [name.strip() for name in header.lstrip().lstrip("#").split(",")]
    data = _named_columns(path, "AltOS", names, ("time", "height", "altitude"))
    time, height, altitude = _increasing(path, data[:, 0], data[:, 1], data[:, 2])
    return FlightLog(str(path), "AltOS", time, height, "barometric", float(np.median(altitude - height)))


def _blue_raven(path: Path, header: str) -> FlightLog:
    names = [name.strip() for name in header.split(",")]
    data = _named_columns(path, "Blue Raven", names, BLUE_RAVEN)
    time, above, sea = _increasing(path, data[:, 0], data[:, 1] * FOOT, data[:, 2] * FOOT)
    return FlightLog(str(path), "Blue Raven", time, above, "barometric", float(np.median(sea - above)))


def _generic(path: Path) -> FlightLog:
    columns, units, _ = read_csv_columns(path)
    lowered = {name.lower(): name for name in columns}
    time_name = lowered.get("time") or lowered.get("t")
    height_name = next((lowered[name] for name in HEIGHT_NAMES if name in lowered), None)
    if time_name is None or height_name is None:
        raise InputError(f"{path}: a flight log needs a time column and a height column (one of "
                         f"{', '.join(HEIGHT_NAMES)}); its columns are {', '.join(columns)}")
    unit = units.get(height_name, "").lower()
    if unit not in HEIGHT_UNITS:
        raise InputError(f"{path}: the height column {height_name!r} has unit {unit or 'none'!r}: say m or ft in "
                         f"its header (e.g. '{height_name} (ft)'); feet and metres cannot be told apart")
    time, height = _increasing(path, np.asarray(columns[time_name], float),
                               np.asarray(columns[height_name], float) * HEIGHT_UNITS[unit])
    return FlightLog(str(path), "generic", time, height, "gps" if "gps" in height_name.lower() else "barometric")
