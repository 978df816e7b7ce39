"""Dormers on gabled and hipped roofs with rooms in them (Roof.attic_storey): boxes standing out of
the two long slopes, evenly spaced along the eaves, one per DORMER_SPACING metres. Each is a closed
solid: its front a wall piece (with the window of the storey behind it, like a gable), its cheeks
sheet metal, its top flat or a small gable in the roof's material; its back and bottom lie inside the
roof. Only roofs over outlines that take the exact ridged profiles (_roofs.exact_profile) get them."""

from __future__ import annotations

import numpy as np
import shapely

from ._materials import ROOF_PART_SHEET, ROOF_PART_SURFACE
from ._roofs import Roof, Triangles, exact_profile, ridge_frame

DORMER_SHAPES = ("gabled", "hipped")
DORMER_WIDTH = 2.0  # metres along the eaves
DORMER_SPACING = 4.5  # metres of eaves per dormer
DORMER_SETBACK = 0.4  # metres from the eaves to the dormer's front
DORMER_TOP = 0.9  # the front's height: this share of the storey (the window's lintel is at 0.82)...
DORMER_ROOM = 0.8  # ...at most this share of the roof's rise
DORMER_PITCH = np.tan(np.radians(35.0))  # of a gabled dormer's own roof
END_MARGIN = 0.8  # metres between a dormer and a gable wall
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


def dormers(polygon: shapely.Polygon, top: float, roof: Roof) -> tuple[Triangles, Triangles]:
    """(roof triangles, wall triangles) of the dormers of `roof` over `polygon` at the walls' `top`:
    none where the roof has no rooms, is not gabled or hipped, or has too little rise for a window."""
    if roof.attic_storey <= 0 or roof.shape not in DORMER_SHAPES or not exact_profile(polygon):
        return Triangles.empty(), Triangles.empty()
    across, along, (v0, v1), (u0, u1) = ridge_frame(polygon, roof.direction)
    half = (v1 - v0) / 2
    slope = roof.height / half  # metres of rise per metre in from the eaves
    high = min(DORMER_TOP * roof.attic_storey, DORMER_ROOM * roof.height)
    if high < MIN_STOREY * roof.attic_storey or high < slope * DORMER_SETBACK + 1.0:
        return Triangles.empty(), Triangles.empty()
    rise = DORMER_PITCH * DORMER_WIDTH / 2
    gabled = roof.seed % 2 == 0 and high + rise <= DORMER_ROOM * roof.height
    apex = high + rise if gabled else high
    back = apex / slope + 0.2  # where the dormer's top has sunk into the roof
    margin = back + END_MARGIN if roof.shape == "hipped" else END_MARGIN  # a hip closes in on the slope's ends
    usable = (u1 - u0) - 2 * margin
    count = int(usable // DORMER_SPACING)
    if count < 1 or back >= half:
        return Triangles.empty(), Triangles.empty()
    spots = u0 + margin + (np.arange(count) + 0.5) * usable / count
    corners = _corners(DORMER_WIDTH, DORMER_SETBACK, back, high, apex)
    front_faces = FRONT + (FRONT_GABLE if gabled else [])
    hidden = HIDDEN + (BACK_GABLE if gabled else [])
    tops = GABLED_TOP if gabled else FLAT_TOP
    part = np.repeat(
        [ROOF_PART_SURFACE] * len(hidden) + [ROOF_PART_SHEET] * len(CHEEKS) + [ROOF_PART_SURFACE] * len(tops), 3
    )
    along_front = np.array([[corners[c][0] for c in face] for face in front_faces]).ravel() + DORMER_WIDTH / 2
    w, f = DORMER_WIDTH / 2, DORMER_SETBACK
    plan = np.array([(-w, f), (w, f), (w, back), (-w, back)])  # the dormer seen from above
    fronts, surfaces = [], []
    for eaves, e_u, e_v in ((v0, -along, across), (v1, along, -across)):  # the frame turned, not mirrored
        centres = np.outer(spots, along) + eaves * across
        footprints = shapely.polygons(centres[:, None] + plan[None, :, :1] * e_u + plan[None, :, 1:] * e_v)
        centres = centres[shapely.contains(polygon, footprints)]  # outlines that are not quite rectangles
        if not len(centres):
            continue
        front = _solid(corners, front_faces, centres, e_u, e_v, top)
        front.along = np.tile(along_front, len(centres))
        front.edge_length = np.full(len(front.positions), DORMER_WIDTH)
        fronts.append(front)
        solid = _solid(corners, hidden + CHEEKS + tops, centres, e_u, e_v, top)
        solid.part = np.tile(part, len(centres)).astype(np.int64)
        surfaces.append(solid)
    return Triangles.join(surfaces), Triangles.join(fronts)
