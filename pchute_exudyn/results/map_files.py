"""Map files of named points, tracks and polygons in latitude and longitude: KML 2.2 (Google Earth), GeoJSON (RFC
7946) and GPX 1.1 (GPS receivers and their software), as text, with the standard library alone; ``map_page`` draws
the same map as an HTML page and writes the four files.

A map (``GeoMap``) is a list of layers, each a name (``site``, ``landing``, ``track``, ``ellipse``, or any other a
caller chooses) holding points (``MapPoint``), open lines (``MapLine``, ``closed=False``: a track) and closed
outlines (``closed=True``: a polygon). Coordinates are geodetic latitude and longitude in degrees (east positive);
a sample any of whose values is not finite (a body absent from part of a run) is left out of every format alike.
Heights:

* GeoJSON's third coordinate and GPX's ``ele`` are ``altitudes``: above the planet's reference ellipsoid (m), what
  RFC 7946 asks for (GPX leaves the datum open);
* KML draws a line at its ``heights`` above the ground (m, ``altitudeMode`` relativeToGround), so that a track ends
  on Google Earth's terrain where the run touched the case's ground; a point sits on the ground.

Coordinates are written to 1e-10 deg (1 cm) and heights to 1 mm. GPX has no polygon: a closed outline is a track
whose last point is its first, its ``type`` the layer's name.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

import numpy as np

from .io import json_text

KML_NAMESPACE = "http://www.opengis.net/kml/2.2"
GPX_NAMESPACE = "http://www.topografix.com/GPX/1/1"
CREATOR = "pchute-exudyn"

LAYER_COLOURS = {"site": "#d62728", "landing": "#1f77b4", "end": "#7f7f7f", "track": "#ff7f0e",
                 "ellipse": "#2ca02c", "target": "#e377c2", "release": "#8c564b"}
"""Each usual layer's colour (#rrggbb) in every format that has colours; another layer is drawn in OTHER_COLOUR."""
OTHER_COLOUR = "#9467bd"


@dataclass(frozen=True)
class MapPoint:
    """A named point.

    Attributes
    ----------
    name : str
    latitude, longitude : float
        Geodetic latitude and longitude (deg, east positive).
    description : str
        One line shown beside the name.
    altitude : float, optional
        Above the reference ellipsoid (m).
    """

    name: str
    latitude: float
    longitude: float
    description: str = ""
    altitude: float | None = None


@dataclass(frozen=True)
class MapLine:
    """A named line through points in order: a track (``closed=False``) or a polygon's outline (``closed=True``;
    the files close the ring).

    Attributes
    ----------
    name : str
    latitudes, longitudes : sequence of float
        Geodetic latitude and longitude (deg) of each point.
    description : str
    altitudes : sequence of float, optional
        Each point above the reference ellipsoid (m): GeoJSON and GPX.
    heights : sequence of float, optional
        Each point above the ground (m): KML.
    closed : bool
    """

    name: str
    latitudes: tuple
    longitudes: tuple
    description: str = ""
    altitudes: tuple | None = None
    heights: tuple | None = None
    closed: bool = False

    def samples(self) -> tuple:
        """(latitudes, longitudes, altitudes or None, heights or None) as arrays, the samples where any of them is
        not finite left out; a closed line's ring ends at its first point."""
        arrays = [None if v is None else np.asarray(v, float)
                  for v in (self.latitudes, self.longitudes, self.altitudes, self.heights)]
        kept = np.logical_and.reduce([np.isfinite(a) for a in arrays if a is not None])
        arrays = [None if a is None else a[kept] for a in arrays]
        lat, lon = arrays[:2]
        if self.closed and len(lat) and (lat[0] != lat[-1] or lon[0] != lon[-1]):
            arrays = [None if a is None else np.append(a, a[0]) for a in arrays]
        return tuple(arrays)


@dataclass(frozen=True)
class MapLayer:
    """A named group of points and lines drawn alike (``LAYER_COLOURS``)."""

    name: str
    points: tuple = ()
    lines: tuple = ()

    @property
    def colour(self) -> str:
        return LAYER_COLOURS.get(self.name, OTHER_COLOUR)


@dataclass(frozen=True)
class GeoMap:
    """A map: its title, a description and its layers. ``earth``: the coordinates are on the Earth, so a page may
    draw map tiles under them (another planet's latitudes on the Earth's tiles would mislead); ``radius`` (m): the
    planet's equatorial radius, by which a page measures distances (its scale bar)."""

    title: str
    layers: tuple = field(default_factory=tuple)
    description: str = ""
    earth: bool = True
    radius: float = 6378137.0


def _degrees(value: float) -> str:
    return f"{value:.10f}".rstrip("0").rstrip(".") if math.isfinite(value) else "nan"


def _metres(value: float) -> str:
    return f"{value:.3f}"


# -- GeoJSON ---------------------------------------------------------------------------------------------------------

def _position(lat, lon, alt=None) -> list:
    position = [round(float(lon), 10), round(float(lat), 10)]
    return position + [round(float(alt), 3)] if alt is not None else position


def _counterclockwise(ring: list) -> list:
    """RFC 7946's right-hand rule: an exterior ring runs counterclockwise (a shoelace area > 0)."""
    area = sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(ring, ring[1:]))
    return ring if area >= 0 else ring[::-1]


def geojson_data(geo_map: GeoMap) -> dict:
    """The map as a GeoJSON FeatureCollection (RFC 7946: [longitude, latitude, altitude] positions); each feature's
    properties: ``name``, ``layer``, ``description``."""
    features = []
    for layer in geo_map.layers:
        for point in layer.points:
            if not (math.isfinite(point.latitude) and math.isfinite(point.longitude)):
                continue
            alt = point.altitude if point.altitude is not None and math.isfinite(point.altitude) else None
            features.append(_feature({"type": "Point", "coordinates": _position(point.latitude, point.longitude, alt)},
                                     point.name, layer.name, point.description))
        for line in layer.lines:
            lat, lon, alt, _ = line.samples()
            positions = [_position(*p) for p in zip(lat, lon, *([alt] if alt is not None else []))]
            if len(positions) < (4 if line.closed else 2):
                continue
            geometry = ({"type": "Polygon", "coordinates": [_counterclockwise(positions)]} if line.closed
                        else {"type": "LineString", "coordinates": positions})
            features.append(_feature(geometry, line.name, layer.name, line.description))
    return {"type": "FeatureCollection", "features": features}


def _feature(geometry: dict, name: str, layer: str, description: str) -> dict:
    return {"type": "Feature", "geometry": geometry,
            "properties": {"name": name, "layer": layer, "description": description}}


def geojson_text(geo_map: GeoMap) -> str:
    """``geojson_data`` as strict JSON text, a feature a line."""
    features = geojson_data(geo_map)["features"]
    return ('{"type": "FeatureCollection", "features": [\n' + ",\n".join(json_text(f) for f in features)
            + "\n]}\n")


# -- KML -------------------------------------------------------------------------------------------------------------

def _kml_colour(colour: str, alpha: str = "ff") -> str:
    """#rrggbb as KML's aabbggrr."""
    return alpha + colour[5:7] + colour[3:5] + colour[1:3]


def _sub(parent, tag: str, text: str | None = None, **attributes):
    element = ET.SubElement(parent, tag, attributes)
    if text is not None:
        element.text = text
    return element


def kml_text(geo_map: GeoMap) -> str:
    """The map as a KML 2.2 document: a style and a folder per layer, a placemark per point and line."""
    root = ET.Element("kml", xmlns=KML_NAMESPACE)
    document = _sub(root, "Document")
    _sub(document, "name", geo_map.title)
    if geo_map.description:
        _sub(document, "description", geo_map.description)
    for layer in geo_map.layers:
        style = _sub(document, "Style", id=f"layer-{layer.name}")
        icon = _sub(style, "IconStyle")
        _sub(icon, "color", _kml_colour(layer.colour))
        _sub(_sub(icon, "Icon"), "href", "http://maps.google.com/mapfiles/kml/shapes/placemark_circle.png")
        line_style = _sub(style, "LineStyle")
        _sub(line_style, "color", _kml_colour(layer.colour))
        _sub(line_style, "width", "2")
        poly = _sub(style, "PolyStyle")
        _sub(poly, "color", _kml_colour(layer.colour, "40"))
    for layer in geo_map.layers:
        folder = _sub(document, "Folder")
        _sub(folder, "name", layer.name)
        for point in layer.points:
            if math.isfinite(point.latitude) and math.isfinite(point.longitude):
                placemark = _placemark(folder, point.name, point.description, layer.name)
                _sub(_sub(placemark, "Point"), "coordinates", f"{_degrees(point.longitude)},{_degrees(point.latitude)}")
        for line in layer.lines:
            _kml_line(folder, line, layer.name)
    return _xml(root)


def _placemark(folder, name: str, description: str, layer: str):
    placemark = _sub(folder, "Placemark")
    _sub(placemark, "name", name)
    if description:
        _sub(placemark, "description", description)
    _sub(placemark, "styleUrl", f"#layer-{layer}")
    return placemark


def _kml_line(folder, line: MapLine, layer: str) -> None:
    lat, lon, _, heights = line.samples()
    if len(lat) < (4 if line.closed else 2):
        return
    placemark = _placemark(folder, line.name, line.description, layer)
    if heights is None:
        coordinates = " ".join(f"{_degrees(x)},{_degrees(y)}" for y, x in zip(lat, lon))
    else:
        coordinates = " ".join(f"{_degrees(x)},{_degrees(y)},{_metres(h)}" for y, x, h in zip(lat, lon, heights))
    if line.closed:
        ring = _sub(_sub(_sub(placemark, "Polygon"), "outerBoundaryIs"), "LinearRing")
        _sub(ring, "tessellate", "1")
        _sub(ring, "coordinates", coordinates)
        return
    geometry = _sub(placemark, "LineString")
    _sub(geometry, "tessellate", "1")
    _sub(geometry, "altitudeMode", "clampToGround" if heights is None else "relativeToGround")
    _sub(geometry, "coordinates", coordinates)


# -- GPX -------------------------------------------------------------------------------------------------------------

def gpx_text(geo_map: GeoMap) -> str:
    """The map as GPX 1.1: a waypoint per point, a track per line (``type``: its layer)."""
    root = ET.Element("gpx", version="1.1", creator=CREATOR, xmlns=GPX_NAMESPACE)
    metadata = _sub(root, "metadata")
    _sub(metadata, "name", geo_map.title)
    if geo_map.description:
        _sub(metadata, "desc", geo_map.description)
    for layer in geo_map.layers:
        for point in layer.points:
            if not (math.isfinite(point.latitude) and math.isfinite(point.longitude)):
                continue
            waypoint = _sub(root, "wpt", lat=_degrees(point.latitude), lon=_degrees(point.longitude))
            if point.altitude is not None and math.isfinite(point.altitude):
                _sub(waypoint, "ele", _metres(point.altitude))
            _described(waypoint, point.name, point.description, layer.name)
    for layer in geo_map.layers:
        for line in layer.lines:
            lat, lon, altitudes, _ = line.samples()
            if len(lat) < 2:
                continue
            track = _described(_sub(root, "trk"), line.name, line.description, layer.name)
            segment = _sub(track, "trkseg")
            for i in range(len(lat)):
                sample = _sub(segment, "trkpt", lat=_degrees(lat[i]), lon=_degrees(lon[i]))
                if altitudes is not None:
                    _sub(sample, "ele", _metres(altitudes[i]))
    return _xml(root)


def _xml(root) -> str:
    """An XML document's text, one element a line."""
    ET.indent(root, space=" ")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _described(element, name: str, description: str, layer: str):
    """GPX's name, desc and type, in the schema's order."""
    _sub(element, "name", name)
    if description:
        _sub(element, "desc", description)
    _sub(element, "type", layer)
    return element
