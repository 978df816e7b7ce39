"""Real building footprints from GeoJSON or OpenStreetMap XML, extruded by their height or level tags.

Polygons in longitude/latitude are projected to local metres (equirectangular about the data's
centre; north is -z). Each footprint gets its own object space, turned to the footprint's
minimum rotated rectangle, so interior-mapped rooms run along its walls.
"""

from __future__ import annotations

import json
import re
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import numpy as np
import shapely

from ..errors import CityshadeError
from ._buildings import BuildingMass
from ._camera import Camera
from ._city import City

EARTH_RADIUS = 6_371_000.0
DEFAULT_HEIGHT = 10.0
LEVEL_HEIGHT = 3.2
STYLES = 8


def _number(value) -> float | None:
    """'12', 12, '12 m', '12.5m' -> float; anything else -> None."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    if isinstance(value, str):
        match = re.match(r"^\s*(\d+(?:\.\d+)?)\s*(m|metres|meters)?\s*$", value)
        if match:
            return float(match.group(1))
    return None


def _height(properties: dict) -> tuple[float, float]:
    """(height, floor height) from 'height' or 'building:levels' / 'levels' properties."""
    levels = _number(properties.get("building:levels", properties.get("levels")))
    height = _number(properties.get("height"))
    if height is None:
        height = levels * LEVEL_HEIGHT if levels else DEFAULT_HEIGHT
    floor_height = height / levels if levels else LEVEL_HEIGHT
    return max(height, 2.5), float(np.clip(floor_height, 2.5, 6.0))


def _rings(geometry: dict, where: str) -> list[list]:
    kind = geometry.get("type") if isinstance(geometry, dict) else None
    coords = geometry.get("coordinates") if isinstance(geometry, dict) else None
    if kind == "Polygon":
        return [coords[0]]
    if kind == "MultiPolygon":
        return [polygon[0] for polygon in coords]
    raise CityshadeError(f"{where}: geometry type {kind!r} is not a footprint; use Polygon or MultiPolygon")


def _read_features(path: Path) -> list:
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise CityshadeError(f"{path}: cannot read GeoJSON ({exc})") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise CityshadeError(f"{path}:{exc.lineno}:{exc.colno}: error: invalid JSON: {exc.msg}") from None
    features = data.get("features") if isinstance(data, dict) else None
    if not isinstance(features, list) or not features:
        raise CityshadeError(f"{path}: expected a GeoJSON FeatureCollection with at least one feature")
    return features


def _mass(points: np.ndarray, height: float, floor_height: float, seed: int) -> BuildingMass:
    polygon = shapely.Polygon(points).buffer(0)
    rectangle = np.asarray(polygon.minimum_rotated_rectangle.exterior.coords)[:4]
    edges = np.diff(np.vstack([rectangle, rectangle[:1]]), axis=0)
    longest = edges[np.argmax(np.linalg.norm(edges, axis=1))]
    yaw = float(np.arctan2(-longest[1], longest[0]))  # turns local +x onto the longest side
    c, s = np.cos(yaw), np.sin(yaw)
    outline = np.asarray(polygon.exterior.coords)[:-1]
    local = np.stack([c * outline[:, 0] - s * outline[:, 1], s * outline[:, 0] + c * outline[:, 1]], axis=1)
    low = local.min(axis=0)
    local -= low
    origin = (c * low[0] + s * low[1], -s * low[0] + c * low[1])
    return BuildingMass("prism", origin, tuple(map(tuple, local)), height, yaw=yaw, floor_height=floor_height,
                        seed=seed, style=seed % STYLES)


def load_geojson(path: Path | str) -> City:
    """A City of the file's polygons (lon/lat or projected metres), with 'aerial' and 'street' views."""
    path = Path(path)
    rings, tags = [], []
    for index, feature in enumerate(_read_features(path)):
        where = f"{path}: feature {index}"
        if not isinstance(feature, dict) or "geometry" not in feature:
            raise CityshadeError(f"{where}: not a GeoJSON Feature (no 'geometry')")
        for ring in _rings(feature["geometry"], where):
            try:
                points = np.asarray(ring, dtype=np.float64)[:, :2]
            except (TypeError, ValueError, IndexError):
                raise CityshadeError(f"{where}: coordinates must be [x, y] number pairs") from None
            if len(points) < 4:
                raise CityshadeError(f"{where}: a footprint needs at least 3 corners")
            rings.append(points)
            tags.append(_height(feature.get("properties") or {}))
    return _city(path, rings, tags)


def load_osm(path: Path | str) -> City:
    """A City of the closed ways tagged `building` in an OpenStreetMap XML extract."""
    path = Path(path)
    try:
        root = ElementTree.parse(path).getroot()
    except ElementTree.ParseError as exc:
        line, column = exc.position
        raise CityshadeError(f"{path}:{line}:{column + 1}: error: invalid OSM XML: {exc}") from None
    except OSError as exc:
        raise CityshadeError(f"{path}: cannot read OSM XML ({exc})") from None
    nodes = {n.get("id"): (float(n.get("lon")), float(n.get("lat"))) for n in root.iter("node")}
    rings, tags = [], []
    for way in root.iter("way"):
        properties = {t.get("k"): t.get("v") for t in way.iter("tag")}
        refs = [r.get("ref") for r in way.iter("nd")]
        if "building" not in properties or len(refs) < 4 or refs[0] != refs[-1]:
            continue
        missing = [r for r in refs if r not in nodes]
        if missing:
            raise CityshadeError(f"{path}: way {way.get('id')} refers to node {missing[0]}, which the extract lacks")
        rings.append(np.asarray([nodes[r] for r in refs]))
        tags.append(_height(properties))
    if not rings:
        raise CityshadeError(f"{path}: no closed way tagged 'building'")
    return _city(path, rings, tags)


def load_footprints(path: Path | str) -> City:
    """GeoJSON (.geojson, .json) or OpenStreetMap XML (.osm) by the file's extension."""
    path = Path(path)
    if path.suffix.lower() == ".osm":
        return load_osm(path)
    if path.suffix.lower() in (".geojson", ".json"):
        return load_geojson(path)
    raise CityshadeError(f"{path}: unknown footprint format {path.suffix!r}; use .geojson, .json or .osm")


def _city(path: Path, rings: list[np.ndarray], tags: list[tuple[float, float]]) -> City:
    everything = np.vstack(rings)
    geographic = np.all(np.abs(everything[:, 0]) <= 180) and np.all(np.abs(everything[:, 1]) <= 90)
    centre = everything.mean(axis=0)
    masses, placed = [], []
    for seed, (ring, (height, floor_height)) in enumerate(zip(rings, tags)):
        if geographic:  # x east, z south (north is -z)
            metres = np.stack([(ring[:, 0] - centre[0]) * np.cos(np.radians(centre[1])),
                               -(ring[:, 1] - centre[1])], axis=1) * np.radians(1.0) * EARTH_RADIUS
        else:
            metres = np.stack([ring[:, 0] - centre[0], -(ring[:, 1] - centre[1])], axis=1)
        if shapely.Polygon(metres).buffer(0).area < 4.0:
            continue  # slivers and degenerate rings have no rooms
        masses.append(_mass(metres, height, floor_height, seed))
        placed.append(metres)
    if not masses:
        raise CityshadeError(f"{path}: no footprint larger than 4 square metres")
    placed = np.vstack(placed)
    x0, z0 = placed.min(axis=0) - 40.0
    x1, z1 = placed.max(axis=0) + 40.0
    radius = 0.5 * float(np.hypot(x1 - x0, z1 - z0))
    tallest = max(m.height for m in masses)
    viewpoints = {
        "aerial": Camera((x0, tallest + 0.6 * radius, z1), ((x0 + x1) / 2, 0.0, (z0 + z1) / 2), fov_y=55.0),
        "street": Camera((x0 + 10.0, 1.7, z1 - 10.0), ((x0 + x1) / 2, tallest / 3, (z0 + z1) / 2), fov_y=65.0),
    }
    return City(path.stem, 0, masses, [], (float(x0), float(z0), float(x1), float(z1)), viewpoints)
