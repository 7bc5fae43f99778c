"""The day's air from a radiosonde sounding: the University of Wyoming's text listing (weather.uwyo.edu, "Text:
List"), as ``[atmosphere] model = "sounding"`` reads it.

The listing is a header (station, time), a ruled table head naming the columns and their units (PRES hPa, HGHT m,
TEMP C, DWPT C, RELH %, MIXR g/kg, DRCT deg, SKNT knot, THTA, THTE, THTV K), then one level per line in fixed
seven-character fields; a field can be blank. Read:

* **the air** at every level with a pressure, a height and a temperature: its density from the moist air's state
  (``physics.barometric.moist_air_density``; a blank mixing ratio counts as dry air), its temperature;
* **the wind** at every level with a height, a direction and a speed: east and north (m/s) of the wind coming from
  DRCT at SKNT knots (``physics.wind.wind_from_direction``);
* **the heights**: HGHT is geopotential (m' above sea level), converted to geometric altitude
  (``physics.barometric.geometric_altitude``);
* **below the station** (``sounding_air``): the lowest level's air continued down at the standard lapse, to
  UNDERGROUND.

A listing whose head differs, a field that is not a number, heights that do not rise or fewer than two usable levels
are refused in one line naming the file, the line and the value.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import CaseError
from ..physics.atmosphere import TabulatedAtmosphere, Wind
from ..physics.barometric import geometric_altitude, lapse_layer, moist_air_density
from ..physics.wind import wind_from_direction

COLUMNS = ("PRES", "HGHT", "TEMP", "DWPT", "RELH", "MIXR", "DRCT", "SKNT")
"""The leading columns of a listing, in order (the potential temperatures after them are not read)."""
UNITS = ("hPa", "m", "C", "C", "%", "g/kg", "deg", "knot")
FIELD = 7
"""Characters per field."""
KNOT = 1852.0 / 3600.0
"""m/s per knot."""
UNDERGROUND = (-500.0, 100.0)
"""m: the air table reaches from this altitude below sea level up to the station in steps of this size, the
station's air continued down at the standard lapse (``physics.barometric.lapse_layer``). A run never flies below
its ground, but its step control asks the air at every body's place, a packed canopy's included (at the start
frame's origin, sea level, until it deploys)."""


@dataclass(frozen=True)
class Sounding:
    """A sounding's air and wind, altitudes in m above sea level (geometric), strictly increasing.

    Attributes
    ----------
    source, station : str
        The file and its first line (station and time).
    altitude, pressure, temperature, density : ndarray
        m, Pa, K, kg/m^3 at the levels with a temperature.
    wind_altitude, east, north : ndarray
        m and m/s (air moving east and north) at the levels with a wind.
    """

    source: str
    station: str
    altitude: np.ndarray
    pressure: np.ndarray
    temperature: np.ndarray
    density: np.ndarray
    wind_altitude: np.ndarray
    east: np.ndarray
    north: np.ndarray


def read_wyoming_sounding(path) -> Sounding:
    """The sounding at ``path`` (module docstring); CaseError naming the file, the line and the value."""
    path = Path(path)
    if not path.is_file():
        raise CaseError(str(path), "", "sounding file not found")
    lines = path.read_text(errors="replace").splitlines()
    head = next((i for i, line in enumerate(lines) if line.split()[:2] == ["PRES", "HGHT"]), None)
    if head is None:
        raise CaseError(str(path), "", "not a University of Wyoming sounding: no table head 'PRES   HGHT   TEMP ...' "
                                        "(the Text: List output of weather.uwyo.edu), nor an IGRA 2 "
                                        "data file (header records beginning '#' and the station's ID)")
    _check_head(path, lines, head)
    levels = [_fields(path, number + 1, line) for number, line in enumerate(lines[head + 3:], start=head + 3)
              if line.strip() and not line.startswith(("-", "<", "Station"))]
    rows = np.array(levels, float).reshape(-1, len(COLUMNS))
    station = lines[0].strip() if head > 0 else ""
    return _sounding(path, station, rows)


def _check_head(path: Path, lines: list, head: int) -> None:
    names, units = lines[head].split(), lines[head + 1].split() if head + 1 < len(lines) else []
    if tuple(names[:len(COLUMNS)]) != COLUMNS or tuple(units[:len(UNITS)]) != UNITS:
        raise CaseError(str(path), "", f"line {head + 1}: the table head must begin {' '.join(COLUMNS)} in "
                                       f"{' '.join(UNITS)} (University of Wyoming units); it is "
                                       f"{' '.join(names[:len(COLUMNS)])} in {' '.join(units[:len(UNITS)])}")


def _fields(path: Path, number: int, line: str) -> list:
    """The leading fields of one level (nan where blank)."""
    values = []
    for k, name in enumerate(COLUMNS):
        text = line[k * FIELD:(k + 1) * FIELD].strip()
        try:
            values.append(float(text) if text else np.nan)
        except ValueError:
            raise CaseError(str(path), "", f"line {number}, column {name}: {text!r} is not a number") from None
    return values


def _sounding(path: Path, station: str, rows: np.ndarray) -> Sounding:
    pressure, height, temperature, _, _, mixing, direction, speed = rows.T
    east, north = np.array([wind_from_direction(s * KNOT, d) for s, d in zip(speed, direction)], float).reshape(-1, 2).T
    return profile_sounding(str(path), station, height, pressure * 100.0, temperature + 273.15, mixing / 1000.0,
                            east, north, "HGHT")


def profile_sounding(source: str, station: str, height, pressure, temperature, mixing_ratio, east, north,
                     height_name: str = "height") -> Sounding:
    """The ``Sounding`` of levels given in SI, nan where a level lacks a value: ``height`` geopotential (m'),
    ``pressure`` (Pa), ``temperature`` (K), water-vapour ``mixing_ratio`` (kg/kg; nan: dry air), the wind ``east``
    and ``north`` (m/s). Every reader (a listing, an IGRA 2 file, a weather model's grid) ends here, so any profile
    becomes air and wind one way. CaseError naming ``source`` (and ``height_name``, the file's own name for the
    heights) when fewer than two levels are usable or the heights do not rise."""
    height, pressure, temperature, mixing, east, north = (np.asarray(column, float) for column in (
        height, pressure, temperature, mixing_ratio, east, north))
    air = np.isfinite(pressure) & np.isfinite(height) & np.isfinite(temperature)
    wind = np.isfinite(height) & np.isfinite(east) & np.isfinite(north)
    for usable, what in ((air, "a pressure, a height and a temperature"), (wind, "a height and a wind")):
        if np.count_nonzero(usable) < 2:
            raise CaseError(source, "", f"fewer than two levels with {what}: a sounding needs at least two")
        rising = np.diff(height[usable])
        if np.any(rising <= 0.0):
            at = float(height[usable][1:][rising <= 0.0][0])
            raise CaseError(source, "", f"{height_name} = {at:g} m does not rise above the level before it: a "
                                        "sounding's heights must increase")
    ratio = np.where(np.isfinite(mixing[air]), mixing[air], 0.0)
    return Sounding(source, station, geometric_altitude(height[air]), pressure[air], temperature[air],
                    moist_air_density(pressure[air], temperature[air], ratio), geometric_altitude(height[wind]),
                    east[wind], north[wind])


def sounding_air(sounding: Sounding, gamma: float, gas_constant: float) -> tuple:
    """(``TabulatedAtmosphere``, ``Wind``) of a sounding: its levels' density and temperature (the speed of sound
    from ``gamma`` (-) and ``gas_constant`` (J/(kg K))), continued below its lowest level to UNDERGROUND; its winds
    (held beyond its ends)."""
    lowest = float(sounding.altitude[0])
    below = np.arange(UNDERGROUND[0], lowest, UNDERGROUND[1])
    below = below[below < lowest - 1.0]
    _, temperature, density = lapse_layer(below - lowest, float(sounding.pressure[0]),
                                          float(sounding.temperature[0]))
    atmosphere = TabulatedAtmosphere(tuple(np.concatenate([below, sounding.altitude])),
                                     tuple(np.concatenate([density, sounding.density])), sounding.source,
                                     tuple(np.concatenate([temperature, sounding.temperature])), gamma, gas_constant)
    return atmosphere, Wind(tuple(sounding.wind_altitude), tuple(sounding.east), tuple(sounding.north))
