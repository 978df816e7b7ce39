"""Map buildings' masses as triangle rows: outlines (courtyards included) extruded from their base
to their walls' top, the roof and its gables, and an underside where the mass floats.

Rows are (object-space positions, object-space normals, facade coordinates) arrays, one row per
vertex, three per triangle; facade coordinates are (metres along the wall from its edge's start,
metres up, window bay width) on walls and (x, z, 0) on roofs.
"""

from __future__ import annotations

import numpy as np
import shapely

from ._roofs import Triangles, flat, roof_triangles

QUAD = np.array([0, 2, 1, 0, 3, 2])  # corners a-low, b-low, b-high, a-high: counter-clockwise seen from outside


def bays(d: np.ndarray, room: np.ndarray) -> np.ndarray:
    """Window bay widths of walls along edge vectors d: whole bays per facade, a room wide where
    the facade runs along a room axis, so windows sit in rooms and never touch a corner. `room` is
    one room size (3,) or one per edge (n, 3)."""
    along_x = np.abs(d[:, 0]) >= np.abs(d[:, 1])
    nominal = np.where(along_x, room[..., 0], room[..., 2])
    length = np.linalg.norm(d, axis=1)
    return length / np.maximum(1, np.round(length / nominal))


def edge_walls(a: np.ndarray, b: np.ndarray, room: np.ndarray, base: np.ndarray, top: np.ndarray):
    """Flat wall quads on the edges a -> b (n, 2), each from its base to its top (n,), with its
    building's room size (n, 3); edges without length have none. This is where wall vertices get
    their facade coordinates, for one building's rings and for a whole city's at once alike."""
    d = b - a
    length = np.linalg.norm(d, axis=1)
    keep = length > 1e-9
    a, b, d, length, room = a[keep], b[keep], d[keep], length[keep], room[keep]
    n = np.stack([d[:, 1], -d[:, 0]], axis=1) / length[:, None]
    corners = np.stack([a, b, b, a], axis=1)[:, QUAD]  # (edges, 6, 2)
    heights = np.stack([base[keep], base[keep], top[keep], top[keep]], axis=1)[:, QUAD].ravel()
    along = (np.array([0.0, 1.0, 1.0, 0.0])[QUAD])[None, :] * length[:, None]
    positions = np.column_stack([corners[..., 0].ravel(), heights, corners[..., 1].ravel()])
    normals = np.repeat(np.column_stack([n[:, 0], np.zeros(len(a)), n[:, 1]]), 6, axis=0)
    facade = np.column_stack([along.ravel(), heights, np.repeat(bays(d, room), 6)])
    return positions, normals, facade


def _ring_walls(ring: np.ndarray, room: np.ndarray, base: float, top: float):
    """Flat wall quads on a ring's edges (closing edge included), from base to top."""
    count = len(ring)
    return edge_walls(ring, np.roll(ring, -1, axis=0), np.broadcast_to(room, (count, 3)), np.full(count, base),
                      np.full(count, top))


def gable_rows(walls: Triangles, room: np.ndarray):
    """Wall pieces above the walls' top (gables) with facade coordinates that carry on the wall below."""
    n = walls.normals
    edge = np.stack([-n[:, 2], n[:, 0]], axis=1) * walls.edge_length[:, None]
    return walls.positions, n, np.column_stack([walls.along, walls.positions[:, 1], bays(edge, room)])


def roof_rows(roof: Triangles):
    p = roof.positions
    return p, roof.normals, np.column_stack([p[:, 0], p[:, 2], np.zeros(len(p))])


def _join(rows: list):
    return tuple(np.concatenate([r[i] for r in rows]).reshape(-1, 3) for i in range(3))


def outline_rows(mass, outline: np.ndarray, room: np.ndarray):
    """(wall rows, roof rows) of a mass over its counter-clockwise object-space outline."""
    # holes clockwise: their walls face the courtyard
    polygon = shapely.orient_polygons(shapely.Polygon(outline, mass.holes))
    holes = [np.asarray(ring.coords)[:-1] for ring in polygon.interiors]
    top = mass.wall_top
    roof, gables = roof_triangles(polygon, top, mass.roof)
    if not mass.walls:  # a canopy: the roof's underside at its eaves
        roof = Triangles.join([roof, flat(polygon, top, up=False)])
    elif mass.base > 0:
        roof = Triangles.join([roof, flat(polygon, mass.base, up=False)])
    walls = [_ring_walls(ring, room, mass.base, top) for ring in [outline, *holes]] if mass.walls else []
    return _join([*walls, gable_rows(gables, room)]), roof_rows(roof)
