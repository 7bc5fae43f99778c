"""The day's air from a weather model's grid: a forecast (GFS) or a reanalysis (ERA5) on pressure levels in a netCDF
file, as ``[atmosphere] model = "forecast"`` reads it (through xarray, imported only here and only then).

The grid's coordinates and fields are found by name, their units by their ``units`` attributes:

* coordinates: latitude (``latitude``, ``lat``), longitude (``longitude``, ``lon``; 0..360 or -180..180), the
  pressure level (``pressure_level``, ``isobaricInhPa``, ``level``, ``lev``, ``plev``, ``isobaric``; hPa or Pa), the
  time (``valid_time``, then ``time``: a dimension, a coordinate along one, e.g. cfgrib's ``step``, or a single
  value), the ensemble member (``number``, ``ensemble``, ``member``, ``realization``, ``ens``);
* fields: the height as geopotential (m^2/s^2, divided by g0 = 9.80665 m/s^2: ERA5's ``z``) or geopotential height
  (gpm or m: GFS's ``gh``), the temperature (K), the wind east and north (m/s).

At the case's start point and time each field is interpolated on every level: bilinearly in latitude and longitude
between the four grid points around the site, linearly in time between the two times around it; an ensemble file's
``member`` is chosen first. The levels then go through ``soundings.profile_sounding`` as a radiosonde's do: the
geopotential heights become geometric altitudes, the density is p / (R T) (dry air: the files carry no humidity).

A file that is no netCDF, a field or coordinate missing or in units other than these (or with values that do not fit
them, e.g. deg C labelled K), a site outside the grid or a time outside the file are refused in one line naming the
file, what is wrong and what is allowed.
"""

from __future__ import annotations

import importlib.util
from datetime import datetime
from pathlib import Path

import numpy as np

from ..errors import CaseError
from ..physics.atmosphere import US76_G0
from ..physics.barometric import pressure_altitude
from .soundings import Sounding, profile_sounding

COORDINATES = {"latitude": ("latitude", "lat"), "longitude": ("longitude", "lon"),
               "level": ("pressure_level", "isobaricInhPa", "level", "lev", "plev", "isobaric"),
               "time": ("valid_time", "time"), "member": ("number", "ensemble", "member", "realization", "ens")}
"""The names each coordinate goes by, in the order they are looked for."""
FIELDS = {"height": ("z", "gh", "hgt", "geopotential", "hgtprs"), "temperature": ("t", "tmp", "air", "tmpprs"),
          "east": ("u", "ugrd", "uwnd", "ugrdprs"), "north": ("v", "vgrd", "vwnd", "vgrdprs")}
"""The names each field goes by (ERA5, GFS through cfgrib, NCEP reanalysis, GFS through OPeNDAP)."""
GEOPOTENTIAL = ("m2s-2", "m2/s2")
GEOPOTENTIAL_HEIGHT = ("gpm", "m", "gpmeter", "gpmeters", "geopotentialmeters")
KELVIN = ("k", "kelvin", "degk", "degreesk")
METRES_PER_SECOND = ("ms-1", "m/s", "meters/second", "metres/second", "meter/second", "metre/second")
LEVEL_SCALE = {"hpa": 100.0, "mb": 100.0, "mbar": 100.0, "millibar": 100.0, "millibars": 100.0, "pa": 1.0}
"""Pa per unit of the pressure levels."""
UNITS = {"height": ("m**2 s**-2 (geopotential) or gpm (geopotential height)", GEOPOTENTIAL + GEOPOTENTIAL_HEIGHT),
         "temperature": ("K", KELVIN), "east": ("m s**-1", METRES_PER_SECOND), "north": ("m s**-1", METRES_PER_SECOND)}
TEMPERATURE_RANGE = (150.0, 350.0)
"""K: a weather model's temperatures between the ground and the stratosphere lie within this."""
HEIGHT_SLACK = 3000.0
"""m: a level's geopotential height lies within this of its pressure's standard height (below 11 km); a unit error
(geopotential read as height, a factor 9.8) does not."""
TROPOPAUSE_PRESSURE = 22632.0
"""Pa: the standard pressure at 11 km, the top of the layer ``pressure_altitude`` holds for."""
LISTED = 6
"""Times or members named in a message."""


def read_forecast(path, site: tuple, time: datetime | None, member) -> Sounding:
    """The profile of the weather file ``path`` at ``site`` ((latitude, longitude) deg), ``time`` (UTC; None: the
    file's only time) and ensemble ``member`` (None: the file's only one), as a Sounding (module docstring)."""
    path = Path(path)
    grid = _open(path)
    try:
        names = {kind: _coordinate(grid, kind) for kind in COORDINATES}
        for kind in ("latitude", "longitude", "level"):
            if names[kind] is None:
                raise _error(path, f"has no {kind} coordinate (named {', '.join(COORDINATES[kind])}); its "
                                   f"coordinates are: {', '.join(map(str, grid.coords)) or 'none'}")
        fields = {kind: _field_name(path, grid, kind) for kind in FIELDS}
        levels = _levels(path, grid[names["level"]])
        selection, weights, label = _corners(path, grid, names, site, time, member)
        values = {kind: _interpolated(path, grid[name], names, selection, weights) for kind, name in fields.items()}
        height = _height(path, grid[fields["height"]], values["height"], levels)
    finally:
        grid.close()
    _check_temperature(path, fields["temperature"], values["temperature"])
    order = np.argsort(-levels)   # the ground up
    station = f"{path.name} at {site[0]:.4f} N, {site[1]:.4f} E, {label}"
    return profile_sounding(str(path), station, height[order], levels[order], values["temperature"][order],
                            np.full(len(levels), np.nan), values["east"][order], values["north"][order],
                            "the geopotential height")


def _error(path: Path, message: str) -> CaseError:
    return CaseError(str(path), "", message)


def _open(path: Path):
    """The file as an xarray Dataset; one line when it is missing, no netCDF, or xarray or its netCDF backend is
    not installed."""
    if not path.is_file():
        raise _error(path, "weather file not found")
    with path.open("rb") as handle:
        head = handle.read(8)
    hdf5 = head.startswith(b"\x89HDF")
    if not (head.startswith(b"CDF") or hdf5):
        raise _error(path, "is not a netCDF file (it begins with neither 'CDF' nor the HDF5 signature of netCDF-4); "
                           "model = \"forecast\" reads a weather model's netCDF on pressure levels (convert a GRIB "
                           "file first, e.g. with cfgrib)")
    try:
        import xarray
    except ImportError:
        xarray = None
    if xarray is None or (hdf5 and not any(importlib.util.find_spec(m) for m in ("netCDF4", "h5netcdf"))):
        raise _error(path, "reading a netCDF weather file needs xarray and netCDF4: pip install "
                           "'pchute-exudyn[weather]'")
    try:
        return xarray.open_dataset(path)
    except Exception:   # any backend's complaint about the file: one line, not its traceback
        raise _error(path, "cannot be read as netCDF: the file may be cut short or damaged") from None


def _coordinate(grid, kind: str) -> str | None:
    return next((name for name in COORDINATES[kind] if name in grid.coords or name in grid.dims), None)


def _field_name(path: Path, grid, kind: str) -> str:
    name = next((name for name in FIELDS[kind] if name in grid.data_vars), None)
    if name is None:
        raise _error(path, f"has no {kind} field (named {', '.join(FIELDS[kind])}); its fields are: "
                           f"{', '.join(map(str, grid.data_vars)) or 'none'}")
    unit = _unit(grid[name].attrs.get("units"))
    allowed, units = UNITS[kind]
    if unit not in units:
        raise _error(path, f"field {name}: units {grid[name].attrs.get('units')!r} are not known; allowed: "
                           f"{allowed}")
    return name


def _unit(text) -> str:
    """A units attribute compared without spaces, case, '**', '^' or '.' ('m**2 s**-2' -> 'm2s-2')."""
    return "".join(str(text).lower().split()).replace("**", "").replace("^", "").replace(".", "")


def _levels(path: Path, coordinate) -> np.ndarray:
    """The pressure levels in Pa."""
    unit = _unit(coordinate.attrs.get("units"))
    if unit not in LEVEL_SCALE:
        raise _error(path, f"pressure level {coordinate.name}: units {coordinate.attrs.get('units')!r} are not "
                           "known; allowed: hPa, millibars, Pa")
    return np.atleast_1d(np.asarray(coordinate.values, float)) * LEVEL_SCALE[unit]


def _corners(path: Path, grid, names: dict, site: tuple, time: datetime | None, member) -> tuple:
    """({dimension: indices}, {dimension: weights}, the time and member as words) of the grid points around the
    site, the times around ``time`` and the chosen member."""
    for kind in ("latitude", "longitude"):
        if grid[names[kind]].ndim != 1:
            raise _error(path, f"its {kind} {names[kind]} is not one list of values (a regular latitude-longitude "
                               "grid is read, not a projected one)")
    latitude = np.atleast_1d(np.asarray(grid[names["latitude"]].values, float))
    longitude = np.atleast_1d(np.asarray(grid[names["longitude"]].values, float))
    east = site[1] % 360.0 if longitude.max() > 180.0 else (site[1] + 180.0) % 360.0 - 180.0
    inside = [_bracket(latitude, site[0]), _bracket(longitude, east)]
    if None in inside:
        raise _error(path, f"the start point ({site[0]:g} N, {site[1]:g} E) lies outside the file's grid: "
                           f"latitude {latitude.min():g} to {latitude.max():g} deg, longitude {longitude.min():g} "
                           f"to {longitude.max():g} deg")
    selection = {grid[names[kind]].dims[0]: index for kind, (index, _) in zip(("latitude", "longitude"), inside)}
    weights = {grid[names[kind]].dims[0]: weight for kind, (_, weight) in zip(("latitude", "longitude"), inside)}
    label = _time_corners(path, grid, names["time"], time, selection, weights)
    return selection, weights, label + _member(path, grid, names["member"], member, selection, weights)


def _bracket(coordinate: np.ndarray, value: float) -> tuple | None:
    """(two indices, their weights) of the points of ``coordinate`` (ascending or descending) around ``value``; one
    point of weight 1 when it sits on one; None when it lies outside."""
    if not coordinate.min() <= value <= coordinate.max():
        return None
    order = np.argsort(coordinate)
    ordered = coordinate[order]
    if len(ordered) == 1:
        return [int(order[0])], np.array([1.0])
    low = int(min(np.searchsorted(ordered, value, side="right") - 1, len(ordered) - 2))
    share = (value - ordered[low]) / (ordered[low + 1] - ordered[low])
    return [int(order[low]), int(order[low + 1])], np.array([1.0 - share, share])


def _time_corners(path: Path, grid, name: str | None, time: datetime | None, selection: dict, weights: dict) -> str:
    """Put the times around ``time`` into ``selection`` and ``weights``; the time in words."""
    if name is None:
        raise _error(path, f"has no time coordinate (named {', '.join(COORDINATES['time'])})")
    coordinate = grid[name]
    if not np.issubdtype(coordinate.dtype, np.datetime64) or coordinate.ndim > 1:
        raise _error(path, f"its time coordinate {name} is not a list of dates and times")
    times = np.atleast_1d(coordinate.values).astype("datetime64[s]")
    first, last = (np.datetime_as_string(t, unit="m") for t in (times.min(), times.max()))
    if time is None:
        if len(times) > 1:
            listed = ", ".join(np.datetime_as_string(t, unit="m") for t in times[:LISTED])
            raise _error(path, f"holds {len(times)} times from {first} to {last} UTC ({listed}"
                               f"{', ...' if len(times) > LISTED else ''}): choose one with [atmosphere] time = "
                               "\"YYYY-MM-DDTHH:MM\" (UTC)")
        time = times[0].astype(datetime)
    seconds = (times - np.datetime64("1970-01-01T00:00:00")).astype(float)
    around = _bracket(seconds, (np.datetime64(time, "s") - np.datetime64("1970-01-01T00:00:00")).astype(float))
    if around is None:
        raise _error(path, f"time {time:%Y-%m-%dT%H:%M} UTC is outside the file's times: {first} to {last} UTC")
    if coordinate.ndim == 1:
        selection[coordinate.dims[0]], weights[coordinate.dims[0]] = around
    return f"{time:%Y-%m-%dT%H:%M} UTC"


def _member(path: Path, grid, name: str | None, member, selection: dict, weights: dict) -> str:
    """Put the chosen ensemble member into ``selection``; the member in words ('' without an ensemble)."""
    coordinate = grid[name] if name is not None else None
    if coordinate is None or coordinate.ndim != 1:
        if member is not None:
            raise _error(path, f"has no ensemble members (no {', '.join(COORDINATES['member'])} dimension): leave "
                               "[atmosphere] member out")
        return ""
    values = [v.item() for v in np.asarray(coordinate.values)]
    listed = ", ".join(str(v) for v in values[:LISTED]) + (", ..." if len(values) > LISTED else "")
    if member is None and len(values) > 1:
        raise _error(path, f"holds {len(values)} ensemble members ({name} = {listed}): choose one with "
                           "[atmosphere] member = N (a study can vary it)")
    chosen = values[0] if member is None else member
    if chosen not in values:
        raise _error(path, f"has no ensemble member {member!r}: its members are {name} = {listed}")
    selection[coordinate.dims[0]], weights[coordinate.dims[0]] = [values.index(chosen)], np.array([1.0])
    return f", member {chosen}"


def _interpolated(path: Path, field, names: dict, selection: dict, weights: dict) -> np.ndarray:
    """The field on every level at the site, time and member: the weighted sum over the selected grid points."""
    level = field[names["level"]].dims[0] if names["level"] in field.coords and field[names["level"]].ndim else None
    wanted = [d for d in selection if d in field.dims]
    extra = [d for d in field.dims if d not in wanted and d != level and field.sizes[d] > 1]
    if level is None or extra:
        raise _error(path, f"field {field.name} is not on pressure levels at one time and member (its dimensions: "
                           f"{', '.join(map(str, field.dims))})")
    block = field.isel({d: selection[d] for d in wanted}).squeeze([d for d in field.dims if d not in wanted
                                                                  and d != level])
    values = np.asarray(block.transpose(*wanted, level).values, float)
    for dimension in wanted:   # contract the leading axis with its weights, one dimension after another
        values = np.tensordot(weights[dimension], values, axes=1)
    return values


def _height(path: Path, field, values: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """The levels' geopotential heights (m'), the geopotential divided by g0; refused when they are far from their
    pressures' standard heights."""
    height = values / US76_G0 if _unit(field.attrs.get("units")) in GEOPOTENTIAL else values
    low = (levels >= TROPOPAUSE_PRESSURE) & np.isfinite(height)
    far = np.abs(height[low] - pressure_altitude(levels[low])) > HEIGHT_SLACK
    if np.any(far):
        k = int(np.flatnonzero(far)[0])
        raise _error(path, f"field {field.name} gives {height[low][k]:.0f} m at {levels[low][k] / 100.0:g} hPa, "
                           f"where the standard atmosphere has {pressure_altitude(levels[low][k]):.0f} m: its units "
                           f"({field.attrs.get('units')!r}) do not fit its values (allowed: m**2 s**-2 for "
                           "geopotential, gpm for geopotential height)")
    return height


def _check_temperature(path: Path, name: str, values: np.ndarray) -> None:
    finite = values[np.isfinite(values)]
    if len(finite) and not (TEMPERATURE_RANGE[0] <= finite.min() and finite.max() <= TEMPERATURE_RANGE[1]):
        raise _error(path, f"field {name} runs from {finite.min():g} to {finite.max():g}, not temperatures in K "
                           f"({TEMPERATURE_RANGE[0]:g} to {TEMPERATURE_RANGE[1]:g} K): its units say K (deg C "
                           "labelled K?)")
