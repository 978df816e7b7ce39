"""Features as a reader found them (source coordinates + OpenStreetMap-style tags) -> MapData in local metres.

Every reader produces the same raw features, so every format shares one set of rules:

- geometry: coordinates that are not finite (or not on the Earth, for longitude/latitude) drop the
  feature; invalid polygons are repaired with `shapely.make_valid`, keeping the polygonal parts
  (each becomes its own record); outlines under MIN_AREA are skipped; outlines with more than
  MAX_VERTICES corners are simplified to SIMPLIFY_TOLERANCE (a 16,000-corner outline adds nothing
  a 10 cm tolerance does not keep). All of it is counted in `MapData.report` with the element id.
- buildings: `building=*` is an outline, `building:part=*` a part; a part's parent is the outline
  that holds its inner point. An outline is drawn only where no part stands (its `remainder`: the
  outline minus its parts, keeping the outline's tags; none where the parts cover at least
  PARTS_COVER of its area) and under parts that float (`beneath_parts`: drawn up to their base), so
  no wall of the outline stands where a part's wall does; pieces thinner than SLIVER_WIDTH or under
  SLIVER_AREA are dropped (counted). An outline with neither is `replaced_by_parts`.
  `building=roof` (or `building:part=roof`) has no walls.
- everything else is read by the map features (maps/features/, one module each, with the tags they
  read and their defaults): roads, railways, trees, lamps, entrances and shops; polygons by the area
  tags of the features (features.AREA_TAGS).
- areas: the coastline (land on its left) splits the data's bounds into land and
  sea, and the sea faces become water areas. A coastline the extract cuts off inside the bounds is
  carried on straight from its last segment to the edge; where pieces still leave a face unclosed,
  the side of the nearest coastline decides the whole face.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pyproj
import shapely

from ._model import Area, CityObject, MapBuilding, MapData, ReadReport
from ._projection import LOCAL, LocalMetres, Projection, in_range
from .features import FEATURES, area_kind, is_building
from .features.buildings import add_buildings

MIN_AREA = 0.5  # square metres
MAX_VERTICES = 4096
SIMPLIFY_TOLERANCE = 0.1  # metres
PARTS_COVER = 0.9
SLIVER_WIDTH = 1.0  # metres: a remainder of an outline beside its parts thinner than this is a sliver
SLIVER_AREA = 4.0  # square metres: a smaller piece of that remainder is one too


@dataclass
class Raw:
    """One feature in source coordinates: a (Multi)Polygon, LineString or Point, and its tags."""

    source_id: str
    geometry: shapely.Geometry
    tags: dict[str, str]
    fixed: dict = field(default_factory=dict)  # attributes a reader measured from geometry (CityJSON heights)
    parent: str | None = None  # a part's outline when the format names it (CityJSON); else found by position


def _declared_bounds(projection, declared) -> tuple[float, float, float, float] | None:
    """The file's declared lon/lat extent in map metres (the box around its projected corners)."""
    if declared is None:
        return None
    x0, y0, x1, y1 = declared
    corners = projection.points(np.array([(x0, y0), (x0, y1), (x1, y1), (x1, y0)]))
    if not np.isfinite(corners).all():
        return None
    return tuple(float(v) for v in (*corners.min(axis=0), *corners.max(axis=0)))


def assemble(path: Path, raws: list[Raw], report: ReadReport, source_crs=None, declared=None) -> MapData:
    """Project `raws` about their centre and sort them into buildings, roads, areas, trees and lamps.

    `source_crs` None means longitude/latitude (WGS 84); "local" means metres kept as they are.
    `declared`: the extent the file declares (OpenStreetMap's <bounds>), lon/lat (x0, y0, x1, y1).
    """
    raws = _finite(raws, report, geographic=source_crs is None)
    if not raws:
        return MapData(path, (0.0, 0.0), LOCAL, report=report)
    geometries = np.asarray([raw.geometry for raw in raws], dtype=object)
    x0, y0, x1, y1 = shapely.total_bounds(geometries)
    centre = ((x0 + x1) / 2.0, (y0 + y1) / 2.0)
    local = isinstance(source_crs, str) and source_crs == LOCAL
    projection = LocalMetres(centre) if local else _projection(centre, source_crs, report)
    with np.errstate(invalid="ignore", over="ignore"):
        projected = projection.geometries(geometries)
    for raw, geometry in zip(raws, projected):
        raw.geometry = geometry
    _project_faces(raws, projection)
    raws = _finite(raws, report, geographic=False)  # points the projection cannot reach from the centre
    data = MapData(path, projection.origin, projection.crs, report=report)
    data.declared_bounds = _declared_bounds(projection, declared)
    coast, named_parents = [], []
    for raw in raws:
        kind = shapely.get_type_id(raw.geometry)
        if "city_object" in raw.fixed:
            _add_city_object(data, raw, projection)
        elif kind in (3, 6):  # Polygon, MultiPolygon
            if is_building(raw.tags):
                records = _add_buildings(data, raw)
                if raw.parent is not None:
                    named_parents += [(record, raw.parent) for record in records]
            else:
                _add_area(data, raw)
        elif kind in (1, 5):  # LineString, MultiLineString
            if raw.tags.get("natural") == "coastline":
                coast.append(raw.geometry)
            else:
                _add_line(data, raw)
        elif kind == 0:
            for feature in FEATURES:
                feature.read_point(raw.source_id, (raw.geometry.x, raw.geometry.y), raw.tags, data)
    _link_parts(data.buildings, named_parents, report)
    for feature in FEATURES:
        feature.link(data)
    if coast:
        _add_sea(data, coast)
    return data


def _project_faces(raws: list[Raw], projection) -> None:
    """CityJSON's faces (buildings' `surfaces`, other objects' `faces`), all in one call: plan to map
    metres, heights as given."""
    rings = [ring for raw in raws for rings in (raw.fixed.get("surfaces") or {}).values() for ring in rings]
    rings += [face.ring for raw in raws for face in raw.fixed.get("faces", ())]
    if not rings:
        return
    points = np.vstack(rings)
    with np.errstate(invalid="ignore", over="ignore"):
        plan = projection.points(points[:, :2])
    projected = iter(np.split(np.column_stack([plan, points[:, 2]]), np.cumsum([len(r) for r in rings])[:-1]))
    for raw in raws:
        if raw.fixed.get("surfaces") is not None:
            raw.fixed["surfaces"] = {
                kind: [next(projected) for _ in rings] for kind, rings in raw.fixed["surfaces"].items()
            }
    for raw in raws:
        if "faces" in raw.fixed:
            raw.fixed["faces"] = [(face.semantic, next(projected)) for face in raw.fixed["faces"]]


def _add_city_object(data: MapData, raw: Raw, projection) -> None:
    """A CityJSON object that is no building, its faces projected (maps/_cityjson.py)."""
    kind, cls, lod, attributes = raw.fixed["city_object"]
    faces = [(semantic, ring) for semantic, ring in raw.fixed["faces"] if np.isfinite(ring).all()]
    if not faces:
        data.report.skip(kind, "no face the projection can reach", raw.source_id)
        return
    data.city_objects.append(CityObject(raw.source_id, kind, cls, faces, lod, attributes))


def _projection(centre: tuple[float, float], source_crs, report: ReadReport):
    """Projection from `source_crs` (None: lon/lat), or metres as they are when the data's centre
    is not on the Earth in it (a system named wrongly, or one pyproj cannot project from)."""
    try:
        return Projection(centre, source_crs or "EPSG:4326")
    except (pyproj.exceptions.CRSError, pyproj.exceptions.ProjError, ValueError):
        report.fallback(
            "crs",
            "unknown coordinate system, or the data is not on the Earth in it (taken as metres)",
            str(source_crs)[:60],
        )
        return LocalMetres(centre)


def _finite(raws: list[Raw], report: ReadReport, geographic: bool) -> list[Raw]:
    """Drop features with a coordinate that is NaN, infinite or (for lon/lat) off the Earth."""
    if not raws:
        return raws
    coords, owner = shapely.get_coordinates([raw.geometry for raw in raws], return_index=True)
    bad = ~np.isfinite(coords).all(axis=1)
    if geographic:
        bad |= ~in_range(coords[:, 0], coords[:, 1])
    else:
        bad |= (np.abs(coords) > 1e8).any(axis=1)  # metres beyond a thousand Earth radii
    dropped = set(np.unique(owner[bad]).tolist())
    empty = [i for i, raw in enumerate(raws) if shapely.is_empty(raw.geometry)]
    why = "longitude/latitude not finite or out of range" if geographic else "coordinate not finite or beyond 1e8 m"
    for i in sorted(dropped):
        report.skip(_what(raws[i].tags), why, raws[i].source_id)
    for i in empty:
        report.skip(_what(raws[i].tags), "no coordinates", raws[i].source_id)
    dropped.update(empty)
    return [raw for i, raw in enumerate(raws) if i not in dropped]


def _what(tags: dict[str, str]) -> str:
    if is_building(tags):
        return "building"
    for key in ("highway", "railway", "natural", "waterway", "landuse", "leisure"):
        if key in tags:
            return key
    return "feature"


def _polygons(raw: Raw, report: ReadReport) -> list[shapely.Polygon]:
    """The valid polygons of a (Multi)Polygon: repaired when invalid, tiny ones skipped."""
    geometry = raw.geometry
    what = _what(raw.tags)
    if shapely.get_num_coordinates(geometry) > MAX_VERTICES:
        geometry = shapely.simplify(geometry, SIMPLIFY_TOLERANCE, preserve_topology=True)
        report.repair(what, f"more than {MAX_VERTICES} corners, simplified to {SIMPLIFY_TOLERANCE} m", raw.source_id)
    if not geometry.is_valid:
        reason = shapely.is_valid_reason(geometry).split("[")[0].strip().lower()
        geometry = shapely.make_valid(geometry)
        report.repair(what, f"invalid outline ({reason}), made valid", raw.source_id)
        polygons = [part for part in shapely.get_parts(geometry) if shapely.get_type_id(part) in (3, 6)]
        polygons = [p for multi in polygons for p in shapely.get_parts(multi)]
    else:
        polygons = list(shapely.get_parts(geometry))
    kept = [p for p in polygons if p.area >= MIN_AREA]
    if not kept:
        report.skip(what, f"zero area (under {MIN_AREA} m²)", raw.source_id)
    return list(shapely.orient_polygons(kept)) if kept else []


def _add_buildings(data: MapData, raw: Raw) -> list[MapBuilding]:
    polygons = _polygons(raw, data.report)
    if raw.fixed.get("surfaces") is not None and len(polygons) > 1:  # one record draws all its given faces
        polygons = [max(polygons, key=lambda p: p.area)]
    return add_buildings(data, raw.source_id, polygons, raw.tags, raw.fixed)


def _add_area(data: MapData, raw: Raw) -> None:
    kind = area_kind(raw.tags)
    if kind is None:
        if not raw.tags:
            data.report.skip("feature", "polygon without tags", raw.source_id)
        return
    for polygon in _polygons(raw, data.report):
        data.areas.append(Area(raw.source_id, polygon, kind, raw.tags))


def _add_line(data: MapData, raw: Raw) -> None:
    tags = raw.tags
    lines = [line for line in shapely.get_parts(raw.geometry) if line.length > 0.0]
    taken = any(feature.read_line(raw.source_id, lines, tags, data) for feature in FEATURES)
    if not (taken or tags.get("highway") or tags.get("railway")):
        data.report.skip("feature", "a line that is no road, railway or tree row", raw.source_id)


def _link_parts(buildings: list[MapBuilding], named: list[tuple[MapBuilding, str]], report: ReadReport) -> None:
    """Give each part its named outline or the smallest one holding its inner point; mark outlines their
    parts cover, and cut those they cover in part down to where no part stands."""
    first = {}
    for building in buildings:
        if not building.is_part:
            first.setdefault(building.source_id, building.index)
    for part, parent in named:
        part.parent = first.get(parent)
    outlines = [b for b in buildings if not b.is_part]
    parts = [b for b in buildings if b.is_part and b.parent is None]
    if not outlines or not parts:
        _mark_replaced(buildings, report)
        return
    tree = shapely.STRtree([b.outline for b in outlines])
    inner = shapely.point_on_surface([p.outline for p in parts])
    part_index, outline_index = tree.query(inner, predicate="within")
    best: dict[int, int] = {}
    for p, o in zip(part_index.tolist(), outline_index.tolist()):
        if p not in best or outlines[o].footprint_area < outlines[best[p]].footprint_area:
            best[p] = o
    for p, o in best.items():
        parts[p].parent = outlines[o].index
    _mark_replaced(buildings, report)


def _mark_replaced(buildings: list[MapBuilding], report: ReadReport) -> None:
    children: dict[int, list[MapBuilding]] = {}
    for part in buildings:
        if part.is_part and part.parent is not None:
            children.setdefault(part.parent, []).append(part)
    for index, parts in children.items():
        building = buildings[index]
        if building.surfaces is not None:  # drawn as given beside its parts, which are drawn as given too
            continue
        covering = shapely.union_all([p.outline for p in parts])
        uncovered = shapely.difference(building.outline, covering)
        if building.outline.area - uncovered.area >= PARTS_COVER * building.outline.area:
            # the parts are the building; what they leave uncovered is mapping noise, but the outline
            # still stands under those that float (else their base would hang over empty ground)
            remainder, dropped = None, 0.0
        else:
            remainder, dropped = _without_slivers(uncovered)
        taken = shapely.union_all([p.outline for p in parts if not _floats(p)])
        for part in sorted(filter(_floats, parts), key=lambda p: (p.min_height or 0.0, p.min_level or 0.0)):
            below = shapely.intersection(building.outline, part.outline)
            under, lost = _without_slivers(shapely.difference(below, taken))
            taken, dropped = shapely.union(taken, part.outline), dropped + lost
            if under is not None:
                building.beneath_parts.append((under, part))
        if dropped > 0.01:
            why = f"under {SLIVER_WIDTH:g} m wide or {SLIVER_AREA:g} m² beside its building:part ways, not drawn"
            report.skip("building outline sliver", why, building.source_id)
        if remainder is None and not building.beneath_parts:
            building.replaced_by_parts = True
            continue
        building.remainder = remainder if remainder is not None else shapely.Polygon()
        if remainder is None:
            why = "covered by its building:part ways, drawn only under those that float"
        else:
            why = "partly covered by its building:part ways, drawn where none stands"
            why += " and under those that float" if building.beneath_parts else ""
        report.repair("building outline", why, building.source_id)


def _floats(part: MapBuilding) -> bool:
    """A part whose walls start above the ground (upper storeys, a bridge): the outline stays beneath it."""
    return (part.min_height or 0.0) > 0.0 or (part.min_level or 0.0) > 0.0


def _without_slivers(area: shapely.Geometry) -> tuple[shapely.Geometry | None, float]:
    """(`area` without pieces thinner than SLIVER_WIDTH or under SLIVER_AREA, or None if nothing is left;
    the area dropped). An opening (mitred, so square corners stay square) clipped back to `area`, so the
    edges it keeps are exactly those of `area`: along a part, the part's own."""
    half = SLIVER_WIDTH / 2.0
    opened = area.buffer(-half, join_style="mitre").buffer(half, join_style="mitre")
    pieces = [
        piece
        for piece in shapely.get_parts(shapely.intersection(opened, area))
        if isinstance(piece, shapely.Polygon) and piece.area >= SLIVER_AREA
    ]
    kept = shapely.union_all(pieces) if pieces else None
    return kept, area.area - (kept.area if kept is not None else 0.0)


def _extended(line: shapely.LineString, reach: float) -> shapely.LineString:
    """An open coastline cut at the extract's edge, carried straight on past the data's bounds."""
    if line.is_closed:
        return line
    points = np.asarray(line.coords)
    head, tail = points[0] - points[1], points[-1] - points[-2]
    head *= reach / max(np.linalg.norm(head), 1e-9)
    tail *= reach / max(np.linalg.norm(tail), 1e-9)
    return shapely.LineString(np.vstack([points[0] + head, points, points[-1] + tail]))


def _add_sea(data: MapData, coast: list) -> None:
    """Split the data's bounds along the coastline; faces on the coastline's right (sea) become water."""
    x0, y0, x1, y1 = data.bounds()
    bounds = shapely.box(x0 - 50.0, y0 - 50.0, x1 + 50.0, y1 + 50.0)
    reach = 2.0 * float(np.hypot(x1 - x0, y1 - y0)) + 200.0
    merged = shapely.get_parts(shapely.line_merge(shapely.union_all(coast)))
    lines = shapely.union_all([_extended(line, reach) for line in merged])
    clipped = shapely.intersection(lines, bounds)
    faces = shapely.get_parts(shapely.polygonize([shapely.union(bounds.boundary, clipped)]))
    segments = [line for line in shapely.get_parts(clipped) if line.length > 0.0]
    if not segments:
        return
    tree = shapely.STRtree(segments)
    for face in faces:
        inside = shapely.point_on_surface(face)
        line = segments[int(tree.nearest(inside))]
        along = line.project(inside)
        a = line.interpolate(max(along - 0.01, 0.0))
        b = line.interpolate(min(along + 0.01, line.length))
        c = line.interpolate(along)
        cross = (b.x - a.x) * (inside.y - c.y) - (b.y - a.y) * (inside.x - c.x)
        if cross < 0.0:  # right of the coastline's direction: the sea
            data.areas.append(Area("coastline", face, "water", {"natural": "coastline"}))
