"""What is drawn: cameras, building masses, city layouts and their meshes. No GL here."""

from ._buildings import SHAPES, BuildingMass, box, cylinder, dome
from ._camera import Camera, look_at, perspective
from ._city import (CITIES, GROUND_ASPHALT, GROUND_BALLAST, GROUND_BULB, GROUND_GRASS, GROUND_LAND, GROUND_MARKING,
                    GROUND_MATERIALS, GROUND_PAVEMENT, GROUND_POST, GROUND_RAIL, GROUND_SAND, GROUND_WATER,
                    MAP_GROUND_MATERIALS, City, default_city, grid_city, make_city)
from ._footprints import load_footprints
from ._materials import ROOF_PATTERNS
from ._batch import batch
from ._meshes import SURFACE_CODES, SURFACE_PLAIN_WALL, SURFACE_ROOF, SURFACE_WALL, VERTEX_ATTRIBUTES, VERTEX_DTYPE, VERTEX_FORMAT, building_record, building_vertices
from ._paths import PATHS, camera_path
from ._wall_faces import CORNER_TURN, WallFaces, storeys, wall_faces
from ._raycast import intersect
from ._roofs import Roof
from ._records import (BUILDING_DTYPE, FLAG_CURTAINS, FLAG_FURNITURE, FLAG_ROOM_VARIATION, FLAGS, SHAPE_CODES,
                       rotation_y)
from ._doors import DOOR_CONSTANTS, DOOR_HEIGHT, DOOR_WIDTH, MAX_DOORS, door_hit, door_on_edge
from ._uses import LIT_SCHEDULE, USE_CODES, USE_COUNT, USES, lit_share, lit_shares

__all__ = [
    "SHAPES", "BuildingMass", "box", "cylinder", "dome", "Camera", "look_at", "perspective", "CITIES", "City",
    "default_city", "grid_city", "make_city", "load_footprints", "VERTEX_ATTRIBUTES", "VERTEX_DTYPE", "VERTEX_FORMAT",
    "batch", "building_record", "building_vertices", "BUILDING_DTYPE", "rotation_y", "PATHS", "camera_path",
    "intersect", "SURFACE_ROOF", "SURFACE_PLAIN_WALL", "SURFACE_WALL", "GROUND_ASPHALT", "GROUND_GRASS", "GROUND_PAVEMENT", "FLAG_CURTAINS", "FLAG_FURNITURE",
    "FLAG_ROOM_VARIATION", "FLAGS", "SHAPE_CODES", "SURFACE_CODES", "GROUND_MATERIALS", "MAP_GROUND_MATERIALS", "Roof", "GROUND_BALLAST", "GROUND_BULB", "GROUND_LAND",
    "GROUND_MARKING", "GROUND_POST", "GROUND_RAIL", "GROUND_SAND", "GROUND_WATER", "ROOF_PATTERNS", "CORNER_TURN",
    "WallFaces", "storeys", "wall_faces",
    "DOOR_CONSTANTS", "DOOR_HEIGHT", "DOOR_WIDTH", "MAX_DOORS", "door_hit", "door_on_edge", "LIT_SCHEDULE", "USE_CODES", "USE_COUNT", "USES", "lit_share", "lit_shares",
]
