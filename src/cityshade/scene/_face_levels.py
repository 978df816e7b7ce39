"""facade.level, a grammar condition: the storey a wall face's bottom sits at, 0 on the ground.

A mass's walls start at its first level (`BuildingMass.first_level`: for a building part raised off
the ground its building:min_level, which the maps guess from its min_height over its storey height
where it is not tagged), carried in the record's flags word from bit LEVEL_SHIFT. Its walls, gables
and dormer fronts start at that level. A dome's rings stack from its foot: ring k starts k storeys
up the arc (its face's base, an arc length, is k storeys), so its level is the first level plus k.
shaders/grammar/building.glsl `grammar_face_level` is the twin.
"""

from __future__ import annotations

import numpy as np

from ._records import SHAPE_DOME

LEVEL_SHIFT = 12  # the flags' bits below are FLAG_* and the use (scene/_uses.py)
LEVEL_MASK = 0xFFF
LEVEL_CODES = {"LEVEL_SHIFT": LEVEL_SHIFT, "LEVEL_MASK": LEVEL_MASK}


def face_levels(first_level, shape, base, storey) -> np.ndarray:
    """facade.level of faces of masses of `shape` (SHAPE_* codes) starting at `first_level`, whose
    faces start at `base` (metres, the face record's base) with storeys `storey` high."""
    base, storey = np.asarray(base, np.float32), np.asarray(storey, np.float32)
    stacked = np.floor(base / np.where(storey > 0, storey, np.float32(1)) + np.float32(0.5))
    return np.asarray(first_level) + np.where(np.asarray(shape) == SHAPE_DOME, stacked, 0).astype(np.int64)


def vertex_face_levels(vertices: np.ndarray, records: np.ndarray, rows=slice(None)) -> np.ndarray:
    """facade.level of the face of each vertex (VERTEX_DTYPE; those of `rows`) of buildings with
    BUILDING_DTYPE `records`."""
    ids = records["ids"][vertices["ids"][rows, 0]]
    first = (ids[:, 2] >> LEVEL_SHIFT) & LEVEL_MASK
    return face_levels(first, ids[:, 3], vertices["face"][rows, 1], vertices["facade"][rows, 3])
