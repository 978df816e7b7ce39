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

from dataclasses import dataclass

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


def _turns(d: np.ndarray) -> np.ndarray:
    """Signed turn (radians, left positive) from the previous edge into each edge of a closed ring."""
    prev = np.roll(d, 1, axis=0)
    cross = prev[:, 0] * d[:, 1] - prev[:, 1] * d[:, 0]
    dot = np.sum(prev * d, axis=1)
    return np.arctan2(cross, dot)


def wall_faces(lengths: np.ndarray, directions: np.ndarray, nominal_bay: float, first_column: int = 0) -> WallFaces:
    """Faces of a closed ring from its edges' lengths (arc lengths for curves) and directions
    (n, 2); the building lies left of the edges (counter-clockwise outlines, clockwise holes).
    Columns start at `first_column` (rings of one building follow each other)."""
    n = len(lengths)
    turns = _turns(directions)
    corner = np.abs(turns) > CORNER_TURN + 1e-6  # a regular 12-gon's turns are 30 degrees up to rounding
    if not corner.any():  # one face all round: it starts at edge 0
        starts = np.array([0])
    else:
        starts = np.nonzero(corner)[0]
    # faces as runs of edges from each start to the next (the last run wraps round to the first start)
    face_of_edge = (np.searchsorted(starts, np.arange(n), side="right") - 1) % len(starts)
    order = (np.arange(n) - starts[0]) % n  # position of each edge from the first face's start
    edges_by_order = np.argsort(order)
    cumulative = np.zeros(n)
    cumulative[edges_by_order] = np.concatenate([[0.0], np.cumsum(lengths[edges_by_order])[:-1]])
    face_start = cumulative[starts]
    width = np.bincount(face_of_edge, weights=lengths, minlength=len(starts))
    bays = np.maximum(1, np.round(width / nominal_bay)).astype(np.int64)
    bay = width / bays
    faces = len(starts)
    if faces == 1:
        depth = bay.copy()
    else:
        depth = 0.5 * (np.roll(bay, 1) + np.roll(bay, -1))
    # room columns: a convex corner (a left turn) shares the room on both of its sides
    convex = turns[starts] > 0
    first = np.zeros(faces, dtype=np.int64)
    last = np.zeros(faces, dtype=np.int64)
    column = first_column
    for f in range(faces):
        if f > 0 and convex[f]:
            column -= 1  # this face's first bay is the previous face's last
        first[f] = column
        last[f] = column + bays[f] - 1
        column = last[f] + 1
    if faces > 1 and convex[0]:
        last[-1] = first[0]  # the closing corner: the last face's last bay is the first face's first
    return WallFaces(
        along=cumulative - face_start[face_of_edge],
        width=width[face_of_edge],
        bay=bay[face_of_edge],
        depth=depth[face_of_edge],
        columns=np.stack([first, last], axis=1)[face_of_edge],
    )


def ring_columns(faces: WallFaces) -> int:
    """One past the highest room column of a ring: where the next ring's columns start."""
    return int(faces.columns.max()) + 1 if len(faces.columns) else 0


def storeys(base: float, top: float, floor_height: float) -> tuple[float, int]:
    """(storey height, levels): whole storeys of about `floor_height` between base and top."""
    if top <= base:
        return floor_height, 0
    levels = max(1, round((top - base) / floor_height))
    return (top - base) / levels, levels
