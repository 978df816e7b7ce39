"""Platforms, a map feature added as one module (maps/features/platforms.py): read from a hand-made
station, counted by `info`, drawn as their own ground class and labelled in datasets."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely

from cityshade.commands.info import summary
from cityshade.dataset.testing import GROUND_CLASSES
from cityshade.maps import guess_missing, load_map, map_city
from cityshade.scene import GROUND_BALLAST, GROUND_PLATFORM

STATION = Path(__file__).parents[1] / "data" / "maps" / "platforms.osm"


def test_platform_areas_are_read_and_counted_but_not_highway_platforms():
    info = summary(guess_missing(load_map(STATION)))
    assert info["platforms"] == 2 and abs(info["platform_m2"] - 450.0) < 5.0


def test_platforms_are_a_ground_class_of_their_own_labelled_pavement():
    city = map_city(load_map(STATION))
    layer = next(layer for layer in city.layers if layer.name == "platforms")
    tris = layer.ground.reshape(-1, 3, 4)
    assert len(tris) and (tris[:, :, 3] == GROUND_PLATFORM).all() and np.allclose(tris[:, :, 1], 0.0)
    slabs = [shapely.Polygon(t[:, [0, 2]]) for t in tris]
    assert abs(sum(s.area for s in slabs) - 450.0) < 5.0
    ground = city.ground_mesh.reshape(-1, 3, 4)
    ballast = shapely.union_all([shapely.Polygon(t[:, [0, 2]]) for t in ground if t[0, 3] == GROUND_BALLAST])
    assert shapely.union_all(slabs).intersection(ballast).area < 1e-6  # cut, not drawn over each other
    assert GROUND_CLASSES[GROUND_PLATFORM] == "pavement"
