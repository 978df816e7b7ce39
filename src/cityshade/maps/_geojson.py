"""GeoJSON (a FeatureCollection, a Feature or a bare geometry) with OpenStreetMap-style properties.

Polygons and MultiPolygons (with holes) are buildings unless their properties make them land use
(`natural=water`, `leisure=park`, ...); one without any such tag is read as `building=yes`, which
is what a footprint file means. LineStrings are roads, railways or tree rows by their tags; Points
with `natural=tree` or `highway=street_lamp` are trees and lamps, with `entrance=*` doors and with
`shop=*` shops. Anything else (MultiPoint,
GeometryCollection, null geometry, coordinates that are not number pairs) is counted and skipped.

Coordinates are longitude/latitude (RFC 7946) unless a legacy `crs` member names another system,
or unless most coordinates could not be one (then they are metres, kept as they are).
Numbers too long for a float (thousands of digits) read as infinity and drop their feature.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pyproj
import shapely

from .._json import check_depth
from ..errors import UsageError
from ._assemble import Raw, assemble
from ._model import MapData, ReadReport
from ._projection import LOCAL, in_range
from .features import area_kind, is_building, point_kind

GEOGRAPHIC_SHARE = 0.5  # of coordinates inside lon/lat ranges for a file without `crs` to be lon/lat
LONG_INTEGER = re.compile(r"\d{16}")  # digits past a float's precision: such integers are read as floats


def parse_json(path: Path, text: str):
    """json.loads with one-line errors: position of a syntax error, nesting too deep (checked first)."""
    try:
        check_depth(text)
    except ValueError as exc:
        raise UsageError(f"{path}: JSON nested too deeply to be a map ({exc}; maps nest ten at most)") from None
    # the per-number hook only where a long integer may occur: it costs a Python call per number
    parse_int = (
        (lambda digits: float(digits) if len(digits) > 15 else int(digits)) if LONG_INTEGER.search(text) else None
    )
    try:
        return json.loads(text, parse_int=parse_int)
    except json.JSONDecodeError as exc:
        raise UsageError(f"{path}:{exc.lineno}:{exc.colno}: error: invalid JSON: {exc.msg}") from None


def _positions(value) -> np.ndarray | None:
    """An (n, 2) float array from a list of [x, y(, z)] positions, or None if it is not one."""
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        return None
    if array.ndim != 2 or array.shape[1] not in (2, 3) or len(array) == 0:
        return None
    return array[:, :2]


def _polygon(rings, report: ReadReport, element: str) -> shapely.Polygon | None:
    if not isinstance(rings, list) or not rings:
        return None
    arrays = [_positions(ring) for ring in rings]
    if any(a is None or len(a) < 3 for a in arrays):
        return None
    if not all(np.array_equal(a[0], a[-1]) for a in arrays):
        report.repair("feature", "ring not closed, closed", element)
        arrays = [a if np.array_equal(a[0], a[-1]) else np.vstack([a, a[:1]]) for a in arrays]
    return shapely.Polygon(arrays[0], arrays[1:])


def _geometry(value, report: ReadReport, element: str) -> tuple[shapely.Geometry | None, str]:
    """A shapely geometry and '' or None and why it cannot be one."""
    if not isinstance(value, dict):
        return None, "no geometry"
    kind, coords = value.get("type"), value.get("coordinates")
    if kind == "Polygon":
        polygon = _polygon(coords, report, element)
        return (polygon, "") if polygon is not None else (None, "Polygon coordinates are not rings of [x, y]")
    if kind == "MultiPolygon":
        if not isinstance(coords, list) or not coords:
            return None, "MultiPolygon coordinates are not rings of [x, y]"
        polygons = [_polygon(rings, report, element) for rings in coords]
        if any(p is None for p in polygons):
            return None, "MultiPolygon coordinates are not rings of [x, y]"
        return shapely.MultiPolygon(polygons), ""
    if kind == "LineString":
        line = _positions(coords)
        return (shapely.LineString(line), "") if line is not None and len(line) >= 2 else (None, "bad LineString")
    if kind == "MultiLineString":
        lines = [_positions(c) for c in coords] if isinstance(coords, list) and coords else [None]
        if any(line is None or len(line) < 2 for line in lines):
            return None, "bad MultiLineString"
        return shapely.MultiLineString(lines), ""
    if kind == "Point":
        point = _positions([coords]) if isinstance(coords, list) else None
        return (shapely.Point(point[0]), "") if point is not None else (None, "Point coordinates are not [x, y]")
    return None, f"geometry type {str(kind)[:40]!r} is not read"


def _tags(properties, report: ReadReport, element: str) -> dict[str, str]:
    """Properties as OpenStreetMap-style string tags; lists and objects are dropped and counted."""
    if properties is None:
        return {}
    if not isinstance(properties, dict):
        report.fallback("properties", "not an object (ignored)", element)
        return {}
    tags = {}
    for key, value in properties.items():
        if isinstance(value, bool):
            tags[str(key)] = "yes" if value else "no"
        elif isinstance(value, (str, int, float)):
            tags[str(key)] = str(value)
        elif value is not None:
            report.fallback(str(key)[:40], "a list or object where a value belongs (ignored)", element)
    return tags


def _features(path: Path, data) -> list:
    if isinstance(data, dict) and data.get("type") == "FeatureCollection":
        features = data.get("features")
        if not isinstance(features, list):
            raise UsageError(f"{path}: the FeatureCollection's 'features' is not a list")
        return features
    if isinstance(data, dict) and data.get("type") == "Feature":
        return [data]
    if isinstance(data, dict) and "coordinates" in data:
        return [{"type": "Feature", "geometry": data, "properties": {}}]
    raise UsageError(f"{path}: not GeoJSON (expected a FeatureCollection, a Feature or a geometry)")


def _source_crs(path: Path, data, raws: list[Raw], report: ReadReport):
    """None for lon/lat, a pyproj CRS from a legacy `crs` member, or LOCAL for metres."""
    named = data.get("crs") if isinstance(data, dict) else None
    if isinstance(named, dict) and isinstance(named.get("properties"), dict):
        name = str(named["properties"].get("name", ""))
        try:
            crs = pyproj.CRS.from_user_input(name)
            return None if crs.is_geographic else crs
        except pyproj.exceptions.CRSError:
            report.fallback("crs", "unknown coordinate system (longitude/latitude assumed)", name[:60])
    if not raws:
        return None
    coords = shapely.get_coordinates([raw.geometry for raw in raws])
    coords = coords[np.isfinite(coords).all(axis=1)]
    if len(coords) and in_range(coords[:, 0], coords[:, 1]).mean() < GEOGRAPHIC_SHARE:
        return LOCAL
    return None


def read_geojson(path: Path, text: str) -> MapData:
    data = parse_json(path, text)
    report = ReadReport()
    raws = []
    for index, feature in enumerate(_features(path, data)):
        element = f"feature/{index}"
        if not isinstance(feature, dict):
            report.skip("feature", "not a GeoJSON Feature object", element)
            continue
        if isinstance(feature.get("id"), (str, int)) and not isinstance(feature.get("id"), bool):
            element = f"feature/{index} (id {str(feature['id'])[:40]})"
        tags = _tags(feature.get("properties"), report, element)
        with np.errstate(invalid="ignore"):  # NaN corners are reported by `assemble`, not warned about here
            geometry, why = _geometry(feature.get("geometry"), report, element)
        if geometry is None:
            report.skip("feature", why, element)
            continue
        kind = shapely.get_type_id(geometry)
        if kind in (3, 6) and not is_building(tags) and area_kind(tags) is None:
            tags["building"] = "yes"  # a footprint file's polygons are buildings
        elif kind == 0 and point_kind(tags) is None:
            report.skip("feature", "a Point that is no tree, street lamp, entrance or shop", element)
            continue
        raws.append(Raw(element, geometry, tags))
    return assemble(path, raws, report, _source_crs(path, data, raws, report))
