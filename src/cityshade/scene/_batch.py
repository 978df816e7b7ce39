"""A whole city's masses meshed at once: the same vertices as building_vertices, mass by mass, in
a few numpy passes over every building instead of a Python loop over them.

The walls of every prism (outlines and courtyards, their faces, bays and room columns: ring_faces),
flat roofs and undersides (shapely triangulates them all in one call), the building records and the
move to world space are computed for all buildings together; pitched and pointed roofs (with their
gables and dormers), parapets, cylinders and domes are meshed building by building with the
per-building code. A mass's rows keep their order: walls, gables, dormer fronts, roof, underside.
"""

from __future__ import annotations

from dataclasses import replace
from itertools import chain

import numpy as np
import shapely

from ._buildings import BuildingMass, room_sizes
from ._extrusions import dormer_rows, gable_rows, roof_rows, wall_quads, wall_rows
from ._given import given_mass_rows
from ._meshes import (
    SURFACE_DORMER,
    SURFACE_PLAIN_WALL,
    SURFACE_ROOF,
    SURFACE_WALL,
    VERTEX_DTYPE,
    building_records,
    mass_rows,
    simplified_outline,
    vertex_records,
)
from ._records import BUILDING_DTYPE
from ._roof_units import rooftop_units
from ._roofs import Triangles, flat_rows, follows_skeleton, parapet_roofs, triangulated
from ._rooftop import roof_with_rooftop
from ._skeleton import skeletons_ahead
from ._wall_faces import ring_faces

PLAIN_OUTLINE = 64  # simplified_outline returns outlines of up to this many corners as they are
SECTIONS = ("walls", "gables", "dormers", "roof", "underside", "plain")  # a mass's rows, in this order


class _Sections:
    """Rows gathered section by section, in any order of buildings, put in building order."""

    def __init__(self):
        self.chunks = []  # (sort key per row, rows: _extrusions.py)

    def add(self, section: str, building: np.ndarray, rows):
        """`rows` kept as the vertex records store them (float32, int32): half the bytes to hold and sort."""
        if len(building):
            rows = (*(np.asarray(r, np.float32) for r in rows[:4]), np.asarray(rows[4], np.int32))
            self.chunks.append((np.asarray(building, np.int64) * len(SECTIONS) + SECTIONS.index(section), rows))

    def ordered(self):
        """(rows, surface kind, building) per row, buildings in order, each in SECTIONS order."""
        key = np.concatenate([k for k, _ in self.chunks])
        order = np.argsort(key, kind="stable")  # stable: a section's rows keep their order
        rows = tuple(np.concatenate([r[f] for _, r in self.chunks])[order] for f in range(5))
        key = key[order]
        section = key % len(SECTIONS)
        surface = np.where(section >= SECTIONS.index("roof"), SURFACE_ROOF, SURFACE_WALL)
        surface[section == SECTIONS.index("dormers")] = SURFACE_DORMER
        surface[section == SECTIONS.index("plain")] = SURFACE_PLAIN_WALL
        return rows, surface, key // len(SECTIONS)


def batch(masses: list[BuildingMass]) -> tuple[np.ndarray, np.ndarray]:
    """All masses as one vertex array (one draw call) and their records (one SSBO)."""
    masses = list(masses)  # a city's MassTable makes each mass when read: once, then read by index
    if not masses:
        return np.zeros(0, VERTEX_DTYPE), np.zeros(0, BUILDING_DTYPE)
    sections = _Sections()
    rooms = room_sizes(
        np.array([m.extent for m in masses]),
        np.array([m.room_width for m in masses]),
        np.array([m.floor_height for m in masses]),
    )
    prisms = np.flatnonzero([m.shape == "prism" and not m.given for m in masses])
    points, counts = _outlines([masses[i] for i in prisms])
    plain = counts >= 3
    points = points[np.repeat(plain, counts)]
    _prism_rows(masses, rooms, prisms[plain], points, counts[plain], sections)
    given = np.flatnonzero([bool(m.given) for m in masses])
    for section, (rows, owner) in zip(("walls", "roof", "plain"), given_mass_rows([masses[i] for i in given])):
        sections.add(section, given[owner], rows)
    for i in sorted(set(range(len(masses))) - set(prisms[plain].tolist()) - set(given.tolist())):  # cylinders, domes
        walls, fronts, roof, _ = mass_rows(masses[i])
        sections.add("walls", np.full(len(walls[0]), i), walls)
        sections.add("dormers", np.full(len(fronts[0]), i), fronts)
        sections.add("roof", np.full(len(roof[0]), i), roof)
    rows, surface, building = sections.ordered()
    yaw = np.array([m.yaw for m in masses])
    origin = np.array([m.position for m in masses], dtype=np.float64)
    vertices = vertex_records(rows, surface, building, np.cos(yaw)[building], np.sin(yaw)[building], origin[building])
    return vertices, building_records(masses, rooms)


def _ring_next(counts: np.ndarray) -> np.ndarray:
    """For rings of `counts` points stored one after another: the index of each point's successor."""
    index = np.arange(counts.sum()) + 1
    ends = np.cumsum(counts)
    index[ends[counts > 0] - 1] = (ends - counts)[counts > 0]
    return index


def _outlines(masses: list[BuildingMass]) -> tuple[np.ndarray, np.ndarray]:
    """(points, corners per mass) of the prisms' outlines as _prism_triangles meshes them:
    simplified where dense, repeated corners dropped, counter-clockwise."""
    footprints = [
        np.asarray(m.footprint, np.float64) if len(m.footprint) > PLAIN_OUTLINE else m.footprint for m in masses
    ]
    footprints = [simplified_outline(f) if isinstance(f, np.ndarray) else f for f in footprints]
    counts = np.array([len(f) for f in footprints], dtype=np.int64)
    points = np.array(list(chain.from_iterable(footprints)), dtype=np.float64).reshape(-1, 2)
    moved = np.any(points[_ring_next(counts)] != points, axis=1)  # a repeated corner has no wall (or normal)
    counts = np.bincount(np.repeat(np.arange(len(counts)), counts)[moved], minlength=len(counts))
    points = points[moved]
    after = points[_ring_next(counts)]
    twice_area = np.zeros(len(counts))
    starts = np.cumsum(counts) - counts
    nonempty = counts > 0
    twice_area[nonempty] = np.add.reduceat(points[:, 0] * after[:, 1] - after[:, 0] * points[:, 1], starts[nonempty])
    ring = np.repeat(np.arange(len(counts)), counts)
    turn = twice_area[ring] < 0
    order = np.arange(len(points))
    order[turn] = (2 * starts[ring] + counts[ring] - 1 - order)[turn]  # clockwise rings reversed
    return points[order], counts


def _prism_rows(
    masses: list[BuildingMass],
    rooms: np.ndarray,
    index: np.ndarray,
    points: np.ndarray,
    counts: np.ndarray,
    sections: _Sections,
):
    """The rows of the prisms masses[index] with outlines (points, counts), added to `sections`."""
    if not len(index):
        return
    chosen = [masses[i] for i in index]
    ring = np.repeat(np.arange(len(index)), counts)
    holes = [[np.asarray(h, np.float64) for h in m.holes] for m in chosen]
    hole_owner = np.repeat(np.arange(len(index)), [len(h) for h in holes])
    hole_counts = np.array([len(h) for h in chain.from_iterable(holes)], dtype=np.int64)
    rings = shapely.linearrings(points, indices=ring)
    if len(hole_owner):
        hole_points = np.concatenate(list(chain.from_iterable(holes)))
        hole_rings = shapely.linearrings(hole_points, indices=np.repeat(np.arange(len(hole_counts)), hole_counts))
        owner = np.concatenate([np.arange(len(index)), hole_owner])
        order = np.argsort(owner, kind="stable")  # each outline, then its courtyards
        polygons = shapely.polygons(np.concatenate([rings, hole_rings])[order], indices=owner[order])
    else:
        polygons = shapely.polygons(rings)
    polygons = shapely.orient_polygons(polygons)  # courtyards clockwise: their walls face in

    top = np.array([m.wall_top for m in chosen])
    ahead = [polygons[k] for k, m in enumerate(chosen) if follows_skeleton(polygons[k], m.roof)]
    with skeletons_ahead(ahead):  # CGAL on other cores while the rest is meshed
        base = np.array([m.base for m in chosen])
        walled = np.array([m.walls for m in chosen])

        # walls: each outline's edges, then its courtyards' (as oriented), mass by mass
        a, b, owner, rank = [points], [points[_ring_next(counts)]], [ring], [np.zeros(len(points))]
        if len(hole_owner):
            courtyards, of = shapely.get_rings(
                polygons[hole_owner[np.r_[0, np.flatnonzero(np.diff(hole_owner)) + 1]]], return_index=True
            )
            courtyards = courtyards[np.r_[1, np.diff(of)] == 0]  # each polygon's first ring is its outline
            coords, which = shapely.get_coordinates(courtyards, return_index=True)
            open_ring = np.r_[which[1:] == which[:-1], False]  # the closing point repeats the first
            coords, which = coords[open_ring], which[open_ring]
            ring_counts = np.bincount(which, minlength=len(courtyards))
            a.append(coords)
            b.append(coords[_ring_next(ring_counts)])
            owner.append(hole_owner[which])
            rank.append(1.0 + which)
        a, b, owner, rank = (np.concatenate(x) for x in (a, b, owner, rank))
        order = np.lexsort((rank, owner))  # stable within a ring: its edges in order
        a, b, owner, rank = a[order], b[order], owner[order], rank[order]
        on_walls = walled[owner]
        a, b, owner, rank = a[on_walls], b[on_walls], owner[on_walls], rank[on_walls]
        storey = _storeys(base, top, np.array([m.floor_height for m in chosen]))
        walls, column = _wall_rows(a, b, owner, rank, np.array([m.room_width for m in chosen]), base, top, storey)
        sections.add("walls", np.repeat(index[owner[np.linalg.norm(b - a, axis=1) > 1e-9]], 6), walls)

        # flat roofs and undersides: one triangulation of every polygon that needs one
        flat_top = np.array([(m.roof.shape == "flat" or m.roof.height <= 0) and m.roof.parapet <= 0 for m in chosen])
        underside = ~walled | (base > 0)
        needed = np.flatnonzero(flat_top | underside)
        tris, owner = triangulated(polygons[needed])
        owner = needed[owner]
        up = flat_top[owner]
        sections.add("roof", np.repeat(index[owner[up]], 3), roof_rows(*flat_rows(tris[up], top[owner[up]])))
        down = underside[owner]
        sections.add(
            "underside",
            np.repeat(index[owner[down]], 3),
            roof_rows(*flat_rows(tris[down], np.where(walled, base, top)[owner[down]], up=False)),
        )

        # flat roofs inside parapets at once, their rooftop units roof piece by roof piece
        rimmed = np.flatnonzero(np.array([m.roof.shape == "flat" or m.roof.height <= 0 for m in chosen]) & ~flat_top)
        inside = parapet_roofs(polygons[rimmed], top[rimmed], np.array([chosen[k].roof.parapet for k in rimmed]))
        sections.add("roof", index[rimmed[inside.owner]], roof_rows(inside.rows.positions, inside.rows.normals))
        units = [
            rooftop_units(piece, top[k] - chosen[k].roof.parapet, chosen[k].roof.seed)
            for piece, k in zip(inside.pieces, rimmed[inside.piece_owner])
        ]
        if units:
            owner = np.repeat(rimmed[inside.piece_owner], [len(u.positions) for u in units])
            units = Triangles.join(units)
            sections.add("roof", index[owner], roof_rows(units.positions, units.normals, units.roof_parts()))

        # pitched and pointed roofs, mass by mass
        for k in np.setdiff1d(np.flatnonzero(~flat_top), rimmed):
            roof, gables, fronts = roof_with_rooftop(polygons[k], top[k], chosen[k].roof)
            gable, after_gables = gable_rows(gables, chosen[k], column[k])
            sections.add("gables", np.full(len(gables.positions), index[k]), gable)
            sections.add(
                "dormers", np.full(len(fronts.positions), index[k]), dormer_rows(fronts, chosen[k], after_gables)
            )
            sections.add(
                "roof",
                np.full(len(roof.positions), index[k]),
                roof_rows(roof.positions, roof.normals, roof.roof_parts()),
            )


def _storeys(base: np.ndarray, top: np.ndarray, floor_height: np.ndarray) -> np.ndarray:
    """storeys' storey height for walls from base up to top (top above base)."""
    return (top - base) / np.maximum(1, np.round((top - base) / floor_height))


def _wall_rows(a, b, owner, rank, room_width, base, top, storey):
    """Wall rows of the edges a -> b, ring after ring (each ring's edges together, `rank` telling a
    mass's rings apart), as ring_wall_rows makes them mass by mass; also each mass's next room
    column (where its gables' rooms go)."""
    next_column = np.zeros(len(room_width), dtype=np.int64)
    new_ring = np.ones(len(owner), bool)  # none when no mass of the batch has plain walls
    new_ring[1:] = (owner[1:] != owner[:-1]) | (rank[1:] != rank[:-1])
    ring = np.cumsum(new_ring) - 1
    ring_owner = owner[new_ring]
    d = b - a
    length = np.linalg.norm(d, axis=1)
    keep = length > 1e-9
    a, b, d, length, ring = a[keep], b[keep], d[keep], length[keep], ring[keep]
    if not len(a):
        empty = np.zeros((0, 3))
        return (empty, empty, np.zeros((0, 4)), np.zeros((0, 4)), np.zeros((0, 2), dtype=np.int64)), next_column
    counts = np.bincount(ring, minlength=len(ring_owner))
    has_walls = counts > 0
    faces, span = ring_faces(length, d, counts[has_walls], room_width[ring_owner[has_walls]])
    # a mass's rings number their rooms on from the ring before (from 0 after a ring without walls)
    spans = np.zeros(len(ring_owner), dtype=np.int64)
    spans[has_walls] = span
    before = np.cumsum(spans) - spans
    restart = np.r_[True, ring_owner[1:] != ring_owner[:-1]] | np.r_[True, ~has_walls[:-1]]
    first = before - before[np.maximum.accumulate(np.where(restart, np.arange(len(ring_owner)), 0))]
    faces = replace(faces, columns=faces.columns + first[ring, None])
    last_ring = np.r_[ring_owner[1:] != ring_owner[:-1], True]
    next_column[ring_owner[last_ring]] = np.where(has_walls, first + spans, 0)[last_ring]
    positions, normals, along = wall_quads(a, b, base[ring_owner][ring], top[ring_owner][ring])
    edge = np.repeat(np.arange(len(a)), 6)
    vertex_owner = ring_owner[ring][edge]
    rows = wall_rows(
        positions, normals, faces, edge, along, (base[vertex_owner], top[vertex_owner]), storey[vertex_owner]
    )
    return rows, next_column
