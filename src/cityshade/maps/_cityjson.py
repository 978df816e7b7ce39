"""CityJSON 1.1 / 2.0: Building and BuildingPart objects with LoD1/LoD2 Solid or MultiSurface geometry.

Of each object the geometry with the highest LoD is read. What is kept:
- the footprint: the union of the GroundSurface faces seen from above, or (without semantics) of
  all faces seen from above; each polygon of it becomes one record;
- heights from the geometry itself: `height` = top - ground and `min_height` = bottom - ground,
  where the ground is the lowest point of the whole building (parts included), and `roof_height` =
  top - lowest roof point when the RoofSurface faces are not all level (`roof_shape=flat` when they are);
- every face's outer ring by semantic type in `MapBuilding.surfaces` (z above the ground), for
  stages that can draw the given walls and roofs instead of rebuilding them from the outline.
Attributes named like OpenStreetMap tags (`roof:shape`, `building:colour`, ...) are read as tags.
Coordinates use `metadata.referenceSystem` when it names an EPSG code, else they are metres.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import shapely

from ..errors import UsageError
from ._assemble import Raw, assemble
from ._geojson import parse_json
from ._model import MapData, ReadReport
from ._projection import LOCAL

BUILDING_TYPES = ("Building", "BuildingPart")
FLAT_ROOF = 0.3  # metres: roof faces within this height of each other make a flat roof
_EPSG = re.compile(r"EPSG(?:/0/|::|:)(\d+)", re.IGNORECASE)


def _vertices(path: Path, data: dict) -> np.ndarray:
    try:
        vertices = np.asarray(data.get("vertices"), dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise UsageError(f"{path}: 'vertices' is not a list of [x, y, z] numbers") from None
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise UsageError(f"{path}: 'vertices' is not a list of [x, y, z] numbers")
    transform = data.get("transform")
    if isinstance(transform, dict):
        try:
            scale = np.asarray(transform.get("scale", (1, 1, 1)), dtype=np.float64).reshape(3)
            translate = np.asarray(transform.get("translate", (0, 0, 0)), dtype=np.float64).reshape(3)
        except (TypeError, ValueError):
            raise UsageError(f"{path}: 'transform' needs 'scale' and 'translate' of three numbers") from None
        vertices = vertices * scale + translate
    return vertices


def _faces(geometry: dict) -> list[tuple[list, object]]:
    """(rings as index lists, semantic value) of every face of a Solid, MultiSolid or MultiSurface."""
    kind, boundaries = geometry.get("type"), geometry.get("boundaries")
    values = (geometry.get("semantics") or {}).get("values")
    if kind in ("MultiSurface", "CompositeSurface"):
        shells, shell_values = [boundaries], [values]
    elif kind == "Solid":
        shells, shell_values = boundaries[:1], [values[0] if values else None]
    elif kind in ("MultiSolid", "CompositeSolid"):
        shells = [solid[0] for solid in boundaries]
        shell_values = [v[0] if v else None for v in values] if values else [None] * len(shells)
    else:
        raise ValueError(f"geometry type {str(kind)[:40]!r}")
    return [
        (face, face_values[i] if face_values else None)
        for shell, face_values in zip(shells, shell_values)
        for i, face in enumerate(shell)
    ]


def _listed(value) -> list:
    return value if isinstance(value, list) else []


def _names(value, known: dict) -> list[str]:
    """The object names in a `children` or `parents` list that the file defines."""
    return [name for name in _listed(value) if isinstance(name, str) and name in known]


def _best_geometry(obj: dict) -> dict | None:
    geometries = [g for g in _listed(obj.get("geometry")) if isinstance(g, dict) and g.get("boundaries")]
    if not geometries:
        return None

    def lod(g):
        try:
            return float(g.get("lod", 0))
        except (TypeError, ValueError):
            return 0.0

    return max(geometries, key=lod)


def _surfaces(geometry: dict, vertices: np.ndarray) -> dict[str, list[np.ndarray]]:
    names = [
        s.get("type", "unclassified") if isinstance(s, dict) else "unclassified"
        for s in (geometry.get("semantics") or {}).get("surfaces", [])
    ]
    surfaces: dict[str, list[np.ndarray]] = {}
    for rings, value in _faces(geometry):
        name = names[value] if isinstance(value, int) and 0 <= value < len(names) else "unclassified"
        indices = np.asarray(rings[0], dtype=np.int64)
        if indices.ndim != 1 or len(indices) < 3 or indices.min() < 0:
            raise ValueError("a face's ring is not a list of at least 3 vertex indices")
        surfaces.setdefault(name, []).append(vertices[indices])
    if not surfaces:
        raise ValueError("no faces")
    return surfaces


def _footprint(surfaces: dict[str, list[np.ndarray]]) -> shapely.Geometry:
    faces = surfaces.get("GroundSurface") or [ring for rings in surfaces.values() for ring in rings]
    polygons = [shapely.make_valid(shapely.Polygon(ring[:, :2])) for ring in faces if len(ring) >= 3]
    return shapely.union_all([p for p in polygons if p.area > 0.0])


def _roof(surfaces: dict[str, list[np.ndarray]], top: float) -> dict:
    roofs = surfaces.get("RoofSurface")
    if not roofs:
        return {}
    lowest = min(float(ring[:, 2].min()) for ring in roofs)
    if top - lowest <= FLAT_ROOF:
        return {"roof_shape": "flat", "roof_height": 0.0}
    return {"roof_height": top - lowest}


def _tags(obj: dict) -> dict[str, str]:
    attributes = obj.get("attributes")
    if not isinstance(attributes, dict):
        return {}
    return {
        str(k): str(v) for k, v in attributes.items() if isinstance(v, (str, int, float)) and not isinstance(v, bool)
    }


def read_cityjson(path: Path, text: str) -> MapData:
    # coordinates that overflow or are NaN are skipped and counted where they are used, not warned about
    with np.errstate(over="ignore", invalid="ignore"):
        return _read_cityjson(path, text)


def _read_cityjson(path: Path, text: str) -> MapData:
    data = parse_json(path, text)
    if not isinstance(data, dict) or data.get("type") != "CityJSON" or not isinstance(data.get("CityObjects"), dict):
        raise UsageError(f"{path}: not CityJSON (expected type 'CityJSON' with 'CityObjects')")
    vertices = _vertices(path, data)
    objects = data["CityObjects"]
    report = ReadReport()
    read: dict[str, tuple[dict, np.ndarray]] = {}
    for name, obj in objects.items():
        element = f"CityObject/{name}"
        if not isinstance(obj, dict) or obj.get("type") not in BUILDING_TYPES:
            report.skip(
                "CityObject",
                f"type {str(obj.get('type') if isinstance(obj, dict) else obj)[:30]!r} "
                "is not a Building or BuildingPart",
                element,
            )
            continue
        geometry = _best_geometry(obj)
        if geometry is None:
            continue  # a building made only of parts: its outline is the union of theirs (below)
        try:
            surfaces = _surfaces(geometry, vertices)
        except (IndexError, TypeError, ValueError, KeyError, AttributeError, OverflowError) as exc:
            report.skip("building", f"malformed geometry ({str(exc)[:60]})", element)
            continue
        points = np.vstack([ring for rings in surfaces.values() for ring in rings])
        if not np.isfinite(points).all():
            report.skip("building", "coordinate not finite", element)
            continue
        read[name] = (surfaces, points)
    raws = []
    for name, obj in objects.items():
        if not isinstance(obj, dict) or obj.get("type") not in BUILDING_TYPES:
            continue
        family = [name] + _names(obj.get("children"), read)
        parents = [p for p in _names(obj.get("parents"), objects) if isinstance(objects[p], dict)]
        # the parent and its children, and this object's own family (a parent need not list its parts)
        siblings = [parents[0]] + _names(objects[parents[0]].get("children"), objects) if parents else []
        ground_family = siblings + family
        lows = [read[n][1][:, 2].min() for n in ground_family if n in read]
        if name not in read and len(family) == 1:
            if _best_geometry(obj) is None:
                report.skip("building", "no geometry and no parts with geometry", f"CityObject/{name}")
            continue  # a malformed geometry is counted above
        ground = float(min(lows))
        members = [name] if name in read else family[1:]
        surfaces = {}
        for member in members:
            for kind, rings in read[member][0].items():
                surfaces.setdefault(kind, []).extend(ring - (0.0, 0.0, ground) for ring in rings)
        points = np.vstack([read[m][1] for m in members])
        top, bottom = float(points[:, 2].max()), float(points[:, 2].min())
        footprint = _footprint(surfaces)
        if footprint.is_empty:
            report.skip("building", "no face with an area seen from above", f"CityObject/{name}")
            continue
        tags = _tags(obj)
        tags.setdefault("building:part" if obj["type"] == "BuildingPart" else "building", "yes")
        fixed = {"height": top - ground, "min_height": bottom - ground, **_roof(surfaces, top - ground)}
        fixed["surfaces"] = surfaces if name in read else None
        parent = f"CityObject/{parents[0]}" if parents and obj["type"] == "BuildingPart" else None
        raws.append(Raw(f"CityObject/{name}", footprint, tags, fixed, parent))
    metadata = data.get("metadata") if isinstance(data.get("metadata"), dict) else {}
    match = _EPSG.search(str(metadata.get("referenceSystem", "")))
    return assemble(path, raws, report, f"EPSG:{match.group(1)}" if match else LOCAL)
