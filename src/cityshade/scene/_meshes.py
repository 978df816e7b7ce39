"""Building masses -> one batched triangle list with per-facade attributes.

Every vertex carries its world position, its object-space position (the building's local frame,
where interior mapping ray-casts), its object-space normal, facade coordinates (u metres along
its face, v metres up, the window bay width and the storey height), its face (width, base and top,
the depth of the rooms behind it: _wall_faces.py), the building's index, the surface kind and the
room columns of the face's first and last bay.
"""

from __future__ import annotations

import numpy as np
import shapely

from ._buildings import BuildingMass
from ._dome_faces import dome_faces
from ._doors import door_record
from ._extrusions import empty_rows, outline_rows, roof_rows, wall_rows
from ._given import given_rows
from ._materials import guessed_roof, linear, roof_material, wall_tint
from ._records import BUILDING_DTYPE, SHAPES
from ._uses import USES
from ._wall_faces import WallFaces, storeys, wall_faces

SURFACE_WALL, SURFACE_ROOF = 0, 1
SURFACE_PLAIN_WALL = 2  # a wall face too narrow for its building's grammar (render/_facades.py)
SURFACE_DORMER = 3  # a dormer's front: one window bay with its room, whatever the building's facade
SURFACE_CODES = {
    "SURFACE_WALL": SURFACE_WALL,
    "SURFACE_ROOF": SURFACE_ROOF,
    "SURFACE_PLAIN_WALL": SURFACE_PLAIN_WALL,
    "SURFACE_DORMER": SURFACE_DORMER,
}

VERTEX_DTYPE = np.dtype(
    [
        ("position", "<f4", 3),
        ("local", "<f4", 3),
        ("normal", "<f4", 3),
        ("facade", "<f4", 4),  # u along the face, v up, bay width, storey height (metres)
        ("face", "<f4", 4),  # the face's width, base, top, room depth (metres)
        ("ids", "<i4", 4),  # building index, surface kind, room column of the face's first and last bay
    ]
)

CURVE_SEGMENTS = 48
# A dome's facets: fine enough that its windows and silhouette lie within a pixel's edge of the exact
# hemisphere (the twin's) in a dome-filling view (tests/grammar/test_dome_grammar.py).
DOME_SEGMENTS = 128
DOME_RINGS = 32
# Outlines with a vertex per less than 5 cm on average (surveyed or generated curves, fuzzed data)
# are simplified within 1 cm: a third of a pixel for a 40 m building filling a 1280-pixel view.
OUTLINE_STEP = 0.05
OUTLINE_TOLERANCE = 0.01


def _signed_area(points: np.ndarray) -> float:
    x, z = points[:, 0], points[:, 1]
    return 0.5 * float(np.sum(x * np.roll(z, -1) - np.roll(x, -1) * z))


def _curved_walls(ring: np.ndarray, centre: np.ndarray, radius: float, mass: BuildingMass):
    """Quads on a closed circle's chords with smooth (per-vertex) normals; facade u is the arc
    length (the twin's exact circle), the whole circle one face."""
    a, b = ring[:-1], ring[1:]
    arc = np.full(len(a), 2 * np.pi * radius / len(a))
    faces = wall_faces(arc, b - a, mass.room_width)
    height = mass.extent[1]
    order = [0, 2, 1, 0, 3, 2]  # corners a-bottom, b-bottom, b-top, a-top; counter-clockwise from outside
    point = np.stack([a, b, b, a], axis=1)[:, order].reshape(-1, 2)
    normal = (point - centre) / radius
    along = (np.stack([np.zeros(len(a)), arc, arc, np.zeros(len(a))], axis=1)[:, order]).ravel()
    y = np.tile(np.array([0.0, 0.0, height, height])[order], len(a))
    positions = np.column_stack([point[:, 0], y, point[:, 1]])
    normals = np.column_stack([normal[:, 0], np.zeros(len(y)), normal[:, 1]])
    storey, _ = storeys(0.0, height, mass.floor_height)
    return wall_rows(positions, normals, faces, np.repeat(np.arange(len(a)), 6), along, (0.0, height), storey)


def simplified_outline(points: np.ndarray) -> np.ndarray:
    """The outline, or where it has more vertices than can be seen (a vertex per less than
    OUTLINE_STEP metres on average) its simplification within OUTLINE_TOLERANCE metres."""
    ring = np.vstack([points, points[:1]])
    perimeter = float(np.sum(np.linalg.norm(ring[1:] - ring[:-1], axis=1)))
    if len(points) <= max(64, perimeter / OUTLINE_STEP):
        return points
    outline = shapely.Polygon(points)
    polygon = outline.simplify(OUTLINE_TOLERANCE, preserve_topology=False)  # Douglas-Peucker: n log n
    if polygon.geom_type != "Polygon" or not polygon.is_valid or len(polygon.exterior.coords) < 4:
        polygon = outline.simplify(OUTLINE_TOLERANCE, preserve_topology=True)  # slower, never invalid
    if polygon.geom_type != "Polygon" or len(polygon.exterior.coords) < 4:
        return points
    return np.asarray(polygon.exterior.coords)[:-1]


def _prism_triangles(mass: BuildingMass, smooth: bool):
    pts = simplified_outline(np.asarray(mass.footprint, dtype=np.float64))
    pts = pts[np.any(np.roll(pts, -1, axis=0) != pts, axis=1)]  # a repeated corner has no wall (or normal)
    if _signed_area(pts) < 0:
        pts = pts[::-1]
    if not smooth:
        return outline_rows(mass, pts)  # walls (courtyards, gables), dormer fronts and the roof's shape
    height = mass.extent[1]
    centre = pts.mean(axis=0)
    radius = pts.max(axis=0)[0] / 2
    angles = np.linspace(0, 2 * np.pi, CURVE_SEGMENTS + 1)
    ring = centre + radius * np.stack([np.cos(-angles), np.sin(-angles)], axis=1)
    ring = ring[::-1]
    walls = _curved_walls(ring, centre, radius, mass)
    top = _roof_triangles(ring[:-1])
    roof = roof_rows(
        np.stack([top[:, 0], np.full(len(top), height), top[:, 1]], axis=1),
        np.broadcast_to([0.0, 1.0, 0.0], (len(top), 3)),
    )
    return walls, empty_rows(), roof


def _roof_triangles(outline: np.ndarray) -> np.ndarray:
    """Corners (n, 2) of triangles covering a simple polygon (convex or not), one winding:
    constrained Delaunay triangulation."""
    polygon = shapely.Polygon(outline)
    if not polygon.is_valid:
        polygon = polygon.buffer(0)
    triangles = shapely.get_coordinates(shapely.constrained_delaunay_triangles(polygon)).reshape(-1, 4, 2)[:, :3]
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    turn = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    triangles = np.where((turn > 0)[:, None, None], triangles[:, [0, 2, 1]], triangles)
    return triangles.reshape(-1, 2)


def _dome_triangles(mass: BuildingMass):
    """A hemisphere of rings (_dome_faces.py): each storey a face round the dome, with facade u the
    longitude on the storey's middle circle and v the arc length; the cap above the last ring with
    windows is the roof. Mesh rows are DOME_RINGS steps of latitude, cut at every storey's edge so
    that no triangle spans two faces."""
    radius = mass.extent[0] / 2
    centre = np.array([radius, 0.0, radius])
    rings = dome_faces(radius, mass.floor_height, mass.room_width)
    steps = np.linspace(0, np.pi / 2, DOME_RINGS + 1)
    edges = np.append(rings.lat[:, 0], np.pi / 2)  # every ring's base, and the pole
    steps = steps[np.min(np.abs(steps[:, None] - edges[None, :]), axis=1) > 1e-6]  # no sliver rows
    lat = np.sort(np.concatenate([steps, edges]))
    lon = np.linspace(0, 2 * np.pi, DOME_SEGMENTS + 1)
    i, j = np.meshgrid(np.arange(len(lat) - 1), np.arange(DOME_SEGMENTS), indexing="ij")
    # 6 vertices per quad: corners (i, j), (i, j + 1), (i + 1, j + 1) and (i, j), (i + 1, j + 1), (i + 1, j)
    row = np.stack([i, i, i + 1, i, i + 1, i + 1], axis=-1).reshape(-1)
    column = np.stack([j, j + 1, j + 1, j, j + 1, j], axis=-1).reshape(-1)
    phi, theta = lat[row], lon[column]
    n = np.stack([np.cos(phi) * np.cos(theta), np.sin(phi), -np.cos(phi) * np.sin(theta)], axis=1)
    positions = centre + radius * n
    ring = np.repeat(rings.ring_of(0.5 * (lat[:-1] + lat[1:]) * radius)[i.ravel()], 6)
    wall = np.repeat(0.5 * (lat[:-1] + lat[1:])[i.ravel()] < rings.cap, 6)
    faces = WallFaces(np.zeros(len(rings.base)), rings.width, rings.bay, rings.bay, rings.columns)
    along = theta * rings.circle[ring]
    walls = wall_rows(positions, n, faces, ring, along, (rings.base[ring], rings.top[ring]), rings.storey)
    walls[2][:, 1] = phi * radius  # v runs up the arc
    walls = tuple(part[wall] for part in walls)
    return walls, empty_rows(), roof_rows(positions[~wall], n[~wall])


def mass_rows(mass: BuildingMass):
    """(wall rows, dormer front rows, roof rows, plain wall rows) of one mass in its object space
    (_extrusions.py rows); plain walls only on faces as given (_given.py)."""
    if mass.given:
        return given_rows(mass)
    if mass.shape == "dome":
        return (*_dome_triangles(mass), empty_rows())
    return (*_prism_triangles(mass, smooth=mass.shape == "cylinder"), empty_rows())


def vertex_records(
    rows, surface: np.ndarray, building: np.ndarray, cos_yaw: np.ndarray, sin_yaw: np.ndarray, origin: np.ndarray
) -> np.ndarray:
    """(local, normal, facade, face, room columns) rows as VERTEX_DTYPE records: their surface kind,
    building index, the rotation about +y and the world origin (x, z), each given per row or once."""
    out = np.zeros(len(rows[0]), dtype=VERTEX_DTYPE)
    for field, part in zip(("local", "normal", "facade", "face"), rows):
        out[field] = part
    out["ids"][:, 0] = building
    out["ids"][:, 1] = surface
    out["ids"][:, 2:] = rows[4]
    out["position"] = world_positions(out["local"], cos_yaw, sin_yaw, origin)
    return out


def world_positions(local: np.ndarray, cos_yaw: np.ndarray, sin_yaw: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """Object-space float32 points (n, 3) placed in the world (float64, to be stored as float32):
    rotation_y(yaw) applied term by term in float64, in this order, so that one building or a city
    at once, and the GPU's vertex stage (shaders/common/building_vertex.glsl), get the same floats."""
    local = np.asarray(local, np.float32).astype(np.float64)
    x, z = local[:, 0], local[:, 2]
    return np.column_stack(
        [cos_yaw * x + sin_yaw * z + origin[..., 0], local[:, 1], cos_yaw * z - sin_yaw * x + origin[..., 1]]
    )


def building_vertices(mass: BuildingMass, index: int) -> np.ndarray:
    """The triangles of one mass as VERTEX_DTYPE records (world and object space)."""
    parts = mass_rows(mass)
    rows = tuple(np.concatenate(part) for part in zip(*parts))
    surface = np.repeat(
        [SURFACE_WALL, SURFACE_DORMER, SURFACE_ROOF, SURFACE_PLAIN_WALL], [len(part[0]) for part in parts]
    )
    return vertex_records(
        rows, surface, index, np.cos(mass.yaw), np.sin(mass.yaw), np.asarray(mass.position, np.float64)
    )


def building_records(masses: list[BuildingMass], rooms: np.ndarray | None = None) -> np.ndarray:
    """The masses' BUILDING_DTYPE records (one SSBO), filled a column at a time; `rooms`: their
    room sizes where the caller has them."""
    rec = np.zeros(len(masses), dtype=BUILDING_DTYPE)
    rec["origin_yaw"] = [(m.position[0], 0.0, m.position[1], m.yaw) for m in masses]
    rec["room"][:, :3] = np.array([m.room_size for m in masses]) if rooms is None else rooms
    rec["room"][:, 3] = [m.wall_jitter for m in masses]
    rec["extent"] = [(*m.extent, m.lights) for m in masses]
    rec["ids"] = [(m.seed, m.style, m.flags, SHAPES[m.shape]) for m in masses]
    tints, roofs = {}, {}  # a city has few distinct colours: each converted once
    for k, m in enumerate(masses):
        key = (m.wall_colour, m.wall_material)
        if key not in tints:
            tint = wall_tint(*key)
            tints[key] = None if tint is None else (*linear(tint), 1.0)
        if tints[key] is not None:
            rec["tint"][k] = tints[key]
        key = (m.roof.colour, m.roof.material)
        if {"roof_material", "roof_colour"} <= m.guessed:  # the map is silent: varied building to building
            home = m.use in (USES["home"], USES["mixed"])
            key = guessed_roof(m.seed, home, m.roof.shape == "flat", m.roof.material, m.roof.colour)[::-1]
        if key not in roofs:
            material, colour = roof_material(key[1])
            roofs[key] = (*linear(key[0] if key[0] is not None else colour), material)
        rec["roof"][k] = roofs[key]
        if m.doors:
            rec["doors"][k] = door_record(m.doors)
    return rec


def building_record(mass: BuildingMass) -> np.ndarray:
    return building_records([mass]).reshape(())
