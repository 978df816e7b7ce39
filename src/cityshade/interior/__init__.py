"""Interior mapping (van Dongen 2008): parameters, the numpy twin of the shader, and the
polygonised-interiors baseline, its geometry and its passes of the frame."""

from ._faces import FACE_CODES, FACE_NAMES, room_state
from ._hash import pcg_hash
from ._polygonised import LAYERS as POLYGONISED_LAYERS
from ._polygonised import polygonised_vertices, quad_counts, room_grid
from ._polygonised_pass import ROOM_TEXTURES, PolygonisedGPU, room_passes
from ._reference import GrammarFacades, InteriorParams, find_room, reference_ids, reference_surfaces, room_id, trace
from ._solids import cast_masses
from ._windows import WindowCount, windows_straddling_rooms

__all__ = [
    "ROOM_TEXTURES",
    "PolygonisedGPU",
    "room_passes",
    "GrammarFacades",
    "FACE_CODES",
    "FACE_NAMES",
    "InteriorParams",
    "POLYGONISED_LAYERS",
    "cast_masses",
    "find_room",
    "pcg_hash",
    "polygonised_vertices",
    "quad_counts",
    "reference_ids",
    "reference_surfaces",
    "room_grid",
    "room_id",
    "room_state",
    "trace",
    "WindowCount",
    "windows_straddling_rooms",
]
