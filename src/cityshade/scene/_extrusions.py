"""Map buildings' masses as triangle rows: outlines (courtyards included) extruded from their base
to their walls' top, the roof and its gables, and an underside where the mass floats.

Rows are (object-space positions, object-space normals, facade coordinates, face, room columns)
arrays, one row per vertex, three per triangle (wall_rows, roof_rows; the faces: _wall_faces.py).
"""

from __future__ import annotations

import numpy as np
import shapely

from ._roofs import Triangles, flat
from ._rooftop import roof_with_rooftop
from ._wall_faces import WallFaces, ring_columns, storeys, wall_faces

QUAD = np.array([0, 2, 1, 0, 3, 2])  # corners a-low, b-low, b-high, a-high: counter-clockwise seen from outside


def wall_quads(a: np.ndarray, b: np.ndarray, base, top):
    """Flat wall quads on the edges a -> b (n, 2), none of them without length, from base to top
    (one each or per edge): (positions, normals, metres along the edge) per vertex."""
    d = b - a
    length = np.linalg.norm(d, axis=1)
    n = np.stack([d[:, 1], -d[:, 0]], axis=1) / length[:, None]
    corners = np.stack([a, b, b, a], axis=1)[:, QUAD]  # (edges, 6, 2)
    heights = np.stack(np.broadcast_arrays(base, base, top, top, np.zeros(len(a))), axis=1)[:, QUAD].ravel()
    along = ((np.array([0.0, 1.0, 1.0, 0.0])[QUAD])[None, :] * length[:, None]).ravel()
    positions = np.column_stack([corners[..., 0].ravel(), heights, corners[..., 1].ravel()])
    normals = np.repeat(np.column_stack([n[:, 0], np.zeros(len(a)), n[:, 1]]), 6, axis=0)
    return positions, normals, along


def ring_wall_rows(ring: np.ndarray, mass, base: float, top: float, first_column: int = 0):
    """Flat wall quads on a ring's edges (closing edge included), from base to top, with the facade
    coordinates of the faces they belong to (wall_rows); returns (rows, the next ring's first column)."""
    a, b = ring, np.roll(ring, -1, axis=0)
    d = b - a
    length = np.linalg.norm(d, axis=1)
    keep = length > 1e-9
    a, b, d, length = a[keep], b[keep], d[keep], length[keep]
    faces = wall_faces(length, d, mass.room_width, first_column)
    positions, normals, along = wall_quads(a, b, base, top)
    storey, _ = storeys(base, top, mass.floor_height)
    rows = wall_rows(positions, normals, faces, np.repeat(np.arange(len(a)), 6), along, (base, top), storey)
    return rows, ring_columns(faces)


def wall_rows(positions, normals, faces: WallFaces, edge: np.ndarray, along: np.ndarray, span: tuple, storey):
    """Rows of wall vertices: object-space positions and normals, facade coordinates (u metres along
    the face, v metres up, bay width, storey height), the face (width, base, top of `span`, room
    depth) and its room columns (first bay, last bay). `edge` is each vertex's entry in `faces`,
    `along` its metres from that edge's start; span and storey once or per vertex."""
    count = len(positions)
    facade = np.column_stack(
        [faces.along[edge] + along, positions[:, 1], faces.bay[edge], np.broadcast_to(storey, count)]
    )
    face = np.column_stack(
        [faces.width[edge], np.broadcast_to(span[0], count), np.broadcast_to(span[1], count), faces.depth[edge]]
    )
    return positions, normals, facade, face, faces.columns[edge]


def _piece_rows(walls: Triangles, mass, first_column: int):
    """Wall pieces above the walls' top: each a face of its edge's length, its storeys carrying on
    those of the wall below; every piece (Triangles.piece) its own run of room columns, one per bay,
    from `first_column` on, so that no two pieces share a room or a window's key. Returns (rows, the
    column after the last piece's)."""
    length = walls.edge_length
    bays = np.maximum(1, np.round(length / mass.room_width)).astype(np.int64)
    piece = walls.piece.astype(np.int64)
    piece_bays = np.zeros(piece.max() + 1 if len(piece) else 0, np.int64)
    np.maximum.at(piece_bays, piece, bays)
    first = first_column + (np.cumsum(piece_bays) - piece_bays)[piece]
    faces = WallFaces(
        np.zeros(len(length)), length, length / bays, length / bays, np.stack([first, first + bays - 1], 1)
    )
    storey, _ = storeys(mass.base, mass.wall_top, mass.floor_height)
    rows = wall_rows(
        walls.positions, walls.normals, faces, np.arange(len(length)), walls.along, (mass.base, mass.height), storey
    )
    return rows, first_column + int(piece_bays.sum())


def gable_rows(walls: Triangles, mass, first_column: int):
    """Gables: wall pieces up to the ridge, each gable's rooms in columns of its own after the walls'
    (`first_column`); returns (rows, the column after the gables')."""
    return _piece_rows(walls, mass, first_column)


def dormer_rows(fronts: Triangles, mass, first_column: int):
    """Dormer fronts (_dormers.py): one bay each, the storey of rooms in the roof behind it; every
    dormer's room in a column of its own after the gables' (`first_column`, gable_rows)."""
    rows, _ = _piece_rows(fronts, mass, first_column)
    return rows


def empty_rows():
    """Rows of no vertices (a mass without dormers)."""
    return roof_rows(np.zeros((0, 3)), np.zeros((0, 3)))


def roof_rows(positions: np.ndarray, normals: np.ndarray, part: np.ndarray | int = 0):
    """Rows of roof vertices: facade coordinates (x, z, 0, 0), no face, and in place of room
    columns the roof part (ROOF_PART_*, once or per vertex; the shader's ids.z) and 0."""
    count = len(positions)
    facade = np.column_stack([positions[:, 0], positions[:, 2], np.zeros((count, 2))])
    ids = np.zeros((count, 2), dtype=np.int64)
    ids[:, 0] = part
    return positions, normals, facade, np.zeros((count, 4)), ids


def join_rows(rows: list):
    return tuple(np.concatenate([r[i] for r in rows]) for i in range(5))


def outline_rows(mass, outline: np.ndarray):
    """(wall rows, dormer front rows, roof rows) of a mass over its counter-clockwise object-space outline."""
    # holes clockwise: their walls face the courtyard
    polygon = shapely.orient_polygons(shapely.Polygon(outline, mass.holes))
    holes = [np.asarray(ring.coords)[:-1] for ring in polygon.interiors]
    top = mass.wall_top
    roof, gables, fronts = roof_with_rooftop(polygon, top, mass.roof)
    if not mass.walls:  # a canopy: the roof's underside at its eaves
        roof = Triangles.join([roof, flat(polygon, top, up=False)])
    elif mass.base > 0:
        roof = Triangles.join([roof, flat(polygon, mass.base, up=False)])
    walls, column = [], 0
    for ring in [outline, *holes] if mass.walls else []:
        rows, column = ring_wall_rows(ring, mass, mass.base, top, column)
        walls.append(rows)
    gable, column = gable_rows(gables, mass, column)
    return (
        join_rows([*walls, gable]),
        dormer_rows(fronts, mass, column),
        roof_rows(roof.positions, roof.normals, roof.roof_parts()),
    )
