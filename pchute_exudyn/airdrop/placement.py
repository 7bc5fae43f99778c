"""Where a case's descent starts, as case keys: moving every body and confluence that has an initial position by one
offset (the release point), the aircraft's keys, and the start frame's site (latitude, longitude) both ways."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..case.files import load_merged
from ..case.overrides import apply_override, parse_override
from ..errors import InputError
from ..physics.planet import FlatPlanet


def merged_data(path, overrides: dict) -> dict:
    """The case file's merged keys (its ``extends`` chain) with ``overrides`` (dotted key -> value) applied."""
    origins: dict = {}
    data = load_merged(Path(path), origins)
    for key, value in overrides.items():
        apply_override(data, origins, key, value)
    return data


def parsed_overrides(entries) -> dict:
    """``--set`` entries ("key=value") as dotted key -> value, in order."""
    return dict(parse_override(entry) for entry in entries)


def initial_tables(data: dict) -> dict:
    """Dotted key prefix -> the ``initial`` table of every body and confluence that has one."""
    found = {}
    for name, body in data.get("bodies", {}).items():
        if isinstance(body, dict) and isinstance(body.get("initial"), dict):
            found[f"bodies.{name}.initial"] = body["initial"]
    for name, system in data.get("systems", {}).items():
        confluence = system.get("confluence") if isinstance(system, dict) else None
        if isinstance(confluence, dict) and isinstance(confluence.get("initial"), dict):
            found[f"systems.{name}.confluence.initial"] = confluence["initial"]
    return found


def moved(data: dict, east: float, north: float, up: float = 0.0) -> dict:
    """Overrides moving every initial position of ``data`` by (``east``, ``north``, ``up``) (m): the whole
    arrangement of the start keeps its shape (a static line's anchor is the vehicle's own)."""
    keys = {}
    for prefix, table in initial_tables(data).items():
        for key, shift in (("east", east), ("north", north), ("altitude", up)):
            if key == "altitude" and (shift == 0.0 or key not in table):   # east, north: always written
                continue
            keys[f"{prefix}.{key}"] = float(table.get(key, 0.0)) + shift
    return keys


def vehicle_start(data: dict, vehicle: str) -> tuple:
    """The vehicle's initial (east, north, altitude) (m) as the keys give them."""
    table = data["bodies"][vehicle]["initial"]
    return float(table.get("east", 0.0)), float(table.get("north", 0.0)), table.get("altitude")


def has_site(case, data: dict) -> bool:
    """Whether the case places its start on a planet's surface: an ellipsoid planet and [start] latitude_deg and
    longitude_deg both given (as a forecast's air needs them)."""
    start = data.get("start", {})
    return not isinstance(case.planet, FlatPlanet) and {"latitude_deg", "longitude_deg"} <= set(start)


def check_site(case, data: dict, flag: str) -> None:
    """InputError naming ``flag`` when the case has no site (``has_site``)."""
    if isinstance(case.planet, FlatPlanet):
        raise InputError(f"{flag}: case {case.source} flies over a flat planet, which has no latitude or longitude; "
                         "give the target as --target-east and --target-north (m)")
    if not has_site(case, data):
        raise InputError(f"{flag}: case {case.source} has no site ([start] latitude_deg, longitude_deg); add them "
                         "(`pchute new --latitude --longitude`) or give the target as --target-east and "
                         "--target-north (m)")


def site_to_local(start, latitude_deg: float, longitude_deg: float, altitude: float) -> tuple:
    """(east, north) (m) in ``start``'s frame (a ``StartFrame``) of the point at that latitude, longitude (deg) and
    geodetic altitude (m)."""
    local = start.axes.T @ (start.planet.cartesian(latitude_deg, longitude_deg, altitude) - start.origin)
    return float(local[0]), float(local[1])


def local_to_site(start, east: float, north: float, altitude: float) -> tuple:
    """(latitude, longitude) (deg) of the point ``east``, ``north`` (m) of ``start``'s frame at geodetic
    ``altitude`` (m)."""
    latitude, longitude, _ = start.planet.geodetic(start.to_planet(start.local_position(altitude, east, north)))
    return float(latitude), float((np.asarray(longitude) + 180.0) % 360.0 - 180.0)
