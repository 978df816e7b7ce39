"""CityJSON 1.0, 1.1 and 2.0 documents and CityJSONSeq (`.city.jsonl`), drawn as given.

Of each city object one geometry is read: the highest LoD it has, or the one asked for (`lod`, "2"
picks the highest of 2, 2.0, 2.1, 2.2 ...); the geometries and their checks are _cityjson_geometry.py.
Coordinates: `transform` scale and translate (a 1.1/2.0 file without one is read as coordinates,
counted), `metadata.referenceSystem` through pyproj (a compound system such as EPSG:7415 gives its
plan part; heights stay as given), metres kept as they are where none is named.

- Buildings (Building, BuildingPart, BuildingInstallation, BuildingConstructiveElement): a record per
  object with geometry, its faces by semantic type in `MapBuilding.surfaces` with heights as given
  (drawn as they are: maps/_given.py), its footprint the union of its GroundSurfaces seen from above
  (of all its faces without them), `height`, `min_height` and the roof's measured from the faces
  above the ground of its whole building (parts included). A Building without geometry is drawn by
  its parts (its outline, their union, is replaced by them). Attributes `storeysAboveGround`,
  `roofType`, `function`, `usage`, `yearOfConstruction`, `measuredHeight` are read as the
  OpenStreetMap tags they mean; attributes named like tags (`roof:shape`, ...) as those tags.
- Every other city object (Road, LandUse, PlantCover, WaterBody, Bridge, ...) becomes a CityObject
  record with its faces (maps/features/city_objects.py draws them).
- CityJSONSeq: the first line is the header (version, transform, CRS, templates), each further line
  one CityJSONFeature (a building with its parts) read on its own, so memory follows the largest
  feature, not the file. A line that is not a feature is skipped and counted with its line number.
"""

from __future__ import annotations

import gc
import json
import re
from collections import Counter
from collections.abc import Iterable
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from .._json import check_depth
from ..errors import UsageError
from ._assemble import Raw, assemble
from ._cityjson_geometry import NO_TEMPLATES, Face, Templates, facing_out, geometry_faces, merged_walls, vertex_array
from ._geojson import parse_json
from ._model import MapData, ReadReport
from ._projection import LOCAL

BUILDING_TYPES = ("Building", "BuildingPart", "BuildingInstallation", "BuildingConstructiveElement")
VERSIONS = ("1.0", "1.1", "2.0")
FLAT_ROOF = 0.3  # metres: roof faces within this height of each other make a flat roof
_EPSG = re.compile(r"EPSG(?:/0/|::|:)(\d+)", re.IGNORECASE)
# CityJSON attributes -> the OpenStreetMap tag they mean (maps/_tags.py reads the tags)
ATTRIBUTE_TAGS = {
    "storeysAboveGround": "building:levels",
    "storeysBelowGround": "building:levels:underground",
    "roofType": "roof:type",
    "function": "building:function",
    "usage": "building:use",
    "yearOfConstruction": "start_date",
    "measuredHeight": "measured_height",
}
CLASS_ATTRIBUTES = ("class", "function", "usage", "type", "bgt_fysiekvoorkomen", "plus_fysiekvoorkomen")


@dataclass
class _Header:
    version: str
    scale: np.ndarray
    translate: np.ndarray
    transformed: bool  # False: the file has no transform
    crs: str | None
    templates: Templates


def _header(path: Path, data: dict, report: ReadReport) -> _Header:
    version = str(data.get("version", ""))
    if version not in VERSIONS:
        report.fallback("CityJSON", f"version {version[:12]!r} is not 1.0, 1.1 or 2.0 (read as 2.0)", str(path.name))
    transform = data.get("transform")
    scale, translate = np.ones(3), np.zeros(3)
    if isinstance(transform, dict):
        try:
            scale = np.asarray(transform.get("scale", (1, 1, 1)), dtype=np.float64).reshape(3)
            translate = np.asarray(transform.get("translate", (0, 0, 0)), dtype=np.float64).reshape(3)
        except (TypeError, ValueError, OverflowError):
            raise UsageError(f"{path}: 'transform' needs 'scale' and 'translate' of three numbers each") from None
        if not (np.isfinite(scale).all() and np.isfinite(translate).all()) or not np.all(scale != 0):
            raise UsageError(f"{path}: 'transform' scale must be finite and non-zero, translate finite")
    elif version != "1.0":
        report.repair("CityJSON", "no 'transform': vertices read as coordinates", str(path.name))
    metadata = data.get("metadata") if isinstance(data.get("metadata"), dict) else {}
    return _Header(version, scale, translate, isinstance(transform, dict), _crs(metadata, report), _templates(data))


def _crs(metadata: dict, report: ReadReport) -> str | None:
    """The file's system as pyproj reads it ('EPSG:n'), None where none is named (metres as they are)."""
    named = metadata.get("referenceSystem")
    if named is None:
        return None
    match = _EPSG.search(str(named))
    if match is None:
        report.fallback("crs", "referenceSystem names no EPSG code (coordinates taken as metres)", str(named)[:60])
        return None
    return f"EPSG:{match.group(1)}"  # one pyproj cannot use is counted where it projects (maps/_assemble.py)


def _templates(data: dict) -> Templates:
    templates = data.get("geometry-templates")
    if not isinstance(templates, dict):
        return NO_TEMPLATES
    vertices = vertex_array(templates.get("vertices-templates"))
    geometries = templates.get("templates")
    if vertices is None or not isinstance(geometries, list):
        return NO_TEMPLATES
    return Templates(geometries, vertices)


def _lod(geometry: dict, templates: Templates) -> str:
    if geometry.get("type") == "GeometryInstance":
        template = geometry.get("template")
        if isinstance(template, int) and 0 <= template < len(templates.geometries):
            inner = templates.geometries[template]
            geometry = inner if isinstance(inner, dict) else geometry
    return str(geometry.get("lod", "0"))


def _lod_key(lod: str) -> tuple[float, str]:
    try:
        return float(lod), lod
    except ValueError:
        return -1.0, lod


def _chosen(obj: dict, lod: str | None, templates: Templates) -> tuple[dict | None, bool]:
    """(the geometry to draw or None, whether the object has any geometry at all)."""
    geometries = [g for g in _listed(obj.get("geometry")) if isinstance(g, dict)]
    if lod is not None:
        wanted = [g for g in geometries if _lod(g, templates) == lod or _lod(g, templates).split(".")[0] == lod]
        return (max(wanted, key=lambda g: _lod_key(_lod(g, templates))) if wanted else None), bool(geometries)
    if not geometries:
        return None, False
    return max(geometries, key=lambda g: _lod_key(_lod(g, templates))), True


def _listed(value) -> list:
    return value if isinstance(value, list) else []


def _tags(obj: dict) -> dict[str, str]:
    attributes = obj.get("attributes")
    if not isinstance(attributes, dict):
        return {}
    tags = {}
    for key, value in attributes.items():
        if isinstance(value, (str, int, float)) and not isinstance(value, bool):
            tags[ATTRIBUTE_TAGS.get(str(key), str(key))] = str(value)
    for key in ("building:function", "building:use"):  # a use named in words is the building's kind
        word = tags.get(key, "").strip().lower()
        if word.isalpha():
            tags.setdefault("building", word)
    return tags


def _kind(obj: dict) -> str | None:
    attributes = obj.get("attributes") if isinstance(obj.get("attributes"), dict) else {}
    for key in CLASS_ATTRIBUTES:
        if isinstance(attributes.get(key), (str, int)) and not isinstance(attributes.get(key), bool):
            return str(attributes[key])[:60]
    return None


class _Reader:
    """City objects -> raw features, a document (or a CityJSONSeq feature) at a time."""

    def __init__(self, path: Path, header: _Header, lod: str | None, report: ReadReport):
        self.path, self.header, self.lod, self.report = path, header, lod, report
        self.raws: list[Raw] = []
        self.types: dict[str, str] = {}  # source id -> CityJSON type of what was read

    def vertices(self, value, element: str) -> np.ndarray:
        vertices = vertex_array(value)
        if vertices is None:
            raise UsageError(f"{self.path}: {element}: 'vertices' is not a list of [x, y, z] numbers")
        with np.errstate(over="ignore", invalid="ignore"):
            return vertices * self.header.scale + self.header.translate

    def faces(self, name: str, obj: dict, vertices: np.ndarray) -> list[Face] | None:
        element = f"CityObject/{name}"
        geometry, has_any = _chosen(obj, self.lod, self.header.templates)
        if geometry is None:
            if has_any:
                self.report.skip(str(obj.get("type"))[:40], f"no geometry at LoD {self.lod}", element)
            return None
        try:
            faces = geometry_faces(geometry, vertices, self.header.templates, self.report, element)
        except (TypeError, ValueError, OverflowError, IndexError) as exc:
            self.report.skip(str(obj.get("type"))[:40], f"malformed geometry ({str(exc)[:60]})", element)
            return None
        if not faces:
            self.report.skip(str(obj.get("type"))[:40], "no surface left to draw", element)
            return None
        return faces, _lod(geometry, self.header.templates)

    def add(self, objects: dict, vertices: np.ndarray) -> None:
        read = {}
        for name, obj in objects.items():
            if not isinstance(obj, dict) or not isinstance(obj.get("type"), str):
                self.report.skip("CityObject", "not an object with a 'type'", f"CityObject/{name}")
                continue
            found = self.faces(name, obj, vertices)
            if found is not None:
                read[name] = found
        buildings = [name for name in read if objects[name]["type"] in BUILDING_TYPES]
        merged = dict(zip(buildings, merged_walls([read[name][0] for name in buildings])))
        for name, obj in objects.items():
            if not isinstance(obj, dict) or not isinstance(obj.get("type"), str):
                continue
            self._missing_links(name, obj, objects)
            if obj["type"] in BUILDING_TYPES:
                self._building(name, obj, objects, read, merged)
            elif name in read:
                self._city_object(name, obj, read[name])

    def _missing_links(self, name: str, obj: dict, objects: dict) -> None:
        for key in ("parents", "children"):
            for other in _listed(obj.get(key)):
                if not isinstance(other, str) or other not in objects:
                    why = f"'{key}' names {str(other)[:40]!r}, which the file does not define (ignored)"
                    self.report.repair("CityObject", why, f"CityObject/{name}")

    def _city_object(self, name: str, obj: dict, found) -> None:
        faces, lod = found
        attributes = obj.get("attributes") if isinstance(obj.get("attributes"), dict) else {}
        fixed = {"city_object": (obj["type"], _kind(obj), lod, attributes), "faces": faces}
        plan = shapely.multipoints(np.vstack([f.ring[:, :2] for f in faces]))  # walls alone have no outline
        self.raws.append(Raw(f"CityObject/{name}", plan, {}, fixed))

    def _building(self, name: str, obj: dict, objects: dict, read: dict, merged: dict) -> None:
        children = [c for c in _listed(obj.get("children")) if isinstance(c, str) and c in objects]
        parents = [p for p in _listed(obj.get("parents")) if isinstance(p, str) and isinstance(objects.get(p), dict)]
        drawn_parts = [c for c in children if c in read]
        family = [name, *children]
        if parents:  # the parent and all its parts share one ground
            family = [parents[0], *_listed(objects[parents[0]].get("children")), *family]
        lows = [min(float(f.ring[:, 2].min()) for f in read[n][0]) for n in family if isinstance(n, str) and n in read]
        if name not in read:
            if drawn_parts:  # its outline: the parts' union, replaced by them (maps/_assemble.py)
                faces = [face for part in drawn_parts for face in read[part][0]]
                self._add_building(name, obj, faces, None, min(lows), parents)
            elif not children and name not in read and not _listed(obj.get("geometry")):
                self.report.skip("building", "no geometry and no parts with geometry", f"CityObject/{name}")
            return
        lod = read[name][1]
        self._add_building(name, obj, merged[name], lod, min(lows), parents)

    def _add_building(self, name, obj, faces: list[Face], lod, ground: float, parents: list[str]) -> None:
        element = f"CityObject/{name}"
        footprint = _outline([f for f in faces if f.semantic == "GroundSurface"] or faces)
        if footprint.is_empty:
            self.report.skip("building", "no face with an area seen from above", element)
            return
        faces = facing_out(faces, footprint, self.report, element)
        surfaces: dict[str, list[np.ndarray]] = {}
        for face in faces:
            if face.semantic != "ClosureSurface":  # closes a solid where nothing is built: not drawn
                surfaces.setdefault(face.semantic or "unclassified", []).append(face.ring)
        points = np.vstack([f.ring for f in faces])
        top, bottom = float(points[:, 2].max()), max(float(points[:, 2].min()), ground)  # merged walls: snapped
        tags = _tags(obj)
        tags.setdefault("building:part" if obj["type"] != "Building" else "building", "yes")
        if obj["type"] != "Building":
            tags.pop("building", None)
        fixed = {
            "height": top - ground,
            "min_height": bottom - ground,
            **_roof(surfaces, top),
            "ground": ground,
            "lod": lod,
            "surfaces": surfaces if lod is not None else None,
        }
        parent = f"CityObject/{parents[0]}" if parents and obj["type"] != "Building" else None
        self.raws.append(Raw(element, footprint, tags, fixed, parent))
        self.types[element] = obj["type"]


def _outline(faces: list[Face]) -> shapely.Geometry:
    """The faces' union seen from above."""
    plan = np.vstack([f.ring[:, :2] for f in faces])
    which = np.repeat(np.arange(len(faces)), [len(f.ring) for f in faces])
    polygons = shapely.polygons(shapely.linearrings(plan, indices=which))
    bad = ~shapely.is_valid(polygons)  # seen from above, walls are lines and many roofs self-touch
    polygons[bad] = shapely.make_valid(polygons[bad])
    polygons = [p for p in shapely.get_parts(polygons) if shapely.get_type_id(p) in (3, 6) and p.area > 0.0]
    return shapely.union_all(polygons) if polygons else shapely.Polygon()


def _roof(surfaces: dict[str, list[np.ndarray]], top: float) -> dict:
    roofs = surfaces.get("RoofSurface")
    if not roofs:
        return {}
    lowest = min(float(ring[:, 2].min()) for ring in roofs)
    if top - lowest <= FLAT_ROOF:
        return {"roof_shape": "flat", "roof_height": 0.0}
    return {"roof_height": top - lowest}


def _document(path: Path, data, what: str = "CityJSON") -> dict:
    if not isinstance(data, dict) or data.get("type") != what or not isinstance(data.get("CityObjects"), dict):
        raise UsageError(f"{path}: not {what} (expected type '{what}' with 'CityObjects')")
    return data


@contextmanager
def _collector_paused():
    """The cyclic garbage collector off while a file's objects are read: the parsed JSON and the faces
    are millions of live objects that hold no cycles, and each full collection walks all of them
    (reading a 5,000-building tile took a third longer with it on)."""
    was_on = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_on:
            gc.enable()


def read_cityjson(path: Path, text: str, lod: str | None = None) -> MapData:
    """A CityJSON document (see the module docstring)."""
    with _collector_paused():
        return _read_document(path, text, lod)


def _read_document(path: Path, text: str, lod: str | None) -> MapData:
    data = _document(path, parse_json(path, text))
    report = ReadReport()
    reader = _Reader(path, _header(path, data, report), lod, report)
    with np.errstate(over="ignore", invalid="ignore"):
        reader.add(data["CityObjects"], reader.vertices(data.get("vertices"), "the document"))
    return _finish(path, reader)


def read_cityjson_seq(path: Path, lines: Iterable[str], lod: str | None = None) -> MapData:
    """A CityJSONSeq stream: a header line, then one CityJSONFeature per line."""
    with _collector_paused():
        return _read_sequence(path, lines, lod)


def _read_sequence(path: Path, lines: Iterable[str], lod: str | None) -> MapData:
    lines = iter(lines)
    first = next(lines, "")
    data = _document(path, _line(path, 1, first))
    report = ReadReport()
    reader = _Reader(path, _header(path, data, report), lod, report)
    for number, line in enumerate(lines, start=2):
        if not line.strip():
            continue
        try:
            feature = _line(path, number, line)
        except UsageError as exc:
            report.skip("CityJSONFeature", str(exc).split(": ", 2)[-1][:80], f"line {number}")
            continue
        if isinstance(feature, dict) and feature.get("type") == "CityJSON":
            why = f"a second header (version {str(feature.get('version'))[:10]}) inside the sequence, ignored"
            report.skip("CityJSON", why, f"line {number}")
            continue
        if not isinstance(feature, dict) or feature.get("type") != "CityJSONFeature":
            report.skip("CityJSONFeature", "line is not a CityJSONFeature", f"line {number}")
            continue
        objects = feature.get("CityObjects")
        vertices = vertex_array(feature.get("vertices"))
        if not isinstance(objects, dict) or vertices is None:
            report.skip("CityJSONFeature", "no 'CityObjects' object or 'vertices' list", f"line {number}")
            continue
        with np.errstate(over="ignore", invalid="ignore"):
            reader.add(objects, vertices * reader.header.scale + reader.header.translate)
    return _finish(path, reader)


def _line(path: Path, number: int, line: str):
    try:
        check_depth(line)
        return json.loads(line)
    except ValueError as exc:  # JSONDecodeError is one
        column = f":{exc.colno}" if isinstance(exc, json.JSONDecodeError) else ""
        raise UsageError(f"{path}:{number}{column}: error: invalid JSON line ({str(exc)[:60]})") from None


def _finish(path: Path, reader: _Reader) -> MapData:
    with np.errstate(over="ignore", invalid="ignore"):
        data = assemble(path, reader.raws, reader.report, reader.header.crs or LOCAL)
    grounds = [b.ground for b in data.buildings if b.surfaces is not None]
    data.ground_level = min(grounds) if grounds else 0.0
    data.drawn_types = Counter(reader.types[s] for s in {b.source_id for b in data.buildings} if s in reader.types)
    data.drawn_types.update(o.type for o in data.city_objects)
    return data
