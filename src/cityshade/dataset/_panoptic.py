"""COCO panoptic segmentation of a sample (`--panoptic`): a PNG whose pixels hold segment ids as
R + 256 G + 256^2 B (0 = void) and the segments' records (id, category_id, area, bbox, iscrowd);
`panoptic.json` at the dataset's root gathers them with the images and the categories.

Buildings are the one thing category, one segment per building (OSM or CityObject id, all its
parts); every other native class is a stuff category with one segment per image. Category ids
are the native class index + 1 for stuff and BUILDING_CATEGORY for buildings; ignored classes
are void.
"""

from __future__ import annotations

import numpy as np

from ._classes import CLASS_COLOURS, CLASSES, IGNORE

BUILDING_CLASSES = ("wall", "window", "door", "shop_front", "balcony_relief", "roof")
BUILDING_CATEGORY = 100
STUFF_ID_BASE = 1 << 23  # stuff segment ids: base + category id; building segments: the building number
STUFF = tuple(name for name in CLASSES if name not in BUILDING_CLASSES)


def categories() -> list[dict]:
    """The COCO panoptic categories: the stuff classes and `building`."""
    stuff = [
        {
            "id": CLASSES.index(name) + 1,
            "name": name,
            "supercategory": "stuff",
            "isthing": 0,
            "color": [int(c) for c in CLASS_COLOURS[CLASSES.index(name)]],
        }
        for name in STUFF
    ]
    building = {"id": BUILDING_CATEGORY, "name": "building", "supercategory": "building", "isthing": 1}
    return stuff + [{**building, "color": [int(c) for c in CLASS_COLOURS[CLASSES.index("wall")]]}]


def id_to_rgb(ids: np.ndarray) -> np.ndarray:
    """HxW segment ids -> HxWx3 uint8 (R + 256 G + 256^2 B), as panopticapi.utils.id2rgb."""
    ids = ids.astype(np.uint32)
    return np.stack([(ids >> s) & 255 for s in (0, 8, 16)], axis=-1).astype(np.uint8)


def panoptic(classes: np.ndarray, buildings: np.ndarray) -> tuple[np.ndarray, list[dict]]:
    """(HxWx3 uint8 panoptic PNG, segments_info) from the class image and the building numbers."""
    stuff_category = np.zeros(256, np.uint32)
    for name in STUFF:
        stuff_category[CLASSES.index(name)] = CLASSES.index(name) + 1
    ids = np.where(stuff_category[classes] > 0, STUFF_ID_BASE + stuff_category[classes], 0).astype(np.uint32)
    is_building = (buildings > 0) & (classes != IGNORE)
    ids[is_building] = buildings[is_building]
    values, inverse, counts = np.unique(ids.ravel(), return_inverse=True, return_counts=True)
    rows, columns = (a.ravel() for a in np.indices(ids.shape))
    low = [np.full(len(values), np.iinfo(np.int64).max) for _ in range(2)]
    high = [np.full(len(values), -1) for _ in range(2)]
    for k, coordinate in enumerate((columns, rows)):  # each segment's bounding box
        np.minimum.at(low[k], inverse, coordinate)
        np.maximum.at(high[k], inverse, coordinate)
    segments = [
        {
            "id": int(value),
            "category_id": int(value - STUFF_ID_BASE) if value >= STUFF_ID_BASE else BUILDING_CATEGORY,
            "area": int(counts[k]),
            "bbox": [int(low[0][k]), int(low[1][k]), int(high[0][k] - low[0][k] + 1), int(high[1][k] - low[1][k] + 1)],
            "iscrowd": 0,
        }
        for k, value in enumerate(values.tolist())
        if value != 0
    ]
    return id_to_rgb(ids), segments


def panoptic_document(records: list[dict]) -> dict:
    """panoptic.json from each sample's (index, width, height, segments_info), in index order."""
    images, annotations = [], []
    for record in records:
        name = f"{record['index']:07d}"
        images.append(
            {
                "id": record["index"],
                "file_name": f"{name}.rgb.png",
                "width": record["width"],
                "height": record["height"],
            }
        )
        annotations.append(
            {"image_id": record["index"], "file_name": f"{name}.png", "segments_info": record["segments_info"]}
        )
    return {
        "info": {"description": "cityshade dataset: images in samples/, panoptic PNGs in panoptic/"},
        "licenses": [],
        "images": images,
        "annotations": annotations,
        "categories": categories(),
    }
