"""A run on a map: its start point, every body's ground track and the vehicle's touchdown (or last) point, from the
run's own latitude and longitude columns (``registries.columns``); ``map_files`` and ``map_page`` write it.

Layers: ``site`` (the case's ``[start]`` latitude and longitude: the origin of east and north), ``track`` (each
body's latitude and longitude, the vehicle first), ``landing`` (the vehicle's last sample when the run ended at
touchdown) or ``end`` (its last sample when the run ended at its duration).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import InputError
from ..physics.planet import Planet, StartFrame
from ..registries.columns import column, owner
from .io import FILES_KEY, RESULT_MARKER, atomic_write_text, json_text, result_files
from .map_files import GeoMap, MapLayer, MapLine, MapPoint
from .map_page import write_map_files
from .result import Result, read_summary

MAP_STEM = "map"
"""A run's or a study's map files: ``map.kml``, ``map.geojson``, ``map.gpx``, ``map.html``."""


def on_earth(site: dict | None) -> bool:
    """Whether a ``RunSummary.site`` is on the Earth (a map may draw the Earth's tiles under it)."""
    return isinstance(site, dict) and str(site.get("planet", "")).strip().lower() == "earth"


def site_point(site: dict, name: str = "start point") -> MapPoint:
    """The start point of a ``RunSummary.site`` as a map point."""
    return MapPoint(name, site["latitude_deg"], site["longitude_deg"],
                    f"the case's [start] latitude_deg {site['latitude_deg']:g}, longitude_deg "
                    f"{site['longitude_deg']:g} on {site['planet']}: the origin of east and north")


def ground_places(site: dict, east, north, altitude: float) -> tuple:
    """Geodetic latitudes and longitudes (deg) of the points ``east``, ``north`` (m, along the start point's axes, as
    a run's columns give them) at ``altitude`` (m above the reference ellipsoid) of the run whose start point is
    ``site`` (``RunSummary.site``): the start frame rebuilt from the planet's semi-axes (its gravity plays no part)."""
    planet = Planet(1.0, site["equatorial_radius"], site["polar_radius"], name=site["planet"])
    frame = StartFrame(planet, site["latitude_deg"], site["longitude_deg"])
    local = np.array([frame.local_position(altitude, e, n) for e, n in zip(east, north)])
    latitude, longitude, _ = planet.geodetic(frame.to_planet(local))
    return latitude, longitude


def _bodies(result: Result) -> list:
    """The run's bodies with a latitude column, the vehicle first (a body has attitude columns, a confluence not)."""
    found = [owner(name, "{owner}_latitude") for name in result.names]
    bodies = [name for name in found if name is not None and column("{owner}_tilt_deg", name) in result]
    return sorted(bodies, key=lambda name: name != result.vehicle)


def run_map(result: Result, title: str | None = None) -> GeoMap:
    """The map of a run (module docstring); InputError when the run has no latitude column (a flat planet's run, or
    one saved before they were written)."""
    vehicle = result.vehicle
    latitude, longitude = column("{owner}_latitude", vehicle), column("{owner}_longitude", vehicle)
    if latitude not in result or longitude not in result:
        raise InputError(f"the run has no {latitude} column: a run on a flat planet has no latitude and longitude, "
                         "and a run saved by an earlier version has none (rerun the case)")
    summary = result.summary
    site = getattr(summary, "site", None)
    tracks = []
    for body in _bodies(result) or [vehicle]:
        tracks.append(MapLine(f"{body} track", result[column("{owner}_latitude", body)],
                              result[column("{owner}_longitude", body)], f"{body}'s centre of mass over the ground",
                              altitudes=result[column("{owner}_altitude", body)],
                              heights=result[column("{owner}_height", body)]))
    landed = getattr(summary, "end", None) == "touchdown"
    end = MapLayer("landing" if landed else "end", (_last_place(result, landed),))
    layers = ([MapLayer("site", (site_point(site),))] if site else []) + [MapLayer("track", lines=tuple(tracks)), end]
    name = title or getattr(summary, "case", None) or "run"
    return GeoMap(name, tuple(layers), f"{name}: {getattr(summary, 'method', '')} run, {len(result.time)} samples",
                  earth=on_earth(site), **planet_radius(site))


def _last_place(result: Result, landed: bool) -> MapPoint:
    """The vehicle's last sample with a place: its touchdown (``landed``) or where the run ended."""
    vehicle = result.vehicle
    latitude, longitude = (result[column(t, vehicle)] for t in ("{owner}_latitude", "{owner}_longitude"))
    finite = np.flatnonzero(np.isfinite(latitude) & np.isfinite(longitude))
    last = int(finite[-1]) if len(finite) else -1
    east, north, altitude = (float(result[column(t, vehicle)][last])
                             for t in ("{owner}_east", "{owner}_north", "{owner}_altitude"))
    return MapPoint("touchdown" if landed else "end of the run", float(latitude[last]), float(longitude[last]),
                    f"{vehicle} at t = {result.time[last]:.3f} s: {east:.1f} m east, {north:.1f} m north of the start "
                    "point", altitude)


def planet_radius(site: dict | None) -> dict:
    """``GeoMap``'s ``radius`` (m) of a ``RunSummary.site``: its planet's equatorial radius ({} without a site)."""
    return {"radius": float(site["equatorial_radius"])} if isinstance(site, dict) else {}


def write_run_map(folder, out=None) -> list:
    """Write the map files (``MAP_STEM``) of the run in result folder ``folder`` into ``out`` (default the folder
    itself, where its summary.json then lists them among the run's files, so that a later run replacing the result
    replaces them too); returns their paths."""
    folder = Path(folder)
    try:
        geo_map = run_map(Result.load(folder))
    except InputError as exc:
        raise InputError(f"{folder}: {exc}") from None
    paths = write_map_files(geo_map, Path(out) if out is not None else folder, MAP_STEM)
    if out is None or Path(out).resolve() == folder.resolve():
        _list_files(folder, [p.name for p in paths])
    return paths


def _list_files(folder: Path, names: list) -> None:
    """Add ``names`` to the files the result folder's summary.json lists (``io.result_files``)."""
    listed = result_files(folder)
    if listed is None:
        raise InputError(f"{folder}: not a result folder of `pchute run` (its {RESULT_MARKER} lists no files)")
    summary = read_summary(folder)
    written = listed + [name for name in names if name not in listed]
    atomic_write_text(folder / RESULT_MARKER, json_text({**summary, FILES_KEY: written}, indent=2) + "\n")

