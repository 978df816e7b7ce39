"""Platforms of railway, tram and bus stops mapped as areas (`railway=platform`,
`public_transport=platform` polygons): a ground class of light concrete kerb-to-kerb slabs, claimed
above the ballast beside them and below the carriageway (PLATFORM_RANK), labelled pavement in
datasets (scene.GROUND_TABLE)."""

from __future__ import annotations

import shapely

from ...scene import GROUND_PLATFORM, Layer
from .._ground import union_of
from ._feature import Built, Feature, Surface

AREA_TAGS = {("railway", "platform"): "platform", ("public_transport", "platform"): "platform"}
PLATFORM_RANK = 15  # after carriageways (10), before ballast (20) and pavements (30)


class Platforms(Feature):
    name = "platforms"
    area_tags = AREA_TAGS

    def summary(self, data):
        platforms = [a.polygon for a in data.areas if a.kind == "platform"]
        return {"platforms": len(platforms), "platform_m2": round(shapely.union_all(platforms).area, 1)}

    def build(self, data):
        platforms = union_of([a.polygon for a in data.areas if a.kind == "platform"])
        return Built(Layer(self.name), [Surface(platforms, GROUND_PLATFORM, PLATFORM_RANK)])
