"""Dormers on gabled and hipped roofs with rooms in them (Roof.attic_storey): boxes standing out of
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


def _corners(w: float, front: float, back: float, high: float, apex: float) -> dict[str, np.ndarray]:
    corners = {}
    for name, v in (("F", front), ("B", back)):
        for side, u in (("L", -w / 2), ("R", w / 2)):
            corners[f"{name}{side}0"] = np.array([u, 0.0, v])
            corners[f"{name}{side}1"] = np.array([u, high, v])
        corners[f"{name}A"] = np.array([0.0, apex, v])
    return corners


def _solid(corners, faces, centres: np.ndarray, e_u: np.ndarray, e_v: np.ndarray, top: float) -> Triangles:
    """The faces of one dormer (in its frame) at every centre (n, 2, object x, z), u along e_u and
    v along e_v (a rotation of the frame: windings kept), lifted to the walls' `top`."""
    local = np.array([[corners[c] for c in face] for face in faces]).reshape(-1, 3)  # (rows, u y v)
    plane = centres[:, None, :] + local[None, :, 0, None] * e_u + local[None, :, 2, None] * e_v
    positions = np.stack([plane[..., 0], np.broadcast_to(top + local[:, 1], plane.shape[:2]), plane[..., 1]], axis=2)
    positions = positions.reshape(-1, 3)
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
    where the roof has no rooms, is not gabled or hipped, or has too little rise for a window."""
    if roof.attic_storey <= 0 or roof.shape not in DORMER_SHAPES:
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
    fronts, surfaces = [], []
    for a, e_u, e_v, edge, slope in zip(starts, along, inward, length, slopes):
        count = int((edge - 2 * END_MARGIN) // DORMER_SPACING)
        if not np.isfinite(slope) or slope < MIN_SLOPE or count < 1 or high < slope * DORMER_SETBACK + 1.0:
            continue
        back = apex / slope + 0.2  # where the dormer's top has sunk into the roof
        centres = a + np.outer(END_MARGIN + (np.arange(count) + 0.5) * (edge - 2 * END_MARGIN) / count, e_u)
        centres = centres[_fitting(polygon, tris, centres, e_u, e_v, back, slope, top)]
        if not len(centres):
            continue
        corners = _corners(DORMER_WIDTH, DORMER_SETBACK, back, high, apex)
        front_faces = FRONT + (FRONT_GABLE if gabled else [])
        front = _solid(corners, front_faces, centres, e_u, e_v, top)
        along = np.array([[corners[c][0] for c in face] for face in front_faces]).ravel() + DORMER_WIDTH / 2
        front.along = np.tile(along, len(centres))
        front.edge_length = np.full(len(front.positions), DORMER_WIDTH)
        fronts.append(front)
        hidden = HIDDEN + (BACK_GABLE if gabled else [])
        tops = GABLED_TOP if gabled else FLAT_TOP
        solid = _solid(corners, hidden + CHEEKS + tops, centres, e_u, e_v, top)
        part = [ROOF_PART_SURFACE] * len(hidden) + [ROOF_PART_SHEET] * len(CHEEKS) + [ROOF_PART_SURFACE] * len(tops)
        solid.part = np.tile(np.repeat(part, 3), len(centres)).astype(np.int64)
        surfaces.append(solid)
    return Triangles.join(surfaces), Triangles.join(fronts)


def _fitting(polygon, tris: np.ndarray, centres, e_u, e_v, back: float, slope: float, top: float) -> np.ndarray:
    """Which dormers at `centres` on the eaves stand inside the outline on the one roof face that
    rises from those eaves at `slope` (the roof there is that plane, nothing lower cuts in)."""
    u = np.array([-1.0, 0.0, 1.0]) * DORMER_WIDTH / 2
    v = np.array([DORMER_SETBACK, (DORMER_SETBACK + back) / 2, back])
    uu, vv = (g.ravel() for g in np.meshgrid(u, v))
    points = (centres[:, None] + uu[:, None] * e_u + vv[:, None] * e_v).reshape(-1, 2)
    inside = shapely.contains_xy(polygon, points[:, 0], points[:, 1]).reshape(len(centres), -1).all(axis=1)
    heights = roof_heights(tris, points).reshape(len(centres), -1) - top
    return inside & np.all(np.abs(heights - slope * vv) <= PLANE_TOLERANCE, axis=1)
