"""The map writers on a made-up map (``results.map_files``, ``results.map_page``): RFC 7946's ring orientation, samples
that are not finite left out of every format, the page's tiles on the Earth only and its inline data that cannot
close its script early."""

import json
import math
import xml.etree.ElementTree as ET

from pchute_exudyn.results.map_files import (
    GPX_NAMESPACE,
    KML_NAMESPACE,
    GeoMap,
    MapLayer,
    MapLine,
    MapPoint,
    geojson_data,
    gpx_text,
    kml_text,
)
from pchute_exudyn.results.map_page import TILES, page_html

CLOCKWISE = MapLine("square", (1.0, 1.0, 0.0, 0.0), (0.0, 1.0, 1.0, 0.0), closed=True)   # N, NE, E, origin
GAPPED = MapLine("gapped", (10.0, math.nan, 10.2, 10.3, 10.4), (20.0, 20.1, math.inf, 20.3, 20.4),
                 altitudes=(5.0, 4.0, 3.0, 2.0, 1.0), heights=(1.0, 1.0, 1.0, math.nan, 0.5))


def _map(earth=True, name="drop zone") -> GeoMap:
    return GeoMap(name, (MapLayer("site", (MapPoint("start", 10.0, 20.0), MapPoint("nowhere", math.nan, 0.0))),
                         MapLayer("track", lines=(GAPPED,)), MapLayer("ellipse", lines=(CLOCKWISE,))), earth=earth)


def test_a_polygon_is_closed_and_counterclockwise_as_rfc_7946_asks():
    ring = next(f for f in geojson_data(_map())["features"] if f["geometry"]["type"] == "Polygon")
    ring = ring["geometry"]["coordinates"][0]
    assert ring[0] == ring[-1] and len(ring) == 5
    area = sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(ring, ring[1:])) / 2.0   # shoelace, lon-lat
    assert area == 1.0                                                              # positive: counterclockwise


def test_samples_that_are_not_finite_are_left_out_of_every_format():
    features = geojson_data(_map())["features"]
    assert [f["properties"]["name"] for f in features] == ["start", "gapped", "square"]   # 'nowhere' has no latitude
    track = next(f for f in features if f["properties"]["name"] == "gapped")
    # a NaN or inf in any of a sample's columns (its height too) leaves it out: the same points in every format
    assert track["geometry"]["coordinates"] == [[20.0, 10.0, 5.0], [20.4, 10.4, 1.0]]
    kml = ET.fromstring(kml_text(_map()))
    line = kml.find(f".//{{{KML_NAMESPACE}}}LineString/{{{KML_NAMESPACE}}}coordinates").text
    assert line == "20,10,1.000 20.4,10.4,0.500"
    gpx = ET.fromstring(gpx_text(_map()))
    points = gpx.findall(f".//{{{GPX_NAMESPACE}}}trkpt")
    assert [(p.get("lat"), p.get("lon")) for p in points[:2]] == [("10", "20"), ("10.4", "20.4")]
    assert [w.find(f"{{{GPX_NAMESPACE}}}name").text for w in gpx.findall(f"{{{GPX_NAMESPACE}}}wpt")] == ["start"]


def test_the_page_draws_tiles_on_the_earth_only_and_its_data_cannot_close_its_script():
    assert TILES in page_html(_map(earth=True)) and TILES not in page_html(_map(earth=False))
    page = page_html(_map(name="</script><script>alert(1)</script>"))
    data = page.split('<script id="map-setup" type="application/json">', 1)[1].split("</script>", 1)[0]
    assert json.loads(data)["title"] == "</script><script>alert(1)</script>"
    assert "<title>&lt;/script&gt;" in page
