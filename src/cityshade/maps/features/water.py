"""Water (`natural=water`, `waterway=riverbank`, `landuse=reservoir|basin`, `leisure=swimming_pool`
polygons, and the sea the coastline leaves, maps/_assemble.py): one ground class that reflects the
sky (shaders/city/map_ground.glsl)."""

from __future__ import annotations

import shapely

from ...scene import GROUND_WATER, Layer
from .._ground import union_of
from ._feature import Built, Feature, Surface

AREA_TAGS = {
    ("natural", "water"): "water",
    ("waterway", "riverbank"): "water",
    ("landuse", "reservoir"): "water",
    ("landuse", "basin"): "water",
    ("leisure", "swimming_pool"): "water",
}
WATER_RANK = 40  # under the roads and their pavements, over paved squares and green


class Water(Feature):
    name = "water"
    area_tags = AREA_TAGS

    def wants_line(self, tags):
        return tags.get("natural") == "coastline"  # the sea's edge (maps/_assemble.py)

    def summary(self, data):
        return {"water_m2": round(shapely.union_all([a.polygon for a in data.areas if a.kind == "water"]).area, 1)}

    def build(self, data):
        water = union_of([a.polygon for a in data.areas if a.kind == "water"])
        return Built(Layer(self.name), [Surface(water, GROUND_WATER, WATER_RANK)])
