"""A building read with its faces (CityJSON) -> a mass that draws them as given (scene/_given.py).

The mass's object space is the one building_mass turns to the footprint's longest side; the faces
keep their heights as given (metres above the file's datum), so the mass's base and top are its
lowest and highest point. Walls (WallSurface, and faces without semantics that stand within
STEEP of vertical) carry the facade registry's facade; roofs (RoofSurface) the roof material the
tags or the guessing model give; ground, floor and ceiling faces are drawn plain with the roof's.
Storeys are `building:levels` (storeysAboveGround) over the building's height where given, else
the type's default storey. BuildingParts take their building's facade style.
"""

from __future__ import annotations

import numpy as np
import shapely

from ..scene import GIVEN_FLOOR, GIVEN_ROOF, GIVEN_WALL, BuildingMass, Roof
from ._defaults import defaults_for
from ._model import MapBuilding, to_scene

WALLS = ("WallSurface", "Window", "Door", "InteriorWallSurface")
FLOORS = ("GroundSurface", "OuterFloorSurface", "FloorSurface")
STEEP = 0.95  # |normal y| below this: a face without semantics is a wall
FLOOR_HEIGHT_RANGE = (2.5, 6.0)


def _kind(semantic: str, ring: np.ndarray) -> int:
    if semantic in WALLS:
        return GIVEN_WALL
    if semantic in FLOORS:
        return GIVEN_FLOOR
    if semantic == "unclassified":
        return GIVEN_WALL if _vertical_share(ring) < STEEP else GIVEN_ROOF
    return GIVEN_ROOF


def _vertical_share(ring: np.ndarray) -> float:
    """|normal . up| of a ring in map metres (x east, y north, z up)."""
    a, b = ring, np.roll(ring, -1, axis=0)
    normal = np.array(
        [
            np.sum((a[:, 1] - b[:, 1]) * (a[:, 2] + b[:, 2])),
            np.sum((a[:, 2] - b[:, 2]) * (a[:, 0] + b[:, 0])),
            np.sum((a[:, 0] - b[:, 0]) * (a[:, 1] + b[:, 1])),
        ]
    )
    length = np.linalg.norm(normal)
    return float(abs(normal[2]) / length) if length > 0 else 1.0


def given_mass(
    building: MapBuilding, polygon: shapely.Polygon, frame, style: int, use: int, roof: Roof
) -> BuildingMass | None:
    """The mass of a building with faces, on its scene-space footprint `polygon`; `frame` is
    building_mass's (yaw, low, to_local) for it."""
    yaw, low, to_local = frame
    rings = [(semantic, ring) for semantic, group in building.surfaces.items() for ring in group]
    if not rings:
        return None
    points = np.vstack([ring for _, ring in rings])  # every ring at once: to object space, heights kept
    plan = to_local(to_scene(points[:, :2]), yaw) - low
    local = np.column_stack([plan[:, 0], points[:, 2], plan[:, 1]]).tolist()
    ends = np.cumsum([len(ring) for _, ring in rings]).tolist()
    faces = [
        (_kind(semantic, ring), tuple(map(tuple, local[end - len(ring) : end])))
        for (semantic, ring), end in zip(rings, ends)
    ]
    heights = np.concatenate([[p[1] for p in ring] for _, ring in faces])
    base, top = float(heights.min()), float(heights.max())
    if top - base <= 0.05:
        return None
    defaults = defaults_for(building.kind)
    storey = (top - building.ground) / building.levels if building.levels else defaults.storey
    exterior = to_local(np.asarray(shapely.orient_polygons(polygon).exterior.coords)[:-1], yaw) - low
    c, s = np.cos(yaw), np.sin(yaw)
    return BuildingMass(
        "prism",
        (float(c * low[0] + s * low[1]), float(-s * low[0] + c * low[1])),
        tuple(map(tuple, exterior.tolist())),
        top,
        yaw=yaw,
        floor_height=float(np.clip(storey, *FLOOR_HEIGHT_RANGE)),
        seed=building.index,
        style=style,
        use=use,
        shop_front=building.shop_front,
        base=base,
        roof=roof,
        wall_colour=building.building_colour,
        wall_material=building.building_material,
        guessed=frozenset(building.guessed),
        given=tuple(faces),
    )
