"""What is drawn: cameras, building masses, city layouts and their meshes. No GL here."""

from ._buildings import BuildingMass, box, cylinder, dome
from ._camera import Camera, look_at, perspective
from ._city import CITIES, GROUND_ASPHALT, GROUND_GRASS, GROUND_PAVEMENT, City, default_city, grid_city, make_city
from ._footprints import load_footprints
from ._meshes import VERTEX_ATTRIBUTES, VERTEX_DTYPE, VERTEX_FORMAT, batch, building_record, building_vertices
from ._records import BUILDING_DTYPE, rotation_y
from ._roofs import Roof

__all__ = [
    "BuildingMass", "box", "cylinder", "dome", "Camera", "look_at", "perspective", "CITIES", "City",
    "GROUND_ASPHALT", "GROUND_GRASS", "GROUND_PAVEMENT",
    "default_city", "grid_city", "make_city", "load_footprints", "VERTEX_ATTRIBUTES", "VERTEX_DTYPE", "VERTEX_FORMAT",
    "batch", "building_record", "building_vertices", "BUILDING_DTYPE", "rotation_y", "Roof",
]
