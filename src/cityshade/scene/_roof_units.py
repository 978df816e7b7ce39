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


def _candidates(rng, room: shapely.Geometry, sizes: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(places (S, TRIES, 4) of x0, z0, x1, z1, whether their corners are in the room (S, TRIES),
    heights (S,)): TRIES candidate places for a box of each of `sizes` ((S, 3, 2): low and high
    metres along x, across and high), all drawn at once."""
    x0, z0, x1, z1 = room.bounds
    shape = (len(sizes), TRIES)
    draw = rng.random((6, *shape))  # one call: sizes, turns, places and heights of every candidate
    low, span = sizes[:, :, 0], sizes[:, :, 1] - sizes[:, :, 0]
    w = low[:, :1] + draw[0] * span[:, :1]
    d = low[:, 1:2] + draw[1] * span[:, 1:2]
    turned = draw[2] < 0.5  # long side along x or along z
    w, d = np.where(turned, d, w), np.where(turned, w, d)
    x = x0 + draw[3] * (x1 - x0) - w / 2
    z = z0 + draw[4] * (z1 - z0) - d / 2
    heights = low[:, 2] + draw[5, :, 0] * span[:, 2]
    places = np.stack([x, z, x + w, z + d], axis=2)
    corners = places[..., [[0, 1], [2, 1], [2, 3], [0, 3]]].reshape(-1, 2)
    inside = shapely.contains_xy(room, corners[:, 0], corners[:, 1]).reshape(*shape, 4).all(axis=2)
    return places, inside, heights


def _clear(places: np.ndarray, taken: list) -> np.ndarray:
    """Which places (n, 4) keep CLEARANCE from every `taken` one."""
    if not taken:
        return np.ones(len(places), dtype=bool)
    t = np.array(taken)
    near = (places[:, None, :2] < t[None, :, 2:] + CLEARANCE) & (places[:, None, 2:] > t[None, :, :2] - CLEARANCE)
    return ~near.all(axis=2).any(axis=1)


def unit_count(area: float) -> int:
    """How many ventilation and air-conditioning units a roof of `area` square metres carries."""
    return min(max(round(area / ROOF_PER_UNIT), 1), MAX_UNITS)


def rooftop_units(roof: shapely.Polygon, y: float, seed: int) -> Triangles:
    """Closed boxes standing at height `y` on the flat `roof` (object space, inside the parapet):
    a housing on roofs of HOUSING_ROOF square metres or more, then unit_count small units; those
    that find no place are left out."""
    room = roof.buffer(-CLEARANCE, join_style="mitre")
    if room.is_empty:
        return Triangles.empty()
    shapely.prepare(room)
    rng = np.random.default_rng([seed, 0x0F1A7])
    sizes = np.array(([HOUSING_SIZE] if roof.area >= HOUSING_ROOF else []) + [UNIT_SIZE] * unit_count(roof.area))
    candidates, inside, drawn = _candidates(rng, room, sizes)
    convex = room.convex_hull.area - room.area < 1e-6  # corners inside: the whole box inside
    placed, heights = [], []
    for options, fits, height in zip(candidates, inside, drawn):
        for k in np.flatnonzero(fits & _clear(options, placed)):
            if convex or room.contains(shapely.box(*options[k])):
                placed.append(options[k])
                heights.append(height)
                break
    if not placed:
        return Triangles.empty()
    placed, heights = np.array(placed), np.array(heights)
    low = np.column_stack([placed[:, 0], np.full(len(placed), y), placed[:, 1]])
    high = np.column_stack([placed[:, 2], y + heights, placed[:, 3]])
    solid = boxes(low, high)
    solid.part = np.full(len(solid.positions), ROOF_PART_SHEET, np.int64)
    return solid
