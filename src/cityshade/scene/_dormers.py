"""Dormers on gabled and hipped roofs with rooms in them (Roof.attic_storey) that have them
(Roof.dormers: where the map says so, or by the rule in maps/_roofs.py): boxes standing out of
the slopes that rise from the long eaves (outline and courtyards), evenly spaced, one per
DORMER_SPACING metres, kept where the slope's own face holds the whole dormer. Each is a closed
solid: its front a wall piece (with the window of the storey behind it, like a gable), its cheeks
sheet metal, its top flat or a small gable in the roof's material; its back and bottom lie inside
the roof."""

from __future__ import annotations

import numpy as np
import shapely

from ._materials import ROOF_PART_SHEET, ROOF_PART_SURFACE
from ._roofs import Roof, Triangles

DORMER_SHAPES = ("gabled", "hipped")
DORMER_WIDTH = 2.0  # metres along the eaves
DORMER_SPACING = 4.5  # metres of eaves per dormer
DORMER_SETBACK = 0.4  # metres from the eaves to the dormer's front
DORMER_TOP = 0.9  # the front's height: this share of the storey (the window's lintel is at 0.82)...
DORMER_ROOM = 0.8  # ...at most this share of the roof's rise
DORMER_PITCH = np.tan(np.radians(35.0))  # of a gabled dormer's own roof
END_MARGIN = 0.8  # metres between a dormer and the end of its eaves
LONG_SIDE = 0.6  # eaves at least this share of the longest edge's length carry dormers
MIN_SLOPE = 0.15  # metres of rise per metre in from the eaves: flatter (or a gable's edge) has none
PLANE_TOLERANCE = 0.02  # metres: the roof under a dormer is the plane rising from its eaves
MIN_STOREY = 0.6  # a front lower than this share of the storey would cut the window: no dormers

# a dormer's corners in its own frame: u along the eaves from its middle, y up from the walls' top,
# v in from the eaves; F/B front/back, L/R left/right (-u/+u), 0/1 bottom/top, A the gable's apex
FRONT = [("FL0", "FL1", "FR1"), ("FL0", "FR1", "FR0")]
FRONT_GABLE = [("FL1", "FA", "FR1")]
HIDDEN = [("BL0", "BR1", "BL1"), ("BL0", "BR0", "BR1"), ("FL0", "FR0", "BR0"), ("FL0", "BR0", "BL0")]
BACK_GABLE = [("BL1", "BR1", "BA")]
CHEEKS = [("FL0", "BL0", "BL1"), ("FL0", "BL1", "FL1"), ("FR0", "FR1", "BR1"), ("FR0", "BR1", "BR0")]
FLAT_TOP = [("FL1", "BL1", "BR1"), ("FL1", "BR1", "FR1")]
GABLED_TOP = [("FL1", "BL1", "BA"), ("FL1", "BA", "FA"), ("FR1", "FA", "BA"), ("FR1", "BA", "BR1")]


def _local(faces, back: np.ndarray, high: float, apex: float) -> np.ndarray:
    """(dormers, rows, 3) corners in each dormer's frame (u, y, v) of `faces`, for dormers whose
    backs stand `back` (n,) metres in from the eaves."""
    w, v_front = DORMER_WIDTH / 2, DORMER_SETBACK
    u = {"L": -w, "R": w, "A": 0.0}
    rows = [c for face in faces for c in face]
    y = np.array([apex if c[1] == "A" else high if c[2] == "1" else 0.0 for c in rows])
    local = np.zeros((len(back), len(rows), 3))
    local[..., 0] = [u[c[1]] for c in rows]
    local[..., 1] = y
    local[..., 2] = np.where([c[0] == "F" for c in rows], v_front, back[:, None])
    return local


def _solid(local: np.ndarray, centres: np.ndarray, e_u: np.ndarray, e_v: np.ndarray, top: float) -> Triangles:
    """Dormer faces given in their frames (local: (n, rows, 3) of u, y, v) at `centres` (n, 2,
    object x, z), u along e_u and v along e_v (n, 2; a rotation of the frame: windings kept),
    lifted to the walls' `top`."""
    plane = centres[:, None] + local[..., :1] * e_u[:, None] + local[..., 2:] * e_v[:, None]
    positions = np.stack([plane[..., 0], top + local[..., 1], plane[..., 1]], axis=2).reshape(-1, 3)
    tris = positions.reshape(-1, 3, 3)
    normals = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    return Triangles(positions, np.repeat(normals, 3, axis=0))


def upward(surface: Triangles) -> np.ndarray:
    """The triangles (n, 3, 3) of a roof surface that face up (the slopes, not walls or undersides)."""
    return surface.positions.reshape(-1, 3, 3)[surface.normals[::3, 1] > 0.05]


def roof_heights(tris: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Heights of the roof of upward triangles `tris` (n, 3, 3) over object-space (x, z) points
    (m, 2); -inf where no triangle covers a point."""
    a, b, c = (tris[:, k, [0, 2]] for k in range(3))
    e1, e2, p = b - a, c - a, points[:, None, :] - a[None]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (p[..., 0] * e2[:, 1] - p[..., 1] * e2[:, 0]) / det
        t = (e1[:, 0] * p[..., 1] - e1[:, 1] * p[..., 0]) / det
    inside = (s >= -1e-9) & (t >= -1e-9) & (s + t <= 1 + 1e-9) & (np.abs(det) > 1e-12)
    y = tris[:, 0, 1] + s * (tris[:, 1, 1] - tris[:, 0, 1]) + t * (tris[:, 2, 1] - tris[:, 0, 1])
    return np.where(inside, y, -np.inf).max(axis=1, initial=-np.inf)


def _eaves(polygon: shapely.Polygon) -> tuple[np.ndarray, np.ndarray]:
    """(starts, ends) of the outline's and courtyards' edges as long as LONG_SIDE of their ring's
    longest, each running with the roof on its left (shapely's orientation: exterior
    counter-clockwise)."""
    polygon = shapely.orient_polygons(polygon)
    starts, ends = [], []
    for ring in (polygon.exterior, *polygon.interiors):
        points = np.asarray(ring.coords)
        length = np.linalg.norm(points[1:] - points[:-1], axis=1)
        long = (length >= LONG_SIDE * length.max()) & (length >= DORMER_WIDTH + 2 * END_MARGIN)
        starts.append(points[:-1][long])
        ends.append(points[1:][long])
    return np.concatenate(starts), np.concatenate(ends)


def dormers(polygon: shapely.Polygon, top: float, roof: Roof, surface: Triangles) -> tuple[Triangles, Triangles]:
    """(roof triangles, wall triangles) of the dormers of `roof` over `polygon` at the walls' `top`,
    whose roof `surface` they stand out of: along every long eave where the roof rises from it, as
    many as fit in the face that rises from that eave (clear of hips, valleys and gables); none
    where the roof has no rooms or no dormers, is not gabled or hipped, or has too little rise."""
    if roof.attic_storey <= 0 or not roof.dormers or roof.shape not in DORMER_SHAPES:
        return Triangles.empty(), Triangles.empty()
    high = min(DORMER_TOP * roof.attic_storey, DORMER_ROOM * roof.height)
    if high < MIN_STOREY * roof.attic_storey:
        return Triangles.empty(), Triangles.empty()
    rise = DORMER_PITCH * DORMER_WIDTH / 2
    gabled = roof.seed % 2 == 0 and high + rise <= DORMER_ROOM * roof.height
    apex = high + rise if gabled else high
    tris = upward(surface)
    starts, ends = _eaves(polygon)
    length = np.linalg.norm(ends - starts, axis=1)
    along = (ends - starts) / length[:, None]
    inward = np.stack([-along[:, 1], along[:, 0]], axis=1)  # into the roof; (along, inward) keeps windings
    middle = (starts + ends) / 2
    samples = roof_heights(tris, np.concatenate([middle + 0.5 * inward, middle + 1.5 * inward]))
    slopes = samples[len(middle) :] - samples[: len(middle)]  # metres of rise per metre in from each eave
    count = ((length - 2 * END_MARGIN) // DORMER_SPACING).astype(np.int64)
    with np.errstate(invalid="ignore"):
        used = np.isfinite(slopes) & (slopes >= MIN_SLOPE) & (count >= 1) & (high >= slopes * DORMER_SETBACK + 1.0)
    if not used.any():
        return Triangles.empty(), Triangles.empty()
    edge = np.repeat(np.flatnonzero(used), count[used])  # each candidate dormer's eave
    rank = np.arange(len(edge)) - np.repeat(np.cumsum(count[used]) - count[used], count[used])
    spacing = (length[edge] - 2 * END_MARGIN) / count[edge]
    centres = starts[edge] + (END_MARGIN + (rank + 0.5) * spacing)[:, None] * along[edge]
    back = apex / slopes[edge] + 0.2  # where the dormer's top has sunk into the roof
    fits = _fitting(polygon, tris, centres, along[edge], inward[edge], back, slopes[edge], top)
    if not fits.any():
        return Triangles.empty(), Triangles.empty()
    centres, e_u, e_v, back = centres[fits], along[edge[fits]], inward[edge[fits]], back[fits]
    front_faces = FRONT + (FRONT_GABLE if gabled else [])
    front_local = _local(front_faces, back, high, apex)
    front = _solid(front_local, centres, e_u, e_v, top)
    front.along = front_local[..., 0].ravel() + DORMER_WIDTH / 2
    front.edge_length = np.full(len(front.positions), DORMER_WIDTH)
    front.piece = np.repeat(np.arange(len(centres)), front_local.shape[1])
    hidden = HIDDEN + (BACK_GABLE if gabled else [])
    tops = GABLED_TOP if gabled else FLAT_TOP
    solid = _solid(_local(hidden + CHEEKS + tops, back, high, apex), centres, e_u, e_v, top)
    part = [ROOF_PART_SURFACE] * len(hidden) + [ROOF_PART_SHEET] * len(CHEEKS) + [ROOF_PART_SURFACE] * len(tops)
    solid.part = np.tile(np.repeat(part, 3), len(centres)).astype(np.int64)
    return solid, front


def _fitting(polygon, tris: np.ndarray, centres, e_u, e_v, back, slope, top: float) -> np.ndarray:
    """Which dormers at `centres` on their eaves (frames e_u, e_v, depths `back`, slopes: one each)
    stand inside the outline on the one roof face that rises from their eaves at their slope (the
    roof there is that plane, nothing lower cuts in)."""
    u = np.tile([-1.0, 0.0, 1.0], 3) * DORMER_WIDTH / 2
    v = DORMER_SETBACK + np.repeat([0.0, 0.5, 1.0], 3)[None] * (back - DORMER_SETBACK)[:, None]  # (n, 9)
    points = centres[:, None] + u[None, :, None] * e_u[:, None] + v[..., None] * e_v[:, None]
    points = points.reshape(-1, 2)
    inside = shapely.contains_xy(polygon, points[:, 0], points[:, 1]).reshape(len(centres), -1).all(axis=1)
    heights = roof_heights(tris, points).reshape(len(centres), -1) - top
    return inside & np.all(np.abs(heights - slope[:, None] * v) <= PLANE_TOLERANCE, axis=1)
