"""Building masses -> one batched triangle list with per-facade attributes.

Every vertex carries its world position, its object-space position (the building's local frame,
where interior mapping ray-casts), its object-space normal, facade coordinates (u metres along
the facade, v metres up, and the window bay width), the building's index and the surface kind.
"""

from __future__ import annotations

import numpy as np
import shapely

from ._buildings import BuildingMass
from ._records import BUILDING_DTYPE, SHAPES, rotation_y
from ._extrusions import outline_rows
from ._materials import linear, roof_material, wall_tint

SURFACE_WALL, SURFACE_ROOF = 0, 1

VERTEX_DTYPE = np.dtype(
    [
        ("position", "<f4", 3),
        ("local", "<f4", 3),
        ("normal", "<f4", 3),
        ("facade", "<f4", 3),
        ("ids", "<i4", 2),  # building index, surface kind
    ]
)
VERTEX_FORMAT = "3f 3f 3f 3f 2i"
VERTEX_ATTRIBUTES = ("in_position", "in_local", "in_normal", "in_facade", "in_ids")

CURVE_SEGMENTS = 48
DOME_RINGS = 16


def _signed_area(points: np.ndarray) -> float:
    x, z = points[:, 0], points[:, 1]
    return 0.5 * float(np.sum(x * np.roll(z, -1) - np.roll(x, -1) * z))


def _walls(ring: np.ndarray, normals: np.ndarray, height: float, bay: np.ndarray, u0: np.ndarray):
    """Quads standing on each ring edge; normals are per ring vertex (smooth) or per edge (flat)."""
    a, b = ring[:-1], ring[1:]
    na, nb = normals
    length = np.linalg.norm(b - a, axis=1)
    ua, ub = u0, u0 + length
    tris = []
    for (pa, pb, qa, qb, ea, eb, wa, wb, w) in zip(a, b, na, nb, ua, ub, bay, bay, bay):
        corners = [
            (pa, 0.0, qa, ea),
            (pb, 0.0, qb, eb),
            (pb, height, qb, eb),
            (pa, height, qa, ea),
        ]
        for i in (0, 2, 1, 0, 3, 2):  # counter-clockwise seen from outside
            p, y, n, u = corners[i]
            tris.append(((p[0], y, p[1]), (n[0], 0.0, n[1]), (u, y, w)))
    return tris


def _prism_triangles(mass: BuildingMass, room: np.ndarray, smooth: bool):
    pts = np.asarray(mass.footprint, dtype=np.float64)
    if _signed_area(pts) < 0:
        pts = pts[::-1]
    if smooth:
        centre = pts.mean(axis=0)
        radius = pts.max(axis=0)[0] / 2
        angles = np.linspace(0, 2 * np.pi, CURVE_SEGMENTS + 1)
        ring = centre + radius * np.stack([np.cos(-angles), np.sin(-angles)], axis=1)
        ring = ring[::-1]
        normal = (ring - centre) / radius
        normals = (normal[:-1], normal[1:])
        circumference = 2 * np.pi * radius
        bay = np.full(CURVE_SEGMENTS, circumference / max(1, round(circumference / mass.room_width)))
    else:
        return outline_rows(mass, pts, room)
    edge_len = np.linalg.norm(ring[1:] - ring[:-1], axis=1)
    u0 = np.concatenate([[0.0], np.cumsum(edge_len)[:-1]])
    walls = _walls(ring, normals, mass.extent[1], bay, u0)
    roof = [((p[0], mass.extent[1], p[1]), (0.0, 1.0, 0.0), (p[0], p[1], 0.0)) for p in _roof_triangles(ring[:-1])]
    return walls, roof


def _roof_triangles(outline: np.ndarray) -> list:
    """Triangles covering a simple polygon (convex or not): constrained Delaunay triangulation."""
    polygon = shapely.Polygon(outline)
    if not polygon.is_valid:
        polygon = polygon.buffer(0)
    points = []
    for tri in shapely.constrained_delaunay_triangles(polygon).geoms:
        a, b, c = np.asarray(tri.exterior.coords)[:3]
        # one winding for every roof triangle
        points += [a, c, b] if (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0 else [a, b, c]
    return points


def _dome_triangles(mass: BuildingMass):
    radius = mass.extent[0] / 2
    centre = np.array([radius, 0.0, radius])
    lat = np.linspace(0, np.pi / 2, DOME_RINGS + 1)
    lon = np.linspace(0, 2 * np.pi, CURVE_SEGMENTS + 1)
    circumference = 2 * np.pi * radius
    bay = circumference / max(1, round(circumference / mass.room_width))

    def vertex(i, j):
        n = np.array([np.cos(lat[i]) * np.cos(lon[j]), np.sin(lat[i]), -np.cos(lat[i]) * np.sin(lon[j])])
        return (tuple(centre + radius * n), tuple(n), (lon[j] * radius, lat[i] * radius, bay))

    tris = []
    for i in range(DOME_RINGS):
        for j in range(CURVE_SEGMENTS):
            a, b, c, d = vertex(i, j), vertex(i, j + 1), vertex(i + 1, j + 1), vertex(i + 1, j)
            tris += [a, b, c, a, c, d]
    return tris, []


def _as_rows(triangles):
    """Per-vertex (position, normal, facade) tuples, or arrays of each, as three (n, 3) arrays."""
    if isinstance(triangles, tuple):
        return triangles
    return tuple(np.asarray([t[i] for t in triangles], dtype=np.float64).reshape(-1, 3) for i in range(3))


def building_vertices(mass: BuildingMass, index: int) -> np.ndarray:
    """The triangles of one mass as VERTEX_DTYPE records (world and object space)."""
    room = mass.room_size
    if mass.shape == "dome":
        walls, roof = _dome_triangles(mass)
    else:
        walls, roof = _prism_triangles(mass, room, smooth=mass.shape == "cylinder")
    walls, roof = _as_rows(walls), _as_rows(roof)
    out = np.zeros(len(walls[0]) + len(roof[0]), dtype=VERTEX_DTYPE)
    for field, w, r in zip(("local", "normal", "facade"), walls, roof):
        out[field] = np.concatenate([w, r])
    out["ids"][:, 0] = index
    out["ids"][len(walls[0]):, 1] = SURFACE_ROOF
    rot = rotation_y(mass.yaw)
    origin = np.array([mass.position[0], 0.0, mass.position[1]])
    out["position"] = out["local"].astype(np.float64) @ rot.T + origin
    return out


def building_record(mass: BuildingMass) -> np.ndarray:
    rec = np.zeros((), dtype=BUILDING_DTYPE)
    rec["origin_yaw"] = (mass.position[0], 0.0, mass.position[1], mass.yaw)
    rec["room"][:3] = mass.room_size
    rec["room"][3] = mass.wall_jitter
    rec["extent"][:3] = mass.extent
    rec["extent"][3] = mass.lights
    rec["ids"] = (mass.seed, mass.style, mass.flags, SHAPES[mass.shape])
    tint = wall_tint(mass.wall_colour, mass.wall_material)
    if tint is not None:
        rec["tint"] = (*linear(tint), 1.0)
    material, colour = roof_material(mass.roof.material)
    rec["roof"] = (*linear(mass.roof.colour if mass.roof.colour is not None else colour), material)
    return rec


def batch(masses: list[BuildingMass]) -> tuple[np.ndarray, np.ndarray]:
    """All masses as one vertex array (one draw call) and their records (one SSBO)."""
    vertices = np.concatenate([building_vertices(m, i) for i, m in enumerate(masses)]) if masses else np.zeros(0, VERTEX_DTYPE)
    records = np.stack([building_record(m) for m in masses]) if masses else np.zeros(0, BUILDING_DTYPE)
    return vertices, records
