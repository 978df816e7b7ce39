"""The semantic classes of a dataset and how the id AOV's codes map to them (numpy).

The id AOV gives per pixel (face code, room, building index + 1, w): w is the facade grammar's
label (assets.LABELS) on buildings and the ground material on the ground; trees are their own
faces, trunk (with its fins) and foliage (leaf cards and fronds), and belong to no building.
"""

from __future__ import annotations

import numpy as np

from ..assets import LABELS
from ..interior import FACE_NAMES
from ..scene import GROUND_TABLE

CLASSES = (
    "sky",
    "road",
    "pavement",
    "lane_marking",
    "grass",
    "water",
    "wall",
    "window",
    "door",
    "shop_front",
    "balcony_relief",
    "roof",
    "tree_trunk",
    "lamp",
    "rail",
    "bare_ground",
    "foliage",
    "terrain",
)
IGNORE = 255  # the class image's value for classes a config ignores
CLASS_COLOURS = np.array(
    [
        (112, 160, 220),
        (60, 60, 64),
        (170, 160, 150),
        (250, 250, 250),
        (80, 170, 60),
        (30, 80, 190),
        (200, 170, 130),
        (60, 200, 230),
        (150, 60, 30),
        (230, 60, 160),
        (230, 200, 40),
        (170, 40, 40),
        (90, 55, 30),
        (255, 140, 0),
        (120, 90, 160),
        (150, 120, 70),
        (20, 110, 30),
        (140, 150, 80),
    ],
    np.uint8,
)

# ground materials (scene.GROUND_TABLE, by id) -> class
GROUND_CLASSES = tuple(GROUND_TABLE[material][0] for material in range(len(GROUND_TABLE)))
# facade grammar labels -> class ('room' is what shows through a window's glass, 'cornice' is relief)
LABEL_CLASSES = {
    "wall": "wall",
    "window": "window",
    "room": "window",
    "door": "door",
    "balcony": "balcony_relief",
    "shop": "shop_front",
    "roof": "roof",
    "cornice": "balcony_relief",
}

FACE_CODES = {name: code for code, name in FACE_NAMES.items()}
FACE_EXTERIOR, FACE_ROOF, FACE_GROUND = FACE_CODES["exterior"], FACE_CODES["roof"], FACE_CODES["ground"]
TREE_CLASSES = {FACE_CODES["trunk"]: "tree_trunk", FACE_CODES["foliage"]: "foliage"}
NOT_BUILDING = [FACE_CODES["none"], FACE_GROUND, *TREE_CLASSES]
INTERIOR_FACES = [FACE_CODES[name] for name in ("ceiling", "floor", "wall x", "wall z", "furniture", "curtain")]


def _lookup(names) -> np.ndarray:
    return np.array([CLASSES.index(n) for n in names], np.uint8)


_GROUND = _lookup(GROUND_CLASSES)
_LABEL = np.array([CLASSES.index(LABEL_CLASSES.get(name, "wall")) for name in LABELS], np.uint8)


def on_building(face: np.ndarray) -> np.ndarray:
    """Where the id AOV's face code is a building's (its facades, roofs, rooms seen through glass)."""
    return ~np.isin(face, NOT_BUILDING)


def class_image(ids: np.ndarray, ignore=()) -> np.ndarray:
    """HxW uint8 class indices from the id AOV (HxWx4 uint32)."""
    face, label = ids[..., 0], ids[..., 3]
    out = np.zeros(face.shape, np.uint8)  # sky
    building = on_building(face)
    out[building & (face == FACE_EXTERIOR)] = CLASSES.index("wall")  # bay-texture and relief facades
    out[building & np.isin(face, INTERIOR_FACES)] = CLASSES.index("window")  # seen through glass
    graded = building & (label > 0) & (label < len(LABELS))  # the grammar's own label wins
    out[graded] = _LABEL[label[graded]]
    out[face == FACE_ROOF] = CLASSES.index("roof")
    ground = face == FACE_GROUND
    out[ground] = _GROUND[np.minimum(label[ground], len(_GROUND) - 1)]
    for code, name in TREE_CLASSES.items():
        out[face == code] = CLASSES.index(name)
    for name in ignore:
        out[out == CLASSES.index(name)] = IGNORE
    return out


def instance_image(ids: np.ndarray) -> np.ndarray:
    """HxW uint32: mass index + 1 on buildings and roofs, 0 elsewhere (on trees in front of one too)."""
    return np.where(on_building(ids[..., 0]), ids[..., 2], 0).astype(np.uint32)


def building_instances(masses: np.ndarray, mass_building: np.ndarray, mass_part: np.ndarray) -> np.ndarray:
    """HxWx2 uint32 from an instance_image: channel 0 the building number, channel 1 the part
    number within it (both 1-based, 0 where no building is)."""
    out = np.zeros((*masses.shape, 2), np.uint32)
    hit = (masses > 0) & (masses <= len(mass_building))
    out[hit, 0] = mass_building[masses[hit] - 1]
    out[hit, 1] = mass_part[masses[hit] - 1]
    return out


# Cityscapes (cityscapesScripts' labels.py): native class -> (labelId, trainId). Facades, windows,
# doors, shop fronts, balconies and roofs are all `building` (Cityscapes' `wall` is a free-standing
# wall); trunks and foliage `vegetation`; lamp posts `pole`; lane paint `road`; bare ground and grass
# `terrain`; water has no Cityscapes class and is `unlabeled`, as are ignored classes.
CITYSCAPES_LABELS = {
    "unlabeled": (0, 255),
    "road": (7, 0),
    "sidewalk": (8, 1),
    "rail track": (10, 255),
    "building": (11, 2),
    "pole": (17, 5),
    "vegetation": (21, 8),
    "terrain": (22, 9),
    "sky": (23, 10),
}
CITYSCAPES_OF = {
    "sky": "sky",
    "road": "road",
    "pavement": "sidewalk",
    "lane_marking": "road",
    "grass": "terrain",
    "water": "unlabeled",
    "wall": "building",
    "window": "building",
    "door": "building",
    "shop_front": "building",
    "balcony_relief": "building",
    "roof": "building",
    "tree_trunk": "vegetation",
    "lamp": "pole",
    "rail": "rail track",
    "bare_ground": "terrain",
    "foliage": "vegetation",
    "terrain": "terrain",
}


def _cityscapes_table(column: int) -> np.ndarray:
    table = np.full(256, CITYSCAPES_LABELS["unlabeled"][column], np.uint8)  # IGNORE -> unlabeled
    for index, name in enumerate(CLASSES):
        table[index] = CITYSCAPES_LABELS[CITYSCAPES_OF[name]][column]
    return table


CITYSCAPES_LABEL_IDS, CITYSCAPES_TRAIN_IDS = _cityscapes_table(0), _cityscapes_table(1)


def cityscapes_images(classes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(labelIds, trainIds) uint8 images of a native class image."""
    return CITYSCAPES_LABEL_IDS[classes], CITYSCAPES_TRAIN_IDS[classes]
