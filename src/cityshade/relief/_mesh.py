"""A facade's relief as triangles: the geometry baseline of the paper's Table 3.

Front faces are the rectangles of equal depth and material (texel runs merged along rows, then
equal runs merged across consecutive rows); side walls stand wherever neighbouring texels differ
in depth and take the material of the higher one, as the tracers texture them. Coordinates are in
map space, like the traced facades, so both draw with the same facade frames. Every quad is wound
counter-clockwise seen from outside in world space, so the mesh can be drawn with back faces culled.
"""

from __future__ import annotations

import numpy as np

from ._maps import DetailMaps
from ._reference import FACE_FRONT, FACE_NEG_X, FACE_NEG_Y, FACE_POS_X, FACE_POS_Y

MESH_VERTEX = np.dtype([("pos", "<f4", 3), ("face", "<i4"), ("material", "<i4")])
# Outward normal of each face in map space (x along, y up, z depth into the wall).
OUTWARD = {
    FACE_FRONT: (0, 0, -1),
    FACE_NEG_X: (-1, 0, 0),
    FACE_POS_X: (1, 0, 0),
    FACE_NEG_Y: (0, -1, 0),
    FACE_POS_Y: (0, 1, 0),
}


def _wound(corners: tuple, face: int) -> tuple:
    """The corners in the order that is counter-clockwise seen from outside in world space. Map
    space goes to world as (along, up, -out), a mirror, so that is clockwise seen from outside in
    map space."""
    a, b, c = (np.asarray(p, float) for p in corners[:3])
    clockwise = np.dot(np.cross(b - a, c - a), OUTWARD[face]) < 0
    return corners if clockwise else corners[::-1]


def _merge_rows(rows: list[list[tuple]]) -> list[tuple]:
    """rows[i] lists (start, end, key) runs of row i; returns (start, end, row0, row1, key) rectangles
    where a run repeats exactly in consecutive rows."""
    open_runs: dict[tuple, int] = {}
    out = []
    for i, runs in enumerate(rows + [[]]):
        current = set(runs)
        for run, first in list(open_runs.items()):
            if run not in current:
                out.append((run[0], run[1], first, i, run[2]))
                del open_runs[run]
        for run in runs:
            open_runs.setdefault(run, i)
    return out


def _runs(values: np.ndarray, keep) -> list[tuple]:
    """(start, end, key) runs of equal consecutive rows of an (n, k) array, where keep(key)."""
    change = np.flatnonzero(np.r_[True, np.any(values[1:] != values[:-1], axis=1)])
    ends = np.r_[change[1:], len(values)]
    out = []
    for s, e in zip(change, ends):
        key = tuple(int(v) for v in values[s])
        if keep(key):
            out.append((int(s), int(e), key))
    return out


def relief_mesh(maps: DetailMaps) -> tuple[np.ndarray, np.ndarray]:
    """(vertices MESH_VERTEX, uint32 triangle indices) of the facade's relief."""
    depth, material = maps.depth.astype(np.int64), maps.material.astype(np.int64)
    rows, cols = depth.shape
    quads = []  # (corner0, corner1, corner2, corner3, face, material)
    both = np.stack([depth, material], axis=-1)
    for x0, x1, y0, y1, (d, m) in _merge_rows([_runs(both[r], lambda k: True) for r in range(rows)]):
        quads.append(((x0, y0, d), (x1, y0, d), (x1, y1, d), (x0, y1, d), FACE_FRONT, m))
    # Walls between columns c-1 and c: key = (depth left, depth right, material of the higher).
    for c in range(1, cols):
        left, right = depth[:, c - 1], depth[:, c]
        higher = np.where(left < right, material[:, c - 1], material[:, c])
        keys = np.stack([left, right, higher], axis=-1)
        for y0, y1, (dl, dr, m) in _runs(keys, lambda k: k[0] != k[1]):
            face = FACE_POS_X if dl < dr else FACE_NEG_X  # facing the deeper side
            quads.append(
                ((c, y0, min(dl, dr)), (c, y1, min(dl, dr)), (c, y1, max(dl, dr)), (c, y0, max(dl, dr)), face, m)
            )
    for r in range(1, rows):
        below, above = depth[r - 1], depth[r]
        higher = np.where(below < above, material[r - 1], material[r])
        keys = np.stack([below, above, higher], axis=-1)
        for x0, x1, (db, da, m) in _runs(keys, lambda k: k[0] != k[1]):
            face = FACE_POS_Y if db < da else FACE_NEG_Y
            quads.append(
                ((x0, r, min(db, da)), (x1, r, min(db, da)), (x1, r, max(db, da)), (x0, r, max(db, da)), face, m)
            )
    vertices = np.zeros(4 * len(quads), MESH_VERTEX)
    for q, (*corners, face, m) in enumerate(quads):
        for k, corner in enumerate(_wound(tuple(corners), face)):
            vertices[4 * q + k] = (corner, face, m)
    base = 4 * np.arange(len(quads), dtype=np.uint32)[:, None]
    indices = (base + np.array([0, 1, 2, 0, 2, 3], np.uint32)).reshape(-1)
    return vertices, indices
