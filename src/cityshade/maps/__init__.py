"""Real cities from map data (OpenStreetMap, GeoJSON, CityJSON) as one model in local metres."""

from ._model import (
    AREA_KINDS, BUILDING_ATTRIBUTES, ROOF_SHAPES, TREE_ATTRIBUTES, Area, Lamp, MapBuilding, MapData, MapTree,
    Railway, ReadReport, Road, to_scene,
)
from ._guess import guess_missing
from ._load import load_map

__all__ = [
    "AREA_KINDS", "BUILDING_ATTRIBUTES", "ROOF_SHAPES", "TREE_ATTRIBUTES", "Area", "Lamp", "MapBuilding", "MapData",
    "MapTree", "Railway", "ReadReport", "Road", "guess_missing", "load_map", "to_scene",
]
