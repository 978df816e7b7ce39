"""The constants that Python and GLSL share - face codes, building shapes and flags, surfaces,
ground materials, facade techniques, grammar labels, relief materials and faces - each defined once,
in Python, and emitted as the generated include that every program gets (`#define NAME value`).
A shader that defines one of these names itself fails tests/gl/test_constants.py."""

from __future__ import annotations

from .assets import LABELS
from .gl import declare_constants
from .grammar import FACADE_GRAMMAR
from .interior import FACE_CODES
from .relief import FACADE_RELIEF, GLASS, MATERIALS, RELIEF_FACE_CODES
from .scene import (
    DOOR_CONSTANTS,
    FACE_TABLE_CONSTANTS,
    FLAGS,
    GROUND_MATERIALS,
    LEVEL_CODES,
    MAP_GROUND_MATERIALS,
    ROOF_PARTS,
    ROOF_PATTERNS,
    SHAPE_CODES,
    SURFACE_CODES,
    TINT_GAIN,
    USE_CODES,
)

CONSTANTS: dict[str, int | str] = {
    **FACE_CODES,  # id AOV faces: FACE_NONE ... FACE_GROUND, FACE_TRUNK, FACE_FOLIAGE
    **SHAPE_CODES,  # SHAPE_PRISM, SHAPE_CYLINDER, SHAPE_DOME
    **FLAGS,  # FLAG_FURNITURE, FLAG_CURTAINS, FLAG_ROOM_VARIATION, FLAG_NO_INTERIOR
    **USE_CODES,  # USE_MIXED ... USE_PUBLIC, USE_COUNT, and where the use sits in the flags (USE_SHIFT, USE_MASK)
    **LEVEL_CODES,  # where a mass's first level sits in the flags (LEVEL_SHIFT, LEVEL_MASK): scene/_face_levels.py
    **SURFACE_CODES,  # SURFACE_WALL, SURFACE_ROOF, SURFACE_PLAIN_WALL, SURFACE_DORMER
    "TINT_GAIN": f"{TINT_GAIN:.1f}",  # building_tint's gain (common/facade.glsl)
    **GROUND_MATERIALS,  # GROUND_ASPHALT, GROUND_PAVEMENT, GROUND_GRASS
    **MAP_GROUND_MATERIALS,  # GROUND_WATER ... GROUND_BULB: maps' water, paint, tracks, lamps
    **ROOF_PATTERNS,  # ROOF_PLAIN ... ROOF_WOOD: roof.glsl's patterns
    **ROOF_PARTS,  # ROOF_PART_SURFACE, ROOF_PART_SHEET and the sheet metal's colour
    "FACADE_GRAMMAR": FACADE_GRAMMAR,
    "FACADE_RELIEF": FACADE_RELIEF,
    "GRAMMAR_WALL_LABEL": LABELS.index("wall"),
    "GRAMMAR_ROOM_LABEL": LABELS.index("room"),
    "GRAMMAR_DOOR_LABEL": LABELS.index("door"),
    "GRAMMAR_WINDOW_LABEL": LABELS.index("window"),
    **FACE_TABLE_CONSTANTS,  # FACE_WORDS: the buildings' face table (scene/_face_table.py)
    **DOOR_CONSTANTS,  # DOOR_WIDTH, DOOR_HEIGHT, DOOR_PLANE, DOOR_FACING, MAX_DOORS: scene/_doors.py
    "RELIEF_GLASS": f"{GLASS}u",  # compared with the uint materials of the relief maps
    "RELIEF_FRAME": f"{MATERIALS.index('frame')}u",
    "RELIEF_WALL": f"{MATERIALS.index('wall')}u",
    **RELIEF_FACE_CODES,  # FACE_FRONT, FACE_NEG_X, FACE_POS_X, FACE_NEG_Y, FACE_POS_Y
}

declare_constants("constants", CONSTANTS)
