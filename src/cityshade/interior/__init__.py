"""Interior mapping (van Dongen 2008): parameters and the numpy twin of the shader."""

from ._faces import FACE_NAMES
from ._reference import InteriorParams, find_room, reference_ids, room_id, trace

__all__ = ["FACE_NAMES", "InteriorParams", "find_room", "reference_ids", "room_id", "trace"]
