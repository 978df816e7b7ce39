"""Street lamps of a map: point lights (bulb position and reach) and their posts as small boxes
in the ground mesh (a thin post, a lamp head whose underside glows at night)."""

from __future__ import annotations

import numpy as np

from ._ground import GROUND_BULB, GROUND_POST
from ._model import MapData, to_scene

REACH_PER_METRE = 3.5  # a lamp lights the ground out to 3.5 times its height
POST_HALF, HEAD_HALF, HEAD_DEPTH = 0.07, 0.25, 0.3

# the 12 triangles of a unit box [0, 1]^3 as corner indices (bit 0: x, bit 1: y, bit 2: z)
_BOX = np.array([(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                 (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])
_CORNERS = np.array([((i >> 0) & 1, (i >> 1) & 1, (i >> 2) & 1) for i in range(8)], float)


def lamp_lights(map_data: MapData) -> np.ndarray:
    """(N, 4) float32: scene x, y, z of each bulb and the reach of its light in metres."""
    if not map_data.lamps:
        return np.zeros((0, 4), np.float32)
    xz = to_scene(np.array([lamp.position for lamp in map_data.lamps], float))
    height = np.array([lamp.height for lamp in map_data.lamps], float)
    return np.c_[xz[:, 0], height - HEAD_DEPTH, xz[:, 1], height * REACH_PER_METRE].astype(np.float32)


def boxes(low: np.ndarray, high: np.ndarray, material: int) -> np.ndarray:
    """Triangles (N*36, 4) of axis-aligned boxes from corners `low` to `high` (N, 3)."""
    corners = low[:, None, :] + _CORNERS[None, :, :] * (high - low)[:, None, :]
    vertices = corners[:, _BOX.ravel(), :].reshape(-1, 3)
    return np.c_[vertices, np.full(len(vertices), material)].astype(np.float32)


def lamp_posts(lights: np.ndarray) -> np.ndarray:
    """Posts and glowing heads for lamp lights from `lamp_lights`."""
    if not len(lights):
        return np.zeros((0, 4), np.float32)
    x, bulb, z = lights[:, 0], lights[:, 1], lights[:, 2]
    top = bulb + HEAD_DEPTH
    post = boxes(np.c_[x - POST_HALF, np.zeros_like(x), z - POST_HALF], np.c_[x + POST_HALF, bulb, z + POST_HALF],
                 GROUND_POST)
    head = boxes(np.c_[x - HEAD_HALF, bulb, z - HEAD_HALF], np.c_[x + HEAD_HALF, top, z + HEAD_HALF], GROUND_BULB)
    return np.concatenate([post, head])
