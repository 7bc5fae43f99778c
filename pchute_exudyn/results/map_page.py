"""A map as one HTML page that opens from the file system with no server and no network (``map.html``), and the
map's four files (``write_map_files``).

The page carries everything it draws: Leaflet 1.9.4 (BSD-2-Clause, its licence in ``results/leaflet/LICENSE``) and
the map's GeoJSON (``map_files.geojson_data``) inline. Each layer of the map is an overlay that can be switched off;
points are circles and lines SVG paths, so they draw without any tile. A map on the Earth (``GeoMap.earth``) also
gets an OpenStreetMap tile layer under them when the network gives one; on another planet there are no tiles (the
Earth's would mislead). The page exposes what it drew as ``window.pchuteMap``: ``counts`` (features per layer) and
``map`` (the Leaflet map), for a test or a curious user's console.
"""

from __future__ import annotations

import html
import json
from importlib import resources
from pathlib import Path

from .io import atomic_write_text
from .map_files import LAYER_COLOURS, OTHER_COLOUR, GeoMap, geojson_data, geojson_text, gpx_text, kml_text

SUFFIXES = (".kml", ".geojson", ".gpx", ".html")
"""The files ``write_map_files`` writes, in this order, as ``<stem><suffix>``."""
TILES = "https://tile.openstreetmap.org/{z}/{x}/{y}.png"
TILE_CREDIT = '&copy; <a href="https://www.openstreetmap.org/copyright">OpenStreetMap</a> contributors'

_SCRIPT = """
(function () {
  var data = JSON.parse(document.getElementById("map-data").textContent);
  var setup = JSON.parse(document.getElementById("map-setup").textContent);
  // distances (the scale bar) on the map's own planet: Web Mercator's sphere of the planet's equatorial radius
  var map = L.map("map", {crs: L.extend({}, L.CRS.EPSG3857, {R: setup.radius})});
  var overlays = {}, counts = {}, base = {};
  function text(tag, content) { var e = document.createElement(tag); e.textContent = content; return e; }
  data.features.forEach(function (feature) {
    var name = feature.properties.layer, colour = setup.colours[name] || setup.other;
    if (!overlays[name]) { overlays[name] = L.featureGroup().addTo(map); counts[name] = 0; }
    var drawn = L.geoJSON(feature, {
      style: function (f) {
        return f.geometry.type === "Point" ? {color: "#000", weight: 1, fillColor: colour, fillOpacity: 0.9}
                                           : {color: colour, weight: 2, fillOpacity: 0.12};
      },
      pointToLayer: function (f, at) { return L.circleMarker(at, {radius: 6}); }
    });
    var popup = document.createElement("div");
    popup.appendChild(text("b", feature.properties.name));
    if (feature.properties.description) { popup.appendChild(text("div", feature.properties.description)); }
    drawn.bindPopup(popup);
    drawn.addTo(overlays[name]);
    counts[name] += 1;
  });
  if (setup.tiles) {
    base["OpenStreetMap"] = L.tileLayer(setup.tiles, {maxZoom: 19, attribution: setup.credit}).addTo(map);
  }
  var bounds = L.latLngBounds([]);
  Object.keys(overlays).forEach(function (name) { bounds.extend(overlays[name].getBounds()); });
  if (!bounds.isValid()) { map.setView([0, 0], 2); }
  else if (bounds.getNorthEast().equals(bounds.getSouthWest())) { map.setView(bounds.getCenter(), 15); }
  else { map.fitBounds(bounds, {padding: [20, 20]}); }
  L.control.layers(base, overlays, {collapsed: false}).addTo(map);
  L.control.scale({imperial: false}).addTo(map);
  var title = L.control({position: "bottomleft"});
  title.onAdd = function () { var e = text("div", setup.title); e.className = "map-title"; return e; };
  title.addTo(map);
  window.pchuteMap = {map: map, counts: counts};
})();
"""

_STYLE = """
html, body, #map { height: 100%; margin: 0; }
.map-title { background: rgba(255, 255, 255, 0.85); padding: 2px 6px; font: 13px sans-serif; }
"""


def _asset(name: str) -> str:
    """A Leaflet file shipped in ``results/leaflet``."""
    return resources.files(__package__).joinpath("leaflet", name).read_text(encoding="utf-8")


def _inline_json(data) -> str:
    """JSON text that may stand inside a <script> element: '<' escaped (no '</script>' can close it early)."""
    return json.dumps(data, allow_nan=False, separators=(",", ":")).replace("<", "\\u003c")


def page_html(geo_map: GeoMap) -> str:
    """The map as a self-contained HTML page (Leaflet and the map's GeoJSON inline)."""
    setup = {"title": geo_map.title, "colours": LAYER_COLOURS, "other": OTHER_COLOUR, "radius": geo_map.radius,
             "tiles": TILES if geo_map.earth else None, "credit": TILE_CREDIT}
    data = geojson_data(geo_map)
    return "\n".join([
        "<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{html.escape(geo_map.title)}</title>",
        f"<style>\n{_asset('leaflet.css')}\n</style>", f"<style>{_STYLE}</style>",
        f"<script>\n{_asset('leaflet.js')}\n</script>", "</head>", "<body>", '<div id="map"></div>',
        f'<script id="map-data" type="application/json">{_inline_json(data)}</script>',
        f'<script id="map-setup" type="application/json">{_inline_json(setup)}</script>',
        f"<script>{_SCRIPT}</script>", "</body>", "</html>", ""])


def write_map_files(geo_map: GeoMap, folder, stem: str = "map") -> list:
    """Write ``<stem>.kml``, ``.geojson``, ``.gpx`` and ``.html`` into ``folder``, each atomically; returns their
    paths in SUFFIXES' order."""
    texts = (kml_text(geo_map), geojson_text(geo_map), gpx_text(geo_map), page_html(geo_map))
    paths = [Path(folder) / f"{stem}{suffix}" for suffix in SUFFIXES]
    for path, text in zip(paths, texts):
        atomic_write_text(path, text)
    return paths
