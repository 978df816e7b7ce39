"""One CityJSON geometry -> its polygons with their semantic surface type, checked and repaired.

Every geometry type of CityJSON 1.0-2.0 is read: MultiSurface and CompositeSurface (a list of
surfaces), Solid (shells of surfaces: the outer shell, inner shells are cavities and not drawn),
MultiSolid and CompositeSolid (the outer shell of each solid) and GeometryInstance (a template's
geometry placed by its 4x4 matrix at its reference vertex). Semantic values follow the boundaries'
nesting one level above the rings; where they do not match the boundaries the faces are read
without semantics and the repair is counted.

A surface is its outer ring (inner rings are openings: LoD3 windows and doors are surfaces of their
own); it is skipped and counted where an index is not a whole number, not a vertex of the file, its
vertex is not finite, or the ring has no area in its own plane. Faces are returned with the file's
vertex coordinates (x, y, height as given).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from ._model import ReadReport

SURFACE_DEPTH = {"MultiSurface": 0, "CompositeSurface": 0, "Solid": 1, "MultiSolid": 2, "CompositeSolid": 2}
MIN_FACE_AREA = 1e-4  # square metres: a ring with less area in its own plane is a line or a point
PLANAR = 0.05  # metres: a corner further than this from its face's plane makes the face not planar


@dataclass(frozen=True)
class Face:
    """One surface: its outer ring (n, 3) in the file's coordinates and its semantic type (None: not given)."""

    ring: np.ndarray
    semantic: str | None
    normal: np.ndarray  # unit normal (Newell's), counter-clockwise rings face it


@dataclass(frozen=True)
class Templates:
    """The file's `geometry-templates`: template geometries and their own vertices."""

    geometries: list
    vertices: np.ndarray


NO_TEMPLATES = Templates([], np.zeros((0, 3)))


def vertex_array(value) -> np.ndarray | None:
    """(n, 3) float64 vertices; a vertex that is not three numbers becomes NaN (its faces are skipped).
    None when `value` is not a list."""
    if not isinstance(value, list):
        return None
    try:
        array = np.asarray(value, dtype=np.float64)
        if array.ndim == 2 and array.shape[1] == 3:
            return array
    except (TypeError, ValueError, OverflowError):
        pass
    out = np.full((len(value), 3), np.nan)
    for i, vertex in enumerate(value):
        try:
            point = np.asarray(vertex, dtype=np.float64)
        except (TypeError, ValueError, OverflowError):
            continue
        if point.shape == (3,):
            out[i] = point
    return out


def _surfaces(boundaries, values, depth: int):
    """(surface, semantic value) pairs of boundaries nested `depth` levels above the surfaces."""
    if depth == 0:
        values = values if isinstance(values, list) and len(values) == len(boundaries) else None
        return [(s, values[i] if values else None) for i, s in enumerate(boundaries)], values is not None
    out, matched = [], True
    # a Solid's first shell is its outside; a MultiSolid's solids each have one
    groups = boundaries[:1] if depth == 1 else [solid[0] for solid in boundaries if isinstance(solid, list) and solid]
    if depth == 1:
        group_values = [values[0]] if isinstance(values, list) and values else [None]
    else:
        group_values = (
            [v[0] if isinstance(v, list) and v else None for v in values]
            if isinstance(values, list) and len(values) == len(boundaries)
            else [None] * len(groups)
        )
    for group, value in zip(groups, group_values):
        if not isinstance(group, list):
            continue
        pairs, ok = _surfaces(group, value, 0)
        out += pairs
        matched &= ok or value is None
    return out, matched


def _ring(surface, vertices: np.ndarray, report: ReadReport, element: str) -> np.ndarray | None:
    ring = surface[0] if isinstance(surface, list) and surface else None
    try:
        indices = np.asarray(ring, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        indices = np.zeros((0, 2))
    if indices.ndim != 1 or len(indices) < 3 or not np.all(indices == np.floor(indices)):
        report.skip("surface", "ring is not a list of at least 3 vertex indices", element)
        return None
    indices = indices.astype(np.int64)
    if indices.min() < 0 or indices.max() >= len(vertices):
        report.skip("surface", f"vertex index out of range (the file has {len(vertices)} vertices)", element)
        return None
    points = vertices[indices]
    if not np.isfinite(points).all():
        report.skip("surface", "vertex not three finite numbers", element)
        return None
    return points


def _rings(pairs, vertices: np.ndarray, report: ReadReport, element: str) -> list:
    """Every surface's outer ring as points (or None where it is skipped): all at once where every ring
    is a plain list of at least three whole indices of the file's vertices, else one by one (_ring)."""
    outer = [s[0] if isinstance(s, list) and s and isinstance(s[0], list) else None for s, _ in pairs]
    try:
        if not outer or any(r is None or len(r) < 3 for r in outer):
            raise ValueError
        numbers = np.array([i for r in outer for i in r], dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        return [_ring(surface, vertices, report, element) for surface, _ in pairs]
    whole = numbers.ndim == 1 and np.all(numbers == np.floor(numbers))
    if not whole or numbers.min() < 0 or numbers.max() >= len(vertices):
        return [_ring(surface, vertices, report, element) for surface, _ in pairs]
    points = vertices[numbers.astype(np.int64)]
    if not np.isfinite(points).all():
        return [_ring(surface, vertices, report, element) for surface, _ in pairs]
    ends = np.cumsum([len(r) for r in outer])
    return np.split(points, ends[:-1])


def newell_normal(points: np.ndarray) -> np.ndarray:
    """The ring's area vector (Newell's method): its direction the normal, its length twice the area."""
    a, b = points, np.roll(points, -1, axis=0)
    return np.array(
        [
            np.sum((a[:, 1] - b[:, 1]) * (a[:, 2] + b[:, 2])),
            np.sum((a[:, 2] - b[:, 2]) * (a[:, 0] + b[:, 0])),
            np.sum((a[:, 0] - b[:, 0]) * (a[:, 1] + b[:, 1])),
        ]
    )


def newell_normals(rings: list[np.ndarray]) -> np.ndarray:
    """newell_normal of many rings at once."""
    counts = np.array([len(r) for r in rings])
    points = np.vstack(rings)
    starts = np.cumsum(counts) - counts
    nxt = np.arange(len(points)) + 1
    nxt[starts + counts - 1] = starts
    a, b = points, points[nxt]
    terms = np.column_stack(
        [
            (a[:, 1] - b[:, 1]) * (a[:, 2] + b[:, 2]),
            (a[:, 2] - b[:, 2]) * (a[:, 0] + b[:, 0]),
            (a[:, 0] - b[:, 0]) * (a[:, 1] + b[:, 1]),
        ]
    )
    return np.add.reduceat(terms, starts, axis=0)


def _instance(geometry: dict, vertices: np.ndarray, templates: Templates):
    """A GeometryInstance as (template geometry, its vertices placed in the file's coordinates)."""
    template = geometry.get("template")
    if not isinstance(template, int) or not 0 <= template < len(templates.geometries):
        raise ValueError(f"template {str(template)[:20]} is not one of the file's {len(templates.geometries)}")
    reference = geometry.get("boundaries")
    if not (isinstance(reference, list) and len(reference) == 1 and isinstance(reference[0], int)):
        raise ValueError("an instance's boundaries must be one vertex index")
    if not 0 <= reference[0] < len(vertices):
        raise ValueError("an instance's reference vertex is out of range")
    matrix = np.asarray(geometry.get("transformationMatrix", np.eye(4).ravel()), dtype=np.float64).reshape(4, 4)
    local = templates.vertices
    placed = local @ matrix[:3, :3].T + matrix[:3, 3] + vertices[reference[0]]
    inner = templates.geometries[template]
    if not isinstance(inner, dict):
        raise ValueError("the template is not a geometry")
    return inner, placed


def geometry_faces(
    geometry: dict, vertices: np.ndarray, templates: Templates, report: ReadReport, element: str
) -> list[Face]:
    """The checked faces of one geometry object (see the module docstring). Raises ValueError
    (with what is wrong) when the geometry as a whole cannot be read."""
    if geometry.get("type") == "GeometryInstance":
        try:
            geometry, vertices = _instance(geometry, vertices, templates)
        except (TypeError, ValueError, OverflowError) as exc:
            raise ValueError(f"geometry instance: {exc}") from None
    kind = geometry.get("type")
    if kind not in SURFACE_DEPTH:
        raise ValueError(f"geometry type {str(kind)[:40]!r} has no surfaces")
    boundaries = geometry.get("boundaries")
    if not isinstance(boundaries, list):
        raise ValueError("'boundaries' is not a list")
    semantics = geometry.get("semantics") if isinstance(geometry.get("semantics"), dict) else {}
    surfaces = semantics.get("surfaces") if isinstance(semantics.get("surfaces"), list) else []
    names = [s.get("type") if isinstance(s, dict) and isinstance(s.get("type"), str) else None for s in surfaces]
    pairs, matched = _surfaces(boundaries, semantics.get("values"), SURFACE_DEPTH[kind])
    if semantics and not matched:
        report.repair("geometry", "semantic values do not match the boundaries, read without semantics", element)
        pairs = [(surface, None) for surface, _ in pairs]
    rings, kinds = [], []
    for (_, value), ring in zip(pairs, _rings(pairs, vertices, report, element)):
        if ring is not None:
            rings.append(ring)
            kinds.append(names[value] if isinstance(value, int) and 0 <= value < len(names) else None)
    if not rings:
        return []
    normals = newell_normals(rings)
    length = np.linalg.norm(normals, axis=1)
    off = _off_plane(rings, normals / np.maximum(length, 1e-300)[:, None])
    faces = []
    for ring, kind, normal, size, distance in zip(rings, kinds, normals, length, off):
        if size / 2.0 < MIN_FACE_AREA:
            report.skip("surface", "degenerate (no area in its plane)", element)
            continue
        if distance > PLANAR:
            report.repair(
                "surface", f"not planar (a corner over {PLANAR:g} m off its plane): drawn in its plane", element
            )
        faces.append(Face(ring, kind, normal / size))
    return faces


def _off_plane(rings: list[np.ndarray], normals: np.ndarray) -> np.ndarray:
    """Per ring: the largest distance of a corner from the plane through its centroid."""
    counts = np.array([len(r) for r in rings])
    points = np.vstack(rings)
    starts = np.cumsum(counts) - counts
    which = np.repeat(np.arange(len(rings)), counts)
    centre = np.add.reduceat(points, starts, axis=0) / counts[:, None]
    distance = np.abs(np.sum((points - centre[which]) * normals[which], axis=1))
    return np.maximum.reduceat(distance, starts)


PLANE_ANGLE = 0.02  # radians-ish: normals closer than this are one plane's
PLANE_OFFSET = 0.02  # metres
UPRIGHT = 0.01  # |normal z| under this: a vertical wall


FACING = {"RoofSurface": 1.0, "OuterCeilingSurface": -1.0, "GroundSurface": -1.0, "OuterFloorSurface": 1.0}


def facing_out(faces: list[Face], footprint, report: ReadReport, element: str) -> list[Face]:
    """The faces with rings that face the wrong way turned round (counted): roofs and floors facing
    down, ground and ceilings facing up, walls facing into the footprint (the point a step in front
    of the wall inside it, the point a step behind outside)."""
    normals = np.array([f.normal for f in faces])
    inverted = np.array([normal[2] * FACING.get(f.semantic, 0.0) < -0.1 for f, normal in zip(faces, normals)])
    walls = np.flatnonzero([f.semantic == "WallSurface" for f in faces] & (np.abs(normals[:, 2]) < 0.7))
    if len(walls):  # every wall's two test points at once
        plan = normals[walls, :2]
        step = plan / np.linalg.norm(plan, axis=1)[:, None] * 0.3
        centre = np.array([faces[i].ring[:, :2].mean(axis=0) for i in walls])
        front = shapely.contains_xy(footprint, *(centre + step).T)
        back = shapely.contains_xy(footprint, *(centre - step).T)
        inverted[walls] = front & ~back
    out = []
    for face, turn in zip(faces, inverted):
        if turn:
            report.repair("surface", f"{face.semantic} facing the wrong way: turned", element)
            face = Face(face.ring[::-1], face.semantic, -face.normal)
        out.append(face)
    return out


def _signed_areas(points: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """Twice the signed area of 2D rings stored one after another."""
    starts = np.cumsum(counts) - counts
    nxt = np.arange(len(points)) + 1
    nxt[starts + counts - 1] = starts
    cross = points[:, 0] * points[nxt, 1] - points[nxt, 0] * points[:, 1]
    return np.add.reduceat(cross, starts)


def _dissolved(rings: list[np.ndarray]) -> np.ndarray | None:
    """The one ring round coplanar rings wound alike that share whole edges (each inner edge run once
    each way), found by cancelling those edges; None where the rest is not one simple ring."""
    edges = {}
    for ring in rings:
        points = [tuple(p) for p in ring.tolist()]
        for a, b in zip(points, points[1:] + points[:1]):
            if (b, a) in edges:
                del edges[(b, a)]
            else:
                edges[(a, b)] = True
    after = {}
    for a, b in edges:
        if a in after:
            return None  # two boundary edges leave one corner: not a simple ring
        after[a] = b
    if len(after) < 3:
        return None
    start = next(iter(after))
    out, point = [start], after[start]
    while point != start and len(out) <= len(after):
        out.append(point)
        point = after.get(point)
        if point is None:
            return None
    return np.array(out) if len(out) == len(after) else None


def merged_walls(buildings: list[list[Face]]) -> list[list[Face]]:
    """Per building: vertical wall faces lying in one plane (a wall the file splits in triangles, as
    3D BAG does) merged into the polygons they make together, so that the wall is one face with whole
    windows; every other face as it was. All buildings' faces are grouped in one pass."""
    faces = [face for building in buildings for face in building]
    if not faces:
        return [list(b) for b in buildings]
    owner = np.repeat(np.arange(len(buildings)), [len(b) for b in buildings])
    normals = np.array([f.normal for f in faces])
    wall = np.array([f.semantic in (None, "WallSurface") for f in faces]) & (np.abs(normals[:, 2]) < UPRIGHT)
    index = np.flatnonzero(wall)
    plan = normals[index, :2] / np.linalg.norm(normals[index, :2], axis=1)[:, None]
    counts = np.array([len(faces[i].ring) for i in index], dtype=np.int64)
    starts = np.cumsum(counts) - counts
    points = np.vstack([faces[i].ring for i in index]) if len(index) else np.zeros((0, 3))
    centre = np.add.reduceat(points[:, :2], starts, axis=0) / counts[:, None] if len(index) else np.zeros((0, 2))
    offset = np.sum(centre * plan, axis=1)
    semantic = np.array([faces[i].semantic == "WallSurface" for i in index])
    keys = np.column_stack([owner[index], semantic, np.round(plan / PLANE_ANGLE), np.round(offset / PLANE_OFFSET)])
    _, group, sizes = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    group = group.ravel()
    alone = np.ones(len(faces), dtype=bool)
    alone[index[sizes[group] > 1]] = False
    out = [[] for _ in buildings]
    for i in np.flatnonzero(~wall):
        out[owner[i]].append(faces[i])
    for i in np.flatnonzero(wall & alone):
        out[owner[i]].append(faces[i])
    members: dict[int, list[int]] = {}  # group -> its faces' places in `index`, in file order
    for k in np.flatnonzero(sizes[group] > 1):
        members.setdefault(group[k], []).append(k)
    unjoined = []
    for g, ks in members.items():
        face = faces[index[ks[0]]]
        ring = _dissolved([faces[index[k]].ring for k in ks])
        if ring is not None:  # pieces sharing whole edges: their outline, no overlay needed
            out[owner[index[ks[0]]]].append(Face(ring, face.semantic, face.normal))
        else:
            out[owner[index[ks[0]]]].append(None)  # its place, filled by the overlay below
            unjoined.append(g)
    if unjoined:
        overlaid = _overlaid([members[g] for g in unjoined], faces, index, plan, offset, points, counts, starts)
        filled = iter(overlaid)
        out = [[part for face in b for part in (next(filled) if face is None else [face])] for b in out]
    merged = set(owner[index[[ks[0] for ks in members.values()]]]) if members else set()
    return [out[b] if b in merged else list(faces_of) for b, faces_of in enumerate(buildings)]


def _overlaid(groups: list[list[int]], faces, index, plan, offset, points, counts, starts) -> list[list[Face]]:
    """The union of each group's coplanar wall pieces (in their plane's (u, z)), as faces facing the
    way the pieces did: the wall pieces that do not share whole edges."""
    ks = np.concatenate(groups)
    frame = np.repeat([g[0] for g in groups], [len(g) for g in groups])  # each group's frame: its first face's
    across = np.column_stack([-plan[:, 1], plan[:, 0]])
    which = np.concatenate([np.full(counts[k], f) for k, f in zip(ks, frame)])
    rings = np.vstack([points[starts[k] : starts[k] + counts[k]] for k in ks])
    uv = np.column_stack([np.sum(rings[:, :2] * across[which], axis=1), rings[:, 2]])
    sign = np.sign(_signed_areas(uv, counts[ks]))
    polygons = shapely.polygons(shapely.linearrings(uv, indices=np.repeat(np.arange(len(ks)), counts[ks])))
    bad = ~shapely.is_valid(polygons)
    polygons[bad] = shapely.make_valid(polygons[bad])
    out, at = [], 0
    for members in groups:
        k, face = members[0], faces[index[members[0]]]
        foot, direction = plan[k] * offset[k], across[k]
        parts = []
        for part in shapely.get_parts(shapely.union_all(polygons[at : at + len(members)])):
            if shapely.get_type_id(part) != 3 or part.area <= 0:
                continue
            ring = np.asarray(shapely.orient_polygons(part).exterior.coords)[:-1]  # counter-clockwise in (u, z)
            ring = ring if sign[at] > 0 else ring[::-1]  # facing the way the faces did
            parts.append(
                Face(np.column_stack([foot + ring[:, :1] * direction, ring[:, 1]]), face.semantic, face.normal)
            )
        out.append(parts)
        at += len(members)
    return out
