"""The interior twin's own geometry: building masses as exact solids, ray-cast in numpy.

Built from the building masses alone (position, yaw, footprint, courtyards, height, storey and
room width), never from the GPU's triangle meshes: a prism is its footprint extruded (walls, its
courtyards' walls and a flat roof), a cylinder a circle of the footprint's width, a dome a
hemisphere of it (its storeys are rings, each a face, and its cap a roof: cityshade.scene.dome_faces).
Each wall carries the facade coordinates the documented layout gives it (docs/interior.md): u metres along its face, v metres up, the window bay width and storey height,
and its face: width, base, top, room depth and the room columns of its first and last bay. Faces
and bays follow the layout's rule (cityshade.scene.wall_faces) applied to the twin's own exact
outline.

The GPU draws curves as facets, so on cylinders and domes the two differ by the facets'
sagitta; tests report those pixels rather than hide them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from ..scene import BuildingMass, dome_faces, storeys, wall_faces


@dataclass
class SolidHits:
    """Per ray: distance (inf on a miss), building index (-1), roof or wall, and in the building's
    own frame the hit point, the ray direction, the outward normal, the facade coordinates (u, v,
    bay width, storey height), the face (width, base, top, room depth) and its room columns."""

    t: np.ndarray
    building: np.ndarray
    roof: np.ndarray
    local: np.ndarray
    direction: np.ndarray
    normal: np.ndarray
    facade: np.ndarray
    face: np.ndarray
    columns: np.ndarray


def object_to_world(yaw: float) -> np.ndarray:
    """Rotation by `yaw` about +y taking the building's +x toward world -z for positive yaw
    (the records' convention: x' = x cos + z sin, z' = -x sin + z cos)."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def whole_bays(length, nominal) -> np.ndarray:
    """Bay width: `length` cut into whole bays of about `nominal` metres (at least one)."""
    return length / np.maximum(1, np.round(length / nominal))


def _counter_clockwise(points: np.ndarray) -> np.ndarray:
    x, z = points[:, 0], points[:, 1]
    area = np.sum(x * np.roll(z, -1) - np.roll(x, -1) * z)
    return points if area >= 0 else points[::-1]


def _inside_polygon(x: np.ndarray, z: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Even-odd rule: does a ray toward +x from (x, z) cross the outline an odd number of times."""
    inside = np.zeros(x.shape, dtype=bool)
    for (ax, az), (bx, bz) in zip(ring, np.roll(ring, -1, axis=0)):
        straddles = (az > z) != (bz > z)
        with np.errstate(divide="ignore", invalid="ignore"):
            cross_x = ax + (z - az) * (bx - ax) / (bz - az)
        inside ^= straddles & (x < cross_x)
    return inside


def _rings(mass: BuildingMass) -> list[np.ndarray]:
    """The outline counter-clockwise and its courtyards clockwise (the building on their left),
    each without repeated corners."""
    polygon = shapely.orient_polygons(
        shapely.Polygon(_counter_clockwise(np.asarray(mass.footprint, float)), mass.holes)
    )
    rings = [np.asarray(polygon.exterior.coords)[:-1], *(np.asarray(r.coords)[:-1] for r in polygon.interiors)]
    return [ring[np.any(np.roll(ring, -1, axis=0) != ring, axis=1)] for ring in rings]


def _round_face(mass: BuildingMass, width: float, top: float):
    """Facade rows' constant parts of a face all round (a cylinder): bay, storey, face, columns."""
    bay = whole_bays(width, mass.room_width)
    storey, _ = storeys(0.0, top, mass.floor_height)
    return bay, storey, (width, 0.0, top, bay), (0, round(width / bay) - 1)


def _prism(mass: BuildingMass, eye: np.ndarray, d: np.ndarray, height: float):
    n = len(d)
    best = np.full(n, np.inf)
    normal, facade, face = np.zeros((n, 3)), np.zeros((n, 4)), np.zeros((n, 4))
    columns = np.zeros((n, 2), dtype=np.int64)
    roof = np.zeros(n, dtype=bool)
    storey, _ = storeys(0.0, height, mass.floor_height)
    rings = _rings(mass)
    first_column = 0
    for ring in rings:
        edges = np.roll(ring, -1, axis=0) - ring
        lengths = np.hypot(edges[:, 0], edges[:, 1])
        faces = wall_faces(lengths, edges, mass.room_width, first_column)
        first_column = int(faces.columns.max()) + 1
        for k, (a, edge, length) in enumerate(zip(ring, edges, lengths)):
            outward = np.array([edge[1], 0.0, -edge[0]]) / length  # right of the edge, the building on its left
            a3 = np.array([a[0], 0.0, a[1]])
            with np.errstate(divide="ignore", invalid="ignore"):  # rays along the wall: inf, nan
                t = ((a3 - eye) @ outward) / (d @ outward)
                hit = eye + d * t[:, None]
            along = ((hit[:, 0] - a[0]) * edge[0] + (hit[:, 2] - a[1]) * edge[1]) / length
            ok = (t > 1e-9) & (along >= 0) & (along <= length) & (hit[:, 1] >= 0) & (hit[:, 1] <= height) & (t < best)
            best = np.where(ok, t, best)
            normal[ok] = outward
            facade[ok] = np.stack(
                [faces.along[k] + along[ok], hit[ok, 1], np.full(ok.sum(), faces.bay[k]), np.full(ok.sum(), storey)],
                axis=1,
            )
            face[ok] = (faces.width[k], 0.0, height, faces.depth[k])
            columns[ok] = faces.columns[k]
    with np.errstate(divide="ignore", invalid="ignore"):  # level rays never meet the roof
        t = (height - eye[1]) / d[:, 1]
        top = eye + d * t[:, None]
    inside = np.zeros(n, dtype=bool)
    for ring in rings:  # even-odd over the outline and its courtyards
        inside ^= _inside_polygon(top[:, 0], top[:, 2], ring)
    ok = (t > 1e-9) & (t < best) & inside
    best = np.where(ok, t, best)
    normal[ok] = (0.0, 1.0, 0.0)
    roof |= ok
    return best, roof, normal, facade, face, columns


def _quadratic_roots(a, b, c):
    """Both roots (near, far) of a t^2 + b t + c = 0 per ray; nan where there are none."""
    disc = b * b - 4 * a * c
    with np.errstate(invalid="ignore", divide="ignore"):
        root = np.sqrt(np.where(disc >= 0, disc, np.nan))
        return (-b - root) / (2 * a), (-b + root) / (2 * a)


def _cylinder(mass: BuildingMass, eye: np.ndarray, d: np.ndarray, height: float):
    width, _, depth = mass.extent
    radius = width / 2
    centre = np.array([width / 2, depth / 2])
    bay, storey, wall, column_range = _round_face(mass, 2 * np.pi * radius, height)
    n = len(d)
    best = np.full(n, np.inf)
    normal, facade = np.zeros((n, 3)), np.zeros((n, 4))
    ox, oz = eye[0] - centre[0], eye[2] - centre[1]
    a = d[:, 0] ** 2 + d[:, 2] ** 2
    for t in _quadratic_roots(a, 2 * (ox * d[:, 0] + oz * d[:, 2]), np.full(n, ox * ox + oz * oz - radius * radius)):
        y = eye[1] + d[:, 1] * t
        ok = (t > 1e-9) & (y >= 0) & (y <= height) & (t < best)
        best = np.where(ok, t, best)
        rx, rz = (ox + d[:, 0] * t) / radius, (oz + d[:, 2] * t) / radius
        angle = np.mod(np.arctan2(rz, rx), 2 * np.pi)  # facade u runs counter-clockwise from +x
        normal[ok] = np.stack([rx, np.zeros(n), rz], axis=1)[ok]
        facade[ok] = np.stack([angle * radius, y, np.full(n, bay), np.full(n, storey)], axis=1)[ok]
    with np.errstate(divide="ignore", invalid="ignore"):  # level rays never meet the roof
        t = (height - eye[1]) / d[:, 1]
        top = eye + d * t[:, None]
    ok = (t > 1e-9) & (t < best) & ((top[:, 0] - centre[0]) ** 2 + (top[:, 2] - centre[1]) ** 2 <= radius * radius)
    best = np.where(ok, t, best)
    normal[ok] = (0.0, 1.0, 0.0)
    return best, ok, normal, facade, np.tile(wall, (n, 1)), np.tile(column_range, (n, 1))


def _dome(mass: BuildingMass, eye: np.ndarray, d: np.ndarray, height: float):
    radius = mass.extent[0] / 2
    centre = np.array([radius, 0.0, radius])
    rings = dome_faces(radius, mass.floor_height, mass.room_width)
    n = len(d)
    best = np.full(n, np.inf)
    normal, facade, face = np.zeros((n, 3)), np.zeros((n, 4)), np.zeros((n, 4))
    columns = np.zeros((n, 2), dtype=np.int64)
    cap = np.zeros(n, dtype=bool)
    o = eye - centre
    for t in _quadratic_roots(np.sum(d * d, axis=1), 2 * (d @ o), np.full(n, o @ o - radius * radius)):
        r = (o + d * t[:, None]) / radius
        ok = (t > 1e-9) & (r[:, 1] >= 0) & (t < best)
        best = np.where(ok, t, best)
        # longitude counter-clockwise seen from above, from +x; latitude up from the ground
        lon = np.mod(np.arctan2(-r[:, 2], r[:, 0]), 2 * np.pi)
        lat = np.arcsin(np.clip(r[:, 1], -1, 1))
        k = rings.ring_of(np.nan_to_num(lat) * radius)  # each storey a ring, its own face (misses: any)
        normal[ok] = r[ok]
        facade[ok] = np.stack([lon * rings.circle[k], lat * radius, rings.bay[k], np.full(n, rings.storey)], axis=1)[ok]
        face[ok] = np.stack([rings.width[k], rings.base[k], rings.top[k], rings.bay[k]], axis=1)[ok]
        columns[ok] = rings.columns[k][ok]
        cap = np.where(ok, lat >= rings.cap, cap)
    return best, cap, normal, facade, face, columns


SOLIDS = {"prism": _prism, "cylinder": _cylinder, "dome": _dome}


def cast_masses(masses: list[BuildingMass], eye: np.ndarray, dirs: np.ndarray) -> SolidHits:
    """Nearest hit of rays (eye (3,), unit dirs (N, 3), world space) with the masses' solids."""
    n = len(dirs)
    out = SolidHits(
        np.full(n, np.inf),
        np.full(n, -1, dtype=np.int64),
        np.zeros(n, dtype=bool),
        np.zeros((n, 3)),
        np.zeros((n, 3)),
        np.zeros((n, 3)),
        np.zeros((n, 4)),
        np.zeros((n, 4)),
        np.zeros((n, 2), dtype=np.int64),
    )
    for index, mass in enumerate(masses):
        rot = object_to_world(mass.yaw)
        eye_local = rot.T @ (eye - np.array([mass.position[0], 0.0, mass.position[1]]))
        d_local = dirs @ rot  # rot.T applied to each row
        t, roof, normal, facade, face, columns = SOLIDS[mass.shape](mass, eye_local, d_local, float(mass.extent[1]))
        nearer = t < out.t
        out.t[nearer] = t[nearer]
        out.building[nearer] = index
        out.roof[nearer] = roof[nearer]
        out.local[nearer] = eye_local + d_local[nearer] * t[nearer, None]
        out.direction[nearer] = d_local[nearer]
        out.normal[nearer] = normal[nearer]
        out.facade[nearer] = facade[nearer]
        out.face[nearer] = face[nearer]
        out.columns[nearer] = columns[nearer]
    return out
