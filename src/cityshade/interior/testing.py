"""What the tests use of cityshade.interior's internals: its numpy twins and the parts they check one by one."""

from ._faces import (
    FACE_CEILING,
    FACE_CURTAIN,
    FACE_EXTERIOR,
    FACE_FLOOR,
    FACE_FURNITURE,
    FACE_ROOF,
    FACE_WALL_X,
    FACE_WALL_Z,
)
from ._reference import face_frame
from ._solids import object_to_world

__all__ = [
    "FACE_CEILING",
    "FACE_CURTAIN",
    "FACE_EXTERIOR",
    "FACE_FLOOR",
    "FACE_FURNITURE",
    "FACE_ROOF",
    "FACE_WALL_X",
    "FACE_WALL_Z",
    "face_frame",
    "object_to_world",
]
