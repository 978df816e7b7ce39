"""Facade coordinates of the walls standing on an outline ring: where faces begin and end, how wide
they are, and the window bays and rooms along them.

A face is a run of ring edges that turn by at most CORNER_TURN between them: a round tower or a
curved block drawn as many short segments is one face, with one continuous arc-length coordinate,
so its window run does not restart at every vertex. A turn beyond CORNER_TURN is a corner: a face
(and its last bay) ends there. 30 degrees: a regular polygon of 12 or more sides (how OpenStreetMap
draws round towers and curved walls, and how the meshes draw cylinders) is one face, while a
building's corners (90 degrees, and the 45 degrees of bay windows and chamfered street corners)
end faces.

Every face holds a whole number of bays of about the nominal width. The rooms behind a face are
one bay wide and one storey high; their depth is the bay width of the faces meeting it, so that at
a convex (outward) corner the last room of one face and the first of the next are the same box,
and they carry the same column number: the same room is seen through both facades.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

CORNER_TURN = np.radians(30.0)


@dataclass(frozen=True)
class WallFaces:
    """Per ring edge (in the ring's order): the facade coordinate u at the edge's start (metres
    along its face from the face's start), its face's width, bay width and room depth, and the room
    columns of the face's first and last bay (numbered around the building)."""

    along: np.ndarray
    width: np.ndarray
    bay: np.ndarray
    depth: np.ndarray
    columns: np.ndarray  # (edges, 2) int


def wall_faces(lengths: np.ndarray, directions: np.ndarray, nominal_bay: float, first_column: int = 0) -> WallFaces:
    """Faces of a closed ring from its edges' lengths (arc lengths for curves) and directions
    (n, 2); the building lies left of the edges (counter-clockwise outlines, clockwise holes).
    Columns start at `first_column` (rings of one building follow each other)."""
    if not len(lengths):
        return WallFaces(np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 2), dtype=np.int64))
    faces, _ = ring_faces(lengths, directions, np.array([len(lengths)]), np.array([nominal_bay], dtype=np.float64))
    return replace(faces, columns=faces.columns + first_column)


def ring_faces(
    lengths: np.ndarray, directions: np.ndarray, counts: np.ndarray, nominal_bay: np.ndarray
) -> tuple[WallFaces, np.ndarray]:
    """wall_faces of many closed rings at once, their edges stored one ring after another (`counts`
    edges each, none empty), each ring with its nominal bay width and room columns from 0; also
    each ring's column count (ring_columns). A ring's numbers do not depend on the other rings."""
    n, rings = len(lengths), len(counts)
    ring = np.repeat(np.arange(rings), counts)
    ends = np.cumsum(counts)
    begins = ends - counts
    prev = np.arange(n) - 1
    prev[begins] = ends - 1
    turns = _turns(directions[prev], directions)
    start = np.abs(turns) > CORNER_TURN + 1e-6  # a regular 12-gon's turns are 30 degrees up to rounding
    start[begins[np.add.reduceat(start, begins) == 0]] = True  # one face all round: it starts at edge 0
    starts = np.flatnonzero(start)
    faces_in_ring = np.add.reduceat(start.astype(np.int64), begins)
    first_face = np.cumsum(faces_in_ring) - faces_in_ring
    face_ring = ring[starts]
    # faces as runs of edges from each start to the next (the last run wraps round to the first start)
    face = first_face[ring] + (np.cumsum(start) - first_face[ring] - 1) % faces_in_ring[ring]
    # arc length from the ring's first face start, edge by edge in that order
    first_start = starts[first_face] - begins
    by_order = begins[ring] + (np.arange(n) - begins[ring] + first_start[ring]) % counts[ring]
    cumulative = np.empty(n)
    cumulative[by_order] = _sums_before(lengths[by_order], counts)
    width = np.bincount(face, weights=lengths, minlength=len(starts))
    bays = np.maximum(1, np.round(width / nominal_bay[face_ring])).astype(np.int64)
    bay = width / bays
    index = np.arange(len(starts)) - first_face[face_ring]  # face number within its ring
    size = faces_in_ring[face_ring]
    before, after = first_face[face_ring] + (index - 1) % size, first_face[face_ring] + (index + 1) % size
    depth = np.where(size == 1, bay, 0.5 * (bay[before] + bay[after]))
    # room columns: a convex corner (a left turn) shares the room on both of its sides, so the face
    # after it starts on the column of the face before it's last bay
    convex = turns[starts] > 0
    shared = np.cumsum(convex & (index > 0))
    bays_before = np.cumsum(bays) - bays
    first = (bays_before - bays_before[first_face][face_ring]) - (shared - shared[first_face][face_ring])
    last = first + bays - 1
    closing = (faces_in_ring > 1) & convex[first_face]  # the last face's last bay is the first face's first
    last[(first_face + faces_in_ring - 1)[closing]] = first[first_face[closing]]
    columns = np.maximum.reduceat(np.maximum(first, last), first_face) + 1
    return WallFaces(
        along=cumulative - cumulative[starts][face],
        width=width[face],
        bay=bay[face],
        depth=depth[face],
        columns=np.stack([first, last], axis=1)[face],
    ), columns


def _turns(prev: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Signed turn (radians, left positive) from the previous edges `prev` into edges `d`."""
    cross = prev[:, 0] * d[:, 1] - prev[:, 1] * d[:, 0]
    dot = np.sum(prev * d, axis=1)
    return np.arctan2(cross, dot)


def _sums_before(values: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """For rings of `counts` values stored one after another: the sum of the ring's values before
    each, added one by one in order (the same floats as np.cumsum on the ring alone)."""
    out = np.zeros(len(values))
    begins = np.cumsum(counts) - counts
    widths = 2 ** np.ceil(np.log2(np.maximum(counts, 1))).astype(np.int64)
    for width in np.unique(widths):  # rings padded to a power of two: a few tables, not a loop over rings
        rings = np.flatnonzero(widths == width)
        position = begins[rings, None] + np.arange(width)
        inside = np.arange(width) < counts[rings, None]
        table = np.where(inside, values[np.where(inside, position, 0)], 0.0)
        sums = np.cumsum(table[:, :-1], axis=1)
        out[position[:, 1:][inside[:, 1:]]] = sums[inside[:, 1:]]
    return out


def ring_columns(faces: WallFaces) -> int:
    """One past the highest room column of a ring: where the next ring's columns start."""
    return int(faces.columns.max()) + 1 if len(faces.columns) else 0


def storeys(base: float, top: float, floor_height: float) -> tuple[float, int]:
    """(storey height, levels): whole storeys of about `floor_height` between base and top."""
    if top <= base:
        return floor_height, 0
    levels = max(1, round((top - base) / floor_height))
    return (top - base) / levels, levels
