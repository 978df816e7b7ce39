"""Street lamps (`highway=street_lamp` points, height from `height`, 1..30 m, else LAMP_HEIGHT),
lamps along lit roads (`lit=yes`) where the map has none, and, where the map is silent (no `lit`
tag and no mapped lamp near), lamps guessed along the streets of built-up areas: point lights (bulb
position and reach) and their posts as small boxes in the ground mesh (a thin post, a lamp head that
glows at night).

Guessed lamps (GUESSED_LAMPS: spacing and mounting height by road class, typical of European town
streets: about 30 m on main roads with 10 m columns, 40 m on residential streets with 6 m ones,
25 m on pedestrian streets) stand on the right-hand kerb of roads with at least BUILT_UP_BUILDINGS
buildings within BUILT_UP_REACH metres of the lamp; never on motorways or trunk roads (lit there
only when tagged), on `lit=no` roads, in tunnels, on bridges, or within MAPPED_NEARBY metres of a
lamp the map has or one of a lit road. They are flagged `guessed` and counted by `cityshade info`."""

from __future__ import annotations

import numpy as np
import shapely

from ...scene import GROUND_BULB, GROUND_POST, Layer
from .._model import Lamp, MapData, to_scene
from .._tags import length
from ._feature import Built, Feature
from .streets import DRIVEN

LAMP_HEIGHT = 6.0  # metres, when `height` is not tagged (or not 1..30 m)
REACH_PER_METRE = 3.5  # a lamp lights the ground out to 3.5 times its height
POST_HALF, HEAD_HALF, HEAD_DEPTH = 0.07, 0.25, 0.3
LIT_ROAD_SPACING = 35.0  # metres between lamps placed along a lit road
LIT_ROAD_HEIGHT = 8.0
MAPPED_NEARBY = 20.0  # no lamp is placed this close to a mapped one
KERB_OFFSET = 0.8  # metres beyond the carriageway's edge
GUESSED_LAMPS = {  # road class -> (metres between guessed lamps, mounting height in metres)
    "primary": (30.0, 10.0),
    "secondary": (30.0, 10.0),
    "tertiary": (35.0, 8.0),
    "unclassified": (40.0, 6.0),
    "residential": (40.0, 6.0),
    "living_street": (35.0, 5.0),
    "pedestrian": (25.0, 5.0),
}
BUILT_UP_REACH = 50.0  # metres around a guessed lamp in which buildings are counted
BUILT_UP_BUILDINGS = 3  # a lamp is guessed only where at least this many stand within reach

# the 12 triangles of a unit box [0, 1]^3 as corner indices (bit 0: x, bit 1: y, bit 2: z)
_BOX = np.array(
    [
        (0, 1, 3),
        (0, 3, 2),
        (4, 6, 7),
        (4, 7, 5),
        (0, 4, 5),
        (0, 5, 1),
        (2, 3, 7),
        (2, 7, 6),
        (0, 2, 6),
        (0, 6, 4),
        (1, 5, 7),
        (1, 7, 3),
    ]
)
_CORNERS = np.array([((i >> 0) & 1, (i >> 1) & 1, (i >> 2) & 1) for i in range(8)], float)


def _kerb_points(roads: list, spacing: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((N, 2) map points, (N,) index of each one's road): every `spacing[i]` metres along road i (the
    first half a spacing in), on its right-hand kerb (KERB_OFFSET beyond the carriageway)."""
    if not roads:
        return np.zeros((0, 2)), np.zeros(0, int)
    lines = np.array([r.line for r in roads], dtype=object)
    counts = np.floor(shapely.length(lines) / spacing).astype(int)
    owner = np.repeat(np.arange(len(roads)), counts)
    along = (np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts) + 0.5) * spacing[owner]
    ahead = shapely.get_coordinates(shapely.line_interpolate_point(lines[owner], along + 0.5))
    behind = shapely.get_coordinates(shapely.line_interpolate_point(lines[owner], along - 0.5))
    tangent = (ahead - behind) / np.maximum(np.linalg.norm(ahead - behind, axis=1, keepdims=True), 1e-9)
    right = np.c_[tangent[:, 1], -tangent[:, 0]]
    offset = np.array([r.width / 2 + KERB_OFFSET for r in roads])[owner]
    return ((ahead + behind) / 2 + right * offset[:, None]).reshape(-1, 2), owner


def _away_from(points: np.ndarray, lamps: list[Lamp]) -> np.ndarray:
    """Which of `points` lie MAPPED_NEARBY metres or more from every lamp in `lamps`."""
    keep = np.ones(len(points), bool)
    if lamps and len(points):
        mapped = shapely.points([lamp.position for lamp in lamps])
        near = shapely.STRtree(mapped).query(shapely.points(points), predicate="dwithin", distance=MAPPED_NEARBY)[0]
        keep[near] = False
    return keep


def _lit_kind(kind: str) -> bool:
    return kind in DRIVEN or kind == "pedestrian"


def lit_road_lamps(map_data: MapData) -> list[Lamp]:
    """Lamps every LIT_ROAD_SPACING metres beside each lit driven or pedestrian street (`lit=yes`),
    on its right-hand kerb, except within MAPPED_NEARBY metres of a lamp the map has."""
    roads = [r for r in map_data.roads if r.lit and _lit_kind(r.kind) and not r.tunnel and not r.bridge]
    points, _ = _kerb_points(roads, np.full(len(roads), LIT_ROAD_SPACING))
    points = points[_away_from(points, map_data.lamps)]
    return [
        Lamp(f"lit road lamp {i}", (float(x), float(y)), LIT_ROAD_HEIGHT, from_lit_road=True)
        for i, (x, y) in enumerate(points)
    ]


def guessed_lamps(map_data: MapData, placed: list[Lamp] = ()) -> list[Lamp]:
    """Lamps guessed where the map is silent (GUESSED_LAMPS, the module's docstring), away from the
    mapped lamps and the lit roads' lamps `placed`."""
    roads = [
        r
        for r in map_data.roads
        if r.kind in GUESSED_LAMPS and not r.lit and r.tags.get("lit") != "no" and not r.tunnel and not r.bridge
    ]
    outlines = [b.outline for b in map_data.buildings if b.drawn]
    if not roads or len(outlines) < BUILT_UP_BUILDINGS:
        return []
    spacing = np.array([GUESSED_LAMPS[r.kind][0] for r in roads])
    points, owner = _kerb_points(roads, spacing)
    pairs = shapely.STRtree(outlines).query(shapely.points(points), predicate="dwithin", distance=BUILT_UP_REACH)
    built_up = np.bincount(pairs[0], minlength=len(points)) >= BUILT_UP_BUILDINGS
    keep = built_up & _away_from(points, [*map_data.lamps, *placed])
    return [
        Lamp(f"guessed lamp {i}", (float(x), float(y)), GUESSED_LAMPS[roads[k].kind][1], guessed=True)
        for i, ((x, y), k) in enumerate(zip(points[keep], owner[keep]))
    ]


def all_lamps(map_data: MapData) -> list[Lamp]:
    """The mapped lamps, the lit roads' and the guessed ones."""
    lit = lit_road_lamps(map_data)
    return [*map_data.lamps, *lit, *guessed_lamps(map_data, lit)]


def lamp_lights(map_data: MapData) -> np.ndarray:
    """(N, 4) float32: scene x, y, z of each bulb (mapped, lit roads' and guessed lamps) and the reach
    of its light in metres."""
    lamps = all_lamps(map_data)
    if not lamps:
        return np.zeros((0, 4), np.float32)
    xz = to_scene(np.array([lamp.position for lamp in lamps], float))
    height = np.array([lamp.height for lamp in lamps], float)
    return np.c_[xz[:, 0], height - HEAD_DEPTH, xz[:, 1], height * REACH_PER_METRE].astype(np.float32)


def boxes(low: np.ndarray, high: np.ndarray, material: int) -> np.ndarray:
    """Triangles (N*36, 4) of axis-aligned boxes from corners `low` to `high` (N, 3)."""
    corners = low[:, None, :] + _CORNERS[None, :, :] * (high - low)[:, None, :]
    vertices = corners[:, _BOX.ravel(), :].reshape(-1, 3)
    return np.c_[vertices, np.full(len(vertices), material)].astype(np.float32)


def lamp_posts(lights: np.ndarray) -> np.ndarray:
    """Posts and glowing heads for lamp lights from `lamp_lights`."""
    if not len(lights):
        return np.zeros((0, 4), np.float32)
    x, bulb, z = lights[:, 0], lights[:, 1], lights[:, 2]
    top = bulb + HEAD_DEPTH
    post = boxes(
        np.c_[x - POST_HALF, np.zeros_like(x), z - POST_HALF], np.c_[x + POST_HALF, bulb, z + POST_HALF], GROUND_POST
    )
    head = boxes(np.c_[x - HEAD_HALF, bulb, z - HEAD_HALF], np.c_[x + HEAD_HALF, top, z + HEAD_HALF], GROUND_BULB)
    return np.concatenate([post, head])


class Lamps(Feature):
    name = "lamps"

    def point_kind(self, tags):
        return "highway" if tags.get("highway") == "street_lamp" else None

    def read_point(self, source_id, point, tags, data):
        if tags.get("highway") == "street_lamp" and tags.get("natural") != "tree":
            height = length(tags.get("height", ""))
            lamp_height = height if height and 1.0 <= height <= 30.0 else LAMP_HEIGHT
            data.lamps.append(Lamp(source_id, (float(point[0]), float(point[1])), height=lamp_height))

    def summary(self, data):
        return {"street_lamps": len(data.lamps), "street_lamps_guessed": len(guessed_lamps(data, lit_road_lamps(data)))}

    def build(self, data):
        lights = lamp_lights(data)
        return Built(Layer(self.name, lamp_posts(lights), lights))
