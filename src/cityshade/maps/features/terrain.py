"""The relief a DEM gives the map (--terrain, terrain/): its mesh as a layer of open ground under
every other surface, finest under the data (terrain/_mesh.py), BASE_DEPTH below the surfaces draped
on it so they never share a depth."""

from __future__ import annotations

import numpy as np

from ...scene import GROUND_TERRAIN, Layer
from ...terrain import terrain_mesh
from .._model import to_scene
from ._feature import Built, Feature
from .land import BASE_DEPTH

FOCUS_MARGIN = 60.0  # metres around the data drawn at the finest level


class Relief(Feature):
    name = "terrain"

    def summary(self, data):
        if data.terrain is None:
            return {}
        low, high = data.terrain.relief()
        rows, columns = data.terrain.shape
        return {"terrain": {"samples": [rows, columns], "spacing_m": round(data.terrain.spacing, 2),
                            "lowest_m": round(low, 2), "highest_m": round(high, 2)}}  # fmt: skip

    def build(self, data):
        if data.terrain is None:
            return Built(Layer(self.name))
        west, south, east, north = data.bounds()
        focus = (west - FOCUS_MARGIN, south - FOCUS_MARGIN, east + FOCUS_MARGIN, north + FOCUS_MARGIN)
        points = terrain_mesh(data.terrain, focus)
        ground = np.empty((len(points), 4), np.float32)
        ground[:, [0, 2]] = to_scene(points[:, :2])
        ground[:, 1] = points[:, 2] - BASE_DEPTH
        ground[:, 3] = GROUND_TERRAIN
        return Built(Layer(self.name, ground))
