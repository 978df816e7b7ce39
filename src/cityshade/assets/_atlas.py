"""Single-texture atlas of all room faces (paper §3.2 and §4.2)."""

from __future__ import annotations

import numpy as np

from ._rooms import FACES


def room_atlas(textures: dict, padding: int = 4) -> tuple[np.ndarray, dict]:
    """Pack room_textures() output into one (H, W, 4) uint8 image and its layout.

    Face f (index in layout["face_order"]) of variant k sits in column k, row f of a
    grid, origin bottom-left (row 0 of the image is v = 0). Each cell is
    tile + 2 * padding texels; the padding repeats the tile's edge texels so mipmapped
    bilinear sampling does not bleed between tiles. The tile's texels start at

        x0 = k * (tile + 2 * padding) + padding,   y0 = f * (tile + 2 * padding) + padding

    so a face coordinate (u, v) in [0, 1] maps to atlas coordinates
    ((x0 + u * tile) / W, (y0 + v * tile) / H), W = columns * cell, H = rows * cell.
    """
    stacks = [np.asarray(textures[face]) for face in FACES]
    variants, tile = stacks[0].shape[0], stacks[0].shape[1]
    if any(s.shape != stacks[0].shape for s in stacks) or stacks[0].shape[1] != stacks[0].shape[2]:
        raise ValueError("room_atlas needs four square face stacks of one shape (variants, size, size, 4)")
    cell = tile + 2 * padding
    atlas = np.empty((len(FACES) * cell, variants * cell, 4), np.uint8)
    for f, stack in enumerate(stacks):
        padded = np.pad(stack, ((0, 0), (padding, padding), (padding, padding), (0, 0)), mode="edge")
        # (variants, cell, cell, 4) -> one row of the grid, variants side by side.
        atlas[f * cell : (f + 1) * cell] = padded.transpose(1, 0, 2, 3).reshape(cell, variants * cell, 4)
    layout = {"tile": tile, "padding": padding, "columns": variants, "rows": len(FACES), "face_order": list(FACES)}
    return atlas, layout
