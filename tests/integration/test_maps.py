"""Runs and studies on a map (``pchute map``): the latitude and longitude columns against the case's site and the
ellipsoid's radii of curvature, and the KML, GeoJSON and GPX files read back by their own libraries (the KML against
the OGC KML 2.2 schema), their points where the run's columns put them; the HTML page in headless Chromium."""

import json
import math
import pathlib
import time

import numpy as np
import pytest

import pchute_exudyn as pc
from pchute_exudyn.cli import main
from pchute_exudyn.registries.columns import GEODETIC_TEMPLATES, column
from tests.browser import chromium_page, screenshot_is_blank
from tests.helpers import ROOT

CASE = ROOT / "cases" / "airdrop" / "static_line.toml"
SITE = (35.2, -117.6)   # a drop zone in the Mojave: the case's own start is 0, 0
OVERRIDES = [f"start.latitude_deg={SITE[0]}", f"start.longitude_deg={SITE[1]}", "vehicle.initial.altitude=120",
             "atmosphere.wind.speed=6", "atmosphere.wind.from_deg=250"]   # 12 s to touchdown, 250 m downwind
TOLERANCE_DEG = 1e-9

ZONE_CASE = f"""
extends = "{CASE.as_posix()}"
[start]
latitude_deg = {SITE[0]}
longitude_deg = {SITE[1]}
[bodies.vehicle.initial]
altitude = 120.0
[atmosphere.wind]
speed = 6.0
from_deg = 250.0
"""

STUDY = """
[study]
name = "drop zone"
case = "zone_case.toml"
runs = 3
seed = 11
histories = true

[[study.configurations]]
method = "sp"

[parameters."atmosphere.wind.speed"]
distribution = "uniform"
low = 3.0
high = 9.0
[parameters."atmosphere.wind.from_deg"]
distribution = "uniform"
low = 200.0
high = 300.0
"""


@pytest.fixture(scope="module")
def mapped_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("maps") / "run"
    result = pc.simulate(pc.load_case(CASE, OVERRIDES))
    result.save(folder, plot=False)
    assert main(["map", str(folder)]) == 0
    return result, folder


def _geojson(path):
    import geojson

    text = path.read_text()
    collection = geojson.loads(text)
    assert collection.is_valid, collection.errors()
    return json.loads(text)["features"]   # the library rounds coordinates to 6 digits: the file's own numbers


def _kml(path):
    from fastkml import kml, validator

    assert validator.validate(file_to_validate=path)   # the OGC KML 2.2 schema fastkml ships
    document = kml.KML.from_string(path.read_bytes()).features[0]
    return {folder.name: folder.features for folder in document.features}


def _gpx(path):
    import gpxpy

    return gpxpy.parse(path.read_text())


@pytest.mark.parametrize("rotating", [False, True])
def test_latitude_and_longitude_start_at_the_site_and_follow_the_radii_of_curvature(mapped_run, rotating):
    """On a turning Earth (an inertial frame) too: the place is over the ground, as east and north are."""
    result = pc.simulate(pc.load_case(CASE, [*OVERRIDES, "planet.rotation_rate=7.292115e-5"])) if rotating \
        else mapped_run[0]
    lat, lon = result["vehicle_latitude"], result["vehicle_longitude"]
    assert abs(lat[0] - SITE[0]) < TOLERANCE_DEG and abs(lon[0] - SITE[1]) < TOLERANCE_DEG
    # a point n m north and e m east of the site, h above it: dlat = n / (M + h), dlon = e / ((N + h) cos(lat))
    a, b = 6378137.0, 6356752.314245
    e2, phi = 1.0 - (b / a) ** 2, math.radians(SITE[0])
    meridian = a * (1.0 - e2) / (1.0 - e2 * math.sin(phi) ** 2) ** 1.5
    normal = a / math.sqrt(1.0 - e2 * math.sin(phi) ** 2)
    h, east, north = result["vehicle_altitude"], result["vehicle_east"], result["vehicle_north"]
    assert north[-1] > 200.0 and east[-1] > 50.0                 # the wind carried it well off the site
    assert np.abs(np.radians(lat - SITE[0]) * (meridian + h) - north).max() < 0.02          # m
    assert np.abs(np.radians(lon - SITE[1]) * (normal + h) * math.cos(phi) - east).max() < 0.02
    assert result.units["vehicle_latitude"] == "deg" == result.units["canopy_longitude"]
    geodetic = [n for n in result.names if any(n == column(t, n.rsplit("_", 1)[0]) for t in GEODETIC_TEMPLATES)]
    assert result.names[-len(geodetic):] == geodetic             # after every other column: those keep their places


def test_a_run_map_in_kml_geojson_and_gpx_puts_the_run_where_its_columns_do(mapped_run):
    result, folder = mapped_run
    start = (result["vehicle_latitude"][0], result["vehicle_longitude"][0])
    landing = (result["vehicle_latitude"][-1], result["vehicle_longitude"][-1])
    assert result.summary.end == "touchdown" and result.summary.final.place == landing
    listed = json.loads((folder / "summary.json").read_text())["result_files"]
    assert {"map.kml", "map.geojson", "map.gpx", "map.html"} <= set(listed)   # replaced with the result

    features = {f["properties"]["name"]: f["geometry"] for f in _geojson(folder / "map.geojson")}
    track = features["vehicle track"]["coordinates"]                   # RFC 7946: longitude first
    assert np.allclose(track[0][:2], start[::-1], rtol=0, atol=TOLERANCE_DEG)
    assert np.allclose(features["touchdown"]["coordinates"][:2], landing[::-1], rtol=0, atol=TOLERANCE_DEG)
    assert np.allclose(features["start point"]["coordinates"], SITE[::-1], rtol=0, atol=TOLERANCE_DEG)
    assert {f["properties"]["layer"] for f in _geojson(folder / "map.geojson")} == {"site", "track", "landing"}

    folders = _kml(folder / "map.kml")
    tracks = {p.name: list(p.geometry.coords) for p in folders["track"]}
    assert set(tracks) == {"vehicle track", "canopy track"}
    assert np.allclose(tracks["vehicle track"][0][:2], start[::-1], rtol=0, atol=TOLERANCE_DEG)
    assert tracks["vehicle track"][0][2] == pytest.approx(result["vehicle_height"][0], abs=1e-3)   # above ground
    assert np.allclose(list(folders["landing"][0].geometry.coords)[0], landing[::-1], rtol=0, atol=TOLERANCE_DEG)

    gpx = _gpx(folder / "map.gpx")
    first = gpx.tracks[0].segments[0].points[0]
    assert gpx.tracks[0].name == "vehicle track"
    assert abs(first.latitude - start[0]) < TOLERANCE_DEG and abs(first.longitude - start[1]) < TOLERANCE_DEG
    touchdown = next(w for w in gpx.waypoints if w.name == "touchdown")
    assert abs(touchdown.latitude - landing[0]) < TOLERANCE_DEG and abs(touchdown.longitude - landing[1]) < TOLERANCE_DEG


def test_the_map_page_draws_its_layers_offline(mapped_run):
    _, folder = mapped_run
    with chromium_page(900, 700) as browser:
        browser.get((folder / "map.html").as_uri())
        deadline = time.monotonic() + 10.0
        counts = None
        while counts is None and time.monotonic() < deadline:
            counts = browser.execute_script("return window.pchuteMap ? window.pchuteMap.counts : null")
        assert counts == {"site": 1, "track": 2, "landing": 1}
        paths = browser.execute_script("return document.querySelectorAll('.leaflet-overlay-pane path').length")
        assert paths == 4                                            # the two tracks and two circles, drawn in SVG
        errors = [e["message"] for e in browser.get_log("browser") if e["level"] == "SEVERE"
                  and "tile.openstreetmap.org" not in e["message"]]   # the tiles are refused: no network here
        assert errors == []
        assert not screenshot_is_blank(browser.get_screenshot_as_png())


def test_a_study_map_has_its_touchdowns_ellipses_and_tracks(tmp_path):
    from pchute_exudyn.study import load_study, run_study

    (tmp_path / "zone_case.toml").write_text(ZONE_CASE)
    path = tmp_path / "zone.toml"
    path.write_text(STUDY)
    run_study(load_study(path), tmp_path / "zone", workers=1, progress=False)
    assert main(["map", str(tmp_path / "zone")]) == 0
    report = tmp_path / "zone" / "report"
    rows = [json.loads(line) for line in (tmp_path / "zone" / "runs.jsonl").read_text().splitlines()]
    landings = {f"run {r['run']}": (r["final_latitude"], r["final_longitude"]) for r in rows}
    assert len(landings) == 3 and all(r["touchdown_time"] and r["site"]["latitude_deg"] == SITE[0] for r in rows)

    by_layer = {}
    for feature in _geojson(report / "map.geojson"):
        by_layer.setdefault(feature["properties"]["layer"], []).append(feature)
    assert {name: len(f) for name, f in by_layer.items()} == {"site": 1, "track": 3, "ellipse": 3, "landing": 3}
    for feature in by_layer["landing"]:
        assert np.allclose(feature["geometry"]["coordinates"][:2], landings[feature["properties"]["name"]][::-1],
                           rtol=0, atol=TOLERANCE_DEG)
    for feature in by_layer["track"]:   # each kept run's track starts at the site and ends at its touchdown
        coordinates = feature["geometry"]["coordinates"]
        assert np.allclose(coordinates[0][:2], SITE[::-1], rtol=0, atol=TOLERANCE_DEG)
        run = feature["properties"]["name"].removesuffix(" track")
        assert np.allclose(coordinates[-1][:2], landings[run][::-1], rtol=0, atol=TOLERANCE_DEG)
    # the 3-sigma outline holds the touchdowns: the mean point lies inside it, its size the footprint's
    ring = np.array(next(f for f in by_layer["ellipse"] if f["properties"]["name"] == "3 sigma ellipse")
                    ["geometry"]["coordinates"][0])
    centre = np.mean(list(landings.values()), axis=0)[::-1]
    assert ring[:, 0].min() < centre[0] < ring[:, 0].max() and ring[:, 1].min() < centre[1] < ring[:, 1].max()

    kml = _kml(report / "map.kml")
    assert len(kml["ellipse"]) == 3 and len(kml["landing"]) == 3
    gpx = _gpx(report / "map.gpx")
    assert {w.name for w in gpx.waypoints} == {"start point", *landings}
    assert len(gpx.tracks) == 6                                       # three tracks and three ellipse outlines


def test_a_run_on_a_flat_planet_has_no_place_and_no_map(tmp_path, capsys):
    result = pc.simulate(pc.load_case(ROOT / "cases" / "simple" / "simple.toml"), duration=0.05)
    assert not [n for n in result.names if n.endswith(("_latitude", "_longitude"))]
    result.save(tmp_path / "flat", plot=False)
    assert main(["map", str(tmp_path / "flat")]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "flat planet" in err and "Traceback" not in err
    assert not list(pathlib.Path(tmp_path / "flat").glob("map.*"))
