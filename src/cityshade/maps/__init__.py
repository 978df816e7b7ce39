"""Real cities from map data (OpenStreetMap, GeoJSON, CityJSON) as one model in local metres."""

from ._cameras import (
    STREET_VIEWS,
    aerial_camera,
    framed_area,
    spot_camera,
    street_camera,
    street_choice,
    street_segment,
)
from ._doors import on_ground
from ._guess import guess_missing
from ._learn import PRIOR_FILE, Prior, load_prior, prior_city
from ._load import load_map
from ._masses import building_masses, facade_style
from ._model import (
    AREA_KINDS,
    BUILDING_ATTRIBUTES,
    ROOF_SHAPES,
    TREE_ATTRIBUTES,
    Area,
    Lamp,
    MapBuilding,
    MapData,
    MapTree,
    Railway,
    ReadReport,
    Road,
    to_scene,
)
from ._open import city_from_map
from ._prior import hide_sizes, prior_bytes, train_prior
from ._scene import city_from_guessed, map_city
from ._sun import require_map_for_date, sky_clock, sky_settings, sun_and_moon
from ._tiling import measure_load, tiled_extract
from .features import FEATURES
from .features.streets import MAIN_ROADS, ROAD_LINKS

__all__ = [
    "FEATURES",
    "on_ground",
    "MAIN_ROADS",
    "ROAD_LINKS",
    "AREA_KINDS",
    "BUILDING_ATTRIBUTES",
    "ROOF_SHAPES",
    "TREE_ATTRIBUTES",
    "Area",
    "Lamp",
    "MapBuilding",
    "MapData",
    "MapTree",
    "Railway",
    "ReadReport",
    "Road",
    "building_masses",
    "facade_style",
    "guess_missing",
    "PRIOR_FILE",
    "Prior",
    "load_prior",
    "prior_city",
    "hide_sizes",
    "prior_bytes",
    "train_prior",
    "load_map",
    "to_scene",
    "measure_load",
    "tiled_extract",
    "aerial_camera",
    "spot_camera",
    "street_camera",
    "street_segment",
    "street_choice",
    "framed_area",
    "STREET_VIEWS",
    "city_from_map",
    "map_city",
    "city_from_guessed",
    "sky_settings",
    "sky_clock",
    "sun_and_moon",
    "require_map_for_date",
]
