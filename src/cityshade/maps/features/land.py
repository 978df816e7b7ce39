"""Land use and the land under it (`leisure=park`, `landuse=grass|forest|farmland`, `natural=sand`,
`place=square`, ... polygons; see AREA_TAGS): green, paved and sandy ground classes, and the plain
land that reaches the horizon under the whole map."""

from __future__ import annotations

import numpy as np
import shapely

from ...scene import GROUND_GRASS, GROUND_LAND, GROUND_PAVEMENT, GROUND_SAND, GROUND_TERRAIN, Layer
from ...terrain import raised
from .._ground import triangles, union_of
from .._model import to_scene
from ._feature import Built, Feature, Surface

# (key, value) -> area kind; a polygon's first tag found here (or in another feature's table) decides
AREA_TAGS = {
    ("leisure", "park"): "park",
    ("leisure", "garden"): "park",
    ("leisure", "playground"): "park",
    ("landuse", "grass"): "grass",
    ("landuse", "village_green"): "grass",
    ("landuse", "recreation_ground"): "grass",
    ("leisure", "pitch"): "grass",
    ("landuse", "cemetery"): "grass",
    ("natural", "grassland"): "meadow",
    ("landuse", "meadow"): "meadow",
    ("natural", "heath"): "meadow",
    ("natural", "scrub"): "meadow",
    ("landuse", "forest"): "forest",
    ("natural", "wood"): "forest",
    ("landuse", "farmland"): "farmland",
    ("landuse", "orchard"): "farmland",
    ("landuse", "allotments"): "farmland",
    ("natural", "beach"): "sand",
    ("natural", "sand"): "sand",
    ("place", "square"): "pavement",
    ("amenity", "parking"): "pavement",
    ("highway", "pedestrian"): "pavement",
}
GREEN = ("grass", "park", "meadow", "forest", "farmland")
# ground material and rank (features/_feature.py) of each kind's surface
SURFACES = {"pavement": (GROUND_PAVEMENT, 50), "sand": (GROUND_SAND, 60), **dict.fromkeys(GREEN, (GROUND_GRASS, 70))}
HORIZON = 400_000.0  # metres of land plane around the map: its edge sinks below the horizon seen from 3 km up
LAND_MARGIN = 2000.0  # metres of finely divided land around the map's bounds
LAND_CELL = 250.0  # metres: the land grid's cell under the map (coarser for maps over 32 km wide)
LAND_CELLS = 128  # cells a side at most
BASE_DEPTH = 0.3  # the land plane lies this far below the map's surfaces, so they never share a depth


def _lines(start: float, end: float, cell: float, through=()) -> np.ndarray:
    """Grid lines from start to end about `cell` apart, passing through each of `through` inside."""
    stops = [start, *sorted(v for v in through if start < v < end), end]
    pieces = [np.linspace(a, b, max(1, int(np.ceil((b - a) / cell))) + 1) for a, b in zip(stops[:-1], stops[1:])]
    return np.unique(np.concatenate(pieces))


def land_plane(bounds: tuple[float, float, float, float], y: float = -BASE_DEPTH, terrain=None) -> np.ndarray:
    """Plain land reaching HORIZON metres around the map (map metres). Under the map and LAND_MARGIN
    around it the land is a grid of small cells: the rasteriser interpolates the depth of a
    triangle hundreds of kilometres wide too coarsely to keep it BASE_DEPTH below the map's
    surfaces (from the air, whole views lost their streets and water to it); beyond, where it
    meets nothing, a few large triangles reach the horizon. With a `terrain` the land leaves out
    the terrain's own grid (its lines run along the grid's edges), follows the terrain's height (the
    grid's edge carried on beyond it) and is the terrain's ground, so no edge shows where the grid ends."""
    x0, y0, x1, y1 = bounds
    x0, y0, x1, y1 = x0 - LAND_MARGIN, y0 - LAND_MARGIN, x1 + LAND_MARGIN, y1 + LAND_MARGIN
    cell = max(LAND_CELL, max(x1 - x0, y1 - y0) / LAND_CELLS)
    west, south, east, north = terrain.bounds() if terrain is not None else (np.inf,) * 4
    xs, ys = _lines(x0, x1, cell, (west, east)), _lines(y0, y1, cell, (south, north))
    ax, ay = np.meshgrid(xs[:-1], ys[:-1], indexing="ij")
    bx, by = np.meshgrid(xs[1:], ys[1:], indexing="ij")
    a, b = np.stack([ax.ravel(), ay.ravel()], 1), np.stack([bx.ravel(), by.ravel()], 1)
    if terrain is not None:  # the terrain's mesh covers its grid
        covered = (a[:, 0] >= west) & (b[:, 0] <= east) & (a[:, 1] >= south) & (b[:, 1] <= north)
        a, b = a[~covered], b[~covered]
    c, d = np.stack([b[:, 0], a[:, 1]], 1), np.stack([a[:, 0], b[:, 1]], 1)
    grid = np.stack([a, c, b, a, b, d], axis=1).reshape(-1, 2)  # counter-clockwise seen from above (map y north)
    scene = to_scene(grid)
    inner = np.empty((len(scene), 4), np.float32)
    material = GROUND_LAND if terrain is None else GROUND_TERRAIN
    inner[:, 0], inner[:, 1], inner[:, 2], inner[:, 3] = scene[:, 0], y, scene[:, 1], material
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    outer = shapely.box(cx - HORIZON, cy - HORIZON, cx + HORIZON, cy + HORIZON).difference(shapely.box(x0, y0, x1, y1))
    land = np.concatenate([inner, triangles(outer, y, material)])
    return land if terrain is None else raised(land, terrain)


def area_sizes(areas) -> dict[str, float]:
    """Square metres of each area kind's union (overlapping polygons count once)."""
    return {
        kind: shapely.union_all([a.polygon for a in areas if a.kind == kind]).area
        for kind in sorted({a.kind for a in areas})
    }


class Land(Feature):
    name = "land"
    area_tags = AREA_TAGS

    def summary(self, data):
        areas = area_sizes(data.areas)
        return {
            "area_m2": {kind: round(area, 1) for kind, area in areas.items()},
            "green_m2": round(sum(areas.get(kind, 0.0) for kind in GREEN), 1),
            "green_kinds": [kind for kind in areas if kind in GREEN],  # the kinds `green_m2` sums
        }

    def build(self, data):
        by_surface: dict[tuple[int, int], list] = {}
        for area in data.areas:
            if area.kind in SURFACES:
                by_surface.setdefault(SURFACES[area.kind], []).append(area.polygon)
        ranked = sorted(by_surface.items(), key=lambda item: item[0][1])
        surfaces = [Surface(union_of(polygons), material, rank) for (material, rank), polygons in ranked]
        return Built(
            Layer(self.name, land_plane(data.bounds(), data.ground_level - BASE_DEPTH, data.terrain)), surfaces
        )
