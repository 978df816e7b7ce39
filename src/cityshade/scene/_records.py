"""The per-building record uploaded as a std430 SSBO; mirrors shaders/common/buildings.glsl, whose
shape and flag codes come from here (cityshade.shader_constants)."""

from __future__ import annotations

import numpy as np

from ._doors import MAX_DOORS

SHAPE_PRISM, SHAPE_CYLINDER, SHAPE_DOME = 0, 1, 2
SHAPES = {"prism": SHAPE_PRISM, "cylinder": SHAPE_CYLINDER, "dome": SHAPE_DOME}

FLAG_FURNITURE = 1
FLAG_CURTAINS = 2
FLAG_ROOM_VARIATION = 4
FLAG_NO_INTERIOR = 8  # no rooms behind the glass: dark panes (sheds, garages, saunas)
FLAG_SHOP_FRONT = 16  # shops on the ground floor: its rooms are lit in opening hours (scene/_uses.py)

# for the shaders (cityshade.shader_constants)
SHAPE_CODES = {f"SHAPE_{name.upper()}": code for name, code in SHAPES.items()}
FLAGS = {
    "FLAG_FURNITURE": FLAG_FURNITURE,
    "FLAG_CURTAINS": FLAG_CURTAINS,
    "FLAG_ROOM_VARIATION": FLAG_ROOM_VARIATION,
    "FLAG_NO_INTERIOR": FLAG_NO_INTERIOR,
    "FLAG_SHOP_FRONT": FLAG_SHOP_FRONT,
}

BUILDING_DTYPE = np.dtype(
    [
        ("origin_yaw", "<f4", 4),
        ("room", "<f4", 4),
        ("extent", "<f4", 4),
        ("ids", "<i4", 4),
        (
            "facade",
            "<i4",
            4,
        ),  # x: technique (0 window bay, 1 grammar, 2 relief), y: grammar start rule, zw: grammar seed
        ("tint", "<f4", 4),  # rgb: linear facade tint; w: 1 if tinted (tagged colour or material), 0: the style's own
        ("roof", "<f4", 4),  # rgb: linear roof colour; w: roof material id (ROOF_* in shaders/city/roof.glsl)
        ("doors", "<f4", (MAX_DOORS, 4)),  # per door: x, z on the outline, outward normal x, z (zero: none); _doors.py
    ]
)
assert BUILDING_DTYPE.itemsize % 16 == 0


def rotation_y(yaw: float) -> np.ndarray:
    """Object-to-world rotation about +y; the same matrix as building_rotation() in GLSL."""
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
