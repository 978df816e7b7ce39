"""Windows that show more than one room, counted in the id AOV: each window should open onto
exactly one room.

Two counts, from `Renderer.render_ids(camera, windows=True)` (face, room, building + 1, window):
- windows: the pixels that see a room through one window (the shader's key of the grammar's window
  rectangle or of the window bay, per building) should all carry one room id;
- glass patches: 4-connected pixels that see a room on one building, whatever window they belong
  to. A patch showing several rooms is either several windows that touch on the screen (a curtain
  wall's panes where their frames are thinner than a pixel, a shop front's glazing run), each with
  its own room, or one window showing several rooms; the second kind is a straddling window too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._faces import FACE_CEILING, FACE_CURTAIN, FACE_FLOOR, FACE_FURNITURE, FACE_WALL_X, FACE_WALL_Z

ROOM_FACES = (FACE_CEILING, FACE_FLOOR, FACE_WALL_X, FACE_WALL_Z, FACE_FURNITURE, FACE_CURTAIN)


@dataclass(frozen=True)
class WindowCount:
    windows: int
    straddling: int  # windows whose pixels show more than one room
    patches: int
    patches_with_rooms: int  # patches showing more than one room
    patches_of_touching_windows: int  # of those, patches of several windows, one room each
    # per straddling window: (building + 1, its room ids, pixels, a pixel (row, column) of it)
    examples: tuple[tuple[int, tuple[int, ...], int, tuple[int, int]], ...]


def _groups(keys: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Distinct keys, the index of each one's first element, each element's key index, and how many
    distinct values each key holds."""
    unique, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    pairs = np.unique(np.stack([inverse, values], axis=1), axis=0)
    return unique, first, inverse, np.bincount(pairs[:, 0], minlength=len(unique))


def windows_straddling_rooms(ids: np.ndarray) -> WindowCount:
    """Counts over an id AOV with window keys (H, W, 4)."""
    from scipy import ndimage  # a second of imports that `import cityshade` does not pay

    seen = np.isin(ids[..., 0], ROOM_FACES) & (ids[..., 3] != 0)
    building = ids[..., 2][seen].astype(np.int64)
    rooms = ids[..., 1][seen].astype(np.int64)
    windows = ids[..., 3][seen].astype(np.int64)
    keys, first, inverse, rooms_per_window = _groups((building << 32) | windows, rooms)
    patches, _ = ndimage.label(seen)
    patch_keys = (patches[seen].astype(np.int64) << 32) | building
    _, _, patch_of, rooms_per_patch = _groups(patch_keys, rooms)
    _, _, _, windows_per_patch = _groups(patch_keys, windows)
    rows, cols = np.nonzero(seen)
    examples = tuple(
        (
            int(keys[k] >> 32),
            tuple(int(r) for r in np.unique(rooms[inverse == k])),
            int(np.sum(inverse == k)),
            (int(rows[first[k]]), int(cols[first[k]])),
        )
        for k in np.nonzero(rooms_per_window > 1)[0]
    )
    several = rooms_per_patch > 1
    return WindowCount(
        len(keys),
        int(np.sum(rooms_per_window > 1)),
        len(rooms_per_patch),
        int(np.sum(several)),
        int(np.sum(several & (windows_per_patch > 1))),
        examples,
    )
