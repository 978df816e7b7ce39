"""A map's layers laid on its terrain (MapData.terrain): ground split to the terrain's spacing and
raised onto it, water flat at its own level (the lowest ground on its outline), lamps, their lights
and trees standing on the ground under them. The terrain's own layer and the land plane are built
on it already (features/terrain.py, features/land.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import shapely

from ..scene import GROUND_WATER, Layer
from ..terrain import Terrain, draped, raised
from ._model import MapData, to_scene

BUILT_ON_TERRAIN = ("terrain", "land")


def _water_levels(data: MapData, terrain: Terrain):
    """(water pieces in scene x, z, the level of each)."""
    water = shapely.union_all([a.polygon for a in data.areas if a.kind == "water"])
    parts = [p for p in shapely.get_parts(water) if not p.is_empty]
    levels = np.array([terrain.lowest_on(p) for p in parts])
    return shapely.transform(np.asarray(parts, dtype=object), to_scene), levels


def _levelled(ground: np.ndarray, pieces, levels: np.ndarray, terrain: Terrain) -> np.ndarray:
    """Water triangles at the level of the piece each lies in (draped where it lies in none)."""
    out = ground.copy()
    centres = ground[:, [0, 2]].reshape(-1, 3, 2).mean(axis=1)
    piece = np.full(len(centres), -1)
    if len(pieces):
        which, where = shapely.STRtree(pieces).query(shapely.points(centres), predicate="intersects")
        piece[which] = where
    level = np.where(piece >= 0, levels[np.maximum(piece, 0)] if len(levels) else 0.0, np.nan)
    loose = np.repeat(np.isnan(level), 3)
    out[:, 1] += np.repeat(np.nan_to_num(level), 3).astype(out.dtype)
    return np.concatenate([out[~loose], draped(ground[loose], terrain)])


class Draping:
    """Lays a map's ground, lights and trees on its terrain."""

    def __init__(self, data: MapData, terrain: Terrain):
        self.terrain = terrain
        self.pieces, self.levels = _water_levels(data, terrain)

    def ground(self, ground: np.ndarray) -> np.ndarray:
        """Ground triangles draped, water among them levelled."""
        water = ground[:, 3] == GROUND_WATER
        return np.concatenate(
            [draped(ground[~water], self.terrain), _levelled(ground[water], self.pieces, self.levels, self.terrain)]
        )

    def layer(self, layer: Layer) -> Layer:
        """A layer built flat, on the terrain (the terrain's own and the land plane are built on it)."""
        if layer.name in BUILT_ON_TERRAIN:
            return layer
        trees = layer.trees
        if trees is not None and len(trees):
            trees = trees.copy()
            trees["position"] = raised(trees["position"], self.terrain)
        return replace(layer, ground=self.ground(layer.ground), lights=raised(layer.lights, self.terrain), trees=trees)


def draping(data: MapData) -> Draping | None:
    """The Draping of a map with a terrain; None for a flat one."""
    return None if data.terrain is None else Draping(data, data.terrain)
