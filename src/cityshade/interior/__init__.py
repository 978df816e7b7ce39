"""Interior mapping (van Dongen 2008): parameters, the numpy twin of the shader, and the
polygonised-interiors baseline geometry."""

from ._faces import FACE_CODES, FACE_NAMES
from ._polygonised import LAYERS as POLYGONISED_LAYERS, polygonised_vertices, quad_counts, room_grid
from ._reference import InteriorParams, find_room, reference_ids, reference_pixels, room_id, trace

__all__ = ["FACE_CODES", "FACE_NAMES", "InteriorParams", "POLYGONISED_LAYERS", "find_room", "polygonised_vertices",
           "quad_counts", "reference_ids", "reference_pixels", "room_grid", "room_id", "trace"]
