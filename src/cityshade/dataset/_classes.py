"""The semantic classes of a dataset and how the id AOV's codes map to them (numpy).

The id AOV gives per pixel (face code, room, building index + 1, w): w is the facade grammar's
label (assets.LABELS) on buildings and the ground material on the ground. Trees are not in the id
AOV: they are the pixels the frame's depth puts in front of the id AOV's depth (`tree_mask`).
"""

from __future__ import annotations

import numpy as np

from ..assets import LABELS
from ..interior import FACE_NAMES

CLASSES = (
    "sky", "road", "pavement", "lane_marking", "grass", "water", "wall", "window", "door", "shop_front",
    "balcony_relief", "roof", "tree", "lamp", "rail", "bare_ground",
)
IGNORE = 255  # the class image's value for classes a config ignores
CLASS_COLOURS = np.array([
    (112, 160, 220), (60, 60, 64), (170, 160, 150), (250, 250, 250), (80, 170, 60), (30, 80, 190),
    (200, 170, 130), (60, 200, 230), (150, 60, 30), (230, 60, 160), (230, 200, 40), (170, 40, 40),
    (20, 110, 30), (255, 140, 0), (120, 90, 160), (150, 120, 70),
], np.uint8)

# ground materials (scene GROUND_* 0..2, maps' 3..10) -> class
GROUND_CLASSES = ("road", "pavement", "grass", "water", "lane_marking", "rail", "rail", "bare_ground", "bare_ground",
                  "lamp", "lamp")
# facade grammar labels -> class ('room' is what shows through a window's glass, 'cornice' is relief)
LABEL_CLASSES = {"wall": "wall", "window": "window", "room": "window", "door": "door", "balcony": "balcony_relief",
                 "shop": "shop_front", "roof": "roof", "cornice": "balcony_relief"}

FACE_CODES = {name: code for code, name in FACE_NAMES.items()}
FACE_EXTERIOR, FACE_ROOF, FACE_GROUND = FACE_CODES["exterior"], FACE_CODES["roof"], FACE_CODES["ground"]
INTERIOR_FACES = [FACE_CODES[name] for name in ("ceiling", "floor", "wall x", "wall z", "furniture", "curtain")]


def _lookup(names) -> np.ndarray:
    return np.array([CLASSES.index(n) for n in names], np.uint8)


_GROUND = _lookup(GROUND_CLASSES)
_LABEL = np.array([CLASSES.index(LABEL_CLASSES.get(name, "wall")) for name in LABELS], np.uint8)


def class_image(ids: np.ndarray, trees: np.ndarray | None = None, ignore=()) -> np.ndarray:
    """HxW uint8 class indices from the id AOV (HxWx4 uint32) and a tree mask (HxW bool)."""
    face, label = ids[..., 0], ids[..., 3]
    out = np.zeros(face.shape, np.uint8)  # sky
    building = (face >= 1) & (face != FACE_GROUND)
    out[building & (face == FACE_EXTERIOR)] = CLASSES.index("wall")  # bay-texture and relief facades
    out[building & np.isin(face, INTERIOR_FACES)] = CLASSES.index("window")  # seen through glass
    graded = building & (label > 0) & (label < len(LABELS))  # the grammar's own label wins
    out[graded] = _LABEL[label[graded]]
    out[face == FACE_ROOF] = CLASSES.index("roof")
    ground = face == FACE_GROUND
    out[ground] = _GROUND[np.minimum(label[ground], len(_GROUND) - 1)]
    if trees is not None:
        out[trees] = CLASSES.index("tree")
    for name in ignore:
        out[out == CLASSES.index(name)] = IGNORE
    return out


def instance_image(ids: np.ndarray, trees: np.ndarray | None = None) -> np.ndarray:
    """HxW uint32: building index + 1 on buildings and roofs, 0 elsewhere (and in front, on trees)."""
    face = ids[..., 0]
    building = (face >= 1) & (face != FACE_GROUND)
    if trees is not None:
        building &= ~trees
    return np.where(building, ids[..., 2], 0).astype(np.uint32)
