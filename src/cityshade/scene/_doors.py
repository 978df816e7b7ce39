"""Doors: where a building's doors stand, as points on its outline with the outward normal of the wall
there, and the numpy twin of the shader's door test (shaders/city/doors.glsl).

A door is DOOR_WIDTH wide and DOOR_HEIGHT high from the ground, centred on its point; a wall pixel
is in it when it lies on the door's wall (facing the door's way, within DOOR_PLANE of the plane
through the point: outlines drawn as short segments still count as one wall) and within the
door's width and height. The record holds MAX_DOORS (x, z, normal x, normal z); a zero normal is
no door, so a record left zero has none.
"""

from __future__ import annotations

import numpy as np

DOOR_WIDTH = 1.4  # metres
DOOR_HEIGHT = 2.3
DOOR_PLANE = 0.15  # metres off the plane through the door's point that still count as its wall
DOOR_FACING = 0.9  # cosine between a wall's normal and the door's above which the wall can hold it
MAX_DOORS = 4
DOOR_CONSTANTS = {
    "DOOR_WIDTH": DOOR_WIDTH,
    "DOOR_HEIGHT": DOOR_HEIGHT,
    "DOOR_PLANE": DOOR_PLANE,
    "DOOR_FACING": DOOR_FACING,
    "MAX_DOORS": MAX_DOORS,
}


def door_on_edge(a, b, point) -> tuple[float, float, float, float] | None:
    """A door on the wall from footprint corner `a` to `b` (counter-clockwise, so the outside is on
    the right) nearest `point`, moved along the wall just as far as it takes to fit whole; None when
    the wall is narrower than a door. Returns (x, z, normal x, normal z)."""
    a, b, point = (np.asarray(v, dtype=np.float64) for v in (a, b, point))
    edge = b - a
    length = float(np.hypot(*edge))
    if length < DOOR_WIDTH:
        return None
    along = edge / length
    half = DOOR_WIDTH / 2
    s = float(np.clip(np.dot(point - a, along), half, length - half))
    x, z = a + along * s
    return float(x), float(z), float(along[1]), float(-along[0])


def door_record(doors) -> np.ndarray:
    """(MAX_DOORS, 4) float32 for the building record: the first MAX_DOORS doors, zeros after."""
    record = np.zeros((MAX_DOORS, 4), dtype=np.float32)
    if doors:
        record[: min(len(doors), MAX_DOORS)] = np.asarray(doors[:MAX_DOORS], dtype=np.float32)
    return record


def door_hit(local: np.ndarray, normal: np.ndarray, doors) -> tuple[np.ndarray, np.ndarray]:
    """Per wall point (object space, (N, 3), with its outward normal): whether it is in one of the
    doors, and the (u, v) in that door (0..1 across and up), as `door_at` in doors.glsl decides."""
    local, normal = np.asarray(local, dtype=np.float64), np.asarray(normal, dtype=np.float64)
    hit = np.zeros(len(local), dtype=bool)
    uv = np.zeros((len(local), 2))
    for x, z, nx, nz in door_record(doors).astype(np.float64):
        if nx == 0.0 and nz == 0.0:
            continue
        off_x, off_z = local[:, 0] - x, local[:, 2] - z
        across = off_x * nx + off_z * nz
        along = off_x * -nz + off_z * nx  # the way the outline runs: counter-clockwise seen from above
        inside = (
            (normal[:, 0] * nx + normal[:, 2] * nz > DOOR_FACING)
            & (np.abs(across) < DOOR_PLANE)
            & (np.abs(along) < DOOR_WIDTH / 2)
            & (local[:, 1] >= 0.0)
            & (local[:, 1] < DOOR_HEIGHT)
            & ~hit
        )
        uv[inside] = np.stack([along[inside] / DOOR_WIDTH + 0.5, local[inside, 1] / DOOR_HEIGHT], axis=1)
        hit |= inside
    return hit, uv
