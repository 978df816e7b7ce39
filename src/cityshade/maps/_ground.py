"""The ground of a map as flat triangles with a material each: land, grass, water, pavements,
roads, tracks and paint, split so that no two surfaces overlap (nothing to z-fight), over a plane
that reaches the horizon.

Surfaces are decided in priority order (a road crossing a park is road, a park by a river keeps
its bank): each layer is its geometry minus every layer above it (vectorised shapely), and every
polygon is triangulated with its holes by earcut (mapbox_earcut).
"""

from __future__ import annotations

import mapbox_earcut as earcut
import numpy as np
import shapely

from ..scene import (
    GROUND_ASPHALT,
    GROUND_BALLAST,
    GROUND_GRASS,
    GROUND_LAND,
    GROUND_MARKING,
    GROUND_PAVEMENT,
    GROUND_RAIL,
    GROUND_SAND,
    GROUND_WATER,
)
from ._model import MapData, to_scene
from ._streets import StreetSurfaces, street_surfaces

AREA_MATERIALS = {
    "water": GROUND_WATER,
    "grass": GROUND_GRASS,
    "park": GROUND_GRASS,
    "forest": GROUND_GRASS,
    "meadow": GROUND_GRASS,
    "farmland": GROUND_GRASS,
    "pavement": GROUND_PAVEMENT,
    "sand": GROUND_SAND,
}
HORIZON = 400_000.0  # metres of land plane around the map: its edge sinks below the horizon seen from 3 km up
LAND_MARGIN = 2000.0  # metres of finely divided land around the map's bounds
LAND_CELL = 250.0  # metres: the land grid's cell under the map (coarser for maps over 32 km wide)
LAND_CELLS = 128  # cells a side at most
BASE_DEPTH = 0.3  # the land plane lies this far below the map's surfaces, so they never share a depth
PAINT_LIFT = 0.03  # markings and rails over the carriageway


def _earcut(polygon: shapely.Polygon) -> np.ndarray:
    """(K*3, 2) corners of the triangles of one polygon with its holes (mapbox earcut)."""
    rings = [shapely.get_coordinates(ring)[:-1] for ring in (polygon.exterior, *polygon.interiors)]
    corners = np.concatenate(rings)
    ends = np.cumsum([len(ring) for ring in rings]).astype(np.uint32)
    return corners[earcut.triangulate_float64(corners, ends)]


def triangles(geometry, y: float, material: int) -> np.ndarray:
    """(N*3, 4) float32 vertices (x, y, z, material) of a map-space polygonal geometry, triangulated."""
    parts = shapely.get_parts(shapely.get_parts(geometry))
    parts = parts[(shapely.get_type_id(parts) == 3) & ~shapely.is_empty(parts)] if len(parts) else parts
    if not len(parts):
        return np.zeros((0, 4), np.float32)
    scene = to_scene(np.concatenate([_earcut(p) for p in parts]))
    out = np.empty((len(scene), 4), np.float32)
    out[:, 0], out[:, 1], out[:, 2], out[:, 3] = scene[:, 0], y, scene[:, 1], material
    return out


def _union(geometries) -> shapely.Geometry:
    geometries = [g for g in geometries if g is not None and not g.is_empty]
    return shapely.union_all(geometries) if geometries else shapely.Polygon()


def land_plane(bounds: tuple[float, float, float, float], y: float = -BASE_DEPTH) -> np.ndarray:
    """Plain land reaching HORIZON metres around the map (map metres). Under the map and LAND_MARGIN
    around it the land is a grid of small cells: the rasteriser interpolates the depth of a
    triangle hundreds of kilometres wide too coarsely to keep it BASE_DEPTH below the map's
    surfaces (from the air, whole views lost their streets and water to it); beyond, where it
    meets nothing, a few large triangles reach the horizon."""
    x0, y0, x1, y1 = bounds
    x0, y0, x1, y1 = x0 - LAND_MARGIN, y0 - LAND_MARGIN, x1 + LAND_MARGIN, y1 + LAND_MARGIN
    cell = max(LAND_CELL, max(x1 - x0, y1 - y0) / LAND_CELLS)
    xs = np.linspace(x0, x1, int(np.ceil((x1 - x0) / cell)) + 1)
    ys = np.linspace(y0, y1, int(np.ceil((y1 - y0) / cell)) + 1)
    ax, ay = np.meshgrid(xs[:-1], ys[:-1], indexing="ij")
    bx, by = np.meshgrid(xs[1:], ys[1:], indexing="ij")
    a, b = np.stack([ax.ravel(), ay.ravel()], 1), np.stack([bx.ravel(), by.ravel()], 1)
    c, d = np.stack([b[:, 0], a[:, 1]], 1), np.stack([a[:, 0], b[:, 1]], 1)
    grid = np.stack([a, c, b, a, b, d], axis=1).reshape(-1, 2)  # counter-clockwise seen from above (map y north)
    scene = to_scene(grid)
    inner = np.empty((len(scene), 4), np.float32)
    inner[:, 0], inner[:, 1], inner[:, 2], inner[:, 3] = scene[:, 0], y, scene[:, 1], GROUND_LAND
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    outer = shapely.box(cx - HORIZON, cy - HORIZON, cx + HORIZON, cy + HORIZON).difference(shapely.box(x0, y0, x1, y1))
    return np.concatenate([inner, triangles(outer, y, GROUND_LAND)])


def ground_mesh(map_data: MapData, streets: StreetSurfaces | None = None) -> np.ndarray:
    """All ground triangles of a map: areas, pavements, roads, tracks, paint and the land plane."""
    streets = street_surfaces(map_data) if streets is None else streets
    # highest priority first: what is already taken is cut from everything below
    layers = [
        (streets.carriageway, GROUND_ASPHALT),
        (streets.ballast, GROUND_BALLAST),
        (streets.pavement, GROUND_PAVEMENT),
    ]
    by_material: dict[int, list] = {}
    for area in map_data.areas:
        by_material.setdefault(AREA_MATERIALS.get(area.kind, GROUND_GRASS), []).append(area.polygon)
    for material in (GROUND_WATER, GROUND_PAVEMENT, GROUND_SAND, GROUND_GRASS):
        if material in by_material:
            layers.append((_union(by_material[material]), material))
    taken = shapely.Polygon()
    pieces = []
    for geometry, material in layers:
        if geometry.is_empty:
            continue
        own = shapely.difference(geometry, taken) if not taken.is_empty else geometry
        pieces.append(triangles(own, 0.0, material))
        taken = shapely.union(taken, geometry)
    pieces.append(triangles(streets.markings, PAINT_LIFT, GROUND_MARKING))
    pieces.append(triangles(streets.rails, PAINT_LIFT, GROUND_RAIL))
    pieces.extend(streets.bridges)
    pieces.append(land_plane(map_data.bounds()))
    return np.concatenate(pieces)
