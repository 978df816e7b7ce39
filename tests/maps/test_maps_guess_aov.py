"""`--aov guessed`: walls and roofs tinted by whether the map gave them or the guessing model did."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

from cityshade.api import render_city
from cityshade.interior import FACE_NAMES
from cityshade.maps import MapBuilding, MapData, map_city
from cityshade.render import guessed_aov
from cityshade.scene import BuildingMass

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

FACE = {name: code for code, name in FACE_NAMES.items()}
SQUARE = ((0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0))


def _mass(guessed):
    return BuildingMass("prism", (0.0, 0.0), SQUARE, 10.0, guessed=frozenset(guessed))


def test_tint_follows_face_and_building():
    masses = [_mass({"height", "levels", "roof_shape"}), _mass({"height"})]  # the second has tagged levels
    ids = np.zeros((2, 3, 4), np.uint32)
    ids[0, 0] = (FACE["exterior"], 0, 1, 0)  # guessed walls
    ids[0, 1] = (FACE["roof"], 0, 1, 0)  # guessed roof
    ids[0, 2] = (FACE["ceiling"], 3, 2, 0)  # a room behind the walls of the building with tagged levels
    ids[1, 0] = (FACE["roof"], 0, 2, 0)  # tagged roof
    ids[1, 1] = (FACE["ground"], 0, 0, 0)
    image = np.full((2, 3, 3), 100, np.uint8)
    out = guessed_aov(image, ids, masses).astype(int)
    guessed, tagged = out[0, 0], out[1, 0]
    assert guessed[0] > 150 and guessed[2] < 100, "guessed: orange"
    assert tagged[2] > 150 and tagged[0] < 100, "tagged: blue"
    assert (out[0, 1] == guessed).all() and (out[0, 2] == tagged).all()
    assert (out[1, 1] == 100).all() and (out[1, 2] == 100).all()


def test_render_tints_the_guessed_building_orange_and_the_tagged_one_blue():
    tagged = MapBuilding(
        0, "way/1", shapely.box(-30, -8, -10, 8), levels=6.0, roof_shape="flat", tagged={"levels", "roof_shape"}
    )
    silent = MapBuilding(1, "way/2", shapely.box(10, -8, 30, 8))
    city = map_city(MapData(Path("two.osm"), (25.0, 60.2), "EPSG:32635", buildings=[tagged, silent]))
    image, _ = render_city(city, camera="aerial", size=(128, 72), frames=0, time="12:00", samples=0, aov="guessed")
    plain, _ = render_city(city, camera="aerial", size=(128, 72), frames=0, time="12:00", samples=0)
    changed = np.abs(image.astype(int) - plain).max(axis=2) > 8
    assert changed.sum() > 100, "no building pixel was tinted"
    left, right = changed[:, :64], changed[:, 64:]
    orange = image[..., 0].astype(int) - image[..., 2]
    # Scene x grows to the right in the aerial view: the tagged building is on the left.
    assert (orange[:, :64][left] < 0).mean() > 0.9, "tagged building not blue"
    assert (orange[:, 64:][right] > 0).mean() > 0.9, "guessed building not orange"
