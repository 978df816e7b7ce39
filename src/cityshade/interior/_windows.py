"""Windows that straddle rooms, counted in the id AOV: each window should open onto exactly one room.

A window is a 4-connected patch of pixels that see a room (its ceiling, floor, walls, furniture or
curtain) on one building; it straddles when its pixels carry more than one room id.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ._faces import FACE_CEILING, FACE_CURTAIN, FACE_FLOOR, FACE_FURNITURE, FACE_WALL_X, FACE_WALL_Z

ROOM_FACES = (FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z, FACE_FURNITURE, FACE_CURTAIN)


@dataclass(frozen=True)
class WindowCount:
    windows: int
    straddling: int
    # per straddling window: (building + 1, its room ids, pixels, a pixel (row, column) of it)
    examples: tuple[tuple[int, tuple[int, ...], int, tuple[int, int]], ...]


def windows_straddling_rooms(ids: np.ndarray) -> WindowCount:
    """Windows and how many of them show more than one room, in an id AOV (H, W, >= 3: face, room,
    building + 1)."""
    seen = np.isin(ids[..., 0], ROOM_FACES)
    patches, _ = ndimage.label(seen)
    window = (patches.astype(np.int64) << 32) | ids[..., 2].astype(np.int64)  # a patch on one building
    keys, first, inverse = np.unique(window[seen], return_index=True, return_inverse=True)
    rooms = ids[..., 1][seen].astype(np.int64)
    pairs = np.unique(np.stack([inverse, rooms], axis=1), axis=0)
    per_window = np.bincount(pairs[:, 0], minlength=len(keys))
    rows, cols = np.nonzero(seen)
    examples = []
    for k in np.nonzero(per_window > 1)[0]:
        examples.append((int(keys[k] & 0xFFFFFFFF), tuple(int(r) for r in pairs[pairs[:, 0] == k, 1]),
                         int(np.sum(inverse == k)), (int(rows[first[k]]), int(cols[first[k]]))))
    return WindowCount(len(keys), int(np.sum(per_window > 1)), tuple(examples))
