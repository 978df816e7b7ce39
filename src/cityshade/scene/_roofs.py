"""Roofs on top of a building's walls: the roof surfaces and the wall pieces under them (gables).

Every roof is built in the building's object space (x, z metres, y up) from the outline polygon
(with courtyard holes) and the height of the walls' top.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely

from ._materials import ROOF_PART_SURFACE
from ._skeleton import ring_edges, skeleton_triangles


@dataclass(frozen=True)
class Roof:
    """A roof of one of `ROOF_SHAPES` rising `height` metres above the walls' top.

    `direction` (radians, object space, from +x toward +z) is where the main roof face looks,
    downhill: a gabled roof's ridge runs across it, a skillion falls toward it."""

    shape: str = "flat"
    height: float = 0.0
    direction: float = np.pi / 2  # ridge along +x, the footprint's longest side
    colour: tuple[float, float, float] | None = None  # sRGB 0..1; None: the material's colour
    material: str | None = None
    parapet: float = 0.0  # flat roofs: metres the walls rise above the roof as a PARAPET_THICKNESS rim
    seed: int = 0  # the building's: where its rooftop units go
    attic_storey: float = 0.0  # metres: a storey of rooms in the roof (roof:levels), lit by dormers; 0: none
    dormers: bool = True  # whether that storey has dormers (maps/_roofs.py: where tagged, or by rule)


FLAT_ROOF = Roof()

ROUND_SEGMENTS = 8  # chords of a round (barrel) roof's arc
DOME_RINGS = 8
SMOOTH_TURN = np.cos(np.radians(30.0))  # curved roofs are shaded smooth around outline corners gentler than this
SALTBOX_RIDGE = 0.3  # where the ridge stands across the outline, from the back
GAMBREL_KNEE, GAMBREL_RISE = 0.3, 0.6  # the steep lower slopes run this share of the half width, rise this share
MANSARD_KNEE, MANSARD_RISE = 0.2, 0.75
RECTANGULAR = 0.85  # outlines filling this share of their bounding rectangle take the exact ridged profiles
EPS = 1e-6
HALF_HIP = 0.4  # the share of the roof height (and of the half width) the hips of a half-hipped roof take
PARAPET_THICKNESS = 0.25  # metres


@dataclass
class Triangles:
    """Unindexed triangles (3 rows each) in object space: positions and unit normals; wall
    triangles also know where they stand on their outline edge (metres from its start, its length)
    and which piece they belong to (a gable's or a dormer's number), roof triangles may say what part of
    the roof they are (ROOF_PART_*, None: all the surface)."""

    positions: np.ndarray  # (n, 3)
    normals: np.ndarray  # (n, 3)
    along: np.ndarray | None = None  # (n,)
    edge_length: np.ndarray | None = None  # (n,)
    part: np.ndarray | None = None  # (n,)
    piece: np.ndarray | None = None  # (n,)

    @staticmethod
    def empty() -> Triangles:
        return Triangles(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0), np.zeros(0), piece=np.zeros(0, np.int64))

    @staticmethod
    def join(parts: list[Triangles]) -> Triangles:
        """The triangles of `parts` one after another (wall pieces numbered on: each part's after the last's)."""
        parts = [p for p in parts if len(p.positions)]
        if not parts:
            return Triangles.empty()
        walls = all(p.along is not None for p in parts)
        marked = any(p.part is not None for p in parts)
        pieced = all(p.piece is not None for p in parts)
        return Triangles(
            np.concatenate([p.positions for p in parts]),
            np.concatenate([p.normals for p in parts]),
            np.concatenate([p.along for p in parts]) if walls else None,
            np.concatenate([p.edge_length for p in parts]) if walls else None,
            np.concatenate([p.roof_parts() for p in parts]) if marked else None,
            _pieces_after_each_other([p.piece for p in parts]) if pieced else None,
        )

    def roof_parts(self) -> np.ndarray:
        """Each row's ROOF_PART_* code."""
        return self.part if self.part is not None else np.full(len(self.positions), ROOF_PART_SURFACE, np.int64)


def _pieces_after_each_other(pieces: list[np.ndarray]) -> np.ndarray:
    """Pieces' numbers of parts joined: each part's shifted past the numbers of the parts before it."""
    shifts = np.cumsum([0] + [int(p.max()) + 1 for p in pieces[:-1]])
    return np.concatenate([p.astype(np.int64) + shift for p, shift in zip(pieces, shifts)])


def polygon_triangles(polygon: shapely.Polygon) -> np.ndarray:
    """(n, 3, 2) triangles covering a polygon with holes, counter-clockwise in (x, z) seen from +y...

    ...meaning their normal (b - a) x (c - a) points up (+y) once lifted to 3D."""
    tris = shapely.get_coordinates(shapely.constrained_delaunay_triangles(polygon)).reshape(-1, 4, 2)[:, :3]
    return upward(tris)[0] if len(tris) else np.zeros((0, 3, 2))


def upward(tris: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(triangles turned to face up, which of the given ones they are): (n, 3, 2) triangles of a
    triangulation made counter-clockwise seen from +y, slivers (where a polygon touches itself) dropped."""
    tris = tris.copy()
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    cross = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    up = cross < 0  # x right, z toward the viewer: up-facing triangles turn clockwise in (x, z)
    tris[~up] = tris[~up][:, ::-1]
    kept = np.abs(cross) > 1e-9
    return tris[kept], kept


def flat_rows(tris: np.ndarray, y: np.ndarray | float, up: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """(positions, normals) of upward triangles (n, 3, 2) lifted to height y (one or one per
    triangle), facing up (a roof) or down (an underside)."""
    if not up:
        tris = tris[:, ::-1]
    points = tris.reshape(-1, 2)
    positions = np.column_stack(
        [points[:, 0], np.broadcast_to(np.repeat(y, 3) if np.ndim(y) else y, len(points)), points[:, 1]]
    )
    normals = np.zeros_like(positions)
    normals[:, 1] = 1.0 if up else -1.0
    return positions, normals


def flat(polygon: shapely.Polygon, y: float, up: bool = True) -> Triangles:
    """The polygon as a horizontal surface at height y, facing up (a roof) or down (an underside)."""
    return Triangles(*flat_rows(polygon_triangles(polygon), y, up))


def _lift(tris: np.ndarray, plane: np.ndarray, top: float) -> Triangles:
    """2D triangles (n, 3, 2) onto the plane y = top + a x + b z + c, facing up."""
    a, b, c = plane
    points = tris.reshape(-1, 2)
    positions = np.column_stack([points[:, 0], top + a * points[:, 0] + b * points[:, 1] + c, points[:, 1]])
    normal = np.array([-a, 1.0, -b]) / np.sqrt(a * a + b * b + 1.0)
    return Triangles(positions, np.broadcast_to(normal, positions.shape).copy())


def _rings(polygon: shapely.Polygon) -> list[np.ndarray]:
    return [np.asarray(r.coords) for r in (polygon.exterior, *polygon.interiors)]


def _lowest(planes: np.ndarray, points: np.ndarray) -> np.ndarray:
    return (points @ planes[:, :2].T + planes[:, 2]).min(axis=1)


def _clip(region: np.ndarray, g: np.ndarray) -> np.ndarray:
    """The part of a convex polygon where g . (x, z, 1) <= 0 (Sutherland-Hodgman, one line)."""
    if not len(region):
        return region
    value = region @ g[:2] + g[2]
    out = []
    for i in range(len(region)):
        p, q, vp, vq = region[i], region[(i + 1) % len(region)], value[i], value[(i + 1) % len(region)]
        if vp <= 0:
            out.append(p)
        if (vp < 0) != (vq < 0) and vp != vq:
            out.append(p + (q - p) * vp / (vp - vq))
    return np.asarray(out).reshape(-1, 2)


def plane_roof(polygon: shapely.Polygon, top: float, planes: np.ndarray, regions=None) -> tuple[Triangles, Triangles]:
    """A roof whose height over the outline is the lowest of `planes` (rows a, b, c: a x + b z + c),
    a concave piecewise-planar surface (gabled, hipped, gambrel, mansard...), with the wall pieces
    that close it along every outline edge. `regions` (convex polygons where each plane is the
    lowest) saves finding them when the caller knows them."""
    x0, z0, x1, z1 = polygon.bounds
    box = np.array([[x0, z0], [x1, z0], [x1, z1], [x0, z1]]) + np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]])
    roofs = []
    for k, plane in enumerate(planes):
        if regions is not None:
            region = regions[k]
        else:
            region = box
            for j, other in enumerate(planes):
                if j != k:
                    region = _clip(region, plane - other)
        if len(region) < 3:
            continue
        part = shapely.intersection(polygon, shapely.Polygon(region))
        for piece in getattr(part, "geoms", [part]):
            if isinstance(piece, shapely.Polygon) and piece.area > 1e-9:
                roofs.append(_lift(polygon_triangles(piece), plane, top))
    return Triangles.join(roofs), Triangles.join([_walls_under(planes, ring, top) for ring in _rings(polygon)])


def _walls_under(planes: np.ndarray, ring: np.ndarray, top: float) -> Triangles:
    """Wall pieces on every edge of a closed ring (outward to the edges' right) up to the lowest of
    `planes`: under a concave envelope each piece is convex, fanned from its edge's start."""
    a, b = ring[:-1], ring[1:]
    length = np.linalg.norm(b - a, axis=1)
    a, b, length = a[length > 1e-9], b[length > 1e-9], length[length > 1e-9]
    slope = (b - a) @ planes[:, :2].T  # (edges, planes): height gained over the edge
    start = a @ planes[:, :2].T + planes[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        crossings = (start[:, None, :] - start[:, :, None]) / (slope[:, :, None] - slope[:, None, :])
    t = np.nan_to_num(crossings.reshape(len(a), -1), nan=0.0, posinf=0.0, neginf=0.0).clip(0.0, 1.0)
    t = np.sort(np.column_stack([np.zeros(len(a)), t, np.ones(len(a))]), axis=1)

    def envelope(at):
        return np.maximum((start[:, None, :] + at[:, :, None] * slope[:, None, :]).min(axis=2), 0.0)

    height = envelope(t)
    # only the kinks matter: every other point takes the last kink's place (its triangle vanishes)
    bend = np.abs(envelope(t + 1e-6) + envelope(t - 1e-6) - 2 * height) > 1e-9
    bend[:, [0, -1]] = True
    last = np.maximum.accumulate(np.where(bend, np.arange(t.shape[1]), 0), axis=1)
    t, height = np.take_along_axis(t, last, axis=1), np.take_along_axis(height, last, axis=1)
    chain = np.concatenate(
        [
            np.stack([length, np.zeros(len(a))], axis=1)[:, None],
            np.stack([t * length[:, None], height], axis=2)[:, ::-1],
        ],
        axis=1,
    )
    tris = np.stack([np.zeros_like(chain[:, 1:]), chain[:, 1:], chain[:, :-1]], axis=2)  # clockwise: facing out
    u, v = tris[..., 0], tris[..., 1]
    cross = (u[..., 1] - u[..., 0]) * (v[..., 2] - v[..., 0]) - (v[..., 1] - v[..., 0]) * (u[..., 2] - u[..., 0])
    edge, keep = np.nonzero(cross < -1e-9)
    tris = tris[edge, keep]  # (n, 3, 2) of (along, rise)
    e = ((b - a) / length[:, None])[edge]
    along = tris[..., 0]
    positions = np.stack(
        [a[edge, 0, None] + along * e[:, 0, None], top + tris[..., 1], a[edge, 1, None] + along * e[:, 1, None]], axis=2
    ).reshape(-1, 3)
    normals = np.repeat(np.column_stack([e[:, 1], np.zeros(len(e)), -e[:, 0]]), 3, axis=0)
    return Triangles(positions, normals, along.ravel(), np.repeat(length[edge], 3), piece=np.repeat(edge, 3))


def _profile_planes(axis: np.ndarray, points) -> list[np.ndarray]:
    """Planes rising along `axis` through a concave profile of (coordinate along axis, height) points."""
    planes = []
    for (va, ha), (vb, hb) in zip(points[:-1], points[1:]):
        slope = (hb - ha) / (vb - va)
        planes.append(np.array([slope * axis[0], slope * axis[1], ha - slope * va]))
    return planes


def _arc(v0: float, v1: float, h: float, segments: int = ROUND_SEGMENTS) -> list[tuple[float, float]]:
    angles = np.linspace(np.pi, 0.0, segments + 1)
    return list(zip((v0 + v1) / 2 + (v1 - v0) / 2 * np.cos(angles), h * np.sin(angles)))


def ridge_frame(polygon: shapely.Polygon, direction: float):
    """(across, along, (v0, v1), (u0, u1)) of a ridged roof looking toward `direction`: the unit
    directions downhill from the ridge and along it, and the outline's extent along each."""
    across = np.array([np.cos(direction), np.sin(direction)])  # downhill, main face
    along = np.array([-across[1], across[0]])
    points = np.asarray(polygon.exterior.coords)
    return (
        across,
        along,
        ((points @ across).min(), (points @ across).max()),
        ((points @ along).min(), (points @ along).max()),
    )


def exact_profile(polygon: shapely.Polygon) -> bool:
    """Whether a ridged roof over `polygon` takes the exact profiles (_ridged): an outline without
    courtyards that fills RECTANGULAR of its bounding rectangle."""
    x0, z0, x1, z1 = polygon.bounds
    return not polygon.interiors and polygon.area >= RECTANGULAR * (x1 - x0) * (z1 - z0)


def _ridged(polygon: shapely.Polygon, top: float, roof: Roof, shape: Ridged) -> tuple[Triangles, Triangles]:
    """The shapes with a ridge (or a single slope) across `roof.direction`, from profiles over the
    outline's extent across the ridge (v) and along it (u, for the hipped ends)."""
    across, along, (v0, v1), (u0, u1) = ridge_frame(polygon, roof.direction)
    profile = shape.across(v0, v1, roof.height)
    ends = shape.ends(u0, u1, (v1 - v0) / 2, roof.height)
    planes = _profile_planes(across, profile)
    if not ends:  # one plane per strip across the ridge
        cuts = [v for v, _ in profile]
        cuts[0], cuts[-1] = v0 - 1.0, v1 + 1.0
        strips = [
            np.outer([a, b, b, a], across) + np.outer([u0 - 1.0, u0 - 1.0, u1 + 1.0, u1 + 1.0], along)
            for a, b in zip(cuts[:-1], cuts[1:])
        ]
        return plane_roof(polygon, top, np.asarray(planes), strips)
    for end in ends:
        planes += _profile_planes(along, end)
    return plane_roof(polygon, top, np.asarray(planes))


def _pointed(polygon: shapely.Polygon, top: float, roof: Roof, shape: Pointed) -> tuple[Triangles, Triangles]:
    """Pyramids, cones, domes and onions: the outline shrunk toward its centre ring by ring along a
    profile of (scale, height fraction) points; all but pyramids shaded smooth."""
    profile = np.asarray(shape.profile)
    ring = np.asarray(polygon.exterior.coords)
    centre = np.asarray(polygon.centroid.coords)[0]
    if not polygon.contains(shapely.Point(centre)):
        centre = np.asarray(polygon.representative_point().coords)[0]
    flat_grid = centre + (ring[None] - centre) * profile[:, 0, None, None]  # (rings, points + 1, 2)
    grid = np.stack(
        [
            flat_grid[..., 0],
            np.broadcast_to(top + roof.height * profile[:, 1, None], flat_grid.shape[:2]),
            flat_grid[..., 1],
        ],
        axis=2,
    )
    a0, b0, a1, b1 = grid[:-1, :-1], grid[:-1, 1:], grid[1:, :-1], grid[1:, 1:]
    first, second = np.cross(b1 - a0, b0 - a0), np.cross(a1 - a0, b1 - a0)  # area-weighted, outward
    if not shape.smooth:
        n0 = n1 = n2 = first
        m0 = m1 = m2 = second
    else:  # smooth up the profile, and around the ring where the outline turns gently
        quad = first + second  # (rings - 1, points)
        rows = np.zeros((len(grid), quad.shape[1], 3))
        rows[:-1] += quad
        rows[1:] += quad
        edge = np.diff(ring, axis=0)
        edge /= np.maximum(np.linalg.norm(edge, axis=1, keepdims=True), 1e-12)
        gentle = (np.einsum("ij,ij->i", edge, np.roll(edge, 1, axis=0)) > SMOOTH_TURN)[None, :, None]
        left = rows + gentle * np.roll(rows, 1, axis=1)  # at each quad's first corner
        right = rows + np.roll(gentle, -1, axis=1) * np.roll(rows, -1, axis=1)  # at its second
        n0, n1, n2 = left[:-1], right[1:], right[:-1]
        m0, m1, m2 = left[:-1], left[1:], right[1:]
    tris = np.concatenate(
        [np.stack([a0, b1, b0], axis=2).reshape(-1, 3, 3), np.stack([a0, a1, b1], axis=2).reshape(-1, 3, 3)]
    )
    normals = np.concatenate(
        [np.stack([n0, n1, n2], axis=2).reshape(-1, 3, 3), np.stack([m0, m1, m2], axis=2).reshape(-1, 3, 3)]
    )
    area = np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)
    keep = area > 1e-9  # the quads that meet at the apex are triangles
    normals = normals[keep].reshape(-1, 3)
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
    return Triangles(tris[keep].reshape(-1, 3), normals), Triangles.empty()


def _skeleton_roof(
    polygon: shapely.Polygon, top: float, roof: Roof, shape: Ridged
) -> tuple[Triangles, Triangles] | None:
    """Hipped, gabled, mansard and gambrel roofs over any outline, courtyards included: each outline
    edge's face of the straight skeleton, its height a profile of the distance from the eaves that
    reaches `roof.height` at the top (mansard and gambrel faces are cut where the pitch changes, the
    offsets of the outline at the knee), with gable ends where a hip would close with a single
    triangle. None if CGAL fails."""
    tris = skeleton_triangles(polygon)
    if tris is None or not len(tris):
        return None
    edges = ring_edges(polygon)
    if shape.gable_ends:
        tris = _gable_ends(tris, edges)
    deepest = tris[:, :, 2].max()
    profile = np.array(shape.skeleton) * np.array([deepest, roof.height])
    if len(profile) > 2:
        tris = _cut_at(tris, profile[1:-1, 0])
    tris = tris.copy()
    tris[:, :, 2] = np.interp(tris[:, :, 2], profile[:, 0], profile[:, 1])
    positions = np.stack([tris[:, :, 0], top + tris[:, :, 2], tris[:, :, 1]], axis=2)
    normals = np.cross(positions[:, 1] - positions[:, 0], positions[:, 2] - positions[:, 0])
    length = np.linalg.norm(normals, axis=1)
    keep = length > EPS
    positions, normals = positions[keep], normals[keep] / length[keep, None]
    upright = np.abs(normals[:, 1]) < 1e-4
    flip = ~upright & (normals[:, 1] < 0)
    positions[flip], normals[flip] = positions[flip][:, ::-1], -normals[flip]
    roof_tris = Triangles(positions[~upright].reshape(-1, 3), np.repeat(normals[~upright], 3, axis=0))
    return roof_tris, _gable_walls(positions[upright], edges)


def _cut_at(tris: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """Triangles of (x, z, d) cut along the lines where d crosses `levels`, so that a profile with
    kinks at those levels maps each piece onto one plane."""
    bounds = np.concatenate([[-np.inf], levels, [np.inf]])
    out = []
    for tri in tris:
        low, high = tri[:, 2].min(), tri[:, 2].max()
        for lo, hi in zip(bounds[:-1], bounds[1:]):
            if hi <= low or lo >= high:
                continue
            piece = tri
            if lo > low:
                piece = _clip3(piece, lo, above=True)
            if hi < high:
                piece = _clip3(piece, hi, above=False)
            out += [np.stack([piece[0], piece[i], piece[i + 1]]) for i in range(1, len(piece) - 1)]
    return np.asarray(out).reshape(-1, 3, 3)


def _clip3(points: np.ndarray, level: float, above: bool) -> np.ndarray:
    """The part of a convex polygon of (x, z, d) points with d above (or below) `level`."""
    sign = 1.0 if above else -1.0
    value = sign * (points[:, 2] - level)
    out = []
    for i in range(len(points)):
        p, q, vp, vq = points[i], points[(i + 1) % len(points)], value[i], value[(i + 1) % len(points)]
        if vp >= 0:
            out.append(p)
        if (vp < 0) != (vq < 0):
            out.append(p + (q - p) * vp / (vp - vq))
    return np.asarray(out).reshape(-1, 3)


def _gable_walls(tris: np.ndarray, edges) -> Triangles:
    """Upright skeleton triangles as wall pieces of the outline edge each stands on, facing out."""
    if not len(tris):
        return Triangles.empty()
    a = np.array([e[0] for e in edges])
    b = np.array([e[1] for e in edges])
    length = np.linalg.norm(b - a, axis=1)
    e = (b - a) / length[:, None]
    ground = tris[:, :, [0, 2]][:, :, None, :] - a[None, None]  # (triangles, 3, edges, 2)
    offset = np.einsum("tvek,ek->tve", ground, np.stack([e[:, 1], -e[:, 0]], axis=1))
    along = np.einsum("tvek,ek->tve", ground, e)
    on = (np.abs(offset).max(axis=1) < 1e-3) & (along.min(axis=1) > -1e-3) & (along.max(axis=1) < length + 1e-3)
    found = on.any(axis=1)
    tri, edge = np.nonzero(found)[0], on.argmax(axis=1)[found]
    tris, along = tris[tri], along[tri, :, edge]
    normal = np.column_stack([e[edge, 1], np.zeros(len(edge)), -e[edge, 0]])
    inward = np.einsum("ij,ij->i", np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), normal) < 0
    tris[inward], along[inward] = tris[inward][:, ::-1], along[inward][:, ::-1]
    return Triangles(
        tris.reshape(-1, 3),
        np.repeat(normal, 3, axis=0),
        along.ravel(),
        np.repeat(length[edge], 3),
        piece=np.repeat(edge, 3),
    )


def _gable_ends(tris: np.ndarray, edges) -> np.ndarray:
    """A hipped skeleton turned gabled: where an outline edge's face is a single triangle (a hip's
    end), its top moves out over the edge's middle, so the face stands upright and the ridge runs on
    to the gable. Hips sharing their top with another end (pyramids) stay."""
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), EPS)
    keys = np.round(np.column_stack([normals, np.einsum("ij,ij->i", normals, tris[:, 0])]), 3)
    _, group, count = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    ground = tris[:, :, 2] < EPS
    ends = np.array([[a, b] for a, b in edges])  # (edges, 2 corners, 2)
    hip_ends = (count[group.ravel()] == 1) & (ground.sum(axis=1) == 2)  # alone on their plane, two corners down
    moves = []
    for tri, low in zip(tris[hip_ends], ground[hip_ends]):
        base = tri[low][:, :2]
        apart = np.minimum(np.abs(base - ends).max(axis=(1, 2)), np.abs(base - ends[:, ::-1]).max(axis=(1, 2)))
        apex = tri[~low][0]
        for a, b in ends[apart < 1e-3]:  # the outline edge the hip's end stands on
            moves.append((apex, np.array([(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, apex[2]])))
    if len(moves) >= len(edges) - 1:
        return tris
    tops = np.array([apex for apex, _ in moves]).reshape(-1, 3)
    tris = tris.copy()
    for apex, target in moves:
        if np.sum(np.all(np.abs(tops - apex) < 1e-6, axis=1)) == 1:
            tris[np.all(np.abs(tris - apex) < 1e-6, axis=2)] = target
    return tris


def _inward_faces(polygons: np.ndarray, low: np.ndarray, high: np.ndarray) -> tuple[np.ndarray, Triangles]:
    """(owner per row, rows): upright quads on every ring of each of `polygons` from its `low` to its
    `high` height, facing into the polygon, polygon after polygon."""
    oriented = shapely.orient_polygons(polygons)  # exterior counter-clockwise, holes clockwise
    rings, ring_owner = shapely.get_rings(oriented, return_index=True)
    coords, ring = shapely.get_coordinates(rings, return_index=True)
    counts = np.bincount(ring, minlength=len(rings))
    end = np.cumsum(counts)[ring]
    coords = coords[2 * end - counts[ring] - 1 - np.arange(len(coords))]  # each ring reversed: inward
    edge = ring[:-1] == ring[1:]  # a point and the next one on its ring
    a, b, owner = coords[:-1][edge], coords[1:][edge], ring_owner[ring[:-1][edge]]
    d = b - a
    keep = np.hypot(d[:, 0], d[:, 1]) > EPS
    a, b, d, owner = a[keep], b[keep], d[keep], owner[keep]
    normal = np.column_stack([d[:, 1], np.zeros(len(d)), -d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
    corners = np.stack([a, b, b, a], axis=1)[:, [0, 2, 1, 0, 3, 2]]  # counter-clockwise seen from the front
    heights = np.stack([low[owner], low[owner], high[owner], high[owner]], axis=1)[:, [0, 2, 1, 0, 3, 2]]
    positions = np.column_stack([corners[..., 0].ravel(), heights.ravel(), corners[..., 1].ravel()])
    return np.repeat(owner, 6), Triangles(positions, np.repeat(normal, 6, axis=0))


def triangulated(polygons: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(upward triangles (n, 3, 2) as polygon_triangles makes them, the polygon each covers) of
    all `polygons` in one triangulation call."""
    coords, which = shapely.get_coordinates(shapely.constrained_delaunay_triangles(polygons), return_index=True)
    tris, kept = upward(coords.reshape(-1, 4, 2)[:, :3])
    return tris, which[::4][kept]


def _flat_of(polygons: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, Triangles]:
    """(owner per row, rows) of `polygons` as horizontal surfaces facing up, each at its height y."""
    tris, owner = triangulated(polygons)
    return np.repeat(owner, 3), Triangles(*flat_rows(tris, y[owner]))


@dataclass
class ParapetRoofs:
    """Flat roofs inside parapets, many at once: every roof's rows (owner by owner, in the order
    _parapet_roof joins them) and the pieces of roof inside the rims, where rooftop units stand."""

    owner: np.ndarray  # per row: which of the given polygons
    rows: Triangles
    pieces: np.ndarray  # (m,) polygons
    piece_owner: np.ndarray  # (m,)


def parapet_roofs(polygons: np.ndarray, top: np.ndarray, parapet: np.ndarray) -> ParapetRoofs:
    """Flat roofs `parapet` metres below `top` inside a rim PARAPET_THICKNESS wide around each of
    `polygons`: the rim's top (its coping), the roof, the rim's inner faces; just the flat roof where
    no roof is left inside. Shapely's array functions over every outline at once."""
    inner = shapely.buffer(polygons, -PARAPET_THICKNESS, join_style="mitre")
    pieces, piece_owner = shapely.get_parts(inner, return_index=True)
    real = (shapely.get_type_id(pieces) == shapely.GeometryType.POLYGON) & ~shapely.is_empty(pieces)
    pieces, piece_owner = pieces[real], piece_owner[real]
    low = top - parapet
    rimmed = np.zeros(len(polygons), bool)
    rimmed[piece_owner] = True
    outer = polygons.copy()  # the rim, or the whole roof where none is left inside
    if len(pieces):
        inside = shapely.multipolygons(pieces, indices=np.cumsum(rimmed)[piece_owner] - 1)
        outer[rimmed] = shapely.difference(polygons[rimmed], inside)
    outer_owner, outer_rows = _flat_of(outer, top)
    roof_owner, roof = _flat_of(pieces, low[piece_owner])
    faces_owner, faces = _inward_faces(pieces, low[piece_owner], top[piece_owner])
    owner = np.concatenate([outer_owner, piece_owner[roof_owner], piece_owner[faces_owner]])
    order = np.argsort(owner, kind="stable")  # each roof's rows together, in the order above
    rows = Triangles.join([outer_rows, roof, faces])
    return ParapetRoofs(owner[order], Triangles(rows.positions[order], rows.normals[order]), pieces, piece_owner)


def _parapet_roof(polygon: shapely.Polygon, top: float, parapet: float) -> Triangles:
    """parapet_roofs of one outline."""
    return parapet_roofs(np.array([polygon]), np.array([top]), np.array([parapet])).rows


def width_across(outline: shapely.Polygon, direction: float) -> float:
    """The outline's extent along `direction` (radians from +x toward +z): across a ridge."""
    across = np.asarray(outline.exterior.coords) @ np.array([math.cos(direction), math.sin(direction)])
    return float(across.max() - across.min())


class RoofShape:
    """How one `roof:shape` is built over an outline (one class per kind of shape, one instance per
    shape in ROOF_SHAPE_TABLE), and how far it rises where the map gives no height."""

    def build(self, polygon: shapely.Polygon, top: float, roof: Roof) -> tuple[Triangles, Triangles]:
        raise NotImplementedError

    def run(self, outline: shapely.Polygon, direction: float) -> float:
        """The horizontal distance over which the roof rises to its top when its main face looks
        toward `direction`: half the width across the ridge, or the largest inscribed radius where
        a courtyard keeps the ridge from spanning the outline."""
        half = width_across(outline, direction) / 2
        if outline.interiors:
            return min(half, float(shapely.maximum_inscribed_circle(outline, 0.1).length))
        return half

    def default_rise(self, run: float, pitch: float) -> float:
        """The rise over `run` where no tag gives one, `pitch` degrees being the map's default."""
        return math.tan(math.radians(pitch)) * run

    def follows_skeleton(self, polygon: shapely.Polygon) -> bool:
        """Whether `build` starts from the outline's straight skeleton."""
        return False


class Flat(RoofShape):
    def build(self, polygon, top, roof):
        return (
            _parapet_roof(polygon, top, roof.parapet) if roof.parapet > 0 else flat(polygon, top)
        ), Triangles.empty()


@dataclass(frozen=True)
class Pointed(RoofShape):
    """The outline drawn in ring by ring to a point; flat over a courtyard."""

    profile: tuple  # (scale of the outline, share of the rise), eaves to apex
    smooth: bool = True
    # where no tag gives a height: the pitch in degrees (None: the map's), or a dome's rise over its radius
    pitch: float | None = None
    rise_over_radius: float | None = None

    def build(self, polygon, top, roof):
        return _pointed(polygon, top, roof, self) if not polygon.interiors else (flat(polygon, top), Triangles.empty())

    def run(self, outline, direction):
        x0, z0, x1, z1 = outline.bounds
        return min(x1 - x0, z1 - z0) / 2

    def default_rise(self, run, pitch):
        if self.rise_over_radius is not None:
            return self.rise_over_radius * run
        return super().default_rise(run, self.pitch if self.pitch is not None else pitch)


@dataclass(frozen=True)
class Ridged(RoofShape):
    """A ridge (or one slope) across the roof's direction. `skeleton`: the height profile over an
    outline's straight skeleton, (share of the largest distance from the eaves, share of the rise),
    for outlines the exact profiles do not fit; None: hipped's there. `gable_ends`: the skeleton's
    ends closed by gable walls."""

    skeleton: tuple | None = None
    gable_ends: bool = False

    def across(self, v0: float, v1: float, h: float) -> list[tuple[float, float]]:
        """(v, height) points of the profile across the ridge."""
        return [(v0, 0.0), (v0 + (v1 - v0) / 2, h), (v1, 0.0)]

    def ends(self, u0: float, u1: float, half: float, h: float) -> tuple:
        """(u, height) profiles of the two ends along the ridge; () for gable walls."""
        return ()

    def follows_skeleton(self, polygon):
        return bool(polygon.interiors) or (not exact_profile(polygon) and self.skeleton is not None)

    def build(self, polygon, top, roof):
        if self.follows_skeleton(polygon):
            mesh = _skeleton_roof(polygon, top, roof, self if self.skeleton is not None else ROOF_SHAPE_TABLE["hipped"])
            if mesh is not None:
                return mesh
        return _ridged(polygon, top, roof, self)


class Hipped(Ridged):
    def ends(self, u0, u1, half, h):
        return [(u0, 0.0), (u0 + half, h)], [(u1 - half, h), (u1, 0.0)]

    def run(self, outline, direction):  # the hips bound the rise from every side
        half = width_across(outline, direction) / 2
        return min(half, float(shapely.maximum_inscribed_circle(outline, 0.1).length))


class HalfHipped(Ridged):
    def ends(self, u0, u1, half, h):  # a gable wall up to the hip, the hip at the pitch of the sides
        low = (1.0 - HALF_HIP) * h
        return [(u0, low), (u0 + HALF_HIP * half, h)], [(u1 - HALF_HIP * half, h), (u1, low)]


class Skillion(Ridged):
    def across(self, v0, v1, h):
        return [(v0, h), (v1, 0.0)]

    def run(self, outline, direction):  # one slope over the whole width
        return width_across(outline, direction)


class Saltbox(Ridged):
    def across(self, v0, v1, h):  # a short steep back, a long front
        return [(v0, 0.0), (v0 + SALTBOX_RIDGE * (v1 - v0), h), (v1, 0.0)]


class Gambrel(Ridged):
    def across(self, v0, v1, h):
        half = (v1 - v0) / 2
        knee, mid = GAMBREL_KNEE * half, v0 + half
        return [(v0, 0.0), (v0 + knee, GAMBREL_RISE * h), (mid, h), (v1 - knee, GAMBREL_RISE * h), (v1, 0.0)]


class Mansard(Ridged):
    def across(self, v0, v1, h):
        half = (v1 - v0) / 2
        knee, mid, low = MANSARD_KNEE * half, v0 + half, MANSARD_RISE * h
        return [(v0, 0.0), (v0 + knee, low), (mid, h), (v1 - knee, low), (v1, 0.0)]

    def ends(self, u0, u1, half, h):
        knee, low = MANSARD_KNEE * half, MANSARD_RISE * h
        return [(u0, 0.0), (u0 + knee, low), (u0 + half, h)], [(u1 - half, h), (u1 - knee, low), (u1, 0.0)]


class Round(Ridged):
    def across(self, v0, v1, h):
        return _arc(v0, v1, h)


STRAIGHT = ((0.0, 0.0), (1.0, 1.0))
DOME_PROFILE = tuple(
    zip(np.cos(np.linspace(0.0, np.pi / 2, DOME_RINGS + 1)), np.sin(np.linspace(0.0, np.pi / 2, DOME_RINGS + 1)))
)
# a bulb wider than its drum, drawn in to a point
ONION_PROFILE = ((1.0, 0.0), (1.18, 0.1), (1.25, 0.22), (1.2, 0.34), (1.0, 0.46), (0.7, 0.58), (0.4, 0.7))
ONION_PROFILE += ((0.2, 0.8), (0.08, 0.9), (0.0, 1.0))
# every roof shape cityshade builds (maps.ROOF_SHAPES names them for the readers)
ROOF_SHAPE_TABLE: dict[str, RoofShape] = {
    "flat": Flat(),
    "gabled": Ridged(skeleton=STRAIGHT, gable_ends=True),
    "hipped": Hipped(skeleton=STRAIGHT),
    "half-hipped": HalfHipped(),
    "pyramidal": Pointed(((1.0, 0.0), (0.0, 1.0)), smooth=False, pitch=45.0),
    "skillion": Skillion(),
    "gambrel": Gambrel(skeleton=((0.0, 0.0), (GAMBREL_KNEE, GAMBREL_RISE), (1.0, 1.0)), gable_ends=True),
    "mansard": Mansard(skeleton=((0.0, 0.0), (MANSARD_KNEE, MANSARD_RISE), (1.0, 1.0))),
    "dome": Pointed(DOME_PROFILE, rise_over_radius=1.0),
    "onion": Pointed(ONION_PROFILE, rise_over_radius=1.6),
    "round": Round(),
    "cone": Pointed(((1.0, 0.0), (0.0, 1.0)), pitch=60.0),
    "saltbox": Saltbox(),
}


def roof_triangles(polygon: shapely.Polygon, top: float, roof: Roof) -> tuple[Triangles, Triangles]:
    """(roof surfaces, wall pieces between the walls' top and the roof) over `polygon` at `top`.

    Ridged shapes over outlines that fill their bounding rectangle use the exact profiles; hipped,
    gabled, mansard and gambrel roofs over other outlines, and any ridged roof over a courtyard
    (hipped where the shape has no skeleton form), follow the straight skeleton; other ridged shapes
    span the outline's extent across the ridge. Pointed shapes over a courtyard are flat."""
    return _shape_of(roof).build(polygon, top, roof)


def follows_skeleton(polygon: shapely.Polygon, roof: Roof) -> bool:
    """Whether roof_triangles builds `roof` over `polygon` from the outline's straight skeleton."""
    return _shape_of(roof).follows_skeleton(polygon)


def _shape_of(roof: Roof) -> RoofShape:
    return ROOF_SHAPE_TABLE["flat" if roof.height <= 0 else roof.shape]
