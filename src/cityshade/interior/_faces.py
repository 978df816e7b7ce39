"""Face codes of the id AOV, the shaders' FACE_* (through cityshade.shader_constants)."""

import numpy as np

FACE_NONE = 0
FACE_EXTERIOR = 1
FACE_CEILING = 2
FACE_FLOOR = 3
FACE_WALL_X = 4
FACE_WALL_Z = 5
FACE_FURNITURE = 6
FACE_CURTAIN = 7
FACE_ROOF = 8
FACE_GROUND = 9
FACE_TRUNK = 10  # tree trunks, branches and their silhouette fins
FACE_FOLIAGE = 11  # leaf cards and conifer fronds

FACE_NAMES = {
    FACE_NONE: "none",
    FACE_EXTERIOR: "exterior",
    FACE_CEILING: "ceiling",
    FACE_FLOOR: "floor",
    FACE_WALL_X: "wall x",
    FACE_WALL_Z: "wall z",
    FACE_FURNITURE: "furniture",
    FACE_CURTAIN: "curtain",
    FACE_ROOF: "roof",
    FACE_GROUND: "ground",
    FACE_TRUNK: "trunk",
    FACE_FOLIAGE: "foliage",
}

FACE_CODES = {f"FACE_{name.upper().replace(' ', '_')}": code for code, name in FACE_NAMES.items()}


def room_state(lit, variant):
    """The id AOV's fourth channel with ID_ROOM_STATE (building.glsl) where a room is seen:
    1 | lit << 1 | texture variant << 2 (0 where no room is seen)."""
    return 1 | (np.asarray(lit).astype(np.uint32) << 1) | (np.asarray(variant).astype(np.uint32) << 2)
