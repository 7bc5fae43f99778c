"""The readers of each flight computer's log format (``results.flight_log`` picks one by the file's first line).

Each reader returns the fields of a ``FlightLog`` as a dict: ``time`` (s), ``height`` (m), ``kind`` ("barometric"
or "gps"), ``pad_altitude`` (m above sea level, or None) and, where the log has them, ``pressure`` (Pa),
``temperature`` (K), ``latitude_deg``, ``longitude_deg``, ``gps_altitude`` (m above sea level) and ``events``
(``{"apogee": s, "main": s}``: the flight computer's own deployment firings or state changes).

* **AltOS** (Altus Metrum TeleMega, TeleMetrum, EasyMega, EasyMini; AltosUI's CSV export, with or without GPS
  columns): header ``#version,serial,flight,...``; ``time`` s from boost, ``height`` barometric m above the pad,
  the first ``altitude`` barometric m above sea level, ``pressure`` Pa, ``temperature`` deg C (the barometer chip's,
  inside the airframe: board), GPS ``latitude``/``longitude`` and the second ``altitude`` (GPS, m above sea level;
  0 before a fix is read as missing). Events: the first ``state_name`` "drogue" (apogee) and "main". A GPS and a
  sensor record share a time stamp: the first row of each time is kept.
* **Blue Raven** (Featherweight; the app's CSV export): ``Flight_Time_(s)``, ``Baro_Altitude_AGL_(feet)``,
  ``Baro_Altitude_ASL_(feet)``, ``Baro_Press_(atm)``, ``Temperature_(F)`` (board); events: the first
  ``Apo_fired`` and ``Main_fired`` flags.
* **Raven FIP** (Featherweight Raven through the Featherweight Interface Program's CSV export): a ``Time@NAME``,
  ``NAME``, ``bILBA`` triple per channel, each on its own clock (a channel that has ended leaves two empty cells in
  the later rows); the heights are the channel
  ``[Altitude (Baro-Ft-AGL)]`` (ft), the pad from ``[Altitude (Baro-Ft-ASL)]``; ``Baro (Atm)`` and
  ``Temperature (F)`` (board) interpolated onto the heights' clock. The ``bILBA`` flags' last digit turns 1 at the
  Raven's apogee detection (the event "apogee"); the export has no flag for the main's firing.
* **Eggtimer** (Quantum, TRS, Proton: the flight data download): header ``T,Alt,Veloc,...`` (``,`` or ``;``);
  ``T`` in ms (s when its steps are under 1), ``Alt`` barometric ft above the pad (the Eggtimer's default unit; a
  unit the file does not say). Events: the first non-zero ``Drogue`` (else ``Apogee``) and ``Main`` markers after
  the first row.
* **CATS** (Control and Telemetry Systems' CATS Vega): its configurator's / log parser's flight-info export
  (columns ``ts``, ``height``: ``ts`` in ms, s when its steps are under 1; ``height`` m above the pad, the flight
  computer's estimate from its barometers and accelerometers), and its ground station's telemetry record
  (``link,ts[deciseconds],state,...,altitude[m],...``: two radio links' rows, merged in time order; events: the
  first ``state`` 5 (DROGUE: apogee) and 6 (MAIN), the flight states of cats-embedded ``flight_fsm_e``).
* **StratoLogger** (PerfectFlite; the ``time_s,altitude_ft,temperature,voltage`` layout): the generic reader, the
  board temperature's text (``76.7F``) read in K.
* **Generic**: a header with a time column (``time`` or ``t``) and a height column (``height``, ``altitude``,
  ``agl``, ``alt``), each with its unit in brackets (``altitude (ft)``) or after an underscore (``altitude_ft``);
  a height without a unit is refused (feet and metres cannot be told apart); ``#`` comment lines are skipped.

Heights are barometric unless a generic column's name says ``gps``.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from .csv_dialects import TIME_UNITS, split_unit

FOOT = 0.3048
"""m per international foot."""
ATMOSPHERE = 101325.0
"""Pa per standard atmosphere."""
HEIGHT_UNITS = {"m": 1.0, "ft": FOOT, "feet": FOOT}
HEIGHT_NAMES = ("height", "altitude", "agl", "alt")
"""Names of a generic log's height column, in the order they are looked for (the first one present is read)."""
BLUE_RAVEN = ("Flight_Time_(s)", "Baro_Altitude_AGL_(feet)", "Baro_Altitude_ASL_(feet)")
"""The columns a Featherweight Blue Raven export is read by (its header has them; heights in feet)."""
CATS_STATES = {5: "apogee", 6: "main"}
"""CATS flight states (cats-embedded ``flight_fsm_e``: 5 DROGUE, 6 MAIN) and the events their starts are."""
_TEMPERATURE = re.compile(r"^\s*([+-]?[\d.]+)\s*([CFK]?)\s*$", re.IGNORECASE)


def fahrenheit(values):
    """K from deg F."""
    return (np.asarray(values, float) - 32.0) / 1.8 + 273.15


class Table:
    """The header cells and the data rows (line number, cells) of a delimited text file."""

    def __init__(self, path: Path, names: list, rows: list):
        self.path, self.names, self.rows = path, names, rows

    def index(self, name: str, kind: str, occurrence: int = 0) -> int:
        found = [i for i, cell in enumerate(self.names) if cell == name]
        if len(found) <= occurrence:
            raise InputError(f"{self.path}: a {kind} log needs the column {name!r}; its header has "
                             f"{', '.join(self.names[:12])}...")
        return found[occurrence]

    def has(self, name: str) -> bool:
        return name in self.names

    def numbers(self, index: int, blank=None) -> np.ndarray:
        """Column ``index`` as floats; a blank cell is ``blank`` (None: an error), text an error naming the row."""
        values = []
        for number, cells in self.rows:
            cell = cells[index].strip() if index < len(cells) else ""
            if cell == "" and blank is not None:
                values.append(blank)
                continue
            try:
                values.append(float(cell))
            except ValueError:
                raise InputError(f"{self.path}: row {number}, column {self.names[index]!r}: {cell[:30]!r} is not a "
                                 "number; the column must be numeric") from None
        return np.array(values, float)

    def texts(self, index: int) -> list:
        return [cells[index].strip() if index < len(cells) else "" for _, cells in self.rows]

    def lines(self) -> np.ndarray:
        return np.array([number for number, _ in self.rows])


def read_table(path: Path, header_at: int = 0, delimiter: str = ",") -> Table:
    """The table whose header is line ``header_at`` (0-based) of ``path``; a last row cut short is dropped.
    InputError for an empty file or a header with no rows under it."""
    lines = path.read_text(encoding="utf-8-sig", errors="replace").splitlines()
    if not any(line.strip() for line in lines):
        raise InputError(f"{path}: the file is empty; a flight log needs a header row and data rows")
    names = [cell.strip() for cell in lines[header_at].lstrip().lstrip("#").split(delimiter)]
    rows = [(number, line.split(delimiter)) for number, line in enumerate(lines[header_at + 1:], start=header_at + 2)
            if line.strip() and not line.lstrip().startswith("#")]
    if rows and len(rows[-1][1]) < len(names) and len(rows) > 1 and len(rows[-2][1]) >= len(names):
        rows.pop()   # a log cut off mid-row by a power loss
    if not rows:
        raise InputError(f"{path}: the header ({lines[header_at].strip()[:50]!r}) has no data rows under it; a flight "
                         "log needs its samples")
    return Table(path, names, rows)


def in_time_order(path: Path, name: str, time: np.ndarray, lines: np.ndarray, columns: dict) -> tuple:
    """``time`` and ``columns`` with the repeats of a time stamp after its first row dropped; InputError naming the
    row when a time goes back."""
    steps = np.diff(time)
    if np.any(steps < 0.0):
        i = int(np.nonzero(steps < 0.0)[0][0])
        raise InputError(f"{path}: row {lines[i + 1]}, column {name!r}: time goes back ({time[i]:g} s, then "
                         f"{time[i + 1]:g} s); a log's times must not decrease")
    keep = np.concatenate([[True], steps > 0.0])
    return time[keep], {key: (value[keep] if value is not None else None) for key, value in columns.items()}


def first_time(time: np.ndarray, flags: np.ndarray, after: float = -np.inf) -> float | None:
    """The first time after ``after`` (s) at which ``flags`` is set, or None."""
    hits = np.nonzero((flags != 0) & (time > after))[0]
    return float(time[hits[0]]) if len(hits) else None


def _events(**times) -> dict:
    return {name: value for name, value in times.items() if value is not None}


def _time_unit(time: np.ndarray) -> float:
    """ms to s for a clock whose median step is 1 or more (a flight computer logs at 10 Hz or faster)."""
    steps = np.diff(time)
    return 1e-3 if len(steps) and np.median(steps) >= 1.0 else 1.0


def altos(path: Path) -> dict:
    table = read_table(path)
    time_at = table.index("time", "AltOS")
    time = table.numbers(time_at)
    height, altitude = (table.numbers(table.index(name, "AltOS")) for name in ("height", "altitude"))
    optional = {name: table.numbers(table.index(name, "AltOS")) if table.has(name) else None
                for name in ("pressure", "temperature", "latitude", "longitude")}
    gps = table.numbers(table.index("altitude", "AltOS", 1)) if optional["latitude"] is not None else None
    states = np.array(table.texts(table.index("state_name", "AltOS"))) if table.has("state_name") else None
    columns = dict(height=height, altitude=altitude, gps=gps, **optional)
    if states is not None:
        columns.update(drogue=(states == "drogue").astype(float), main=(states == "main").astype(float))
    time, kept = in_time_order(path, "time", time, table.lines(), columns)
    fix = None if gps is None else (kept["latitude"] != 0.0) | (kept["longitude"] != 0.0)
    events = {} if states is None else _events(apogee=first_time(time, kept["drogue"]),
                                                main=first_time(time, kept["main"]))
    return dict(format="AltOS", time=time, height=kept["height"], kind="barometric",
                pad_altitude=float(np.median(kept["altitude"] - kept["height"])), pressure=kept["pressure"],
                temperature=None if kept["temperature"] is None else kept["temperature"] + 273.15,
                latitude_deg=_where(fix, kept["latitude"]), longitude_deg=_where(fix, kept["longitude"]),
                gps_altitude=_where(fix, kept["gps"]), events=events)


def _where(fix, values):
    return None if fix is None else np.where(fix, values, np.nan)


def blue_raven(path: Path) -> dict:
    table = read_table(path)
    names = BLUE_RAVEN + ("Baro_Press_(atm)", "Temperature_(F)", "Apo_fired", "Main_fired")
    columns = {name: table.numbers(table.index(name, "Blue Raven")) if table.has(name) or name in BLUE_RAVEN
               else None for name in names}
    time, kept = in_time_order(path, BLUE_RAVEN[0], columns.pop(BLUE_RAVEN[0]), table.lines(), columns)
    above, sea = kept[BLUE_RAVEN[1]] * FOOT, kept[BLUE_RAVEN[2]] * FOOT
    flags = {name: kept[column] for name, column in (("apogee", "Apo_fired"), ("main", "Main_fired"))}
    return dict(format="Blue Raven", time=time, height=above, kind="barometric",
                pad_altitude=float(np.median(sea - above)),
                pressure=None if kept["Baro_Press_(atm)"] is None else kept["Baro_Press_(atm)"] * ATMOSPHERE,
                temperature=None if kept["Temperature_(F)"] is None else fahrenheit(kept["Temperature_(F)"]),
                events=_events(**{name: None if flag is None else first_time(time, flag)
                                  for name, flag in flags.items()}))


def raven_fip(path: Path) -> dict:
    table = read_table(path)
    names = [name[5:] for name in table.names if name.startswith("Time@")]
    samples = _fip_channels(table, names)

    def channel(name: str, needed: bool = True):
        if name not in samples:
            if needed:
                raise InputError(f"{path}: a Raven FIP export needs the channel {name!r}; it has "
                                 f"{', '.join(names[:8])}...")
            return None, None, None
        lines, time, values, flags = zip(*samples[name]) if samples[name] else ((), (), (), ())
        return np.array(lines), np.array(time, float), (np.array(values, float), np.array(flags))

    lines, time, (above, flags) = channel("[Altitude (Baro-Ft-AGL)]")
    time, kept = in_time_order(path, "Time@[Altitude (Baro-Ft-AGL)]", time, lines,
                               dict(above=above, apogee=np.char.endswith(flags.astype(str), "1").astype(float)))
    extras = {}
    for key, name, convert in (("sea", "[Altitude (Baro-Ft-ASL)]", lambda v: v * FOOT),
                               ("pressure", "Baro (Atm)", lambda v: v * ATMOSPHERE),
                               ("temperature", "Temperature (F)", fahrenheit)):
        _, at, found = channel(name, needed=False)
        extras[key] = None if at is None or len(at) < 2 else convert(np.interp(time, at, found[0]))
    above = kept["above"] * FOOT
    return dict(format="Raven FIP", time=time, height=above, kind="barometric",
                pad_altitude=None if extras["sea"] is None else float(np.median(extras["sea"] - above)),
                pressure=extras["pressure"], temperature=extras["temperature"],
                events=_events(apogee=first_time(time, kept["apogee"])))


def _fip_channels(table: Table, names: list) -> dict:
    """``{channel: [(line, time, value, flags), ...]}`` of a Raven FIP export: a row holds each channel's next sample
    as three cells (time, value, flags), or two empty cells once the channel has ended."""
    samples = {name: [] for name in names}
    for number, cells in table.rows:
        at = 0
        for name in names:
            if at >= len(cells) or cells[at].strip() == "":
                at += 2
                continue
            try:
                samples[name].append((number, float(cells[at]), float(cells[at + 1]), cells[at + 2].strip()))
            except (ValueError, IndexError):
                text = ",".join(cells[at:at + 3]).strip()
                raise InputError(f"{table.path}: row {number}, channel {name!r}: {text[:40]!r} is not a time, a "
                                 "number and its flags") from None
            at += 3
    return samples


def eggtimer(path: Path, delimiter: str) -> dict:
    table = read_table(path, delimiter=delimiter)
    raw = table.numbers(table.index("T", "Eggtimer"))
    markers = {name: table.numbers(table.index(name, "Eggtimer")) if table.has(name) else None
               for name in ("Apogee", "Drogue", "Main")}
    time, kept = in_time_order(path, "T", raw * _time_unit(raw), table.lines(),
                               dict(height=table.numbers(table.index("Alt", "Eggtimer")) * FOOT, **markers))
    after = time[0]   # the first row carries no event: nothing has flown
    fired = {name: None if kept[name] is None else first_time(time, kept[name], after) for name in markers}
    return dict(format="Eggtimer", time=time, height=kept["height"], kind="barometric",
                events=_events(apogee=fired["Drogue"] or fired["Apogee"], main=fired["Main"]))


def cats_flight_info(path: Path) -> dict:
    table = read_table(path)
    raw = table.numbers(table.index("ts", "CATS"))
    time, kept = in_time_order(path, "ts", raw * _time_unit(raw), table.lines(),
                               dict(height=table.numbers(table.index("height", "CATS"))))
    return dict(format="CATS", time=time, height=kept["height"], kind="barometric")


def cats_ground_station(path: Path) -> dict:
    table = read_table(path)
    names = ("ts[deciseconds]", "state", "lat[deg/10000]", "lon[deg/10000]", "altitude[m]")
    ts, state, lat, lon, altitude = (table.numbers(table.index(name, "CATS ground station")) for name in names)
    order = np.argsort(ts, kind="stable")   # the two links' rows interleave; each is a copy of one record
    time, kept = in_time_order(path, names[0], ts[order] * 0.1, table.lines()[order],
                               dict(state=state[order], lat=lat[order] * 1e-4, lon=lon[order] * 1e-4,
                                    height=altitude[order]))
    fix = (kept["lat"] != 0.0) | (kept["lon"] != 0.0)
    events = {name: first_time(time, (kept["state"] == code).astype(float)) for code, name in CATS_STATES.items()}
    return dict(format="CATS", time=time, height=kept["height"], kind="barometric",
                latitude_deg=np.where(fix, kept["lat"], np.nan) if fix.any() else None,
                longitude_deg=np.where(fix, kept["lon"], np.nan) if fix.any() else None, events=_events(**events))


def _unit_of(header: str) -> tuple[str, str]:
    """``"altitude (ft)"`` or ``"altitude_ft"`` -> ``("altitude", "ft")``; no unit -> ``(name, "")``."""
    name, unit = split_unit(header)
    if not unit and "_" in name:
        base, _, suffix = name.rpartition("_")
        if suffix.lower() in set(HEIGHT_UNITS) | set(TIME_UNITS) - {""}:
            return base, suffix.lower()
    return name, unit


def generic(path: Path) -> dict:
    lines = path.read_text(encoding="utf-8-sig", errors="replace").splitlines()
    if not any(line.strip() for line in lines):
        raise InputError(f"{path}: the file is empty; a flight log needs a header row and data rows")
    header_at, fields = _generic_header(path, lines)
    delimiter = next((d for d in (",", ";", "\t") if d in lines[header_at]), ",")
    table = read_table(path, header_at, delimiter)
    (time_at, time_unit), (height_at, height_unit) = fields
    height_name = _unit_of(table.names[height_at])[0]
    if height_unit.lower() not in HEIGHT_UNITS:
        raise InputError(f"{path}: the height column {table.names[height_at]!r} has unit {height_unit or 'none'!r}: "
                         f"say m or ft in its header (e.g. '{height_name} (ft)'); feet and metres cannot be told apart")
    if time_unit not in TIME_UNITS:
        raise InputError(f"{path}: the time column {table.names[time_at]!r} has unit {time_unit!r}: say one of "
                         f"{', '.join(u for u in TIME_UNITS if u)} (or none, seconds)")
    names = [_unit_of(cell)[0].lower() for cell in table.names]
    temperature = _temperatures(table, names.index("temperature")) if "temperature" in names else None
    time, kept = in_time_order(path, table.names[time_at], table.numbers(time_at) * TIME_UNITS[time_unit],
                               table.lines(), dict(height=table.numbers(height_at) * HEIGHT_UNITS[height_unit.lower()],
                                                   temperature=temperature))
    stratologger = [cell.lower() for cell in table.names] == ["time_s", "altitude_ft", "temperature", "voltage"]
    return dict(format="StratoLogger" if stratologger else "generic", time=time, height=kept["height"],
                kind="gps" if "gps" in height_name.lower() else "barometric", temperature=kept["temperature"])


def _generic_header(path: Path, lines: list) -> tuple[int, tuple]:
    """The first line naming a time column and a height column: (its index, ((time index, unit), (height index,
    unit)))."""
    for at, line in enumerate(lines):
        delimiter = next((d for d in (",", ";", "\t") if d in line), ",")
        parsed = [_unit_of(cell.strip()) for cell in line.lstrip().lstrip("#").split(delimiter)]
        lowered = [name.lower() for name, _ in parsed]
        time_at = next((i for i, name in enumerate(lowered) if name in ("time", "t")), None)
        height_at = next((lowered.index(name) for name in HEIGHT_NAMES if name in lowered), None)
        if height_at is None:
            height_at = next((i for i, name in enumerate(lowered) if "gps" in name and "alt" in name), None)
        if time_at is not None and height_at is not None:
            return at, ((time_at, parsed[time_at][1]), (height_at, parsed[height_at][1]))
    first = next(line for line in lines if line.strip())
    raise InputError(f"{path}: a flight log needs a time column and a height column (one of "
                     f"{', '.join(HEIGHT_NAMES)}); its first line is {first.strip()[:60]!r}")


def _temperatures(table: Table, index: int) -> np.ndarray | None:
    """K from cells like ``76.7F``, ``24.5C`` or the header's unit; None when a cell is not a temperature."""
    _, unit = _unit_of(table.names[index])
    values = []
    for text in table.texts(index):
        match = _TEMPERATURE.match(text)
        if not match:
            return None
        value, letter = float(match[1]), (match[2] or unit or "C").upper()
        values.append(fahrenheit(value) if letter == "F" else value + (0.0 if letter == "K" else 273.15))
    return np.array(values, float)
