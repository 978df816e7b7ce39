"""Streets and paths (`highway=*` lines): the tags read with their defaults, and the roads as
surfaces: carriageways joined at crossings (the union of the roads' buffered centrelines), pavements
beside them, lane markings, and bridge decks lifted by their layer. Tunnels are left out; nothing
at ground level runs through a building. All geometry is in map metres (shapely, vectorised).

Width from `width`, else `lanes` x LANE_WIDTH, else ROAD_WIDTHS by class."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely

from ...scene import GROUND_ASPHALT, GROUND_MARKING, GROUND_PAVEMENT, Layer
from .._ground import PAINT_LIFT, triangles, union_of
from .._model import MapData, ReadReport, Road
from .._tags import layer, length, number, yes
from ._feature import Built, Feature, Surface

# OpenStreetMap highway classes: the public road network by rank, and the ramps joining it
MAIN_ROADS = ("motorway", "trunk", "primary", "secondary", "tertiary", "unclassified", "residential")
ROAD_LINKS = ("motorway_link", "trunk_link", "primary_link", "secondary_link", "tertiary_link")
DRIVEN = MAIN_ROADS + ("living_street", "service") + ROAD_LINKS + ("road", "busway")
WITH_PAVEMENT = MAIN_ROADS + ROAD_LINKS + ("road",)  # not service roads
NO_PAVEMENT = ("motorway", "trunk", "motorway_link", "trunk_link")  # pavements only where `sidewalk=*` says
CENTRE_LINE = MAIN_ROADS + ROAD_LINKS[1:]  # a motorway ramp has edge lines only
CENTRE_LINE_WIDTH = 6.0  # metres: a narrower carriageway has no centre line unless `lanes` is tagged
UNMARKED = ("residential",)  # streets whose centre is not painted unless `lanes` is tagged
DIVIDED_LANES = {"motorway": 2, "trunk": 2}  # lanes each way where `lanes` is not tagged
SKIPPED = ("corridor", "elevator", "proposed", "construction", "platform", "raceway")  # indoors, not built, not a way
PAVEMENT_WIDTH = 2.5
MARKING_WIDTH = 0.15
DASH, GAP = 3.0, 6.0
WIDTH_RANGE = (1.0, 30.0)
BRIDGE_STOREY = 5.0  # metres a bridge deck stands above the ground per layer
CARRIAGEWAY_RANK, PAVEMENT_RANK = 10, 30
LANE_WIDTH = 3.0
# Carriageway width in metres by highway class when neither `width` nor `lanes` is tagged.
ROAD_WIDTHS = {
    "motorway": 14.0,
    "trunk": 12.0,
    "primary": 10.0,
    "secondary": 9.0,
    "tertiary": 8.0,
    "unclassified": 6.0,
    "residential": 6.5,
    "service": 4.0,
    "living_street": 5.0,
    "pedestrian": 6.0,
    "motorway_link": 5.0,
    "trunk_link": 5.0,
    "primary_link": 5.0,
    "secondary_link": 5.0,
    "tertiary_link": 5.0,
    "track": 3.0,
    "busway": 3.5,
    "footway": 2.0,
    "cycleway": 2.0,
    "path": 1.5,
    "steps": 2.0,
    "bridleway": 2.0,
    "corridor": 2.0,
}
DEFAULT_ROAD_WIDTH = 5.0
NOT_ROADS = {"proposed", "construction", "abandoned", "razed", "disused", "platform", "elevator", "no"}


@dataclass
class StreetSurfaces:
    carriageway: shapely.Geometry
    pavement: shapely.Geometry
    markings: shapely.Geometry
    bridges: list = field(default_factory=list)  # triangle arrays (see _ground.triangles), already lifted
    junctions: shapely.Geometry = field(default_factory=shapely.Polygon)


def dashes(lines, dash: float = DASH, gap: float = GAP) -> np.ndarray:
    """Straight dashes `dash` long every `dash + gap` metres along each line, centred on its length."""
    lines = np.asarray(lines, dtype=object)
    if not len(lines):
        return np.zeros(0, dtype=object)
    lengths = shapely.length(lines)
    period = dash + gap
    counts = np.floor((lengths + gap) / period).astype(int)
    owner = np.repeat(np.arange(len(lines)), counts)
    k = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    start = (lengths[owner] - (counts[owner] * period - gap)) / 2 + k * period
    a = shapely.get_coordinates(shapely.line_interpolate_point(lines[owner], start))
    b = shapely.get_coordinates(shapely.line_interpolate_point(lines[owner], start + dash))
    return shapely.linestrings(np.stack([a, b], axis=1))


def lane_lines(roads) -> tuple[list, list]:
    """(solid lines, dashed lines): the centre line of two-way roads (solid on roads of four lanes or
    more) and the dividers between lanes in the same direction. Without a `lanes` tag, residential
    streets and carriageways narrower than CENTRE_LINE_WIDTH are not painted, and motorways and trunk
    roads have DIVIDED_LANES each way."""
    solid, dashed = [], []
    for road in roads:
        if road.kind not in CENTRE_LINE or road.width < 5.0:
            continue
        if road.lanes is None and (road.kind in UNMARKED or road.width < CENTRE_LINE_WIDTH):
            continue
        each_way = DIVIDED_LANES.get(road.kind, 1)
        lanes = road.lanes or (each_way if road.oneway else 2 * each_way)
        lane = road.width / lanes
        for k in range(1, lanes):
            offset = -road.width / 2 + k * lane
            line = road.line if abs(offset) < 1e-6 else shapely.offset_curve(road.line, offset)
            if line.is_empty:
                continue
            is_centre = not road.oneway and 2 * k == lanes
            (solid if is_centre and lanes >= 4 else dashed).append(line)
    return solid, dashed


def junction_zones(roads) -> shapely.Geometry:
    """Discs where two or more driven roads share a node: no lane markings run through a crossing."""
    points, owners, widths = [], [], []
    for i, road in enumerate(roads):
        coords = np.asarray(road.line.coords)[:, :2]
        points.append(coords)
        owners.append(np.full(len(coords), i))
        widths.append(np.full(len(coords), road.width))
    if not points:
        return shapely.Polygon()
    points, owners, widths = np.concatenate(points), np.concatenate(owners), np.concatenate(widths)
    keys = np.round(points, 2)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    roads_at = np.zeros(len(first), int)
    np.add.at(roads_at, np.unique(np.c_[inverse, owners], axis=0)[:, 0], 1)
    reach = np.zeros(len(first))
    np.maximum.at(reach, inverse, widths)
    shared = roads_at >= 2
    return union_of(shapely.buffer(shapely.points(points[first][shared]), reach[shared] * 0.6 + 1.0, quad_segs=3))


def paint_outside(junctions: shapely.Geometry, solid, dashed) -> np.ndarray:
    """Marking polygons: solid lines cut at the crossings, dashes that touch a crossing left out."""
    shapely.prepare(junctions)
    solid = shapely.difference(np.asarray(solid, dtype=object), junctions) if len(solid) else np.zeros(0, object)
    strokes = dashes(np.asarray(dashed, dtype=object))
    strokes = strokes[~shapely.intersects(junctions, strokes)] if len(strokes) else strokes
    return shapely.buffer(np.concatenate([solid, strokes]), MARKING_WIDTH / 2, cap_style="flat")


def street_surfaces(map_data: MapData) -> StreetSurfaces:
    """The surfaces of every road of the map (see the module docstring)."""
    roads = [r for r in map_data.roads if not r.tunnel and r.kind not in SKIPPED]
    ground = [r for r in roads if not r.bridge]
    bridges = [r for r in roads if r.bridge]
    width = {id(r): float(np.clip(r.width, *WIDTH_RANGE)) for r in roads}

    def ribbons(selection, extra: float = 0.0, cap: str = "round"):
        if not selection:
            return np.zeros(0, dtype=object)
        lines = np.array([r.line for r in selection], dtype=object)
        half = np.array([width[id(r)] / 2 + extra for r in selection])
        return shapely.buffer(lines, half, quad_segs=2, cap_style=cap)

    driven = [r for r in ground if r.kind in DRIVEN]
    walked = [r for r in ground if r.kind not in DRIVEN]
    sided = [r for r in driven if r.kind in WITH_PAVEMENT and r.sidewalk not in ("no", "none", "separate")]
    sided = [r for r in sided if r.kind not in NO_PAVEMENT or r.sidewalk is not None]
    carriageway = union_of(ribbons(driven))
    pavement = union_of(np.concatenate([ribbons(sided, PAVEMENT_WIDTH), ribbons(walked)]))
    # ground-level surfaces stop at walls: subtract the buildings they touch
    walls = [b.outline for b in map_data.buildings if b.drawn and b.has_walls and not (b.min_height or 0) > 0]
    if walls and not carriageway.is_empty:
        tree = shapely.STRtree(walls)
        touched = np.unique(
            tree.query(shapely.get_parts(shapely.union(carriageway, pavement)), predicate="intersects")[1]
        )
        if len(touched):
            blocked = union_of(np.asarray(walls, dtype=object)[touched])
            carriageway = shapely.difference(carriageway, blocked)
            pavement = shapely.difference(pavement, blocked)
    junctions = junction_zones(driven)
    solid, dashed = lane_lines(driven)
    markings = shapely.GeometryCollection(list(paint_outside(junctions, solid, dashed)))

    decks = []
    for road in bridges:
        lift = BRIDGE_STOREY * max(road.layer, 1)
        deck = ribbons([road], cap="flat")[0]
        decks.append(triangles(deck, lift, GROUND_ASPHALT if road.kind in DRIVEN else GROUND_PAVEMENT))
    return StreetSurfaces(carriageway, pavement, markings, decks, junctions)


def road(source_id: str, line, tags: dict[str, str], report: ReadReport) -> Road:
    kind = tags["highway"]
    lanes = number(tags.get("lanes", "").split(";")[0])
    lanes = int(lanes) if lanes and 1 <= lanes <= 20 else None
    width = length(tags["width"]) if "width" in tags else None
    if "width" in tags and (width is None or not 0.5 <= width <= 100.0):
        report.fallback("width", "not a width of 0.5..100 m", f"{source_id} width={tags['width'][:40]}")
        width = None
    if width is None:
        width = lanes * LANE_WIDTH if lanes else ROAD_WIDTHS.get(kind, DEFAULT_ROAD_WIDTH)
    return Road(
        source_id,
        line,
        kind,
        float(width),
        lanes=lanes,
        layer=layer(tags),
        bridge=yes(tags, "bridge"),
        tunnel=yes(tags, "tunnel"),
        lit=yes(tags, "lit"),
        oneway=tags.get("oneway", "no") in ("yes", "1", "true", "-1") or kind == "motorway",
        sidewalk=tags.get("sidewalk"),
        tags=tags,
    )


def lengths_km(lines) -> dict[str, float]:
    """Kilometres of roads (or railways) by class, longest first."""
    totals: dict[str, float] = {}
    for line in lines:
        totals[line.kind] = totals.get(line.kind, 0.0) + line.line.length / 1000.0
    return {kind: round(km, 3) for kind, km in sorted(totals.items(), key=lambda item: -item[1])}


class Streets(Feature):
    name = "streets"

    def wants_line(self, tags):
        return "highway" in tags

    def read_line(self, source_id, lines, tags, data):
        highway = tags.get("highway")
        if not highway or highway in NOT_ROADS or tags.get("area") == "yes":
            return False
        data.roads += [road(source_id, line, tags, data.report) for line in lines]
        return True

    def summary(self, data):
        return {"roads_km": lengths_km(data.roads)}

    def build(self, data):
        streets = street_surfaces(data)
        raised = [triangles(streets.markings, PAINT_LIFT, GROUND_MARKING), *streets.bridges]
        return Built(
            Layer(self.name, np.concatenate(raised)),
            [
                Surface(streets.carriageway, GROUND_ASPHALT, CARRIAGEWAY_RANK),
                Surface(streets.pavement, GROUND_PAVEMENT, PAVEMENT_RANK),
            ],
        )
