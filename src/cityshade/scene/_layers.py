"""A city's layers: each kind of map data (streets, rail, water, land, trees, lamps, ...) as what it
puts in the city, in three typed parts that every consumer takes the same way. The GPU upload, the
tile cache, export and dataset labels iterate layers through `City`; none of them names one, so a
new kind of map data is a new layer, not a field every consumer reads."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


def no_ground() -> np.ndarray:
    return np.zeros((0, 4), np.float32)


@dataclass(frozen=True)
class Layer:
    """`ground`: (N*3, 4) float32 triangles (x, y, z, material) of the ground mesh, drawn in layer
    order (the material says the colour, shaders/city/map_ground.glsl, and the dataset label,
    GROUND_MATERIAL_TABLE); `lights`: (N, 4) float32 point lights (scene x, y, z of the bulb, reach in
    metres); `trees`: tree records (trees.TREE_DTYPE) or None where the layer plants none."""

    name: str  # the map feature it comes from (maps/features/)
    ground: np.ndarray = field(default_factory=no_ground)
    lights: np.ndarray = field(default_factory=no_ground)
    trees: np.ndarray | None = None
