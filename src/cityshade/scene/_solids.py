"""Small closed solids on roofs (rooftop units, dormers): boxes and gabled boxes as Triangles."""

from __future__ import annotations

import numpy as np

from ._roofs import Triangles

# a box's corners by index (bit 0: x high, bit 1: y high, bit 2: z high) and its faces as two
# triangles each, counter-clockwise seen from outside
BOX_FACES = {
    "bottom": [0, 1, 5, 0, 5, 4],
    "top": [2, 6, 7, 2, 7, 3],
    "-x": [0, 4, 6, 0, 6, 2],
    "+x": [1, 3, 7, 1, 7, 5],
    "-z": [0, 2, 3, 0, 3, 1],
    "+z": [4, 5, 7, 4, 7, 6],
}
FACE_NORMALS = {
    "bottom": (0, -1, 0),
    "top": (0, 1, 0),
    "-x": (-1, 0, 0),
    "+x": (1, 0, 0),
    "-z": (0, 0, -1),
    "+z": (0, 0, 1),
}


def boxes(low: np.ndarray, high: np.ndarray, faces=tuple(BOX_FACES)) -> Triangles:
    """Axis-aligned boxes from corners low to high (n, 3 each), the given faces of each, box after box."""
    bits = np.array([[i & 1, (i >> 1) & 1, (i >> 2) & 1] for i in range(8)], dtype=bool)
    corners = np.where(bits[None], high[:, None], low[:, None])  # (n, 8, 3)
    order = np.concatenate([BOX_FACES[f] for f in faces])
    positions = corners[:, order].reshape(-1, 3)
    normals = np.tile(np.repeat(np.array([FACE_NORMALS[f] for f in faces], np.float64), 6, axis=0), (len(low), 1))
    return Triangles(positions, normals)
