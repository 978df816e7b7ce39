"""Rooftop units on the flat roofs of blocks: a stair and lift housing where the roof is large
enough, and ventilation and air-conditioning boxes, placed from the building's seed inside the
roof and clear of its parapet and of each other. Closed boxes of sheet metal (ROOF_PART_SHEET),
axis-aligned in the building's object space (its x runs along the outline's longest side)."""

from __future__ import annotations

import numpy as np
import shapely

from ._materials import ROOF_PART_SHEET
from ._roofs import Triangles
from ._solids import boxes

CLEARANCE = 0.8  # metres kept free inside the parapet (a maintenance path) and between units
HOUSING_ROOF = 150.0  # square metres of roof from which a block has a stair and lift housing
HOUSING_SIZE = ((3.0, 4.5), (2.4, 3.2), (2.6, 3.2))  # (low, high) metres along x, across, high
UNIT_SIZE = ((0.8, 2.6), (0.7, 1.8), (0.6, 1.5))
ROOF_PER_UNIT = 200.0  # square metres of roof per ventilation or air-conditioning unit
MAX_UNITS = 6
TRIES = 24  # candidate places drawn at once for each box


def _place(rng, room: shapely.Geometry, taken: list, size) -> np.ndarray | None:
    """(x0, z0, x1, z1) of a box of a size drawn in `size` inside the (prepared) `room`, clear of
    the `taken` boxes by CLEARANCE; None when none of TRIES candidates fits."""
    x0, z0, x1, z1 = room.bounds
    (wl, wh), (dl, dh), _ = size
    w = rng.uniform(wl, wh, TRIES)
    d = rng.uniform(dl, dh, TRIES)
    turned = rng.random(TRIES) < 0.5  # long side along x or along z
    w, d = np.where(turned, d, w), np.where(turned, w, d)
    x = rng.uniform(x0, x1, TRIES) - w / 2
    z = rng.uniform(z0, z1, TRIES) - d / 2
    box = np.column_stack([x, z, x + w, z + d])
    fits = np.ones(TRIES, dtype=bool)
    if taken:
        t = np.array(taken)
        near = (box[:, None, :2] < t[None, :, 2:] + CLEARANCE) & (box[:, None, 2:] > t[None, :, :2] - CLEARANCE)
        fits = ~near.all(axis=2).any(axis=1)
    k = np.flatnonzero(fits)
    k = k[shapely.contains(room, shapely.box(*box[k].T))] if len(k) else k
    return box[k[0]] if len(k) else None


def unit_count(area: float) -> int:
    """How many ventilation and air-conditioning units a roof of `area` square metres carries."""
    return int(np.clip(round(area / ROOF_PER_UNIT), 1, MAX_UNITS))


def rooftop_units(roof: shapely.Polygon, y: float, seed: int) -> Triangles:
    """Closed boxes standing at height `y` on the flat `roof` (object space, inside the parapet):
    a housing on roofs of HOUSING_ROOF square metres or more, then unit_count small units; those
    that find no place are left out."""
    room = roof.buffer(-CLEARANCE, join_style="mitre")
    if room.is_empty:
        return Triangles.empty()
    shapely.prepare(room)
    rng = np.random.default_rng([seed, 0x0F1A7])
    sizes = ([HOUSING_SIZE] if roof.area >= HOUSING_ROOF else []) + [UNIT_SIZE] * unit_count(roof.area)
    placed, heights = [], []
    for size in sizes:
        box = _place(rng, room, placed, size)
        height = rng.uniform(*size[2])
        if box is not None:
            placed.append(box)
            heights.append(height)
    if not placed:
        return Triangles.empty()
    placed, heights = np.array(placed), np.array(heights)
    low = np.column_stack([placed[:, 0], np.full(len(placed), y), placed[:, 1]])
    high = np.column_stack([placed[:, 2], y + heights, placed[:, 3]])
    solid = boxes(low, high)
    solid.part = np.full(len(solid.positions), ROOF_PART_SHEET, np.int64)
    return solid
