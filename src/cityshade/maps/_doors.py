"""Doors: where the map gives none, one on the street side of each building whose walls reach the
ground; and every door point turned into a door on its mass's wall.

The guessed door stands in the middle of the wall whose middle is nearest the nearest road (any
`highway=*` but tunnels), among the walls at least a door wide that no other building stands
against (a party wall: PARTY_WALL_PROBE metres out from its middle is inside another building).
Without roads it takes the longest such wall. Mapped entrances (`entrance=*`, linked by the
reader) are kept exactly where they are, only moved along their wall as far as it takes to fit a
whole door (`cityshade.scene.door_on_edge`).
"""

from __future__ import annotations

import numpy as np
import shapely

from ..scene import DOOR_WIDTH, MAX_DOORS, door_on_edge
from ._model import MapBuilding, MapData

PARTY_WALL_PROBE = 0.3  # metres
ON_WALL = 0.6  # metres: a door point this near one of a mass's walls stands on it
STRAIGHT = 0.02  # metres: vertices this near the line of their neighbours do not end a wall (< DOOR_PLANE)


def on_ground(building: MapBuilding) -> bool:
    return building.has_walls and (building.min_height or 0.0) <= 0.0 and (building.min_level or 0.0) <= 0.0


def place_doors(map_data: MapData) -> None:
    """Gives each drawn building on the ground without a mapped entrance one guessed door (all walls
    of all such buildings scored in a few vectorised calls)."""
    drawn = [b for b in map_data.buildings if b.drawn]
    wanted = [b for b in drawn if not b.doors and on_ground(b)]
    if not wanted:
        return
    rings = [np.asarray(b.outline.exterior.coords) for b in wanted]  # counter-clockwise (map x east, y north)
    counts = np.array([len(r) - 1 for r in rings])
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    a = np.concatenate([r[:-1] for r in rings])
    d = np.concatenate([r[1:] for r in rings]) - a
    length = np.hypot(d[:, 0], d[:, 1])
    middle = a + d / 2
    outward = np.stack([d[:, 1], -d[:, 0]], axis=1) / np.maximum(length, 1e-9)[:, None]
    inside, _ = shapely.STRtree([b.outline for b in drawn]).query(
        shapely.points(middle + PARTY_WALL_PROBE * outward), predicate="within"
    )
    shared = np.zeros(len(a), dtype=bool)
    shared[inside] = True
    roads = np.array([r.line for r in map_data.roads if not r.tunnel], dtype=object)
    if len(roads):
        building, road = shapely.STRtree(roads).query_nearest([b.outline for b in wanted], all_matches=False)
        nearest = np.zeros(len(wanted), dtype=np.int64)
        nearest[building] = road
        score = shapely.distance(shapely.points(middle), roads[np.repeat(nearest, counts)])
    else:
        score = -length
    wide = length >= DOOR_WIDTH
    for building, start, count in zip(wanted, starts.tolist(), counts.tolist()):
        edges = slice(start, start + count)
        if not wide[edges].any():
            continue  # walls all narrower than a door (a tower drawn as short segments)
        free = wide[edges] & ~shared[edges]
        if not free.any():
            free = wide[edges]  # shared on every side: a wall anyway
        pick = start + int(np.argmin(np.where(free, score[edges], np.inf)))
        building.doors = [(float(middle[pick, 0]), float(middle[pick, 1]))]
        building.guessed.add("doors")


def mass_doors(points: np.ndarray, outline: shapely.Polygon) -> tuple[tuple[float, float, float, float], ...]:
    """Doors (x, z, outward normal) of a mass on its object-space `outline` (courtyards included) for
    door points in the same frame: each on the wall nearest it (walls run on straight through
    vertices, within STRAIGHT), if one lies within ON_WALL; at most MAX_DOORS."""
    # one wall where the outline runs straight on through a vertex (an entrance mapped as a node of its way);
    # exterior counter-clockwise, courtyards clockwise: walls face out
    polygon = shapely.orient_polygons(shapely.simplify(outline, STRAIGHT, preserve_topology=True))
    rings = [np.asarray(r.coords) for r in (polygon.exterior, *polygon.interiors)]
    a = np.concatenate([r[:-1] for r in rings])
    b = np.concatenate([r[1:] for r in rings])
    d = b - a
    squared = np.maximum(np.sum(d * d, axis=1), 1e-18)
    doors = []
    for point in np.asarray(points, dtype=np.float64).reshape(-1, 2):
        s = np.clip(np.sum((point - a) * d, axis=1) / squared, 0.0, 1.0)
        gap = np.hypot(*(a + d * s[:, None] - point).T)
        edge = int(np.argmin(gap))
        door = door_on_edge(a[edge], b[edge], point) if gap[edge] <= ON_WALL else None
        if door is not None:
            doors.append(door)
        if len(doors) == MAX_DOORS:
            break
    return tuple(doors)
