"""The `guessed` AOV: the picture tinted by where its walls and roofs come from.

Per pixel, the id AOV names the face (wall, roof, a room seen through a window) and the building;
each building mass carries the map attributes the guessing model invented (`BuildingMass.guessed`).
Walls (and the rooms behind them) of a building whose size the map gave neither as a height nor as
levels, and roofs whose shape was guessed, are tinted orange; what the data gave is tinted blue.
Ground, trees and sky stay as they are.
"""

from __future__ import annotations

import numpy as np

from ..interior import FACE_NAMES
from ..scene import BuildingMass

FACE = {name: code for code, name in FACE_NAMES.items()}

GUESSED_TINT = np.array([255, 120, 20], np.float32)
TAGGED_TINT = np.array([40, 140, 255], np.float32)
STRENGTH = 0.55


def guessed_aov(image: np.ndarray, ids: np.ndarray, masses: list[BuildingMass]) -> np.ndarray:
    """HxWx3 uint8 `image` tinted per pixel from the HxWx4 id AOV `ids` (face, room, building + 1, 0)."""
    face, building = ids[..., 0], ids[..., 2].astype(np.int64) - 1
    on_building = (building >= 0) & (building < len(masses)) & (face != FACE["none"]) & (face != FACE["ground"])
    height_guessed = np.array([{"height", "levels"} <= m.guessed for m in masses] + [False])
    roof_guessed = np.array([("roof_shape" in m.guessed) for m in masses] + [False])
    index = np.where(on_building, building, len(masses))
    guessed = np.where(face == FACE["roof"], roof_guessed[index], height_guessed[index])
    tint = np.where(guessed[..., None], GUESSED_TINT, TAGGED_TINT)
    mixed = image.astype(np.float32) * (1 - STRENGTH) + tint * STRENGTH
    return np.where(on_building[..., None], mixed, image).round().astype(np.uint8)
