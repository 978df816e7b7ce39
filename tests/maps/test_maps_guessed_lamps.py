"""Street lamps guessed where the map is silent: along the streets of built-up areas by road class,
flagged as guessed and counted by `info`; none on motorways, `lit=no` roads, open country or next to
a mapped lamp."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely

from cityshade.commands.info import summary
from cityshade.maps import Lamp, MapBuilding, MapData, Road
from cityshade.maps.features.lamps import BUILT_UP_REACH, GUESSED_LAMPS, KERB_OFFSET, MAPPED_NEARBY, guessed_lamps


def street(y: float, kind: str, **tags) -> Road:
    return Road(f"way/{int(y) + 1000}", shapely.LineString([(0, y), (400, y)]), kind, 6.0, tags=tags)


def houses(y: float) -> list[MapBuilding]:
    """A row of 10 m houses every 25 m along a street at `y` (and past its ends), 8 m back from it."""
    return [
        MapBuilding(i, f"way/{i}", shapely.box(x, y + 8, x + 10, y + 18)) for i, x in enumerate(range(-50, 450, 25))
    ]


def town(*roads: Road, lamps=()) -> MapData:
    return MapData(
        Path("town.osm"), (24.94, 60.17), "EPSG:32635", buildings=houses(0.0), roads=list(roads), lamps=list(lamps)
    )


def test_a_residential_street_among_houses_gets_lamps_by_its_class():
    placed = guessed_lamps(town(street(0.0, "residential")))
    spacing, height = GUESSED_LAMPS["residential"]
    assert len(placed) == int(400 // spacing) and all(lamp.guessed for lamp in placed)
    xy = np.array([lamp.position for lamp in placed])
    assert np.allclose(xy[:, 1], -(3.0 + KERB_OFFSET))  # the right-hand kerb of an eastbound street
    assert np.allclose(np.diff(xy[:, 0]), spacing) and {lamp.height for lamp in placed} == {height}


def test_no_lamp_on_a_motorway_an_unlit_road_or_out_of_town():
    assert guessed_lamps(town(street(0.0, "motorway"), street(-4.0, "trunk"))) == []
    assert guessed_lamps(town(street(0.0, "residential", lit="no"))) == []
    far = guessed_lamps(town(street(-BUILT_UP_REACH - 30.0, "residential")))  # fields, not houses
    assert far == []


def test_no_guessed_lamp_beside_a_mapped_one():
    mapped = Lamp("node/1", (100.0, -4.0))
    placed = guessed_lamps(town(street(0.0, "residential"), lamps=[mapped]))
    xy = np.array([lamp.position for lamp in placed])
    assert len(placed) == int(400 // GUESSED_LAMPS["residential"][0]) - 1
    assert np.all(np.hypot(xy[:, 0] - 100.0, xy[:, 1] + 4.0) >= MAPPED_NEARBY)


def test_info_counts_the_guessed_lamps_apart_from_the_mapped():
    data = town(street(0.0, "pedestrian"), lamps=[Lamp("node/1", (-50.0, 50.0))])
    counts = summary(data)
    assert counts["street_lamps"] == 1
    assert counts["street_lamps_guessed"] == len(guessed_lamps(data)) == 400 // GUESSED_LAMPS["pedestrian"][0]
