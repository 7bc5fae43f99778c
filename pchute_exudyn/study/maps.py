"""A study on a map: each run's touchdown point, the footprint's dispersion ellipses (``study.footprint``) as
polygons in latitude and longitude, each kept run's ground track and the start point; and ``write_map``, which maps a
run's result folder or a study folder (``pchute map``).

The touchdown points are the runs' own ``final_latitude`` and ``final_longitude``. The ellipses are those of the
footprint report (k sigma of the bivariate normal fitted to the touchdown points' east and north: 1 sigma, 3 sigma
and the 99 % contour), each point of their outline carried from east and north to latitude and longitude on the
case's ellipsoid through the run's start frame (``results.run_map.ground_places``) at the touchdowns' median
altitude; a study whose runs start from different points has no ellipse on its map (east and north of different
start points do not add up).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..boundary import check_path
from ..errors import InputError
from ..registries.columns import column
from ..results.io import RESULT_MARKER, ensure_writable_dir
from ..results.map_files import GeoMap, MapLayer, MapLine, MapPoint
from ..results.map_page import write_map_files
from ..results.result import Result
from ..results.run_map import MAP_STEM, ground_places, on_earth, planet_radius, site_point, write_run_map
from .footprint import MINIMUM_RUNS, footprint_statistics, touchdown_points
from .store import StudyStore

TRACK_SAMPLES = 1000
"""A study run's track on the map keeps at most this many of its samples (evenly spaced, the last kept): a study of
many runs still makes a page a browser opens at once."""


def write_map(folder, out=None) -> list:
    """Write the map files of ``folder``, a result folder of ``pchute run`` (into it, or ``out``) or a study folder
    (into its ``report`` folder, or ``out``); returns their paths."""
    folder = check_path(folder, "folder", "result or study folder")
    if not folder.is_dir():
        raise InputError(f"{folder}: not a folder: give a result folder of `pchute run` or a study folder")
    if (folder / "runs.csv").is_file():
        target = ensure_writable_dir(Path(out) if out is not None else folder / "report")
        return write_map_files(study_map(folder), target, MAP_STEM)
    if (folder / RESULT_MARKER).is_file():
        if out is not None:
            ensure_writable_dir(out)
        return write_run_map(folder, out)
    raise InputError(f"{folder}: neither a result folder of `pchute run` (no {RESULT_MARKER}) nor a study folder "
                     "(no runs.csv)")


def study_map(folder) -> GeoMap:
    """The map of study folder ``folder`` (module docstring); InputError when its runs record no latitude (a study on
    a flat planet, or one recorded by an earlier version)."""
    from .report import load_table  # here: the report's figures import matplotlib, which a map never draws with

    folder = Path(folder)
    ok = [r for r in load_table(folder) if r.get("status") == "ok" and r.get("reference") != "True"]
    latitude, longitude, landed_at = column("final_latitude"), column("final_longitude"), column("touchdown_time")
    placed = [r for r in ok if _number(r.get(latitude)) and _number(r.get(longitude))]
    if not placed:
        raise InputError(f"{folder}: no ok run records its {latitude}: a study on a flat planet has no latitude and "
                         "longitude, and one recorded by an earlier version has none (run it again into a new folder)")
    records = StudyStore.load_records(folder)
    sites = {json.dumps(records[int(r["run"])].site, sort_keys=True): records[int(r["run"])].site for r in placed
             if int(r["run"]) in records and records[int(r["run"])].site}
    landings = [r for r in placed if _number(r.get(landed_at))]
    ends = [r for r in placed if not _number(r.get(landed_at))]
    layers = [MapLayer("site", tuple(site_point(s) for s in sites.values()))] if sites else []
    tracks = tuple(_tracks(folder, placed))
    if tracks:
        layers.append(MapLayer("track", lines=tracks))
    if len(sites) == 1:
        outlines = _ellipses(next(iter(sites.values())), placed)
        if outlines:
            layers.append(MapLayer("ellipse", lines=outlines))
    layers += [MapLayer(name, tuple(_point(r, landed) for r in rows))
               for name, rows, landed in (("landing", landings, True), ("end", ends, False)) if rows]
    name = f"{folder.name}: {len(landings)} touchdowns of {len(ok)} ok runs"
    return GeoMap(name, tuple(layers), name, earth=all(on_earth(s) for s in sites.values()) and bool(sites),
                  **planet_radius(next(iter(sites.values()), None)))


def _number(value) -> bool:
    return isinstance(value, float) and np.isfinite(value)


def _point(row: dict, landed: bool) -> MapPoint:
    """A run's touchdown (or end) point, described by its time, speed and place east and north of the start."""
    run = int(row["run"])
    what = (f"touchdown at t = {row[column('touchdown_time')]:.2f} s, {row[column('touchdown_speed')]:.2f} m/s over "
            "the ground" if landed else f"end of the run at t = {row[column('final_time')]:.2f} s")
    return MapPoint(f"run {run}", row[column("final_latitude")], row[column("final_longitude")],
                    f"{what}; {row[column('final_east')]:.1f} m east, {row[column('final_north')]:.1f} m north of "
                    "the start point", row.get(column("final_altitude")))


def _ellipses(site: dict, rows: list) -> tuple:
    """The footprint's dispersion ellipses as closed outlines in latitude and longitude (none with fewer than
    MINIMUM_RUNS touchdowns or no spread)."""
    points = touchdown_points(rows)
    if len(points) < MINIMUM_RUNS:
        return ()
    altitudes = [r[column("final_altitude")] for r in rows if _number(r.get(column("touchdown_time")))
                 and _number(r.get(column("final_altitude")))]
    return ellipse_outlines(site, footprint_statistics(points), float(np.median(altitudes)) if altitudes else 0.0)


def ellipse_outlines(site: dict, stats: dict, altitude: float) -> tuple:
    """The dispersion ellipses of ``stats`` (``footprint.footprint_statistics``) as closed map outlines in latitude
    and longitude, carried through the start frame of ``site`` (``RunSummary.site``) at ``altitude`` (m above the
    ellipsoid); none when the points have no spread."""
    from ..views.study_figures import ellipse  # here, as load_table: its module draws with matplotlib

    if not stats["sigma_major"] > 0.0:
        return ()
    outlines = []
    for label, e in stats["ellipses"].items():
        curve = ellipse(stats, e["k"])
        lat, lon = ground_places(site, curve[:, 0], curve[:, 1], altitude)
        outlines.append(MapLine(f"{label} ellipse", lat, lon,
                                f"{e['k']:.3f} sigma: semi-axes {e['semi_major']:.1f} m and {e['semi_minor']:.1f} m, "
                                f"major axis {stats['major_axis_azimuth_deg']:.0f} deg from north; the normal model "
                                f"holds {100 * e['normal_share']:.1f} %, {100 * e['share_inside']:.1f} % of the "
                                f"{stats['count']} touchdowns inside", closed=True))
    return tuple(outlines)


def _tracks(folder: Path, rows: list):
    """The vehicle's ground track of each run whose histories the study kept (``histories/run_NNNNN``)."""
    for row in rows:
        history = folder / "histories" / f"run_{int(row['run']):05d}"
        if not history.is_dir():
            continue
        result = Result.load(history)
        names = [column(t, result.vehicle) for t in ("{owner}_latitude", "{owner}_longitude", "{owner}_altitude",
                                                     "{owner}_height")]
        if not all(name in result for name in names):
            continue
        kept = np.unique(np.append(np.linspace(0, len(result.time) - 1, min(TRACK_SAMPLES, len(result.time)))
                                   .astype(int), len(result.time) - 1))
        lat, lon, alt, height = (result[name][kept] for name in names)
        yield MapLine(f"run {int(row['run'])} track", lat, lon, f"{result.vehicle}'s centre of mass over the ground",
                      altitudes=alt, heights=height)
