"""A release point on a map (``pchute release-point`` on a case with a site): the target, the release point, the
solve's last run from release to landing, and, after a Monte Carlo, its touchdown points and dispersion ellipses;
written as ``map.kml``, ``map.geojson``, ``map.gpx`` and ``map.html`` beside ``release_point.json``
(``results.map_page``). A case without a site (no [start] latitude and longitude, or a flat planet) gets no map.

East and north (m, the start frame) become latitude and longitude through the release case's start frame
(``results.run_map.ground_places``) on the ground (``simulation.ground_altitude``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..case.loader import load_case
from ..results.map_files import GeoMap, MapLayer, MapLine, MapPoint
from ..results.map_page import write_map_files
from ..results.run_map import MAP_STEM, ground_places, on_earth, planet_radius
from ..results.summary import site_of
from ..study.maps import ellipse_outlines


def write_release_map(folder: Path, release, footprint=None) -> list:
    """Write the map files of ``release`` (a ``ReleasePoint``) and ``footprint`` (a ``Footprint`` or None) into
    ``folder``, which holds the release case; returns their paths (none when the case has no site)."""
    if release.latitude_deg is None:
        return []
    case = load_case(Path(folder) / "release_case.toml")
    site = site_of(case.start)
    if site is None:
        return []
    geo_map = release_map(release, footprint, site, case.simulation.ground_altitude)
    return write_map_files(geo_map, Path(folder), MAP_STEM)


def release_map(release, footprint, site: dict, ground: float) -> GeoMap:
    """The map (module docstring) of ``release`` and ``footprint`` over the start point ``site``
    (``RunSummary.site``), the ground at geodetic altitude ``ground`` (m)."""
    def place(east, north):
        lat, lon = ground_places(site, np.atleast_1d(east), np.atleast_1d(north), ground)
        return np.asarray(lat, float), np.asarray(lon, float)

    landing_east = release.release_east + release.drift_east
    landing_north = release.release_north + release.drift_north
    lat, lon = place([release.release_east, landing_east], [release.release_north, landing_north])
    layers = [MapLayer("target", (MapPoint("target", release.target_latitude_deg, release.target_longitude_deg,
                                           f"{release.target_east:.1f} m east, {release.target_north:.1f} m north of "
                                           "the start point", ground),)),
              MapLayer("release", (MapPoint("release point", release.latitude_deg, release.longitude_deg,
                                            f"release at {release.altitude:g} m, {release.airspeed:g} m/s on "
                                            f"heading {release.heading_deg:g} deg", release.altitude),)),
              MapLayer("track", lines=(MapLine("drift", tuple(lat), tuple(lon),
                                               f"release to landing: {release.drift_east:.1f} m east, "
                                               f"{release.drift_north:.1f} m north; miss {release.miss:.2f} m"),))]
    if footprint is not None and footprint.points:
        points = np.asarray(footprint.points, float)
        lat, lon = place(points[:, 0], points[:, 1])
        layers.append(MapLayer("ellipse", lines=ellipse_outlines(site, footprint.statistics, ground)))
        layers.append(MapLayer("landing", tuple(MapPoint(f"run {i}", float(a), float(o), "Monte Carlo touchdown",
                                                         ground) for i, (a, o) in enumerate(zip(lat, lon)))))
    title = f"release point of {Path(release.case).name}"
    return GeoMap(title, tuple(layers), title, earth=on_earth(site), **planet_radius(site))
