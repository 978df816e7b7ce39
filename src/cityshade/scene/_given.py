"""Buildings' faces as given (CityJSON walls, roofs, floors) -> triangle rows, instead of an outline
extruded to a height; every face of every mass at once, in a few numpy and shapely passes.

Each given wall polygon is a face of its own: facade u runs along its horizontal direction (the
direction an outline's edge has when the wall stands on its right: _extrusions.py) from the
polygon's first point that way, v is the height, its bays are a whole number of about the
building's room width across it, and its storeys are the building's, counted from the building's
base, so that walls split in several polygons (or standing at several heights) keep one storey
grid. A grammar facade (windows, doors, relief, rooms behind the windows) is drawn only on the
whole bay-by-storey cells that lie inside the polygon; the rest of a gable, a sloped wall top or any
other non-rectangular wall is drawn as plain wall (SURFACE_PLAIN_WALL), so no window crosses the
polygon's edge. Roofs, and floors and ceilings seen from below, are triangulated in their own
plane. Polygons are triangulated by shapely (constrained Delaunay) in their plane; one that is not
planar is drawn in its plane through its centroid (walls: through its lowest-u point).
"""

from __future__ import annotations

import numpy as np
import shapely

from ._extrusions import empty_rows, roof_rows, wall_rows
from ._wall_faces import WallFaces

GIVEN_WALL, GIVEN_ROOF, GIVEN_FLOOR = 0, 1, 2  # a given face's kind (floors and ceilings face down)
RECTANGLE = 0.995  # a wall polygon filling this much of its (u, v) bounding box is a rectangle
CELL_SLACK = 1e-3  # metres a cell may stick out of its wall and still count as inside it
STEEP = 0.95  # a wall whose normal is this close to vertical is drawn as a roof or floor
MAX_CELLS = 4096  # bay-by-storey cells of one wall at most (a wall wider than that is drawn plain)


def _sums(values: np.ndarray, starts: np.ndarray) -> np.ndarray:
    return np.add.reduceat(values, starts, axis=0)


def _newell(points: np.ndarray, nxt: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Unit normals (faces, 3) of rings stored one after another (`nxt`: each point's successor)."""
    a, b = points, points[nxt]
    n = np.column_stack(
        [
            _sums((a[:, 1] - b[:, 1]) * (a[:, 2] + b[:, 2]), starts),
            _sums((a[:, 2] - b[:, 2]) * (a[:, 0] + b[:, 0]), starts),
            _sums((a[:, 0] - b[:, 0]) * (a[:, 1] + b[:, 1]), starts),
        ]
    )
    length = np.linalg.norm(n, axis=1)
    return n / np.where(length > 0, length, 1.0)[:, None], length > 0


def _triangles(polygons: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """((n, 3, 2) counter-clockwise triangles covering the polygons, the polygon of each)."""
    polygons = np.asarray(polygons, dtype=object)
    bad = ~shapely.is_valid(polygons)
    polygons[bad] = shapely.make_valid(polygons[bad])
    triangles, owner = shapely.get_parts(shapely.constrained_delaunay_triangles(polygons), return_index=True)
    if not len(triangles):
        return np.zeros((0, 3, 2)), np.zeros(0, np.int64)
    corners = shapely.get_coordinates(triangles).reshape(-1, 4, 2)[:, :3]
    a, b, c = corners[:, 0], corners[:, 1], corners[:, 2]
    turn = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    keep = np.abs(turn) > 1e-12
    corners = np.where((turn < 0)[:, None, None], corners[:, [0, 2, 1]], corners)
    return corners[keep], owner[keep]


def _rings(flat: np.ndarray, starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    index = np.repeat(np.arange(len(counts)), counts)
    return shapely.polygons(shapely.linearrings(flat, indices=index))


class _Faces:
    """Every given face of the masses: points stored one ring after another."""

    def __init__(self, masses):
        kinds, owners, rings = [], [], []
        for m, mass in enumerate(masses):
            for kind, ring in mass.given:
                kinds.append(kind)
                owners.append(m)
                rings.append(ring)
        self.kind = np.asarray(kinds, np.int64)
        self.mass = np.asarray(owners, np.int64)
        self.counts = np.array([len(r) for r in rings], np.int64)
        self.points = np.array([p for r in rings for p in r], np.float64).reshape(-1, 3)
        self.starts = np.cumsum(self.counts) - self.counts
        nxt = np.arange(len(self.points)) + 1
        if len(self.counts):
            nxt[self.starts + self.counts - 1] = self.starts
        self.of_point = np.repeat(np.arange(len(self.counts)), self.counts)
        self.normal, self.ok = _newell(self.points, nxt, self.starts) if len(self.counts) else (np.zeros((0, 3)), [])


def plane_triangles(points: np.ndarray, counts: np.ndarray, normal: np.ndarray | None = None):
    """Polygons (rings of `counts` points (x, y, z) stored one after another) triangulated each in
    its plane through its centroid: ((n, 3, 3) triangles wound counter-clockwise about the polygon's
    normal, the polygon of each). `normal`: the polygons' unit normals where the caller has them."""
    starts = np.cumsum(counts) - counts
    if normal is None:
        nxt = np.arange(len(points)) + 1
        nxt[starts + counts - 1] = starts
        normal, _ = _newell(points, nxt, starts)
    helper = np.where((np.abs(normal[:, 1]) < 0.9)[:, None], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0])
    e1 = np.cross(helper, normal)
    e1 /= np.maximum(np.linalg.norm(e1, axis=1), 1e-12)[:, None]
    e2 = np.cross(normal, e1)
    which = np.repeat(np.arange(len(counts)), counts)
    centre = _sums(points, starts) / counts[:, None]
    offset = points - centre[which]
    flat = np.column_stack([np.sum(offset * e1[which], axis=1), np.sum(offset * e2[which], axis=1)])
    triangles, owner = _triangles(_rings(flat, None, counts))
    at = np.repeat(owner, 3)
    uv = triangles.reshape(-1, 2)
    positions = centre[at] + uv[:, :1] * e1[at] + uv[:, 1:] * e2[at]
    return positions.reshape(-1, 3, 3), owner


def _flat_rows(faces: _Faces, chosen: np.ndarray):
    """Roof rows of the faces `chosen`, triangulated in their planes."""
    counts = faces.counts[chosen]
    points = faces.points[np.concatenate([np.arange(s, s + c) for s, c in zip(faces.starts[chosen], counts)])]
    triangles, owner = plane_triangles(points, counts, faces.normal[chosen])
    owner = np.repeat(owner, 3)
    return roof_rows(triangles.reshape(-1, 3), faces.normal[chosen][owner]), faces.mass[chosen][owner]


def _wall_frames(faces: _Faces, chosen: np.ndarray):
    """Per wall: (across, up, origin), and its points in (u, height)."""
    normal = faces.normal[chosen]
    across = np.column_stack([-normal[:, 2], np.zeros(len(chosen)), normal[:, 0]])
    across /= np.linalg.norm(across, axis=1)[:, None]
    up = np.cross(across, normal)
    counts = faces.counts[chosen]
    points = faces.points[np.concatenate([np.arange(s, s + c) for s, c in zip(faces.starts[chosen], counts)])]
    which = np.repeat(np.arange(len(chosen)), counts)
    along = np.sum(points * across[which], axis=1)
    first = np.cumsum(counts) - counts
    low = np.minimum.reduceat(along, first)
    origin = points[first + np.array([np.argmin(along[s : s + c]) for s, c in zip(first, counts)], np.int64)]
    plan = np.column_stack([along - low[which], points[:, 1]])
    return across, up, origin, plan, counts


def _cells(y0, y1, bay, bays, base, storey):
    """The walls' bay-by-storey cells over their whole (u, height) box: (boxes, wall of each)."""
    first = np.floor((y0 - base) / storey).astype(np.int64)
    rows = np.ceil((y1 - base) / storey).astype(np.int64) - first
    per = bays * rows
    wall = np.repeat(np.arange(len(per)), per)
    k = np.arange(per.sum()) - np.repeat(np.cumsum(per) - per, per)
    column, row = k % bays[wall], k // bays[wall] + first[wall]
    x0, x1 = column * bay[wall], (column + 1) * bay[wall]
    boxes = shapely.box(x0, base[wall] + row * storey[wall], x1, base[wall] + (row + 1) * storey[wall])
    return boxes, wall


def _wall_rows(faces: _Faces, chosen: np.ndarray, masses, storey: np.ndarray, columns: np.ndarray):
    """(grammar rows and their masses, plain rows and their masses) of the walls `chosen`."""
    across, up, origin, plan, counts = _wall_frames(faces, chosen)
    polygons = _rings(plan, None, counts)
    u0, y0, u1, y1 = shapely.bounds(polygons).T
    width = u1 - u0
    owner_mass = faces.mass[chosen]
    room = np.array([masses[m].room_width for m in owner_mass])
    bays = np.maximum(1, np.round(width / room)).astype(np.int64)
    bay = width / bays
    base = np.array([masses[m].base for m in owner_mass])
    height = storey[owner_mass]
    rows = np.ceil((y1 - base) / height) - np.floor((y0 - base) / height)
    rectangle = (shapely.area(polygons) >= RECTANGLE * width * (y1 - y0)) | (bays * rows > MAX_CELLS)
    cut = np.flatnonzero(~rectangle)
    boxes, wall = _cells(y0[cut], y1[cut], bay[cut], bays[cut], base[cut], height[cut])
    wall = cut[wall]
    slack = shapely.buffer(polygons[cut], CELL_SLACK, join_style="mitre")
    shapely.prepare(slack)
    grow = np.zeros(len(chosen), np.int64)
    grow[cut] = np.arange(len(cut))
    inside = shapely.contains(slack[grow[wall]], boxes)
    pieces = shapely.intersection(polygons[wall[~inside]], boxes[~inside])
    pieces_wall = wall[~inside]
    keep = shapely.area(pieces) > 1e-9
    grammar = np.concatenate([polygons[rectangle], boxes[inside]])
    grammar_wall = np.concatenate([np.flatnonzero(rectangle), wall[inside]])
    faces_table = WallFaces(
        np.zeros(len(chosen)), width, bay, bay, np.stack([columns[chosen], columns[chosen] + bays - 1], axis=1)
    )
    out = []
    for parts, owner in ((grammar, grammar_wall), (pieces[keep], pieces_wall[keep])):
        triangles, index = _triangles(parts)
        w = np.repeat(owner[index], 3)
        flat = triangles[:, ::-1].reshape(-1, 2)  # (u, height) is mirrored seen from outside
        lift = (flat[:, 1] - origin[w, 1]) / up[w, 1]
        positions = origin[w] + flat[:, :1] * across[w] + lift[:, None] * up[w]
        positions[:, 1] = flat[:, 1]  # exactly the polygon's heights
        span = (base[w], y1[w])
        rows_ = wall_rows(positions, faces.normal[chosen][w], faces_table, w, flat[:, 0], span, height[w])
        out.append((rows_, owner_mass[w]))
    return out


def given_mass_rows(masses):
    """(walls, roof, plain walls): each (rows, mass index per row) of the masses' given faces, every
    mass's rows in its faces' order."""
    faces = _Faces(masses)
    if not len(faces.counts):
        none = (empty_rows(), np.zeros(0, np.int64))
        return none, none, none
    storey = np.array([_storey(m) for m in masses])
    vertical = np.abs(faces.normal[:, 1]) < STEEP
    walls = np.flatnonzero((faces.kind == GIVEN_WALL) & vertical & faces.ok)
    flats = np.flatnonzero(~((faces.kind == GIVEN_WALL) & vertical) & faces.ok)
    # room columns: each wall its own run of them, one after another around its building
    bays = np.zeros(len(faces.counts), np.int64)
    columns = np.zeros(len(faces.counts), np.int64)
    if len(walls):
        across, _, _, plan, counts = _wall_frames(faces, walls)
        width = np.maximum.reduceat(plan[:, 0], np.cumsum(counts) - counts)
        room = np.array([masses[m].room_width for m in faces.mass[walls]])
        bays[walls] = np.maximum(1, np.round(width / room)).astype(np.int64)
        before = np.cumsum(bays) - bays
        first_of_mass = np.searchsorted(faces.mass, faces.mass)
        columns = before - before[first_of_mass]
        grammar, plain = _wall_rows(faces, walls, masses, storey, columns)
    else:
        grammar = plain = (empty_rows(), np.zeros(0, np.int64))
    roof = _flat_rows(faces, flats) if len(flats) else (empty_rows(), np.zeros(0, np.int64))
    return grammar, roof, plain


def _storey(mass) -> float:
    """Whole storeys of about the mass's floor height between its base and top."""
    span = mass.height - mass.base
    return span / max(1, round(span / mass.floor_height))


def given_rows(mass):
    """(wall rows, dormer front rows (none), roof rows, plain wall rows) of one mass with given faces."""
    grammar, roof, plain = given_mass_rows([mass])
    return _ordered(grammar), empty_rows(), _ordered(roof), _ordered(plain)


def _ordered(part):
    return part[0]
